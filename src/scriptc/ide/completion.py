"""Completion: what may be written at the cursor, read from the text before it.

The item being typed is usually broken (that is what typing does), so the context comes from
the text of the item up to the cursor, with strings and comments blanked out, matched against
the places the grammar names things; the names proposed come from the rest of the script,
which did parse:

- after `[`: the items (`goal:`, `action`, `alfa:`, `omega:`, blocks);
- after `[b#LABEL#`: the kinds of block; inside a block's head, the tracks or the jump parts;
- inside `TRJMP(` and `FLSJMP(`: the labels of the script, with their paths;
- in a condition: after `#` the classes, after `?alias>&` the fields of the alias's class,
  after `B:`/`F:`/`E:` the functions of that kind, after the bound name of an assignment the
  scopes, after a field test's field the comparisons, after `?` the aliases, after `{` the
  assignment and evaluation keywords;
- in a rule message: the rule ids after the rulecode, then the action and mutex letters.
"""

from __future__ import annotations

import re

from scriptc.ide.answers import CompletionItem
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.builtins import CLASSES, field_of
from scriptc.ir.nodes import InstructionBlock, JumpBlock, SensorBlock, TerminusBlock
from scriptc.language import (
    COMMENT_PATTERN,
    FIELD_ACCESS,
    FUNCTION_KINDS,
    MUTEXES,
    NAME_CHAR,
    NAME_PATTERN,
    OPEN_COMMENT_PATTERN,
    OPERATORS,
    PARTIAL_NAME_PATTERN,
    RULE_ACTIONS,
    SCOPES,
    STRING_PATTERN,
    TRACKS,
    sigiled,
)
from scriptc.source import Span

__all__ = ["complete"]

# The word being typed: the run of name characters that ends at the cursor. The lookbehind
# makes the search start only where a run starts; without it the search retried the rest of a
# run from each of its characters (quadratic: completion in a 1 MB word took minutes).
_WORD_CHARS = re.compile(rf"(?<!{NAME_CHAR}){PARTIAL_NAME_PATTERN}\Z")
_STRING = re.compile(STRING_PATTERN)
_COMMENT = re.compile(COMMENT_PATTERN)
_OPEN_COMMENT = re.compile(rf"{OPEN_COMMENT_PATTERN}\Z")  # (the closed ones are blanked first)

_KIND_WORD = {InstructionBlock: "blk_inst", JumpBlock: "blk_jump", TerminusBlock: "blk_terminus",
              SensorBlock: "blk_sens"}
# The places of the grammar, as regexes over the text before the cursor: `_W` is the word being
# typed (perhaps empty), `_B` a start of word (no name character before it).
_W = PARTIAL_NAME_PATTERN
_B = f"(?<!{NAME_CHAR})"
_TRACK = "|".join(TRACKS)
_ITEM_START = re.compile(rf"\[\s*{_W}\Z")
_BLOCK_LABEL = re.compile(rf"\[\s*b\s*#{_W}\Z")
_BLOCK_KIND = re.compile(rf"\[\s*b\s*#{_W}#\s*{_W}\Z")
_BLOCK_HEAD = re.compile(rf"\[\s*b\s*#{_W}#\s*(blk_inst|blk_jump)\s*:")
_TRACK_ARG = re.compile(rf"{_B}({_TRACK})\s*\((?:\s*\"\s*\"\s*,)*\s*\Z")
_JUMP_TARGET = re.compile(rf"{_B}(?:TRJMP|FLSJMP)\s*\(\s*{_W}\Z")
_FIELD = re.compile(rf"({sigiled('ALIAS')})\s*{re.escape(FIELD_ACCESS)}\s*{_W}\Z")
_OPERATOR = re.compile(rf"{re.escape(FIELD_ACCESS)}\s*{NAME_PATTERN}\s+{_W}\Z")
_FUNCTION = re.compile(rf"{_B}([{''.join(FUNCTION_KINDS)}])\s*:\s*{_W}\Z")
_CLASS = re.compile(rf"#{_W}\Z")
_SCOPE = re.compile(rf"\{{\s*(?:CLASS\s+{sigiled('CLASS_REF')}|VAR\s+{sigiled('VAR_REF')}|"
                    rf"ATT\s+{sigiled('ALIAS')}\s+{sigiled('ATT_REF')})\s+{_W}\Z")
