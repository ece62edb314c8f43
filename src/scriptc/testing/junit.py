"""JUnit XML, the test report CI services read (docs/testing.md, "JUnit XML"): `report` writes
a run's, `merge` merges the reports of a run's shards into one (`scriptc merge`).

The report holds to the JUnit schema of Jenkins' xUnit plugin (`junit-10.xsd`, which pytest's
reports follow too), the strictest reader among Jenkins, GitLab and GitHub's report actions:

- one `testsuite` (`scriptc test`) in a `testsuites`, with the counts, the seconds the run took,
  when it started and on which machine, and `properties` that say how it ran (the scriptc
  version, the executor, `-k`, the shard);
- one `testcase` per test file, named by its path from the repository's root (as GitHub and
  GitLab resolve files; `classname` is that path without `.test.toml`, its folders dotted, as
  Jenkins groups tests by package), with the seconds it took;
- a failing test has one `failure` (its type the code of the first failure, T006 for an
  expectation): its message lists every failed expectation, one a line, and its text is their
  diagnostics in full, each ending with the `scriptc run` command that replays the run; a
  test that could not run has an `error` with the reason and the diagnostics of the files
  that stopped it (its type the code of the first error), and so has a test file with a
  problem (then no test ran); a test Ctrl-C stopped before it ran is `skipped`;
- the schema admits no properties on a test case, so a test's own facts (its description, how
  and when its session ended, the replay command) are lines `key: value` of its `system-out`.

Text in the XML keeps to the characters XML 1.0 allows: a control character becomes its
visible picture (U+2400 block), anything else XML cannot hold becomes U+FFFD.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from datetime import datetime
from xml.etree import ElementTree as ET

from scriptc.diagnostics.model import Diagnostic, Severity
from scriptc.diagnostics.render import plural, render_text
from scriptc.source import SourceFile
from scriptc.testing.model import TestFile
from scriptc.testing.read import SUFFIX, ReadTest
from scriptc.testing.report import diagnosed
from scriptc.testing.run import ERROR, FAILED, TestResult
from scriptc.testing.shard import test_key

__all__ = ["SUITE", "JUnitError", "is_junit", "merge", "report"]

SUITE = "scriptc test"  # the name of the one test suite
INTERRUPTED = "not run: interrupted (Ctrl-C)"

# What XML 1.0 cannot hold (its `Char` production), to be replaced.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


class JUnitError(ValueError):
    """An input of `merge` that is not a JUnit report: the message names the file, and the
    line and column where XML could not be read."""


def _xml(text: str) -> str:
    return _NOT_XML.sub(lambda m: chr(0x2400 + ord(m.group())) if m.group() < " "
                        else "\ufffd", text)


def _seconds(s: float) -> str:
    """Seconds as the schema's time (`SUREFIRE_TIME`): at most three decimals."""
    return f"{s:.3f}"


def _classname(key: str) -> str:
    stem = key[: -len(SUFFIX)] if key.endswith(SUFFIX) else key
    return stem.replace("/", ".")


def _case(parent: ET.Element, path: str, wall_s: float) -> ET.Element:
    key = test_key(path)
    return ET.SubElement(parent, "testcase", classname=_xml(_classname(key)), name=_xml(key),
                         time=_seconds(wall_s))


def _outcome(case: ET.Element, tag: str, message: str, text: str,
             kind: str | None = None) -> None:
    element = ET.SubElement(case, tag, message=_xml(message))
    if kind is not None:
        element.set("type", kind)
    element.text = _xml(text)


def _listed(diagnostics: Sequence[Diagnostic], source: SourceFile) -> list[str]:
    """One line per diagnostic: `error[T002] at 3:1: unknown key ...`."""
    lines = []
    for d in diagnostics:
        where = source.position(d.span.start)
        lines.append(f"{d.severity.value}[{d.code}] at {where.line}:{where.column}: {d.message}")
    return lines


def _system_out(case: ET.Element, facts: Sequence[tuple[str, str]]) -> None:
    lines = [f"{key}: {value}" for key, value in facts if value]
    if lines:
        ET.SubElement(case, "system-out").text = _xml("\n".join(lines) + "\n")


