"""The configuration: reading, checking (C001, C002, C004, C005 at the right line), finding it
by walking up, the policy it applies (selection, per-file ignores, severities), the user's
functions in the checks, lazy implementations, and the cost of it all on `scriptc lint`'s
fast path.

Case files (tests are data, run by tests/test_cases.py): `tests/cases/config/NAME.toml` (a
scriptc.toml) or `NAME.pyproject.toml` (a pyproject.toml) beside `NAME.diagnostics`, what
checking it reports; `tests/cases/config/repo/` is a repository whose scripts have `NAME.lint`
beside them, what `scriptc lint` reports with the repository's configuration.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest
from harness import CASES
from harness.diagnostics import parsed

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Severity
from scriptc.project.config import (
    ImplementationError,
    Resolver,
    Settings,
    build_settings,
    find_config,
    load_config,
)
from scriptc.project.config.tomlpos import locate
from scriptc.project.setup import Setup
from scriptc.robot.profile import DEFAULT_PROFILE
from scriptc.source import Span

CONFIG_CASES = CASES / "config"
REPO = CONFIG_CASES / "repo"
ROOT = Path(__file__).parent.parent


def test_the_repository_lints_at_once_as_file_by_file() -> None:
    """Linting the repository's folder finds each of its scripts, under a clean configuration,
    and reports for each what its `NAME.lint` case (linted alone) holds."""
    from scriptc.ops.lint import LintOptions, lint_paths

    run = lint_paths([str(REPO)], options=LintOptions(cache=False, jobs=1))
    assert not run.problems
    reports = {Path(r.source.path).resolve(): r for r in run.results}
    scripts = sorted(REPO.rglob("*.script"))
    assert set(reports) == {p.resolve() for p in scripts}  # the configuration is clean
    for script in scripts:
        report = reports[script.resolve()]
        expected = parsed(script.with_suffix(".lint").read_text(encoding="utf-8"))
        assert [(d.code, d.severity.value, d.message) for d in report.diagnostics] == [
            (code, severity, message) for _span, severity, code, message in expected], script


# ---------------------------------------------------------------------------------------------
# reading


def test_valid_configuration_builds_every_setting() -> None:
    loaded = load_config(str(CONFIG_CASES / "valid.toml"))
    assert loaded.diagnostics == []
    s = loaded.settings
    assert s.audio_root == "audio" and s.audio_root_path == str(CONFIG_CASES / "audio")
    assert s.exclude == ("drafts/", "/generated/**") and s.respect_gitignore is True
    assert s.ignore == ("F003", "M00")
    assert s.per_file_ignores == (("legacy/**", ("F001", "unreachable-block")),)
    assert s.severity == (("M004", "error"), ("A", "info"))
    assert s.robot.max_linear_speed == 0.5 and s.robot.max_volume == 0.8
    assert s.robot.min_human_distance == 0.4 and s.robot.max_led_flash_rate == 3.0
    waving, mood = s.functions
    assert (waving.name, waving.kind, waving.arity, waving.params) == ("waving", "B", 0, ())
    assert (mood.kind, mood.arity, mood.params) == ("F", 1, ("who",))
    functions = Setup(s).functions
    assert functions.get("mood").signature == "F: mood(who)"
    assert functions.get("near") is not None  # the standard ones stay
    (rule,) = s.rules
    assert (rule.name, rule.rulecode, rule.implementation) == ("greet", 16, "activity_rules:Greet")
    assert s.rule("greet") is rule and s.function("waving") is waving


def test_defaults() -> None:
    s = Settings()
    assert s.select == ("ALL",) and s.robot is DEFAULT_PROFILE and s.functions == ()
    from scriptc.ir.builtins import STANDARD

    assert Setup(s).functions is STANDARD


def test_wrong_values_are_left_at_their_defaults() -> None:
    loaded = load_config(str(CONFIG_CASES / "invalid_values.toml"))
    s = loaded.settings
    assert s.audio_root == "../elsewhere"  # reported (C002); the path is still what was said
    assert s.exclude == () and s.respect_gitignore is True and s.select == ()
    assert s.per_file_ignores == () and s.severity == ()
    assert s.robot is DEFAULT_PROFILE  # every limit rejected keeps its default
    assert s.functions == ()  # each declaration is wrong somewhere
    assert [r.implementation for r in s.rules] == ["rules:greet"]  # the first of the two


def test_values_that_cannot_be_looked_up_are_left_out() -> None:
    """A function's `kind` written as an array or a table raised TypeError (unhashable) while
    the settings were built: an internal error instead of C002 and the defaults."""
    loaded = load_config(str(CONFIG_CASES / "unhashable_values.toml"))
    assert [d.code for d in loaded.diagnostics] == ["C002", "C002"]
    assert loaded.settings.functions == ()


def test_numbers_the_policy_refuses_are_left_at_their_defaults() -> None:
    """`inf` reached the governor's profile (and `Infinity` the trace); a 327-digit integer
    made building the settings overflow."""
    loaded = load_config(str(CONFIG_CASES / "non_finite_numbers.toml"))
    robot = loaded.settings.robot
    assert robot == replace(DEFAULT_PROFILE, max_angular_acceleration=2.5,
                            source=robot.source)  # the others keep their defaults
    huge = load_config(str(CONFIG_CASES / "huge_integer.toml"))
    assert [d.code for d in huge.diagnostics] == ["C002"]
    assert huge.settings.robot is DEFAULT_PROFILE  # tomllib read nothing: the defaults


def test_a_pyproject_with_an_unreadable_integer_is_still_ours(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text("[tool.scriptc]\nx = " + "1" * 5000 + "\n")
    assert find_config(str(tmp_path)) == str(tmp_path / "pyproject.toml")


def test_a_broken_file_uses_the_defaults() -> None:
    loaded = load_config(str(CONFIG_CASES / "invalid_toml.toml"))
    assert [d.code for d in loaded.diagnostics] == ["C005"]
    assert loaded.settings.select == ("ALL",) and loaded.settings.digest


def test_an_unreadable_or_non_utf8_file(tmp_path: Path) -> None:
    missing = load_config(str(tmp_path / "scriptc.toml"))
    assert [d.code for d in missing.diagnostics] == ["C005"]
    latin = tmp_path / "latin.toml"
    latin.write_bytes(b"audio-root = \"m\xfasica\"\n")
    (problem,) = load_config(str(latin)).diagnostics
    assert problem.code == "C005" and "UTF-8" in problem.message
    assert problem.span == Span(15, 16)  # the byte 0xfa, after 15 ASCII characters


@pytest.mark.parametrize("name", ["unknown_keys.toml", "forms.toml", "invalid_values.toml"])
def test_every_problem_points_into_the_file(name: str) -> None:
    loaded = load_config(str(CONFIG_CASES / name))
    assert loaded.diagnostics
    for d in loaded.diagnostics:
        assert 0 < d.span.start < d.span.end <= len(loaded.source.text), d


# ---------------------------------------------------------------------------------------------
# positions in TOML text


def test_positions_of_keys_and_values() -> None:
    text = (
        'a = "x # not a comment"  # a comment\n'
        'b.c = [1, [2, 3], {d = "]"}]\n'
        '[e."f.g"]\n'
        "h = '''\nmulti ] line'''\n"
        "[[i]]\n"
        "j = 1\n"
        "[[i]]\n"
        "j = 2\n"
        "[i.k]\n"
        "l = 1979-05-27 07:32:00Z\n"
        'm = """a \\""" b"""\n'
    )
    p = locate(text)

    def at(span: Span) -> str:
        return text[span.start:span.end]

    assert at(p.value(("a",))) == '"x # not a comment"'
    assert at(p.key(("b", "c"))) == "c" and at(p.key(("b",))) == "b"
    assert at(p.value(("b", "c", 1, 0))) == "2"
    assert at(p.value(("b", "c", 2, "d"))) == '"]"'
    assert at(p.key(("e", "f.g"))) == '"f.g"'
    assert at(p.value(("e", "f.g", "h"))) == "'''\nmulti ] line'''"
    assert at(p.value(("i", 0, "j"))) == "1" and at(p.value(("i", 1, "j"))) == "2"
    assert at(p.value(("i", 1, "k", "l"))) == "1979-05-27 07:32:00Z"
    assert at(p.value(("i", 1, "k", "m"))) == '"""a \\""" b"""'
    # An unknown path falls back to its nearest known ancestor.
    assert p.find(("i", 1, "k", "nope")) == p.value(("i", 1, "k"))
    assert p.find(("zzz",)) == Span(0, 0)


