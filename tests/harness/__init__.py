"""The one harness of case files (tests are data).

A case is an input file under tests/cases/ with its expected outputs beside it.
tests/test_cases.py runs each input through every aspect that applies to it and compares each
output with its expected file, byte for byte. `pytest --bless` (tests/conftest.py) writes the
expected files from what the code does now instead: review the diff (`git diff tests/cases`)
before committing it. An expected file that is missing fails with the file's name.

The aspects (inputs, then what each writes beside them):

- `diagnostics`: every `NAME.script` and `NAME.json` (thesis JSON) under tests/cases/, and the
  configurations `config/NAME.toml` (a scriptc.toml) and `config/NAME.pyproject.toml`:
  `NAME.diagnostics`, what `scriptc lint` (`scriptc check` for JSON) reports with the default
  configuration: each diagnostic rendered whole, its span, and the text after its fix
  (harness/diagnostics.py says how). Every code of the registry appears in one.
- `lint`: the scripts of the repository `config/repo/` (its scriptc.toml, its functions in
  `activity_functions.py`): `NAME.lint`, what `scriptc lint` reports there, in the same form.
- `compile`: the scripts of `emit/`, and any script with a `NAME.out.json` beside it: the exact
  text `scriptc compile` writes (`NAME.out.json`).
- `decompile`: a thesis JSON file with a `NAME.out.script` beside it: what `scriptc decompile`
  writes.
- `fmt`: `fmt/NAME.script`: `NAME.fmt.script`, what the formatter writes; formatting it again
  changes nothing, and it compiles to the same JSON (or the same codes) as the input. The
  output is a script, so it has its own `NAME.fmt.diagnostics`.
- `listing`: `bytecode/NAME.script`: `NAME.dis`, the listing of its bytecode (`scriptc dis`);
  the thesis's listing 4.1, `examples/test_act.script`, has its listing in `bytecode/` too.
- `ide`: `ide/FEATURE_NAME.script`, a script with the cursor written `$0`: `NAME.expect`, what
  the editor feature answers there (harness/ide.py).
- `trace`: `runtime/NAME.script` (or `.json`) with its scenarios `NAME[.VARIANT].world`:
  `NAME[.VARIANT].trace.jsonl`, the trace of the run, through each executor (harness/runtime.py).
- `test`: `testing/NAME.test.toml`, a test file: `NAME.diagnostics`, what `scriptc test` reports
  in it (its problems, or its failed expectations), and for one that checks `NAME.result.json`,
  the result of its run (harness/testing.py).
- `coverage`: `coverage/NAME/`, a folder of test files and their scripts: `NAME.coverage`,
  `NAME.info` and `NAME.coverage.json`, what `scriptc test --coverage`, `--lcov` and
  `--coverage-data` give over those tests (harness/coverage.py).
- `verify`: `verify/NAME.script`: `NAME.verify`, the line of each property `scriptc verify`
  prints and the diagnostics of the verification (family Y), and `NAME.verify.json`, its
  result as data (harness/verify.py).
- `graph`: `graph/NAME.script`: `NAME.dot` and `NAME.mmd`, the flow graph `scriptc graph` draws
  in DOT and in Mermaid (harness/graph.py).
- `summary`: every expected trace of `runtime/`, `NAME[.VARIANT].trace.jsonl`:
  `NAME[.VARIANT].summary.txt` and `NAME[.VARIANT].summary.it.md`, the session summary for the
  therapist in English (text) and Italian (Markdown) (harness/summary.py).

`render/*.txt` are snapshots of the text renderer over hand-built diagnostics, written by
tests/test_render.py through `expect`. A file under tests/cases/ that is neither an input, an
expected output nor a support file (`SUPPORT`: a case repository's configuration and code) fails
`test_every_file_has_a_case`.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from fnmatch import fnmatchcase as fnmatch
from functools import cache
from pathlib import Path

CASES = Path(__file__).parent.parent / "cases"

# Set by `pytest --bless` (tests/conftest.py): `expect` writes instead of comparing.
BLESS = False


def expect(path: Path, actual: str) -> None:
    """Compare `actual` with the file at `path`, byte for byte (or write it when blessing)."""
    if BLESS:
        if not path.exists() or path.read_bytes() != actual.encode("utf-8"):
            path.write_bytes(actual.encode("utf-8"))
        return
    assert path.exists(), f"missing expected file {relative(path)} (run `pytest --bless`)"
    expected = path.read_bytes().decode("utf-8")
    if actual != expected:
        diff = difflib.unified_diff(expected.splitlines(keepends=True),
                                    actual.splitlines(keepends=True), "expected", "actual")
        raise AssertionError(f"{relative(path)} is not what the code writes now (`pytest "
                             f"--bless` writes it; read the diff first):\n{''.join(diff)}")


def relative(path: Path) -> str:
    """A case file's name as tests show it: relative to tests/cases/ (to the repository for an
    input outside it, such as an example), with `/`."""
    if path.is_relative_to(CASES):
        return path.relative_to(CASES).as_posix()
    return path.relative_to(CASES.parent.parent).as_posix()


def stem(path: Path) -> str:
    """A file's name without its suffix (`a.fmt.script` -> `a.fmt`)."""
    return path.name[: -len(path.suffix)]


