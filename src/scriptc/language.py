"""The language's lexical facts and vocabulary, stated once: what a name, a number, a string
and a comment are, the words of the grammar, and the letters and operators whose meaning the
language fixes (rule actions, mutex commands, scopes, comparisons, function kinds).

Every reader and writer that must agree on these asks here: the scanner, the printer and the
formatter, the editor's tokens, completion, hover and rename, the checks and the emitters of
the letters, the bytecode's verifier and disassembler, the configuration's checks and loader,
the run time's function registry and the thesis-JSON reader. The files that cannot import
Python (the TextMate grammar of the editor extension, the JSON Schemas, the docs' tables) are
written from here by `python -m scriptc.generate`, and tests fail when one is stale
(tests/test_generated.py). A name one of them accepts is then a name for all of them.

The facts come from the grammar where the grammar states them: the patterns of `NAME`,
`NUMBER` and `STRING` (`grammar/condition.lark`) and `COMMENT` (`grammar/script.lark`), the
sigils of the prefixed names (`ALIAS: "?" NAME`), `?THIS`, the accessors and the comparisons
are read from the grammar files, so a change of the grammar changes them (tests hold them
equal to the terminals lark builds). What the grammar leaves to lowering and the checks is
stated here: the item words, the two escapes, and the meaning of each letter.

This module is on the path of `scriptc lint`: it imports only `re` and `scriptc.resources`,
reads the two small grammar files, and does not import lark (only `syntax/` does).
"""

from __future__ import annotations

import re
from collections.abc import Mapping

from scriptc.resources import grammar_path

__all__ = [
    "ASSIGNMENTS",
    "ATT_ACCESS",
    "BLOCK_KINDS",
    "COMMENT_PATTERN",
    "FIELD_ACCESS",
    "FUNCTION_KINDS",
    "GRAMMAR_WORDS",
    "ITEM_KEYWORDS",
    "ITEM_WORDS",
    "JUMP_WORDS",
    "MUTEXES",
    "NAME_CHAR",
    "NAME_CHARS",
    "NAME_PATTERN",
    "NAME_START",
    "NUMBER_PATTERN",
    "OPEN_COMMENT_PATTERN",
    "OPEN_STRING_PATTERN",
    "OPERATORS",
    "OPERATOR_PATTERN",
    "PARTIAL_NAME_PATTERN",
    "RULE_ACTIONS",
    "RULE_MESSAGES",
    "SCOPES",
    "SIGILS",
    "STRING_ESCAPES",
    "STRING_PATTERN",
    "THIS",
    "TRACKS",
    "TRUE",
    "is_activity_name",
    "is_name",
    "name_problem",
    "not_in_name",
    "quote",
    "sigiled",
    "to_name",
    "unescape",
]

_GRAMMARS = {name: grammar_path(name).read_text(encoding="utf-8")
             for name in ("condition.lark", "script.lark")}
# A grammar's text without its `//` comments (no literal of ours holds `//`).
_CODE = {name: re.sub(r"//[^\n]*", "", text) for name, text in _GRAMMARS.items()}
# Each grammar's terminals (`NAME: /.../`, `ALFA: "alfa"`, `ALIAS: "?" NAME`): one regex for
# all of them, since each compiled regex costs this module's import (on the lint path) time.
_TERMINALS: dict[str, dict[str, str]] = {
    name: dict(re.findall(r"^([A-Z_]+)[ \t]*:[ \t]*(.*?)[ \t]*$", text, re.MULTILINE))
    for name, text in _CODE.items()}


def _definition(grammar: str, terminal: str) -> str:
    """The right-hand side of the terminal `terminal: ...` in a grammar file."""
    found = _TERMINALS[grammar].get(terminal)
    if found is None:  # a grammar that no longer states it: fail at import, not with a wrong rule
        raise RuntimeError(f"grammar/{grammar} has no terminal `{terminal}`")
    return found


def _pattern(grammar: str, terminal: str) -> str:
    """The regular expression of the terminal `terminal: /.../`, its groups made
    non-capturing so that it can be embedded in a larger expression."""
    m = re.fullmatch(r"/(.*)/", _definition(grammar, terminal))
    if m is None:
        raise RuntimeError(f"grammar/{grammar}: `{terminal}` is not a regular expression")
    return re.sub(r"(?<!\\)\((?!\?)", "(?:", m.group(1))


def _literal(grammar: str, terminal: str) -> str:
    """The text of the terminal `terminal: "..."`."""
    m = re.fullmatch(r'"([^"\\]*)"', _definition(grammar, terminal))
    if m is None:
        raise RuntimeError(f"grammar/{grammar}: `{terminal}` is not a literal")
    return m.group(1)