def test_positions_never_raise_on_text_they_cannot_follow() -> None:
    for text in ["[", "a = ", 'a = "', "a = [1,", "[[x]", "= 1", "a = {b = 1", "\x00"]:
        locate(text)


# ---------------------------------------------------------------------------------------------
# finding the configuration


def test_found_by_walking_up_and_scriptc_toml_wins(tmp_path: Path) -> None:
    deep = tmp_path / "a" / "b" / "c"
    deep.mkdir(parents=True)
    assert find_config(str(deep)) in (None, *[str(p) for p in Path("/").glob("scriptc.toml")])
    (tmp_path / "a" / "pyproject.toml").write_text('[project]\nname = "scriptc-stuff"\n')
    assert find_config(str(deep)) is None or not find_config(str(deep)).startswith(str(tmp_path))
    (tmp_path / "a" / "pyproject.toml").write_text("[tool.scriptc.lint]\nignore = []\n")
    assert find_config(str(deep)) == str(tmp_path / "a" / "pyproject.toml")
    (tmp_path / "a" / "scriptc.toml").write_text("")
    assert find_config(str(deep)) == str(tmp_path / "a" / "scriptc.toml")
    (tmp_path / "a" / "b" / "scriptc.toml").write_text("")
    assert find_config(str(deep / "x.script")) == str(tmp_path / "a" / "b" / "scriptc.toml")


