"""The language's lexical facts are one fact (src/scriptc/language.py): the grammar, the JSON
Schemas, the configuration, the run time and the thesis-JSON reader agree on what a name is,
and on which words cannot name an activity."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from scriptc import language
from scriptc.analysis.analyze import analyze_json, analyze_script
from scriptc.project.setup import Setup
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

    return {t.name.rsplit("__", 1)[-1]: t for t in script_lark().terminals}


def _same_language(ours: str, theirs: str, samples) -> None:
    for text in samples:
        assert (re.fullmatch(ours, text) is None) == (re.fullmatch(theirs, text) is None), text


# Texts near every terminal's edges: signs, dots, exponents, quotes, escapes, line breaks.
EDGES = st.text(alphabet='aZ_-09+.eE"\\%\n\r ?#@$OP=<>&', max_size=10)


def _same_on_edges(ours: str, theirs: str):
    @FAST
    @given(EDGES)
    def check(text: str) -> None:
        _same_language(ours, theirs, [text])

    return check


@pytest.mark.slow
def test_the_patterns_are_the_grammars_terminals() -> None:
    """language.py reads the terminals from the grammar files; lark reads the same (its
    groups made non-capturing, which changes no match)."""
    terminals = _grammar_terminals()
    assert terminals["NAME"].pattern.to_regexp() == language.NAME_PATTERN
    assert re.compile(language.NUMBER_PATTERN).groups == 0
    assert re.compile(language.STRING_PATTERN).groups == 0
    for terminal, ours in (("NUMBER", language.NUMBER_PATTERN),
                           ("STRING", language.STRING_PATTERN),
                           ("COMMENT", language.COMMENT_PATTERN),
                           ("OPERATOR", language.OPERATOR_PATTERN),
                           *((t, language.sigiled(t)) for t in language.SIGILS)):
        theirs = terminals[terminal].pattern.to_regexp()
        _same_language(ours, theirs, ["1", "-.5", "1e", "+1.E-3", "..", '"a\\"', '"a\\\nb"',
                                      '"a\rb"', '"\\q"', "%a\n%", "%%", "OP=", "OP!", "?a",
                                      "#b-2", "@_", "$9", "?THIS", "٣", "aé"])
        _same_on_edges(ours, theirs)()
    for terminal, literal in (("THIS", language.THIS), ("FIELD_ACCESS", language.FIELD_ACCESS),
                              ("ATT_ACCESS", language.ATT_ACCESS)):
        assert terminals[terminal].pattern.value == literal
    assert (terminals["ALFA"].pattern.value,
            terminals["OMEGA"].pattern.value) == language.RULE_MESSAGES
    assert tuple(terminals[t].pattern.value for t in ("MV", "LD", "AO")) == language.TRACKS


def test_the_name_is_split_into_its_classes() -> None:
    assert language.NAME_PATTERN == language.NAME_START + language.NAME_CHAR + "*"
    assert all(re.fullmatch(language.NAME_CHAR, c) for c in language.NAME_CHARS)
    assert {chr(c) for c in range(0x3000) if re.fullmatch(language.NAME_CHAR, chr(c))} == \
        language.NAME_CHARS  # ASCII only: `é` and `٣` are not name characters
    assert set("abcdefghijklmnopqrstuvwxyz"
               "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") == language.NAME_CHARS


def test_every_word_of_the_grammar_is_in_one_group() -> None:
    """A keyword the grammar gains must be given its place here (and so in the editor's
    grammar, completion and tokens, which read these groups)."""
    literals = {str(t.pattern.value) for t in _grammar_terminals().values()
                if type(t.pattern).__name__ == "PatternStr"}
    assert {w for w in literals if language.is_name(w)} == language.GRAMMAR_WORDS
    groups = [set(language.ITEM_KEYWORDS) | {"b"}, set(language.BLOCK_KINDS),
              set(language.TRACKS), set(language.JUMP_WORDS), set(language.ASSIGNMENTS),
              {language.TRUE}, set(language.FUNCTION_KINDS)]
    assert sum(len(g) for g in groups) == len(set().union(*groups))  # disjoint
    assert set().union(*groups) - {"action"} == language.GRAMMAR_WORDS
    assert set(language.RULE_MESSAGES) <= set(language.ITEM_KEYWORDS)
    assert set(language.ITEM_KEYWORDS) | {"b"} == language.ITEM_WORDS


def test_the_comparisons_are_the_operator_terminals() -> None:
    theirs = _grammar_terminals()["OPERATOR"].pattern.to_regexp()
    written = {f"OP{chr(c)}" for c in range(33, 127) if re.fullmatch(theirs, f"OP{chr(c)}")}
    assert written == set(language.OPERATORS) == {"OP=", "OP<", "OP>"}


def test_the_letters() -> None:
    assert "".join(language.RULE_ACTIONS) == "ARDBC"
    assert "".join(language.MUTEXES) == "LMU"
    assert "".join(language.SCOPES) == "ULT"
    assert "".join(language.FUNCTION_KINDS) == "BFE"


@FAST
@given(st.text(max_size=12))
@example('a"b\\c')
@example("\\q")
def test_quote_and_unescape_are_inverse(value: str) -> None:
    quoted = language.quote(value)
    assert language.unescape(quoted[1:-1]) == value
    assert (re.fullmatch(language.STRING_PATTERN, quoted) is not None) == (
        "\n" not in value and "\r" not in value)


def _is_string(text: str) -> bool:
    """A string literal, read by hand: quotes around characters that are neither a quote, a
    backslash nor a line break, or a backslash and any character but a line break."""
    if len(text) < 2 or text[0] != '"' or text[-1] != '"':
        return False
    i, end = 1, len(text) - 1
    while i < end:
        ch = text[i]
        if ch in "\n\r" or ch == '"':
            return False
        if ch == "\\":
            if i + 1 >= end or text[i + 1] in "\n\r":
                return False
            i += 1
        i += 1
    return True


@FAST
@given(st.text(alphabet='ab"\\\n\r ', max_size=12))
@example('"a\\"')
@example('"\\\\"')
@example('"a\\\nb"')
def test_the_string_pattern_is_the_string_literal(text: str) -> None:
    assert (re.fullmatch(language.STRING_PATTERN, text) is not None) == _is_string(text)


def test_unescape_keeps_unknown_escapes() -> None:
    assert language.unescape('a\\qb\\"c\\\\') == 'a\\qb"c\\'


@FAST
@given(st.text(max_size=10))
@example("9lives")
@example("")
@example("wave hands")
def test_to_name_gives_a_name(text: str) -> None:
    name = language.to_name(text)
    assert language.is_name(name)
    if language.is_name(text):
        assert name == text


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


@pytest.mark.slow
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


@pytest.mark.slow
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
    analysis = analyze_script(SourceFile("f.script", script), functions=Setup(built).functions)
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


@pytest.mark.slow
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
