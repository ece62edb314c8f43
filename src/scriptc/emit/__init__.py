"""Back ends over the typed IR: the thesis JSON (`json.py`), the canonical `toparse` text of a
condition (`condition.py`) and the canonical script syntax (`script.py`, used by `decompile`
and by the Python API). Nothing here parses; everything here is a pure function of the IR."""