def test_the_candidates_stop_at_the_nearest_configuration(tmp_path: Path) -> None:
    """What a watcher of one file's configuration must watch: both names in every folder
    from the file's up to the nearest configuration's, whether they exist or not."""
    from scriptc.project.config.load import config_candidates

    deep = tmp_path / "a" / "b"
    deep.mkdir(parents=True)
    (tmp_path / "a" / "pyproject.toml").write_text("[tool.scriptc.lint]\nignore = []\n")
    names = ["scriptc.toml", "pyproject.toml"]
    expected = [str(folder / name) for folder in (deep, tmp_path / "a") for name in names]
    assert config_candidates(str(deep / "x.script")) == expected
    assert config_candidates(str(deep)) == expected
    (deep / "scriptc.toml").write_text("")
    assert config_candidates(str(deep / "x.script")) == expected[:2]
    (tmp_path / "a" / "pyproject.toml").unlink()
    (deep / "scriptc.toml").unlink()
    walked = config_candidates(str(deep / "x.script"))
    assert walked[:4] == expected
    above = find_config(str(deep))  # None, unless a folder above tmp_path has a configuration
    last = Path(above).parent if above else Path("/")  # with none, up to the root
    assert walked[-2:] == [str(last / name) for name in names]


@pytest.mark.parametrize("text, configures", [
    ('[tool.scriptc]\naudio-root = "a"\n', True),
    ("[tool.scriptc.lint]\n", True),
    ('[tool]\nscriptc = { audio-root = "a" }\n', True),
    ('tool.scriptc.audio-root = "a"\n', True),
    ('[project]\nname = "scriptc"\n[project.scripts]\nscriptc = "scriptc.cli.main:main"\n', False),
    ("[tool.ruff]\nline-length = 99\n", False),
    ("[tool.scriptc\nbroken", True),  # broken, but ours: its error is reported
    ('[tool]\nscriptc.audio-root = "a"\n', True),
    ('[tool]\n"scriptc" . lint . ignore = []\n', True),
    ("[tool]\n'scriptc'.audio-root = 'a'\n", True),
])
def test_which_pyproject_files_configure_scriptc(tmp_path: Path, text: str,
                                                 configures: bool) -> None:
    (tmp_path / "pyproject.toml").write_text(text)
    found = find_config(str(tmp_path))
    assert (found == str(tmp_path / "pyproject.toml")) is configures


