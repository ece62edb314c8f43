"""The item parser: lark's LALR(1) tables for a grammar, driven here, with a cache of the shapes
of items.

A script is a long list of items of few shapes: hundreds of `[b#..#blk_inst: MV("..") LD("..")
AO("..")]` that differ only in their labels, numbers and strings. lark's parse loop spends
about 3 us per token on them (bench/bench_frontend.py); this parser reads an item whose shape
it has seen with one regex match per token and builds lark's own tree from a template.

- **The table parse** (`_table_parse`): contextual lexing with the scanners of
  `ContextualFastLexer` (in each parser state only the terminals that state accepts) and the
  LALR loop over lark's own parse table, reducing through lark's own tree-building callbacks:
  the tree is exactly the one lark builds. It also returns, for every token, its type and the
  scanner that read it.
- **The shape trie.** A node stands for a sequence of token types (a prefix of an item's
  shape). The parser state after a prefix depends on the types alone (LALR actions read the
  state and the terminal's type), so each node holds the scanner of that state: walking an item
  down the trie lexes it exactly as the contextual lexer does, without the parse table. Where
  an item ended, the node holds its tree's template: lark's callbacks shape the tree from the
  rules and the types of the children, never their text, so every item of that shape has the
  same tree with its own tokens at the leaves. The template is compiled into a function (Python
  code building the `Tree`) the second time the shape is met.
- **Errors are lark's.** Anything the trie and the table parse do not accept is handed to lark
  itself, which raises the `UnexpectedInput` that `parser.describe` words: messages are those of
  lark's parser, exactly. Beside `parse`, the parser gives lark's `terminals` (which
  `describe` reads): it is a `parser.ItemParser`.

The trie is bounded (`MAX_NODES`): past it, it is dropped and starts again; items of more than
`MAX_SHAPE_TOKENS` tokens are parsed and not recorded. tests/
test_shapes.py checks that trees are lark's, for generated and hand-written items.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Collection
from typing import Any, TypeAlias

from scriptc.syntax.larkshim import (
    Action,
    Child,
    LalrTable,
    Lark,
    ParseTree,
    TerminalDef,
    Token,
    Tree,
    lexer_of,
    token_from_match,
    tokens_from_match,
    tree_code,
)
from scriptc.syntax.lexer import ContextualFastLexer, Scanner

MAX_NODES = 50_000
MAX_SHAPE_TOKENS = 2_000  # longer items are parsed, never recorded
# Items of a shape before it gets its own regex: compiling it takes 5-10 ms (Python's regex
# compiler) and saves about 10 us per item; frequent shapes number in the thousands in a
# repository of activities.
HOT = 256

# Python code of a function and the constants it reads (`C`), see `_template`.
_Code: TypeAlias = tuple[str, list[object]]
# A function that `exec` built from generated code (`_compile`): the code says what it takes
# and returns, the attribute it is stored in says it to the type checker.
_Generated: TypeAlias = Callable[..., Any]
# One token of an item read by the table parse: its match, the match's group (the terminal the
# scanner matched), its type (the keyword, for a name that is one) and the scanner that read it.
_Step: TypeAlias = tuple[re.Match[str], str, str, Scanner]


class _Node:
    __slots__ = ("build", "children", "hot", "match", "next", "retype", "seen", "steps",
                 "template")

    def __init__(self, scanner: Scanner) -> None:
        self.match = scanner.regex.match
        self.retype = scanner.retype
        self.children: dict[str, _Node] = {}
        # Where an item ended (the node is a shape):
        # the tree of its first item and where each of its tokens starts (`_template`)
        self.template: tuple[ParseTree, list[int]] | None = None
        # the compiled template, from the second item of this shape on
        self.build: Callable[[list[re.Match[str]]], ParseTree] | None = None
        self.steps: list[tuple[str, str, Scanner]] = []  # (group, type, scanner) per token
        self.seen = 0  # items of this shape built by `build`
        self.hot: _Hot | None = None  # the shape's own regex, from HOT items on
        self.next: _Node | None = None  # the shape of the item that followed the last one


class _Hot:
    """A frequent shape's regex (one match reads the whole item), the test of the keywords'
    values it cannot express, and the template over that one match."""

    __slots__ = ("build", "check", "match")

    def __init__(self, match: Callable[[str], re.Match[str] | None],
                 check: Callable[[re.Match[str]], bool],
                 build: Callable[[re.Match[str]], ParseTree]) -> None:
        self.match, self.check, self.build = match, check, build


class ShapeParser:
    """`parse(text, start)` as lark's, for the one start symbol `start`."""

    def __init__(self, lark: Lark, start: str) -> None:
        self._lark = lark
        self.start = start
        self._table = LalrTable(lark)
        lexer = lexer_of(lark)
        if not isinstance(lexer, ContextualFastLexer):  # its scanners are what the trie holds
            raise TypeError("the shape parser reads a Lark built with lexer=ContextualFastLexer")
        self._lexer = lexer
        self._ignore = self._lexer.ignore
        self._ws = re.compile(self._lexer.skip or r"\s*")
        self._skipped = {"WS"} if self._lexer.skip else set()  # the terminal `skip` reads
        self._start_state = self._table.start_state(start)
        self._end_state = self._table.end_state(start)
        self._actions: dict[int, dict[str, Action]] = {}
        self._reset()

    @property
    def terminals(self) -> Collection[TerminalDef]:
        """lark's terminals of the grammar (`parser.describe` words an error with them)."""
        return self._lark.terminals

    def _reset(self) -> None:
        self._root = _Node(self._scanner(self._start_state))
        self._nodes = 1
        self._last: _Node | None = None  # the shape of the item parsed last

    def _scanner(self, state: int) -> Scanner:
        return self._lexer.scanner_for(state, self._table.accepts)

    def parse(self, text: str, start: str | None = None) -> ParseTree:
        if start is not None and start != self.start:
            return self._lark.parse(text, start=start)
        last = self._last
        guess = last.next if last is not None else None
        if guess is not None and guess.hot is not None:
            # Items come in patterns (an instruction block, a jump, ...): try the shape that
            # followed the last one, in one match.
            hot = guess.hot
            m = hot.match(text)
            if m is not None and hot.check(m):
                self._last = guess
                return hot.build(m)
        node = self._root
        pos = 0
        matches: list[re.Match[str]] = []
        append = matches.append
        while True:
            m = node.match(text, pos)
            if m is None:
                break
            group = m.lastgroup
            assert group is not None  # a scanner's alternatives are named groups: one matched
            retype = node.retype.get(group)
            type_ = retype.get(m.group(group), group) if retype is not None else group
            append(m)
            pos = m.end()
            child = node.children.get(type_)
            if child is None:
                return self._new_shape(text)
            node = child
        build = node.build
        if build is None or (pos != len(text) and self._ws.fullmatch(text, pos) is None):
            return self._new_shape(text)
        if last is not None:
            last.next = node
        self._last = node
        node.seen += 1
        if node.seen == HOT:
            node.hot = self._hot(node)
        return build(matches)

    # -- shapes not seen yet ----------------------------------------------------------------

    def _new_shape(self, text: str) -> ParseTree:
        parsed = self._table_parse(text)
        if parsed is None:
            return self._lark.parse(text, start=self.start)  # raises lark's error
        tree, path, last = parsed
        if len(path) > MAX_SHAPE_TOKENS:
            return tree  # a shape this long is met once: recording it would only cost
        if self._nodes + len(path) > MAX_NODES:
            self._reset()
        node = self._root
        for i, (_m, _group, type_, _scanner) in enumerate(path):
            child = node.children.get(type_)
            if child is None:
                # (after an ignored token, a comment, the state and so the scanner are the
                # same; the node is another one: the template counts the comment's match)
                child = node.children[type_] = _Node(path[i + 1][3] if i + 1 < len(path)
                                                     else last)
                self._nodes += 1
            node = child
        if node.template is None:
            node.template = (tree, [m.start(group) for m, group, _, _ in path])
            node.steps = [(group, type_, scanner) for _, group, type_, scanner in path]
        elif node.build is None:
            node.build = _compile(*_template(
                *node.template, lambda i, type_, constant:
                f"T(ms[{i}], {constant(node.steps[i][0])}, {constant(type_)})"))
        self._last = None
        return tree

    def _hot(self, node: _Node) -> _Hot:
        """The regex of a shape: per token, the scanner of its state (the whole scanner, in an
        atomic group: the same first match) with the token's own alternative captured, and a
        conditional that fails when another alternative matched; then only blanks. It matches
        exactly the items the trie walk reads as this shape, but for the keywords: which of a
        name's values are keywords is checked on the match (`check`)."""
        assert node.template is not None  # (a shape is hot after HOT items built from it)
        parts: list[str] = []
        checks: list[str] = []
        constants: list[object] = []
        for i, (group, type_, scanner) in enumerate(node.steps):
            # The alternatives after the token's own are never tried when it matches: only
            # those before it can take its place. Whitespace cannot either: the skip before
            # took all of it (it matters only after every other alternative failed).
            before: list[str] = []
            own = ""
            for name, regexp in scanner.alternatives:
                if name == group:
                    own = f"(?P<s{i}>{regexp})"
                    break
                if name not in self._skipped:
                    before.append(f"(?:{regexp})|")
            if before:
                parts.append(f"(?>{scanner.skip}(?:{''.join(before)}{own}))(?(s{i})|(?!))")
            else:
                parts.append(f"(?>{scanner.skip}{own})")
            keywords = scanner.retype.get(group)
            if keywords is not None:
                constants.append(keywords)
                k = len(constants) - 1
                if type_ == group:  # a name: none of the keywords
                    checks.append(f"m.group('s{i}') not in C[{k}]")
                else:  # a keyword: that one
                    checks.append(f"C[{k}].get(m.group('s{i}')) == {type_!r}")
        parts.append(f"{self._lexer.skip}\\Z")
        check = _compile(f"def build(m, C=C):\n    return {' and '.join(checks) or 'True'}\n",
                         constants)
        regex = re.compile("".join(parts))
        # The tokens the tree holds (lark leaves punctuation out), read from the one match at
        # once (`tokens_from_match`): (the group of token i, its type) in the tree's order.
        steps: list[tuple[int, str]] = []

        def token(i: int, type_: str, _constant: Callable[[object], str]) -> str:
            steps.append((regex.groupindex[f"s{i}"], type_))
            return f"ts[{len(steps) - 1}]"

        code, constants = _template(*node.template, token, "ts = TS(ms, C[0])", None)
        constants[0] = tuple(steps)
        return _Hot(regex.match, check, _compile(code, constants))

    def _state_actions(self, state: int) -> dict[str, Action]:
        """The parse table's row of `state` (see `larkshim.Action`)."""
        row = self._actions.get(state)
        if row is None:
            row = self._actions[state] = self._table.actions(state)
        return row

    def _table_parse(self, text: str) -> tuple[ParseTree, list[_Step], Scanner] | None:
        """lark's LALR loop over its own table: (tree, the steps of the tokens, the scanner
        of the last state), or None where lark would raise."""
        actions = self._state_actions
        ignore = self._ignore
        states = [self._start_state]
        values: list[Child] = []
        path: list[_Step] = []
        pos, end = 0, len(text)
        token: Token | None
        while True:
            scanner = self._scanner(states[-1])
            m = scanner.regex.match(text, pos)
            if m is None:
                if pos < end and self._ws.fullmatch(text, pos) is None:
                    return None
                type_, token = "$END", None
            else:
                group = m.lastgroup
                assert group is not None  # a scanner's alternatives are named groups
                retype = scanner.retype.get(group)
                type_ = retype.get(m.group(group), group) if retype is not None else group
                path.append((m, group, type_, scanner))
                pos = m.end()
                if type_ in ignore:
                    continue
                token = token_from_match(m, group, type_)
            row = actions(states[-1])
            while True:
                action = row.get(type_)
                if action is None:
                    return None
                if action[0] is not None:  # a shift
                    states.append(action[0])
                    values.append(token)
                    break
                _, size, callback, origin = action
                children = values[-size:] if size else []
                if size:
                    del states[-size:], values[-size:]
                values.append(callback(children))
                state = actions(states[-1])[origin][0]
                assert state is not None  # the goto of a reduction is a shift (lark asserts it)
                states.append(state)
                if token is None and state == self._end_state:
                    return values[-1], path, scanner
                row = actions(state)


