"""`scriptc init [DIR]`: the scaffold lints clean, its files are valid (configuration, scenario,
workflow, pre-commit), existing files are never overwritten; and the repository's own
`.pre-commit-hooks.yaml` names commands that exist."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.cli.init import FILES
from scriptc.cli.main import VERBS, cli

ROOT = Path(__file__).parent.parent


def run(*args: str):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


@pytest.fixture
def scaffold(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCRIPTC_CACHE_DIR", raising=False)
    result = run("init", "repo")
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines() == [f"created {name}" for name, _ in FILES] + [
        "next: cd repo && scriptc lint . && scriptc test && scriptc verify ."]
    return tmp_path / "repo"


def test_the_scaffold_lints_clean(scaffold: Path) -> None:
    result = run("lint", str(scaffold), "--no-cache")
    assert (result.exit_code, result.stdout) == (0, "")
    assert result.stderr == "checked 1 file: no problems\n"


def test_the_scaffold_is_formatted(scaffold: Path) -> None:
    result = run("fmt", "--check", str(scaffold))
    assert result.exit_code == 0, result.output


def test_the_configuration_is_valid_and_applies(scaffold: Path) -> None:
    from scriptc.project.config import load_config

    loaded = load_config(str(scaffold / "scriptc.toml"))
    assert loaded.diagnostics == []
    assert loaded.settings.robot.max_led_flash_rate == 3.0
    assert loaded.settings.audio_root_path == str(scaffold / "audio")
    assert (scaffold / "audio").is_dir()


def test_the_example_compiles_and_the_scenario_fits_its_schema(scaffold: Path) -> None:
    result = run("compile", str(scaffold / "activities" / "hello.script"), "-o", "-")
    assert result.exit_code == 0 and json.loads(result.stdout)["activityname"] == "hello"
    scenario = json.loads((scaffold / "scenarios" / "hello.json").read_text(encoding="utf-8"))
    (update,) = scenario["updates"]
    assert update == {"at": 500, "objectid": "Human/kid1", "attributename": "poses",
                      "policy": "R", "jsonmsg": {"positionrho": 0.8, "positiontheta": 0.0,
                                                 "positionchangetime": 500}}
    schema = ROOT / "schemas" / "scenario.schema.json"
    if schema.exists():  # the simulator's scenario format
        import jsonschema

        jsonschema.validate(scenario, json.loads(schema.read_text(encoding="utf-8")))


def test_the_workflow_uploads_sarif_and_annotates(scaffold: Path) -> None:
    text = (scaffold / ".github" / "workflows" / "scriptc.yml").read_text(encoding="utf-8")
    assert "scriptc lint . --format github" in text
    assert "scriptc lint . --format sarif" in text and "upload-sarif" in text
    assert "security-events: write" in text and "\t" not in text
    # What it installs is the running scriptc's (tests/test_provenance.py, each case).
    assert "Install scriptc" in text


def test_the_workflow_lints_then_tests_with_the_real_cli(scaffold: Path) -> None:
    """Each step of the workflow's job runs what the CLI has (verbs, options, choices: a
    renamed option fails here); the tests run after the lints, even when a lint failed, as
    long as scriptc was installed."""
    import yaml
    from cli_words import parse, scriptc_commands

    workflow = yaml.safe_load((scaffold / ".github" / "workflows" / "scriptc.yml")
                              .read_text(encoding="utf-8"))
    (job,) = workflow["jobs"].values()
    commands = [(step.get("name"), words) for step in job["steps"]
                for words in scriptc_commands(step.get("run", ""))]
    assert [(name, words[0]) for name, words in commands] == [
        ("Lint (annotations)", "lint"), ("Lint (SARIF for code scanning)", "lint"),
        ("Test", "test"), ("Verify", "verify")]
    for _name, words in commands:
        parse(words)
    (test_step,) = [step for step in job["steps"] if step.get("name") == "Test"]
    assert test_step["if"] == "always() && steps.install.outcome == 'success'"
    assert test_step["run"] == "scriptc test . --format github"
    (verify_step,) = [step for step in job["steps"] if step.get("name") == "Verify"]
    assert verify_step["if"] == test_step["if"]
    assert verify_step["run"] == "scriptc verify . --format github"
    (keep,) = [step for step in job["steps"] if step.get("name") == "Keep the counterexamples"]
    assert keep["uses"].startswith("actions/upload-artifact@")
    assert keep["with"]["path"] == "scriptc-verify/"  # where verify writes its worlds


def test_the_scaffolds_test_passes_and_pins_the_example(scaffold: Path, monkeypatch) -> None:
    """`scriptc test` in the new repository finds the example's test and passes; the test
    fails when the example no longer greets the child of the scenario."""
    monkeypatch.chdir(scaffold)
    result = run("test")
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("PASS  activities/hello.test.toml (2.500 s simulated, ")
    assert "1 passed; " in result.stdout
    example = scaffold / "activities" / "hello.script"
    text = example.read_text(encoding="utf-8")
    example.write_text(text.replace("near(1.0)", "near(0.5)"), encoding="utf-8")
    result = run("test")
    assert result.exit_code == 1
    assert "4 of 4 expectations failed" in result.stdout


def test_the_scaffolds_activity_is_verified(scaffold: Path, monkeypatch) -> None:
    """`scriptc verify .` in the new repository proves every property of the example: it
    ends whatever the child does (the time-out), greets a child who comes, and lasts from
    2.5 s (a child at the first look) to 32.5 s (a child at the last look, at 30.5 s, is
    still greeted)."""
    monkeypatch.chdir(scaffold)
    result = run("verify", ".", "--json")
    assert result.exit_code == 0, result.output
    (found,) = [json.loads(line) for line in result.stdout.splitlines()]
    assert {p["property"]: p["status"] for p in found["properties"]} == dict.fromkeys(
        ("terminates", "goals", "blocks", "duration", "no-stall", "no-progress", "safety"),
        "proved")
    assert found["duration_ms"] == {"min": 2500, "max": 32500}


def test_pre_commit_configuration_runs_real_verbs(scaffold: Path) -> None:
    text = (scaffold / ".pre-commit-config.yaml").read_text(encoding="utf-8")
    entries = re.findall(r"entry: scriptc (\w+)", text)
    assert entries == ["fmt", "lint"] and "--force-exclude" in text
    assert "lint" in VERBS


def test_existing_files_are_never_overwritten(scaffold: Path) -> None:
    (scaffold / "scriptc.toml").write_text("# mine\n", encoding="utf-8")
    (scaffold / "activities" / "hello.script").unlink()
    result = run("init", str(scaffold))
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    assert "created activities/hello.script" in lines
    assert "skipped scriptc.toml (it exists)" in lines
    assert len([line for line in lines if line.startswith("skipped")]) == len(FILES) - 1
    assert (scaffold / "scriptc.toml").read_text(encoding="utf-8") == "# mine\n"


def test_init_in_the_working_folder_and_errors(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = run("init")
    assert result.exit_code == 0
    assert result.stdout.endswith("next: scriptc lint . && scriptc test && scriptc verify .\n")
    (tmp_path / "file").write_text("x")
    refused = run("init", "file")
    assert refused.exit_code == 2 and "is not a folder" in refused.stderr


def test_the_repositorys_pre_commit_hooks() -> None:
    text = (ROOT / ".pre-commit-hooks.yaml").read_text(encoding="utf-8")
    ids = re.findall(r"^- id: (\S+)$", text, re.MULTILINE)
    assert ids == ["scriptc-lint", "scriptc-lint-fix", "scriptc-fmt", "scriptc-fmt-check"]
    for entry in re.findall(r"^  entry: (.+)$", text, re.MULTILINE):
        program, verb, *options = entry.split()
        assert program == "scriptc" and verb in ("lint", "fmt")
        if verb == "lint":
            for option in options:
                assert run("lint", "--help").stdout.count(option) >= 1, option
    assert text.count("language: python") == len(ids)


def test_the_cli_documentation_covers_every_option() -> None:
    """docs/cli.md names each of these verbs' options and the exit statuses."""
    docs = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    from scriptc.cli.main import LazyGroup

    group = cli
    assert isinstance(group, LazyGroup)
    for verb in ("compile", "lint", "check", "decompile", "explain", "init", "show-settings",
                 "clean", "completion"):
        assert f"## `scriptc {verb}" in docs, verb
        command = group.get_command(None, verb)
        for param in command.params:
            for opt in param.opts:
                if opt.startswith("-"):
                    assert f"`{opt}" in docs, f"docs/cli.md lacks {verb} {opt}"
    for status in ("0", "1", "2", "130"):
        assert f"| {status} |" in docs