_ALIAS = re.compile(rf"\?{_W}\Z")
_BRACE = re.compile(rf"\{{\s*{_W}\Z")
# In a CLASS assignment of the text before the cursor: its class, and the alias it binds.
_BINDING = rf"\{{\s*CLASS\s+#({NAME_PATTERN})\s+{NAME_PATTERN}\s+"
_MESSAGE_FIELD = re.compile(r"\[\s*(alfa|omega)\s*:([^\]]*)\Z")



def _letters(table, first: str = "", *, every: bool = False) -> str:
    """The letters of `table` for a snippet's choice: `first` (those the mutex order allows,
    M001 and M002, or those that undo, M004), then with `every` the others in order."""
    assert set(first) <= set(table)
    rest = [k for k in table if k not in first] if every or not first else []
    return ",".join([*first, *rest])


_ITEMS = (
    ("goal:", "goal:${1:id}", "a goal: `[goal:ID]`, then its actions"),
    ("action", "action", "an action: `[action]`, then its blocks"),
    ("alfa:", ('alfa:${1:0}, ${2:rule_id}, "${3}", "${4}", '
               f'${{5|{_letters(RULE_ACTIONS)}|}}, ${{6|{_letters(MUTEXES, "MU")}|}}'),
     "a rule message issued when the script starts"),
    ("omega:", ('omega:${1:0}, ${2:rule_id}, "${3}", "${4}", '
                f'${{5|{_letters(RULE_ACTIONS, "RC", every=True)}|}}, '
                f'${{6|{_letters(MUTEXES, "LM")}|}}'),
     "a rule message issued when the script ends"),
)
_BLOCKS = (
    ("blk_inst", "blk_inst: MV(${1}) LD(${2}) AO(${3})",
     "an instruction block: move, light and sound tracks that run together"),
    ("blk_jump", "blk_jump: CND(${1:! {TRUE\\}}) TRJMP(${2}) FLSJMP(${3})",
     "a jump block: goes to TRJMP's label when the condition holds, else to FLSJMP's"),
    ("blk_terminus", "blk_terminus", "a terminus block: ends the script"),
    ("blk_sens", "blk_sens", "a sensor block: sends a sensor message"),
)
_COMMANDS = {
    "MV": ('"${1:v_x}, ${2:v_y}, ${3:v_theta}, ${4:wait_t}, ${5:duration}"',
           "a move: speeds in m/s, m/s and rad/s, then times in ms"),
    "LD": ('"${1:r}, ${2:g}, ${3:b}, ${4:turnas}, ${5:wait_t}, ${6:duration}"',
           "a light: colour channels in [0, 1], `turnas` 1 on or 0 off, then times in ms"),
    "AO": ('"${1:track_path}, ${2:wait_t}, ${3:duration}"',
           "a sound: the track's path (`Silence` plays nothing), then times in ms"),
}
_KEYWORDS = (
    ("CLASS", f"CLASS #${{1:Human}} ${{2|{_letters(SCOPES)}|}} ?${{3:alias}} (${{4}})",
     "bind an alias to an entity of a class"),
    ("VAR", f"VAR @${{1:name}} ${{2|{_letters(SCOPES)}|}} F: ${{3:now}}()",
     "set a variable to an `F:` function's value"),
    ("ATT", f"ATT ?${{1:alias}} \\$${{2:name}} ${{3|{_letters(SCOPES)}|}} F: ${{4:str}}(${{5}})",
     "bind an attribute to an alias"),
    ("E:", "E: ${1:gt}(${2})", "evaluate an `E:` function (after the `!`)"),
    ("TRUE", "TRUE", "true: the whole condition `{TRUE}`, or an evaluation after the `!`"),
)


def _blank(prefix: str) -> str | None:
    """The prefix with strings emptied and comments turned to spaces (offsets kept); None
    when the cursor is inside a string or a comment."""
    prefix = _COMMENT.sub(lambda m: " " * len(m.group()), prefix)
    if _OPEN_COMMENT.search(prefix):
        return None
    if '"' in _STRING.sub("", prefix):
        return None  # a quote that no closing quote follows: the cursor is in a string
    return _STRING.sub(lambda m: '"' + " " * (len(m.group()) - 2) + '"', prefix)


