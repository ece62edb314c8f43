"""Snapshots (docs/testing.md, "Snapshots"): `snapshot = true` makes a test's whole trace part
of it. How two traces are aligned and their differences told, that a snapshot does not depend
on the folder `scriptc test` runs in (nor on a script loaded at run time by its absolute
path), and `--update`: it writes what is missing or differs, leaves an equal snapshot alone,
and writes nothing for a test that could not run. What the failures say is in the case files
(tests/cases/testing/snapshot_*)."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.cli.main import cli
from scriptc.ops.test import run_one
from scriptc.testing.read import read_test
from scriptc.testing.snapshot import differences, snapshot_path

ROOT = Path(__file__).resolve().parent.parent
LESSONS = ROOT / "tests" / "cases" / "coverage" / "lessons"


def line(t: int, event: str, **fields) -> str:
    return json.dumps({"t": t, "event": event, **fields}, separators=(",", ":"))


A, B, C, D = (line(0, "a"), line(1, "b", x=1), line(2, "c"), line(3, "d"))


def test_equal_traces_have_no_difference() -> None:
    assert differences([A, B, C], [A, B, C]) == []
    assert differences([], []) == []


def test_an_event_replaced_is_shown_beside_the_one_it_replaced_with_the_fields_that_differ(
) -> None:
    (d,) = differences([A, B, C], [A, line(1, "b", x=2, y=0), C])
    assert (d.expected_line, d.found_line) == (2, 2)
    assert d.words() == [
        'the snapshot (line 2): at 1 ms: b {"x": 1}',
        '  the run (event 2): at 1 ms: b {"x": 2, "y": 0} (`x`, `y` differ)']


def test_events_only_in_one_of_them_are_aligned_not_shifted() -> None:
    # One event more in the run, one fewer later: the rest still matches, line for line.
    found = differences([A, B, C, D], [A, line(0, "new"), B, C])
    assert [(d.expected, d.found) for d in found] == [
        (None, {"t": 0, "event": "new"}), ({"t": 3, "event": "d"}, None)]
    assert found[0].words() == ["only in the run (event 2): at 0 ms: new {}"]
    assert found[1].words() == ["only in the snapshot (line 4): at 3 ms: d {}"]
    assert (found[1].expected_line, found[1].found_line) == (4, 4)


def test_a_stretch_replaced_by_a_longer_one_pairs_then_adds() -> None:
    found = differences([A, B, D], [A, line(1, "x"), line(1, "y"), D])
    assert [(d.expected and d.expected["event"], d.found and d.found["event"]) for d in found] \
        == [("b", "x"), (None, "y")]


def _suite(tmp_path: Path) -> Path:
    """The `lessons` suite, with `snapshot = true` in its child's test (whose world queues a
    script by path at run time: the run names it by its absolute path)."""
    folder = tmp_path / "suite" / "lessons"
    shutil.copytree(LESSONS, folder)
    test = folder / "child_comes.test.toml"
    test.write_text("snapshot = true\n" + test.read_text())
    return folder


def test_a_snapshot_is_the_same_from_any_working_folder(tmp_path: Path) -> None:
    folder = _suite(tmp_path)
    written = []
    for where, name in ((tmp_path, "suite/lessons/child_comes.test.toml"),
                        (folder, "child_comes.test.toml"),
                        (folder / "lib", "../child_comes.test.toml")):
        with contextlib.chdir(where):
            test = read_test(name).test
            assert test is not None
            result = run_one(test, update=True)
            assert result.status == "passed" and result.written == (
                os.path.normpath(snapshot_path(name)),), result.verdicts
        written.append((folder / "child_comes.trace.jsonl").read_bytes())
        (folder / "child_comes.trace.jsonl").unlink()
    assert written[0] == written[1] == written[2]
    events = [json.loads(text) for text in written[0].decode().splitlines()]
    loads = [(e["script"], e["path"]) for e in events if e["event"] == "script_load"]
    assert loads == [("lessons", "lessons.script"), ("extra", "lib/extra.script")]
    assert str(tmp_path) not in written[0].decode()


def test_update_writes_what_is_missing_or_differs_and_leaves_an_equal_one(tmp_path) -> None:
    folder = _suite(tmp_path)
    snapshot = folder / "child_comes.trace.jsonl"
    runner = CliRunner()
    with contextlib.chdir(folder):
        result = runner.invoke(cli, ["test", "-j", "1"])
        assert result.exit_code == 1 and not snapshot.exists()
        assert ("error[T007]: `snapshot`: expected the trace to equal the snapshot "
                "`child_comes.trace.jsonl`, found no snapshot: `child_comes.trace.jsonl` does "
                "not exist") in result.output
        assert "write it from this run: scriptc test child_comes.test.toml --update" \
            in result.output
        result = runner.invoke(cli, ["test", "-j", "1", "--update"])
        assert result.exit_code == 0, result.output
        assert "wrote the snapshot child_comes.trace.jsonl" in result.output
        first = snapshot.stat()
        result = runner.invoke(cli, ["test", "-j", "1", "--update"])
        assert result.exit_code == 0 and "wrote" not in result.output
        assert (snapshot.stat().st_ino, snapshot.stat().st_mtime_ns) == \
            (first.st_ino, first.st_mtime_ns)  # not written again
        assert runner.invoke(cli, ["test", "-j", "1"]).exit_code == 0
        text = snapshot.read_text()
        snapshot.write_text(text.replace('"label":"praise"', '"label":"bravo"'))
        result = runner.invoke(cli, ["test", "-j", "1"])
        assert result.exit_code == 1 and "found 1 event that differs, at 3000 ms" \
            in result.output and "(`label` differs)" in result.output
        result = runner.invoke(cli, ["test", "-j", "1", "--update"])
        assert result.exit_code == 0 and snapshot.read_text() == text


def test_update_writes_the_snapshot_of_a_failing_test_which_still_fails(tmp_path) -> None:
    folder = _suite(tmp_path)
    test = folder / "child_comes.test.toml"
    test.write_text(test.read_text().replace('count = "1"', 'count = "2"'))
    with contextlib.chdir(folder):
        result = CliRunner().invoke(cli, ["test", "child_comes.test.toml", "--update"])
    assert result.exit_code == 1 and "1 of 2 expectations failed" in result.output
    assert (folder / "child_comes.trace.jsonl").exists()


def test_a_test_that_cannot_run_writes_no_snapshot(tmp_path: Path) -> None:
    folder = _suite(tmp_path)
    (folder / "lessons.script").write_text("[lessons]\n[goal:g]\n  [action]\n    [b##blk_\n")
    with contextlib.chdir(folder):
        result = CliRunner().invoke(cli, ["test", "child_comes.test.toml", "--update"])
    assert result.exit_code == 2 and not (folder / "child_comes.trace.jsonl").exists()


@pytest.mark.parametrize("value, snapshots", [("true", True), ("false", False)])
def test_snapshot_is_a_boolean_of_the_test_file(tmp_path, value, snapshots) -> None:
    (tmp_path / "t.script").write_text(
        "[t]\n[goal:g]\n  [action]\n    [b##blk_inst: MV() LD() AO(\"Silence, 0, 100\")]\n"
        "    [b##blk_terminus]\n")
    (tmp_path / "t.test.toml").write_text(f'scripts = ["t.script"]\nsnapshot = {value}\n')
    with contextlib.chdir(tmp_path):
        test = read_test("t.test.toml").test
        assert test is not None and (test.snapshot is not None) == snapshots
        result = run_one(test)
    assert [v.code for v in result.verdicts] == (["T007"] if snapshots else [])
    (tmp_path / "t.test.toml").write_text('scripts = ["t.script"]\nsnapshot = "yes"\n')
    with contextlib.chdir(tmp_path):
        read = read_test("t.test.toml")
    assert read.test is None and [d.code for d in read.diagnostics] == ["T003"]
