"""What `scriptc test` gives to CI (docs/testing.md): the JUnit XML report (`--junit`), read
back by the readers CI uses (the JUnit schema of Jenkins' xUnit plugin, tests/data/junit-10.xsd,
and `junitparser`), the GitHub annotations (`--format github`), the shards (`--shard I/N`, the
TEST_TOTAL_SHARDS / TEST_SHARD_INDEX variables, `--durations`) and their law, `scriptc merge`,
and the progress bar on a terminal. The verb runs in this process (click's CliRunner, or the
group's `main` with a fake terminal for the bar). The reports of single tests as case files
are tests/cases/testing/*.junit.xml and *.github (the `test` aspect)."""

from __future__ import annotations

import io
import json
import shutil
from pathlib import Path
from xml.etree import ElementTree

import junitparser
import pytest
import xmlschema
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc import __version__
from scriptc.cli.main import cli
from scriptc.testing.shard import (
    Shard,
    ShardError,
    parse_shard,
    partition,
    shard_from_environment,
)

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
SCHEMA = xmlschema.XMLSchema(ROOT / "tests" / "data" / "junit-10.xsd")

GREETS = """\
description = "greets a child who comes close"
scripts = ["../greeting.script"]
world = "../greeting.world.json"
until = 60000

[[expect]]
event = "block"
where = { label = "hello" }
"""
FAILS = """\
scripts = ["../greeting.script"]
until = 40000

[[expect]]
name = "never says hello"
event = "block"
where = { label = "hello" }

[[expect]]
name = "ends on its own"
outcome = "completed"

[[expect]]
name = "runs to the limit"
outcome = "until"
"""
BROKEN_SCRIPT = "[broken]\n[goal:g]\n[action]\n[b##blk_jump: CND(! {TRUE}) TRJMP(x) FLSJMP()]\n"
ERRS = 'scripts = ["../broken.script"]\n'


def scriptc(*args: str, env: dict[str, str] | None = None):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False, env=env)


