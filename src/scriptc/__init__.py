"""scriptc: the compiler toolchain for the thesis's robot activity language.

The pipeline, and the package that holds each stage (see docs/architecture.md):
source -> syntax (lark) -> ir (typed, with spans) -> check -> emit (thesis JSON, script text).
"""

__version__ = "0.1.0"
