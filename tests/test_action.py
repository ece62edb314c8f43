"""The repository's GitHub Action (`action.yml`, docs/cli.md "The scriptc action"): a composite
action whose inputs are those documented, with their defaults; whose commands are the real
CLI's verbs, options and choices (parsed by click, so a renamed option fails here); whose lint
and test steps, run by bash as the runner runs them, lint with annotations and test, failing on
a failure; and whose install step installs the action's own files, or with `version` the
repository at that ref in the form scriptc's provenance writes."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from cli_words import parse, scriptc_commands
from click.testing import CliRunner

from scriptc.cli.main import cli

ROOT = Path(__file__).parent.parent
ACTION = yaml.safe_load((ROOT / "action.yml").read_text(encoding="utf-8"))
DOCS = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
SECTION = re.search(r"^### The scriptc action\n(.*?)^##", DOCS, re.MULTILINE | re.DOTALL).group(1)
BASH = shutil.which("bash")


def steps() -> dict[str, dict]:
    return {step["name"]: step for step in ACTION["runs"]["steps"]}


def expanded(step: dict, inputs: dict[str, str]) -> tuple[str, dict[str, str]]:
    """The step's `run` and `env` with `${{ inputs.X }}` replaced by the inputs' values
    (their defaults, over which `inputs` is written)."""
    values = {name: spec["default"] for name, spec in ACTION["inputs"].items()} | inputs

    def substitute(text: str) -> str:
        return re.sub(r"\$\{\{\s*inputs\.([\w-]+)\s*\}\}", lambda m: values[m.group(1)], text)

    env = {key: substitute(str(value)) for key, value in step.get("env", {}).items()}
    return substitute(step["run"]), env


def commands_run(step: dict, inputs: dict[str, str]) -> list[list[str]]:
    """The `scriptc` command lines the step runs with these inputs, its variables expanded as
    bash expands them (unquoted: split at spaces)."""
    run, env = expanded(step, inputs)
    return scriptc_commands(re.sub(r"\$(\w+)", lambda m: env[m.group(1)], run))


def test_it_is_a_composite_action_with_described_inputs() -> None:
    assert ACTION["runs"]["using"] == "composite"
    assert ACTION["name"] == "scriptc" and ACTION["description"]
    assert list(steps()) == ["Set up Python for scriptc", "Install scriptc", "scriptc lint",
                             "scriptc test", "scriptc verify"]
    for name, spec in ACTION["inputs"].items():
        assert spec["description"] and isinstance(spec["default"], str), name
        assert spec.get("required", False) is False, name
    for step in ACTION["runs"]["steps"]:
        if "run" in step:  # a composite action's shell steps must name their shell
            assert step["shell"] == "bash", step["name"]
    python = steps()["Set up Python for scriptc"]
    assert python["uses"].startswith("actions/setup-python@")
    assert python["with"] == {"python-version": "${{ inputs.python-version }}",
                              "update-environment": False}


def test_the_documentation_lists_every_input_with_its_default() -> None:
    rows = dict(re.findall(r"^\| `([\w-]+)` \| (`[^`]*`|\(none\)) \|", SECTION, re.MULTILINE))
    assert set(rows) == set(ACTION["inputs"])
    for name, spec in ACTION["inputs"].items():
        assert rows[name] == (f"`{spec['default']}`" if spec["default"] else "(none)"), name


def test_the_documented_workflows_use_the_action_with_its_inputs() -> None:
    whole, fragment = re.findall(r"```yaml\n(.*?)```", SECTION, re.DOTALL)
    workflow = yaml.safe_load(whole)
    (job,) = workflow["jobs"].values()
    checkout, action = job["steps"]
    assert checkout == {"uses": "actions/checkout@v4"}
    assert action["uses"].endswith("/scriptc@<commit>") and set(action) == {"uses"}
    (with_inputs,) = yaml.safe_load(fragment)
    assert set(with_inputs["with"]) <= set(ACTION["inputs"])
    for words in commands_run(steps()["scriptc test"], {k: str(v) for k, v in
                                                       with_inputs["with"].items()}):
        parse(words)


@pytest.mark.parametrize(("step", "inputs", "verb", "options"), [
    ("scriptc lint", {}, "lint", {"paths": (".",), "format_": "github"}),
    ("scriptc lint", {"paths": "activities more", "lint-args": "--ignore F001"}, "lint",
     {"paths": ("activities", "more"), "format_": "github", "ignore": ("F001",)}),
    ("scriptc test", {}, "test", {"paths": (".",), "format_": "github"}),
    ("scriptc test", {"test-args": "-k greeting -j 2"}, "test",
     {"paths": (".",), "format_": "github", "keyword": "greeting", "jobs": 2}),
    ("scriptc verify", {}, "verify", {"paths": (".",), "format_": "github"}),
    ("scriptc verify", {"paths": "activities", "verify-args": "--witness slowest"}, "verify",
     {"paths": ("activities",), "format_": "github", "witnesses": ("slowest",)}),
])
def test_the_steps_run_the_real_cli(step: str, inputs: dict[str, str], verb: str,
                                    options: dict) -> None:
    """Parsed by the CLI's own click command: an option the CLI renamed, or a choice it no
    longer has (`--format github`), fails here."""
    (words,) = commands_run(steps()[step], inputs)
    assert words[0] == verb
    parsed = parse(words).params
    assert {key: parsed[key] for key in options} == options


def test_the_test_step_runs_after_a_failed_lint_but_not_without_scriptc() -> None:
    assert steps()["scriptc lint"]["if"] == "inputs.lint == 'true'"
    assert steps()["scriptc test"]["if"] == \
        "always() && inputs.test == 'true' && steps.install.outcome == 'success'"
    assert steps()["scriptc verify"]["if"] == \
        "always() && inputs.verify == 'true' && steps.install.outcome == 'success'"
    assert steps()["Install scriptc"]["id"] == "install"


# -- the steps, run by bash -----------------------------------------------------------------------


def _bash(run: str, env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    assert BASH is not None
    # The runner's `shell: bash` is `bash --noprofile --norc -eo pipefail {0}`.
    return subprocess.run([BASH, "--noprofile", "--norc", "-eo", "pipefail", "-c", run],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=120,
                          check=False)


@pytest.fixture
def repository(tmp_path: Path, monkeypatch) -> Path:
    """An activity repository (`scriptc init`), its example's test passing."""
    monkeypatch.chdir(tmp_path)
    assert CliRunner().invoke(cli, ["init", "repo"]).exit_code == 0
    return tmp_path / "repo"


