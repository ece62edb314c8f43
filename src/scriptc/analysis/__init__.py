"""Analysing one source (docs/architecture.md):

- `read.py`      bytes -> `SourceFile` (UTF-8, the byte order mark dropped, bad bytes P007);
                 `read_bytes` and `ReadError` for a file that cannot be read at all
- `analyze.py`   `Analysis`, the one result type, the `analyze_*` functions and `finish` (the
                 checks, sorting and suppressions after any front end)
- `suppress.py`  the script's suppression comments
"""
