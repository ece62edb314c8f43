"""scriptc's pytest plugin (entry point `pytest11`, named `scriptc`): the test files of an
activity (`*.test.toml`, docs/testing.md) collected and run as pytest items, with the verdicts
and messages of `scriptc test`, so a repository that runs pytest runs its activities' tests too.

Decisions (docs/testing.md, "With pytest"):

- **Opt-in.** Installing scriptc installs the plugin into every pytest of that environment; it
  must not change a suite that never asked for it (this repository's own holds test files
  that fail on purpose). It collects when the ini option `scriptc_tests` is true (`pytest.ini`,
  `[tool.pytest.ini_options]`, `tox.ini`, `setup.cfg`, or `-o scriptc_tests=true`), and
  always a test file named on the command line (`pytest greeting.test.toml`), as `scriptc test`
  takes a file named whatever its name. Otherwise it imports nothing of scriptc and adds
  nothing; `-p no:scriptc` removes it.
- **Which files**: the `*.test.toml` files pytest's own collection meets (its arguments or
  `testpaths`, `norecursedirs`, `--ignore`, `collect_ignore`), less those the repository's
  scriptc configuration excludes (`exclude`), as `scriptc test` leaves them out.
- **Collecting is checking**: each file is read and checked whole, as `scriptc test` checks it;
  a file with a problem is a collection error whose text is its diagnostics (T001-T005), and
  pytest then runs nothing, as `scriptc test` runs nothing.
- **One item per file**, named by the file's name without `.test.toml`
  (`examples/tests/greeting.test.toml::greeting`), as `scriptc test` and its JUnit report count
  one test per file. `-k` matches the names of the item and of its folders and file, as for
  any pytest item, and the test's `description` (`scriptc test -k` searches it too).
- **Running** is `scriptc test`'s (`scriptc.ops.test.run_one`), in the process that runs the
  item (pytest's own, or an xdist worker's): a test that fails is a failed item whose message
  is the T006 diagnostics `scriptc test` prints for it; a test that cannot run (a script with
  errors) is a failed item whose message is `scriptc test`'s ERROR line and the scripts'
  diagnostics. The simulated time and the replay command are the item's `user_properties`
  (JUnit XML's `<properties>`).

pytest is imported here only (an import contract); scriptc's own modules are imported when a
test file is met, not when pytest loads the plugin.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from scriptc.testing import SUFFIX, is_test_file

if TYPE_CHECKING:
    from collections.abc import Iterator

    from scriptc.project.config.load import Resolver
    from scriptc.testing.model import TestFile

INI = "scriptc_tests"
# The configurations met while collecting, each read once a session.
_RESOLVER: pytest.StashKey[Resolver] = pytest.StashKey()


def pytest_addoption(parser: pytest.Parser, pluginmanager: pytest.PytestPluginManager) -> None:
    parser.addini(INI, type="bool", default=False,
                  help="collect scriptc's test files (*.test.toml) as tests (docs/testing.md)")
    _compiled_as_python_compiles(pluginmanager)


def _compiled_as_python_compiles(pluginmanager: pytest.PytestPluginManager) -> None:
    """pytest rewrites the `assert` statements of every module of a distribution that ships a
    plugin, so that a plugin's helpers explain their failures; scriptc's asserts are its own
    invariants, not tests. Unmarked, scriptc runs under pytest exactly as everywhere else, and
    its modules load as fast (where no bytecode is written, all of them took 1.5 s to rewrite
    and compile against 0.6 s to compile). pytest has no public way to unmark a package: its
    hook keeps the marked names in `_must_rewrite` (pytest 8 and 9), which this reads
    defensively; without it, scriptc is rewritten, which changes nothing but the time. The
    modules imported before this runs (this one and the package `scriptc.testing`, without
    asserts) are the only ones rewritten."""
    hook = getattr(pluginmanager, "rewrite_hook", None)
    marked = getattr(hook, "_must_rewrite", None)
    decided = getattr(hook, "_marked_for_rewrite_cache", None)
    if isinstance(marked, set) and isinstance(decided, dict):
        marked.discard(__name__.partition(".")[0])
        decided.clear()


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> TestFileCollector | None:
    if not is_test_file(file_path.name):
        return None
    named = parent.session.isinitpath(file_path)
    if not named and not (parent.config.getini(INI) and _included(parent.config, file_path)):
        return None
    return TestFileCollector.from_parent(parent, path=file_path)


def _included(config: pytest.Config, path: Path) -> bool:
    """Whether the scriptc configuration over `path` keeps it (`exclude`), as the walk of
    `scriptc test` decides (`scriptc.project.files.discover`)."""
    from scriptc.project.files import discover

    resolver = config.stash.get(_RESOLVER, None)
    if resolver is None:
        from scriptc.project.config.load import Resolver

        resolver = config.stash[_RESOLVER] = Resolver()
    found, _problems = discover([str(path)], resolver=resolver, force_exclude=True,
                                suffix=SUFFIX)
    return bool(found)


class TestFileCollector(pytest.File):
    """A `*.test.toml` file: read and checked when collected; its one item, the test."""

    def collect(self) -> Iterator[TestItem]:
        from scriptc.analysis.read import ReadError
        from scriptc.diagnostics.render import render
        from scriptc.paths import shown_path
        from scriptc.testing.read import read_test

        try:  # named from the working folder, as `scriptc test` names the files it finds
            read = read_test(shown_path(os.fspath(self.path)))
        except ReadError as exc:
            raise self.CollectError(str(exc)) from None
        if read.test is None:
            raise self.CollectError(render("text", [(read.source, read.diagnostics)]))
        name = self.path.name[: -len(SUFFIX)]  # collected for its suffix
        item = TestItem.from_parent(self, name=name, test=read.test)
        if read.test.description:
            item.extra_keyword_matches.add(read.test.description)
        yield item


class TestItem(pytest.Item):
    """One test file's test, run as `scriptc test` runs it."""

    def __init__(self, *, test: TestFile, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.test = test
        # Plugins that wrap every item's call read `funcargs`, which only pytest's functions
        # have (pytest-lsp 1.0 fails every other item without it): an item with no fixtures.
        self.funcargs: dict[str, object] = {}

    def runtest(self) -> None:
        from scriptc.diagnostics.render import render
        from scriptc.ops.test import run_one
        from scriptc.testing.report import failures, test_line
        from scriptc.testing.run import ERROR, FAILED

        result = run_one(self.test)
        if result.time_ms is not None:
            self.user_properties.append(("simulated_ms", result.time_ms))
        self.user_properties.append(("replay", result.replay))
        if result.status == FAILED:
            pytest.fail(render("text", [(self.test.source, failures(self.test, result))]),
                        pytrace=False)
        if result.status == ERROR:
            problems = [(source, list(diagnostics)) for source, diagnostics in result.problems]
            text = test_line(result)
            if problems:
                text += "\n" + render("text", problems)
            pytest.fail(text, pytrace=False)

    def reportinfo(self) -> tuple[Path, int, str]:
        return self.path, 0, self.test.description or self.name