# -- pre-commit: the hooks as another repository uses them, and as `repo: local` hooks ----------


def _manifest() -> list[dict]:
    from pre_commit.clientlib import load_manifest

    return load_manifest(str(ROOT / ".pre-commit-hooks.yaml"))  # pre-commit's own validation


def _fenced_yaml(after: str) -> str:
    docs = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    return re.search(re.escape(after) + r".*?```yaml\n(.*?)```", docs, re.DOTALL).group(1)


def test_the_manifest_is_valid_for_pre_commit() -> None:
    hooks = _manifest()
    assert [h["id"] for h in hooks] == ["scriptc-lint", "scriptc-lint-fix", "scriptc-fmt",
                                        "scriptc-fmt-check"]
    for hook in hooks:
        assert re.search(hook["files"], "activities/a.script")
        assert not re.search(hook["files"], "activities/a.script.json")


def test_the_local_hooks_are_the_manifests_hooks(scaffold: Path) -> None:
    """`scriptc init`'s `repo: local` hooks and the documented ones are the published hooks,
    entry for entry, run by the installed scriptc."""
    import yaml
    from pre_commit.clientlib import load_config

    published = {h["id"]: h for h in _manifest()}
    written = (scaffold / ".pre-commit-config.yaml").read_text(encoding="utf-8")
    assert _fenced_yaml("`.pre-commit-config.yaml`:") == written
    # pre-commit accepts it (recent versions read `system` as their new name, `unsupported`)
    for config in (load_config(str(scaffold / ".pre-commit-config.yaml")),
                   yaml.safe_load(written)):
        (repo,) = config["repos"]
        assert repo["repo"] == "local"
        for hook in repo["hooks"]:
            assert hook["language"] in ("system", "unsupported")
            for key in ("entry", "files", "require_serial"):
                assert hook.get(key, False) == published[hook["id"]].get(key, False), key


