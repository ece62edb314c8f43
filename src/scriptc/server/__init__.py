"""The language server (`scriptc lsp`): the only package that imports pygls and lsprotocol.

- `main`     the pygls server and its handlers, each a few lines over `scriptc.ide`
- `convert`  every conversion between the editor API's offsets and plain data and the
             protocol's positions (lines, columns in the negotiated encoding) and types

Importing this package imports nothing; `scriptc.server.main` loads pygls (about 0.4 s), so
`scriptc lint` never pays for it.
"""
