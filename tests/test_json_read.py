"""Reading thesis JSON into the IR (`scriptc.frontend.thesis_json`): J001/J002/J003, spans into the
JSON text, invented labels, and the fast schema check agreeing with jsonschema."""

from __future__ import annotations

import copy
import json
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc.frontend.jsonpos import parse_json
from scriptc.frontend.thesis_json import _is_valid, _validator, invented_label, script_from_json
from scriptc.ir import nodes as ir
from scriptc.source import SourceFile, Span

DATA = Path(__file__).parent / "data"


def read(text: str):
    source = SourceFile("t.json", text)
    script, diagnostics = script_from_json(source)
    return source, script, diagnostics


def doc(**blocks) -> dict:
    return {"activityname": "a", "alfarulemessages": [], "omegarulemessages": [],
            "goal0": {"goalid": "g", "act0": blocks or {"blk0": {"type": "terminus"}}}}


def text_of(source: SourceFile, span: Span) -> str:
    return source.text[span.start:span.end]


# -- J001 -------------------------------------------------------------------------------------


def test_j001_is_at_the_exact_position() -> None:
    source, script, diagnostics = read('{\n  "activityname": "a",\n  "x": [1, 2,]\n}')
    assert script is None
    [d] = diagnostics
    assert d.code == "J001"
    assert d.message == "a comma before `]`: JSON allows no trailing comma"
    assert source.position(d.span.start) == source.position(source.text.index(",]"))
    assert [label.message for label in d.labels] == ["`]` follows the comma"]


def test_j001_labels_the_first_of_two_keys() -> None:
    source, _script, [d] = read('{"activityname": "a", "activityname": "b"}')
    assert (d.code, text_of(source, d.span)) == ("J001", '"activityname"')
    assert d.labels[0].span == Span(1, 15) and d.labels[0].message == "first defined here"


# -- J002 -------------------------------------------------------------------------------------


def test_j002_names_the_path_and_points_at_the_value() -> None:
    d = doc(blk0={"type": "instruction", "flagged": "flag",
                  "move": [{"v_x": "1", "v_y": "0", "v_theta": "0", "wait_t": "1000",
                            "duration": 5}],
                  "led": [], "audioout": []})
    source, script, [problem] = read(json.dumps(d, indent=1))
    assert script is None
    assert problem.code == "J002"
    assert problem.path == "goal0/act0/blk0/move/0/wait_t"
    assert problem.message == ("`goal0/act0/blk0/move/0/wait_t` must be an integer, "
                               'found the string `"1000"`')
    assert problem.help == "write the number without quotes: `1000`"
    assert text_of(source, problem.span) == '"1000"'


def test_j002_missing_and_unknown_keys_point_at_keys() -> None:
    d = doc(blk0={"type": "jump", "toparse": "! {TRUE}", "truejump": "", "colour": 1})
    source, script, problems = read(json.dumps(d))
    assert script is None
    by_path = {p.path: p for p in problems}
    assert set(by_path) == {"goal0/act0/blk0/falsejump", "goal0/act0/blk0/colour"}
    assert text_of(source, by_path["goal0/act0/blk0/falsejump"].span) == '"blk0"'
    assert (by_path["goal0/act0/blk0/falsejump"].message
            == "`goal0/act0/blk0` has no key `falsejump`")
    assert text_of(source, by_path["goal0/act0/blk0/colour"].span) == '"colour"'


def test_j002_numbering() -> None:
    _source, _script, [problem] = read(json.dumps(doc(blk0={"type": "terminus"},
                                                       blk2={"type": "terminus"})))
    assert problem.code == "J002" and problem.path == "goal0/act0/blk2"
    assert problem.message == ("`goal0/act0` has `blk2` but no `blk1`: keys are numbered from 0 "
                               "without gaps")


def test_j002_on_a_deeply_nested_document() -> None:
    depth = 20_000
    text = '{"activityname": ' + "[" * depth + "]" * depth + "}"
    _source, script, problems = read(text)
    assert script is None
    assert {p.code for p in problems} == {"J002"}
    assert any(p.message.startswith("`activityname` must be a string, found an array")
               for p in problems)
    _, script, [problem] = read("[" * depth + "]" * depth)
    assert problem.message == "the top-level value must be an object, found an array"


# -- the fast check agrees with jsonschema --------------------------------------------------

