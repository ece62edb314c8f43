"""Behaviour of the semantic passes beyond the case files (the fixes they offer are case data:
each case's expected diagnostics hold the text after each fix, tests/harness/diagnostics.py):
the decisions written in the explanations, and the public API."""

from __future__ import annotations

import dataclasses
import subprocess
import sys

from scriptc.analysis.analyze import analyze_script
from scriptc.check import check_script
from scriptc.diagnostics.model import Severity
from scriptc.ir.builtins import STANDARD, Function, Param
from scriptc.source import SourceFile


def lint(text: str, functions=STANDARD):
    analysis = analyze_script(SourceFile("t.script", text), functions)
    assert analysis.script is not None
    front = [d for d in analysis.diagnostics if d.code[0] in "PS" or d.code in ("V001", "V002")]
    assert not front, front
    return analysis.diagnostics


def codes(text: str, functions=STANDARD) -> list[str]:
    return [d.code for d in lint(text, functions)]


def under(text: str, diagnostic) -> str:
    return text[diagnostic.span.start : diagnostic.span.end]


HEAD = "[act]\n"
TAIL = "[goal:g]\n[action]\n[b##blk_terminus]\n"


def blocks(*lines: str) -> str:
    return "[act]\n[goal:g]\n[action]\n" + "\n".join(lines) + "\n"


# -- M: rule messages ----------------------------------------------------------------------


def test_single_alfa_must_be_u_and_single_omega_must_be_l():
    text = HEAD + '[alfa:1,a,"","",A,M]\n[omega:1,a,"","",R,M]\n' + TAIL
    diags = lint(text)
    assert [(d.code, under(text, d)) for d in diags] == [("M001", "M"), ("M002", "M")]


def test_missing_alfa_is_reported_at_the_omega_list():
    text = HEAD + '[omega:0,k,"","",C,L]\n' + TAIL
    (d,) = lint(text)
    assert d.code == "M003" and under(text, d).startswith("[omega:0")


def test_no_leak_warning_when_the_omega_list_is_missing():
    # M003 covers it, with a fix that writes the whole omega list: no duplicate reports.
    text = HEAD + '[alfa:1,a,"","",A,U]\n' + TAIL
    assert codes(text) == ["M003"]


def test_delayed_rules_need_no_undo():
    text = HEAD + '[alfa:1,later,"","",D,M]\n[alfa:0,k,"","",C,U]\n[omega:0,k,"","",R,L]\n' + TAIL
    assert codes(text) == []


def test_an_empty_letter_in_ir_built_by_hand_is_unknown():
    """The front ends never give an empty action or mutex letter (a parse error comes first),
    but the IR may be built by hand: M005 then says it found nothing."""
    source = SourceFile("t.script", HEAD + '[alfa:1,a,"","",A,U]\n[omega:1,a,"","",R,L]\n' + TAIL)
    script = analyze_script(source).script
    alfa = script.alfa[0]
    empty = dataclasses.replace(alfa, mutex=dataclasses.replace(alfa.mutex, text=""))
    (d,) = check_script(dataclasses.replace(script, alfa=(empty,)), source)
    assert (d.code, d.message, d.fix) == ("M005", "unknown mutex command nothing in alfa message",
                                          None)

# -- L: labels ------------------------------------------------------------------------------


def test_duplicate_label_points_at_the_first_definition():
    text = blocks("[b#x#blk_inst: MV() LD() AO()]", "[b#x#blk_terminus]")
    (d,) = lint(text)
    assert d.code == "L001"
    assert d.span.start > d.labels[0].span.start
    assert under(text, d) == "x" and d.labels[0].message == "`x` first defined here"


def test_label_suggestions_stop_after_64_distinct_unknown_targets():
    """Each suggestion is a difflib scan over every label: past 64 distinct unknown targets
    (a script generated wrongly) the others get the plain help, so the pass stays linear. A
    target met again keeps the suggestion it had."""
    jumps = [f"[b##blk_jump: CND(! {{E: gt(1, 2)}}) TRJMP(targe{k}) FLSJMP()]"
             for k in [*range(66), 0]]
    found = [d for d in lint(blocks('[b#target#blk_inst: MV() LD() AO("Silence, 0, 100")]',
                                    *jumps, "[b##blk_terminus]")) if d.code == "L003"]
    suggested = [d.fix is not None and "`target`" in d.help for d in found]
    assert suggested == [True] * 64 + [False, False, True]
    assert found[64].help.startswith("add `targe64` as the label of a block")


