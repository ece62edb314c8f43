"""`scriptc run --plot FILE` (runtime/plot.py)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.cli.main import cli

SCRIPT = """[approach]
[goal:approach]
  [action]
    [b#step#blk_inst: MV("0.25, 0, 0, 0, 200") LD("0, 0, 1, 1, 0, 200") AO()]
    [b##blk_jump: CND({CLASS #Human U ?kid (?THIS>&positionrho OP< 0.5)} ! {TRUE})
                  TRJMP(greet) FLSJMP(step)]
    [b#greet#blk_inst: MV("0, 0, 1, 0, 1500") LD("0, 1, 0, 1, 0, 1000")
                       AO("songs/hello.wav, 0, 1200")]
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


@pytest.mark.slow
def test_png(files: Path) -> None:
    result = run(files, "run.png")
    assert result.exit_code == 0, result.output
    data = (files / "run.png").read_bytes()
    assert data.startswith(b"\x89PNG") and len(data) > 10_000


@pytest.mark.slow
def test_svg_draws_led_colours(files: Path) -> None:
    result = run(files, "run.svg")
    assert result.exit_code == 0, result.output
    svg = (files / "run.svg").read_text(encoding="utf-8")
    assert "#0000ff" in svg and "#00ff00" in svg  # the LED commands, in their colour


def test_other_extensions_are_refused(files: Path) -> None:
    result = run(files, "run.gif")
    assert result.exit_code == 2 and ".png or .svg" in result.output


# -- what the picture holds, read from the figure's artists ------------------------------------

EXAMPLES = Path(__file__).parent.parent / "examples"


def test_map_positions_are_turned_into_the_world_frame() -> None:
    from scriptc.runtime.recorded import map_positions

    # The robot drives from the origin to (1, 0), then turns to face +y.
    samples = [(0, 0.0, 0.0, 0.0), (500, 0.5, 0.0, 0.0), (1000, 1.0, 0.0, math.pi / 2)]
    update = {"event": "update", "attributename": "poses", "policy": "R", "status": "applied"}
    events = [
        {**update, "t": 0, "objectid": "Human/kid", "value": {"positionrho": 2.0,
                                                               "positiontheta": 0.0}},
        # at 1000 ms, 2 m straight ahead of the robot, which faces +y from (1, 0)
        {**update, "t": 1000, "objectid": "Human/kid", "value": {"positionrho": 2.0}},
        # 1 m ahead (+y), then only the bearing: the distance keeps its value (1 m to the
        # robot's left: -x of where it stands)
        {**update, "t": 1000, "objectid": "Object/ball", "value": {"positionrho": 1.0,
                                                                    "positiontheta": 0.0}},
        {**update, "t": 1000, "objectid": "Object/ball", "value": {"positiontheta": math.pi / 2}},
        {**update, "t": 1000, "objectid": "Human/late", "value": {"positionrho": 1.0},
         "status": "dropped"},
        {**update, "t": 1000, "objectid": "Obstacle/wall", "attributename": "tracking",
         "value": {"permanencetime": 10}},
        {**update, "t": 1000, "objectid": "Camera/cam0", "attributename": "tracking",
         "value": {"permanencetime": 10}},
    ]
    paths, no_position = map_positions(events, samples)
    assert sorted(paths) == ["Human/kid", "Object/ball"]
    (t0, x0, y0), (t1, x1, y1) = paths["Human/kid"]
    assert (t0, t1) == (0, 1000)
    assert (x0, y0) == pytest.approx((2.0, 0.0))
    assert (x1, y1) == pytest.approx((1.0, 2.0))
    assert [p[1:] for p in paths["Object/ball"]] == [pytest.approx((1.0, 1.0)),
                                                       pytest.approx((0.0, 0.0))]
    assert no_position == ["Obstacle/wall"]


def test_the_pose_between_samples_is_interpolated() -> None:
    from scriptc.runtime.recorded import pose_at

    samples = [(0, 0.0, 0.0, 0.0), (20, 0.2, -0.1, 0.4)]
    assert pose_at(samples, 10) == pytest.approx((0.1, -0.05, 0.2))
    assert pose_at(samples, 20) == pytest.approx((0.2, -0.1, 0.4))
    assert pose_at(samples, 500) == pytest.approx((0.2, -0.1, 0.4))
    assert pose_at([], 5) == (0.0, 0.0, 0.0)


def test_the_footprint_is_the_models_base() -> None:
    import mujoco

    from scriptc.runtime.recorded import footprint_radius
    from scriptc.runtime.robots.mujoco import load_model

    model = load_model()
    base = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "base")
    assert footprint_radius() == pytest.approx(model.geom_size[base][0])


def drawn(monkeypatch, args: list[str]):
    """Run `scriptc run ... --plot`, keeping the figure it drew."""
    import scriptc.runtime.plot as plot

    figures = []
    draw = plot.draw_run
    monkeypatch.setattr(plot, "draw_run",
                        lambda *a, **k: figures.append(draw(*a, **k)) or figures[-1])
    result = CliRunner().invoke(cli, ["run", *args], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    (figure,) = figures
    return figure


def _known(world: dict) -> set[str]:
    ids = {e["objectid"] for e in world.get("entities", ())}
    ids |= {u["objectid"] for u in world.get("updates", ())
            if u["objectid"].partition("/")[0] in ("Human", "Object", "Obstacle")}
    return ids


@pytest.mark.slow
@pytest.mark.parametrize("name", ["greeting", "joint_attention", "imitation", "turn_taking",
                                  "reward_dance", "approach"])
def test_every_entity_of_every_example_is_drawn_and_labelled(name, tmp_path, monkeypatch) -> None:
    world = EXAMPLES / f"{name}.world.json"
    figure = drawn(monkeypatch, [str(EXAMPLES / f"{name}.script"), "--world", str(world),
                                 "--robot", "kinematic", "--plot", str(tmp_path / "p.png")])
    top, bottom = figure.axes[:2]
    labels = {t.get_text() for t in top.texts}
    known = _known(json.loads(world.read_text(encoding="utf-8")))
    assert known and known <= labels
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert any(text.startswith("robot's footprint") for text in legend)
    assert [t.get_text() for t in bottom.get_yticklabels()] == [
        "move\n(wheels)", "led\n(LEDs)", "audioout\n(speaker)"]
    assert bottom.get_xlabel() == "time (s)" and bottom.get_ylabel() == "track"


@pytest.mark.slow
def test_the_greetings_child_is_where_the_robot_was_told(tmp_path, monkeypatch) -> None:
    """examples/greeting.world.json sends the child's distance and bearing at 2 s and 3 s; the
    robot stands at the origin facing +x until then, so the path is those polar points."""
    figure = drawn(monkeypatch, [str(EXAMPLES / "greeting.script"), "--world",
                                 str(EXAMPLES / "greeting.world.json"), "--plot",
                                 str(tmp_path / "g.png")])
    top = figure.axes[0]
    expected = [(2.5 * math.cos(0.3), 2.5 * math.sin(0.3)), (1.2 * math.cos(0.2),
                                                             1.2 * math.sin(0.2))]
    flat = [c for point in expected for c in point]
    paths = [[c for point in zip(*line.get_data(), strict=True) for c in point]
             for line in top.get_lines()]
    assert any(len(path) == 4 and path == pytest.approx(flat) for path in paths)
    assert {"2 s", "3 s", "Human/kid1"} <= {t.get_text() for t in top.texts}
