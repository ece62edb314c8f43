"""The canonical script syntax (`scriptc.emit.script.format_script`) and the round trips
through it: JSON -> IR -> script text -> IR -> JSON gives the JSON back."""

from __future__ import annotations

import json
import string
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from scriptc.diagnostics.model import Severity
from scriptc.emit.json import emit_json
from scriptc.emit.script import format_block, format_script
from scriptc.formatter import format_text
from scriptc.frontend.script import lower_script
from scriptc.frontend.thesis_json import _validator, script_from_json
from scriptc.ir import nodes as ir
from scriptc.source import SourceFile, Span

DATA = Path(__file__).parent / "data"
THESIS_FILES = ["test_act.json", "script_gen_test_act.json", "dance_example.json"]
S = Span(0, 0)


def lower(text: str) -> ir.Script:
    script, diagnostics = lower_script(SourceFile("round.script", text))
    errors = [d for d in diagnostics if d.severity is Severity.ERROR]
    assert script is not None and not errors, (text, errors)
    return script


def ordered(value):
    if isinstance(value, dict):
        return [(k, ordered(v)) for k, v in value.items()]
    if isinstance(value, list):
        return [ordered(v) for v in value]
    return value


# -- the thesis's files -----------------------------------------------------------------------


@pytest.mark.parametrize("name", THESIS_FILES)
def test_thesis_file_round_trip(name: str) -> None:
    text = (DATA / name).read_text(encoding="utf-8")
    script, diagnostics = script_from_json(SourceFile(name, text))
    assert script is not None and not diagnostics
    again = emit_json(lower(format_script(script)))
    assert ordered(json.loads(again)) == ordered(json.loads(text))
    assert again == text  # the layout is the thesis's, so the bytes come back too


def test_format_of_listing_4_1() -> None:
    text = (DATA / "script_gen_test_act.json").read_text(encoding="utf-8")
    script, _ = script_from_json(SourceFile("t.json", text))
    lines = format_script(script).splitlines()
    assert lines[:5] == [
        "[test_act]",
        '[alfa:0, kick_starter, "", "", C, U]',
        '[omega:0, kick_starter, "", "", R, L]',
        "[goal:test_act_goal]",
        "  [action]",
    ]
    # Wider than the line: wrapped as the formatter wraps it, one command per line.
    assert lines[5:12] == [
        '    [b#g0_a0_b0#blk_inst: MV("10, 0, 0, 1000, 1000",',
        '                             "0, 10, 0, 1000, 1000",',
        '                             "0, -10, 0, 1000, 1000",',
        '                             "-10, 0, 0, 1000, 1000",',
        '                             "0, 0, 50, 1000, 1000",',
        '                             "0, 0, -50, 1000, 1000")',
        '                          LD("1, 0, 0, 1, 0, 2000",',
    ]
    assert lines[17:] == [
        '                          AO("Silence, 1, 1")]',
        '    [b##blk_inst: MV("0, 0, 0, 1000, 1000")',
        '                  LD("1, 1, 1, 1, 1000, 1000")',
        '                  AO("plugins/audio_control/songs/sounds_Excited_R2D2.wav, 0, 4000")]',
        "    [b##blk_jump: CND(! {TRUE}) TRJMP(g0_a0_b4) FLSJMP()]",
        "    [b##blk_jump: CND(! {TRUE}) TRJMP(g0_a0_b0) FLSJMP()]",
        "    [b#g0_a0_b4#blk_terminus]",
    ]


def test_format_blocks() -> None:
    def name(text: str) -> ir.Name:
        return ir.Name(text, S)

    assert format_block(ir.SensorBlock(None, (), S)) == "[b##blk_sens]"
    payload = (ir.Text('a "b"', S), ir.Text("c\\d", S))
    assert format_block(ir.SensorBlock(name("s"), payload, S)) == \
        '[b#s#blk_sens: "a \\"b\\"", "c\\\\d"]'
    assert format_block(ir.InstructionBlock(None, (), (), (), S)) == "[b##blk_inst: MV() LD() AO()]"
    audio = ir.AudioCommand(ir.Text("a, b.wav", S), ir.Number("0", S), ir.Number("1", S), S)
    assert format_block(ir.InstructionBlock(None, (), (), (audio, audio), S)) == \
        '[b##blk_inst: MV() LD() AO("a, b.wav, 0, 1", "a, b.wav, 0, 1")]'


