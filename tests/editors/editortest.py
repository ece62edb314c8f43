"""What every editor test does (tests/editors/): the session an editor goes through with
`scriptc lint`'s own account of each step as the oracle.

The session: open a script with Italian comments, an accented file name and emoji; edit it
right after that non-ASCII text (insert, delete, fix a label, break one), then change the
repository's `scriptc.toml`. After each step the editor reports its buffer's text and its
diagnostics; they must be what `scriptc lint --format json` says of that text under the
configuration of that step, on the same characters. An editor and a server that disagree on
the position encoding disagree on the text after the first edit, and on every column.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

# Italian comments, an accented file name and emoji before the places edited (a case of the
# checks as well, with its diagnostics beside it).
SAMPLE = Path(__file__).parent.parent / "cases" / "checks" / "labels_after_non_ascii.script"
TEXT = SAMPLE.read_text(encoding="utf-8")
CONFIG = "[lint]\nignore = []\n"
# The last step: the configuration now ignores F001 (unreachable code, a warning).
CONFIG_LATER = '[lint]\nignore = ["F001"]\n'

# Each edit as (what to find, where in it, characters to delete, what to insert); each one
# changes the diagnostics, so that an editor can tell when the server has answered it.
EDITS = [
    ("🎵🎵 perché", len("🎵🎵 "), 0, "è "),  # after the emoji: the columns after it move
    ("TRJMP(strat)", len("TRJMP(st"), 1, ""),  # strat -> stat
    ("TRJMP(stat)", len("TRJMP(sta"), 0, "r"),  # stat -> start: no L003
    ("FLSJMP(start)", len("FLSJMP("), len("start"), "fine"),  # L003 again, after the emoji
]


@dataclass(frozen=True)
class Edit:
    """One edit on one line: columns in code points and in UTF-8 bytes (what Neovim's API
    counts), and the text after it."""

    line: int
    start: int
    end: int
    start_byte: int
    end_byte: int
    new_text: str
    text_after: str


def edits() -> list[Edit]:
    text = TEXT
    out = []
    for find, into, delete, insert in EDITS:
        at = text.index(find) + into
        line = text.count("\n", 0, at)
        line_start = text.rfind("\n", 0, at) + 1
        line_text = text[line_start:text.index("\n", at)]
        start, end = at - line_start, at - line_start + delete
        text = text[:at] + insert + text[at + delete:]
        out.append(Edit(line, start, end, len(line_text[:start].encode()),
                        len(line_text[:end].encode()), insert, text))
    return out


def lint(cases: list[tuple[str, str]], folder: Path) -> list[list[dict]]:
    """What `scriptc lint --format json` reports for each (text, configuration), sorted by
    place: code, message, and 0-based line and columns in code points."""
    for n, (text, config) in enumerate(cases):
        case = folder / f"case{n}"
        case.mkdir(parents=True)
        (case / "scriptc.toml").write_text(config, encoding="utf-8")
        (case / "activity.script").write_text(text, encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "scriptc", "lint", "--format", "json",
                           "--no-cache", str(folder)], capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode in (0, 1), done.stderr
    out: list[list[dict]] = [[] for _ in cases]
    for d in json.loads(done.stdout):
        n = int(Path(d["file"]).parent.name[len("case"):])
        out[n].append({"code": d["code"], "message": d["message"], "line": d["line"] - 1,
                       "column": d["column"] - 1, "end_line": d["end_line"] - 1,
                       "end_column": d["end_column"] - 1})
    return [sorted(ds, key=lambda d: (d["line"], d["column"], d["message"])) for ds in out]


@dataclass(frozen=True)
class Session:
    """The files of one editor's session in a test's folder: a repository holding the
    script and its configuration, the editor's orders (JSON, named by the environment
    variable SCRIPTC_EDITOR_TEST) and its record of the session."""

    folder: Path

    @property
    def repo(self) -> Path:
        return self.folder / "repo"

    @property
    def script(self) -> Path:
        return self.repo / "activity.script"

    @property
    def config(self) -> Path:
        return self.repo / "scriptc.toml"

    @property
    def orders(self) -> Path:
        return self.folder / "orders.json"

    @property
    def result(self) -> Path:
        return self.folder / "result.json"

    def prepare(self, **orders) -> dict[str, str]:
        """Lay out the repository and the orders (the common ones and `orders`); returns
        the environment to run the editor in: no user configuration, data or state of this
        machine (a HOME of its own)."""
        self.repo.mkdir(parents=True)
        self.script.write_text(TEXT, encoding="utf-8")
        self.config.write_text(CONFIG, encoding="utf-8")
        self.orders.write_text(json.dumps({
            "file": str(self.script), "root": str(self.repo), "config": str(self.config),
            "config_later": CONFIG_LATER, "result": str(self.result),
            "cmd": [sys.executable, "-m", "scriptc", "lsp"], "timeout_ms": 20000,
            **orders}), encoding="utf-8")
        home = self.folder / "home"
        home.mkdir()
        return {**os.environ, "SCRIPTC_EDITOR_TEST": str(self.orders), "HOME": str(home),
                "XDG_CONFIG_HOME": str(home / "config"), "XDG_DATA_HOME": str(home / "data"),
                "XDG_STATE_HOME": str(home / "state"), "XDG_CACHE_HOME": str(home / "cache"),
                "LANG": "C.UTF-8", "LC_ALL": "C.UTF-8"}

    def record(self, done: subprocess.CompletedProcess) -> dict:
        """The editor's record of the session, once it has exited without an error."""
        assert self.result.exists(), (done.returncode, done.stdout[-2000:], done.stderr[-3000:])
        record = json.loads(self.result.read_text(encoding="utf-8"))
        assert "error" not in record, (record["error"], done.stderr[-3000:])
        assert done.returncode == 0, done.stderr[-3000:]
        assert [s["name"] for s in record["steps"]] == \
            ["open", *[f"edit {n}" for n in range(1, len(EDITS) + 1)], "configuration"]
        for step in record["steps"]:
            assert step["changed"], f"{step['name']}: the diagnostics never changed"
        return record


def expected_steps(folder: Path) -> list[tuple[str, list[dict]]]:
    """(text, diagnostics) after opening, after each edit, and after the configuration
    changed."""
    texts = [TEXT] + [e.text_after for e in edits()]
    cases = [(t, CONFIG) for t in texts] + [(texts[-1], CONFIG_LATER)]
    return list(zip([c[0] for c in cases], lint(cases, folder), strict=True))