@pytest.mark.packaging
def test_the_local_hooks_run_in_pre_commit(scaffold: Path, tmp_path: Path) -> None:
    """pre-commit itself runs the scaffold's hooks (no download: `language: system`): clean
    scripts pass; a script out of layout is rewritten and fails the run."""
    import os
    import shutil
    import subprocess
    import sys

    git = shutil.which("git")
    assert git is not None
    env = {**os.environ, "PRE_COMMIT_HOME": str(tmp_path / "pre-commit-home"),
           "PATH": os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", ""),
           "SCRIPTC_CACHE_DIR": str(tmp_path / "cache")}
    assert shutil.which("scriptc", path=env["PATH"]) is not None

    def pre_commit() -> subprocess.CompletedProcess:
        subprocess.run([git, "add", "-A"], cwd=scaffold, check=True, env=env)
        return subprocess.run([sys.executable, "-m", "pre_commit", "run", "--all-files"],
                              cwd=scaffold, env=env, capture_output=True, text=True, timeout=120,
                              check=False)

    subprocess.run([git, "init", "-q"], cwd=scaffold, check=True, env=env)
    done = pre_commit()
    assert done.returncode == 0, done.stdout + done.stderr
    assert re.findall(r"^(scriptc \w+)\.+Passed$", done.stdout, re.MULTILINE) == [
        "scriptc fmt", "scriptc lint"]
    messy = scaffold / "activities" / "messy.script"
    messy.write_text("[messy]\n[goal:g]\n[action]\n[b##blk_terminus]\n", encoding="utf-8")
    done = pre_commit()
    assert done.returncode == 1 and "files were modified by this hook" in done.stdout
    assert (messy.read_text(encoding="utf-8")
            == "[messy]\n[goal:g]\n  [action]\n    [b##blk_terminus]\n")


def test_the_documented_workflow_is_the_one_init_writes() -> None:
    from scriptc.cli.init import workflow
    from scriptc.project.provenance import PLACEHOLDER, Provenance

    assert _fenced_yaml("`scriptc init` writes this workflow") == \
        workflow(Provenance("vcs", PLACEHOLDER))
