"""The Python API for script generators (`scriptc.api`, docs/api.md) and the example generator
(`examples/generator.py`)."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.analysis.analyze import analyze_script
from scriptc.api import (
    Activity,
    BuildError,
    Built,
    audio,
    build_text,
    fill,
    fill_text,
    led,
    move,
    number_text,
)
from scriptc.bytecode.decode import decode
from scriptc.cli.main import cli
from scriptc.ops.build import emit
from scriptc.source import SourceFile

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data"
GENERATOR = ROOT / "examples" / "generator.py"


def dance() -> Activity:
    act = Activity("dance")
    act.alfa(0, "kick_starter", action="C", mutex="U")
    act.omega(0, "kick_starter", action="R", mutex="L")
    a = act.goal("dance").action()
    a.instruction(moves=[move(0.2, 0, 0, wait=0, duration=1000)],
                  leds=[led(0, 0, 1, wait=0, duration=1000)], label="start")
    a.jump("{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE}", true="start")
    a.terminus()
    return act


def broken() -> Activity:
    """A jump to a label no block carries, a colour out of range, and no terminus."""
    act = Activity("broken")
    a = act.goal("g").action()
    a.instruction(leds=[led(2, 0, 0, wait=0, duration=100)], label="x")
    a.jump("! {TRUE}", true="nowhere")
    return act


# ---------------------------------------------------------------------------------------------
# the builder


def test_builder_prints_the_canonical_script_text():
    assert dance().build().script_text == (
        "[dance]\n"
        '[alfa:0, kick_starter, "", "", C, U]\n'
        '[omega:0, kick_starter, "", "", R, L]\n'
        "[goal:dance]\n"
        "  [action]\n"
        '    [b#start#blk_inst: MV("0.2, 0, 0, 0, 1000") LD("0, 0, 1, 1, 0, 1000") AO()]\n'
        # wider than the line: wrapped as the formatter wraps it
        "    [b##blk_jump: CND({CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE})\n"
        "                  TRJMP(start) FLSJMP()]\n"
        "    [b##blk_terminus]\n"
    )


def test_a_clean_build_gives_json_and_bytecode():
    built = dance().build()
    assert built.ok and built.diagnostics == []
    data = json.loads(built.json())
    assert data["activityname"] == "dance"
    blk0 = data["goal0"]["act0"]["blk0"]
    assert blk0["move"][0] == {"v_x": "0.2", "v_y": "0", "v_theta": "0", "wait_t": 0,
                               "duration": 1000}
    assert data["goal0"]["act0"]["blk1"]["truejump"] == "goal0/act0/blk0"
    # The same outputs as `scriptc compile`'s on the same text.
    analysis = analyze_script(SourceFile("dance.script", built.script_text))
    assert built.json() == emit(analysis.script, "json")
    code = built.bytecode()
    assert isinstance(code, bytes) and code == emit(analysis.script, "bytecode", analysis.source)
    decode(code)  # well formed


def test_several_goals_actions_and_blocks_keep_their_order():
    act = Activity("multi")
    g0 = act.goal("first")
    g0.action().jump("! {TRUE}", true="b", label="a").jump("! {TRUE}", false="a", label="b")
    g0.action().sensor("hello", "wor\"ld", label="s")
    act.goal("second").action().terminus(label="end")
    assert act.build().script_text.splitlines() == [
        "[multi]",
        "[goal:first]",
        "  [action]",
        "    [b#a#blk_jump: CND(! {TRUE}) TRJMP(b) FLSJMP()]",
        "    [b#b#blk_jump: CND(! {TRUE}) TRJMP() FLSJMP(a)]",
        "  [action]",
        '    [b#s#blk_sens: "hello", "wor\\"ld"]',
        "[goal:second]",
        "  [action]",
        "    [b#end#blk_terminus]",
    ]


def test_errors_have_the_cli_codes_and_no_outputs():
    built = broken().build()
    assert not built.ok
    assert built.codes == ["V004", "F003", "L003"]  # sorted by position, as the CLI shows
    with pytest.raises(BuildError, match="cannot be compiled"):
        built.json()
    with pytest.raises(BuildError):
        built.bytecode()
    report = built.report()
    assert "broken.script:" in report and "nowhere" in report
    assert json.loads(built.report("json"))


def _cli_diagnostics(tmp_path: Path, monkeypatch, text: str) -> list[dict]:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("SCRIPTC_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "gen.script").write_text(text, encoding="utf-8", newline="")
    result = CliRunner().invoke(cli, ["lint", "--format", "json", "gen.script"],
                                catch_exceptions=False)
    return json.loads(result.stdout)


@pytest.mark.parametrize("make", [dance, broken])
def test_diagnostics_equal_the_cli_on_the_same_text(make, tmp_path, monkeypatch):
    built = make().build(path="gen.script")
    ours = json.loads(built.report("json"))
    assert ours == _cli_diagnostics(tmp_path, monkeypatch, built.script_text)


def test_a_broken_condition_is_reported_inside_the_generated_text(tmp_path, monkeypatch):
    act = Activity("c")
    a = act.goal("g").action()
    a.jump("{CLASS #Nobody U ?kid ()} ! {E: gt(?kid>&nofield, 1)}", true="e")
    a.terminus(label="e")
    built = act.build(path="gen.script")
    assert not built.ok and built.codes == ["R001"]
    for d in built.errors:
        # Every error points into the condition the caller wrote.
        start = built.script_text.index("CND(") + 4
        assert start <= d.span.start < built.script_text.index(") TRJMP")
    assert json.loads(built.report("json")) == _cli_diagnostics(tmp_path, monkeypatch,
                                                                built.script_text)


def test_syntax_errors_in_names_are_diagnostics_not_exceptions():
    act = Activity("bad name")
    act.goal("g").action().terminus()
    built = act.build()
    assert not built.ok
    assert built.errors[0].span.start < built.script_text.index("\n")


def test_commands_are_type_checked():
    with pytest.raises(ValueError, match="move"):
        Activity("a").goal("g").action().instruction(moves=[led(0, 0, 0, duration=1)])
    with pytest.raises(ValueError, match="condition"):
        Activity("a").goal("g").action().jump(None)  # type: ignore[arg-type]  # on purpose


# ---------------------------------------------------------------------------------------------
# numbers and strings


@pytest.mark.parametrize("value, text", [
    (0, "0"), (-3, "-3"), (0.2, "0.2"), (1.0, "1.0"), (1e-7, "1e-07"), ("0.20", "0.20"),
    (" 5 ", "5"), (Decimal("0.10"), "0.10"), ("+1", "+1"),
])
def test_numbers_keep_their_text(value, text):
    assert number_text(value) == text


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, "nan", "inf", "-Infinity",
                                   Decimal("NaN"), True, None, "", "1,2", [1]])
def test_bad_numbers_are_refused(value):
    with pytest.raises(ValueError):
        number_text(value)  # type: ignore[arg-type]  # wrong types on purpose


def test_a_number_text_reaches_the_json_as_written():
    act = Activity("n")
    act.goal("g").action().instruction(moves=[move("0.50", Decimal("1.25"), -0.1, duration=10)]
                                       ).terminus()
    built = act.build()
    mv = json.loads(built.json())["goal0"]["act0"]["blk0"]["move"][0]
    assert (mv["v_x"], mv["v_y"], mv["v_theta"]) == ("0.50", "1.25", "-0.1")
    with pytest.raises(ValueError, match="finite"):
        move(math.nan, 0, 0, duration=1)


def test_a_non_number_text_is_a_diagnostic():
    act = Activity("n")
    act.goal("g").action().instruction(moves=[move("fast", 0, 0, duration=10)]).terminus()
    built = act.build()
    assert not built.ok and built.errors


def test_strings_are_escaped_and_line_breaks_refused():
    act = Activity("s")
    act.alfa(1, "r", intopic='in "q" \\ x', action="C", mutex="U")
    act.omega(1, "r", action="R", mutex="L")
    act.goal("g").action().instruction(audios=[audio('a, "b".wav', duration=10)]).terminus()
    built = act.build()
    assert built.ok, built.report()
    data = json.loads(built.json())
    assert data["alfarulemessages"][0]["intopic"] == 'in "q" \\ x'
    assert data["goal0"]["act0"]["blk0"]["audioout"][0]["track_path"] == 'a, "b".wav'
    with pytest.raises(ValueError, match="line break"):
        audio("a\nb", duration=1)
    with pytest.raises(ValueError, match="blank"):
        audio(" a.wav", duration=1)
    with pytest.raises(ValueError, match="line break"):
        Activity("x\ny")


# ---------------------------------------------------------------------------------------------
# templates

TEMPLATE = """\
% ${name}: a template; $$ is a dollar, "${name}" in a comment is plain text %
[${name}]
[alfa:0, kick_starter, "${topic}", "", C, U]
[omega:0, kick_starter, "", "", R, L]
[goal:g]
  [action]
    [b#start#blk_inst: MV("${speed}, 0, 0, 0, ${ms}") LD() AO("${song}, 0, ${ms}")]
    [b##blk_jump: CND(${cond}) TRJMP(${target}) FLSJMP()]
    [b#end#blk_terminus]
"""


def test_fill_replaces_placeholders_and_escapes_inside_strings():
    text = fill_text(TEMPLATE, name="tpl", topic='say "hi" \\o/', speed=0.25, ms=1500,
                     song="songs/a.wav", cond="! {TRUE}", target="end")
    assert text.startswith('% tpl: a template; $ is a dollar, "tpl" in a comment')
    assert '[alfa:0, kick_starter, "say \\"hi\\" \\\\o/", "", C, U]' in text
    assert 'MV("0.25, 0, 0, 0, 1500")' in text and "CND(! {TRUE}) TRJMP(end)" in text
    built = fill(TEMPLATE, {"name": "tpl", "topic": 'say "hi"', "speed": 0.25, "ms": 1500,
                            "song": "songs/a.wav", "cond": "! {TRUE}", "target": "end"})
    assert isinstance(built, Built) and built.ok, built.report()
    data = json.loads(built.json())
    assert data["alfarulemessages"][0]["intopic"] == 'say "hi"'
    assert data["goal0"]["act0"]["blk1"]["truejump"] == "goal0/act0/blk2"


def test_fill_reports_missing_unused_and_malformed_placeholders():
    with pytest.raises(ValueError, match=r"no value for the placeholder `\$\{b\}`"):
        fill_text("[${a}] ${b}", a="x")
    with pytest.raises(ValueError, match="no placeholder uses `c`"):
        fill_text("[${a}]", a="x", c=1)
    with pytest.raises(ValueError, match="malformed"):
        fill_text("[${1a}]")
    with pytest.raises(ValueError, match="finite"):
        fill_text("[${a}]", a=math.inf)
    with pytest.raises(ValueError, match="line break"):
        fill_text('["${a}"]', a="x\ny")


def test_fill_leaves_attributes_of_the_language_alone():
    cond = "{ATT ?kid $mood U F: str(\"calm\")} ! {TRUE}"
    assert fill_text("CND(" + cond + ") ${x}", x=1) == "CND(" + cond + ") 1"


def test_a_filled_template_with_errors_reports_them():
    built = fill(TEMPLATE, path="t.script", name="tpl", topic="", speed=0.25, ms=1500,
                 song="songs/a.wav", cond="! {TRUE}", target="missing")
    assert not built.ok and "t.script:" in built.report()
    with pytest.raises(BuildError):
        built.json()


def test_build_text_equals_the_library():
    text = (DATA.parent.parent / "examples" / "test_act.script").read_text(encoding="utf-8")
    built = build_text(text, "test_act.script")
    analysis = analyze_script(SourceFile("test_act.script", text))
    assert built.diagnostics == analysis.diagnostics
    assert built.json() == (DATA / "script_gen_test_act.json").read_text(encoding="utf-8")


# ---------------------------------------------------------------------------------------------
# the example generator


@pytest.mark.slow
def test_the_generator_reproduces_the_thesis_dance_example(tmp_path):
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, str(GENERATOR), str(out), "--steps", "5",
                             "--bytecode"], capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 0, result.stderr
    assert "F003" in result.stderr  # the thesis's file has no terminus: an info
    ours = json.loads((out / "dance_example.json").read_text(encoding="utf-8"))
    assert ours == json.loads((DATA / "dance_example.json").read_text(encoding="utf-8"))
    dance5 = json.loads((out / "dance_5.json").read_text(encoding="utf-8"))
    blk0 = dance5["goal0"]["act0"]["blk0"]
    assert len(blk0["move"]) == 5 and len(blk0["led"]) == 5
    assert [m["v_x"] for m in blk0["move"]] == ["0.2", "-0.2", "0.2", "-0.2", "0.2"]
    assert blk0["audioout"][0]["duration"] == 5000
    assert dance5["goal0"]["act0"]["blk1"] == {"type": "terminus"}
    decode((out / "dance_5.scb").read_bytes())


@pytest.mark.slow
@pytest.mark.parametrize(("steps", "message"), [
    ("0", "a dance has 1 to 1000 steps, not 0"),
    ("-3", "a dance has 1 to 1000 steps, not -3"),
    ("1001", "a dance has 1 to 1000 steps, not 1001"),
    ("two", "not a whole number: 'two'"),
])
def test_the_generator_refuses_a_step_count_it_cannot_dance(tmp_path, steps, message):
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, str(GENERATOR), str(out), "--steps", steps],
                            capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 2
    assert result.stderr.splitlines()[-1].endswith(f"error: argument --steps: {message}")
    assert "Traceback" not in result.stderr and not out.exists()


def test_the_generator_says_when_it_cannot_write(tmp_path):
    (tmp_path / "file").write_text("", encoding="utf-8")
    result = subprocess.run([sys.executable, str(GENERATOR), str(tmp_path / "file" / "out")],
                            capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr.startswith(f"error: cannot write in `{tmp_path / 'file' / 'out'}`: ")


# ---------------------------------------------------------------------------------------------
# the documentation


def test_the_python_examples_of_the_documentation_run():
    text = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 4
    for block in blocks:
        exec(compile(block, "docs/api.md", "exec"), {})


def test_the_documented_script_text_is_the_builders():
    text = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    shown = re.search(r"```scriptc\n(.*?)```", text, re.S).group(1)
    assert shown == dance().build().script_text


def test_names_with_line_breaks_are_refused_when_given():
    action = Activity("a").goal("g").action()
    with pytest.raises(ValueError, match="line break"):
        action.jump("! {TRUE}", true="x\ny")
    with pytest.raises(ValueError, match="line break"):
        action.terminus(label="x\r")


def test_a_robot_profile_is_passed_to_the_safety_checks():
    from scriptc.robot.profile import Profile

    act = Activity("fast")
    act.goal("g").action().instruction(moves=[move(0.3, 0, 0, duration=1000)]).terminus()
    assert act.build().ok and "K001" not in act.build().codes
    slow = act.build(profile=Profile(max_linear_speed=0.1))
    assert "K001" in slow.codes


def test_fill_takes_reserved_names_from_the_mapping():
    built = fill("[a]\n[goal:g]\n  [action]\n    [b##blk_inst: MV() LD() AO(\"${path}, 0, 10\")]\n"
                 "    [b##blk_terminus]\n", {"path": "songs/x.wav"}, path="gen.script")
    assert built.ok and built.source.path == "gen.script"
    assert json.loads(built.json())["goal0"]["act0"]["blk0"]["audioout"][0]["track_path"] == \
        "songs/x.wav"


# ---------------------------------------------------------------------------------------------
# the printed script is in the formatter's layout


def _condition_texts():
    from hypothesis import strategies as st
    from test_emit_script import CONDITION

    from scriptc.emit.condition import condition_text

    # The canonical text with its blanks widened (spaces, tabs, line breaks) as a caller may
    # write it: blanks are never removed, which could join two tokens, and strings are kept.
    def widen(text: str, rnd) -> str:
        return re.sub(r'"(?:\\.|[^"\\])*"| ', lambda m: m.group() if m.group() != " " else
                      rnd.choice([" ", "  ", "\t", "\n    "]), text)

    return st.builds(widen, CONDITION.map(condition_text), st.randoms(use_true_random=False))


@pytest.mark.parametrize("make", [dance, broken])
def test_the_built_text_is_already_formatted(make) -> None:
    from scriptc.formatter import format_text

    text = make().build().script_text
    assert format_text(text).text == text


@pytest.mark.slow
def test_generated_conditions_are_printed_in_the_formatters_layout() -> None:
    from hypothesis import HealthCheck, given, settings

    from scriptc.formatter import format_text

    @settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
    @given(_condition_texts())
    def law(condition: str) -> None:
        act = Activity("gen")
        a = act.goal("g").action()
        a.instruction(leds=[led(0, 0, 1, duration=1000)], label="here")
        a.jump(condition, true="here", label="long_enough_to_wrap_now_and_then")
        text = act.script_text()
        assert format_text(text).text == text
        # Only blanks changed: the caller's tokens are all there, in order.
        assert "".join(text.split()).count("".join(condition.split())) == 1

    law()


def test_a_condition_that_is_not_made_of_tokens_is_printed_as_written() -> None:
    act = Activity("raw")
    act.goal("g").action().jump("{CLASS #Human U ?kid (?THIS>&positionrho < 1.0)} ! {TRUE}")
    built = act.build()
    assert "CND({CLASS #Human U ?kid (?THIS>&positionrho < 1.0)} ! {TRUE})" in built.script_text
    assert "P001" in built.codes
