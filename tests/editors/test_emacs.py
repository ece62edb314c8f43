"""Emacs, in batch, as the language server's client: the session of `editortest` (edits
right after accented letters and emoji, then a change of `scriptc.toml`) through eglot, with
the `scriptc-mode` of docs/editors.md; after each step, the buffer and the diagnostics
eglot placed in it must be what `scriptc lint` says of that text.

Debian's Emacs 28 and eglot 1.9 (`.ci/run`: `apt-get install emacs-nox elpa-eglot`): eglot
1.9 offers no position encoding (UTF-16, the protocol's default) and watches the files the
server asks it to (`file-notify`), so the configuration's change comes as a file event.
`-m "not editor"` leaves these tests out of a quick run.
"""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

import pytest
from editortest import Session, edits, expected_steps

pytestmark = pytest.mark.editor

SESSION = Path(__file__).parent / "emacs_session.el"
EMACS = "/usr/bin/emacs"
# eglot 1.9 shows a diagnostic as "SOURCE [CODE]: MESSAGE".
SHOWN = re.compile(r"scriptc \[(?P<code>[A-Z]\d{3})\]: (?P<message>.*)", re.DOTALL)


def test_emacs_eglot_edits_after_non_ascii_text_and_sees_a_configuration_change(tmp_path):
    assert os.access(EMACS, os.X_OK), f"{EMACS}: install it (.ci/run: apt-get install emacs-nox)"
    session = Session(tmp_path)
    env = session.prepare(edits=[{"line": e.line, "start": e.start, "end": e.end,
                                  "new_text": e.new_text} for e in edits()])
    done = subprocess.run([EMACS, "--batch", "-q", "-l", str(SESSION)], env=env,
                          cwd=session.repo, capture_output=True, text=True, timeout=180,
                          stdin=subprocess.DEVNULL, check=False)
    record = session.record(done)
    assert record["position_encoding"] == "utf-16"  # eglot 1.9 offers none
    for step, (text, diagnostics) in zip(record["steps"], expected_steps(tmp_path / "lint"),
                                         strict=True):
        assert step["lines"] == text.split("\n"), step["name"]
        shown = []
        for d in step["diagnostics"]:
            parts = SHOWN.fullmatch(d.pop("text"))
            assert parts is not None, d
            shown.append({"code": parts["code"], "message": parts["message"], **d})
        assert shown == diagnostics, step["name"]