def test_goals_without_an_id_are_not_one_id_used_twice():
    """A goal without an id is S007 (the front end's); the checks, run on such a script
    through the API, do not call two of them one id used twice (L002)."""
    source = SourceFile("t.script", "[a]\n" + TAIL.replace("goal:g", "goal:") * 2)
    analysis = analyze_script(source)
    assert [d.code for d in analysis.diagnostics] == ["S007", "S007"]
    assert "L002" not in [d.code for d in check_script(analysis.script, source)]


# -- F: flow --------------------------------------------------------------------------------


def test_a_script_without_blocks_has_no_flow():
    """An action without blocks is the front end's error (S006); the checks, run on such a
    script through the API, find no flow to judge (and no block to start from)."""
    source = SourceFile("t.script", "[a]\n[goal:g]\n[action]\n")
    analysis = analyze_script(source)
    assert [d.code for d in analysis.diagnostics] == ["S006"]
    assert check_script(analysis.script, source) == []


def test_constant_true_jump_takes_only_its_true_branch():
    text = blocks(
        "[b##blk_jump: CND({TRUE}) TRJMP(end) FLSJMP()]",
        "[b##blk_inst: MV() LD() AO()]",
        "[b#end#blk_terminus]",
    )
    (d,) = lint(text)
    assert d.code == "F001" and d.severity is Severity.WARNING
    assert under(text, d) == "[b##blk_inst"
    assert d.labels[0].message == "this jump always goes to `end`"


def test_conditional_jump_takes_both_branches():
    text = blocks(
        "[b##blk_jump: CND(! {E: gt(1, 2)}) TRJMP(end) FLSJMP()]",
        "[b##blk_inst: MV() LD() AO()]",
        "[b#end#blk_terminus]",
    )
    assert codes(text) == []


def test_one_warning_per_run_of_unreachable_blocks():
    text = (
        "[act]\n[goal:g]\n[action]\n[b##blk_terminus]\n[b##blk_inst: MV() LD() AO()]\n"
        "[goal:h]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n"
    )
    (d,) = lint(text)
    assert d.code == "F001" and d.message == "3 unreachable blocks"
    assert "goal0/act0/blk1 to goal1/act0/blk1" in d.notes[0]
    assert d.labels[0].message == "the script ends here"


def test_loop_through_an_instruction_block_is_fine():
    text = blocks(
        "[b#top#blk_inst: MV() LD() AO(\"Silence, 0, 100\")]",
        "[b##blk_jump: CND({CLASS #Human T ?kid (B: near(1))} !) TRJMP() FLSJMP(top)]",
        "[b##blk_terminus]",
    )
    assert codes(text) == []


def test_cycle_through_sensor_blocks_is_one_error_with_labels():
    text = blocks(
        "[b#a#blk_jump: CND(! {E: gt(1, 2)}) TRJMP() FLSJMP(c)]",
        "[b#b#blk_sens]",
        "[b#c#blk_jump: CND(! {E: gt(1, 2)}) TRJMP(a) FLSJMP()]",
        "[b##blk_terminus]",
    )
    (d,) = lint(text)
    assert d.code == "F002" and under(text, d) == "[b#a#blk_jump"
    assert [under(text, label) for label in d.labels] == ["[b#b#blk_sens", "[b#c#blk_jump"]


# -- V: values ------------------------------------------------------------------------------


def test_range_bounds_are_inclusive():
    text = ('[act]\n[alfa:4294967295,r,"","",A,U]\n[omega:0,r,"","",R,L]\n[goal:g]\n[action]\n'
            '[b##blk_inst: MV("-0.5, 0, 0, 0, 2147483647") LD("0, 1, 0.5, 0, 2147483647, 0") '
            'AO("Silence, 0, 2147483647")]\n[b##blk_terminus]\n')
    assert codes(text) == []


# -- R: conditions --------------------------------------------------------------------------


