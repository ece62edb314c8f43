"""The one door to lark: every name scriptc takes from lark, and every internal of lark it reads.

No other module imports lark (an import-linter contract holds this). Two kinds of things pass
through here:

- **lark's public API**, re-exported: `Lark` (built with the LALR parser and a custom lexer),
  `Tree` and `Token` (the parse trees the front end lowers, read by `data`, `children`, `type`
  and `start_pos`/`end_pos`), the errors `UnexpectedInput`, `UnexpectedToken`,
  `UnexpectedCharacters` and `UnexpectedEOF` (read by `token`, `expected`, `allowed`,
  `pos_in_stream`), `Lexer` (the base of custom lexers) and `Lark.terminals`.
- **lark's internals**, each read by one function or class below and nowhere else:
  the LALR parser inside a `Lark` (`lark.parser.parser.parser`: its `parse_table` and its
  tree-building `callbacks`) and the lexer instance (`lark.parser.lexer`); the parse table's
  `states`, `start_states` and `end_states`, its actions (`Shift`, or a rule with `expansion`
  and `origin.name`); a terminal's `pattern` (`PatternStr` or a regexp, `to_regexp()`,
  `max_width`, `value`) and `priority`; the custom lexer's interface 2
  (`__future_interface__`, `lex(lexer_state, parser_state)`, `LexerConf.terminals`, `ignore`
  and `callbacks`, the lexer state's `text` (a `TextSlice`, or the text itself before lark
  1.3), the parser state's `position`, `state_stack` and `parse_conf.parse_table`); the
  constructors of `UnexpectedToken` and `UnexpectedCharacters` with a parser state; a `Token`
  made without its constructor (`str.__new__` and its slots), and a `Tree` (`object.__new__`
  and its attributes `data`, `children`, `_meta`).

tests/test_larkshim.py names each of these internals in a test of its own, so that a lark
that changes one fails there, by name; `pyproject.toml` pins lark to the versions that pass it
(with tests/test_shapes.py, which holds the trees equal to lark's own).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, Literal, TypeAlias

from lark import Lark, Token, Tree
from lark.common import LexerConf
from lark.exceptions import (
    UnexpectedCharacters,
    UnexpectedEOF,
    UnexpectedInput,
    UnexpectedToken,
)
from lark.grammar import Rule
from lark.lexer import Lexer, LexerState, PatternStr, TerminalDef
from lark.parsers.lalr_analysis import Shift

if TYPE_CHECKING:  # names for the type checker, from lark's modules of the newest releases
    from lark.parsers.lalr_analysis import ParseTableBase
    from lark.parsers.lalr_parser_state import ParserState as ParserState
    from lark.utils import TextSlice  # lark 1.3 on; before, a lexer is handed the text itself

__all__ = [
    "Action",
    "Child",
    "CustomLexer",
    "LalrTable",
    "Lark",
    "LexerConf",
    "LexerState",
    "ParseTree",
    "TerminalDef",
    "Token",
    "Tree",
    "TreeCallback",
    "UnexpectedCharacters",
    "UnexpectedEOF",
    "UnexpectedInput",
    "UnexpectedToken",
    "accepted_terminals",
    "characters_offset",
    "in_lexer_order",
    "lexed_text",
    "lexer_configuration",
    "lexer_of",
    "state_stack",
    "terminal_literal",
    "terminal_regexp",
    "token_from_match",
    "tokens_from_match",
    "tree_code",
    "unexpected_characters",
    "unexpected_token",
]


# ---------------------------------------------------------------------------------------------
# Trees and tokens

# A tree as lark's parser builds it: rules' trees with `Token` leaves (lark's `ParseTree`,
# spelled here for the type checker alone, whatever lark release is installed).
ParseTree: TypeAlias = "Tree[Token]"

# A child of a `ParseTree`, read where the grammar says what it is: a `Token`, a `ParseTree`,
# or None (an optional part left out: the parsers are built with `maybe_placeholders`). lark
# types the children `Token | Tree[Token]` (no None); the front end reads each child by its
# place in its rule, so the boundary is `Any`, and the function a child is handed to says what
# it takes (`Token`, `ParseTree`).
Child: TypeAlias = Any

# lark's callback that builds the tree of a rule from the values of its children.
TreeCallback: TypeAlias = Callable[[list[Child]], Child]

_new_str = str.__new__


def token_from_match(m: re.Match[str], group: str, type_: str) -> Token:
    """The token of the terminal `type_` that group `group` of a match read: a lark `Token`
    without the cost of its keyword-argument constructor (its slots set directly; no line
    counting, positions are offsets, always set)."""
    value: str = m.group(group)
    token: Token = _new_str(Token, value)
    token.type = type_
    token.value = value
    token.start_pos, token.end_pos = m.span(group)
    token.line = token.column = token.end_line = token.end_column = None
    return token


def tokens_from_match(m: re.Match[str], steps: tuple[tuple[int, str], ...]) -> list[Token]:
    """The tokens that one match read, as `token_from_match` makes them: per step, the
    token of the terminal `type_` read by group number `group` (`steps`: (group, type_)
    pairs). One call for a whole item: a large script has hundreds of thousands of tokens."""
    text = m.string
    tokens: list[Token] = []
    for group, type_ in steps:
        start, end = m.span(group)
        value = text[start:end]
        token: Token = _new_str(Token, value)
        token.type = type_
        token.value = value
        token.start_pos = start
        token.end_pos = end
        token.line = token.column = token.end_line = token.end_column = None
        tokens.append(token)
    return tokens


def tree_code(var: str, data: str, children: str) -> str:
    """A Python statement, for code that `exec` runs with `Tree` and `new_object`
    (`object.__new__`) in its namespace, that makes `var` the tree `Tree(data, children)`
    without its constructor (its attributes `data`, `children` and `_meta` set directly: a
    large script's items make a hundred thousand trees)."""
    return (f"{var} = new_object(Tree); {var}.data = {data}; {var}.children = {children}; "
            f"{var}._meta = None")


# ---------------------------------------------------------------------------------------------
# Terminals (the `TerminalDef`s of `Lark.terminals` and of a lexer's configuration)


def terminal_literal(terminal: TerminalDef) -> str | None:
    """The text of a terminal written as a string in the grammar (`"goal"`), else None."""
    pattern = terminal.pattern
    return pattern.value if isinstance(pattern, PatternStr) else None


def terminal_regexp(terminal: TerminalDef) -> str:
    """The terminal's pattern as a Python regexp."""
    return terminal.pattern.to_regexp()


def in_lexer_order(terminals: Iterable[TerminalDef]) -> list[TerminalDef]:
    """The terminals in the order lark's lexer tries them: by priority, then the longest
    possible match, then the longest literal, then the name."""
    return sorted(terminals, key=lambda t: (-t.priority, -t.pattern.max_width,
                                            -len(t.pattern.value), t.name))


# ---------------------------------------------------------------------------------------------
# Custom lexers (lark's interface 2)


class CustomLexer(Lexer):
    """The base of a lexer that lark's LALR parser drives: `lex(lexer_state, parser_state)`
    yields tokens, reading the parser's state to know which terminals it accepts."""

    __future_interface__ = 2


def lexer_configuration(lexer_conf: LexerConf) -> tuple[list[TerminalDef], frozenset[str],
                                                     dict[str, Callable[[Token], Token]]]:
    """What lark hands a custom lexer: the grammar's terminals, the names of the ignored ones
    and the callbacks by terminal name."""
    return list(lexer_conf.terminals), frozenset(lexer_conf.ignore), dict(lexer_conf.callbacks)


def lexed_text(lexer_state: LexerState) -> tuple[str, int, int]:
    """The text a lexer reads, with the start and end of the part to read."""
    text: TextSlice[str] | str = lexer_state.text  # (str: lark before 1.3, the text itself)
    if isinstance(text, str):
        return text, 0, len(text)
    return text.text, text.start, text.end


def state_stack(parser_state: ParserState[int]) -> list[int]:
    """The parser's stack of states (the last is the current one); it grows and shrinks as
    the parser reads the tokens the lexer yields."""
    return parser_state.state_stack


def accepted_terminals(parser_state: ParserState[int]) -> frozenset[str]:
    """The names of the terminals (and non-terminals) the parser's current state accepts."""
    return frozenset(parser_state.parse_conf.parse_table.states[parser_state.position])


def unexpected_token(token: Token, accepts: Iterable[str], parser_state: ParserState[int],
                     last: Token | None) -> UnexpectedToken:
    """The error lark's lexer raises for a known token where the parser does not accept it."""
    return UnexpectedToken(  # type: ignore[no-untyped-call]  # lark's __init__ is not annotated
        token, set(accepts), state=parser_state, token_history=[last])


def unexpected_characters(text: str, pos: int, accepts: Iterable[str],
                          parser_state: ParserState[int],
                          last: Token | None) -> UnexpectedCharacters:
    """The error lark's lexer raises for text no terminal matches (no line counting)."""
    return UnexpectedCharacters(  # type: ignore[no-untyped-call]  # lark's __init__: no types
        text, pos, 0, 0, allowed=set(accepts), state=parser_state, token_history=[last])


def characters_offset(error: UnexpectedCharacters) -> int:
    """Where the text that no terminal matches starts."""
    # lark declares `pos_in_stream = None` on the base class, which its type checker reads;
    # an `UnexpectedCharacters` sets it to the offset.
    offset: int = error.pos_in_stream  # type: ignore[assignment]  # declared None, see above
    return offset


# ---------------------------------------------------------------------------------------------
# The LALR parser inside a `Lark`


def lexer_of(lark: Lark) -> Lexer:
    """The lexer instance a `Lark` built (for `lexer=` a class: an instance of it)."""
    lexer: Lexer = lark.parser.lexer
    return lexer


# An action of the parse table, as `LalrTable.actions` gives it: a shift
# `(next state, 0, None, None)` or a reduction `(None, the rule's length, lark's callback that
# builds its tree, the name of the rule's non-terminal)`. `action[0] is not None` tells them
# apart (and narrows the type).
Action: TypeAlias = (
    "tuple[int, Literal[0], None, None] | tuple[None, int, TreeCallback, str]"
)


class LalrTable:
    """lark's LALR(1) parse table of a `Lark` and its tree-building callbacks, read as plain
    data: states are numbers, each with its actions by terminal (or non-terminal) name."""

    __slots__ = ("_callbacks", "_table")

    def __init__(self, lark: Lark) -> None:
        parser = lark.parser.parser.parser  # the LALR parser's core: its table and callbacks
        self._table: ParseTableBase[int] = parser.parse_table
        self._callbacks: dict[Rule, TreeCallback] = parser.callbacks

    def start_state(self, start: str) -> int:
        return self._table.start_states[start]

    def end_state(self, start: str) -> int:
        return self._table.end_states[start]

    def accepts(self, state: int) -> frozenset[str]:
        """The names state `state` has an action for."""
        return frozenset(self._table.states[state])

    def actions(self, state: int) -> dict[str, Action]:
        """The actions of `state` by name (see `Action`)."""
        return {
            name: (arg, 0, None, None) if action is Shift
            else (None, len(arg.expansion), self._callbacks[arg], arg.origin.name)
            for name, (action, arg) in self._table.states[state].items()
        }
