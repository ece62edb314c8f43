"""The front ends: what makes the IR from a source (docs/architecture.md).

- `script.py`            lowering: lark trees of a script's items -> IR, with exact spans
- `thesis_json.py`       thesis JSON -> IR (`jsonpos` parses, the schema judges, then the reader)
- `thesis_validator.py`  the thesis schema compiled by fastjsonschema (generated: do not edit)
- `jsonpos.py`           JSON with the span of every key and value
"""
