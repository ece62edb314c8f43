"""The aspects of case files that take one input and write one output: diagnostics (scripts,
thesis JSON, configurations), lint with a repository's configuration, compile, decompile,
the formatter and the bytecode listing. The module docstring of the harness says which
inputs each takes and what it writes."""

from __future__ import annotations

import contextlib
import tempfile
from pathlib import Path

from harness import CASES, Check, beside, expect, files, relative, stem
from harness.diagnostics import rendered

ROOT = CASES.parent.parent
REPO = CASES / "config" / "repo"


def _kind(path: Path) -> str:
    return "json" if path.suffix == ".json" else "script"


def analysis(path: Path, text: str | None = None):
    """The analysis of a case as `scriptc lint` (`scriptc check` for JSON) makes it with the
    default configuration: through the byte decoding the CLI uses (so P007 has cases), named
    by the case's path under tests/cases/. With `text`, of that text instead of the file's."""
    from scriptc.analysis.analyze import analyze_bytes

    data = path.read_bytes() if text is None else text.encode("utf-8")
    return analyze_bytes(relative(path), data, _kind(path))


# -- diagnostics -------------------------------------------------------------------------------

def script_inputs() -> list[Path]:
    """Every script and thesis JSON file of the cases (not the goldens `NAME.out.*` and
    `NAME.coverage.json` and `NAME.verify.json`, nor the JSON of the test files' cases: their
    results and worlds)."""
    return [p for p in files() if p.suffix in (".script", ".json")
            and not p.name.endswith((".out.script", ".out.json", ".coverage.json",
                                     ".verify.json"))
            and not relative(p).startswith("testing/")]


def config_inputs() -> list[Path]:
    return files("config", "*.toml", recursive=False)


def lint_fix(path: Path, name: str, *, isolated: bool = True) -> tuple[int, str]:
    """What `scriptc lint --fix` (without `--unsafe-fixes`) does to the file: how many fixes
    it applies and the text it writes (computed as `--diff` does, writing nothing). `name` is
    the file's name for the configuration (none when `isolated`)."""
    from scriptc.ops.lint import LintOptions, lint_paths

    data = path.read_bytes()
    options = LintOptions(cache=False, jobs=1, diff=True, isolated=isolated)
    run = lint_paths(["-"], _kind(path), stdin=lambda: data, stdin_name=name, options=options)
    assert not run.problems, run.problems
    (report,) = run.reports
    return report.fixed, report.fixed_text if report.fixed_text is not None else report.source.text


def _diagnostics(path: Path) -> None:
    found = analysis(path)
    expect(beside(path, ".diagnostics"), rendered(
        found.source, found.diagnostics, lambda text: analysis(path, text).diagnostics,
        lambda: lint_fix(path, relative(path))))


def _config_diagnostics(path: Path) -> None:
    from scriptc.project.config import load_config

    pyproject = path.name.endswith(".pyproject.toml")
    loaded = load_config(str(path), pyproject=pyproject)

    def again(text: str):
        with tempfile.TemporaryDirectory() as folder:
            copy = Path(folder) / path.name
            copy.write_text(text, encoding="utf-8")
            return load_config(str(copy), pyproject=pyproject).diagnostics

    expect(beside(path, ".diagnostics"), rendered(loaded.source, loaded.diagnostics, again))


def diagnostics_checks() -> list[Check]:
    checks = [Check("diagnostics", p, (beside(p, ".diagnostics"),), lambda p=p: _diagnostics(p))
              for p in script_inputs()]
    checks += [Check("diagnostics", p, (beside(p, ".diagnostics"),),
                     lambda p=p: _config_diagnostics(p)) for p in config_inputs()]
    return checks


# -- lint with the repository's configuration -------------------------------------------------