def _delimited(pattern: str, delimiter: str) -> str:
    """The body of a pattern that opens and closes with `delimiter` (a string, a comment)."""
    if not (pattern.startswith(delimiter) and pattern.endswith(delimiter)):
        raise RuntimeError(f"`{pattern}` is not delimited by `{delimiter}`")
    return pattern[len(delimiter):-len(delimiter)]


# -- names ------------------------------------------------------------------------------------

# A name: activity names, goal ids, labels, rule ids, function names, the names after `?`, `@`,
# `$` and `#` (thesis 4.3 and 4.4).
NAME_PATTERN = _pattern("condition.lark", "NAME")
_PARTS = re.fullmatch(r"(\[[^\]]+\])(\[[^\]]+\])\*", NAME_PATTERN)
if _PARTS is None:
    raise RuntimeError(f"the NAME terminal `{NAME_PATTERN}` is not `[start][char]*`")
# The character class a name starts with, and the class of the characters that follow.
NAME_START, NAME_CHAR = _PARTS.group(1), _PARTS.group(2)
# Every character a name may hold (the classes are ASCII): for scanning by hand.
NAME_CHARS = frozenset(c for c in map(chr, range(128)) if re.fullmatch(NAME_CHAR, c))
# A run of name characters, perhaps empty: the word being typed at an editor's cursor.
PARTIAL_NAME_PATTERN = f"{NAME_CHAR}*"

_NAME = re.compile(NAME_PATTERN)
_NOT_NAME_CHAR = re.compile(NAME_CHAR.replace("[", "[^", 1))

# The names that start with a sigil, by the grammar's terminal: `?kid`, `#Human`, `@count`,
# `$mood` (each is `"sigil" NAME` in the grammar).
SIGILS: Mapping[str, str] = {
    terminal: parts[0][1] for terminal, parts in (
        (t, d.split()) for t, d in _TERMINALS["condition.lark"].items())
    if len(parts) == 2 and parts[1] == "NAME" and re.fullmatch(r'"."', parts[0])}
if set(SIGILS) != {"ALIAS", "CLASS_REF", "VAR_REF", "ATT_REF"}:
    raise RuntimeError(f"grammar/condition.lark states the prefixed names {sorted(SIGILS)}")
THIS = _literal("condition.lark", "THIS")  # the candidate entity of a CLASS assignment's tests
FIELD_ACCESS = _literal("condition.lark", "FIELD_ACCESS")  # `?kid>&positionrho`
ATT_ACCESS = _literal("condition.lark", "ATT_ACCESS")  # `?kid>$mood`

# `[action]` starts an action (lowering reads a bracketed name as the activity name only when
# it is the first item and not `action`); `[alfa:`, `[omega:`, `[goal:` and `[b#` are keywords
# of the grammar where an item opens. A script named by one of them cannot be written.
ITEM_WORDS = frozenset({"action", "alfa", "omega", "goal", "b"})


def is_name(text: str) -> bool:
    """Whether `text` is a name of the language (`NAME_PATTERN`, the whole text)."""
    return _NAME.fullmatch(text) is not None


def is_activity_name(text: str) -> bool:
    """Whether a script can be named `text`: a name that is not one of `ITEM_WORDS`."""
    return is_name(text) and text not in ITEM_WORDS


def name_problem(text: str, *, activity: bool = False) -> str | None:
    """Why `text` is not a name (an activity name with `activity`), as the end of a sentence
    ("... is not a name: <this>"), or None when it is one."""
    if not is_name(text):
        return ("a name is letters, digits, `_` and `-`, and starts with a letter or `_`"
                if text else "a name is not empty")
    if activity and text in ITEM_WORDS:
        return (f"`[{text}]` is an item of the script syntax, not an activity name "
                f"(the words {', '.join(f'`{w}`' for w in sorted(ITEM_WORDS))} cannot name "
                "an activity)")
    return None


def to_name(text: str) -> str:
    """The name nearest `text`: each character a name cannot hold becomes `_`, and `_` goes
    before a first character a name cannot start with (an invented label, say)."""
    name = _NOT_NAME_CHAR.sub("_", text)
    return name if re.match(NAME_START, name) else "_" + name


def sigiled(terminal: str) -> str:
    """The pattern of a prefixed name (`ALIAS`, `CLASS_REF`, `VAR_REF`, `ATT_REF`)."""
    return re.escape(SIGILS[terminal]) + NAME_PATTERN


def not_in_name(pattern: str) -> str:
    """`pattern` matched only as a whole word: neither preceded nor followed by a name
    character (the letter `A` of a rule message, not the `A` of `Ab`)."""
    return f"(?<!{NAME_CHAR}){pattern}(?!{NAME_CHAR})"


