"""The typed IR, which knows nothing of text, lark or JSON: frozen, slotted dataclasses with
source spans (`nodes.py`), the registry of classes, fields and B/F/E functions (`builtins.py`),
reading the numbers and texts of command fields (`fields.py`), the conditions' visitor
(`walk.py`) and moving the spans of IR values and diagnostics (`shift.py`). The front ends that
make IR from script text and from thesis JSON are `scriptc.frontend`."""