def _result_case(suite: ET.Element, test: TestFile, result: TestResult) -> None:
    case = _case(suite, result.path, result.wall_s)
    files = diagnosed(test, result)
    if result.status == FAILED:
        found = [d for _source, diagnostics in files for d in diagnostics]
        head = f"{len(found)} of {plural(len(result.verdicts), 'expectation')} failed"
        # The type is the code of the first failure: T006, an expectation (or T007, a snapshot).
        _outcome(case, "failure", "\n".join([head, *(d.message for d in found)]),
                 render_text(files), found[0].code)
    elif result.status == ERROR:
        # The type is the code of the first error that stopped it (a script's notes aside).
        codes = [d.code for _source, diagnostics in files for d in diagnostics
                 if d.severity is Severity.ERROR]
        _outcome(case, "error", result.reason, render_text(files) or result.reason + "\n",
                 codes[0] if codes else None)
    ended = "" if result.time_ms is None else f"{result.time_ms} ms simulated ({result.outcome})"
    _system_out(case, [("description", result.description), ("status", result.status),
                       ("session", ended), ("replay", result.replay)])


def report(tests: Sequence[TestFile], results: Sequence[TestResult], *,
           invalid: Sequence[ReadTest] = (), interrupted: bool = False,
           properties: Sequence[tuple[str, str]] = (), wall_s: float = 0.0,
           timestamp: datetime | None = None, hostname: str | None = None) -> str:
    """The JUnit XML of a run: a case for each result (in the order of `tests`), each test
    Ctrl-C stopped before it ran skipped (`interrupted`), and a case with an `error` for each
    test file with problems (`invalid`: then nothing ran)."""
    root = ET.Element("testsuites", name=SUITE)
    suite = ET.SubElement(root, "testsuite", name=SUITE)
    if properties:
        holder = ET.SubElement(suite, "properties")
        for name, value in properties:
            ET.SubElement(holder, "property", name=_xml(name), value=_xml(value))
    for read in invalid:
        case = _case(suite, read.source.path, 0.0)
        lines = _listed(read.diagnostics, read.source)
        head = f"the test file has {plural(len(lines), 'problem')}: no test ran"
        _outcome(case, "error", "\n".join([head, *lines]),
                 render_text([(read.source, read.diagnostics)]), read.diagnostics[0].code)
    by_path = {test.source.path: test for test in tests}
    for result in results:
        _result_case(suite, by_path[result.path], result)
    if interrupted:
        for test in tests[len(results):]:
            case = _case(suite, test.source.path, 0.0)
            ET.SubElement(case, "skipped", message=INTERRUPTED)
    _count(suite)
    suite.set("time", _seconds(wall_s))
    if timestamp is not None:
        suite.set("timestamp", timestamp.isoformat(timespec="seconds"))
    if hostname:
        suite.set("hostname", _xml(hostname))
    _total(root)
    return _text(root)


def _count(suite: ET.Element) -> None:
    """A suite's counts from its cases (nested suites' too): an error counts before a failure,
    a failure before a skip."""
    tests = failed = errors = skipped = 0
    for case in suite.iter("testcase"):
        tests += 1
        if case.find("error") is not None:
            errors += 1
        elif case.find("failure") is not None:
            failed += 1
        elif case.find("skipped") is not None:
            skipped += 1
    suite.set("tests", str(tests))
    suite.set("failures", str(failed))
    suite.set("errors", str(errors))
    suite.set("skipped", str(skipped))


def _total(root: ET.Element) -> None:
    """The root's totals: the sums of its suites'."""
    suites = root.findall("testsuite")
    for attribute in ("tests", "failures", "errors"):
        root.set(attribute, str(sum(int(s.get(attribute) or 0) for s in suites)))
    root.set("time", _seconds(sum(_time(s) for s in suites)))