@pytest.mark.parametrize("text", [
    '[tool.mypy]\nmodules = [\n    "scriptc.ir.*", "scriptc.check.*",\n]\n',
    '[project.scripts]\nscriptc = "scriptc.cli.main:main"\n',
    '[tool.importlinter]\nlayers = [\n    "scriptc.cli | scriptc.api",\n]\n',
])
def test_a_pyproject_that_only_names_modules_of_scriptc_is_not_parsed(
        tmp_path: Path, text: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Parsing TOML is most of a cold start's configuration cost: a file that cannot hold the
    table (scriptc's own pyproject.toml, say) is passed over on sight."""
    import tomllib

    def refuse(_text: str) -> None:
        raise AssertionError("parsed")

    monkeypatch.setattr(tomllib, "loads", refuse)
    (tmp_path / "pyproject.toml").write_text(text)
    assert find_config(str(tmp_path)) != str(tmp_path / "pyproject.toml")


def test_a_pyproject_table_is_read_with_its_prefix(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text(
        '[project]\nname = "x"\n\n[tool.scriptc.lint]\nignore = ["F003"]\nselect = "F"\n')
    loaded = load_config(str(tmp_path / "pyproject.toml"))
    (d,) = loaded.diagnostics
    assert d.message == "`tool.scriptc.lint.select` must be an array, not a string"
    assert loaded.source.position(d.span.start).line == 6
    assert loaded.settings.ignore == ("F003",)


def test_resolver_searches_each_folder_once(tmp_path: Path, monkeypatch) -> None:
    (tmp_path / "scriptc.toml").write_text('[lint]\nignore = ["F003"]\n')
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "deeper").mkdir()
    import scriptc.project.config.load as load

    calls = []
    real = load.config_in
    monkeypatch.setattr(load, "config_in", lambda folder: calls.append(folder) or real(folder))
    resolver = Resolver()
    a = resolver.for_file(str(tmp_path / "sub" / "deeper" / "a.script"))
    b = resolver.for_file(str(tmp_path / "sub" / "b.script"))
    assert a is b and a.ignore == ("F003",)
    assert len(calls) == len(set(calls)) == 3
    assert Resolver(isolated=True).for_file(str(tmp_path / "a.script")) == Settings()
    forced = tmp_path / "other.toml"
    forced.write_text('[lint]\nignore = ["F001"]\n')
    assert Resolver(config=str(forced)).for_folder("/").ignore == ("F001",)


# ---------------------------------------------------------------------------------------------
# the policy


def _d(code: str) -> object:
    from scriptc.diagnostics.codes import lookup

    return diagnostic(code, "m", Span(0, 1), severity=lookup(code).severity)


def _codes(settings: Settings, codes: list[str], path: str | None = None) -> list[tuple]:
    return [(d.code, d.severity.value) for d in settings.apply([_d(c) for c in codes], path)]


def test_selection_most_specific_wins_and_errors_always_show() -> None:
    s = build_settings({"lint": {"select": ["F"], "ignore": ["F00"]}})
    assert _codes(s, ["F001", "F002", "M004", "L003"]) == [("F002", "error"), ("L003", "error")]
    s = build_settings({"lint": {"select": ["F001"], "ignore": ["F"]}})
    assert _codes(s, ["F001", "F003"]) == [("F001", "warning")]
    s = build_settings({"lint": {"select": ["F"], "ignore": ["F"]}})  # a tie: ignore wins
    assert _codes(s, ["F001"]) == []
    s = build_settings({"lint": {"ignore": ["unreachable-block", "ALL"]}})
    assert _codes(s, ["F001", "M004", "R003"]) == [("R003", "error")]
    s = build_settings({"lint": {"select": []}})
    assert _codes(s, ["F001", "S001"]) == [("S001", "error")]


def test_severity_overrides_never_lower_an_error() -> None:
    s = build_settings({"lint": {"severity": {"F": "info", "F001": "error", "L003": "info",
                                              "no-terminus": "warning"}}})
    assert _codes(s, ["F001", "F002", "F003", "L003"]) == [
        ("F001", "error"), ("F002", "error"), ("F003", "warning"), ("L003", "error")]


def test_per_file_ignores_match_gitignore_patterns_from_the_root(tmp_path: Path) -> None:
    s = build_settings({"lint": {"per-file-ignores": {"legacy/**": ["F001"],
                                                     "*_draft.script": ["warning-free", "M"],
                                                     "/top.script": ["A001"]}}},
                       root=str(tmp_path))
    codes = ["F001", "M004", "A001"]
    assert _codes(s, codes, str(tmp_path / "legacy" / "x" / "a.script")) == [
        ("M004", "warning"), ("A001", "warning")]
    assert _codes(s, codes, str(tmp_path / "sub" / "b_draft.script")) == [
        ("F001", "warning"), ("A001", "warning")]
    assert _codes(s, codes, str(tmp_path / "top.script")) == [
        ("F001", "warning"), ("M004", "warning")]
    assert _codes(s, codes, str(tmp_path / "sub" / "top.script")) == [
        ("F001", "warning"), ("M004", "warning"), ("A001", "warning")]
    assert len(_codes(s, codes, "/elsewhere/legacy/a.script")) == 3  # outside the root


# ---------------------------------------------------------------------------------------------
# the repository's functions and rules


def test_declared_functions_satisfy_the_checks() -> None:
    from scriptc.analysis.analyze import analyze_bytes

    settings = load_config(str(REPO / "scriptc.toml")).settings
    data = (REPO / "activity.script").read_bytes()
    plain = analyze_bytes("a.script", data)
    configured = analyze_bytes("a.script", data, functions=Setup(settings).functions)
    assert [d.code for d in plain.diagnostics if d.code.startswith("R")] == ["R003", "R003"]
    assert not [d for d in configured.diagnostics if d.code.startswith("R")]


def test_implementations_are_imported_only_when_asked() -> None:
    settings = load_config(str(REPO / "scriptc.toml")).settings
    from scriptc.ops.lint import LintOptions, lint_paths

    lint_paths([str(REPO)], options=LintOptions(cache=False, jobs=1))
    assert "activity_functions" not in sys.modules
    try:
        waving = settings.function("waving").load()
        assert waving({"waving": True}) is True
        assert settings.function("mood").load()("x") == "calm"
    finally:
        sys.modules.pop("activity_functions", None)
        if str(REPO) in sys.path:
            sys.path.remove(str(REPO))


def test_a_missing_implementation_says_what_is_missing(tmp_path: Path) -> None:
    (tmp_path / "scriptc.toml").write_text(
        '[[functions]]\nname = "f"\nkind = "E"\narity = 0\nimplementation = "nomodule_xyz:f"\n'
        '[[rules]]\nname = "r"\nimplementation = "json:no_such_thing"\n')
    settings = load_config(str(tmp_path / "scriptc.toml")).settings
    with pytest.raises(ImplementationError, match="cannot import `nomodule_xyz`"):
        settings.function("f").load()
    with pytest.raises(ImplementationError, match="has no attribute `no_such_thing`"):
        settings.rule("r").load()
    sys.path.remove(str(tmp_path))


# ---------------------------------------------------------------------------------------------
# the schema and the documentation


def _schema() -> dict:
    from scriptc.resources import schema_path

    return json.loads(schema_path("config.schema.json").read_text(encoding="utf-8"))


def test_schema_is_valid_and_holds_the_valid_case() -> None:
    import tomllib

    import jsonschema

    jsonschema.Draft202012Validator.check_schema(_schema())
    data = tomllib.loads((CONFIG_CASES / "valid.toml").read_text(encoding="utf-8"))
    assert list(jsonschema.Draft202012Validator(_schema()).iter_errors(data)) == []


def _keys(schema: dict, node: dict, prefix: str = "") -> list[str]:
    if "$ref" in node:
        node = schema["$defs"][node["$ref"].split("/")[-1]]
    if "items" in node:
        return _keys(schema, node["items"], prefix)
    out = []
    for key, sub in node.get("properties", {}).items():
        out.append(prefix + key)
        out += _keys(schema, sub, prefix + key + ".")
    return out


def test_every_key_is_documented() -> None:
    docs = (ROOT / "docs" / "configuration.md").read_text(encoding="utf-8")
    keys = _keys(_schema(), _schema())
    assert "robot.max-volume" in keys and "functions.implementation" in keys
    for key in keys:
        name = key.split(".")[-1]
        assert any(f"`{form}`" in docs for form in (name, f"[{name}]", f"[[{name}]]")), \
            f"docs/configuration.md does not describe {key}"


@pytest.mark.parametrize("code", ["C001", "C002", "C005"])
def test_explanation_examples_trigger_their_code(tmp_path: Path, code: str) -> None:
    from scriptc.diagnostics.codes import explanation

    example = explanation(code).split("```toml\n", 1)[1].split("```", 1)[0]
    (tmp_path / "scriptc.toml").write_text(example, encoding="utf-8")
    assert code in [d.code for d in load_config(str(tmp_path / "scriptc.toml")).diagnostics]


# ---------------------------------------------------------------------------------------------
# the fast path: jsonschema only when the configuration changed


PROBE = """
import json, sys
from scriptc.cli.main import main
sys.argv = ["scriptc", *json.loads(sys.argv[1])]
try:
    main()
except SystemExit:
    pass
sys.__stderr__.write("\\nMODULES " + json.dumps(sorted({m.split(".")[0] for m in sys.modules})))
"""


def _modules(args: list[str], cwd: Path) -> set[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "NO_COLOR")}
    done = subprocess.run([sys.executable, "-c", PROBE, json.dumps(args)], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=60, check=False)
    return set(json.loads(done.stderr[done.stderr.rindex("MODULES ") + 8:]))


@pytest.mark.slow
def test_jsonschema_is_imported_only_when_the_configuration_changed(tmp_path: Path) -> None:
    (tmp_path / "scriptc.toml").write_text('[lint]\nignore = ["F003"]\n')
    (tmp_path / "a.script").write_text("[a]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n")
    assert "jsonschema" in _modules(["lint", "a.script"], tmp_path)
    second = _modules(["lint", "a.script"], tmp_path)
    assert not second & {"jsonschema", "lark", "rich", "pathspec"}, second
    (tmp_path / "scriptc.toml").write_text('[lint]\nignore = ["F001"]\n')
    assert "jsonschema" in _modules(["lint", "a.script"], tmp_path)


def test_config_severity_is_what_diagnostics_get() -> None:
    s = build_settings({"lint": {"severity": {"M004": "error"}}})
    (d,) = s.apply([_d("M004")])
    assert d.severity is Severity.ERROR


# ---------------------------------------------------------------------------------------------
# The commands that compile or run stop at an error of the configuration


GOOD = ("[a]\n[goal:g]\n[action]\n[b##blk_inst: MV(\"0.1, 0, 0, 0, 100\") LD() AO()]\n"
        "[b##blk_terminus]\n")


@pytest.mark.parametrize("args", [["compile", "a.script", "-o", "a.json"],
                                  ["run", "a.script", "--robot", "kinematic"],
                                  ["lint", "a.script"]])
def test_an_error_in_the_configuration_stops_compile_and_run(tmp_path: Path, args) -> None:
    """A script is not compiled or run under a configuration that does not say what was meant
    (here a flash rate below 1): the error is shown, nothing is written, the status is 1."""
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    (tmp_path / "scriptc.toml").write_text("[robot]\nmax-led-flash-rate = 0\n")
    (tmp_path / "a.script").write_text(GOOD)
    cwd = os.getcwd()
    try:
        os.chdir(tmp_path)
        result = CliRunner().invoke(cli, args, catch_exceptions=False)
    finally:
        os.chdir(cwd)
    assert result.exit_code == 1
    shown = result.stdout + result.stderr  # lint reports on stdout, the others on stderr
    assert "C002" in shown and "max-led-flash-rate" in shown
    assert not (tmp_path / "a.json").exists()
    if args[0] != "lint":
        assert "fix the configuration first: nothing was done" in result.stderr
        assert result.stdout == ""


def test_a_warning_in_the_configuration_does_not_stop_compile(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    (tmp_path / "scriptc.toml").write_text('[lint]\nignore = ["L099"]\n')  # C004, a warning
    (tmp_path / "a.script").write_text(GOOD)
    out = tmp_path / "a.json"
    result = CliRunner().invoke(cli, ["compile", str(tmp_path / "a.script"), "-o", str(out)],
                                catch_exceptions=False)
    assert result.exit_code == 0 and "C004" in result.stderr and out.exists()


def test_a_script_loaded_during_a_run_is_refused_under_a_broken_configuration(
        tmp_path: Path) -> None:
    """A rule or an update may load a script by path while a run goes on: one from a
    repository whose configuration has an error is refused (a LoadError the session reports),
    not run with the defaults."""
    from scriptc.ops.programs import ProgramLoader
    from scriptc.runtime.loading import LoadError

    _loader = ProgramLoader()

    (tmp_path / "scriptc.toml").write_text("[robot]\nmax-linear-speed = 0\n")
    script = tmp_path / "a.script"
    script.write_text(GOOD)
    with pytest.raises(LoadError, match=r"configuration of .* has errors"):
        _loader(str(script))
    (tmp_path / "scriptc.toml").write_text("[robot]\nmax-linear-speed = 1\n")
    assert _loader(str(script)).name