def test_format_is_a_fixed_point_of_lowering() -> None:
    features = Path(__file__).parent / "cases" / "emit" / "features.script"
    text = features.read_text(encoding="utf-8")
    once = format_script(lower(text))
    assert format_script(lower(once)) == once
    assert emit_json(lower(once)) == emit_json(lower(text))


# -- generated scripts ------------------------------------------------------------------------

NAME = st.from_regex(r"[A-Za-z_][A-Za-z0-9_-]{0,8}", fullmatch=True).filter(
    # Words of the language stay out of names used where the grammar reads keywords.
    lambda s: s not in {"TRUE", "CLASS", "VAR", "ATT", "E", "B", "F", "U", "L", "T", "b", "goal",
                        "action", "alfa", "omega", "OP", "MV", "LD", "AO", "CND", "TRJMP",
                        "FLSJMP", "blk_inst", "blk_jump", "blk_terminus", "blk_sens", "blk_sensor"})
NUMBER = st.one_of(
    st.integers(-10_000, 10_000).map(str),
    st.from_regex(r"[+-]?([0-9]{1,4}\.[0-9]{0,3}|\.[0-9]{1,3})", fullmatch=True),
    st.from_regex(r"[0-9]{1,2}[eE][+-]?[0-9]", fullmatch=True),
)
TIME = st.one_of(st.integers(0, 100_000).map(str), st.just("007"))
# Text of strings: no line break (the script syntax cannot write one), quotes, backslashes,
# commas and non-ASCII included.
TEXT = st.text(alphabet=st.sampled_from(list(string.ascii_letters + string.digits
                                             + ' ,./\\"%#[]()àé€😀')),
               max_size=12)
# Audio paths: blanks, commas, quotes and backslashes included (a path is everything before
# the last two commas of its command string).
PATH = st.text(alphabet=st.sampled_from(list(string.ascii_letters + string.digits + ' ,./_-àé\\"')),
               min_size=1, max_size=16).map(str.strip).filter(bool)
SPAN = st.just(S)


def names(st_text):
    return st.builds(ir.Name, st_text, SPAN)


def numbers(st_text):
    return st.builds(ir.Number, st_text, SPAN)


ALIAS = st.builds(ir.AliasRef, names(NAME.map(lambda s: "?" + s)), SPAN)
VALUE = st.one_of(
    st.builds(ir.NumberValue, numbers(NUMBER)),
    st.builds(ir.StringValue, st.builds(ir.Text, TEXT, SPAN)),
    ALIAS,
    st.builds(ir.FieldRef, ALIAS, names(NAME), SPAN),
    st.builds(ir.AttRef, ALIAS, names(NAME), SPAN),
    st.builds(ir.VarRef, names(NAME.map(lambda s: "@" + s)), SPAN),
)


def calls(kind: str):
    return st.builds(ir.Call, st.just(kind), names(NAME), st.lists(VALUE, max_size=3).map(tuple),
                     SPAN)


SCOPE = names(st.sampled_from(["U", "L", "T"]))
TEST = st.one_of(
    st.builds(ir.FieldTest, names(NAME), names(st.sampled_from(["OP=", "OP<", "OP>"])), VALUE,
              SPAN),
    st.builds(ir.CallTest, calls("B"), SPAN),
)
ASSIGNMENT = st.one_of(
    st.builds(ir.ClassAssignment,
              names(st.sampled_from(["Human", "Obstacle", "Object", "Activity"])),
              SCOPE, ALIAS, st.lists(TEST, max_size=3).map(tuple), SPAN),
    st.builds(ir.VarAssignment, st.builds(ir.VarRef, names(NAME.map(lambda s: "@" + s)), SPAN),
              SCOPE, calls("F"), SPAN),
    st.builds(ir.AttAssignment, ALIAS, names(NAME.map(lambda s: "$" + s)), SCOPE, calls("F"), SPAN),
)
EVALUATION = st.one_of(st.builds(ir.CallEvaluation, calls("E"), SPAN),
                       st.builds(ir.TrueEvaluation, SPAN))
CONDITION = st.one_of(
    st.builds(ir.Condition, st.just(()), st.just(()), SPAN, st.just(True)),
    st.builds(ir.Condition, st.lists(ASSIGNMENT, max_size=3).map(tuple),
              st.lists(EVALUATION, max_size=3).map(tuple), SPAN),
)
MOVE = st.builds(ir.MoveCommand, numbers(NUMBER), numbers(NUMBER), numbers(NUMBER),
                 numbers(TIME), numbers(TIME), SPAN)
LED = st.builds(ir.LedCommand, numbers(NUMBER), numbers(NUMBER), numbers(NUMBER),
                numbers(st.sampled_from(["0", "1"])), numbers(TIME), numbers(TIME), SPAN)
