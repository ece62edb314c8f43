"""The language's lexical facts are one fact (src/scriptc/language.py): the grammar, the JSON
Schemas, the configuration, the run time and the thesis-JSON reader agree on what a name is,
and on which words cannot name an activity."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from scriptc import language
from scriptc.driver import analyze_json, analyze_script
from scriptc.resources import schema_path
from scriptc.source import SourceFile

ROOT = Path(__file__).parent.parent
FAST = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# Candidate names: mostly name-like, with the characters a name must refuse mixed in, and
# the words of the language (the keywords and item words are where the mistakes were).
WORDS = ["action", "alfa", "omega", "goal", "b", "blk_inst", "MV", "TRUE", "CLASS", "E", "B",
         "F", "U", "wave-hands", "_x", "x-", "kick_starter"]
CANDIDATES = st.one_of(
    st.sampled_from(WORDS),
    st.text(alphabet="abzAZ_-09 .é:#/\\\"'\t", min_size=0, max_size=8),
    st.from_regex(language.NAME_PATTERN, fullmatch=True),
)


def _grammar_terminals():
    from scriptc.syntax.parser import script_lark

    return {t.name: t for t in script_lark().terminals}


def test_name_and_number_are_the_grammars_terminals() -> None:
    """language.py reads the terminals from the grammar file; lark reads the same."""
    terminals = _grammar_terminals()
    name = next(t for n, t in terminals.items() if n.endswith("NAME"))
    number = next(t for n, t in terminals.items() if n.endswith("NUMBER"))
    assert name.pattern.to_regexp() == language.NAME_PATTERN
    assert number.pattern.to_regexp() == language.NUMBER_PATTERN


def test_the_schemas_name_and_number_patterns_are_the_languages() -> None:
    thesis = json.loads(schema_path("thesis-script.schema.json").read_text(encoding="utf-8"))
    config = json.loads(schema_path("config.schema.json").read_text(encoding="utf-8"))
    assert thesis["$defs"]["name"]["pattern"] == f"^{language.NAME_PATTERN}$"
    assert config["$defs"]["name"]["pattern"] == f"^{language.NAME_PATTERN}$"
    numbers = [d["pattern"] for d in thesis["$defs"].values()
               if isinstance(d, dict) and "[eE]" in d.get("pattern", "")]
    assert numbers == [f"^{language.NUMBER_PATTERN}$"]


def _is_activity_name_in_scripts(word: str) -> bool:
    text = f"[{word}]\n[goal:g]\n[action]\n[b##blk_terminus]\n"
    return analyze_script(SourceFile("n.script", text)).ok


def test_item_words_are_exactly_the_names_that_cannot_name_an_activity() -> None:
    """Every word of the grammar that a name could be, and every word of ITEM_WORDS: it can
    name an activity in the script syntax exactly when `is_activity_name` says so."""
    literals = {str(t.pattern.value) for t in _grammar_terminals().values()
                if type(t.pattern).__name__ == "PatternStr"}
    words = {w for w in literals if language.is_name(w)} | set(language.ITEM_WORDS)
    assert {"goal", "b", "alfa", "omega", "blk_inst", "MV"} <= words
    for word in sorted(words):
        assert _is_activity_name_in_scripts(word) == language.is_activity_name(word), word


@FAST
@given(CANDIDATES)
@example("action")
@example("wave-hands")
def test_is_name_is_the_name_pattern(text: str) -> None:
    assert language.is_name(text) == (re.fullmatch(language.NAME_PATTERN, text) is not None)
    problem = language.name_problem(text, activity=True)
    assert (problem is None) == language.is_activity_name(text)


def _config_text(name: str) -> str:
    # TOML basic strings take JSON's escapes (json.dumps writes no `\/`).
    return (f"[[functions]]\nname = {json.dumps(name, ensure_ascii=False)}\nkind = \"E\"\n"
            "arity = 0\nimplementation = \"operator:truth\"\n")


@FAST
@given(CANDIDATES)
@example("wave-hands")
def test_a_function_name_the_configuration_accepts_runs(name: str) -> None:
    """What the configuration accepts (its schema, its checks, the settings built from it), the
    run time registers and a script calls: `wave-hands` passed lint and stopped `run`."""
    from scriptc.project.config import build_settings
    from scriptc.project.config.validate import check_config
    from scriptc.runtime.configured import implementations_for
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.session import Session
    from scriptc.runtime.trace import Trace

    text = _config_text(name)
    data = tomllib.loads(text)
    problems = check_config(data, SourceFile("scriptc.toml", text))
    built = build_settings(data, path=None, root=".")
    if problems:
        assert not built.functions, name
        return
    assert [f.name for f in built.functions] == [name]
    impls = implementations_for(built)  # raised ValueError for `wave-hands`
    script = ("[a]\n[goal:g]\n[action]\n"
              f"[b##blk_jump: CND(! {{E: {name}()}}) TRJMP() FLSJMP(no)]\n"
              "[b##blk_terminus]\n[b#no#blk_terminus]\n")
    analysis = analyze_script(SourceFile("f.script", script), functions=built.registry)
    assert analysis.ok, [d.message for d in analysis.diagnostics]
    trace = Trace()
    Session([IRProgram(analysis.script, "f.script")], trace=trace, functions=impls).run(1000)
    jumps = [e for e in trace.events if e["event"] == "jump"]
    assert [e["value"] for e in jumps] == [True]


def test_the_run_time_refuses_what_is_not_a_name() -> None:
    import pytest

    from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS

    impls = STANDARD_IMPLEMENTATIONS.extended()
    impls.register("wave-hands", "E", 0, lambda call: True)
    for bad in ("9lives", "two words", "", "a.b"):
        with pytest.raises(ValueError, match="is not a function name: a name"):
            impls.register(bad, "E", 0, lambda call: True)


THESIS = (ROOT / "tests" / "data" / "test_act.json").read_text(encoding="utf-8")


@FAST
@given(CANDIDATES)
@example("action")
@example("alfa")
def test_an_activity_name_check_accepts_decompiles_to_a_script_that_compiles(name: str) -> None:
    from scriptc.emit.script import format_script

    text = THESIS.replace('"activityname":"test_act"', f'"activityname":{json.dumps(name)}', 1)
    assert text != THESIS or name == "test_act"
    checked = analyze_json(SourceFile("t.json", text))
    if not checked.ok:
        assert not language.is_activity_name(name), [d.message for d in checked.diagnostics]
        return
    assert language.is_activity_name(name)
    again = analyze_script(SourceFile("t.script", format_script(checked.script)))
    assert again.ok, [d.message for d in again.diagnostics]
    assert again.script.name.text == name
