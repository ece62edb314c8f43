"""The thesis JSON back end (`scriptc.emit.json`): the golden files of the thesis, the layout,
key order and value types of docs/json.md, and what the back end refuses."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from scriptc.emit.json import EmitError, emit_json, label_paths
from scriptc.frontend.script import lower_script
from scriptc.frontend.thesis_json import _validator
from scriptc.ir import nodes as ir
from scriptc.source import SourceFile, Span

DATA = Path(__file__).parent / "data"
EMIT_CASES = Path(__file__).parent / "cases" / "emit"
S = Span(0, 0)


def compile_text(text: str) -> str:
    script, diagnostics = lower_script(SourceFile("test.script", text))
    errors = [d for d in diagnostics if d.severity.value == "error"]
    assert script is not None and not errors, diagnostics
    return valid(emit_json(script))


def valid(out: str) -> str:
    """`out`, after checking that it satisfies schemas/thesis-script.schema.json."""
    assert [e.message for e in _validator().iter_errors(json.loads(out))] == []
    return out


def ordered(value):
    """A JSON value with every object turned into its list of items, so that comparing two
    values compares key order too."""
    if isinstance(value, dict):
        return [(k, ordered(v)) for k, v in value.items()]
    if isinstance(value, list):
        return [ordered(v) for v in value]
    return value


# -- the thesis's files -----------------------------------------------------------------------


def test_listing_4_1_compiles_to_the_scriptgen_file_byte_for_byte() -> None:
    text = (EMIT_CASES / "test_act.script").read_text(encoding="utf-8")
    expected = (DATA / "script_gen_test_act.json").read_bytes()
    out = compile_text(text)
    assert ordered(json.loads(out)) == ordered(json.loads(expected))
    assert out.encode("utf-8") == expected


def test_dance_example_compiles_byte_for_byte() -> None:
    text = (EMIT_CASES / "dance_example.script").read_text(encoding="utf-8")
    assert compile_text(text).encode("utf-8") == (DATA / "dance_example.json").read_bytes()


def test_listing_4_1_with_the_absolute_path_is_the_repository_file() -> None:
    text = (EMIT_CASES / "test_act.script").read_text(encoding="utf-8").replace(
        '"plugins/audio_control', '"/home/EDITTHIS/Teo_Architecture/plugins/audio_control')
    assert compile_text(text).encode("utf-8") == (DATA / "test_act.json").read_bytes()


# -- layout -----------------------------------------------------------------------------------

MINIMAL = """[a]
[goal:g]
  [action]
    [b##blk_terminus]
"""


def test_layout_of_a_minimal_script() -> None:
    assert compile_text(MINIMAL) == (
        '{\n"activityname":"a",\n"alfarulemessages":[\n],\n"omegarulemessages":[\n],\n'
        '"goal0":{\n"goalid":"g",\n"act0":{\n"blk0":{\n"type":"terminus"\n}\n}\n}\n}\n'
    )


@pytest.mark.parametrize("name", ["features.script", "test_act.script", "dance_example.script"])
def test_every_line_is_one_element(name: str) -> None:
    """ScriptGen's layout, as the emitter writes it: no indentation, and each line one element:
    a bracket, a key with a scalar, a key opening an object or a list, or one string of a list."""
    out = compile_text((EMIT_CASES / name).read_text(encoding="utf-8"))
    for line in out.splitlines():
        assert line == line.strip(), line
        if line in ("{", "}", "]", "},", "],"):
            continue
        element = line.removesuffix(",")
        if element.endswith(("{", "[")):
            json.loads("{" + element[:-1] + "0}")  # one key, then the bracket
            continue
        try:
            value = json.loads(element)
        except json.JSONDecodeError:  # not a value alone: a key and its value
            (value,) = json.loads("{" + element + "}").values()
            assert not isinstance(value, (dict, list)), line
        else:
            assert isinstance(value, str), line


def test_key_order_and_value_types() -> None:
    out = json.loads(compile_text(
        '[k]\n[alfa:7, r, "in", "out", A, M]\n[alfa:0, s, "", "", B, U]\n'
        '[omega:1, r, "", "", D, L]\n'
        '[goal:g]\n[action]\n'
        '[b#x#blk_inst: MV("+0.25, -0.5, 1.0, 007, 1500") LD("0.5, 0, 1, 1, 0, 250") '
        'AO("a, b.wav, 3, 4")]\n'
        '[b##blk_jump: CND(! {TRUE}) TRJMP(x) FLSJMP()]\n'
        '[b##blk_sens: "p"]\n'
        '[action]\n[b#y#blk_terminus]\n'
        '[goal:h]\n[action]\n[b##blk_jump: CND({TRUE}) TRJMP() FLSJMP(y)]\n'
    ))
    assert list(out) == ["activityname", "alfarulemessages", "omegarulemessages", "goal0", "goal1"]
    assert out["alfarulemessages"][0] == {
        "rulecode": 7, "id": "r", "intopic": "in", "outtopic": "out", "action": 65, "mutexcmd": 77}
    assert list(out["alfarulemessages"][0]) == ["rulecode", "id", "intopic", "outtopic", "action",
                                                "mutexcmd"]
    messages = out["alfarulemessages"] + out["omegarulemessages"]
    assert [m["action"] for m in messages] == [65, 66, 68]
    assert [m["mutexcmd"] for m in messages] == [77, 85, 76]
    goal0 = out["goal0"]
    assert list(goal0) == ["goalid", "act0", "act1"]
    blk0 = goal0["act0"]["blk0"]
    assert list(blk0) == ["type", "flagged", "move", "led", "audioout"]
    assert blk0["move"] == [{"v_x": "+0.25", "v_y": "-0.5", "v_theta": "1.0", "wait_t": 7,
                             "duration": 1500}]
    assert list(blk0["move"][0]) == ["v_x", "v_y", "v_theta", "wait_t", "duration"]
    assert blk0["led"] == [{"r": "0.5", "g": "0", "b": "1", "turnas": 1, "wait_t": 0,
                            "duration": 250}]
    assert list(blk0["led"][0]) == ["r", "g", "b", "turnas", "wait_t", "duration"]
    assert blk0["audioout"] == [{"track_path": "a, b.wav", "wait_t": 3, "duration": 4}]
    jump = goal0["act0"]["blk1"]
    assert list(jump) == ["type", "toparse", "truejump", "falsejump"]
    assert jump == {"type": "jump", "toparse": "! {TRUE}", "truejump": "goal0/act0/blk0",
                    "falsejump": ""}
    assert goal0["act0"]["blk2"] == {"type": "sensor", "payload": ["p"]}
    assert out["goal1"]["act0"]["blk0"] == {
        "type": "jump", "toparse": "{TRUE}", "truejump": "", "falsejump": "goal0/act1/blk0"}


def test_strings_are_escaped_and_non_ascii_is_raw_utf8() -> None:
    out = compile_text(
        '[a]\n[alfa:0, r, "\\\\in", "say \\"hi\\"", C, U]\n[goal:g]\n[action]\n'
        '[b##blk_inst: MV() LD() AO("canzone più bella.wav, 0, 1")]\n'
        '[b##blk_sens: "tab\there"]\n'
    )
    assert '"intopic":"\\\\in"' in out
    assert '"outtopic":"say \\"hi\\""' in out
    assert '"track_path":"canzone più bella.wav"' in out
    assert '"tab\\there"' in out
    assert "\\u" not in out
    assert json.loads(out)["alfarulemessages"][0]["outtopic"] == 'say "hi"'


def test_sensor_block_without_payload() -> None:
    out = compile_text("[a]\n[goal:g]\n[action]\n[b##blk_sensor]\n")
    assert '"blk0":{\n"type":"sensor",\n"payload":[\n]\n}' in out


# -- IR built by hand -------------------------------------------------------------------------


def n(text: str) -> ir.Number:
    return ir.Number(text, S)


def name(text: str) -> ir.Name:
    return ir.Name(text, S)


def script_of(*blocks: ir.Block, alfa=(), omega=()) -> ir.Script:
    return ir.Script(name("s"), tuple(alfa), tuple(omega),
                     (ir.Goal(name("g"), (ir.Action(tuple(blocks), S),), S),), S)


def test_hand_built_ir() -> None:
    move = ir.MoveCommand(n("1"), n("0"), n("0"), n("1000.0"), n("1e3"), S)
    block = ir.InstructionBlock(name("here"), (move,), (), (), S)
    jump = ir.JumpBlock(None, ir.Condition((), (ir.TrueEvaluation(S),), S), name("here"), None, S)
    out = json.loads(valid(emit_json(script_of(block, jump))))
    assert out["goal0"]["act0"]["blk0"]["move"][0]["wait_t"] == 1000
    assert out["goal0"]["act0"]["blk0"]["move"][0]["duration"] == 1000
    assert out["goal0"]["act0"]["blk1"]["truejump"] == "goal0/act0/blk0"


def test_label_paths() -> None:
    s = script_of(ir.TerminusBlock(name("a"), S), ir.TerminusBlock(None, S),
                  ir.TerminusBlock(name("c"), S))
    assert label_paths(s) == {"a": "goal0/act0/blk0", "c": "goal0/act0/blk2"}


def _one_move(wait_t: str) -> ir.Script:
    """A script of one block moving once, after `wait_t`."""
    move = ir.MoveCommand(n("1"), n("0"), n("0"), n(wait_t), n("1"), S)
    return script_of(ir.InstructionBlock(None, (move,), (), (), S))


@pytest.mark.parametrize("bad, message", [
    (lambda: script_of(ir.JumpBlock(None, ir.Condition((), (), S), name("nowhere"), None, S)),
     "no block carries"),
    (lambda: script_of(ir.TerminusBlock(name("a"), S), ir.TerminusBlock(name("a"), S)),
     "on two blocks"),
    (lambda: _one_move("1.5"), "not a whole number"),
    (lambda: _one_move("x"), "not a number"),
    (lambda: _one_move("9" * 400), "too large"),
    (lambda: script_of(ir.TerminusBlock(None, S), alfa=(ir.RuleMessage(
        "alfa", n("0"), name("r"), ir.Text("", S), ir.Text("", S), name("AB"), name("U"), S),)),
     "not a single letter"),
])
def test_what_cannot_be_written_raises(bad, message) -> None:
    with pytest.raises(EmitError, match=message):
        emit_json(bad())


@pytest.mark.parametrize("text", ["0", "7", "007", "0000", "1500", "9" * 18, "9" * 19,
                                  "0" * 30 + "12", "9" * 309])
def test_whole_number_times_are_written_as_json_integers(text: str) -> None:
    block = ir.InstructionBlock(None, (ir.MoveCommand(n("1"), n("0"), n("0"), n(text), n("1"), S),),
                                (), (), S)
    out = json.loads(emit_json(script_of(block)))
    assert out["goal0"]["act0"]["blk0"]["move"][0]["wait_t"] == int(text)
    assert f'"wait_t":{int(text)},' in emit_json(script_of(block))


def test_empty_containers_keep_the_layout() -> None:
    s = ir.Script(name("s"), (), (), (ir.Goal(name("g"), (ir.Action((), S),), S),), S)
    assert emit_json(s).endswith('"act0":{\n}\n}\n}\n')


# -- size -------------------------------------------------------------------------------------


@pytest.mark.slow
def test_ten_thousand_blocks_emit_quickly() -> None:
    """A smoke test against quadratic behaviour; bench figures are in the report (typically
    0.05-0.1 s here). The bound is loose because CI machines are shared."""
    lines = ["[big]", "[goal:g]", "[action]"]
    for i in range(10_000):
        if i % 3 == 0:
            lines.append(f'[b#l{i}#blk_inst: MV("0.1, 0, 0, 10, 100") LD("1, 0, 0, 1, 0, 100") '
                         'AO("Silence, 0, 1")]')
        elif i % 3 == 1:
            lines.append("[b##blk_jump: CND({CLASS #Human U ?k (?THIS>&positionrho OP< 1.5)} "
                         f"! {{E: gt(?k>&permanencetime, 2000)}}) TRJMP(l{i - 1}) FLSJMP()]")
        else:
            lines.append("[b##blk_terminus]")
    script, _ = lower_script(SourceFile("big.script", "\n".join(lines)))
    best = min(_timed(lambda: emit_json(script)) for _ in range(3))
    assert best < 1.0
    assert emit_json(script).count('"type":"jump"') == 3333


def _timed(f) -> float:
    start = time.perf_counter()
    f()
    return time.perf_counter() - start


def test_commands_one_field_apart_are_written_apart() -> None:
    """The back end writes each distinct command once (by `MoveCommand.texts`): commands that
    differ in one field only, and commands alike, are each written with their own fields."""
    move, led = ["0", "0", "0", "0", "5"], ["1", "0", "0", "0", "0", "5"]
    audio = ["a.wav", "0", "5"]
    blocks: list[tuple[list[str], list[str], list[str]]] = [(move, led, audio)] * 2
    for i in range(len(move)):
        blocks.append(([*move[:i], "1", *move[i + 1:]], led, audio))
    for i in range(len(led)):
        blocks.append((move, [*led[:i], "1" if led[i] != "1" else "0", *led[i + 1:]], audio))
    for i in range(len(audio)):
        blocks.append((move, led, [*audio[:i], "b.wav" if i == 0 else "1", *audio[i + 1:]]))
    text = "[s]\n[goal:g]\n[action]\n" + "".join(
        f'[b##blk_inst: MV("{", ".join(m)}") LD("{", ".join(d)}") AO("{", ".join(a)}")]\n'
        for m, d, a in blocks) + "[b##blk_terminus]\n"
    written = json.loads(compile_text(text))["goal0"]["act0"]
    for b, (m, d, a) in enumerate(blocks):
        block = written[f"blk{b}"]
        assert [[str(v) for v in c.values()] for c in block["move"]] == [m]
        assert [[str(v) for v in c.values()] for c in block["led"]] == [d]
        assert [[str(v) for v in c.values()] for c in block["audioout"]] == [a]
