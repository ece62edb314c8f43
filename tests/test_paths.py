"""How files are named in every output format (`scriptc.paths`): the same name however the
command line named the file (`./x/y.script`, an absolute path, a folder holding it), never a
leading `./`; relative to the working folder in text, grouped and JSON, relative to the
repository's root in GitHub's format and SARIF (what GitHub attaches to a pull request)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.cli.main import cli
from scriptc.paths import repository_path, shown_path

BROKEN = ("[bad_act]\n[goal:g]\n[action]\n"
          "[b#a#blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n[b##blk_terminus]\n")


def run(*args: str):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


@pytest.fixture
def repo(tmp_path: Path, monkeypatch) -> Path:
    """A git repository (a `.git` folder is all it takes) with one broken script in `x/`."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCRIPTC_CACHE_DIR", raising=False)
    (tmp_path / ".git").mkdir()
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / "y.script").write_text(BROKEN, encoding="utf-8")
    return tmp_path


def names(format_: str, output: str) -> set[str]:
    """The file names an output of `format_` gives."""
    if format_ == "text":
        return {line.split(" --> ")[1].rsplit(":", 2)[0] for line in output.splitlines()
                if " --> " in line}
    if format_ == "grouped":
        return {line[:-1] for line in output.splitlines() if line.endswith(":")}
    if format_ == "json":
        return {record["file"] for record in json.loads(output)}
    if format_ == "sarif":
        run_ = json.loads(output)["runs"][0]
        return {location["physicalLocation"]["artifactLocation"]["uri"]
                for result in run_["results"] for location in result["locations"]}
    assert format_ == "github"
    return {line.split("file=")[1].split(",")[0] for line in output.splitlines()}


FORMATS = ["text", "grouped", "json", "sarif", "github"]


@pytest.mark.parametrize("format_", FORMATS)
@pytest.mark.parametrize("how", ["dot-slash", "absolute", "folder", "dot", "dotdot"])
def test_every_format_names_the_file_the_same_way(repo: Path, format_: str, how: str) -> None:
    path = {"dot-slash": "./x/y.script", "absolute": str(repo / "x" / "y.script"),
            "folder": "x", "dot": ".", "dotdot": "x/../x/y.script"}[how]
    result = run("lint", path, "--format", format_)
    assert result.exit_code == 1
    assert names(format_, result.stdout) == {"x/y.script"}


def test_run_from_a_subfolder(repo: Path) -> None:
    """GitHub resolves against the repository's root; people read paths from where they are."""
    os.chdir(repo / "x")
    for path in ("y.script", ".", "./y.script", str(repo / "x" / "y.script")):
        assert names("github", run("lint", path, "--format", "github").stdout) == {"x/y.script"}
        assert names("sarif", run("lint", path, "--format", "sarif").stdout) == {"x/y.script"}
        assert names("json", run("lint", path, "--format", "json").stdout) == {"y.script"}
        assert names("text", run("lint", path).stdout) == {"y.script"}


def test_sarif_names_its_base(repo: Path) -> None:
    log = json.loads(run("lint", "x", "--format", "sarif").stdout)["runs"][0]
    location = log["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]
    assert location == {"uri": "x/y.script", "uriBaseId": "%SRCROOT%"}
    assert log["originalUriBaseIds"] == {"%SRCROOT%": {"uri": repo.as_uri() + "/"}}


def test_outside_a_repository_the_working_folder_is_the_root(tmp_path: Path,
                                                              monkeypatch) -> None:
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / "y.script").write_text(BROKEN, encoding="utf-8")
    monkeypatch.chdir(tmp_path / "x")
    assert names("github", run("lint", ".", "--format", "github").stdout) == {"y.script"}


def test_a_file_outside_the_root_keeps_its_absolute_name(tmp_path: Path, monkeypatch) -> None:
    (tmp_path / "here").mkdir()
    (tmp_path / "here" / ".git").mkdir()
    elsewhere = tmp_path / "elsewhere.script"
    elsewhere.write_text(BROKEN, encoding="utf-8")
    monkeypatch.chdir(tmp_path / "here")
    assert names("github", run("lint", str(elsewhere), "--format", "github").stdout) == {
        str(elsewhere)}
    assert names("sarif", run("lint", str(elsewhere), "--format", "sarif").stdout) == {
        elsewhere.as_uri()}
    # A relative name outside the working folder is kept as it was written (normalised).
    assert names("json", run("lint", "../here/../elsewhere.script", "--format", "json").stdout
                 ) == {os.path.join("..", "elsewhere.script")}


def test_messages_name_files_the_same_way(repo: Path) -> None:
    result = run("lint", "./x/y.script", "./x/missing.script", "x/")
    assert "error: `x/missing.script` does not exist\n" in result.stderr
    compiled = run("compile", "./x/y.script")
    assert " --> x/y.script:4:36\n" in compiled.stderr


def test_names_that_are_not_paths_are_kept() -> None:
    assert shown_path("-") == "-" and shown_path("<stdin>") == "<stdin>"
    assert repository_path("<stdin>") == "<stdin>"


def test_shown_path_laws(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    inside = os.path.join("a", "b.script")
    for spelling in ("a/b.script", "./a/b.script", "a//b.script", "a/./b.script",
                     "a/c/../b.script", str(tmp_path / "a" / "b.script")):
        assert shown_path(spelling) == inside
    assert shown_path(str(tmp_path.parent / "z.script")) == str(tmp_path.parent / "z.script")
