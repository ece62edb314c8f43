"""The documentation's code runs as written: every ```python block of the README, docs/*.md and
examples/README.md is executed in a fresh folder holding a copy of `examples/`, and every
`scriptc` command of a ```sh block names a verb and options that exist. (Blocks that are not
meant to run are written without a language, or as `text`; none of the Python ones is.)"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from cli_words import scriptc_commands
from click.testing import CliRunner

from scriptc.cli.main import VERBS, cli

ROOT = Path(__file__).parent.parent
DOCUMENTS = [ROOT / "README.md", ROOT / "examples" / "README.md",
             *sorted((ROOT / "docs").glob("*.md"))]


def fenced(language: str) -> list[tuple[str, str]]:
    """(`file:line`, code) of every block fenced as ```language."""
    found = []
    for path in DOCUMENTS:
        text = path.read_text(encoding="utf-8")
        for m in re.finditer(rf"^```{language}\n(.*?)^```", text, re.MULTILINE | re.DOTALL):
            line = text.count("\n", 0, m.start()) + 1
            found.append((f"{path.relative_to(ROOT).as_posix()}:{line}", m.group(1)))
    return found


PYTHON = fenced("python")
SHELL = fenced("sh")


def test_the_documentation_has_code_to_run() -> None:
    assert len(PYTHON) >= 10 and len(SHELL) >= 10  # the extraction finds the blocks


@pytest.mark.parametrize(("where", "code"), PYTHON, ids=[w for w, _ in PYTHON])
def test_every_python_snippet_runs_as_written(where: str, code: str, tmp_path: Path,
                                              monkeypatch) -> None:
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "__doc_snippet__"}
    exec(compile(code, where, "exec"), namespace)


def test_the_executor_contract_shown_is_the_modules() -> None:
    """docs/runtime.md's Protocols name what `scriptc.runtime.executor`'s declare."""
    import scriptc.runtime.executor as executor

    (where, code), = [(w, c) for w, c in PYTHON if "class Executor(Protocol)" in c]
    namespace: dict = {"__name__": "__doc_snippet__"}
    exec(compile(code, where, "exec"), namespace)

    def members(cls) -> set[str]:
        return {name for name in vars(cls) if not name.startswith("_")} | set(
            cls.__annotations__)

    for name in ("Loadable", "Executor", "ReadSink"):
        assert members(namespace[name]) == members(getattr(executor, name)), name


def _commands() -> list[tuple[str, list[str]]]:
    return [(where, words) for where, code in SHELL for words in scriptc_commands(code)]


COMMANDS = _commands()


@pytest.mark.parametrize(("where", "words"), COMMANDS,
                         ids=[f"{w}:{' '.join(c[:2])}" for w, c in COMMANDS])
def test_every_scriptc_command_names_a_verb_and_options_that_exist(where: str,
                                                                   words: list[str]) -> None:
    assert words and words[0] in VERBS, f"{where}: no verb `{words[:1]}`"
    help_text = CliRunner().invoke(cli, [words[0], "--help"]).output
    for word in words[1:]:
        if word.startswith("-") and word != "-":
            option = word.split("=", 1)[0]
            assert re.search(rf"(^|[\s,/]){re.escape(option)}\b", help_text), \
                f"{where}: `scriptc {words[0]}` has no option {option}"


def test_the_decompiled_script_shown_is_what_decompile_prints() -> None:
    text = (ROOT / "docs" / "json.md").read_text(encoding="utf-8")
    shown = re.search(r"\(`scriptc decompile tests/data/test_act\.json`\):\n\n```scriptc\n(.*?)```",
                      text, re.DOTALL).group(1)
    result = CliRunner().invoke(cli, ["decompile", str(ROOT / "tests" / "data" / "test_act.json")])
    assert result.stdout == shown
