"""`python -m scriptc`: the same entry point as the `scriptc` command."""

from scriptc.cli.main import main

if __name__ == "__main__":
    main()
