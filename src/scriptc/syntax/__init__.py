"""The syntax stage, the only user of lark (through `larkshim.py`, its one door). Loads the
grammars of grammar/ (shipped in the wheel), scans a file into bracketed items, parses each
item, and turns lark's errors into diagnostics. Parsing never raises: it returns what it could
parse and diagnostics."""