VALID = [json.loads((DATA / name).read_text(encoding="utf-8"))
         for name in ("test_act.json", "script_gen_test_act.json", "dance_example.json")] + [
    doc(blk0={"type": "sensor", "payload": ["a", "b"]},
        blk1={"type": "jump", "toparse": "{TRUE}", "truejump": "goal0/act0/blk0", "falsejump": ""},
        blk2={"type": "terminus"}),
]
# Copied on each draw: a mutation may later change a drawn list or object in place.
REPLACEMENTS = st.sampled_from([None, True, False, 0, 1, 65, 85, 1.5, 1000.0, -3, "", "x", "10",
                                "flag", "jump", "terminus", "sensor", "instruction", "a b",
                                "line\nbreak", " lead", [], [1], ["s"], {},
                                {"type": "terminus"}]).map(copy.deepcopy)


def _paths(value, prefix=()):
    yield prefix
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _paths(v, prefix + (i,))


@st.composite
def mutated(draw):
    document = copy.deepcopy(draw(st.sampled_from(VALID)))
    for _ in range(draw(st.integers(0, 3))):
        paths = [p for p in _paths(document) if p]
        path = draw(st.sampled_from(paths))
        parent = document
        for step in path[:-1]:
            parent = parent[step]
        action = draw(st.sampled_from(["replace", "delete", "add"]))
        if action == "replace":
            parent[path[-1]] = draw(REPLACEMENTS)
        elif action == "delete":
            del parent[path[-1]]
        elif isinstance(parent, dict):
            key = draw(st.sampled_from(["extra", "goal1", "act1", "blk7", "type", "payload"]))
            parent[key] = draw(REPLACEMENTS)
        else:
            parent.append(draw(REPLACEMENTS))
    return document


@pytest.mark.slow
@settings(max_examples=400, deadline=None)
@given(mutated())
def test_fast_check_agrees_with_jsonschema(document) -> None:
    """fastjsonschema's yes or no is jsonschema's, on the document as the reader hands it over
    (from the positioned parse, cut below the schema's depth)."""
    instance = parse_json(json.dumps(document)).to_python(max_depth=10)
    schema_ok = not any(True for _ in _validator().iter_errors(document))
    assert _is_valid(instance) == schema_ok


@pytest.mark.parametrize("value, ok", [(1, True), (1.0, True), (1.5, False), (True, False),
                                       ("1", False), (None, False)])
def test_fast_check_reads_integers_as_json_schema_does(value, ok: bool) -> None:
    """2020-12: a number with a zero fraction is an integer, a boolean is not."""
    document = copy.deepcopy(VALID[0])
    document["goal0"]["act0"]["blk0"] = {"type": "instruction", "flagged": "flag", "move": [],
                                         "led": [], "audioout": [{"track_path": "a.wav",
                                                                  "wait_t": value,
                                                                  "duration": 0}]}
    assert _is_valid(document) is ok
    assert (not any(True for _ in _validator().iter_errors(document))) is ok


# -- the IR ----------------------------------------------------------------------------------


def test_spans_point_into_the_json_text() -> None:
    text = (DATA / "script_gen_test_act.json").read_text(encoding="utf-8")
    source, script, diagnostics = read(text)
    assert script is not None and diagnostics == []
    assert text_of(source, script.name.span) == "test_act"
    first = script.goals[0].actions[0].blocks[0]
    assert isinstance(first, ir.InstructionBlock)
    assert text_of(source, first.moves[0].v_x.span) == "10"  # inside the quotes
    assert text_of(source, first.moves[0].wait_t.span) == "1000"
    assert text_of(source, first.audios[0].track_path.span) == "Silence"
    assert text_of(source, first.span).startswith('"blk0":{')
    assert text_of(source, script.goals[0].span) == '"goal0"'
    alfa = script.alfa[0]
    assert (alfa.action.text, alfa.mutex.text) == ("C", "U")
    assert text_of(source, alfa.action.span) == "67"
    jump = script.goals[0].actions[0].blocks[2]
    assert isinstance(jump, ir.JumpBlock)
    assert jump.condition_text == "! {TRUE}"
    assert text_of(source, jump.condition.span) == "! {TRUE}"
    assert text_of(source, jump.true_target.span) == "goal0/act0/blk4"


def test_invented_labels_only_on_targets() -> None:
    text = (DATA / "script_gen_test_act.json").read_text(encoding="utf-8")
    _, script, _ = read(text)
    labels = [b.label.text if b.label else None for _, b in script.blocks()]
    assert labels == ["g0_a0_b0", None, None, None, "g0_a0_b4"]
    jumps = [b for _, b in script.blocks() if isinstance(b, ir.JumpBlock)]
    assert [j.true_target.text for j in jumps] == ["g0_a0_b4", "g0_a0_b0"]
    assert [j.false_target for j in jumps] == [None, None]
    assert invented_label((2, 0, 13)) == "g2_a0_b13"