def _text(root: ET.Element) -> str:
    ET.indent(root, space="  ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, "unicode") + "\n"


# -- merging ------------------------------------------------------------------------------------

# The start of a JUnit report: its root element, after the XML declaration and comments.
_ROOT = re.compile(rb"<(testsuites|testsuite)[\s/>]")


def is_junit(data: bytes) -> bool:
    """Whether `data` looks like a JUnit report (its root is `testsuites` or `testsuite`),
    judged from its start without reading it whole."""
    head = data[:4096]
    start = re.search(rb"<[A-Za-z]", head)
    return start is not None and _ROOT.match(head, start.start()) is not None


def _time(element: ET.Element) -> float:
    """An element's `time` in seconds (`1,234.5` as the schema allows: thousands with commas);
    without one, its cases' times added up. A time that is no number of seconds (text,
    negative, `nan`) counts as none: the merged report stays valid."""
    written = (element.get("time") or "").replace(",", "")
    if not written:
        return sum(_time(case) for case in element if case.tag == "testcase")
    try:
        seconds = float(written)
    except ValueError:
        return 0.0
    return seconds if math.isfinite(seconds) and seconds > 0 else 0.0


def _suites(name: str, data: bytes) -> list[ET.Element]:
    try:
        root = ET.fromstring(data)
    except ET.ParseError as exc:
        line, column = exc.position
        raise JUnitError(f"`{name}`:{line}:{column + 1}: not XML: "
                         f"{str(exc).split(':')[0]}") from None
    if root.tag == "testsuite":
        return [root]
    if root.tag == "testsuites":
        return root.findall("testsuite")
    raise JUnitError(f"`{name}` is not a JUnit report: its root is <{root.tag}>, not "
                     "<testsuites> or <testsuite>")


def merge(inputs: Sequence[tuple[str, bytes]]) -> tuple[str, list[str]]:
    """One report of several (`name`, content), and notes for the person merging. The suites
    of the same name become one suite holding all their cases, sorted by class and name (the
    order of a run that was not sharded), its counts counted again, its time the sum of
    theirs, its timestamp the earliest, its properties all theirs (each once), an attribute
    kept where they all agree. A case in several inputs is kept each time, and named in a
    note: sharded runs never give one."""
    groups: dict[str, list[tuple[str, ET.Element]]] = {}
    for name, data in inputs:
        for suite in _suites(name, data):
            groups.setdefault(suite.get("name") or "", []).append((name, suite))
    root = ET.Element("testsuites")
    if len(groups) == 1:
        root.set("name", next(iter(groups)))
    notes: list[str] = []
    for suite_name, members in groups.items():
        root.append(_merge_suite(suite_name, members, notes))
    _total(root)
    return _text(root), notes


def _merge_suite(name: str, members: list[tuple[str, ET.Element]],
                 notes: list[str]) -> ET.Element:
    suites = [suite for _input, suite in members]
    suite = ET.Element("testsuite", name=name)
    seen: list[tuple[str, str]] = []
    for s in suites:
        for p in s.iterfind("properties/property"):
            pair = (p.get("name", ""), p.get("value", ""))
            if pair not in seen:
                seen.append(pair)
    if seen:
        holder = ET.SubElement(suite, "properties")
        for key, value in seen:
            ET.SubElement(holder, "property", name=key, value=value)
    cases: list[tuple[str, ET.Element]] = [(source, case) for source, s in members
                                           for case in s.findall("testcase")]
    cases.sort(key=lambda item: (item[1].get("classname", ""), item[1].get("name", "")))
    where: dict[tuple[str, str], list[str]] = {}
    for source, case in cases:
        suite.append(case)
        where.setdefault((case.get("classname", ""), case.get("name", "")), []).append(source)
    for (_classname, case_name), sources in where.items():
        if len(sources) > 1:
            notes.append(f"`{case_name}` is in {len(sources)} inputs "
                         f"({', '.join(dict.fromkeys(sources))}): each is kept")
    for s in suites:  # nested suites, and the suites' own output, after the cases
        suite.extend(s.findall("testsuite"))
    for stream in ("system-out", "system-err"):
        texts = [e.text for s in suites for e in s.findall(stream) if e.text and e.text.strip()]
        if texts:
            ET.SubElement(suite, stream).text = "".join(t if t.endswith("\n") else t + "\n"
                                                        for t in texts)
    _count(suite)
    suite.set("time", _seconds(sum(_time(s) for s in suites)))
    stamps = sorted(s.get("timestamp", "") for s in suites if s.get("timestamp"))
    if stamps:
        suite.set("timestamp", stamps[0])
    counted = {"name", "tests", "failures", "errors", "skipped", "time", "timestamp"}
    for attribute, value in suites[0].attrib.items():
        if attribute not in counted and all(s.get(attribute) == value for s in suites):
            suite.set(attribute, value)
    return suite
