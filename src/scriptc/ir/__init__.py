"""The typed IR: frozen, slotted dataclasses with source spans (`nodes.py`), the lowering
from lark trees (`lower.py`), the thesis JSON reader (`from_json.py`), the registry of classes,
fields and B/F/E functions (`builtins.py`) and traversal helpers (`walk.py`)."""
