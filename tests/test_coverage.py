"""`scriptc test --coverage` (docs/testing.md, "Coverage"): the points of a script, each kind
of trace event counted, the law that merging the coverage of shards is the coverage of one run
of all the tests (in the library and through `--shard`, `--coverage-data` and `scriptc
merge`), the LCOV tracefile read back by a real LCOV reader (`lcov_cobertura`), the coverage
data against its JSON Schema and every way a data file can be wrong, and `--fail-under`'s
threshold. The summary's text is a case file (tests/cases/coverage/, harness/coverage.py)."""

from __future__ import annotations

import contextlib
import json
import re
import shutil
from pathlib import Path
from xml.etree import ElementTree

import jsonschema
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lcov_cobertura import LcovCobertura

from scriptc.analysis.analyze import analyze_bytes
from scriptc.cli.main import cli
from scriptc.ops import test as ops_test
from scriptc.ops.coverage import measure
from scriptc.resources import schema_path
from scriptc.testing.coverage import (
    Coverage,
    below,
    count,
    from_data,
    lcov,
    merge,
    never_reached,
    read_data,
    shape,
    summary,
)

ROOT = Path(__file__).resolve().parent.parent
LESSONS = ROOT / "tests" / "cases" / "coverage" / "lessons"

SCRIPT = """\
[counted]
[alfa:0, ticker, "", "", A, M]
[alfa:1, guard, "distance=0.5", "", C, M]
[alfa:2, later, "", "", D, U]
[omega:0, ticker, "", "", R, L]
[omega:1, guard, "", "", R, M]
[goal:first]
  [action]
    [b#one#blk_inst: MV() LD() AO("Silence, 0, 1000")]
    [b##blk_jump: CND({TRUE}) TRJMP(two) FLSJMP()]
    [b##blk_inst: MV() LD() AO("Silence, 0, 1000")]
[goal:second]
  [action]
    [b#two#blk_inst: MV() LD() AO("Silence, 0, 1000")]
    [b##blk_terminus]
"""


def counted() -> Coverage:
    analysis = analyze_bytes("counted.script", SCRIPT.encode(), "script")
    assert analysis.script is not None and analysis.ok, analysis.diagnostics
    return Coverage({"counted.script": shape(analysis.script, analysis.source,
                                             "counted.script")})


def test_a_scripts_points_are_its_instruction_blocks_jumps_goals_and_the_rules_it_puts() -> None:
    script = counted().scripts["counted.script"]
    assert [(b.path, b.label, b.line) for b in script.blocks] == [
        ("goal0/act0/blk0", "one", 9), ("goal0/act0/blk2", "", 11), ("goal1/act0/blk0", "two", 14)]
    assert [(j.path, j.label, j.line) for j in script.jumps] == [("goal0/act0/blk1", "", 10)]
    assert [(g.id, g.line) for g in script.goals] == [("first", 7), ("second", 12)]
    # `A`, `B` and `C` put a rule in the chain; `D` only holds it back, `R` takes it out.
    assert [(r.id, r.rulecode, r.line) for r in script.rules] == [("ticker", 0, 2),
                                                                  ("guard", 1, 3)]
    assert script.totals() == {"blocks": (0, 3), "outcomes": (0, 2), "goals": (0, 2),
                               "rules": (0, 2)}


