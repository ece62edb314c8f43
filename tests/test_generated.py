"""Every file that repeats a fact of the code is written from it (`python -m scriptc.generate`,
src/scriptc/generate.py), and every reader agrees with the fact's one home: what a name and a
number are (src/scriptc/language.py), and the robot's limits (src/scriptc/robot/limits.py)."""

from __future__ import annotations

import json
import re
import shutil
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from scriptc import generate, language
from scriptc.robot.limits import BY_KEY, LIMITS, MISSING_LIMIT_RULE, toml_section
from scriptc.robot.profile import DEFAULT_PROFILE
from scriptc.source import SourceFile

ROOT = Path(__file__).parent.parent
FAST = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])


# -- the generated files ------------------------------------------------------------------------


@pytest.mark.parametrize("target", sorted(generate.TARGETS))
def test_the_file_is_what_the_code_writes(target: str) -> None:
    old, new = generate.generated(target)
    assert old == new, f"{target} is stale: run `python -m scriptc.generate`"


def test_a_stale_file_is_found_and_rewritten(tmp_path: Path) -> None:
    for target in generate.TARGETS:
        (tmp_path / target).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(ROOT / target, tmp_path / target)
    assert generate.stale(tmp_path) == []
    schema = tmp_path / "schemas" / "config.schema.json"
    schema.write_text(schema.read_text(encoding="utf-8").replace('"minimum": 1', '"minimum": 2'),
                      encoding="utf-8")
    robot = tmp_path / "docs" / "robot.md"
    robot.write_text(robot.read_text(encoding="utf-8").replace("| 0.5 m/s |", "| 0.7 m/s |"),
                     encoding="utf-8")
    assert generate.stale(tmp_path) == ["schemas/config.schema.json", "docs/robot.md"]
    for target in generate.stale(tmp_path):
        (tmp_path / target).write_text(generate.generated(target, tmp_path)[1], encoding="utf-8")
    assert generate.stale(tmp_path) == []
    assert (tmp_path / "docs" / "robot.md").read_text(encoding="utf-8") == \
        (ROOT / "docs" / "robot.md").read_text(encoding="utf-8")


def test_a_region_the_code_does_not_write_is_an_error() -> None:
    rewrite = generate.TARGETS["docs/robot.md"]
    text = (ROOT / "docs" / "robot.md").read_text(encoding="utf-8")
    with pytest.raises(ValueError, match="generated regions"):
        rewrite(text + "\n<!-- generated: unknown -->\n<!-- end: unknown -->\n")
    with pytest.raises(ValueError, match="generated regions"):
        rewrite(text.replace("<!-- generated: robot-profile -->", ""))


def test_check_names_the_stale_files_and_writes_nothing(capsys) -> None:
    assert generate.main(["--check"]) == 0
    assert capsys.readouterr().out == ""


# -- a name is a name everywhere ----------------------------------------------------------------

CANDIDATES = st.one_of(
    st.from_regex(language.NAME_PATTERN, fullmatch=True),
    st.text(alphabet="aZ_-09é٣ .#?@$\"%OP=<>", max_size=8),
    st.sampled_from(["wave-hands", "_x", "9lives", "x-", "-x", "aé", "a٣", "OP", "b", "TRUE"]),
)


def _tmgrammar() -> dict:
    return json.loads((ROOT / "lsp/vscode/syntaxes/scriptc.tmLanguage.json")
                      .read_text(encoding="utf-8"))


def _schema_name(name: str) -> str:
    return json.loads((ROOT / "schemas" / name).read_text(encoding="utf-8"))["$defs"]["name"][
        "pattern"]


def _registers(name: str) -> bool:
    from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS

    try:
        STANDARD_IMPLEMENTATIONS.extended().register(name, "E", 0, lambda call: True)
    except ValueError:
        return False
    return True