@pytest.mark.slow
@pytest.mark.skipif(BASH is None, reason="the action's steps are bash")
def test_the_lint_and_test_steps_pass_then_fail_with_annotations(repository: Path,
                                                                 tmp_path: Path) -> None:
    environ = {**os.environ, "SCRIPTC_CACHE_DIR": str(tmp_path / "cache"),
               "PATH": os.path.dirname(sys.executable) + os.pathsep + os.environ["PATH"]}
    assert shutil.which("scriptc", path=environ["PATH"]) is not None

    def step(name: str, **inputs: str) -> subprocess.CompletedProcess:
        run, env = expanded(steps()[name], inputs)
        return _bash(run, environ | env, repository)

    lint, test = step("scriptc lint"), step("scriptc test")
    assert (lint.returncode, lint.stdout) == (0, "")
    assert test.returncode == 0 and "PASS  activities/hello.test.toml" in test.stdout
    verify = step("scriptc verify")
    assert (verify.returncode, verify.stdout) == (0, "")  # every property proved: silent
    # A script with an error, and an example that no longer greets the child of its test.
    example = repository / "activities" / "hello.script"
    example.write_text(example.read_text(encoding="utf-8").replace("near(1.0)", "near(0.5)")
                       .replace("TRJMP(greet)", "TRJMP(gret)"), encoding="utf-8")
    lint = step("scriptc lint")
    assert lint.returncode == 1
    assert lint.stdout.startswith("::error file=activities/hello.script,line=")
    assert "L003" in lint.stdout
    example.write_text(example.read_text(encoding="utf-8").replace("TRJMP(gret)", "TRJMP(greet)"),
                       encoding="utf-8")
    test = step("scriptc test")
    assert test.returncode == 1 and "FAIL  activities/hello.test.toml" in test.stdout
    assert "\n::error file=activities/hello.test.toml,line=9,col=1," in test.stdout
    # Without its time-out the example may wait for ever: verify says where.
    example.write_text(example.read_text(encoding="utf-8").replace("TRJMP(done)", "TRJMP(idle)"),
                       encoding="utf-8")
    verify = step("scriptc verify")
    assert verify.returncode == 1
    assert verify.stdout.startswith("::error file=activities/hello.script,line=")
    assert "Y001" in verify.stdout
    # The inputs reach the commands: a selection that leaves the failing test out passes.
    assert step("scriptc test", **{"test-args": "-k nothing-matches"}).returncode == 0
    assert step("scriptc lint", paths="scenarios").returncode == 0


