"""The command line as ruff users type it: a mistyped verb gets the closest one, the group's
options after the verb, shell completion (click's protocol, in real processes),
`scriptc show-settings`, and `scriptc lint --watch` (a real process, changed files, Ctrl-C)."""

from __future__ import annotations

import json
import os
import queue
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from click.testing import CliRunner
from test_cli import process as cli_process

from scriptc import __version__
from scriptc.cli.main import VERBS, cli

CLEAN = "[clean]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n"
BROKEN = ("[broken]\n[goal:g]\n[action]\n[b#a#blk_jump: CND(! {TRUE}) TRJMP(nowhere) "
          "FLSJMP()]\n[b##blk_terminus]\n")


def run(*args: str, env: dict | None = None):
    return CliRunner().invoke(cli, list(args), env=env, catch_exceptions=False)


def process(*args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    """`python -m scriptc` in a process (`test_cli.process`), its output as text."""
    done = cli_process(*args, env=env)
    return subprocess.CompletedProcess(done.args, done.returncode, done.stdout.decode(),
                                       done.stderr.decode())


@pytest.fixture
def files(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCRIPTC_CACHE_DIR", raising=False)
    (tmp_path / "broken.script").write_text(BROKEN, encoding="utf-8")
    return tmp_path


# ---------------------------------------------------------------------------------------------
# the group


@pytest.mark.parametrize("typed, meant", [("lnit", "lint"), ("complie", "compile"),
                                          ("show-setting", "show-settings"), ("clena", "clean")])
def test_a_mistyped_verb_gets_the_closest(typed: str, meant: str) -> None:
    result = run(typed, "x")
    assert result.exit_code == 2
    assert f"no such command `{typed}`; did you mean `{meant}`?" in result.stderr


def test_an_unknown_verb_far_from_any_gets_no_guess() -> None:
    result = run("frobnicate")
    assert result.exit_code == 2
    assert "no such command `frobnicate` (`scriptc --help` lists them)" in result.stderr


def test_group_options_after_the_verb(files: Path) -> None:
    assert "\x1b[" in run("lint", "broken.script", "--color", "always").stdout
    assert "\x1b[" in run("lint", "--colour", "always", "broken.script").stdout
    # The later one wins, before or after the verb.
    assert "\x1b[" not in run("--color", "always", "lint", "broken.script",
                              "--color", "never").stdout
    assert "\x1b[" in run("--color", "never", "explain", "L003", "--color", "always").stdout
    assert run("lint", "broken.script", "--color", "sometimes").exit_code == 2
    for verb in ("lint", "compile", "run", "show-settings"):
        result = run(verb, "--version")
        assert (result.exit_code, result.stdout) == (0, f"scriptc {__version__}\n")


def test_every_verb_is_listed_and_has_help() -> None:
    listed = run("--help").stdout
    for verb in VERBS:
        assert f"  {verb} " in listed
        assert run(verb, "--help").exit_code == 0
        # The group's options are added to a verb once, however often it is looked up.
        command = cli.get_command(None, verb)
        assert cli.get_command(None, verb) is command
        opts = [opt for param in command.params for opt in param.opts]
        assert opts.count("--color") == opts.count("--version") == 1


# ---------------------------------------------------------------------------------------------
# shell completion: click's protocol, in real processes


@pytest.mark.slow
@pytest.mark.parametrize("shell", ["bash", "zsh", "fish"])
def test_the_completion_script_of_each_shell(shell: str) -> None:
    verb = process("completion", shell)
    variable = process(env={"_SCRIPTC_COMPLETE": f"{shell}_source"})
    assert verb.returncode == variable.returncode == 0
    assert verb.stdout == variable.stdout
    assert f"_SCRIPTC_COMPLETE={shell}_complete" in verb.stdout
    assert "scriptc" in verb.stdout
    assert process("completion", "tcsh").returncode == 2


def complete(shell: str, words: str, cword: int | str) -> str:
    result = process(env={"_SCRIPTC_COMPLETE": f"{shell}_complete", "COMP_WORDS": words,
                          "COMP_CWORD": str(cword)})
    assert result.returncode == 0, result.stderr
    return result.stdout


@pytest.mark.slow
def test_completing_a_verb() -> None:
    assert complete("bash", "scriptc li", 1) == "plain,lint\n"
    assert complete("bash", "scriptc c", 1).split() == [
        "plain,compile", "plain,check", "plain,clean", "plain,completion"]
    assert complete("zsh", "scriptc sh", 1) == (
        "plain\nshow-settings\n" + VERBS["show-settings"][1] + "\n")
    assert complete("fish", "scriptc li", "li") == f"plain,lint\t{VERBS['lint'][1]}\n"


@pytest.mark.slow
def test_completing_options_and_their_choices(tmp_path: Path) -> None:
    assert complete("bash", "scriptc lint --for", 2).split() == [
        "plain,--format", "plain,--force-exclude"]
    assert complete("bash", "scriptc lint --format ", 3).split() == [
        "plain,text", "plain,json", "plain,sarif", "plain,github", "plain,grouped"]
    assert "plain,--unsafe-fixes" in complete("bash", "scriptc lint --uns", 2).split()
    assert complete("bash", "scriptc completion ", 2).split() == [
        "plain,bash", "plain,zsh", "plain,fish"]
    # Paths are left to the shell's own file completion.
    assert complete("bash", "scriptc lint ", 2) == "file,\n"


def test_completion_in_process() -> None:
    """The same protocol as above, through click's completer in this process."""
    from click.shell_completion import BashComplete

    completer = BashComplete(cli, {}, "scriptc", "_SCRIPTC_COMPLETE")
    assert [(c.value, c.help) for c in completer.get_completions([], "li")] == [
        ("lint", VERBS["lint"][1])]
    assert [c.value for c in completer.get_completions([], "--co")] == ["--color", "--colour"]
    assert [c.value for c in completer.get_completions(["lint"], "--exi")] == ["--exit-zero"]
    assert run("completion", "bash").stdout == completer.source()
    assert cli.list_commands(None) == list(VERBS) and cli.get_command(None, "nope") is None


def test_completing_verbs_imports_none_of_them() -> None:
    probe = ("import os, sys\nfrom scriptc.cli.main import main\nsys.argv = ['scriptc']\n"
             "try:\n    main()\nexcept SystemExit:\n    pass\n"
             "print(sorted(m for m in sys.modules if m.startswith('scriptc.cli.')))")
    env = {k: v for k, v in os.environ.items() if not k.startswith("_SCRIPTC")}
    env.update({"_SCRIPTC_COMPLETE": "bash_complete", "COMP_WORDS": "scriptc ",
                "COMP_CWORD": "1"})
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          env=env, timeout=60, check=False)
    assert "plain,lint" in done.stdout
    assert done.stdout.strip().splitlines()[-1] == "['scriptc.cli.main']"


# ---------------------------------------------------------------------------------------------
# show-settings


CONFIG = """audio-root = "audio"

[lint]
ignore = ["F003"]
per-file-ignores = { "legacy/**" = ["unreachable-block"] }
severity = { M004 = "error" }

[robot]
max-linear-speed = -1
min-human-distance = 0.6

[[functions]]
name = "waving"
kind = "B"
arity = 0
implementation = "activity_functions:waving"

[[rules]]
name = "greet"
implementation = "activity_rules:Greet"
"""


@pytest.fixture
def configured(files: Path) -> Path:
    (files / "scriptc.toml").write_text(CONFIG, encoding="utf-8")
    (files / "legacy").mkdir()
    (files / "legacy" / "old.script").write_text(CLEAN, encoding="utf-8")
    return files


def test_show_settings_says_where_each_value_comes_from(configured: Path) -> None:
    result = run("show-settings", "legacy/old.script")
    assert result.exit_code == 1  # max-linear-speed = -1 is an error of the configuration
    assert "error[C002]" in result.stderr
    out = result.stdout
    assert "# configuration: scriptc.toml\n" in out
    assert "# cache: .scriptc_cache\n" in out
    lines = {line.split("  #")[0].strip(): line.split("  # ")[1] for line in out.splitlines()
             if "  # " in line and not line.startswith("#")}
    assert lines['audio-root = "audio"'] == "scriptc.toml:1:1"
    assert lines["respect-gitignore = true"] == "default"
    assert lines['select = ["ALL"]'] == "default"
    assert lines['ignore = ["F003"]'] == "scriptc.toml:4:1"
    assert lines['per-file-ignores = { "legacy/**" = ["unreachable-block"] }'] == \
        "scriptc.toml:5:1"
    assert lines["min-human-distance = 0.6"] == "scriptc.toml:10:1"
    assert lines["max-linear-speed = 0.5"].startswith("scriptc.toml:9:1, rejected")
    assert lines["max-volume = 0.8"] == "default"
    assert "# not reported: F003\n" in out
    assert "# severity changed: M004 -> error\n" in out
    assert "# per-file-ignores for this file: unreachable-block\n" in out
    assert ('\n[[functions]]  # scriptc.toml:12:3\nname = "waving"\nkind = "B"\narity = 0\n'
            'implementation = "activity_functions:waving"\n') in out
    assert ('\n[[rules]]  # scriptc.toml:18:3\nname = "greet"\n'
            'implementation = "activity_rules:Greet"\n') in out


def test_show_settings_as_json(configured: Path) -> None:
    record = json.loads(run("show-settings", "legacy/old.script", "--json").stdout)
    assert record["configuration"] == "scriptc.toml"
    settings = record["settings"]
    assert settings["lint.ignore"] == {"value": ["F003"], "rejected": False,
                                       "origin": {"file": "scriptc.toml", "line": 4,
                                                  "column": 1}}
    assert settings["lint.select"] == {"value": ["ALL"], "origin": None, "rejected": False}
    assert settings["robot.max-linear-speed"]["rejected"] is True
    assert settings["robot.max-linear-speed"]["value"] == 0.5
    assert record["codes"]["F003"] == {"reported": False, "severity": "info"}
    assert record["codes"]["M004"] == {"reported": True, "severity": "error"}
    assert record["per_file_ignores_here"] == ["unreachable-block"]


def test_show_settings_without_a_configuration_and_isolated(configured: Path,
                                                            tmp_path_factory) -> None:
    isolated = run("show-settings", "legacy/old.script", "--isolated", "--json")
    assert isolated.exit_code == 0
    record = json.loads(isolated.stdout)
    assert record["configuration"] is None
    assert all(s["origin"] is None for s in record["settings"].values())
    assert "# configuration: none" in run("show-settings", str(
        tmp_path_factory.mktemp("bare")), "--isolated").stdout
    missing = run("show-settings", "nowhere.script")
    assert (missing.exit_code, missing.stderr) == (2, "error: `nowhere.script` does not exist\n")


def test_show_settings_with_a_configuration_named(configured: Path) -> None:
    (configured / "strict.toml").write_text('[lint]\nselect = ["F"]\n', encoding="utf-8")
    result = run("show-settings", "legacy/old.script", "--config", "strict.toml", "--json")
    assert result.exit_code == 0
    record = json.loads(result.stdout)
    assert (record["configuration"], record["cache_dir"]) == ("strict.toml", ".scriptc_cache")
    assert record["settings"]["lint.select"]["origin"] == {"file": "strict.toml", "line": 2,
                                                           "column": 1}
    assert record["settings"]["lint.ignore"]["origin"] is None
    assert run("show-settings", ".", "--config", "strict.toml", "--isolated").exit_code == 2


def test_show_settings_of_a_pyproject_table(files: Path) -> None:
    (files / "pyproject.toml").write_text('[project]\nname = "x"\n\n[tool.scriptc.lint]\n'
                                          'select = ["F"]\n', encoding="utf-8")
    record = json.loads(run("show-settings", ".", "--json").stdout)
    assert record["configuration"] == "pyproject.toml"
    assert record["settings"]["lint.select"]["origin"] == {"file": "pyproject.toml",
                                                           "line": 5, "column": 1}


# ---------------------------------------------------------------------------------------------
# lint --watch: a real process


class Watcher:
    """`scriptc lint --watch` in a process, its output read by threads as it comes."""

    def __init__(self, folder: Path, *args: str) -> None:
        env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "NO_COLOR")}
        self.proc = subprocess.Popen([sys.executable, "-m", "scriptc", "lint", "--watch", *args],
                                     cwd=folder, env=env, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
        self.out: queue.Queue[str] = queue.Queue()
        self.err: queue.Queue[str] = queue.Queue()
        for stream, sink in ((self.proc.stdout, self.out), (self.proc.stderr, self.err)):
            threading.Thread(target=lambda s=stream, q=sink: [q.put(line) for line in s],
                             daemon=True).start()

    def until(self, sink: queue.Queue, text: str, seconds: float = 30) -> list[str]:
        """The lines read until one holds `text` (fails after `seconds`)."""
        seen = []
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            try:
                line = sink.get(timeout=0.2)
            except queue.Empty:
                continue
            seen.append(line)
            if text in line:
                return seen
        raise AssertionError(f"no {text!r} within {seconds} s; read {seen!r}")

    def stop(self) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            return self.proc.wait(timeout=30)
        finally:
            if self.proc.poll() is None:
                self.proc.kill()


@pytest.mark.slow
def test_watch_lints_again_on_change_and_stops_at_ctrl_c(tmp_path: Path) -> None:
    (tmp_path / "a.script").write_text(CLEAN, encoding="utf-8")
    watcher = Watcher(tmp_path, ".", "--format", "grouped")
    try:
        watcher.until(watcher.err, "watching for changes")
        assert watcher.out.empty()  # clean: nothing on stdout
        (tmp_path / "a.script").write_text(BROKEN.replace("[broken]", "[a]"), encoding="utf-8")
        lines = watcher.until(watcher.out, "L003")
        assert lines[0] == "a.script:\n"
        watcher.until(watcher.err, "watching for changes")
        # A new script is seen too, and a file lint does not read is not.
        (tmp_path / "notes.txt").write_text("not a script", encoding="utf-8")
        (tmp_path / "b.script").write_text(BROKEN.replace("[broken]", "[b]"), encoding="utf-8")
        watcher.until(watcher.out, "b.script:")
        watcher.until(watcher.err, "watching for changes")
        # A change of the configuration re-lints too.
        (tmp_path / "scriptc.toml").write_text('exclude = ["b.script"]\n', encoding="utf-8")
        watcher.until(watcher.err, "checked 1 file: 1 error")
    finally:
        status = watcher.stop()
    assert status == 130
    assert "Traceback" not in "".join(list(watcher.err.queue))


@pytest.mark.slow
def test_watch_follows_a_named_file_across_atomic_saves(tmp_path: Path) -> None:
    # Editors (and --fix) save by renaming a new file over the old one: a watch on the file
    # itself would go blind after the first save, so its folder is watched.
    (tmp_path / "sub").mkdir()
    script = tmp_path / "sub" / "a.script"
    script.write_text(CLEAN, encoding="utf-8")
    (tmp_path / "sub" / "other.script").write_text(CLEAN, encoding="utf-8")
    watcher = Watcher(tmp_path, "sub/a.script", "--format", "json")
    try:
        watcher.until(watcher.out, "[]")
        watcher.until(watcher.err, "watching for changes")
        for round_ in range(3):
            text = BROKEN.replace("[broken]", f"[a{round_}]") if round_ % 2 == 0 else CLEAN
            (tmp_path / "sub" / ".a.script.tmp").write_text(text, encoding="utf-8")
            os.replace(tmp_path / "sub" / ".a.script.tmp", script)
            watcher.until(watcher.out, "L003" if round_ % 2 == 0 else "[]")
            watcher.until(watcher.err, "watching for changes")
    finally:
        status = watcher.stop()
    assert status == 130


def test_which_changes_count() -> None:
    from scriptc.cli.watch import Watched

    root = os.path.abspath(os.sep + "project")
    watched = Watched.__new__(Watched)
    watched.folders = {os.path.join(root, "activities")}
    watched.files = frozenset({os.path.join(root, "one.txt")})
    watched.targets = [root]
    counts = {name: watched.relevant(os.path.join(root, *name.split("/"))) for name in (
        "activities/a.script", "activities/deep/b.script", "one.txt", "scriptc.toml",
        "activities/.gitignore", "c.script", "activities/notes.txt",
        "activities/.a.script.tmp", "activities/.hidden/c.script",
        ".scriptc_cache/.gitignore", "activities/.scriptc_cache/x.script")}
    assert [name for name, counted in counts.items() if counted] == [
        "activities/a.script", "activities/deep/b.script", "one.txt", "scriptc.toml",
        "activities/.gitignore"]


def test_watch_rounds_in_process(files: Path, monkeypatch) -> None:
    """The loop of `--watch` over a stand-in for watchfiles (the real one is run above): the
    first wake-up lints, an empty wake-up does not, a change does, Ctrl-C ends it with 130."""
    import types

    from scriptc.cli import watch as watch_module

    seen = {}

    def fake_watch(*targets, watch_filter, **options):
        seen["targets"], seen["options"] = targets, options
        yield set()  # the watcher is set up: the first round
        yield set()  # a wake-up with nothing to report
        assert watch_filter("modified", str(files / "broken.script"))
        assert not watch_filter("modified", str(files / "notes.txt"))
        (files / "new.script").write_text(CLEAN.replace("[clean]", "[new]"), encoding="utf-8")
        yield {("added", str(files / "new.script"))}
        raise KeyboardInterrupt

    monkeypatch.setitem(sys.modules, "watchfiles", types.SimpleNamespace(watch=fake_watch))
    monkeypatch.setattr(watch_module, "_is_terminal", lambda stream: True)
    result = run("lint", ".", "--watch", "--format", "grouped")
    assert result.exit_code == 130
    assert seen["targets"] == (str(files),)
    assert seen["options"]["yield_on_timeout"] and seen["options"]["raise_interrupt"]
    rounds = result.stdout.split("\x1b[2J\x1b[H")  # the screen is cleared between rounds
    assert len(rounds) == 2 and all("broken.script:" in r for r in rounds)
    assert result.stderr.count("watching for changes (Ctrl-C stops)") == 2
    assert result.stderr.count("checked 1 file: 1 error") == 1
    assert result.stderr.count("checked 2 files") == 1
    # Written to a file, no screen is cleared.
    assert "\x1b[2J" not in run("lint", ".", "--watch", "-o", "report.txt").stdout


def test_watch_without_a_watcher_says_so(files: Path, monkeypatch) -> None:
    import types

    def no_watcher(*targets, **options):
        raise OSError(28, "inotify watch limit reached")
        yield

    monkeypatch.setitem(sys.modules, "watchfiles", types.SimpleNamespace(watch=no_watcher))
    result = run("lint", ".", "--watch")
    assert (result.exit_code, result.stderr) == (
        2, "error: cannot watch the files: inotify watch limit reached\n")
    monkeypatch.setitem(sys.modules, "watchfiles", None)  # not installed
    result = run("lint", ".", "--watch")
    assert result.exit_code == 2 and "pip install watchfiles" in result.stderr


def test_watch_refuses_stdin(files: Path) -> None:
    result = run("lint", "-", "--watch")
    assert result.exit_code == 2 and "--watch cannot watch stdin" in result.stderr
