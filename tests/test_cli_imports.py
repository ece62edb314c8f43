"""Cold start: `scriptc lint` imports only what linting uses. pygls (~0.4 s), mujoco and
jsonschema are for other verbs, rich only shows an explanation's markdown in a terminal and
watchfiles only serves `--watch` (docs/performance.md). Each check runs the CLI in a fresh
interpreter and looks at sys.modules at exit."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = "[clean_act]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n"
HEAVY = ("pygls", "lsprotocol", "mujoco", "jsonschema", "fastjsonschema", "rich", "hypothesis",
         "watchfiles")

PROBE = """
import inspect, json, sys
SIGNATURES = []
_signature = inspect.signature
def _counted(obj, *args, **kwargs):
    SIGNATURES.append(repr(obj))
    return _signature(obj, *args, **kwargs)
inspect.signature = _counted
from scriptc.cli.main import main
sys.argv = ["scriptc", *json.loads(sys.argv[1])]
try:
    main()
except SystemExit:
    pass
sys.stdout.flush()
sys.__stderr__.write("\\nSIGNATURES " + json.dumps(SIGNATURES))
sys.__stderr__.write("\\nMODULES " + json.dumps(sorted(sys.modules)))
"""


def probe(args: list[str], cwd: Path) -> dict[str, list[str]]:
    """The modules loaded by `scriptc ARGS` run in a fresh interpreter, and the
    objects whose signature `inspect.signature` computed on the way."""
    env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "NO_COLOR")}
    done = subprocess.run([sys.executable, "-c", PROBE, json.dumps(args)], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=60, check=False)
    found = {}
    for word in ("SIGNATURES", "MODULES"):
        marker = done.stderr.rindex(f"\n{word} ") + len(word) + 2
        found[word] = json.loads(done.stderr[marker:].split("\n", 1)[0])
    return found


def loaded_after(args: list[str], cwd: Path) -> set[str]:
    return set(probe(args, cwd)["MODULES"])


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "a.script").write_text(SCRIPT, encoding="utf-8")
    (tmp_path / "b.script").write_text(SCRIPT.replace("[action]\n", ""), encoding="utf-8")
    return tmp_path


@pytest.mark.slow
@pytest.mark.parametrize("args", [
    ["lint", "a.script"],
    ["lint", "b.script"],  # with errors to render
    ["lint", "."],
    ["lint", "b.script", "--format", "json"],
    ["lint", "b.script", "--format", "github"],
    ["compile", "a.script", "-o", "-"],
])
def test_lint_and_compile_stay_light(folder: Path, args: list[str]) -> None:
    loaded = loaded_after(args, folder)
    assert "scriptc" in loaded and "click" in loaded  # the probe did run the CLI
    assert not loaded & set(HEAVY), f"`scriptc {' '.join(args)}` imported {loaded & set(HEAVY)}"


def test_lint_computes_no_signature(folder: Path) -> None:
    """`@dataclass` gives a class without a docstring one made of its signature, and the first
    `inspect.signature` of a process compiles `tokenize`'s patterns: 17 ms of a cold `scriptc
    lint` on the reference machine. The classes on the lint path have docstrings (`@node`
    writes the same text itself when a node has none)."""
    for args in (["lint", "a.script"], ["lint", "b.script"]):
        assert probe(args, folder)["SIGNATURES"] == []


def test_version_and_help_do_not_load_the_compiler(folder: Path) -> None:
    for args in (["--version"], ["--help"]):
        loaded = loaded_after(args, folder)
        assert not loaded & {"lark", *HEAVY}, loaded & {"lark", *HEAVY}


@pytest.mark.slow
def test_a_lint_with_its_cache_built_loads_neither_lark_nor_tempfile(folder: Path) -> None:
    """The first lint of a folder builds the item parser's cache with lark (whose grammar
    loader brings tempfile); the next ones need neither. tempfile (with shutil, random, bz2 and
    lzma) also came with `importlib.resources`, which only reading an explanation needs."""
    loaded_after(["lint", "a.script"], folder)
    loaded = loaded_after(["lint", "a.script"], folder)
    assert not loaded & {"lark", "tempfile"}, loaded & {"lark", "tempfile"}
    # Nor the IR's node classes: the results come from the cache.
    assert "scriptc.ir.nodes" not in loaded


@pytest.mark.slow
def test_colour_on_demand_loads_rich_only_for_markdown(folder: Path) -> None:
    """Diagnostics are coloured without rich (the renderer writes ANSI codes itself); the
    probe can tell, since an explanation's markdown in colour does import it."""
    assert "rich" not in loaded_after(["--color", "always", "lint", "b.script"], folder)
    assert "rich" in loaded_after(["--color", "always", "explain", "L003"], folder)


@pytest.mark.slow
def test_a_check_of_valid_json_imports_no_schema_library(folder: Path) -> None:
    """The yes or no of thesis JSON is the schema compiled ahead of time
    (frontend/thesis_validator.py): compiling it with fastjsonschema at run time cost a cold
    `scriptc check` about 50 ms and the import 20 more; jsonschema (~180 ms) words only what
    is wrong with an invalid document."""
    data = (Path(__file__).parent / "data" / "test_act.json").read_bytes()
    (folder / "act.json").write_bytes(data)
    loaded = loaded_after(["check", "act.json"], folder)
    assert "scriptc" in loaded
    assert not loaded & {"jsonschema", "fastjsonschema"}, loaded & {"jsonschema", "fastjsonschema"}
    (folder / "bad.json").write_text('{"activityname": 3}', encoding="utf-8")
    assert "jsonschema" in loaded_after(["check", "bad.json"], folder)