def _fake_python(tmp_path: Path) -> Path:
    """A `python` that makes a virtual environment whose python records what pip is asked
    to install, and whose `scriptc` says its version: the install step without a download."""
    fake = tmp_path / "fake-python"
    fake.write_text(
        "#!/bin/sh\n"
        'if [ "$1 $2" != "-m venv" ]; then exit 9; fi\n'
        'mkdir -p "$3/bin"\n'
        "printf '#!/bin/sh\\nprintf \"%%s\\\\n\" \"$@\" > \"$(dirname \"$0\")/pip-args\"\\n' "
        '> "$3/bin/python"\n'
        "printf '#!/bin/sh\\necho scriptc 0.1.0\\n' > \"$3/bin/scriptc\"\n"
        'chmod +x "$3/bin/python" "$3/bin/scriptc"\n', encoding="utf-8")
    fake.chmod(0o755)
    return fake


@pytest.mark.skipif(BASH is None or sys.platform == "win32", reason="the action's steps are bash")
@pytest.mark.parametrize("version", ["", "v1.2"])
def test_the_install_step_installs_the_actions_ref(version: str, tmp_path: Path) -> None:
    from scriptc.project.provenance import provenance

    runner_temp, output, path_file = tmp_path / "temp", tmp_path / "output", tmp_path / "path"
    runner_temp.mkdir()
    run, env = expanded(steps()["Install scriptc"], {"version": version})
    assert env["PYTHON"] == "${{ steps.python.outputs.python-path }}"
    assert env["ACTION_PATH"] == "${{ github.action_path }}"
    env |= {"PYTHON": str(_fake_python(tmp_path)), "ACTION_PATH": str(ROOT),
            "ACTION_REPOSITORY": "someone/scriptc", "SERVER_URL": "https://github.com",
            "RUNNER_TEMP": str(runner_temp), "GITHUB_OUTPUT": str(output),
            "GITHUB_PATH": str(path_file), "PATH": os.environ["PATH"]}
    done = _bash(run, env, tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.endswith("scriptc 0.1.0\n")
    venv = runner_temp / "scriptc-action" / "venv"
    args = (venv / "bin" / "pip-args").read_text(encoding="utf-8").splitlines()
    assert args[:3] == ["-m", "pip", "install"]
    if version:
        # The form scriptc's provenance gives a scriptc installed from a repository at a ref.
        record = {"url": "https://github.com/someone/scriptc",
                  "vcs_info": {"vcs": "git", "commit_id": version}}

        class Installed:
            version = "0.1.0"

            def read_text(self, name: str) -> str | None:
                return json.dumps(record) if name == "direct_url.json" else None

        assert args[-1] == provenance(Installed()).requirement()  # type: ignore[arg-type]
    else:
        assert args[-1] == str(ROOT)
    # Only scriptc goes on the later steps' PATH.
    (bin_dir,) = path_file.read_text(encoding="utf-8").splitlines()
    assert os.listdir(bin_dir) == ["scriptc"]
    assert os.path.realpath(Path(bin_dir) / "scriptc") == os.path.realpath(venv / "bin" / "scriptc")


@pytest.mark.skipif(BASH is None or sys.platform == "win32", reason="the action's steps are bash")
def test_a_version_without_the_actions_repository_is_refused(tmp_path: Path) -> None:
    run, env = expanded(steps()["Install scriptc"], {"version": "v1.2"})
    env |= {"PYTHON": str(_fake_python(tmp_path)), "ACTION_PATH": str(ROOT),
            "ACTION_REPOSITORY": "", "SERVER_URL": "https://github.com",
            "RUNNER_TEMP": str(tmp_path), "GITHUB_OUTPUT": str(tmp_path / "o"),
            "GITHUB_PATH": str(tmp_path / "p"), "PATH": os.environ["PATH"]}
    done = _bash(run, env, tmp_path)
    assert done.returncode == 1
    assert done.stdout.startswith("::error::scriptc action: cannot tell its own repository")
    assert not (tmp_path / "scriptc-action").exists()
