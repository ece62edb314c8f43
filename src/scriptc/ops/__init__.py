"""What each verb does, as a library call that prints nothing: the CLI and the API parse,
call one of these and show what it returns.

- `lint.py`      `scriptc lint` and `scriptc check`: `lint_paths` (discovery, the configuration
                 of each file, the cache, worker processes, fix rounds) -> `LintRun`
- `build.py`     `scriptc compile` and `decompile`: one file read under its setup, the back
                 ends, default output names
- `programs.py`  `scriptc run`: the programs of the files, the loader a session gets for
                 scripts met by path, the run's defaults
- `format.py`    `scriptc fmt`: `FormatRun`, each file's outcome

This package sits above `analysis/`, `project/`, `runtime/` and `ide/` and below `cli/`,
`server/` and `api.py` (docs/architecture.md).
"""
