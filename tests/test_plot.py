"""`scriptc run --plot FILE` (runtime/plot.py)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from click.testing import CliRunner

from scriptc.cli.main import cli

SCRIPT = """[approach]
[goal:approach]
  [action]
    [b#step#blk_inst: MV("0.25, 0, 0, 0, 200") LD("0, 0, 1, 1, 0, 200") AO()]
    [b##blk_jump: CND({CLASS #Human U ?kid (?THIS>&positionrho OP< 0.5)} ! {TRUE}) TRJMP(greet) FLSJMP(step)]
    [b#greet#blk_inst: MV("0, 0, 1, 0, 1500") LD("0, 1, 0, 1, 0, 1000") AO("songs/hello.wav, 0, 1200")]
    [b##blk_terminus]
"""
WORLD = {"entities": [{"objectid": "Human/kid1", "x": 1.5, "y": 0.0},
                      {"objectid": "Object/ball", "x": 0.5, "y": -0.6, "v_y": 0.1}]}


@pytest.fixture
def files(tmp_path: Path) -> Path:
    (tmp_path / "a.script").write_text(SCRIPT, encoding="utf-8")
    (tmp_path / "w.json").write_text(json.dumps(WORLD), encoding="utf-8")
    return tmp_path


def run(files: Path, out: str):
    return CliRunner().invoke(cli, ["run", str(files / "a.script"), "--world",
                                    str(files / "w.json"), "--plot", str(files / out)],
                              catch_exceptions=False)


def test_png(files: Path) -> None:
    result = run(files, "run.png")
    assert result.exit_code == 0, result.output
    data = (files / "run.png").read_bytes()
    assert data.startswith(b"\x89PNG") and len(data) > 10_000


def test_svg_draws_led_colours(files: Path) -> None:
    result = run(files, "run.svg")
    assert result.exit_code == 0, result.output
    svg = (files / "run.svg").read_text(encoding="utf-8")
    assert "#0000ff" in svg and "#00ff00" in svg  # the LED commands, in their colour


def test_other_extensions_are_refused(files: Path) -> None:
    result = run(files, "run.gif")
    assert result.exit_code == 2 and ".png or .svg" in result.output
