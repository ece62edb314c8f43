"""Each internal of lark that scriptc relies on, named by a test of its own (syntax/larkshim.py is
the only module that reads them). A lark release that changes one fails here, under the
internal's name, before anything else does; `pyproject.toml` pins lark to the versions that pass
this file and tests/test_shapes.py."""

from __future__ import annotations

import re
from typing import ClassVar

import pytest

from scriptc.syntax import larkshim
from scriptc.syntax.larkshim import (
    CustomLexer,
    LalrTable,
    Lark,
    Token,
    Tree,
    UnexpectedCharacters,
    UnexpectedToken,
    accepted_terminals,
    in_lexer_order,
    lexed_text,
    lexer_configuration,
    lexer_of,
    state_stack,
    terminal_literal,
    terminal_regexp,
    token_from_match,
    tokens_from_match,
    tree_code,
)
from scriptc.syntax.lexer import ContextualFastLexer
from scriptc.syntax.parser import script_lark

ITEM = '[b#start#blk_inst: MV("1, 0, 0, 0, 100") LD() AO()]'


@pytest.fixture(scope="module")
def lark() -> Lark:
    return script_lark()


@pytest.fixture(scope="module")
def table(lark: Lark) -> LalrTable:
    return LalrTable(lark)


def test_lark_parser_parser_parser_holds_the_parse_table_and_callbacks(table: LalrTable) -> None:
    """`Lark.parser.parser.parser` (the LALR parser's core): `parse_table` and `callbacks`."""
    assert isinstance(table.start_state("item"), int)
    assert isinstance(table.end_state("item"), int)


def test_parse_table_states_start_states_and_end_states(lark: Lark, table: LalrTable) -> None:
    """`ParseTable.states` (actions by name, per state), `start_states`, `end_states`."""
    start = table.start_state("item")
    assert "LSQB" in table.accepts(start)  # every item opens with `[`
    assert table.end_state("item") != start
    with pytest.raises(KeyError):
        table.start_state("no_such_start")


def test_shift_and_reduce_actions(table: LalrTable) -> None:
    """An action is `(Shift, next state)` or `(Reduce, rule)`, the rule with `expansion` (its
    length) and `origin.name` (its non-terminal); `callbacks` has one per rule."""
    start = table.start_state("item")
    shift_to, size, callback, origin = table.actions(start)["LSQB"]
    assert isinstance(shift_to, int) and (size, callback, origin) == (0, None, None)
    reductions = set()
    seen, todo = {start}, [start]
    while todo:
        for to, size, callback, origin in table.actions(todo.pop()).values():
            if to is None:
                assert size >= 0 and callable(callback) and isinstance(origin, str)
                reductions.add(origin)
            elif to not in seen:
                seen.add(to)
                todo.append(to)
    assert {"name_item", "goal_item", "block", "inst_body", "track"} <= reductions


def test_callbacks_build_lark_trees(lark: Lark, table: LalrTable) -> None:
    """The tree-building callbacks take the children and give lark's `Tree` (what the shape
    parser's table parse calls): the parse of an item by the table equals lark's."""
    from scriptc.syntax.shapes import ShapeParser

    parsed = ShapeParser(lark, "item")._table_parse(ITEM)
    assert parsed is not None and parsed[0] == lark.parse(ITEM, start="item")
    assert isinstance(parsed[0], Tree) and parsed[0].data == "block"


def test_lark_parser_lexer_is_the_custom_lexer_instance(lark: Lark) -> None:
    """`Lark.parser.lexer`: an instance of the class given as `lexer=`."""
    assert isinstance(lexer_of(lark), ContextualFastLexer)


class Recording(ContextualFastLexer):
    """The custom lexer, keeping what lark hands it: its configuration, and per `lex` call the
    text, the parser's stack of states and what the current state accepts."""

    confs: ClassVar[list] = []
    calls: ClassVar[list] = []

    def __init__(self, lexer_conf) -> None:
        Recording.confs.append(lexer_conf)
        super().__init__(lexer_conf)

    def lex(self, lexer_state, parser_state):
        Recording.calls.append((lexed_text(lexer_state), list(state_stack(parser_state)),
                                accepted_terminals(parser_state)))
        yield from super().lex(lexer_state, parser_state)


@pytest.fixture(scope="module")
def recording() -> Lark:
    from scriptc.resources import grammar_path

    path = grammar_path("script.lark")
    return Lark(path.read_text(encoding="utf-8"), parser="lalr", lexer=Recording, start=["item"],
                maybe_placeholders=True, import_paths=[str(path.parent)])


def test_lexer_conf_terminals_ignore_and_callbacks(recording: Lark) -> None:
    """`LexerConf.terminals` (`TerminalDef`s: `name`, `pattern`, `priority`), `ignore`,
    `callbacks`, as lark hands a custom lexer its configuration."""
    terminals, ignore, callbacks = lexer_configuration(Recording.confs[-1])
    assert {"NAME", "NUMBER", "STRING", "LSQB"} <= {t.name for t in terminals}
    assert {"WS", "COMMENT"} <= ignore and isinstance(callbacks, dict)