def beside(path: Path, suffix: str) -> Path:
    """The file beside `path` with its suffix replaced (`a.fmt.script`, `.diagnostics` ->
    `a.fmt.diagnostics`)."""
    return path.with_name(stem(path) + suffix)


@cache
def _tree() -> tuple[Path, ...]:
    """Every file under tests/cases/, sorted, leaving out hidden folders (a `.scriptc_cache`
    that linting `config/repo` from an editor leaves at its root) and `__pycache__` (Python
    writes one beside a case repository's functions module when a case imports it, unless
    PYTHONDONTWRITEBYTECODE is set): listed once per run."""
    return tuple(sorted(p for p in CASES.rglob("*") if p.is_file()
                        and not any(part.startswith(".") or part == "__pycache__"
                                    for part in p.relative_to(CASES).parts)))


def files(folder: str = "", pattern: str = "*", *, recursive: bool = True) -> list[Path]:
    """The files under tests/cases/FOLDER (in it alone, unless `recursive`) whose name
    matches `pattern`, sorted."""
    base = CASES / folder
    return [p for p in _tree() if fnmatch(p.name, pattern)
            and (p.parent == base or (recursive and p.is_relative_to(base)))]


@dataclass(frozen=True)
class Check:
    """One aspect of one case: `run` computes the outputs and `expect`s each of `expected`."""

    aspect: str
    input: Path
    expected: tuple[Path, ...]
    run: Callable[[], None] = field(compare=False)
    variant: str = ""
    reads: tuple[Path, ...] = ()  # input files beyond `input` (scenarios)

    @property
    def id(self) -> str:
        variant = f"[{self.variant}]" if self.variant else ""
        return f"{self.aspect}:{relative(self.input)}{variant}"


# Files under tests/cases/ that are neither inputs nor expected outputs: what the cases need,
# the configuration of a case repository (`config/repo/`, `runtime/repo/`) and the Python code
# of the functions and rules it declares.
SUPPORT = ("scriptc.toml", "*.py")


def checks() -> list[Check]:
    """Every check of every case, aspect by aspect."""
    from harness import aspects, coverage, graph, ide, runtime, summary, testing, verify

    out: list[Check] = []
    for make in (*aspects.ASPECTS, ide.checks, runtime.checks, testing.checks, coverage.checks,
                 verify.checks, graph.checks, summary.checks):
        out.extend(make())
    return out


def unaccounted(all_checks: Iterable[Check]) -> list[str]:
    """The files under tests/cases/ no check reads or expects, and that are no support file
    (render snapshots aside)."""
    known = {p for pattern in SUPPORT for p in files("", pattern)}
    for check in all_checks:
        known.add(check.input)
        known.update(check.expected)
        known.update(check.reads)
    return [relative(p) for p in files()
            if p not in known and not relative(p).startswith("render/")]
