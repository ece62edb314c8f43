"""The differential property of issue 3: the two executors must agree. Generated scripts
(`strategies.scripts()`) and generated scenarios (timed map updates of Humans, Objects and
Obstacles with positions, tracking, categories, so that conditions go both ways) run through
one session each with the reference interpreter over the IR and with the VM over the verified
bytecode of the same script (kinematic robot, standard rules and functions); the traces must be
identical, line for line. The VM also runs with its searches interpreted instruction by
instruction (`compile_searches=False`) and must agree again.

Only scripts that pass the checker count (the others never run); each run is bounded with
`until`, so scripts that loop with time passing end too.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import conditions, scripts

from scriptc import bytecode
from scriptc.analysis.analyze import analyze_bytes
from scriptc.ops.build import emit
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.scenario import scenario_from_data
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.runtime.vm import VMProgram

# Property tests over generated input: the slow tier (CONTRIBUTING.md).
pytestmark = pytest.mark.slow

UNTIL = 20_000

ENTITIES = ["Human/h0", "Human/h1", "Human/h2", "Object/o0", "Object/o1", "Obstacle/b0"]
RHO = st.sampled_from([0.1, 0.5, 0.8, 1.0, 1.5, 2.0, 2.5, 3.0, 10.0, 500.0, 2000.0])


@st.composite
def updates(draw):
    entity = draw(st.sampled_from(ENTITIES))
    cls = entity.split("/")[0]
    kinds = ["poses", "poses", "tracking"]
    if cls == "Object":
        kinds += ["category", "istarget"]
    if cls == "Obstacle":
        kinds += ["isfixed"]
    kind = draw(st.sampled_from(kinds))
    policy = draw(st.sampled_from("RA")) if kind in ("poses", "tracking") else "R"
    if kind == "poses":
        msg = {"positionrho": draw(RHO), "positiontheta": draw(st.sampled_from([0.0, 0.5, -1.0]))}
    elif kind == "tracking":
        msg = {"permanencetime": draw(st.integers(0, 5000)),
               "appearanceon": draw(st.integers(0, UNTIL))}
    elif kind == "category":
        msg = draw(st.sampled_from(["ball", "a", "z", "10", "0.5"]))
    else:
        msg = draw(st.sampled_from(["s_true", "s_false"]))
    # Most updates come early, so that the first jumps already see entities.
    at = draw(st.one_of(st.integers(0, 50), st.integers(0, 3000), st.integers(0, UNTIL)))
    return {"at": at, "objectid": entity, "attributename": kind,
            "policy": policy, "jsonmsg": msg}


SCENARIOS = st.lists(updates(), max_size=14).map(
    lambda us: {"updates": sorted(us, key=lambda u: u["at"])})


def _trace(program, scenario: dict) -> str:
    trace = Trace()
    Session([program], scenario=scenario_from_data(scenario), trace=trace,
            robot="kinematic").run(UNTIL)
    return trace.text()


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(text=scripts(), scenario=SCENARIOS)
def test_the_ir_interpreter_and_the_vm_write_the_same_trace(text: str, scenario: dict) -> None:
    analysis = analyze_bytes("gen.script", text.encode("utf-8"), "script")
    if not analysis.ok:
        return  # refused scripts never run
    program = bytecode.load(emit(analysis.script, "bytecode", analysis.source))
    expected = _trace(IRProgram(analysis.script, "gen.script"), scenario).splitlines()
    assert _trace(VMProgram(program, "gen.script"), scenario).splitlines() == expected
    assert _trace(VMProgram(program, "gen.script", compile_searches=False),
                  scenario).splitlines() == expected


@st.composite
def looping_scripts(draw):
    """A loop of generated conditions evaluated again and again while the scenario changes the
    map: an instruction block that takes time, then jumps whose exits go on, skip ahead or go
    back to the top."""
    n = draw(st.integers(1, 4))
    ms = draw(st.sampled_from([250, 500, 1000]))
    lines = ["[loop]", "[goal:g0]", "  [action]",
             f'    [b#top#blk_inst: MV("0.1, 0, 0.1, 0, {ms}") LD() AO()]']
    labels = ["top"] + [f"j{i}" for i in range(n)] + ["tail"]
    for i in range(n):
        if i == n // 2:
            lines.append("[goal:g1]")
            lines.append("  [action]")
        t = draw(st.sampled_from(["", "top", "tail", *labels[i + 2:]]))
        f = draw(st.sampled_from(["", "top", "tail", *labels[i + 2:]]))
        lines.append(f"    [b#j{i}#blk_jump: CND({draw(conditions())}) TRJMP({t}) FLSJMP({f})]")
    lines.append('    [b#tail#blk_inst: MV() LD("0, 0, 1, 1, 0, 300") AO()]')
    lines.append("    [b##blk_jump: CND({TRUE}) TRJMP(top) FLSJMP()]")
    return "\n".join(lines) + "\n"


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(text=looping_scripts(), scenario=SCENARIOS)
def test_conditions_evaluated_again_and_again_agree(text: str, scenario: dict) -> None:
    test_the_ir_interpreter_and_the_vm_write_the_same_trace.hypothesis.inner_test(text, scenario)


def test_generated_scripts_mostly_pass_the_checker() -> None:
    """The property above is vacuous for refused scripts: make sure most generated ones run."""
    ok = []

    @settings(max_examples=40, deadline=None, database=None)
    @given(text=scripts())
    def count(text: str) -> None:
        ok.append(analyze_bytes("gen.script", text.encode("utf-8"), "script").ok)

    count()
    assert sum(ok) >= len(ok) // 3, f"{sum(ok)} of {len(ok)} generated scripts pass the checker"