def _compile(code: str, constants: list[object]) -> _Generated:
    """The function `build` that `code` defines, reading `constants` as `C`."""
    namespace: dict[str, object] = {"T": token_from_match, "TS": tokens_from_match, "Tree": Tree,
                                    "new_object": object.__new__, "C": constants}
    exec(compile(code, "<item shape>", "exec"), namespace)
    build = namespace["build"]
    assert callable(build)
    return build


def _template(tree: ParseTree, starts: list[int],
              token_of: Callable[[int, str, Callable[[object], str]], str],
              prelude: str = "", *first: object) -> _Code:
    """Python code of a function `build(ms)` that builds `tree` again from the match or
    matches `ms` of an item of the same shape, and the constants it reads (`first`, then rule
    names and token types, as lark made them). Token i starts at `starts[i]` in the item; its
    code is `token_of(i, its type, constant)` (`constant(value)`: the code reading a
    constant); `prelude` is a line run first. Each tree is a statement of its own
    (`larkshim.tree_code`), children first."""
    index = {start: i for i, start in enumerate(starts)}
    constants: list[object] = list(first)
    lines = [prelude] if prelude else []

    def constant(value: object) -> str:
        constants.append(value)
        return f"C[{len(constants) - 1}]"

    def code(node: Token | ParseTree | None) -> str:
        if node is None:
            return "None"
        if isinstance(node, Token):
            assert node.start_pos is not None  # (the table parse's tokens have their offsets)
            return token_of(index[node.start_pos], node.type, constant)
        children = ", ".join(code(child) for child in node.children)
        var = f"t{len(lines)}"
        lines.append(tree_code(var, constant(node.data), f"[{children}]"))
        return var

    result = code(tree)
    body = "".join(f"    {line}\n" for line in lines)
    code_text = (f"def build(ms, T=T, TS=TS, Tree=Tree, new_object=new_object, C=C):\n{body}"
                 f"    return {result}\n")
    return code_text, constants