def test_each_kind_of_event_counts_for_the_script_its_name_was_loaded_from() -> None:
    coverage = counted()
    load = {"t": 0, "event": "script_load", "script": "counted", "path": "counted.script",
            "reason": "queue"}
    events = [
        {"t": 0, "event": "session_start", "scripts": ["counted"]},
        # Before its load the name is no script: nothing counts.
        {"t": 0, "event": "block", "script": "counted", "path": "goal0/act0/blk0"},
        load,
        {"t": 0, "event": "rule_fire", "script": "counted", "id": "ticker", "rulecode": 0},
        {"t": 0, "event": "rule_fire", "script": "other", "id": "guard", "rulecode": 1},
        {"t": 0, "event": "block", "script": "counted", "path": "goal0/act0/blk0"},
        {"t": 1, "event": "block", "script": "counted", "path": "goal0/act0/blk0"},
        {"t": 2, "event": "jump", "script": "counted", "path": "goal0/act0/blk1", "value": True},
        {"t": 3, "event": "jump", "script": "counted", "path": "goal0/act0/blk1", "value": False},
        {"t": 3, "event": "jump", "script": "counted", "path": "goal0/act0/blk1", "value": False},
        {"t": 4, "event": "goal", "script": "counted", "goalid": "first", "record": "reached"},
        {"t": 4, "event": "goal", "script": "counted", "goalid": "second",
         "record": "interrupted"},
        {"t": 4, "event": "block", "script": "counted", "path": "goal9/act0/blk0"},
        # The same name loaded from a file that is not measured: its events count nowhere.
        {**load, "path": "elsewhere/counted.script"},
        {"t": 5, "event": "block", "script": "counted", "path": "goal1/act0/blk0"},
        {"t": 5, "event": "goal", "script": "counted", "goalid": "second", "record": "reached"},
        {**load, "t": 6},
        {"t": 6, "event": "block", "script": "counted", "path": "goal1/act0/blk0"},
    ]
    count(coverage, events)
    script = coverage.scripts["counted.script"]
    assert [b.hits for b in script.blocks] == [2, 0, 1]
    assert [(j.true, j.false) for j in script.jumps] == [(1, 2)]
    assert [g.hits for g in script.goals] == [1, 0]
    assert [r.hits for r in script.rules] == [1, 0]
    assert script.totals() == {"blocks": (2, 3), "outcomes": (2, 2), "goals": (1, 2),
                               "rules": (1, 2)}
    assert never_reached(coverage) == [
        "never fired: rule `guard` (counted.script:3)",
        "never reached: block goal0/act0/blk2 (counted.script:11)",
        "never reached: goal `second` (counted.script:12)"]


def test_a_jump_never_reached_and_one_outcome_never_taken_are_told_apart() -> None:
    coverage = counted()
    script = coverage.scripts["counted.script"]
    assert "never reached: jump goal0/act0/blk1 (counted.script:10)" in never_reached(coverage)
    script.jumps[0].true = 3
    assert "never taken: the false outcome of jump goal0/act0/blk1 (counted.script:10)" \
        in never_reached(coverage)
    script.jumps[0].false = 1
    assert not [line for line in never_reached(coverage) if "jump" in line]


# -- the law: the shards' coverage merged is one run's -----------------------------------------


@pytest.fixture(scope="module")
def example_run():
    """Every test of examples/tests/ and of the `lessons` suite (a script loaded at run time
    among them), run once."""
    with contextlib.chdir(ROOT):
        run = ops_test.test_paths(["examples/tests", "tests/cases/coverage/lessons"],
                         ops_test.TestOptions(jobs=1))
        assert run.results and not run.problems
        yield run


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_merging_the_shards_coverage_is_the_coverage_of_one_run(example_run, data) -> None:
    run = example_run
    shards = data.draw(st.integers(1, 5), label="shards")
    where = data.draw(st.lists(st.integers(0, shards - 1), min_size=len(run.tests),
                               max_size=len(run.tests)), label="shard of each test")
    with contextlib.chdir(ROOT):
        whole = measure(run.tests, run.results)
        parts = []
        for shard in range(shards):
            mine = [i for i, s in enumerate(where) if s == shard]
            part = measure([run.tests[i] for i in mine], [run.results[i] for i in mine])
            # Each shard writes its data file; the merge reads them.
            parts.append((f"shard{shard}.json", part.text().encode()))
    order = data.draw(st.permutations(parts), label="order")
    assert merge(read_data(order)).text() == whole.text()
    assert whole.tests == len(run.tests)


def test_shards_coverage_data_merged_by_scriptc_merge_is_one_runs(tmp_path: Path) -> None:
    runner = CliRunner()
    with contextlib.chdir(ROOT):
        whole = tmp_path / "whole.json"
        result = runner.invoke(cli, ["test", "examples/tests", "-q", "-j", "1",
                                     "--coverage-data", str(whole)])
        assert result.exit_code == 0, result.output
        parts = []
        for i in (1, 2, 3):
            part = tmp_path / f"part{i}.json"
            result = runner.invoke(cli, ["test", "examples/tests", "-q", "-j", "1", "--shard",
                                         f"{i}/3", "--coverage-data", str(part)])
            assert result.exit_code == 0, result.output
            parts.append(str(part))
        merged, info = tmp_path / "merged.json", tmp_path / "merged.info"
        assert runner.invoke(cli, ["merge", str(merged), *parts]).exit_code == 0
        assert runner.invoke(cli, ["merge", str(info), *parts]).exit_code == 0
        whole_info = tmp_path / "whole.info"
        assert runner.invoke(cli, ["test", "examples/tests", "-q", "-j", "1", "--lcov",
                                   str(whole_info)]).exit_code == 0
    assert merged.read_text() == whole.read_text()
    assert info.read_text() == whole_info.read_text()
    assert json.loads(whole.read_text())["tests"] == len(list(
        (ROOT / "examples" / "tests").glob("*.test.toml")))


