"""A contextual lexer for lark's LALR parser, built from the grammar's own terminals.

lark's contextual lexer spends most of a parse counting lines and columns for every token;
scriptc computes positions from offsets only when it shows them, so this lexer skips that work
(about twice as fast on large scripts, see bench/bench_compile.py). It keeps lark's semantics:
in each parser state only the terminals that state accepts are tried, in lark's order, and a
keyword that a name pattern also matches (`goal`, `b`, `TRUE`) is recognised only where the
parser accepts the keyword, so labels such as `b#goal#` remain names.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, NoReturn

from scriptc.syntax.larkshim import (
    CustomLexer,
    LexerConf,
    LexerState,
    TerminalDef,
    Token,
    accepted_terminals,
    in_lexer_order,
    lexed_text,
    lexer_configuration,
    state_stack,
    terminal_literal,
    terminal_regexp,
    token_from_match,
    unexpected_characters,
    unexpected_token,
)

if TYPE_CHECKING:
    from scriptc.syntax.larkshim import ParserState


class Scanner:
    """The terminals of a parser state in one regex (`regex`, a named group per terminal, in
    lark's order), and the keywords a name pattern also matches (`retype`: by the name
    terminal, the keyword's text -> its terminal)."""

    __slots__ = ("alternatives", "ignore", "regex", "retype", "skip")

    def __init__(self, terminals: Sequence[TerminalDef], ignore: frozenset[str],
                 skip: str = "") -> None:
        regexps = [t for t in terminals if terminal_literal(t) is None]
        kept: list[TerminalDef] = []
        self.retype: dict[str, dict[str, str]] = {}
        for t in terminals:
            literal = terminal_literal(t)
            if literal is not None:
                owner = next((r for r in regexps if re.fullmatch(terminal_regexp(r), literal)),
                             None)
                if owner is not None:
                    # A keyword that the name pattern also matches: retype after matching.
                    self.retype.setdefault(owner.name, {})[literal] = t.name
                    continue
            kept.append(t)
        # Whitespace (`skip`) is consumed in the same match as the token that follows it.
        self.alternatives = [(t.name, terminal_regexp(t))
                             for t in in_lexer_order(kept)]  # in match order
        alternatives = "|".join(f"(?P<{name}>{regexp})" for name, regexp in self.alternatives)
        self.regex = re.compile(f"{skip}(?:{alternatives})")
        self.ignore = ignore
        self.skip = skip


class ContextualFastLexer(CustomLexer):
    """A custom lexer of lark's: `lex(lexer_state, parser_state)` (the parser's state tells
    which terminals it accepts)."""

    def __init__(self, lexer_conf: LexerConf) -> None:
        self.terminals, self.ignore, self.callbacks = lexer_configuration(lexer_conf)
        self.by_name = {t.name: t for t in self.terminals}
        # The ignored whitespace terminal is folded into every token's match (see Scanner).
        self.skip = "".join(
            f"(?:{terminal_regexp(self.by_name[n])})?" for n in self.ignore if n == "WS"
        )
        self._by_state: dict[int, Scanner] = {}
        self._by_accepts: dict[frozenset[str], Scanner] = {}
        self._root: Scanner | None = None

    def scanner_for(self, position: int,
                    accepts: Callable[[int], Iterable[str]]) -> Scanner:
        """The scanner of parser state `position`, whose accepted names `accepts(position)`
        gives: the terminals that state accepts (built on first use, shared by the states
        that accept the same terminals)."""
        scanner = self._by_state.get(position)
        if scanner is None:
            accepted = frozenset(accepts(position))
            scanner = self._by_accepts.get(accepted)
            if scanner is None:
                names = accepted | self.ignore
                scanner = Scanner(
                    [t for t in self.terminals if t.name in names], self.ignore, self.skip
                )
                self._by_accepts[accepted] = scanner
            self._by_state[position] = scanner
        return scanner

    def _root_scanner(self) -> Scanner:
        if self._root is None:
            self._root = Scanner(self.terminals, self.ignore, self.skip)
        return self._root

    def lex(self, lexer_state: LexerState,
            parser_state: ParserState[int]) -> Iterator[Token]:
        text, pos, end = lexed_text(lexer_state)
        ignore = self.ignore
        callbacks = self.callbacks
        by_state = self._by_state
        states = state_stack(parser_state)
        ws = re.compile(self.skip) if self.skip else None
        last: Token | None = None  # the last token yielded, for the errors' history
        while pos < end:
            position = states[-1]
            scanner = by_state.get(position)
            if scanner is None:
                scanner = self.scanner_for(position, lambda _p: accepted_terminals(parser_state))
            m = scanner.regex.match(text, pos, end)
            if m is None:
                if ws is not None:
                    blank = ws.match(text, pos, end)
                    assert blank is not None  # an optional group: it always matches
                    pos = blank.end()
                    if pos >= end:
                        break
                self._fail(text, pos, end, parser_state, last)
            group = m.lastgroup
            assert group is not None  # one of the alternatives, each a named group, matched
            type_ = group
            retype = scanner.retype.get(group)
            if retype is not None:
                type_ = retype.get(m.group(group), group)
            pos = m.end()
            if type_ in ignore:
                if type_ in callbacks:
                    callbacks[type_](token_from_match(m, group, type_))
                continue
            last = token_from_match(m, group, type_)
            yield last

    def _fail(self, text: str, pos: int, end: int, parser_state: ParserState[int],
              last: Token | None) -> NoReturn:
        """No terminal of this state matches: report a known token in the wrong place as
        UnexpectedToken (as lark does) and anything else as UnexpectedCharacters."""
        accepts = accepted_terminals(parser_state)
        root = self._root_scanner()
        m = root.regex.match(text, pos, end)
        if (m is not None and m.lastgroup is not None and m.lastgroup not in self.ignore
                and m.end() > pos):
            type_ = m.lastgroup
            type_ = root.retype.get(type_, {}).get(m.group(), type_)
            token = Token(type_, m.group(), pos, end_pos=m.end())
            raise unexpected_token(token, accepts, parser_state, last)
        raise unexpected_characters(text, pos, accepts, parser_state, last)