def test_terminal_patterns_literal_regexp_priority_and_width(lark: Lark) -> None:
    """`TerminalDef.pattern`: `PatternStr` with `value` for literals, `to_regexp()`,
    `max_width`; `priority`: the order lark's lexer tries them in."""
    by_name = {t.name: t for t in lark.terminals}
    assert terminal_literal(by_name["LSQB"]) == "["
    assert terminal_literal(by_name["NAME"]) is None
    assert re.fullmatch(terminal_regexp(by_name["NAME"]), "blink_2")
    assert re.fullmatch(terminal_regexp(by_name["LSQB"]), "[")
    ordered = [t.name for t in in_lexer_order(lark.terminals)]
    # a longer literal is tried before its prefix (`blk_sensor` before `blk_sens`)
    assert ordered.index("SENSOR") < ordered.index("SENS")


def test_custom_lexer_interface_2_reads_the_parser_state(recording: Lark) -> None:
    """`__future_interface__ = 2`: lark calls `lex(lexer_state, parser_state)`; the lexer state's
    `text` (a `TextSlice` or the text), the parser state's `state_stack`, `position` and
    `parse_conf.parse_table.states`."""
    assert issubclass(Recording, CustomLexer)
    Recording.calls.clear()
    assert recording.parse(ITEM, start="item") == script_lark().parse(ITEM, start="item")
    (text, start, end), stack, accepts = Recording.calls[0]
    assert (text, start, end) == (ITEM, 0, len(ITEM))
    assert len(stack) == 1 and isinstance(stack[0], int) and "LSQB" in accepts


def test_lexer_errors_made_with_a_parser_state(lark: Lark) -> None:
    """`UnexpectedToken(token, expected, state=, token_history=)` and
    `UnexpectedCharacters(text, pos, line, column, allowed=, state=, token_history=)`, as the
    custom lexer raises them, read by `token`, `expected`, `pos_in_stream` and `allowed`."""
    with pytest.raises(UnexpectedToken) as wrong:
        lark.parse("[goal: goal goal]", start="item")
    assert wrong.value.token.type and "RSQB" in wrong.value.expected
    with pytest.raises(UnexpectedCharacters) as junk:
        lark.parse("[goal: ~]", start="item")
    assert junk.value.pos_in_stream == 7 and junk.value.allowed


def test_a_token_made_without_its_constructor_is_lark_token() -> None:
    """`Token` is a `str` with the slots `type`, `value`, `start_pos`, `end_pos`, `line`,
    `column`, `end_line`, `end_column`, set here without `Token.__new__`."""
    m = re.compile(r"\s*(?P<NAME>[a-z]+)").match("  blink")
    token = token_from_match(m, "NAME", "NAME")
    made = Token("NAME", "blink", 2, end_pos=7)
    assert isinstance(token, Token) and token == made == "blink"
    assert (token.type, token.value, token.start_pos, token.end_pos) == \
        (made.type, made.value, made.start_pos, made.end_pos)
    assert Tree("x", [token]) == Tree("x", [made])


def test_a_tree_made_without_its_constructor_is_lark_tree() -> None:
    """`tree_code` makes a `Tree` with the attributes lark's constructor sets (`data`,
    `children`, `_meta`): equal to lark's, its `meta` made on demand as lark makes it."""
    namespace: dict[str, object] = {"Tree": Tree, "new_object": object.__new__,
                                    "kids": ["a", None]}
    exec(tree_code("made", "'rule'", "kids"), namespace)
    made = namespace["made"]
    built = Tree("rule", ["a", None])
    assert type(made) is Tree and made == built and made.children is namespace["kids"]
    assert vars(made) == vars(built) and made.meta.empty and repr(made) == repr(built)


def test_the_tokens_of_a_match_at_once_are_those_made_one_by_one() -> None:
    """`tokens_from_match` makes, in one call, the tokens `token_from_match` makes: by group
    number, in the order asked, with their slots."""
    regex = re.compile(r"\s*(?P<NAME>[a-z]+)\s*(?P<EQ>=)\s*(?P<NUMBER>[0-9]+)")
    m = regex.match("  blink = 42")
    steps = ((regex.groupindex["NUMBER"], "NUMBER"), (regex.groupindex["NAME"], "NAME"))
    at_once = tokens_from_match(m, steps)
    one_by_one = [token_from_match(m, "NUMBER", "NUMBER"), token_from_match(m, "NAME", "NAME")]
    slots = ("type", "value", "start_pos", "end_pos", "line", "column", "end_line", "end_column")
    assert [[getattr(t, s) for s in slots] for t in at_once] == \
        [[getattr(t, s) for s in slots] for t in one_by_one] == \
        [["NUMBER", "42", 10, 12, None, None, None, None],
         ["NAME", "blink", 2, 7, None, None, None, None]]
    assert all(type(t) is Token for t in at_once) and at_once == ["42", "blink"]


def test_the_shim_is_the_only_importer_of_lark() -> None:
    """Every other module takes lark's names from the shim (the import contract checks the
    same statically; this names what the shim hands out)."""
    assert set(larkshim.__all__) >= {"Lark", "Tree", "Token", "UnexpectedInput"}
    for name in larkshim.__all__:
        assert hasattr(larkshim, name), name
