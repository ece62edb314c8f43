"""The editor extension's grammar (lsp/vscode/syntaxes/scriptc.tmLanguage.json) and the word and
indentation patterns of its language configuration, built from the language's facts
(`scriptc.language`) and the map's classes (`scriptc.ir.builtins`).

The TextMate grammar is how VS Code colours a script before (and without) the language
server: its regular expressions (Oniguruma's, which read these patterns as Python does) are
the language's own, never written again by hand. `python -m scriptc.generate` writes the
files; tests/test_generated.py fails when one is stale, and lsp/vscode/tests/*.test.script
(vscode-tmgrammar-test, tests/test_textmate.py) test the scopes.
"""

from __future__ import annotations

import re
from typing import Any

from scriptc.ir.builtins import CLASSES
from scriptc.language import (
    ASSIGNMENTS,
    ATT_ACCESS,
    BLOCK_KINDS,
    COMMENT_PATTERN,
    FIELD_ACCESS,
    FUNCTION_KINDS,
    ITEM_KEYWORDS,
    MUTEXES,
    NAME_CHAR,
    NAME_PATTERN,
    NUMBER_PATTERN,
    OPERATOR_PATTERN,
    OPERATORS,
    RULE_ACTIONS,
    RULE_MESSAGES,
    SCOPES,
    SIGILS,
    STRING_ESCAPES,
    STRING_PATTERN,
    THIS,
    TRACKS,
    TRUE,
    not_in_name,
)

__all__ = ["decrease_indent", "first_line", "grammar", "increase_indent", "word_pattern"]

_QUOTE = STRING_PATTERN[0]
_STRING_BODY = STRING_PATTERN[1:-1]
_PERCENT = COMMENT_PATTERN[0]
_COMMENTS = rf"(?:{COMMENT_PATTERN}\s*)*"  # comments between two tokens
# The rest of a line from a string that does not close on it (a scanner error): items end
# there, so that one missing quote does not colour the rest of the file.
_OPEN_STRING_TO_EOL = rf"{_QUOTE}{_STRING_BODY}\\?$"
_ITEM_END = rf"\]|(?={_OPEN_STRING_TO_EOL})"


def _literal(text: str) -> str:
    """`text` as a regular expression, only its metacharacters escaped (the JSON stays
    readable: `#`, `&` and `@` need no backslash)."""
    return re.sub(r"([.^$*+?()\[\]{}|\\])", r"\\\1", text)


def _sigil(terminal: str) -> str:
    return _literal(SIGILS[terminal])


def _choice(words) -> str:
    """An alternation of words, the longest first (so that none hides a longer one)."""
    return "|".join(sorted(words, key=len, reverse=True))


def _letters(table) -> str:
    return "[" + "".join(table) + "]"


def _include(name: str) -> dict[str, str]:
    """A reference to a rule of the grammar's repository."""
    return {"include": f"#{name}"}


def _scope(name: str) -> dict[str, str]:
    return {"name": f"{name}.scriptc"}


def _captures(*names: str) -> dict[str, dict[str, str]]:
    return {str(i): _scope(n) for i, n in enumerate(names, 1) if n}


def _sigiled(terminal: str, scope: str) -> dict[str, Any]:
    return {"match": f"({_sigil(terminal)}){NAME_PATTERN}",
            "captures": {"0": _scope(scope), "1": _scope("punctuation.definition."
                                                          + ("class" if terminal == "CLASS_REF"
                                                             else "variable"))}}


def _number() -> str:
    # Not inside a name, a decimal or a sigil's name (`b2`, `1.2.3`, `?kid2`): neither a name
    # character, a dot nor a sigil before it; neither a letter, a digit, `_` nor a dot after.
    chars = NAME_CHAR[1:-1]
    dash = "-" if chars.endswith("-") else ""
    chars = chars.removesuffix("-")
    sigils = "".join(_literal(s) for s in (*SIGILS.values(), "&"))
    return f"(?<![{chars}.{sigils}{dash}]){NUMBER_PATTERN}(?![{chars}.])"


def _delimited(name: str | None, begin: str, end: str, patterns: list[dict[str, Any]],
               begin_name: str, end_name: str) -> dict[str, Any]:
    named = {"name": f"{name}.scriptc"} if name else {}
    return {**named, "begin": begin, "beginCaptures": {"0": _scope(begin_name)}, "end": end,
            "endCaptures": {"0": _scope(end_name)}, "patterns": patterns}


