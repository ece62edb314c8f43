"""The coverage of a test run as a library call (`scriptc test --coverage`, docs/testing.md):
the scripts the tests ran, read as `scriptc run` reads them, and what their traces reached
(`scriptc.testing.coverage`). Prints nothing.

The scripts measured are those the tests name (`scripts`) and those the runs loaded by path
(a `script_vect` update, an override naming a file): each read once, under its repository's
setup, into the IR whose spans give each point its line. A `.scb` file has no source to point
at, and a script that cannot be read or has errors never ran: neither is measured.
"""

from __future__ import annotations

from collections.abc import Sequence

from scriptc.analysis.read import ReadError
from scriptc.ops.build import read_configured
from scriptc.project.setup import setup_for
from scriptc.source import SourceKind
from scriptc.testing.coverage import (
    Coverage,
    ScriptCoverage,
    count,
    loaded_paths,
    script_key,
    shape,
)
from scriptc.testing.model import TestFile
from scriptc.testing.run import ERROR, TestResult

__all__ = ["measure"]


def measure(tests: Sequence[TestFile], results: Sequence[TestResult]) -> Coverage:
    """The coverage of `results` (the runs of `tests`) over the scripts they ran."""
    wanted: dict[str, str] = {}  # a script's name in coverage -> a path to read it by
    for test in tests:
        for path in test.scripts:
            wanted.setdefault(script_key(path), path)
    ran = [r for r in results if r.status != ERROR]
    for result in ran:
        for path in loaded_paths(result.events):
            wanted.setdefault(script_key(path), path)
    coverage = Coverage(tests=len(ran))
    for key in sorted(wanted):
        script = _read(wanted[key])
        if script is not None:
            coverage.scripts[key] = script
    for result in ran:
        count(coverage, result.events)
    return coverage


def _read(path: str) -> ScriptCoverage | None:
    """The points of the script at `path`, or None when it is not measured (bytecode, a file
    that cannot be read, a configuration or a script with errors)."""
    kind = SourceKind.of_path(path)
    if kind is SourceKind.BYTECODE:
        return None
    setup = setup_for(path)
    if setup.failed:
        return None
    try:
        analysis = read_configured(path, kind, setup)
    except ReadError:
        return None
    if not analysis.ok or analysis.script is None:
        return None
    return shape(analysis.script, analysis.source, path)
