"""An activity repository (docs/architecture.md, docs/configuration.md):

- `config/`        its configuration files, read and checked (`Settings`, `Resolver`)
- `setup.py`       a file's setup: settings -> function registry -> robot profile, once
- `files.py`       the files of a run: folders walked (.gitignore, exclusions), `discover`
- `cache.py`       the results cache under `.scriptc_cache/`
- `provenance.py`  where the running scriptc was installed from
"""
