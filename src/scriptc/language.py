"""The language's lexical facts, stated once: what a name is, and which words cannot name an
activity.

Every reader and writer that must agree on these asks here: the configuration's checks and
loader (`[[functions]]`, `[[rules]]`), the run time's function registry, the thesis-JSON reader
(`scriptc check`: the activity name, goal ids, rule ids), and the JSON Schemas, whose name
patterns tests/test_language.py holds equal to `NAME_PATTERN`. A name one of them accepts is
then a name for all of them: what the configuration accepts, the run time runs; what `check`
accepts, `decompile` writes as a script that compiles.

The facts come from the grammar where the grammar states them: `NAME_PATTERN` and
`NUMBER_PATTERN` are the regular expressions of the `NAME` and `NUMBER` terminals of
`grammar/condition.lark` (which the script grammar imports), read from the grammar file, so a
change of the grammar changes them. What the grammar leaves to lowering is stated here:
`ITEM_WORDS`, the words that, alone in brackets, are an item of the script syntax rather than
an activity name. This module is on the path of `scriptc lint`: it imports only `re` and
`scriptc.resources`, and reads one small file.

More of the language's facts (its keywords and tokens, for the editor's grammar and
completion) are meant to join these here, each as a constant with the test that holds its
other copies equal to it.
"""

from __future__ import annotations

import re

from scriptc.resources import grammar_path

__all__ = ["NAME_PATTERN", "NUMBER_PATTERN", "ITEM_WORDS", "is_name", "is_activity_name",
           "name_problem"]


def _terminal(grammar: str, terminal: str) -> str:
    """The regular expression of the terminal `terminal: /.../` in a grammar file."""
    text = grammar_path(grammar).read_text(encoding="utf-8")
    m = re.search(rf"^{terminal}\s*:\s*/(.*)/\s*$", text, re.MULTILINE)
    if m is None:  # a grammar that no longer states it: fail at import, not with a wrong rule
        raise RuntimeError(f"grammar/{grammar} has no terminal `{terminal}: /.../`")
    return m.group(1)


# A name: activity names, goal ids, labels, rule ids, function names, the names after `?`, `@`,
# `$` and `#` (thesis 4.3 and 4.4).
NAME_PATTERN = _terminal("condition.lark", "NAME")
# A number in the script syntax and in the number fields of the thesis JSON.
NUMBER_PATTERN = _terminal("condition.lark", "NUMBER")

_NAME = re.compile(NAME_PATTERN)

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
