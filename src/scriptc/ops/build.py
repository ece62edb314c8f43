"""`scriptc compile` and `scriptc decompile` as library calls: reading one file under its
repository's setup (`read_configured`, which `scriptc run` uses too), the back ends of
`compile --emit` (`emit`), where `compile` writes without `-o` (`default_output`), and script
syntax for a script read from thesis JSON (`decompile`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal, overload

from scriptc.analysis.analyze import Analysis, analyze_bytes, analyze_file
from scriptc.gcpause import gc_paused
from scriptc.ir.nodes import Script
from scriptc.paths import shown_path
from scriptc.project.setup import Setup
from scriptc.source import SourceFile, SourceKind

__all__ = ["EMITTERS", "decompile", "default_output", "emit", "read_configured"]

# The back ends of `scriptc compile --emit`: name -> (suffix of the default output file,
# module and function turning a checked Script into the output: text, or bytes for bytecode).
EMITTERS: dict[str, tuple[str, str, str]] = {
    "json": (".json", "scriptc.emit.json", "emit_json"),
    "bytecode": (".scb", "scriptc.emit.codegen", "emit_bytecode"),
}
# Back ends that also take the SourceFile: the bytecode records lines and columns of spans.
_WITH_SOURCE = frozenset({"bytecode"})


def read_configured(path: str, kind: SourceKind, setup: Setup, *,
                    stdin: Callable[[], bytes] | None = None,
                    stdin_name: str = "<stdin>") -> Analysis:
    """Read and analyse one file (`-`: `stdin()`, shown as `stdin_name`) under its setup: the
    repository's functions and robot profile, then its policy over the diagnostics. Raises
    `scriptc.analysis.read.ReadError` when the file cannot be read."""
    if path == "-":
        if stdin is None:
            from scriptc.analysis.read import ReadError

            raise ReadError("reading stdin is not supported here")
        analysis = analyze_bytes(shown_path(stdin_name), stdin(), kind, setup.functions,
                                 setup.profile)
    else:
        analysis = analyze_file(path, kind, shown_path(path), setup.functions, setup.profile)
    # Stdin without a name has no path the per-file ignores could match.
    shown = None if path == "-" and stdin_name == "<stdin>" else analysis.source.path
    analysis.diagnostics = setup.apply(analysis.diagnostics, shown)
    return analysis


@overload
def emit(script: Script, back_end: Literal["json"] = "json", source: SourceFile | None = None
         ) -> str: ...
@overload
def emit(script: Script, back_end: Literal["bytecode"], source: SourceFile | None = None
         ) -> bytes: ...
@overload
def emit(script: Script, back_end: str, source: SourceFile | None = None) -> str | bytes: ...
def emit(script: Script, back_end: str = "json", source: SourceFile | None = None
         ) -> str | bytes:
    """The output of one back end for a checked script: text (json) or bytes (bytecode).
    `source`, when given, lets the bytecode carry source lines (docs/bytecode.md)."""
    import importlib

    _suffix, module, function = EMITTERS[back_end]
    # the back end's function, found by name (EMITTERS): the script (and source) in, text or
    # bytes out
    emitter: Callable[..., str | bytes] = getattr(importlib.import_module(module), function)
    with gc_paused():
        if back_end in _WITH_SOURCE:
            return emitter(script, source)
        return emitter(script)


def decompile(script: Script) -> str:
    """Script syntax for a script (read from thesis JSON)."""
    from scriptc.emit.script import format_script

    return format_script(script)


def default_output(input_path: str, back_end: str = "json") -> str:
    """Where `scriptc compile FILE` writes without `-o`: beside the input, its suffix
    replaced by the back end's (`dance.script` -> `dance.json`); stdout (`-`) for stdin."""
    import os

    if input_path == "-":
        return "-"
    root, _ext = os.path.splitext(input_path)
    return root + EMITTERS[back_end][0]
