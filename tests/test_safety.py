"""The safety pass (check/safety.py: K001, K002) and the robot profile (scriptc/robot/profile.py).
Case files: tests/cases/safety/."""

from __future__ import annotations

import pytest

from scriptc.analysis.analyze import analyze_bytes
from scriptc.check import check_script
from scriptc.check.context import Context
from scriptc.check.safety import check_safety
from scriptc.project.config import Settings, build_settings
from scriptc.robot.profile import DEFAULT_PROFILE, Profile


def block(mv: str = "", ld: str = "") -> str:
    return f"[s]\n[goal:g]\n[action]\n[b##blk_inst: MV({mv}) LD({ld}) AO()]\n[b##blk_terminus]\n"


def codes(text: str, profile: Profile | None = None) -> list[str]:
    analysis = analyze_bytes("s.script", text.encode(), "script")
    if profile is None:
        return [d.code for d in analysis.diagnostics if d.code.startswith("K")]
    ctx = Context(analysis.script, analysis.source)
    ctx.profile = profile
    return [d.code for d in check_safety(ctx)]


def test_defaults_are_safe_and_complete() -> None:
    p = DEFAULT_PROFILE
    assert 0 < p.max_linear_speed <= 1.0 and 0 < p.max_angular_speed <= 3.0
    assert p.max_led_flash_rate == 3.0 and 0 < p.max_volume <= 1
    assert p.min_human_distance > 0 and p.source == "defaults"


def test_the_configuration_overrides_the_defaults_key_by_key() -> None:
    settings = build_settings({"robot": {"max-linear-speed": 1.2}}, path="/repo/scriptc.toml")
    p = settings.robot
    assert p.max_linear_speed == 1.2 and p.source == "/repo/scriptc.toml"
    assert p.max_angular_speed == DEFAULT_PROFILE.max_angular_speed
    assert Settings().robot is DEFAULT_PROFILE
    assert build_settings({"robot": {}}, path="/repo/scriptc.toml").robot is DEFAULT_PROFILE


@pytest.mark.parametrize("mv, expected", [
    ('"0.5, 0, 0, 0, 1000"', []),
    ('"0.51, 0, 0, 0, 1000"', ["K001"]),
    ('"0.3, 0.4, 0, 0, 1000"', []),  # 0.5 m/s exactly
    ('"-0.6, 0, 0, 0, 1000"', ["K001"]),
    ('"0, 0, -1.6, 0, 1000"', ["K001"]),
    ('"1, 0, 2, 0, 1000"', ["K001", "K001"]),
])
def test_speeds(mv: str, expected: list[str]) -> None:
    assert codes(block(mv=mv)) == expected


def test_a_profile_on_the_context_is_used() -> None:
    assert codes(block(mv='"0.8, 0, 0, 0, 1000"'), Profile(max_linear_speed=1.0)) == []
    assert codes(block(mv='"0.8, 0, 0, 0, 1000"'), Profile(max_linear_speed=0.7)) == ["K001"]


@pytest.mark.parametrize("ld, expected", [
    # on 100, off 100, four times: 4 flashes within 700 ms
    (('"1, 0, 0, 1, 0, 100", "1, 0, 0, 1, 100, 100", "1, 0, 0, 1, 100, 100", '
      '"1, 0, 0, 1, 100, 100"'), ["K002"]),
    # three flashes in a second are allowed
    ('"1, 0, 0, 1, 0, 100", "1, 0, 0, 1, 100, 100", "1, 0, 0, 1, 100, 100"', []),
    # on 150, off 200 (2.9 Hz): never 4 in one second
    (", ".join(['"1, 1, 1, 1, 200, 150"'] * 8), []),
    # turnas 0 commands are dark intervals
    (", ".join(['"1, 0, 0, 1, 0, 50"', '"1, 0, 0, 0, 0, 50"'] * 4), ["K002"]),
    # a light that stays on and changes colour does not flash
    (", ".join(f'"{i % 2}, 1, 0, 1, 0, 50"' for i in range(20)), []),
    # black is off
    (", ".join(['"1, 0, 0, 1, 0, 50"', '"0, 0, 0, 1, 0, 50"'] * 4), ["K002"]),
])
def test_flashes(ld: str, expected: list[str]) -> None:
    assert codes(block(ld=ld)) == expected


