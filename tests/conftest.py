"""What every test module shares: tests/ on the import path (for `harness`), the one bless
command (`pytest --bless` writes the expected files of the case files, tests/harness/, and the
files generated from the code, `python -m scriptc.generate`), and the tiers (the markers of
pyproject.toml: `lsp`, `editor`, `packaging` and `browser` tests are `slow` too, so
`pytest -m "not slow"` leaves every tier out)."""

import signal
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

# The tiers that are slow by nature: a test marked with one of them is marked `slow` as well.
SLOW_TIERS = ("lsp", "editor", "packaging", "browser")
# Folders whose every test belongs to a tier.
TIER_FOLDERS = {"lsp": "lsp", "editors": "editor"}


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--bless", action="store_true", default=False,
                     help="write the expected files of the case files (tests/cases/) and the "
                          "files generated from the code from what the code does now, instead "
                          "of comparing; review `git diff`")


def pytest_configure(config: pytest.Config) -> None:
    # A suite started in the background by a non-interactive shell (`cmd &`, as some CI
    # runners and scripts do) inherits SIGINT ignored, and so would every `scriptc` it starts:
    # the tests of Ctrl-C (in process and in subprocesses) would then see nothing. Python's own
    # handler is what a terminal gives; a handler, unlike an ignored signal, is not inherited
    # across exec, so the subprocesses start with Ctrl-C as a user's shell gives it too.
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if config.getoption("--bless"):
        import harness

        from scriptc import generate

        harness.BLESS = True
        # The files generated from the code (docs/diagnostics.md, the schemas, the TextMate
        # grammar) are blessed too: adding a diagnostic is then one bless, not two commands.
        generate.main([])


@pytest.hookimpl(tryfirst=True)  # before `-m` deselects by these markers
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    tests = Path(__file__).parent
    for item in items:
        folder = item.path.relative_to(tests).parts[0] if item.path.is_relative_to(tests) else ""
        if folder in TIER_FOLDERS:
            item.add_marker(TIER_FOLDERS[folder])
        if any(item.get_closest_marker(tier) for tier in SLOW_TIERS):
            item.add_marker(pytest.mark.slow)