@pytest.mark.slow
@FAST
@given(CANDIDATES)
@example("aé")
@example("a٣")
def test_every_reader_agrees_on_what_a_name_is(text: str) -> None:
    """The editor's tokens (which read `\\w`, Unicode, before), the printer's, completion's
    word, the TextMate grammar's labels, both schemas, the configuration's loader and the run
    time's registry accept exactly the names of the grammar."""
    from scriptc.emit.printer import _TOKEN as printer_token
    from scriptc.ide.completion import _WORD_CHARS
    from scriptc.ide.tokens import _TOKEN as editor_token
    from scriptc.project.config import build_settings

    name = language.is_name(text)
    editor = editor_token.fullmatch(text)
    assert (editor is not None and editor.lastgroup == "name") == name, text
    printer = printer_token.fullmatch(text)
    assert (printer is not None and printer.lastgroup == "name") == name, text
    if name:
        assert _WORD_CHARS.search("x " + text).group() == text
    repository = _tmgrammar()["repository"]
    label = next(p for p in repository["item-body"]["patterns"]
                 if p.get("name") == "entity.name.label.scriptc")["match"]
    assert (re.fullmatch(label, text) is not None) == name
    for schema in ("config.schema.json", "thesis-script.schema.json"):
        assert (re.search(_schema_name(schema), text) is not None) == name
    declared = build_settings({"functions": [{"name": text, "kind": "E", "arity": 0,
                                              "implementation": "m:f"}]})
    assert bool(declared.functions) == name
    assert _registers(text) == name


NUMBERISH = st.text(alphabet="+-.eE019٣ x", max_size=8)


@FAST
@given(NUMBERISH)
@example("٣")
@example("1e3")
@example(".5")
def test_every_reader_agrees_on_what_a_number_is(text: str) -> None:
    """ASCII digits only: `\\d` took `٣` for a digit in the editor's tokens."""
    from scriptc.emit.printer import _TOKEN as printer_token
    from scriptc.ide.tokens import _TOKEN as editor_token
    from scriptc.ir.fields import NUMBER_RE

    number = re.fullmatch(language.NUMBER_PATTERN, text) is not None
    for token, group in ((editor_token, "number"), (printer_token, "num")):
        m = token.fullmatch(text)
        assert (m is not None and m.lastgroup == group) == number, text
    assert (NUMBER_RE.fullmatch(text) is not None) == number
    tm = _tmgrammar()["repository"]["number"]["match"]
    assert (re.fullmatch(tm, text) is not None) == number
    thesis = json.loads((ROOT / "schemas/thesis-script.schema.json").read_text(encoding="utf-8"))
    assert (re.search(thesis["$defs"]["numberText"]["pattern"], text) is not None) == number


def test_the_editor_grammar_knows_every_word_and_letter() -> None:
    """The words and letters the TextMate grammar colours are the language's."""
    text = json.dumps(_tmgrammar())
    for word in language.GRAMMAR_WORDS | language.ITEM_WORDS:
        assert word in text, word
    repository = _tmgrammar()["repository"]
    rule = {p.get("name"): p["match"] for p in repository["rule-message"]["patterns"]
            if "match" in p}
    actions = rule["constant.language.rule-action.scriptc"]
    mutexes = rule["constant.language.mutex.scriptc"]
    for letter in "ABCDEFGHIJKLMNOPQRSTUVWXYZ":
        assert (re.match(actions, f"{letter},") is not None) == (letter in language.RULE_ACTIONS)
        assert (re.match(mutexes, f"{letter}]") is not None) == (letter in language.MUTEXES)
    assert language.THIS.startswith(language.SIGILS["ALIAS"])


# -- the robot's limits -------------------------------------------------------------------------


def test_the_profile_is_the_table() -> None:
    assert DEFAULT_PROFILE.limits() == {limit.field: limit.default for limit in LIMITS}
    for limit in LIMITS:
        assert limit.accepts(limit.default), limit.key  # a default is a value one may give


VALUES = st.one_of(st.sampled_from([0, 0.0, 1, 1.0, -1, 0.5, 2, 1e-9, 1.0000001]),
                   st.floats(min_value=-3, max_value=3, allow_nan=False))


@pytest.mark.slow
@FAST
@given(st.sampled_from(LIMITS), VALUES)
def test_the_checks_and_the_loader_keep_one_range(limit, value) -> None:
    """A value the schema's checks accept is the profile's; one they reject (C002) keeps the
    default (before: `max-volume`'s maximum and the minimums were written again in the
    loader, and a missing limit was 'not checked' in the schema)."""
    from scriptc.project.config import build_settings
    from scriptc.project.config.validate import check_config

    text = f"[robot]\n{limit.key} = {value!r}\n"
    table = tomllib.loads(text)
    problems = check_config(table, SourceFile("scriptc.toml", text))
    robot = build_settings(table, path="/r/scriptc.toml").robot
    given_value = getattr(robot, limit.field)
    if limit.accepts(value):
        assert problems == [] and given_value == value
    else:
        assert [d.code for d in problems] == ["C002"] and given_value == limit.default