def test_the_flash_rate_comes_from_the_profile() -> None:
    ld = ", ".join(['"1, 0, 0, 1, 100, 100"'] * 4)
    assert codes(block(ld=ld), Profile(max_led_flash_rate=5.0)) == []
    assert codes(block(ld=ld), Profile(max_led_flash_rate=2.0)) == ["K002"]


def test_one_report_per_block_and_k002_is_an_error() -> None:
    ld = ", ".join(['"1, 0, 0, 1, 100, 100"'] * 12)
    analysis = analyze_bytes("s.script", block(ld=ld).encode(), "script")
    found = [d for d in analysis.diagnostics if d.code == "K002"]
    assert len(found) == 1 and found[0].severity.value == "error" and not analysis.ok
    ctx = Context(analysis.script, analysis.source)
    assert [d.code for d in check_script(analysis.script, analysis.source)
            if d.code.startswith("K")] == ["K002"] and ctx.script is analysis.script


def loop(ld: str, ao: str = "", target: str = "FLSJMP(x)") -> str:
    return (f"[s]\n[goal:g]\n[action]\n[b#x#blk_inst: MV() LD({ld}) AO({ao})]\n"
            f"[b##blk_jump: CND(! {{E: gt(1, 2)}}) TRJMP(end) {target}]\n"
            "[b#end#blk_terminus]\n")


def test_a_block_that_loops_back_repeats_its_pattern() -> None:
    assert codes(loop('"1, 0, 0, 1, 0, 100"', '"Silence, 0, 200"')) == ["K002"]
    # the light fills the block: it stays on across the seam
    assert codes(loop('"1, 0, 0, 1, 0, 100"')) == []
    # 2 Hz loop
    assert codes(loop('"1, 0, 0, 1, 0, 250"', '"Silence, 0, 500"')) == []
    # no jump back: a single flash
    assert codes(loop('"1, 0, 0, 1, 0, 100"', '"Silence, 0, 200"', "FLSJMP(end)")) == []


def test_lint_and_compile_use_the_repository_profile(tmp_path) -> None:
    """The configuration's `[robot]` limits are what K001 checks against, in `lint` (and its
    worker processes and cache) as in `compile`."""
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    script = tmp_path / "fast.script"
    script.write_text('[fast]\n[goal:g]\n  [action]\n'
                      '    [b##blk_inst: MV("10, 0, 0, 0, 1000") LD() AO()]\n'
                      "    [b##blk_terminus]\n", encoding="utf-8")
    runner = CliRunner()
    assert "K001" in runner.invoke(cli, ["lint", "--no-cache", str(script)]).output
    (tmp_path / "scriptc.toml").write_text("[robot]\nmax-linear-speed = 20\n", encoding="utf-8")
    result = runner.invoke(cli, ["lint", "--no-cache", str(script)])
    assert result.exit_code == 0 and "K001" not in result.output, result.output
    compiled = runner.invoke(cli, ["compile", str(script), "-o", str(tmp_path / "fast.json")])
    assert compiled.exit_code == 0 and "K001" not in compiled.output, compiled.output


def test_k001_names_the_profile_and_where_it_comes_from() -> None:
    """K001's notes give the profile's limit, and the configuration file it comes from when
    it is not the defaults (once per check: the words are written once)."""
    analysis = analyze_bytes("s.script", block(mv='"0.9, 0, 2.5, 0, 1000"').encode(), "script")
    for profile, source in ((DEFAULT_PROFILE, ""),
                            (build_settings({"robot": {"max-linear-speed": 0.7}},
                                            path="/repo/scriptc.toml").robot,
                             " (from /repo/scriptc.toml)")):
        ctx = Context(analysis.script, analysis.source)
        ctx.profile = profile
        found = [d for d in check_safety(ctx) if d.code == "K001"]
        linear = f"{profile.max_linear_speed:g}"
        assert [d.message for d in found] == [
            f"this move goes at 0.9 m/s, above the robot profile's {linear} m/s",
            "this move turns at 2.5 rad/s, above the robot profile's 1.5 rad/s"]
        assert [d.notes[-1] for d in found] == [
            f"profile{source}: max-linear-speed = {linear}",
            f"profile{source}: max-angular-speed = 1.5"]
        assert found[0].notes[0].startswith(f"the run-time governor slows it to {linear} m/s")