def test_u_binding_in_an_earlier_block_counts_and_keeps_its_class():
    text = blocks(
        "[b##blk_jump: CND({CLASS #Obstacle U ?o (B: near(1))} !) TRJMP() FLSJMP()]",
        "[b##blk_jump: CND(! {E: eq(?o>&isfixed, 1)} {E: eq(?o>&istarget, 1)}) TRJMP() FLSJMP()]",
        "[b##blk_terminus]",
    )
    diags = lint(text)
    assert [(d.code, under(text, d)) for d in diags] == [("R002", "istarget")]
    assert diags[0].notes == ("`istarget` is a field of `Object`",)


def test_alias_with_two_classes_in_the_script_has_no_field_check_outside():
    text = blocks(
        "[b##blk_jump: CND({CLASS #Obstacle U ?o (B: near(1))} !) TRJMP() FLSJMP()]",
        "[b##blk_jump: CND({CLASS #Human U ?o (B: near(1))} !) TRJMP() FLSJMP()]",
        "[b##blk_jump: CND(! {E: eq(?o>&isfixed, 1)}) TRJMP() FLSJMP()]",
        "[b##blk_terminus]",
    )
    assert codes(text) == []


def test_latest_binding_in_a_condition_gives_the_class():
    text = blocks(
        "[b##blk_jump: CND({CLASS #Obstacle T ?o ()} {CLASS #Human T ?o ()} ! "
        "{E: eq(?o>&isfixed, 1)}) TRJMP() FLSJMP()]",
        "[b##blk_terminus]",
    )
    diags = lint(text)
    assert [d.code for d in diags] == ["R008", "R002"]
    assert diags[1].labels[0].message == "`?o` is bound to a `Human` here"


def test_alias_in_its_own_tests_is_unbound():
    text = blocks(
        "[b##blk_jump: CND({CLASS #Human T ?kid (?THIS>&id OP= ?kid>&id)} !) TRJMP() FLSJMP()]",
        "[b##blk_terminus]",
    )
    (d,) = lint(text)
    assert d.code == "R006" and d.labels[0].message == "`?kid` is bound here, after this use"


def test_custom_functions_extend_the_registry():
    registry = STANDARD.extended([Function("sees", "E", (Param("who", "an alias"),), "doc",
                                           "repo")])
    text = blocks(
        "[b##blk_jump: CND({CLASS #Human T ?kid ()} ! {E: sees(?kid)}) TRJMP() FLSJMP()]",
        "[b##blk_terminus]",
    )
    assert codes(text) == ["R003"]
    assert codes(text, registry) == []


def test_function_kind_is_reported_before_arity():
    text = blocks("[b##blk_jump: CND(! {E: near(1, 2, 3)}) TRJMP() FLSJMP()]", "[b##blk_terminus]")
    assert codes(text) == ["R004"]


# -- A: audio -------------------------------------------------------------------------------


def test_silence_and_repository_paths_are_fine():
    text = blocks('[b##blk_inst: MV() LD() AO("Silence, 0, 1", "plugins/audio_control/songs/'
                  'sounds_Excited_R2D2.wav, 0, 4000", "a/../b.wav, 0, 1")]', "[b##blk_terminus]")
    assert codes(text) == []


# -- API ------------------------------------------------------------------------------------


def test_check_script_returns_sorted_diagnostics():
    text = blocks('[b##blk_inst: MV() LD("2, 0, 0, 5, 0, 1") AO("/x.wav, 0, 1")]')
    analysis = analyze_script(SourceFile("t.script", text))
    diags = check_script(analysis.script, analysis.source)
    assert [d.code for d in diags] == ["F003", "V004", "V005", "A001"]
    assert diags == sorted(diags, key=lambda d: d.sort_key())


def test_importing_the_checks_is_cheap():
    code = ("import sys, scriptc.check; "
            "print(sorted(m for m in ('lark', 'jsonschema', 'rich', 'click', 'difflib') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_jump_whose_branches_both_leave_is_named():
    text = blocks(
        '[b#top#blk_inst: MV() LD() AO("Silence, 0, 100")]',
        "[b##blk_jump: CND(! {E: gt(1, 2)}) TRJMP(end) FLSJMP(top)]",
        "[b##blk_inst: MV() LD() AO()]",
        "[b#end#blk_terminus]",
    )
    (d,) = lint(text)
    assert d.code == "F001" and d.message == "unreachable block" and not d.notes
    assert d.labels[0].message == "neither branch of this jump goes on to the next block"