def _lint(path: Path) -> None:
    from scriptc.ops.lint import LintOptions, lint_paths

    def linted(text: str | None):
        """What `scriptc lint` run in tests/cases/ reports of the file (of `text` given as its
        content, as `--stdin-filename` gives it)."""
        options = LintOptions(cache=False, jobs=1)
        with contextlib.chdir(CASES):
            if text is None:
                run = lint_paths([relative(path)], options=options)
            else:
                run = lint_paths(["-"], stdin=lambda: text.encode("utf-8"),
                                 stdin_name=relative(path), options=options)
        assert not run.problems, run.problems
        (report,) = [r for r in run.results if r.source.path.endswith(".script")]
        return report

    def fixed() -> tuple[int, str]:
        with contextlib.chdir(CASES):
            return lint_fix(path, relative(path), isolated=False)

    report = linted(None)
    expect(beside(path, ".lint"), rendered(report.source, report.diagnostics,
                                           lambda text: linted(text).diagnostics, fixed))


def lint_checks() -> list[Check]:
    return [Check("lint", p, (beside(p, ".lint"),), lambda p=p: _lint(p))
            for p in files("config/repo", "*.script")]


# -- compile and decompile --------------------------------------------------------------------

def _compile(path: Path) -> None:
    from scriptc.emit.json import emit_json

    found = analysis(path)
    assert found.ok, "a case with a golden JSON file must compile"
    expect(beside(path, ".out.json"), emit_json(found.script))


def _decompile(path: Path) -> None:
    from scriptc.emit.script import format_script

    found = analysis(path)
    assert found.script is not None, found.diagnostics
    expect(beside(path, ".out.script"), format_script(found.script))


def compile_checks() -> list[Check]:
    scripts = [p for p in script_inputs() if p.suffix == ".script"
               and (relative(p).startswith("emit/") or beside(p, ".out.json").exists())]
    out = [Check("compile", p, (beside(p, ".out.json"),), lambda p=p: _compile(p)) for p in scripts]
    out += [Check("decompile", p, (beside(p, ".out.script"),), lambda p=p: _decompile(p))
            for p in script_inputs() if p.suffix == ".json" and beside(p, ".out.script").exists()]
    return out


# -- the formatter ----------------------------------------------------------------------------

def _meaning(text: str) -> tuple[str | None, list[str]]:
    """The thesis JSON of a script (None when it has errors) and its diagnostic codes."""
    from scriptc.analysis.analyze import analyze_script
    from scriptc.emit.json import emit_json
    from scriptc.source import SourceFile

    found = analyze_script(SourceFile("x.script", text))
    return ((emit_json(found.script) if found.ok else None),
            sorted(d.code for d in found.diagnostics))


def _fmt(path: Path) -> None:
    from scriptc.formatter import format_text

    text = path.read_bytes().decode("utf-8")
    result = format_text(text)
    assert result.text is not None, result.diagnostics
    expect(beside(path, ".fmt.script"), result.text)
    assert format_text(result.text).text == result.text, "formatting twice changed the text"
    assert _meaning(result.text) == _meaning(text), "formatting changed the meaning"


def fmt_inputs() -> list[Path]:
    return [p for p in files("fmt", "*.script") if not p.name.endswith(".fmt.script")]


def fmt_checks() -> list[Check]:
    return [Check("fmt", p, (beside(p, ".fmt.script"),), lambda p=p: _fmt(p)) for p in fmt_inputs()]


# -- the bytecode listing ---------------------------------------------------------------------

# The example of the thesis's listing 4.1 is listed too; its listing is a case file.
EXAMPLE = ROOT / "examples" / "test_act.script"


def _listing(path: Path, listing: Path) -> None:
    from scriptc.analysis.analyze import analyze_bytes
    from scriptc.bytecode import disassemble, encode, load
    from scriptc.emit.codegen import codegen

    found = analyze_bytes(path.name, path.read_bytes())
    assert found.ok, found.diagnostics
    expect(listing, disassemble(load(encode(codegen(found.script, found.source))).program))


def listing_checks() -> list[Check]:
    out = [Check("listing", p, (beside(p, ".dis"),), lambda p=p: _listing(p, beside(p, ".dis")))
           for p in files("bytecode", "*.script")]
    listing = CASES / "bytecode" / f"{stem(EXAMPLE)}.dis"
    out.append(Check("listing", EXAMPLE, (listing,), lambda: _listing(EXAMPLE, listing)))
    return out


ASPECTS = (diagnostics_checks, lint_checks, compile_checks, fmt_checks, listing_checks)