def test_j003_keeps_a_target_no_block_carries() -> None:
    d = doc(blk0={"type": "jump", "toparse": "! {TRUE}", "truejump": "goal0/act0/blk9",
                  "falsejump": "blk0"},
            blk1={"type": "terminus"})
    source, script, problems = read(json.dumps(d))
    assert script is not None
    assert [(p.code, p.path) for p in problems] == [("J003", "goal0/act0/blk0/truejump"),
                                                    ("J003", "goal0/act0/blk0/falsejump")]
    assert problems[0].help == "`goal0/act0` has blocks `blk0` to `blk1`"
    assert text_of(source, problems[0].span) == "goal0/act0/blk9"
    jump = script.goals[0].actions[0].blocks[0]
    assert (jump.true_target.text, jump.false_target.text) == ("g0_a0_b9", "blk0")
    assert all(b.label is None for _, b in script.blocks())


def test_condition_positions_survive_escapes() -> None:
    toparse = '{CLASS #Human U ?k ()} {ATT ?k $m U F: str("\\u00e9\\\\")} ! {E: nope(?k>$m)}'
    text = ('{"activityname": "a", "alfarulemessages": [], "omegarulemessages": [], '
            '"goal0": {"goalid": "g", "act0": {"blk0": {"type": "jump", "toparse": "'
            + toparse.replace("\\", "\\\\").replace('"', '\\"').replace("\\\\u00e9", "\\u00e9")
            + '", "truejump": "", "falsejump": ""}}}}')
    source, script, diagnostics = read(text)
    assert diagnostics == []
    jump = script.goals[0].actions[0].blocks[0]
    call = jump.condition.evaluations[0].call
    assert text_of(source, call.name.span) == "nope"
    string = jump.condition.assignments[1].call.args[0]
    assert string.text.value == "é\\"
    assert text_of(source, string.span) == '\\"\\u00e9\\\\\\\\\\"'


def test_condition_parse_errors_are_reported_and_the_block_kept() -> None:
    d = doc(blk0={"type": "jump", "toparse": "! {E: gt(1, 2)", "truejump": "", "falsejump": ""})
    _source, script, problems = read(json.dumps(d))
    assert script is not None
    assert [p.code for p in problems] == ["P002"]
    assert isinstance(script.goals[0].actions[0].blocks[0], ir.JumpBlock)


def test_numbers_keep_their_text() -> None:
    d = doc(blk0={"type": "instruction", "flagged": "flag", "move": [], "audioout": [],
                  "led": [{"r": "0.50", "g": "+1", "b": ".5", "turnas": 1, "wait_t": 1e3,
                           "duration": 10}]})
    _, script, problems = read(json.dumps(d).replace("1000.0", "1e3"))
    assert problems == []
    led = script.goals[0].actions[0].blocks[0].leds[0]
    assert [x.text for x in (led.r, led.g, led.b, led.turnas, led.wait_t, led.duration)] == \
        ["0.50", "+1", ".5", "1", "1e3", "10"]


# -- imports ---------------------------------------------------------------------------------


@pytest.mark.slow
def test_jsonschema_is_imported_only_when_validating() -> None:
    code = ("import sys, scriptc.frontend.thesis_json, scriptc.frontend.jsonpos, "
            "scriptc.emit.json, scriptc.emit.script, scriptc.emit.condition\n"
            "assert 'jsonschema' not in sys.modules, 'jsonschema imported'\n"
            "from scriptc.frontend.thesis_json import script_from_json\n"
            "from scriptc.source import SourceFile\n"
            "script_from_json(SourceFile('x.json', '[]'))\n"
            "assert 'jsonschema' in sys.modules\n")
    subprocess.run([sys.executable, "-c", code], check=True)


@pytest.mark.parametrize("name", ["test_act.json", "script_gen_test_act.json",
                                  "dance_example.json"])
def test_valid_thesis_files_skip_jsonschema(name: str) -> None:
    """The thesis's files are read without running jsonschema at all (the fast check says yes)."""
    code = ("import sys\nfrom scriptc.frontend.thesis_json import script_from_json\n"
            "from scriptc.source import SourceFile\n"
            f"text = open({str(DATA / name)!r}, encoding='utf-8').read()\n"
            "script, diagnostics = script_from_json(SourceFile('x.json', text))\n"
            "assert script is not None and not diagnostics\n"
            "assert 'jsonschema' not in sys.modules\n")
    subprocess.run([sys.executable, "-c", code], check=True)