AUDIO = st.builds(ir.AudioCommand, st.builds(ir.Text, PATH, SPAN), numbers(TIME), numbers(TIME),
                  SPAN)
RULE = st.builds(ir.RuleMessage, st.just("alfa"), numbers(st.integers(0, 2**32 - 1).map(str)),
                 names(NAME), st.builds(ir.Text, TEXT, SPAN), st.builds(ir.Text, TEXT, SPAN),
                 names(st.sampled_from("ARDBC")), names(st.sampled_from("LMU")), SPAN)


@st.composite
def scripts(draw) -> ir.Script:
    shape = draw(st.lists(st.lists(st.integers(1, 4), min_size=1, max_size=3), min_size=1,
                          max_size=3))
    count = sum(sum(action) for action in shape)
    labels = [f"l{i}" if draw(st.booleans()) else None for i in range(count)]
    targets = [label for label in labels if label] or [None]
    target = st.one_of(st.none(), st.sampled_from(targets)).map(
        lambda t: ir.Name(t, S) if t else None)
    block_strategy = st.one_of(
        st.tuples(st.just("inst"), st.lists(MOVE, max_size=2), st.lists(LED, max_size=2),
                  st.lists(AUDIO, max_size=2)),
        st.tuples(st.just("jump"), CONDITION, target, target),
        st.tuples(st.just("term")),
        st.tuples(st.just("sens"), st.lists(st.builds(ir.Text, TEXT, SPAN), max_size=3)),
    )
    goals = []
    i = 0
    for g, action_sizes in enumerate(shape):
        actions = []
        for size in action_sizes:
            blocks = []
            for _ in range(size):
                label = ir.Name(labels[i], S) if labels[i] else None
                i += 1
                kind, *parts = draw(block_strategy)
                if kind == "inst":
                    blocks.append(ir.InstructionBlock(label, tuple(parts[0]), tuple(parts[1]),
                                                      tuple(parts[2]), S))
                elif kind == "jump":
                    blocks.append(ir.JumpBlock(label, parts[0], parts[1], parts[2], S))
                elif kind == "term":
                    blocks.append(ir.TerminusBlock(label, S))
                else:
                    blocks.append(ir.SensorBlock(label, tuple(parts[0]), S))
            actions.append(ir.Action(tuple(blocks), S))
        goals.append(ir.Goal(ir.Name(f"goal_{g}", S), tuple(actions), S))
    alfa = tuple(draw(st.lists(RULE, max_size=2)))
    omega = tuple(m.__class__(**{**{f: getattr(m, f) for f in m.__slots__}, "kind": "omega"})
                  for m in draw(st.lists(RULE, max_size=2)))
    return ir.Script(ir.Name(draw(NAME), S), alfa, omega, tuple(goals), S)


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scripts())
def test_script_text_round_trip(script: ir.Script) -> None:
    """IR -> script text -> IR gives the same JSON."""
    assert emit_json(lower(format_script(script))) == emit_json(script)


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scripts())
def test_json_round_trip(script: ir.Script) -> None:
    """IR -> JSON -> IR -> JSON is the identity on the text, and the reader's script prints
    as script text that compiles to the same JSON."""
    out = emit_json(script)
    assert [e.message for e in _validator().iter_errors(json.loads(out))] == []
    back, diagnostics = script_from_json(SourceFile("gen.json", out))
    assert back is not None and not diagnostics, diagnostics
    assert emit_json(back) == out
    assert emit_json(lower(format_script(back))) == out


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scripts())
def test_printed_and_decompiled_scripts_are_already_formatted(script: ir.Script) -> None:
    """One layout: the printer's text of any IR, and of the script read back from its JSON
    (what `scriptc decompile` writes), is a fixpoint of the formatter."""
    text = format_script(script)
    assert format_text(text).text == text
    back, _ = script_from_json(SourceFile("gen.json", emit_json(script)))
    decompiled = format_script(back)
    assert format_text(decompiled).text == decompiled


@pytest.mark.parametrize("name", THESIS_FILES)
def test_decompiled_thesis_files_pass_fmt_check(name: str, tmp_path: Path) -> None:
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    out = tmp_path / "out.script"
    runner = CliRunner()
    assert runner.invoke(cli, ["decompile", str(DATA / name), "-o", str(out)]).exit_code in (0, 1)
    checked = runner.invoke(cli, ["fmt", "--check", str(out)])
    assert (checked.exit_code, checked.output) == (0, "")