def test_merge_refuses_two_versions_of_a_script_and_what_is_not_coverage(tmp_path) -> None:
    coverage = counted()
    first = coverage.text()
    changed = json.loads(first)
    changed["scripts"][0]["digest"] = "sha256:" + "0" * 64
    with pytest.raises(ValueError, match=re.escape(
            "`a.json` and `b.json` measured different versions of `counted.script`")):
        merge(read_data([("a.json", first.encode()), ("b.json", json.dumps(changed).encode())]))
    (tmp_path / "a.json").write_text(first)
    (tmp_path / "b.json").write_text(json.dumps(changed))
    (tmp_path / "c.json").write_text('{"not": "coverage"}')
    runner = CliRunner()
    with contextlib.chdir(tmp_path):
        result = runner.invoke(cli, ["merge", "out.json", "a.json", "b.json"])
        assert result.exit_code == 2 and "different versions of `counted.script`" \
            in result.output
        result = runner.invoke(cli, ["merge", "out.info", "a.json", "c.json"])
        assert result.exit_code == 2 and "`c.json` is not" in result.output
        assert not (tmp_path / "out.json").exists() and not (tmp_path / "out.info").exists()
        result = runner.invoke(cli, ["merge", "out.lcov", "a.json", "a.json"])
        assert result.exit_code == 0, result.output
    doubled = set((tmp_path / "out.lcov").read_text().splitlines())
    assert "DA:9,0" in doubled and "BRDA:10,0,0,-" in doubled


# -- the data file -----------------------------------------------------------------------------


