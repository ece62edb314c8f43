"""`scriptc test` (docs/testing.md) beyond its case files (tests/cases/testing/, the `test`
aspect): the verb through click's CliRunner in this process (exit status, one line per test,
discovery with .gitignore and `exclude`, `-k`, the worker pool, Ctrl-C), the replay command
replaying the run, the laws (a test gives the same result and trace every time, with one worker
or several), what `where` matches, and where each character of a TOML string is."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc.cli.main import cli
from scriptc.project.config.tomlpos import locate, string_offsets
from scriptc.testing.expect import matches

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

GREETS = """\
description = "the greeting greets a child who comes close"
scripts = ["greeting.script"]
world = "greeting.world.json"
until = 60000

[[expect]]
event = "block"
where = { label = "hello" }
within = [2000, 4000]
"""
CLOSES_ALONE = """\
description = "closes alone after 30 s"
scripts = ["greeting.script"]

[[expect]]
outcome = "completed"
time = { min = 30000, max = 35000 }
"""
FAILS = """\
scripts = ["greeting.script"]

[[expect]]
name = "never happens"
event = "block"
where = { label = "hello" }
"""


def scriptc(*args: str):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


@pytest.fixture
def activity(tmp_path: Path, monkeypatch) -> Path:
    """A repository with the greeting example and its world."""
    for name in ("greeting.script", "greeting.world.json"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def write(folder: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text, encoding="utf-8")


# -- the verb -----------------------------------------------------------------------------------


def test_passing_tests_exit_0_with_a_line_each(activity: Path) -> None:
    write(activity, {"greets.test.toml": GREETS, "closes.test.toml": CLOSES_ALONE})
    result = scriptc("test", "-j", "1")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0].startswith("PASS  closes.test.toml (32.000 s simulated, ")
    assert lines[1].startswith("PASS  greets.test.toml (6.000 s simulated, ")
    assert lines[2].startswith("2 passed; 38.000 s simulated in ")
    assert len(lines) == 3


def test_a_failure_exits_1_with_its_diagnostic_and_the_replay(activity: Path) -> None:
    write(activity, {"greets.test.toml": GREETS, "fails.test.toml": FAILS})
    result = scriptc("test", "-j", "1")
    assert result.exit_code == 1
    out = result.stdout
    assert "FAIL  fails.test.toml (32.000 s simulated, " in out
    assert "): 1 of 1 expectation failed\n" in out
    assert ("error[T006]: `never happens`: expected at least 1 `block` event with label = "
            "\"hello\" during the run, found 0\n --> fails.test.toml:3:1\n") in out
    assert ("= help: replay the run: scriptc run greeting.script --robot kinematic "
            "--no-governor --until 600000\n") in out
    assert out.endswith("1 passed, 1 failed; 38.000 s simulated in " + out.rsplit(" in ", 1)[1])


def test_a_broken_test_file_stops_everything_with_exit_2(activity: Path) -> None:
    """As pytest stops on an error while collecting: no test runs, whatever -k selects."""
    write(activity, {"greets.test.toml": GREETS, "broken.test.toml": 'scripts = ["x.script"]\n'})
    result = scriptc("test", "-k", "greets")
    assert result.exit_code == 2
    assert "error[T004]: the script `x.script` does not exist" in result.stdout
    assert "PASS" not in result.stdout
    assert "error: fix the test files first: no test ran" in result.stderr


def test_a_script_with_errors_is_an_error_exit_2(activity: Path) -> None:
    write(activity, {"bad.script": "[bad]\n[goal:g]\n[action]\n[b##blk_jump: CND(! {TRUE}) "
                                   "TRJMP(nowhere) FLSJMP()]\n",
                     "bad.test.toml": 'scripts = ["bad.script"]\n',
                     "greets.test.toml": GREETS})
    result = scriptc("test", "-j", "1")
    assert result.exit_code == 2
    assert "ERROR bad.test.toml: `bad.script` has errors\n" in result.stdout
    assert "error[L003]" in result.stdout and "--> bad.script:4:" in result.stdout
    assert "PASS  greets.test.toml" in result.stdout
    assert "1 passed, 1 error;" in result.stdout


def test_a_path_that_does_not_exist_exits_2(activity: Path) -> None:
    result = scriptc("test", "nowhere")
    assert result.exit_code == 2
    assert "error: `nowhere` does not exist" in result.stderr


def test_no_test_found_says_so(activity: Path) -> None:
    result = scriptc("test")
    assert result.exit_code == 0
    assert "warning: no test files (*.test.toml) found under the given paths" in result.stderr


def test_k_selects_by_path_or_description_in_any_case(activity: Path) -> None:
    write(activity, {"greets.test.toml": GREETS, "other.test.toml": CLOSES_ALONE})
    by_description = scriptc("test", "-k", "CHILD WHO")
    assert "greets.test.toml" in by_description.stdout
    assert "other.test.toml" not in by_description.stdout
    by_path = scriptc("test", "-k", "other")
    assert "other.test.toml" in by_path.stdout and "greets" not in by_path.stdout
    nothing = scriptc("test", "-k", "zebra")
    assert nothing.exit_code == 0 and nothing.stdout == ""
    assert "no test matches `-k zebra` (2 found)" in nothing.stderr


def test_discovery_respects_gitignore_exclude_and_hidden_folders(activity: Path) -> None:
    (activity / ".git").mkdir()
    write(activity, {
        ".gitignore": "ignored/\n",
        "scriptc.toml": 'exclude = ["excluded"]\n',
        **{name: GREETS.replace('"greeting', '"../greeting') for name in (
            "tests/a.test.toml", "ignored/b.test.toml", "excluded/c.test.toml",
            ".hidden/d.test.toml", "tests/not_a_test.toml")},
    })
    result = scriptc("test")
    assert result.exit_code == 0, result.output
    assert [line.split()[1] for line in result.stdout.splitlines()[:-1]] == [
        os.path.join("tests", "a.test.toml")]
    named = scriptc("test", "ignored/b.test.toml")  # a file named is taken
    assert "PASS  ignored/b.test.toml" in named.stdout


def test_quiet_leaves_out_the_tests_that_pass(activity: Path) -> None:
    write(activity, {"greets.test.toml": GREETS, "fails.test.toml": FAILS})
    result = scriptc("test", "-q", "-j", "1")
    assert "greets" not in result.stdout and "FAIL  fails.test.toml" in result.stdout


def test_ctrl_c_reports_what_ran_and_exits_130(activity: Path, monkeypatch) -> None:
    """Ctrl-C in the middle: the tests that finished are reported, then how far it got."""
    from scriptc.ops import test as ops_test

    write(activity, {"a.test.toml": GREETS, "b.test.toml": CLOSES_ALONE})
    real = ops_test.run_one

    def interrupted_second(test, executor="vm", **options):
        if test.source.path.startswith("b"):
            raise KeyboardInterrupt
        return real(test, executor, **options)

    monkeypatch.setattr(ops_test, "run_one", interrupted_second)
    result = scriptc("test", "-j", "1")
    assert result.exit_code == 130
    assert "PASS  a.test.toml" in result.stdout and "b.test.toml" not in result.stdout
    assert "error: interrupted (Ctrl-C): 1 of 2 tests ran" in result.stderr


# -- the replay, and the laws -------------------------------------------------------------------


def test_the_replay_command_replays_the_run(activity: Path) -> None:
    """The help of a failure is a `scriptc run` command; it runs the same session: the same
    trace, event for event (an inline world is taken from the test file itself)."""
    from scriptc.ops.test import run_one
    from scriptc.testing.read import read_test

    world = ('[world]\nupdates = [{ at = 1000, objectid = "Human/kid1", attributename = '
             '"poses", policy = "R", jsonmsg = { positionrho = 1.0, positiontheta = 0.0 } }]\n')
    write(activity, {"inline.test.toml": FAILS + world})
    test = read_test("inline.test.toml").test
    assert test is not None
    result = run_one(test)
    assert result.status == "passed"  # the child comes at 1 s: hello is said
    words = result.replay.split()
    assert words[:2] == ["scriptc", "run"] and "--world" in words
    replayed = scriptc(*words[1:], "--trace", "replay.jsonl")
    assert replayed.exit_code == 0, replayed.output
    trace = [json.loads(line) for line in Path("replay.jsonl").read_text().splitlines()]
    assert trace == [json.loads(json.dumps(e)) for e in result.events]


# Expectations over the examples, each of a kind, for the laws below.
EXPECTATIONS = st.sampled_from([
    'event = "block"\nwhere = { label = "hello" }',
    'event = "jump"\ncount = ">=2"\nwithin = [0, 5000]',
    'event = "cmd_start"\nwhere = { track = "led" }\ncount = "<=3"',
    'at = 3500\nled = [0.2, 0.8, 0.3]\npose = { theta = 0.17 }',
    'at = "end"\nblock = "none"',
    'outcome = "completed"\ntime = { max = 20000 }',
    'distance = { to = "Human/*", min = 1.3 }',
])


@settings(max_examples=15, deadline=None)
@given(st.lists(EXPECTATIONS, min_size=1, max_size=5), st.sampled_from([None, True]))
def test_the_same_test_gives_the_same_result_every_time(tmp_path_factory, expectations,
                                                          governor) -> None:
    """Byte for byte: the result's JSON and the trace, run after run."""
    from scriptc.ops.test import run_one
    from scriptc.testing.read import test_from_text

    folder = tmp_path_factory.mktemp("law")
    for name in ("greeting.script", "greeting.world.json"):
        shutil.copy(EXAMPLES / name, folder / name)
    text = 'scripts = ["greeting.script"]\nworld = "greeting.world.json"\n'
    if governor is not None:
        text += "governor = true\n"
    text += "".join(f"\n[[expect]]\n{e}\n" for e in expectations)
    read = test_from_text(text, str(folder / "law.test.toml"))
    assert read.test is not None, read.diagnostics
    first, second = run_one(read.test), run_one(read.test)
    assert json.dumps(first.as_dict()) == json.dumps(second.as_dict())
    assert [json.dumps(e) for e in first.events] == [json.dumps(e) for e in second.events]
    assert len(first.verdicts) == len(expectations)