def grammar() -> dict[str, Any]:
    """The TextMate grammar of the script syntax (scope `source.scriptc`)."""
    string_patterns = [_include("escape")]
    label = {"name": "entity.name.label.scriptc", "match": NAME_PATTERN}
    kinds = _choice(BLOCK_KINDS)
    return {
        "name": "scriptc",
        "scopeName": "source.scriptc",
        "fileTypes": ["script"],
        "patterns": [_include("comment"), _include("item"), _include("unterminated-string")],
        "repository": {
            "comment": {
                "name": "comment.block.percentage.scriptc",
                "begin": _literal(_PERCENT),
                "beginCaptures": {"0": _scope("punctuation.definition.comment.begin")},
                "end": _literal(_PERCENT),
                "endCaptures": {"0": _scope("punctuation.definition.comment.end")},
            },
            "string": _delimited("string.quoted.double", _QUOTE, f"{_QUOTE}|$", string_patterns,
                                 "punctuation.definition.string.begin",
                                 "punctuation.definition.string.end"),
            "command-string": _delimited(
                "string.quoted.double.command", _QUOTE, f"{_QUOTE}|$",
                [*string_patterns, {"name": "constant.numeric.scriptc", "match": _number()},
                 {"name": "punctuation.separator.field.scriptc", "match": ","}],
                "punctuation.definition.string.begin", "punctuation.definition.string.end"),
            "escape": {"patterns": [
                {"name": "constant.character.escape.scriptc",
                 "match": r"\\[" + _literal("".join(sorted(STRING_ESCAPES))) + "]"},
                {"name": "invalid.illegal.escape.scriptc", "match": r"\\."},
            ]},
            "number": {"name": "constant.numeric.scriptc", "match": _number()},
            "comma": {"name": "punctuation.separator.comma.scriptc", "match": ","},
            "item": {"patterns": [
                _include("rule-message"),
                _include("goal"),
                _include("block"),
                {"name": "meta.item.action.scriptc", "match": r"(\[)\s*(action)\s*(\])",
                 "captures": _captures("punctuation.section.item.begin",
                                       "keyword.other.action", "punctuation.section.item.end")},
                {"name": "meta.item.activity.scriptc", "match": rf"(\[)\s*({NAME_PATTERN})\s*(\])",
                 "captures": _captures("punctuation.section.item.begin",
                                       "entity.name.section.activity",
                                       "punctuation.section.item.end")},
                _delimited("meta.item", r"\[", _ITEM_END, [_include("item-body")],
                           "punctuation.section.item.begin", "punctuation.section.item.end"),
                {"name": "invalid.illegal.stray-bracket.scriptc", "match": r"\]"},
            ]},
            "rule-message": {
                "name": "meta.item.rule-message.scriptc",
                "begin": rf"(\[)\s*({_choice(RULE_MESSAGES)})\s*(:)",
                "beginCaptures": _captures("punctuation.section.item.begin",
                                           "keyword.other.rule-message",
                                           "punctuation.separator.colon"),
                "end": _ITEM_END,
                "endCaptures": {"0": _scope("punctuation.section.item.end")},
                "patterns": [
                    _include("comment"), _include("string"), _include("number"), _include("comma"),
                    {"name": "constant.language.rule-action.scriptc",
                     "match": not_in_name(_letters(RULE_ACTIONS)) + rf"(?=\s*{_COMMENTS},)"},
                    {"name": "constant.language.mutex.scriptc",
                     "match": not_in_name(_letters(MUTEXES)) + rf"(?=\s*{_COMMENTS}\])"},
                    {"name": "entity.name.function.rule.scriptc", "match": NAME_PATTERN},
                ],
            },
            "goal": {
                "name": "meta.item.goal.scriptc",
                "begin": rf"(\[)\s*(goal)\s*(:)\s*({NAME_PATTERN})?",
                "beginCaptures": _captures("punctuation.section.item.begin", "keyword.other.goal",
                                           "punctuation.separator.colon",
                                           "entity.name.section.goal"),
                "end": _ITEM_END,
                "endCaptures": {"0": _scope("punctuation.section.item.end")},
                "patterns": [_include("comment"),
                             {"name": "entity.name.section.goal.scriptc", "match": NAME_PATTERN}],
            },
            "block": {
                "name": "meta.item.block.scriptc",
                "begin": rf"(\[)\s*(b)\s*(#)\s*({NAME_PATTERN})?\s*(#)\s*({kinds})"
                         rf"(?!{NAME_CHAR})",
                "beginCaptures": _captures("punctuation.section.item.begin", "keyword.other.block",
                                           "punctuation.separator.label", "entity.name.label",
                                           "punctuation.separator.label", "storage.type.block"),
                "end": _ITEM_END,
                "endCaptures": {"0": _scope("punctuation.section.item.end")},
                "patterns": [_include("item-body")],
            },
            "item-body": {"patterns": [
                _include("comment"), _include("track"), _include("cnd"), _include("jump"),
                _include("string"), _include("number"), _include("comma"),
                {"name": "punctuation.separator.colon.scriptc", "match": ":"},
                {"name": "keyword.other.block.scriptc", "match": rf"(?<!{NAME_CHAR})b(?=\s*#)"},
                {"name": "storage.type.block.scriptc", "match": not_in_name(f"(?:{kinds})")},
                {"name": "punctuation.separator.label.scriptc", "match": "#"},
                {"name": "keyword.other.scriptc",
                 "match": not_in_name(f"(?:{_choice(ITEM_KEYWORDS)})")},
                label,
            ]},
            "track": {
                "name": "meta.track.scriptc",
                "begin": rf"(?<!{NAME_CHAR})({_choice(TRACKS)})\s*(\()",
                "beginCaptures": _captures("support.function.track",
                                           "punctuation.section.parens.begin"),
                "end": rf"\)|(?={_OPEN_STRING_TO_EOL})",
                "endCaptures": {"0": _scope("punctuation.section.parens.end")},
                "patterns": [_include("comment"), _include("command-string"), _include("comma")],
            },
            "jump": {
                "match": rf"(?<!{NAME_CHAR})(TRJMP|FLSJMP)\s*(\()\s*({NAME_PATTERN})?\s*(\))",
                "captures": _captures("keyword.control.jump", "punctuation.section.parens.begin",
                                      "entity.name.label.reference",
                                      "punctuation.section.parens.end"),
            },
            "cnd": {
                "name": "meta.condition.scriptc",
                "begin": rf"(?<!{NAME_CHAR})(CND)\s*(\()",
                "beginCaptures": _captures("keyword.control.conditional",
                                           "punctuation.section.parens.begin"),
                "end": rf"\)|(?={_OPEN_STRING_TO_EOL})",
                "endCaptures": {"0": _scope("punctuation.section.parens.end")},
                "patterns": [_include("condition")],
            },
            "condition": {"patterns": _condition()},
            "unterminated-string": {
                "name": "string.quoted.double.unterminated.scriptc "
                        "invalid.illegal.unterminated-string.scriptc",
                "match": _OPEN_STRING_TO_EOL,
            },
        },
    }


