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

from lark.exceptions import UnexpectedCharacters, UnexpectedToken
from lark.lexer import Lexer, PatternStr, Token


_new_str = str.__new__


def match_token(m: re.Match, group: str, type_: str) -> Token:
    """The token of the terminal `type_` that group `group` of a scanner's match read: a lark
    Token without the cost of its keyword-argument constructor."""
    value = m.group(group)
    token = _new_str(Token, value)
    token.type = type_
    token.value = value
    token.start_pos, token.end_pos = m.span(group)
    token.line = token.column = token.end_line = token.end_column = None
    return token


class _Scanner:
    __slots__ = ("regex", "retype", "ignore", "skip", "alternatives")

    def __init__(self, terminals, ignore: frozenset[str], skip: str = "") -> None:
        regexps = [t for t in terminals if not isinstance(t.pattern, PatternStr)]
        kept = []
        self.retype: dict[str, dict[str, str]] = {}
        for t in terminals:
            if isinstance(t.pattern, PatternStr):
                owner = next(
                    (r for r in regexps if re.fullmatch(r.pattern.to_regexp(), t.pattern.value)),
                    None,
                )
                if owner is not None:
                    # A keyword that the name pattern also matches: retype after matching.
                    self.retype.setdefault(owner.name, {})[t.pattern.value] = t.name
                    continue
            kept.append(t)
        kept.sort(key=lambda t: (-t.priority, -t.pattern.max_width, -len(t.pattern.value), t.name))
        # Whitespace (`skip`) is consumed in the same match as the token that follows it.
        self.alternatives = [(t.name, t.pattern.to_regexp()) for t in kept]  # in match order
        alternatives = "|".join(f"(?P<{name}>{regexp})" for name, regexp in self.alternatives)
        self.regex = re.compile(f"{skip}(?:{alternatives})")
        self.ignore = ignore
        self.skip = skip


class ContextualFastLexer(Lexer):
    """Interface 2 of lark's custom lexers: `lex(lexer_state, parser_state)`."""

    __future_interface__ = 2

    def __init__(self, lexer_conf) -> None:
        self.terminals = list(lexer_conf.terminals)
        self.by_name = {t.name: t for t in self.terminals}
        self.ignore = frozenset(lexer_conf.ignore)
        # The ignored whitespace terminal is folded into every token's match (see _Scanner).
        self.skip = "".join(
            f"(?:{self.by_name[n].pattern.to_regexp()})?" for n in self.ignore if n == "WS"
        )
        self.callbacks = dict(lexer_conf.callbacks)
        self._by_state: dict[int, _Scanner] = {}
        self._by_accepts: dict[frozenset[str], _Scanner] = {}
        self._root: _Scanner | None = None

    def _scanner(self, parser_state) -> _Scanner:
        return self.scanner_for(parser_state.position, parser_state.parse_conf.parse_table)

    def scanner_for(self, position: int, parse_table) -> _Scanner:
        """The scanner of parser state `position`: the terminals that state accepts (built on
        first use, shared by the states that accept the same terminals)."""
        scanner = self._by_state.get(position)
        if scanner is None:
            accepts = frozenset(parse_table.states[position])
            scanner = self._by_accepts.get(accepts)
            if scanner is None:
                names = accepts | self.ignore
                scanner = _Scanner(
                    [t for t in self.terminals if t.name in names], self.ignore, self.skip
                )
                self._by_accepts[accepts] = scanner
            self._by_state[position] = scanner
        return scanner

    def _root_scanner(self) -> _Scanner:
        if self._root is None:
            self._root = _Scanner(self.terminals, self.ignore, self.skip)
        return self._root

    def lex(self, lexer_state, parser_state):
        text_slice = lexer_state.text
        text, pos, end = text_slice.text, text_slice.start, text_slice.end
        ignore = self.ignore
        callbacks = self.callbacks
        by_state = self._by_state
        state_stack = parser_state.state_stack
        ws = re.compile(self.skip) if self.skip else None
        while pos < end:
            scanner = by_state.get(state_stack[-1]) or self._scanner(parser_state)
            m = scanner.regex.match(text, pos, end)
            if m is None:
                if ws is not None:
                    pos = ws.match(text, pos, end).end()
                    if pos >= end:
                        break
                self._fail(text, pos, end, parser_state, lexer_state)
            group = type_ = m.lastgroup
            retype = scanner.retype.get(group)
            if retype is not None:
                type_ = retype.get(m.group(group), group)
            pos = m.end()
            if type_ in ignore:
                if type_ in callbacks:
                    callbacks[type_](match_token(m, group, type_))
                continue
            token = match_token(m, group, type_)
            lexer_state.last_token = token
            yield token

    def _fail(self, text, pos, end, parser_state, lexer_state):
        """No terminal of this state matches: report a known token in the wrong place as
        UnexpectedToken (as lark does) and anything else as UnexpectedCharacters."""
        accepts = set(parser_state.parse_conf.parse_table.states[parser_state.position])
        root = self._root_scanner()
        m = root.regex.match(text, pos, end)
        if m is not None and m.lastgroup not in self.ignore and m.end() > pos:
            type_ = m.lastgroup
            type_ = root.retype.get(type_, {}).get(m.group(), type_)
            token = Token(type_, m.group(), pos, end_pos=m.end())
            raise UnexpectedToken(token, accepts, state=parser_state,
                                  token_history=[lexer_state.last_token])
        raise UnexpectedCharacters(text, pos, 0, 0, allowed=accepts, state=parser_state,
                                   token_history=[lexer_state.last_token])