def complete(snapshot: Snapshot, offset: int) -> list[CompletionItem]:
    item = snapshot.item_at(offset)
    if item is None or offset <= item.span.start:
        return []
    if item.closed and offset >= item.span.end:
        return []  # after the `]`
    if snapshot.in_comment(offset) is not None:
        return []
    prefix = _blank(snapshot.text[item.span.start:offset])
    if prefix is None:
        return []
    found = _WORD_CHARS.search(prefix)
    assert found is not None  # the pattern matches, if only the empty word at the end
    word = found.group()
    span = Span(offset - len(word), offset)
    return _Completer(snapshot, prefix, span).run()


class _Completer:
    def __init__(self, snapshot: Snapshot, prefix: str, span: Span) -> None:
        self.snapshot = snapshot
        self.prefix = prefix
        self.span = span

    def item(self, label: str, kind: str, **kw) -> CompletionItem:
        return CompletionItem(label, kind, kw.pop("span", self.span), **kw)

    def run(self) -> list[CompletionItem]:
        p = self.prefix
        if _ITEM_START.fullmatch(p):
            return self.items()
        if _BLOCK_LABEL.fullmatch(p):
            return []  # a new label: any name
        if _BLOCK_KIND.fullmatch(p):
            return [self.item(name, "keyword", snippet=snippet, insert_text=name, documentation=doc)
                    for name, snippet, doc in _BLOCKS]
        if _JUMP_TARGET.search(p):
            return self.labels()
        message = _MESSAGE_FIELD.match(p)
        if message:
            return self.message(message)
        if "CND" in p:
            found = self.condition(p)
            if found is not None:
                return found
        head = _BLOCK_HEAD.match(p)
        if head is None:
            return []
        before = p[:len(p) - len(self.word)]
        balanced = before.count("(") == before.count(")")
        after_part = before.rstrip()[-1:] in (":", ")")
        if head.group(1) == "blk_inst":
            track = _TRACK_ARG.search(p)
            if track:
                snippet, doc = _COMMANDS[track.group(1)]
                plain = re.sub(r"\$\{\d+:([^}]*)\}", r"\1", snippet)
                return [self.item(f"{track.group(1)} command", "snippet", snippet=snippet,
                                  insert_text=plain, documentation=doc)]
            if balanced and after_part:
                # The tracks not written yet, in their order (`MV() LD() AO()`).
                present = re.findall(rf"{_B}({_TRACK})\s*\(", before)
                last = max(TRACKS.index(t) for t in present) if present else -1
                return [self.item(name, "keyword", snippet=f"{name}(${{1}})",
                                  insert_text=f"{name}()", documentation=_COMMANDS[name][1])
                        for name in TRACKS[last + 1:]]
        if head.group(1) == "blk_jump" and balanced and after_part:
            if "CND" not in before:
                return [self.item("CND", "keyword", snippet="CND(${1:! {TRUE\\}})",
                                  insert_text="CND()",
                                  documentation="the condition, in the rule grammar")]
            if "TRJMP" not in before:
                return [self.item("TRJMP", "keyword", snippet="TRJMP(${1}) FLSJMP(${2})",
                                  insert_text="TRJMP() FLSJMP()",
                                  documentation=("where to go when the condition holds, "
                                                 "and when not"))]
            if "FLSJMP" not in before:
                return [self.item("FLSJMP", "keyword", snippet="FLSJMP(${1})",
                                  insert_text="FLSJMP()",
                                  documentation="where to go when the condition does not hold")]
        return []

    @property
    def word(self) -> str:
        return self.snapshot.text[self.span.start:self.span.end]

    # -- items ------------------------------------------------------------------------------

    def items(self) -> list[CompletionItem]:
        out = [self.item(name, "item", snippet=snippet, insert_text=name, documentation=doc)
               for name, snippet, doc in _ITEMS]
        for name, snippet, doc in _BLOCKS:
            # The label comes first: `b#${1:label}#`, the block's own places after it.
            later = re.sub(r"\$\{(\d+)", lambda m: "${" + str(int(m.group(1)) + 1), snippet)
            out.append(self.item(f"b##{name}", "item", snippet="b#${1}#" + later,
                                 insert_text=f"b##{name}", documentation=doc))
        return out

    # -- labels ------------------------------------------------------------------------------

    def labels(self) -> list[CompletionItem]:
        """Every label of the script, in execution order, with the path a jump to it gets
        (hundreds in a large script: each is kept cheap to build)."""
        item = self.item
        return [item(name, "label", detail=f"{info.path} · {_KIND_WORD[type(info.block)]}",
                     sort_text=f"{info.order:06d}")
                for name, info in self.snapshot.index.label_blocks.items()]

    # -- rule messages ------------------------------------------------------------------------

    def message(self, m: re.Match[str]) -> list[CompletionItem]:
        """In a rule message: `m` is `_MESSAGE_FIELD`'s match of the prefix."""
        kind, fields = m.group(1), m.group(2)
        field_index = fields.count(",")
        if field_index == 1:
            script = self.snapshot.script
            ids = []
            if script is not None:
                for message in (*script.alfa, *script.omega):
                    if message.id.text and message.id.text not in ids:
                        ids.append(message.id.text)
            return [self.item(i, "rule", detail="rule id") for i in ids]
        if field_index == 4:
            return [self.item(k, "letter", detail="rule action", documentation=v)
                    for k, v in RULE_ACTIONS.items()]
        if field_index == 5:
            order = _letters(MUTEXES, "MU" if kind == "alfa" else "LM", every=True).split(",")
            return [self.item(k, "letter", detail="mutex", documentation=MUTEXES[k],
                              sort_text=str(order.index(k))) for k in order]
        return []

    # -- conditions -----------------------------------------------------------------------------

    def condition(self, p: str) -> list[CompletionItem] | None:
        m = _FIELD.search(p)
        if m:
            return self.fields(m.group(1), p)
        if _OPERATOR.search(p):
            return [self.item(op, "operator", documentation=f"the field is {word} the value")
                    for op, word in OPERATORS.items()]
        m = _FUNCTION.search(p)
        if m:
            return self.functions(m.group(1))
        if _SCOPE.search(p):
            return [self.item(k, "scope", documentation=f"the binding lasts {v}")
                    for k, v in SCOPES.items()]
        if _CLASS.search(p):
            return [self.item(name, "class", documentation=", ".join(f.name for f in fields))
                    for name, fields in CLASSES.items()]
        if _ALIAS.search(p):
            start = self.span.start - 1  # the `?` is part of the alias
            names = sorted(self.snapshot.index.alias_bindings)
            names += [a for _, a in re.findall(_BINDING + f"({sigiled('ALIAS')})", p)
                      if a not in names]
            out = [self.item(a, "variable", span=Span(start, self.span.end), detail="alias")
                   for a in names if a != "?" + self.word]
            out.append(self.item("?THIS", "variable", span=Span(start, self.span.end),
                                 detail="the candidate entity of a CLASS assignment's tests"))
            return out
        if _BRACE.search(p):
            return [self.item(name, "keyword", snippet=snippet, insert_text=name, documentation=doc)
                    for name, snippet, doc in _KEYWORDS]
        return None

    def fields(self, alias: str, p: str) -> list[CompletionItem]:
        if alias == "?THIS":
            classes = re.findall(rf"\{{\s*CLASS\s+#({NAME_PATTERN})", p)
            cls = classes[-1] if classes else None
        else:
            here = re.findall(_BINDING + re.escape(alias) + f"(?!{NAME_CHAR})", p)
            cls = here[-1] if here else self.snapshot.index.alias_class(alias)
        names = [c for c in CLASSES if c == cls] or list(CLASSES)  # the class, if known
        seen: dict[str, CompletionItem] = {}
        for c in names:
            for f in CLASSES[c]:
                if f.name not in seen:
                    owner = c if cls in CLASSES else ", ".join(
                        k for k in CLASSES if field_of(k, f.name) is not None)
                    seen[f.name] = self.item(f.name, "field", detail=f"{f.type} · {owner}",
                                             documentation=f.doc)
        return list(seen.values())

    def functions(self, kind: str) -> list[CompletionItem]:
        out = []
        for function in self.snapshot.functions:
            if function.kind != kind:
                continue
            params = ", ".join(f"${{{i + 1}:{p.name}}}" for i, p in enumerate(function.params))
            out.append(self.item(function.name, "function", detail=function.signature,
                                 documentation=function.doc, snippet=f"{function.name}({params})",
                                 insert_text=f"{function.name}()"))
        return out