def _condition() -> list[dict[str, Any]]:
    nested = [_include("condition")]
    return [
        _include("comment"),
        _include("string"),
        _delimited(None, r"\{", rf"\}}|(?={_OPEN_STRING_TO_EOL})", nested,
                   "punctuation.section.braces.begin", "punctuation.section.braces.end"),
        _delimited(None, r"\(", rf"\)|(?={_OPEN_STRING_TO_EOL})", nested,
                   "punctuation.section.parens.begin", "punctuation.section.parens.end"),
        {"name": "keyword.other.assignment.scriptc",
         "match": not_in_name(f"(?:{_choice(ASSIGNMENTS)})")},
        {"name": "constant.language.boolean.scriptc", "match": not_in_name(TRUE)},
        {"match": rf"(?<!{NAME_CHAR})({_letters(FUNCTION_KINDS)})\s*(:)",
         "captures": _captures("keyword.other.function-kind", "punctuation.separator.colon")},
        {"name": "keyword.operator.comparison.scriptc", "match": OPERATOR_PATTERN},
        {"name": "keyword.operator.quantifier.scriptc", "match": "!"},
        {"match": rf"({_literal(FIELD_ACCESS)})\s*({NAME_PATTERN})?",
         "captures": _captures("keyword.operator.accessor", "variable.other.member.field")},
        {"match": rf"({_literal(ATT_ACCESS)})\s*({NAME_PATTERN})?",
         "captures": _captures("keyword.operator.accessor", "variable.other.member.attribute")},
        {"match": rf"({_sigil('CLASS_REF')})({_choice(CLASSES)})(?!{NAME_CHAR})",
         "captures": {"0": _scope("support.class"),
                      "1": _scope("punctuation.definition.class")}},
        _sigiled("CLASS_REF", "entity.name.type.class"),
        {"match": (f"({_sigil('ALIAS')}){_literal(THIS.removeprefix(SIGILS['ALIAS']))}"
                   f"(?!{NAME_CHAR})"),
         "captures": {"0": _scope("variable.language.this"),
                      "1": _scope("punctuation.definition.variable")}},
        _sigiled("ALIAS", "variable.other.alias"),
        _sigiled("VAR_REF", "variable.other.var"),
        _sigiled("ATT_REF", "variable.other.attribute"),
        _include("number"),
        _include("comma"),
        {"name": "storage.modifier.scope.scriptc", "match": not_in_name(_letters(SCOPES))},
        {"name": "entity.name.function.scriptc", "match": rf"{NAME_PATTERN}(?=\s*\()"},
        {"name": "invalid.illegal.operator.scriptc",
         "match": "[" + "".join(_literal(op.removeprefix("OP")) for op in OPERATORS) + "]"},
    ]


def word_pattern() -> str:
    """What VS Code takes for one word (double-click, word-based suggestions): a name with its
    sigil, a comparison, a number."""
    sigils = "".join(_literal(s) for s in SIGILS.values())
    return f"[{sigils}]?{NAME_PATTERN}|{OPERATOR_PATTERN}|{NUMBER_PATTERN}"


def first_line() -> str:
    """A first line that makes a file a script whatever its name: comments, then the
    activity's `[name]`."""
    return rf"^\s*{_COMMENTS}\[{NAME_PATTERN}\]\s*(?:{_literal(_PERCENT)}.*)?$"


def increase_indent() -> str:
    """After `[goal:...]` and `[action]` (comments may follow), the next line is indented."""
    return rf"^\s*\[\s*(?:goal\s*:[^\]]*|action\s*)\]\s*{_COMMENTS}$"


def decrease_indent() -> str:
    return r"^\s*\[\s*goal\s*:"