def test_the_coverage_data_is_valid_against_its_schema(example_run) -> None:
    schema = json.loads(schema_path("coverage.schema.json").read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    with contextlib.chdir(ROOT):
        data = measure(example_run.tests, example_run.results).as_data()
    assert list(jsonschema.Draft202012Validator(schema).iter_errors(data)) == []
    assert data["scripts"] and all(s["blocks"] for s in data["scripts"])


BAD = [
    ({"format": "other"}, "its `format` must be \"scriptc-coverage\""),
    ({"version": 2}, "of version 2, and this scriptc reads version 1"),
    ({"tests": -1}, "`tests` must be a whole number, 0 or more"),
    ({"tests": True}, "`tests` must be a whole number"),
    ({"scripts": {}}, "`scripts` must be a list of tables"),
    ({"scripts": [{"path": 3}]}, "`scripts[0].path` must be a text"),
    ({"scripts": [{"path": "a", "name": "a", "digest": "d", "blocks": [
        {"path": "goal0/act0/blk0", "label": "", "line": 1, "hits": 1.5}]}]},
     "`scripts[0].blocks[0].hits` must be a whole number"),
    ({"scripts": [{"path": "a", "name": "a", "digest": "d", "blocks": [], "jumps": [
        {"path": "p", "label": "", "line": 1, "true": 0}]}]},
     "`scripts[0].jumps[0].false` must be a whole number"),
    ({"scripts": [{"path": "a", "name": "a", "digest": "d", "blocks": [], "jumps": [],
                   "goals": [], "rules": []}] * 2}, "`scripts[1]` names `a` a second time"),
]


@pytest.mark.parametrize("change, message", BAD, ids=[m for _c, m in BAD])
def test_a_data_file_that_is_not_coverage_says_what_and_where(change, message) -> None:
    data = {"format": "scriptc-coverage", "version": 1, "tests": 0, "scripts": [], **change}
    with pytest.raises(ValueError) as error:
        from_data(data, "d.json")
    assert str(error.value).startswith("`d.json` ") and message in str(error.value)
    not_json = re.escape("`d.json` is not scriptc coverage data: not JSON")
    with pytest.raises(ValueError, match=not_json):
        read_data([("d.json", b"{")])


# -- LCOV, read back -------------------------------------------------------------------------


def test_the_lcov_tracefile_reads_back_in_lcov_cobertura(example_run) -> None:
    with contextlib.chdir(ROOT):
        coverage = measure(example_run.tests, example_run.results)
    parsed = LcovCobertura(lcov(coverage)).parse(timestamp=0)
    files = {path: info for package in parsed["packages"].values()
             for path, info in package["classes"].items()}
    assert sorted(files) == sorted(coverage.scripts)
    for path, script in coverage.scripts.items():
        info = files[path]
        lines: dict[int, int] = {}
        for block in script.blocks:
            lines[block.line] = lines.get(block.line, 0) + block.hits
        # Instruction blocks are lines; each jump's two outcomes are branches of its line;
        # goals are functions.
        assert {n: int(v["hits"]) for n, v in info["lines"].items() if v["branch"] == "false"} \
            == lines
        assert info["lines-total"] == len(lines)
        assert info["lines-covered"] == sum(hits > 0 for hits in lines.values())
        reached, total = script.totals()["outcomes"]
        assert (info["branches-covered"], info["branches-total"]) == (reached, total)
        for jump in script.jumps:
            line = info["lines"][jump.line]
            assert (line["branch"], line["branches-total"], line["branches-covered"]) == \
                ("true", 2, (jump.true > 0) + (jump.false > 0))
        assert info["methods"] == {g.id: [str(g.line), str(g.hits)] for g in script.goals}
    xml = ElementTree.fromstring(LcovCobertura(lcov(coverage)).convert())
    reached, total = coverage.totals()["outcomes"]
    assert xml.get("branches-valid") == str(total) and xml.get("branches-covered") == str(reached)


def test_lcov_marks_a_jump_never_reached_with_a_dash() -> None:
    text = lcov(counted())
    assert "BRDA:10,0,0,-\nBRDA:10,0,1,-\nBRF:2\nBRH:0\n" in text
    assert text.startswith("TN:\nSF:counted.script\nFN:7,first\nFN:12,second\n")
    assert text.endswith("DA:9,0\nDA:11,0\nDA:14,0\nLF:3\nLH:0\nend_of_record\n")


# -- the verb: --coverage, --lcov, --fail-under ------------------------------------------------


def run_lessons(tmp_path: Path, *args: str):
    shutil.copytree(LESSONS, tmp_path / "lessons")
    with contextlib.chdir(tmp_path):
        return CliRunner().invoke(cli, ["test", "lessons", "-j", "1", *args])


def test_coverage_prints_the_summary_and_writes_the_files(tmp_path: Path) -> None:
    result = run_lessons(tmp_path, "--coverage", "--lcov", "out/l.info", "--coverage-data",
                         "d.json")
    assert result.exit_code == 2 and "the folder `out` does not exist" in result.output
    assert "PASS" not in result.output  # refused before any test ran
    (tmp_path / "out").mkdir()
    result = run_lessons(tmp_path / "out", "--coverage", "--lcov", "l.info",
                         "--coverage-data", "d.json")
    assert result.exit_code == 0, result.output
    assert "  lessons/lessons.script     3/4 75.0%      5/6 83.3%   3/4 75.0%  1/2 50.0%" \
        in result.output
    assert "never reached: block `encore` (lessons/lessons.script:25)" in result.output
    data = from_data(json.loads((tmp_path / "out" / "d.json").read_text()), "d.json")
    assert (tmp_path / "out" / "l.info").read_text() == lcov(data)
    assert summary(data) in result.output


@pytest.mark.parametrize("percent, status, short", [
    ("0", 0, None), ("80", 0, None), ("80.01", 1, "blocks 80.0% (4 of 5)"),
    ("83.4", 1, "blocks 80.0% (4 of 5); jump outcomes 83.3% (5 of 6)"), ("100", 1, "blocks")])
def test_fail_under_fails_when_blocks_or_jump_outcomes_are_below(tmp_path, percent, status,
                                                                 short) -> None:
    result = run_lessons(tmp_path, "--fail-under", percent)
    assert result.exit_code == status, result.output
    assert "coverage of" not in result.output  # the summary is --coverage's
    if short:
        assert f"error: coverage under {float(percent):g}%: {short}" in result.output
    else:
        assert "coverage under" not in result.output


def test_fail_under_does_not_hide_a_worse_status(tmp_path: Path) -> None:
    shutil.copytree(LESSONS, tmp_path / "lessons")
    broken = tmp_path / "lessons" / "nobody.test.toml"
    broken.write_text(broken.read_text().replace("max = 23000", "max = 21000"))
    with contextlib.chdir(tmp_path):
        result = CliRunner().invoke(cli, ["test", "lessons", "-j", "1", "--fail-under", "0"])
    assert result.exit_code == 1 and "FAIL  lessons/nobody.test.toml" in result.output
    with contextlib.chdir(tmp_path):
        result = CliRunner().invoke(cli, ["test", "lessons", "--fail-under", "101"])
    assert result.exit_code == 2 and "101" in result.output


def test_below_counts_a_kind_with_nothing_to_reach_as_complete() -> None:
    assert below(Coverage(), 100) == []
    coverage = counted()
    assert below(coverage, 0) == []
    assert below(coverage, 1) == ["blocks 0.0% (0 of 3)", "jump outcomes 0.0% (0 of 2)"]
