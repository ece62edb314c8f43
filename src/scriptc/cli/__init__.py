"""The `scriptc` command: a click shell over `scriptc.ops` and the renderers, one module per
verb (`compile`, `lint`, `check`, `decompile`, `explain`, ...), loaded only when that verb runs
so that a cold `scriptc lint` pays for nothing else. A verb parses its arguments, calls the
library and prints: reading, analysing, choosing output paths and writing files are
`scriptc.ops`'s (and `scriptc.project.setup`'s); formatting diagnostics is
`scriptc.diagnostics.render`'s.

Exit status, for every verb: 0 no errors (warnings alone pass), 1 errors found, 2 a usage
problem, an unreadable file or an internal error (never a traceback; SCRIPTC_DEBUG=1 shows
it), 130 interrupted (Ctrl-C, as shells count it).
"""