# -- numbers, strings, comments ---------------------------------------------------------------

# A number in the script syntax and in the number fields of the thesis JSON: ASCII digits only
# (`\d` would also accept the digits of other scripts).
NUMBER_PATTERN = _pattern("condition.lark", "NUMBER")
# A string: on one line, with the escapes `\\` and `\"` (lowering reports any other).
STRING_PATTERN = _pattern("condition.lark", "STRING")
_STRING_BODY = _delimited(STRING_PATTERN, '"')
# A string as an editor sees one being typed: perhaps not closed yet.
OPEN_STRING_PATTERN = f'"{_STRING_BODY}"?'
# What a backslash in a string may escape (each stands for itself); the grammar accepts any
# escaped character and lowering reports the others (P006).
STRING_ESCAPES = frozenset({"\\", '"'})
_ESCAPED = re.compile(r"\\([" + re.escape("".join(sorted(STRING_ESCAPES))) + "])")

# A comment: `% ... %`, over several lines if need be; a `%` inside a string is not one.
COMMENT_PATTERN = _pattern("script.lark", "COMMENT")
_COMMENT_BODY = _delimited(COMMENT_PATTERN, "%")
OPEN_COMMENT_PATTERN = f"%{_COMMENT_BODY}%?"


def quote(value: str) -> str:
    """`value` as a string literal of the language: `\\` and `"` escaped, nothing else."""
    return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'


def unescape(body: str) -> str:
    """A string literal's body with the language's escapes resolved; any other backslash
    stays as written (lowering reports it, P006)."""
    return _ESCAPED.sub(r"\1", body) if "\\" in body else body


# -- the words of the grammar ------------------------------------------------------------------

# Every word the two grammars write as a literal (`"goal"`, `MV: "MV"`, ...): the keywords.
# Each belongs to exactly one of the groups below (tests/test_language.py holds that).
GRAMMAR_WORDS = frozenset(
    w for text in _CODE.values() for w in re.findall(r'"([^"\\]*)"', text) if _NAME.fullmatch(w))

# The words that open an item after `[` (with `[b#`, a block).
ITEM_KEYWORDS = ("goal", "action", "alfa", "omega")
RULE_MESSAGES = (_literal("script.lark", "ALFA"), _literal("script.lark", "OMEGA"))
BLOCK_KINDS = ("blk_inst", "blk_jump", "blk_terminus", "blk_sens", "blk_sensor")
TRACKS = tuple(_literal("script.lark", t) for t in ("MV", "LD", "AO"))
JUMP_WORDS = ("CND", "TRJMP", "FLSJMP")
ASSIGNMENTS = ("CLASS", "VAR", "ATT")
TRUE = "TRUE"
# The kinds of function a condition calls (`B: near(1.0)`): the letter before the `:`.
FUNCTION_KINDS: Mapping[str, str] = {
    "B": "a boolean about the candidate entity of a CLASS assignment (its tests)",
    "F": "a string, the value of a VAR or ATT assignment",
    "E": "a boolean, an evaluation after the `!`",
}

# -- the letters and operators --------------------------------------------------------------

# A comparison of a field test (`?kid>&positionrho OP< 1.5`): the field is <meaning> the value.
OPERATOR_PATTERN = _pattern("condition.lark", "OPERATOR")
OPERATORS: Mapping[str, str] = {"OP=": "equal to", "OP<": "less than", "OP>": "greater than"}
_WRITTEN = {f"OP{chr(c)}" for c in range(33, 127) if re.fullmatch(OPERATOR_PATTERN, f"OP{chr(c)}")}
if set(OPERATORS) != _WRITTEN:  # the grammar grew (or lost) a comparison: say what it means
    raise RuntimeError(f"the OPERATOR terminal writes {sorted(_WRITTEN)}, "
                       f"the language knows {sorted(OPERATORS)}")

# The ACTION field of a rule message (`[alfa:1, guard, "", "", A, U]`), thesis 4.4.
RULE_ACTIONS: Mapping[str, str] = {
    "A": "activate and add the rule",
    "R": "remove the rule",
    "D": "activate the rule and delay it for later use",
    "B": "bring a delayed rule back",
    "C": "recover a removed rule",
}
# The MUTEX field of a rule message: how issuing it holds the map's propagation.
MUTEXES: Mapping[str, str] = {
    "L": "lock map propagation, then issue",
    "M": "issue",
    "U": "issue, then unlock map propagation",
}
# The scope of an assignment (`{CLASS #Human U ?kid (...)}`): how long the binding lasts.
SCOPES: Mapping[str, str] = {
    "U": "until the script ends (or a rule removes it)",
    "L": "until the rule that bound it passes the map on",
    "T": "until the map returns to the map producer (one loop)",
}
