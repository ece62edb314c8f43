"""Where the running scriptc came from (`scriptc.project.provenance`, PEP 610
`direct_url.json`), the install line `scriptc init` writes into its CI workflow for each case,
and the install commands of the messages that need an extra (`run --plot` without
matplotlib)."""

from __future__ import annotations

import json
import shlex
import sys
from importlib import metadata
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner
from packaging.requirements import Requirement

from scriptc.cli.init import WORKFLOW_PATH
from scriptc.cli.main import cli
from scriptc.project.provenance import PLACEHOLDER, extra_install_command, provenance

COMMIT = "9f2c1e0d8b7a6f5e4d3c2b1a0f9e8d7c6b5a4f3e"


class FakeDistribution(metadata.Distribution):
    """An installed scriptc as importlib.metadata sees it: its METADATA and, when pip wrote
    one, its direct_url.json."""

    def __init__(self, direct_url: dict | str | None, version: str = "1.2.3",
                 requires: tuple[str, ...] = ()) -> None:
        self.direct_url = direct_url if not isinstance(direct_url, dict) else json.dumps(direct_url)
        self.meta = "".join([f"Metadata-Version: 2.1\nName: scriptc\nVersion: {version}\n",
                             *(f"Requires-Dist: {r}\n" for r in requires)])

    def read_text(self, filename):
        if filename == "METADATA":
            return self.meta
        if filename == "direct_url.json":
            return self.direct_url
        return None

    def locate_file(self, path):
        return Path("/nowhere") / path


VCS = {"url": "https://example.org/team/scriptc.git",
       "vcs_info": {"vcs": "git", "commit_id": COMMIT, "requested_revision": "main"}}
ARCHIVE = {"url": "https://example.org/files/scriptc-1.2.3.tar.gz",
           "archive_info": {"hashes": {"sha256": "ab" * 32}}}
EDITABLE = {"url": "file:///home/me/scriptc", "dir_info": {"editable": True}}


@pytest.mark.parametrize(("record", "kind", "requirement"), [
    (VCS, "vcs", f"scriptc @ git+https://example.org/team/scriptc.git@{COMMIT}"),
    ({**VCS, "subdirectory": "python"}, "vcs",
     f"scriptc @ git+https://example.org/team/scriptc.git@{COMMIT}#subdirectory=python"),
    (None, "index", "scriptc==1.2.3"),
    (ARCHIVE, "url",
     f"scriptc @ https://example.org/files/scriptc-1.2.3.tar.gz#sha256={'ab' * 32}"),
    ({"url": ARCHIVE["url"], "archive_info": {"hash": "sha256=" + "cd" * 32}}, "url",
     f"scriptc @ https://example.org/files/scriptc-1.2.3.tar.gz#sha256={'cd' * 32}"),
    (EDITABLE, "local", None),
    ({"url": "file:///home/me/scriptc", "dir_info": {}}, "local", None),
    ({"url": "file:///tmp/scriptc-1.2.3-py3-none-any.whl", "archive_info": {}}, "local", None),
    ({"url": "file:///home/me/scriptc", "vcs_info": {"vcs": "git", "commit_id": COMMIT}},
     "local", None),
    ("{not json", "local", None),
    ({"no": "url"}, "local", None),
])
def test_provenance_of_each_kind_of_install(record, kind, requirement) -> None:
    origin = provenance(FakeDistribution(record))
    assert (origin.kind, origin.requirement()) == (kind, requirement)
    if requirement is None:
        assert origin.reason  # says why, in words
    else:
        parsed = Requirement(requirement)  # pip reads it
        assert parsed.name == "scriptc"
        with_extra = Requirement(origin.requirement(["plot"]))
        assert (with_extra.name, with_extra.extras, with_extra.url, str(with_extra.specifier)) \
            == ("scriptc", {"plot"}, parsed.url, str(parsed.specifier))


def test_an_editable_install_says_what_it_is_and_where() -> None:
    reason = provenance(FakeDistribution(EDITABLE)).reason
    assert "editable" in reason and "/home/me/scriptc" in reason


def test_scriptc_not_installed_at_all(monkeypatch) -> None:
    def missing(name):
        raise metadata.PackageNotFoundError(name)

    monkeypatch.setattr(metadata, "distribution", missing)
    origin = provenance()
    assert origin.requirement() is None and "not installed" in origin.reason
    assert extra_install_command("plot", ["matplotlib"]).endswith(" -m pip install matplotlib")