def test_a_limit_not_given_keeps_its_default() -> None:
    from scriptc.project.config import Settings, build_settings

    assert Settings().robot is DEFAULT_PROFILE
    only = build_settings({"robot": {"max-volume": 0.5}}, path="/r/scriptc.toml").robot
    assert only.max_volume == 0.5 and only.source == "/r/scriptc.toml"
    for limit in LIMITS:
        if limit.key != "max-volume":
            assert getattr(only, limit.field) == limit.default
    schema = json.loads((ROOT / "schemas/config.schema.json").read_text(encoding="utf-8"))
    assert MISSING_LIMIT_RULE in schema["$defs"]["robot"]["description"]


def test_init_writes_the_table() -> None:
    from scriptc.cli.init import CONFIG

    assert toml_section() in CONFIG
    robot = tomllib.loads(CONFIG)["robot"]
    assert robot == {limit.key: limit.default for limit in LIMITS}


def test_show_settings_and_the_docs_show_the_defaults() -> None:
    """`show-settings` of a folder without configuration, and every `key = value  # default`
    line of the docs (docs/cli.md shows its output)."""
    from scriptc.project.config.describe import describe

    report = describe(str(ROOT / "tests" / "data"), isolated=True)
    shown = {s.key: s.value for s in report.settings if s.key.startswith("robot.")}
    assert shown == {f"robot.{limit.key}": limit.default for limit in LIMITS}
    lines = 0
    for path in sorted((ROOT / "docs").glob("*.md")):
        for m in re.finditer(r"^([a-z-]+) = ([0-9.]+) +# default$", path.read_text("utf-8"),
                             re.MULTILINE):
            if m.group(1) in BY_KEY:
                lines += 1
                assert float(m.group(2)) == BY_KEY[m.group(1)].default, (path.name, m.group(0))
    assert lines == len(LIMITS)


def test_the_prose_states_the_defaults() -> None:
    """Where the docs and the codes' explanations give a limit's value in passing
    (`max-linear-speed` (0.5 m/s by default)), it is the table's default."""
    texts = [*(ROOT / "docs").glob("*.md"),
             *(ROOT / "src/scriptc/diagnostics/explanations").glob("*.md")]
    found = 0
    for path in texts:
        for m in re.finditer(r"`([a-z-]+)` \(([0-9.]+) ", path.read_text(encoding="utf-8")):
            if m.group(1) in BY_KEY:
                found += 1
                assert float(m.group(2)) == BY_KEY[m.group(1)].default, (path.name, m.group(0))
    assert found >= 5


@FAST
@given(st.text(alphabet="ab_.:9é -", max_size=10))
@example("activity.functions:smiling")
@example("a:é")
def test_the_loader_and_the_schema_read_one_implementation_pattern(text: str) -> None:
    from scriptc.project.config import build_settings

    schema = json.loads((ROOT / "schemas/config.schema.json").read_text(encoding="utf-8"))
    pattern = schema["$defs"]["implementation"]["pattern"]
    declared = build_settings({"rules": [{"name": "r", "implementation": text}]})
    assert bool(declared.rules) == (re.search(pattern, text) is not None)


def test_the_rule_grammar_docs_list_the_languages_letters() -> None:
    """docs/rules.md explains each letter in its own words (tables), docs/language.md names
    them in passing: the letters are the language's, all of them."""
    rules = (ROOT / "docs" / "rules.md").read_text(encoding="utf-8")

    def column(header: str) -> set[str]:
        table = rules[rules.index(f"| {header} |"):]
        table = table[:table.index("\n\n")]
        return set(re.findall(r"^\| `(\w)` \|", table, re.MULTILINE))

    assert column("action") == set(language.RULE_ACTIONS)
    assert column("mutex") == set(language.MUTEXES)
    assert column("scope") == set(language.SCOPES)
    text = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
    assert f"ACTION one of `{' '.join(language.RULE_ACTIONS)}`" in text
    assert f"MUTEX one of `{' '.join(language.MUTEXES)}`" in text
    assert all(f"`{op}`" in rules for op in language.OPERATORS)