@pytest.mark.slow
def test_workers_give_what_one_process_gives(activity: Path) -> None:
    """-j 2 runs the tests in two worker processes: the same lines and diagnostics, in the
    same order, as one process (the wall times aside)."""
    write(activity, {f"t{i}.test.toml": (GREETS, CLOSES_ALONE, FAILS)[i % 3] for i in range(7)})

    def without_times(text: str) -> list[str]:
        return [line.split(", ")[0] if line.startswith(("PASS", "FAIL")) else
                line.split(" in ")[0] for line in text.splitlines()]

    one, two = scriptc("test", "-j", "1"), scriptc("test", "-j", "2")
    assert one.exit_code == two.exit_code == 1
    assert without_times(one.stdout) == without_times(two.stdout)


@pytest.mark.slow
def test_ctrl_c_stops_the_workers_at_once(activity: Path) -> None:
    """SIGINT to `scriptc test -j 2` running long tests: exit 130 within a few seconds, what
    finished reported, no worker left behind."""
    long_test = ('scripts = ["loop.script"]\nuntil = 2000000000\n[[expect]]\n'
                 'outcome = "until"\n')
    write(activity, {"loop.script": "[loop]\n[goal:g]\n[action]\n"
                                    "[b#again#blk_inst: MV() LD() AO(\"Silence, 0, 1\")]\n"
                                    "[b##blk_jump: CND(! {TRUE}) TRJMP(again) FLSJMP()]\n",
                     **{f"long{i}.test.toml": long_test for i in range(4)}})
    process = subprocess.Popen([sys.executable, "-m", "scriptc", "test", "-j", "2"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    time.sleep(3)
    children = subprocess.run(["pgrep", "-P", str(process.pid)], capture_output=True,
                              text=True, check=False).stdout.split()
    assert len(children) >= 2  # the workers are running
    start = time.monotonic()
    process.send_signal(signal.SIGINT)
    _stdout, stderr = process.communicate(timeout=30)
    assert process.returncode == 130
    assert time.monotonic() - start < 10
    assert b"interrupted (Ctrl-C): 0 of 4 tests ran" in stderr and b"Traceback" not in stderr
    for pid in children:
        assert not Path(f"/proc/{pid}").exists() or \
            "zombie" in Path(f"/proc/{pid}/status").read_text()


# -- the pieces ---------------------------------------------------------------------------------


def test_where_matches_a_subset_and_true_is_not_one() -> None:
    event = {"track": "led", "command": {"r": 1.0, "g": 0, "turnas": 1}, "value": True}
    assert matches({"track": "led"}, event)
    assert matches({"command": {"r": 1}}, event)  # 1 and 1.0 are the same number
    assert matches({"command": {"r": 1.0, "turnas": 1}}, event)
    assert not matches({"command": {"r": 1.0, "b": 0}}, event)  # a key the event lacks
    assert not matches({"value": 1}, event) and matches({"value": True}, event)
    assert not matches({"command": {"turnas": True}}, event)
    assert matches({"a": [1, 2]}, {"a": [1.0, 2]}) and not matches({"a": [1]}, {"a": [1, 2]})
    assert not matches({"a": {"b": 1}}, {"a": 1})


def _escaped(value: str, escape: list[bool]) -> str:
    """`value` as the body of a TOML basic string: quotes, backslashes and control characters
    escaped, and each character whose `escape` is set (`\\uXXXX` or `\\UXXXXXXXX`)."""
    out = []
    for char, chosen in zip(value, escape, strict=True):
        if char in '"\\':
            out.append("\\" + char)
        elif chosen or ord(char) < 0x20 or ord(char) == 0x7F:
            out.append(f"\\u{ord(char):04x}" if ord(char) < 0x10000 else f"\\U{ord(char):08x}")
        else:
            out.append(char)
    return "".join(out)


@settings(max_examples=200)
@given(st.text(st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=12),
       st.sampled_from(["basic", "literal", "multi", "multi_literal"]),
       st.lists(st.booleans(), min_size=12, max_size=12))
def test_string_offsets_find_each_character(value: str, kind: str, escape: list[bool]) -> None:
    """Each character of a TOML string's value is at its offset, or is written there as an
    escape; one offset more is the closing quote."""
    if kind == "basic":
        written = '"' + _escaped(value, escape[:len(value)]) + '"'
    elif kind == "multi":
        written = '"""\n' + _escaped(value, escape[:len(value)]) + '"""'
    elif kind in ("literal", "multi_literal"):
        bad = "'\n\r" if kind == "literal" else "'\r"
        value = "".join(c for c in value if c not in bad and (c == "\n" or c.isprintable()))
        written = f"'{value}'" if kind == "literal" else f"'''\n{value}'''"
    text = f"k = {written}\n"
    assert tomllib.loads(text)["k"] == value
    offsets = string_offsets(text, locate(text).value(("k",)))
    assert len(offsets) == len(value) + 1
    for char, at in zip(value, offsets, strict=False):
        assert text[at] == char or text[at] == "\\"
    assert text[offsets[-1]] in "\"'"


def test_the_schema_agrees_with_the_code() -> None:
    """The test file's schema is a valid JSON Schema, and its lists are the code's: the robots,
    the outcomes, the keys of an `[[expect]]` (those of each kind, and `name`)."""
    import jsonschema

    from scriptc.runtime.robots import ROBOTS
    from scriptc.testing.model import OUTCOMES
    from scriptc.testing.read import KINDS, schema

    jsonschema.Draft202012Validator.check_schema(schema())
    assert schema()["properties"]["robot"]["enum"] == sorted(ROBOTS)
    expect = schema()["$defs"]["expect"]["properties"]
    assert tuple(expect["outcome"]["enum"]) == OUTCOMES
    assert set(expect) == {key for keys in KINDS.values() for key in keys} | {"name"}


# -- the verdicts, one rule at a time -------------------------------------------------------------


def _judge(text: str, events=(), *, states=(), final=None, outcome="completed", time_ms=10_000):
    """The verdicts of the expectations of `text` (after a `scripts` line) over a run made of
    `events` (`(t, kind, fields)`), observed `states`, the `final` state and the end."""
    from scriptc.testing.expect import Run, judge
    from scriptc.testing.read import test_from_text

    read = test_from_text(f'scripts = ["{EXAMPLES / "greeting.script"}"]\n{text}',
                          str(ROOT / "t.test.toml"))
    assert read.test is not None, read.diagnostics
    trace = [{"t": t, "event": kind, **fields} for t, kind, fields in events]
    return judge(read.test.expectations,
                 Run(trace, {s.t: s for s in states}, final, outcome, time_ms))


def _state(t=0, *, x=0.0, led=None, audio=None, block=None):
    from scriptc.robot.motion import Pose
    from scriptc.runtime.loop import Observation

    return Observation(t, Pose(x, 0.0, 0.0), led, audio, block,
                       None if block is None else "goal0/act0/blk0",
                       None if block is None else "s")


BLOCKS = [(1000, "block", {"label": "a"}), (2000, "block", {"label": "b"}),
          (3000, "block", {"label": "a"})]


@pytest.mark.parametrize(("count", "within", "passed"), [
    ('">=2"', "[0, 3000]", True), ('">=2"', "[0, 2999]", False), ('"2"', "[1000, 3000]", True),
    ('"1"', "[1001, 3000]", True), ('"<=1"', "[0, 3000]", False), ('"<=1"', "[1000, 2999]", True),
    ('"0"', "[1001, 2999]", True), ("0", "[3000, 3000]", False), ('" >= 3 "', "[0, 9000]", False),
])
def test_a_count_over_a_window_with_both_ends_included(count: str, within: str,
                                                       passed: bool) -> None:
    (verdict,) = _judge(f'[[expect]]\nevent = "block"\nwhere = {{ label = "a" }}\n'
                        f'count = {count}\nwithin = {within}\n', BLOCKS)
    assert verdict.passed is passed


def test_too_few_shows_the_matching_outside_the_window_first() -> None:
    (verdict,) = _judge('[[expect]]\nevent = "block"\nwhere = { label = "a" }\n'
                        'within = [1500, 2500]\n', BLOCKS)
    assert not verdict.passed and verdict.found == "0"
    assert verdict.notes[0] == "the nearest `block` events:"
    # both `a` events are outside (500 ms before and after: the earlier first), then `b`
    assert [n.split(":")[0] for n in verdict.notes[1:]] == ["at 1000 ms", "at 3000 ms",
                                                             "at 2000 ms"]
    assert verdict.notes[1].endswith("(outside the window)")
    assert verdict.notes[3].endswith("(`label` differs)")


def test_too_many_shows_the_first_matching_and_how_many_more() -> None:
    events = [(t, "jump", {"value": True}) for t in range(0, 5000, 1000)]
    (verdict,) = _judge('[[expect]]\nevent = "jump"\ncount = "<=1"\n', events)
    assert verdict.found == "5"
    assert verdict.notes == ("the matching events during the run:", 'at 0 ms: {"value": true}',
                             'at 1000 ms: {"value": true}', 'at 2000 ms: {"value": true}',
                             "and 2 more")


def test_a_state_within_its_tolerances() -> None:
    states = [_state(500, x=0.105, led=(0.2, 0.805, 0.3), audio="a.wav", block="go")]
    text = ('[[expect]]\nat = 500\npose = {{ x = 0.1, tolerance = {tol} }}\n'
            'led = [0.2, 0.8, 0.3]\naudio = "a.wav"\nblock = "go"\n')
    (inside,) = _judge(text.format(tol=0.005), states=states)
    (outside,) = _judge(text.format(tol=0.004), states=states)
    assert inside.passed and not outside.passed
    assert outside.found == "pose x 0.105"
    assert outside.notes == (("the state at 500 ms: pose x 0.105, y 0, theta 0; led [0.2, "
                             "0.805, 0.3]; audio `a.wav`; block `go` (goal0/act0/blk0 of `s`)"),)
    (green,) = _judge("[[expect]]\nat = 500\nled = [0.2, 0.79, 0.3]\n", states=states)
    assert not green.passed and green.found == "led [0.2, 0.805, 0.3]"


def test_off_is_nothing_lit_or_black_and_none_is_nothing() -> None:
    dark = [_state(1, led=(0.0, 0.0, 0.0)), _state(2, led=None), _state(3, led=(0.0, 0.01, 0))]
    verdicts = _judge("".join(f'[[expect]]\nat = {t}\nled = "off"\naudio = "none"\n'
                              f'block = "none"\n' for t in (1, 2, 3)), states=dark)
    assert [v.passed for v in verdicts] == [True, True, False]
    (black,) = _judge("[[expect]]\nat = 1\nled = [0, 0, 0]\n", states=dark)
    assert not black.passed  # black is dark, not a colour lit


def test_a_state_after_the_end_is_not_known_but_the_end_is() -> None:
    final = _state(6000, block=None)
    late, end = _judge('[[expect]]\nat = 7000\nblock = "none"\n[[expect]]\nat = "end"\n'
                       'block = "none"\n', final=final, time_ms=6000)
    assert not late.passed and late.found == "the run ended at 6000 ms (`completed`)"
    assert end.passed


def test_outcome_and_time_bounds_are_included() -> None:
    def verdict(time: str, outcome: str = "completed", ended: int = 5000) -> bool:
        (v,) = _judge(f"[[expect]]\noutcome = \"{outcome}\"\ntime = {time}\n", time_ms=ended)
        return v.passed

    assert verdict("{ min = 5000, max = 5000 }") and verdict("{ max = 5000 }")
    assert not verdict("{ min = 5001 }") and not verdict("{ max = 4999 }")
    assert not verdict("{ max = 9000 }", outcome="until")


def test_a_fatal_error_fails_a_test_unless_an_outcome_is_expected() -> None:
    error = [(40, "error", {"code": "no-progress", "message": "stuck", "fatal": True})]
    (implicit,) = _judge("", error, outcome="error", time_ms=40)
    assert not implicit.passed and implicit.index is None
    assert implicit.notes == ("at 40 ms: no-progress: stuck",)
    (expected,) = _judge('[[expect]]\noutcome = "error"\n', error, outcome="error")
    assert expected.passed
    assert _judge('[[expect]]\ntime = { max = 50 }\n', error, outcome="error", time_ms=40)[1:]


def _pose(t: int, objectid: str, rho, status: str = "applied") -> tuple:
    return (t, "update", {"objectid": objectid, "attributename": "poses", "policy": "R",
                          "value": {"positionrho": rho, "positiontheta": 0.0}, "status": status})


def test_a_distance_holds_from_each_update_to_the_next() -> None:
    updates = [_pose(0, "Human/a", 0.4), _pose(1000, "Human/a", 2.0),
               _pose(1500, "Human/b", 0.3, status="dropped"), _pose(2000, "Object/c", 0.1),
               _pose(3000, "Human/b", 0.8)]

    def kept(to: str, within: str = "", low: float = 0.5) -> bool:
        (v,) = _judge(f'[[expect]]\ndistance = {{ to = "{to}", min = {low} }}\n{within}',
                      updates)
        return v.passed

    assert not kept("Human/a") and not kept("Human/*")
    assert kept("Human/a", "within = [1000, 9000]")  # 0.4 m held until 1000 ms only
    assert not kept("Human/a", "within = [999, 9000]")  # the 0.4 m of 0 ms holds at 999
    assert kept("Human/b")  # the dropped update never reached the map
    assert not kept("Human/b", low=0.9) and kept("Human/b", "within = [0, 2999]", low=0.9)
    assert kept("Human/nobody")  # never placed: no distance
    (v,) = _judge('[[expect]]\ndistance = { to = "Human/*", min = 0.5 }\n', updates)
    assert v.found == "0.4 m from `Human/a` at 0 ms"


def test_colours_only_on_demand() -> None:
    from scriptc.testing.report import summary_line, test_line
    from scriptc.testing.run import TestResult

    passed = TestResult("a.test.toml", "", "passed", "scriptc run a.script", 1500, "completed")
    assert test_line(passed, wall=False) == "PASS  a.test.toml (1.500 s simulated)\n"
    assert test_line(passed, wall=False, color=True).startswith("\x1b[1;32mPASS \x1b[0m ")
    failed = TestResult("b.test.toml", "", "error", "", reason="why")
    assert test_line(failed, color=True) == "\x1b[1;31mERROR\x1b[0m b.test.toml: why\n"
    assert summary_line([passed, failed]) == "1 passed, 1 error; 1.500 s simulated\n"
    assert summary_line([passed], 12.25, color=True) == \
        "\x1b[1;32m1 passed\x1b[0m; 1.500 s simulated in 12.2 s\n"


def test_run_takes_a_test_files_world_or_says_what_is_wrong(activity: Path) -> None:
    write(activity, {"w.test.toml": GREETS.replace('world = "greeting.world.json"\n', "")
                     + "[world]\noperator = [{ at = 100, command = \"jump\" }]\n"})
    result = scriptc("run", "greeting.script", "--world", "w.test.toml", "--robot", "kinematic")
    assert result.exit_code == 2
    assert "error[T005]: in `[world]`: operator[0].command: must be one of" in result.stderr
    write(activity, {"w.test.toml": GREETS})
    result = scriptc("run", "greeting.script", "--world", "w.test.toml", "--robot", "kinematic")
    assert result.exit_code == 0 and "completed at 6000 ms" in result.stdout