@pytest.fixture
def repo(tmp_path: Path, monkeypatch) -> Path:
    """A git repository (`.git` is all it takes) with the greeting example at its root and
    its tests under `tests/`."""
    for name in ("greeting.script", "greeting.world.json"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    (tmp_path / ".git").mkdir()
    (tmp_path / "tests").mkdir()
    monkeypatch.chdir(tmp_path)
    for variable in ("TEST_TOTAL_SHARDS", "TEST_SHARD_INDEX", "TEST_SHARD_STATUS_FILE"):
        monkeypatch.delenv(variable, raising=False)
    return tmp_path


def write(folder: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text, encoding="utf-8")


def read_junit(path: Path) -> junitparser.JUnitXml:
    """The report as CI reads it: valid by the xUnit plugin's schema, then parsed by
    junitparser."""
    SCHEMA.validate(str(path))
    return junitparser.JUnitXml.fromfile(str(path))


def cases(report: junitparser.JUnitXml) -> dict[str, junitparser.TestCase]:
    found = {}
    for suite in report:
        for case in suite:
            assert case.name not in found, f"{case.name} is listed twice"
            found[case.name] = case
    return found


# -- JUnit XML --------------------------------------------------------------------------------


def test_junit_lists_every_test_with_its_failures_errors_and_timings(repo: Path) -> None:
    write(repo, {"tests/greets.test.toml": GREETS, "tests/fails.test.toml": FAILS,
                 "tests/errs.test.toml": ERRS, "broken.script": BROKEN_SCRIPT})
    result = scriptc("test", "-j", "1", "--junit", "report.xml")
    assert result.exit_code == 2  # a test could not run: the report is written all the same
    report = read_junit(repo / "report.xml")
    (suite,) = list(report)
    assert suite.name == "scriptc test"
    assert (suite.tests, suite.failures, suite.errors, suite.skipped) == (3, 1, 1, 0)
    assert 0 < suite.time < 60
    assert suite.timestamp and suite.hostname
    assert {p.name: p.value for p in suite.properties()} == {"scriptc": __version__,
                                                             "executor": "vm"}
    found = cases(report)
    assert sorted(found) == ["tests/errs.test.toml", "tests/fails.test.toml",
                             "tests/greets.test.toml"]
    greets, fails, errs = (found[f"tests/{n}.test.toml"] for n in ("greets", "fails", "errs"))
    assert greets.classname == "tests.greets" and greets.is_passed and greets.time > 0
    assert "description: greets a child who comes close\n" in greets.system_out
    assert "replay: scriptc run greeting.script --world greeting.world.json" in \
        greets.system_out
    (failure,) = fails.result
    assert isinstance(failure, junitparser.Failure) and failure.type == "T006"
    # Every failed expectation in the message, one a line; in full, with the replay, below.
    assert failure.message.splitlines() == [
        "2 of 3 expectations failed",
        ('`never says hello`: expected at least 1 `block` event with label = "hello" during '
        "the run, found 0"),
        "`runs to the limit`: expected the outcome `until`, found `completed` at 32000 ms"]
    assert " --> tests/fails.test.toml:4:1\n" in failure.text
    assert " --> tests/fails.test.toml:13:1\n" in failure.text
    assert failure.text.count("= help: replay the run: scriptc run greeting.script "
                              "--robot kinematic --no-governor --until 40000\n") == 2
    (error,) = errs.result
    assert isinstance(error, junitparser.Error)
    assert error.message == "`broken.script` has errors" and error.type == "L003"
    assert "--> broken.script:4:1" in error.text


def test_a_broken_test_file_is_an_error_of_the_report_and_nothing_runs(repo: Path) -> None:
    write(repo, {"tests/greets.test.toml": GREETS,
                 "tests/typo.test.toml": 'scirpts = ["../greeting.script"]\n'})
    result = scriptc("test", "--junit", "report.xml")
    assert result.exit_code == 2
    found = cases(read_junit(repo / "report.xml"))
    assert list(found) == ["tests/typo.test.toml"]
    (error,) = found["tests/typo.test.toml"].result
    assert isinstance(error, junitparser.Error) and error.type == "T003"
    assert error.message.splitlines() == [
        "the test file has 2 problems: no test ran",
        "error[T003] at 1:1: the test file lacks the required key `scripts`",
        "error[T002] at 1:1: unknown key `scirpts`"]
    assert " --> tests/typo.test.toml:1:1\n" in error.text


def test_tests_ctrl_c_stopped_are_skipped(repo: Path, monkeypatch) -> None:
    from scriptc.ops import test as ops_test

    write(repo, {"tests/a.test.toml": GREETS, "tests/b.test.toml": GREETS,
                 "tests/c.test.toml": GREETS})
    real = ops_test.run_one

    def interrupted_second(test, *args, **kwargs):
        if test.source.path.endswith("b.test.toml"):
            raise KeyboardInterrupt
        return real(test, *args, **kwargs)

    monkeypatch.setattr(ops_test, "run_one", interrupted_second)
    assert scriptc("test", "-j", "1", "--junit", "report.xml").exit_code == 130
    found = cases(read_junit(repo / "report.xml"))
    assert found["tests/a.test.toml"].is_passed
    for name in ("tests/b.test.toml", "tests/c.test.toml"):
        (skipped,) = found[name].result
        assert isinstance(skipped, junitparser.Skipped)
        assert skipped.message == "not run: interrupted (Ctrl-C)"


def test_an_output_that_cannot_be_written_stops_before_any_test(repo: Path) -> None:
    write(repo, {"tests/greets.test.toml": GREETS})
    for option in ("--junit", "--durations"):
        result = scriptc("test", option, "missing/folder/out.xml")
        assert result.exit_code == 2
        assert result.stdout == ""
        assert ("cannot write `missing/folder/out.xml`: the folder `missing/folder` does not "
                "exist") in result.stderr


def test_junit_names_tests_from_the_repository_root_wherever_it_runs(repo: Path,
                                                                       monkeypatch) -> None:
    write(repo, {"tests/greets.test.toml": GREETS})
    monkeypatch.chdir(repo / "tests")
    for path in (".", "greets.test.toml", str(repo / "tests")):
        assert scriptc("test", path, "--junit", "../r.xml").exit_code == 0
        assert list(cases(read_junit(repo / "r.xml"))) == ["tests/greets.test.toml"]


# -- --format github --------------------------------------------------------------------------


def test_github_annotates_each_failed_expectation_at_its_expect(repo: Path,
                                                                monkeypatch) -> None:
    write(repo, {"tests/fails.test.toml": FAILS, "tests/errs.test.toml": ERRS,
                 "broken.script": BROKEN_SCRIPT})
    monkeypatch.chdir(repo / "tests")  # GitHub's paths are from the repository's root
    result = scriptc("test", "-j", "1", "--format", "github")
    assert result.exit_code == 2
    annotations = [line for line in result.stdout.splitlines() if line.startswith("::")]
    assert [a.split("::")[1] for a in annotations] == [
        "notice file=broken.script,line=4,col=1,endLine=4,endColumn=13,title=F003",
        "error file=broken.script,line=4,col=35,endLine=4,endColumn=36,title=L003",
        "error file=tests/fails.test.toml,line=4,col=1,endLine=4,endColumn=11,title=T006",
        "error file=tests/fails.test.toml,line=13,col=1,endLine=13,endColumn=11,title=T006"]
    assert annotations[2].split("::")[2].startswith(
        '`never says hello`: expected at least 1 `block` event with label = "hello" during '
        "the run, found 0%0Anote: the nearest `block` events:%0Aat 0 ms: ")
    assert annotations[3].endswith("%0Ahelp: replay the run: scriptc run ../greeting.script "
                                   "--robot kinematic --no-governor --until 40000")
    # The lines of the tests and the summary stay, for the log; no text diagnostic.
    assert "FAIL  fails.test.toml (32.000 s simulated, " in result.stdout
    assert "error[T006]" not in result.stdout
    assert result.stdout.splitlines()[-1].startswith("0 passed, 1 failed, 1 error; ")


def test_github_annotates_a_broken_test_file(repo: Path) -> None:
    write(repo, {"tests/typo.test.toml": 'scripts = ["../greeting.script"]\nuntil = "x"\n'})
    result = scriptc("test", "--format", "github")
    assert result.exit_code == 2
    assert result.stdout.startswith(
        "::error file=tests/typo.test.toml,line=2,col=9,endLine=2,endColumn=12,title=T003::")


# -- shards -----------------------------------------------------------------------------------

NAMES = [f"tests/t{i:02}.test.toml" for i in range(11)]


def sharded_repo(repo: Path) -> None:
    write(repo, {name: (GREETS if i % 3 else FAILS) for i, name in enumerate(NAMES)})


def test_a_shard_split_of_4_runs_each_test_exactly_once(repo: Path) -> None:
    """The issue's figure: four jobs, by `--shard I/4` and by the variables, each run their
    part; merged, their JUnit reports list every test once."""
    sharded_repo(repo)
    by_option, by_variables = [], []
    for i in range(4):
        result = scriptc("test", "-j", "1", "--shard", f"{i + 1}/4", "--junit", f"opt{i}.xml")
        assert result.exit_code == 1, result.output
        by_option.append(set(cases(read_junit(repo / f"opt{i}.xml"))))
        assert f"shard {i + 1}/4: {len(by_option[-1])} of the 11 tests\n" in result.stderr
        report = read_junit(repo / f"opt{i}.xml")
        assert {p.name: p.value for suite in report for p in suite.properties()}["shard"] == \
            f"{i + 1}/4"
        result = scriptc("test", "-j", "1", "--junit", f"env{i}.xml",
                         env={"TEST_TOTAL_SHARDS": "4", "TEST_SHARD_INDEX": str(i)})
        assert result.exit_code == 1
        by_variables.append(set(cases(read_junit(repo / f"env{i}.xml"))))
    assert by_option == by_variables  # the same split, whichever way it is asked for
    assert sorted(len(part) for part in by_option) == [2, 3, 3, 3]  # by count: even
    assert sorted(set().union(*by_option)) == NAMES
    merged = scriptc("merge", "all.xml", *(f"opt{i}.xml" for i in range(4)))
    assert merged.exit_code == 0 and merged.stderr == ""
    report = read_junit(repo / "all.xml")
    assert list(cases(report)) == NAMES  # every test once, in the order of one run
    (suite,) = list(report)
    assert report.name == suite.name == "scriptc test"
    assert (suite.tests, suite.failures, suite.errors) == (11, 4, 0)
    assert [(p.name, p.value) for p in suite.properties()] == [
        ("scriptc", __version__), ("executor", "vm"), ("shard", "1/4"), ("shard", "2/4"),
        ("shard", "3/4"), ("shard", "4/4")]


def test_durations_recorded_by_a_run_balance_the_shards(repo: Path) -> None:
    sharded_repo(repo)
    write(repo, {"tests/errs.test.toml": ERRS, "broken.script": BROKEN_SCRIPT})
    assert scriptc("test", "-j", "1", "--durations", "d.json").exit_code == 2
    recorded = json.loads((repo / "d.json").read_text(encoding="utf-8"))["durations"]
    # Every test that ran; not the one that could not (loading alone is no measure of it).
    assert sorted(recorded) == NAMES and all(s >= 0 for s in recorded.values())
    (repo / "tests" / "errs.test.toml").unlink()
    # One test weighs as much as all the others: it has a shard of its own.
    heavy = dict.fromkeys(NAMES, 0.001) | {NAMES[5]: 1.0}
    (repo / "d.json").write_text(json.dumps({"durations": heavy}), encoding="utf-8")
    parts = []
    for i in range(2):
        result = scriptc("test", "-j", "1", "--shard", f"{i + 1}/2", "--durations", "d.json",
                         "--junit", f"s{i}.xml")
        assert result.exit_code == i  # t05 passes; the other shard has the failures
        parts.append(sorted(cases(read_junit(repo / f"s{i}.xml"))))
    assert parts == [[NAMES[5]], [n for n in NAMES if n != NAMES[5]]]
    # A shard only reads the file: another job may be reading it still.
    assert json.loads((repo / "d.json").read_text(encoding="utf-8"))["durations"] == heavy
    # A run that is not sharded records what it ran, and keeps the rest.
    assert scriptc("test", "-k", "t05", "--durations", "d.json").exit_code == 0
    updated = json.loads((repo / "d.json").read_text(encoding="utf-8"))["durations"]
    assert updated[NAMES[5]] != 1.0 and {k: v for k, v in updated.items() if k != NAMES[5]} \
        == {k: v for k, v in heavy.items() if k != NAMES[5]}


def test_without_a_durations_file_yet_shards_go_by_count(repo: Path) -> None:
    sharded_repo(repo)
    result = scriptc("test", "--shard", "1/2", "--durations", "none.json")
    assert ("warning: no durations recorded in `none.json` yet: the shards are balanced by "
            "the number of tests\n") in result.stderr
    assert "shard 1/2: 6 of the 11 tests\n" in result.stderr
    assert not (repo / "none.json").exists()


@pytest.mark.parametrize(("text", "message"), [
    ("[]", ("`d.json` is not a durations file: a JSON object whose `durations` maps each test "
           "to the seconds it took (`scriptc test --durations FILE` writes one)")),
    ('{"durations": {"a": -1}}', "`a` has -1"),
    ('{"durations": {"a": NaN}}', "NaN is not a number of seconds"),
    ('{"durations": {"a": true}}', "`a` has true"),
    ("{", "is not a durations file"),
])
def test_a_durations_file_that_is_not_one_is_refused(repo: Path, text: str,
                                                     message: str) -> None:
    sharded_repo(repo)
    (repo / "d.json").write_text(text, encoding="utf-8")
    result = scriptc("test", "--durations", "d.json")
    assert result.exit_code == 2 and result.stdout == ""
    assert message in result.stderr


@pytest.mark.parametrize(("args", "env", "message"), [
    (["--shard", "0/4"], {}, "`0/4` is not a shard: I goes from 1 to N"),
    (["--shard", "5/4"], {}, "`5/4` is not a shard: I goes from 1 to N"),
    (["--shard", "1/0"], {}, "`1/0` is not a shard: I goes from 1 to N"),
    (["--shard", "two/4"], {}, "`two/4` is not a shard: write I/N"),
    (["--shard", "2"], {}, "`2` is not a shard: write I/N"),
    ([], {"TEST_TOTAL_SHARDS": "4"}, "TEST_TOTAL_SHARDS is set but TEST_SHARD_INDEX is not"),
    ([], {"TEST_SHARD_INDEX": "0"}, "TEST_SHARD_INDEX is set but TEST_TOTAL_SHARDS is not"),
    ([], {"TEST_TOTAL_SHARDS": "4", "TEST_SHARD_INDEX": "4"},
     "TEST_TOTAL_SHARDS=4 and TEST_SHARD_INDEX=4 name no shard"),
    ([], {"TEST_TOTAL_SHARDS": "0", "TEST_SHARD_INDEX": "0"}, "name no shard"),
    ([], {"TEST_TOTAL_SHARDS": "x", "TEST_SHARD_INDEX": "0"}, "name no shard"),
])
def test_a_shard_that_names_none_is_refused(repo: Path, args: list[str], env: dict[str, str],
                                            message: str) -> None:
    sharded_repo(repo)
    result = scriptc("test", *args, env=env)
    assert result.exit_code == 2 and result.stdout == ""
    assert message in result.stderr


def test_the_option_wins_over_the_variables_and_bazel_is_told(repo: Path) -> None:
    sharded_repo(repo)
    status = repo / "sharding.status"
    env = {"TEST_TOTAL_SHARDS": "2", "TEST_SHARD_INDEX": "1",
           "TEST_SHARD_STATUS_FILE": str(status)}
    result = scriptc("test", "--shard", "1/3", env=env)
    assert "shard 1/3: 4 of the 11 tests" in result.stderr
    assert not status.exists()  # Bazel did not shard this run: the option did
    result = scriptc("test", env=env)
    assert "shard 2/2: 5 of the 11 tests" in result.stderr
    assert status.exists()
    # The variables are not even read then: half of them set is no error with the option.
    result = scriptc("test", "--shard", "3/3", env={"TEST_TOTAL_SHARDS": "2"})
    assert "shard 3/3: 3 of the 11 tests" in result.stderr


def test_more_shards_than_tests_leaves_some_empty(repo: Path) -> None:
    write(repo, {"tests/a.test.toml": GREETS})
    result = scriptc("test", "--shard", "2/2", "--junit", "r.xml")
    assert result.exit_code == 0
    assert "shard 2/2: 0 of the 1 tests\n" in result.stderr
    assert cases(read_junit(repo / "r.xml")) == {}
    # `-k` found its test: the shard is empty, not the selection.
    result = scriptc("test", "-k", "a.test", "--shard", "2/2")
    assert result.exit_code == 0
    assert result.stderr == "shard 2/2: 0 of the 1 tests\n"


def test_the_first_tests_scripts_are_loaded_before_any_test_is_timed(repo: Path,
                                                                     monkeypatch) -> None:
    """A test's seconds (what `--durations` records and shards are balanced by) leave out
    the imports and the grammar, which the first test to run would pay for: they are loaded
    before it, in one process as before the workers."""
    from scriptc.ops import test as ops_test

    write(repo, {"tests/a.test.toml": GREETS, "tests/b.test.toml": GREETS})
    calls: list[str] = []
    prepare, run_one = ops_test._prepare, ops_test.run_one

    def spy_prepare(test, *args, **kwargs):
        calls.append(f"prepare {test.source.path}")
        return prepare(test, *args, **kwargs)

    def spy_run_one(test, *args, **kwargs):
        calls.append(f"run {test.source.path}")
        return run_one(test, *args, **kwargs)

    monkeypatch.setattr(ops_test, "_prepare", spy_prepare)
    monkeypatch.setattr(ops_test, "run_one", spy_run_one)
    assert scriptc("test", "-j", "1").exit_code == 0
    assert calls == ["prepare tests/a.test.toml", "run tests/a.test.toml",
                     "run tests/b.test.toml"]


def test_shard_parsing() -> None:
    assert parse_shard("2/4") == Shard(1, 4) and str(Shard(1, 4)) == "2/4"
    assert parse_shard(" 1 / 1 ") == Shard(0, 1)
    assert shard_from_environment({}) is None
    assert shard_from_environment({"TEST_TOTAL_SHARDS": "", "TEST_SHARD_INDEX": ""}) is None
    assert shard_from_environment({"TEST_TOTAL_SHARDS": "3", "TEST_SHARD_INDEX": "2"}) == \
        Shard(2, 3)
    with pytest.raises(ShardError):
        shard_from_environment({"TEST_TOTAL_SHARDS": "3", "TEST_SHARD_INDEX": "-1"})


# Tests (distinct names) with durations, some not recorded (None), split into N shards; or all
# of one duration (0.0: tests faster than the millisecond a durations file records).
NAMES_ = st.text("abcdef/.", min_size=1, max_size=8)
TESTS = st.dictionaries(NAMES_, st.none() | st.floats(0, 100, allow_nan=False), max_size=40) \
    | st.builds(dict.fromkeys, st.lists(NAMES_, max_size=40), st.sampled_from([0.0, 2.5]))


@settings(max_examples=300, deadline=None)
@given(TESTS, st.integers(1, 12), st.randoms(use_true_random=False))
def test_shards_partition_the_tests_and_the_heaviest_is_within_the_longest_of_even(
        tests: dict[str, float | None], total: int, rng) -> None:
    keys = list(tests)
    durations = {k: v for k, v in tests.items() if v is not None}
    parts = partition(keys, total, durations)
    assert len(parts) == total
    assert sorted(i for part in parts for i in part) == list(range(len(keys)))
    if durations:
        average = sum(durations.values()) / len(durations)
        weights = [durations.get(k, average) for k in keys]
    else:
        weights = [1.0] * len(keys)
    loads = [sum(weights[i] for i in part) for part in parts]
    if keys:
        assert max(loads) <= sum(weights) / total + max(weights) + 1e-9
    if len(set(weights)) <= 1:  # by count, or all alike: even to one test
        sizes = [len(part) for part in parts]
        assert max(sizes) - min(sizes) <= 1
    # The split depends on the tests, not on the order they were found in.
    shuffled = keys[:]
    rng.shuffle(shuffled)
    again = partition(shuffled, total, durations)
    assert [sorted(shuffled[i] for i in part) for part in again] == \
        [sorted(keys[i] for i in part) for part in parts]


# -- scriptc merge ----------------------------------------------------------------------------

SUITE = """<?xml version="1.0"?>
<testsuite name="{name}" tests="{n}" failures="0" errors="0" time="{time}" hostname="{host}"
           timestamp="{stamp}">
  <properties><property name="p" value="{value}"/></properties>
  {cases}
  <system-out>{out}</system-out>
</testsuite>
"""


def junit_file(path: Path, *, name: str = "pytest", cases: str = "", time: str = "1.5",
               host: str = "a", value: str = "1", out: str = "",
               stamp: str = "2026-05-02T10:00:00") -> str:
    n = cases.count("<testcase")
    path.write_text(SUITE.format(name=name, n=n, time=time, host=host, value=value,
                                 cases=cases, out=out, stamp=stamp), encoding="utf-8")
    return str(path)


def test_merge_joins_suites_of_one_name_and_keeps_the_others(repo: Path) -> None:
    a = junit_file(repo / "a.xml", cases='<testcase classname="m" name="z" time="1"/>'
                   '<testcase classname="m" name="x" time="2"><failure message="f"/></testcase>',
                   time="1,001.5", out="first")
    b = junit_file(repo / "b.xml", cases='<testcase classname="m" name="y"><error/></testcase>'
                   '<testsuite name="inner" tests="1" failures="0" errors="0">'
                   '<testcase name="n"/></testsuite>',
                   host="b", value="2", out="second", stamp="2026-05-01T09:00:00")
    c = junit_file(repo / "c.xml", name="other", time="",  # no time: its cases' added up
                   cases='<testcase name="q" time="0.25"><skipped/></testcase>')
    d = junit_file(repo / "d.xml", out="\n  ", stamp="2026-05-03T08:00:00", time="-3")
    e = junit_file(repo / "e.xml", time="nan", value="1")  # no number of seconds: none
    result = scriptc("merge", "out.xml", a, b, c, d, e)
    assert result.exit_code == 0, result.output
    report = read_junit(repo / "out.xml")
    assert report.name is None  # two suites of two names: neither names the whole
    first, other = list(report)
    assert first.name == "pytest" and other.name == "other"
    assert [case.name for case in first] == ["x", "y", "z", "n"]  # junitparser reads deep
    # The suite nested in b's is kept after the cases, and its case counted.
    root = ElementTree.parse(repo / "out.xml").getroot()
    assert [case.get("name") for case in root.iterfind("testsuite/testsuite/testcase")] == ["n"]
    assert (first.tests, first.failures, first.errors, first.skipped) == (4, 1, 1, 0)
    assert first.time == pytest.approx(1003.0)
    assert first.hostname is None  # the machines differ: neither is kept
    assert first.timestamp == "2026-05-01T09:00:00"  # the earliest
    assert [(p.name, p.value) for p in first.properties()] == [("p", "1"), ("p", "2")]
    assert [suite.findtext("system-out") for suite in root] == ["first\nsecond\n", None]
    assert (other.tests, other.skipped, other.hostname, other.time) == (1, 1, "a", 0.25)
    assert (report.tests, report.failures, report.errors) == (5, 1, 1)


def test_merge_chooses_the_kind_from_a_table(monkeypatch) -> None:
    """A kind is a row of `KINDS`: by the output's suffix, then by what the inputs hold; the
    error names the input that is not of the kind most inputs are."""
    from scriptc.testing import merge

    def lines(inputs):
        return "".join(data.decode() for _name, data in inputs), []

    plain = merge.Kind("plain text", (".txt", ".xml"), lambda data: data.startswith(b"line"),
                       lines)
    (junit_kind,) = [kind for kind in merge.KINDS if kind.name == "JUnit XML"]
    monkeypatch.setattr(merge, "KINDS", (junit_kind, plain))
    junit, text = ("a.xml", b"<testsuite name='s'/>"), ("a.txt", b"line 1\n")
    assert merge.kind_for("out.xml", [junit]).name == "JUnit XML"
    assert merge.kind_for("out.xml", [text, text]) is plain  # .xml fits both: the inputs say
    assert merge.kind_for("-", [text]) is plain
    assert merge.kind_for("OUT.TXT", [text]) is plain
    with pytest.raises(merge.MergeError, match=r"^`a.xml` is not a plain text file: merge"):
        merge.kind_for("-", [text, text, junit])
    with pytest.raises(merge.MergeError, match=r"^`a.txt` is not a JUnit XML file: merge"):
        merge.kind_for("-", [junit, text, junit])
    with pytest.raises(merge.MergeError, match=r"end it with .xml \(JUnit XML\), .txt or .xml "
                                               r"\(plain text\)$"):
        merge.kind_for("out.csv", [text])


def test_merge_says_when_a_test_is_in_several_inputs(repo: Path) -> None:
    one = '<testcase classname="m" name="x"/>'
    a, b = junit_file(repo / "a.xml", cases=one), junit_file(repo / "b.xml", cases=one)
    result = scriptc("merge", "-", a, b)
    assert result.exit_code == 0
    assert result.stderr == f"note: `x` is in 2 inputs ({a}, {b}): each is kept\n"
    assert result.stdout.count("<testcase") == 2


@pytest.mark.parametrize(("output", "inputs", "message"), [
    ("out.txt", ["a.xml"], ("`out.txt`: scriptc merge cannot tell what to write by this "
                           "name: end it with .xml (JUnit XML)")),
    ("out.xml", ["a.xml", "missing.xml"], "`missing.xml` does not exist"),
    ("out.xml", ["a.xml", "tests"], "`tests` is a folder: name the files to merge"),
    ("out.xml", ["a.xml", "d.json"], ("`d.json` is not a JUnit XML file (what `out.xml` is to "
                                     "be): merge files of one kind")),
    ("-", ["d.json"], "`d.json` is not a JUnit XML file: merge files of one kind"),
    ("out.xml", ["a.xml", "bad.xml"], "`bad.xml`:3:3: not XML: mismatched tag"),
    ("out.xml", ["a.xml", "other.xml"], ("`other.xml` is not a JUnit report: its root is "
                                        "<{urn:x}testsuite>, not <testsuites> or <testsuite>")),
    ("a.xml", ["b.xml", "./a.xml"], ("the output `a.xml` is one of the inputs: refusing to "
                                    "overwrite it")),
    ("nowhere/out.xml", ["a.xml"], ("cannot write `nowhere/out.xml`: the folder `nowhere` "
                                   "does not exist")),
])
def test_merge_refuses_what_it_cannot_merge(repo: Path, output: str, inputs: list[str],
                                            message: str) -> None:
    junit_file(repo / "a.xml")
    junit_file(repo / "b.xml")
    (repo / "d.json").write_text('{"durations": {}}', encoding="utf-8")
    (repo / "bad.xml").write_text("<testsuite name='x'>\n<testcase>\n</testsuite>\n",
                                  encoding="utf-8")
    (repo / "other.xml").write_text("<?xml version='1.0'?>\n<!-- c -->\n<testsuite "
                                    "xmlns='urn:x'/>", encoding="utf-8")
    before = (repo / "a.xml").read_bytes()
    result = scriptc("merge", output, *inputs)
    assert result.exit_code == 2 and result.stdout == ""
    assert message in result.stderr, result.stderr
    assert not (repo / "out.xml").exists() and (repo / "a.xml").read_bytes() == before


def test_merge_needs_inputs(repo: Path) -> None:
    result = scriptc("merge", "out.xml")
    assert result.exit_code == 2 and "Missing argument 'INPUT...'" in result.stderr


# -- the progress bar -------------------------------------------------------------------------


class Terminal(io.StringIO):
    """A stream that says it is a terminal, writing into a log shared with the other stream,
    so that the order of what went to stdout and to stderr shows."""

    def __init__(self, name: str, log: list[tuple[str, str]]) -> None:
        super().__init__()
        self.name, self.log = name, log

    def isatty(self) -> bool:
        return True

    def write(self, text: str) -> int:
        self.log.append((self.name, text))
        return super().write(text)


def on_a_terminal(monkeypatch, *args: str) -> tuple[int, list[tuple[str, str]]]:
    """`scriptc ARGS` in this process, stdout and stderr a terminal's."""
    import sys

    log: list[tuple[str, str]] = []
    monkeypatch.setattr(sys, "stdout", Terminal("out", log))
    monkeypatch.setattr(sys, "stderr", Terminal("err", log))
    monkeypatch.setenv("TERM", "xterm")
    monkeypatch.setenv("NO_COLOR", "1")
    status = cli.main(list(args), prog_name="scriptc", standalone_mode=False)
    return status, log


def test_the_progress_bar_shows_on_a_terminal_with_many_tests(repo: Path,
                                                              monkeypatch) -> None:
    quick = GREETS.replace("until = 60000", "until = 500").replace(
        '[[expect]]\nevent = "block"\nwhere = { label = "hello" }\n', "")
    write(repo, {f"tests/t{i:02}.test.toml": quick for i in range(50)})
    status, log = on_a_terminal(monkeypatch, "test", "-j", "1")
    assert status == 0
    bar = [i for i, (stream, text) in enumerate(log) if stream == "err" and "testing" in text]
    lines = [i for i, (stream, text) in enumerate(log) if stream == "out" and "PASS" in text]
    assert bar and len(lines) == 50
    assert "50/50" in "".join(text for stream, text in log if stream == "err")
    assert max(bar) < min(lines)  # the lines wait for the end, under the bar
    assert log[-1][0] == "out" and log[-1][1].startswith("50 passed; ")
    # Fewer than 50 tests, or -q: no bar, the lines as they come.
    for args in (["-k", "t0"], ["-q"]):
        _status, log = on_a_terminal(monkeypatch, "test", "-j", "1", *args)
        assert [stream for stream, _text in log] == ["out"] * len(log)