def test_the_running_scriptc_is_read_from_its_own_metadata(monkeypatch) -> None:
    seen = []

    def distribution(name):
        seen.append(name)
        return FakeDistribution(VCS)

    monkeypatch.setattr(metadata, "distribution", distribution)
    assert provenance().kind == "vcs" and seen == ["scriptc"]


# -- the workflow `scriptc init` writes -------------------------------------------------------


def init(tmp_path: Path, monkeypatch, record):
    monkeypatch.setattr(metadata, "distribution", lambda name: FakeDistribution(record))
    result = CliRunner().invoke(cli, ["init", str(tmp_path / "repo")], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    text = (tmp_path / "repo" / WORKFLOW_PATH).read_text(encoding="utf-8")
    steps = {step.get("name"): step for step in yaml.safe_load(text)["jobs"]["scriptc"]["steps"]}
    return result, steps


@pytest.mark.parametrize(("record", "requirement"), [
    (VCS, f"scriptc @ git+https://example.org/team/scriptc.git@{COMMIT}"),
    (None, "scriptc==1.2.3"),
])
def test_the_workflow_installs_the_running_scriptc(tmp_path, monkeypatch, record,
                                                    requirement) -> None:
    result, steps = init(tmp_path, monkeypatch, record)
    install = steps["Install scriptc"]
    assert shlex.split(install["run"]) == ["python", "-m", "pip", "install", requirement]
    assert result.stderr == ""
    # The SARIF steps run after errors were found, never without scriptc.
    for name in ("Lint (SARIF for code scanning)", "Upload to code scanning"):
        assert steps[name]["if"] == "always() && steps.install.outcome == 'success'"
    assert install["id"] == "install"


def test_a_local_checkout_gets_a_step_that_says_what_to_write(tmp_path, monkeypatch) -> None:
    result, steps = init(tmp_path, monkeypatch, EDITABLE)
    run = steps["Install scriptc"]["run"]
    assert "pip install" not in run and run.rstrip().endswith("exit 1")
    assert "::error::Edit the step 'Install scriptc'" in run
    text = (tmp_path / "repo" / WORKFLOW_PATH).read_text(encoding="utf-8")
    assert f'#   python -m pip install "{PLACEHOLDER}"' in text
    # init still succeeds, and says so plainly.
    assert "created .github/workflows/scriptc.yml" in result.stdout
    assert result.stderr.startswith(f"warning: {WORKFLOW_PATH} cannot install scriptc: ")
    assert "editable install" in result.stderr and PLACEHOLDER in result.stderr


def test_no_warning_when_the_workflow_was_not_written(tmp_path, monkeypatch) -> None:
    (tmp_path / "repo" / ".github" / "workflows").mkdir(parents=True)
    (tmp_path / "repo" / WORKFLOW_PATH).write_text("mine\n", encoding="utf-8")
    monkeypatch.setattr(metadata, "distribution", lambda name: FakeDistribution(EDITABLE))
    result = CliRunner().invoke(cli, ["init", str(tmp_path / "repo")], catch_exceptions=False)
    assert result.exit_code == 0 and result.stderr == ""
    assert (tmp_path / "repo" / WORKFLOW_PATH).read_text(encoding="utf-8") == "mine\n"


# -- the install commands of messages -----------------------------------------------------------


def test_the_plot_extras_command_is_the_extras_own_requirements() -> None:
    dist = FakeDistribution(None, requires=("click>=8", 'matplotlib>=3.7; extra == "plot"',
                                            "pytest>=8; extra == 'test'"))
    command = extra_install_command("plot", ["matplotlib"], dist)
    assert shlex.split(command) == [sys.executable, "-m", "pip", "install", "matplotlib>=3.7"]


def test_run_plot_without_matplotlib_says_a_command_that_works(tmp_path, monkeypatch) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "matplotlib" else real(name, *a))
    script = tmp_path / "a.script"
    script.write_text("[a]\n[goal:g]\n  [action]\n    [b##blk_terminus]\n", encoding="utf-8")
    result = CliRunner().invoke(cli, ["run", str(script), "--plot", str(tmp_path / "p.png")])
    assert result.exit_code == 2
    assert "scriptc[plot]" not in result.stderr
    command = result.stderr.splitlines()[-1].strip()
    words = shlex.split(command)
    assert words[:4] == [sys.executable, "-m", "pip", "install"]
    assert Requirement(words[4]).name == "matplotlib"
