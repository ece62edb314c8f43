"""Lowering: lark trees of the items of a script -> the typed IR, with exact spans.

The grammar is flat (a list of items); lowering assembles the hierarchy Script > Goal >
Action > Block and reports what is out of place (S codes), reads the comma-separated fields
of command strings into Numbers (V001, V002), resolves string escapes (P006) and lowers
conditions. It never raises: a broken part is reported and left out.

Entry points: `lower_script(source)` for script syntax, `parse_condition(text, base)` for a
condition on its own (thesis JSON's `toparse`).
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable
from enum import Enum
from typing import Final

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, Label, TextEdit
from scriptc.gcpause import gc_paused
from scriptc.ir import nodes as ir
from scriptc.ir.fields import fields_pattern, read_number
from scriptc.language import COMMENT_PATTERN, STRING_ESCAPES, STRING_PATTERN, TRACKS, unescape
from scriptc.source import SourceFile, Span

# The parse trees (lark stays behind syntax/): a child is read by its place in its rule.
from scriptc.syntax.larkshim import Child, ParseTree, Token, Tree
from scriptc.syntax.parser import (
    ParsedItem,
    ParsedScript,
    each_item,
    parse_condition_tree,
    script_parser,
)
from scriptc.syntax.scan import scan

MOVE_FIELDS = ("v_x", "v_y", "v_theta", "wait_t", "duration")
LED_FIELDS = ("r", "g", "b", "turnas", "wait_t", "duration")
AUDIO_FIELDS = ("track_path", "wait_t", "duration")
RULE_FIELDS = ("rulecode", "id", "intopic", "outtopic", "action", "mutex")
# A command string whose fields are all there and all numbers (the audio path aside).
_WELL_FORMED = {"MV": fields_pattern(len(MOVE_FIELDS)), "LD": fields_pattern(len(LED_FIELDS)),
                "AO": fields_pattern(len(AUDIO_FIELDS), text_first=True)}
_ESCAPE = re.compile(r"\\(.)", re.DOTALL)
_TRUE_EVAL = re.compile(r"\{\s*TRUE\s*\}")


# Rule and terminal names without the namespace (`_kind`): where a node is known to be a tree,
# `_KINDS.get(tree.data) or _kind(tree)` saves a call (a large script has 100,000 trees).
_KINDS: dict[str, str] = {}


def _kind(node: ParseTree | Token) -> str:
    """A rule or terminal name without the namespace lark adds to imported grammars."""
    name = node.data if isinstance(node, Tree) else node.type
    kind = _KINDS.get(name)
    if kind is None:
        kind = _KINDS[name] = str(name).rsplit("__", 1)[-1]
    return kind


# `Span(a, b)` without the named tuple's keyword-handling `__new__`: the leaves of a large
# script make hundreds of thousands of spans.
_span = tuple.__new__


def _well_formed(track: str, raw: str) -> tuple[tuple[str, int, int], ...] | None:
    """The fields of a command string whose fields are all there and all numbers (the audio
    path aside), as (text, start, end) within `raw`; None for any other string, which
    `Lowerer.command` reads field by field, reporting what is wrong."""
    m = _WELL_FORMED[track].fullmatch(raw) if "\\" not in raw else None
    if m is None or (track == "AO" and m.group(1)[-1] == ","):
        return None  # (an audio path whose last part is blank: its blanks belong to the path)
    return tuple((raw[a:b], a, b) for a, b in m.regs[1:])


# The fields of each command string met, by track: a script repeats its commands (a still
# move, a LED off), and each string is split once (bounded, like the parser's shapes).
_SPLIT: dict[str, dict[str, tuple[tuple[str, int, int], ...] | None]] = {
    track: {} for track in _WELL_FORMED}
_MAX_SPLIT = 4096


class _Unseen(Enum):
    """A command string not split yet (None is a split: not well formed)."""

    UNSEEN = 0


_UNSEEN: Final = _Unseen.UNSEEN
# The tracks of an instruction block, in the order they are written.
_TRACK_ORDER = list(TRACKS)

# The parentheses of a condition, strings and comments skipped (either may hold one).
_PARENS = re.compile(f"{STRING_PATTERN}|{COMMENT_PATTERN}|[()]")


# Text up to the `)` closing an open parenthesis, with parentheses nested two deep inside (a
# condition's deepest: a test list holding a call) and no string or comment before it.
_CLOSE = re.compile(r'(?:[^()"%]++|\((?:[^()"%]++|\([^()"%]*+\))*+\))*+\)')


def _closing_paren(text: str, at: int, end: int) -> int:
    """Where the `)` closing a parenthesis opened just before `at` is, within `end` (-1: not
    there); strings and comments may hold parentheses, which do not count."""
    m = _CLOSE.match(text, at, end)
    if m is not None:
        # (the common case, in one match: the loop below costs a fifth of lowering a jump)
        return m.end() - 1
    depth = 1
    for m in _PARENS.finditer(text, at, end):
        if m.group() == "(":
            depth += 1
        elif m.group() == ")":
            depth -= 1
            if depth == 0:
                return m.start()
    return -1


class Lowerer:
    """`text` is the text being lowered; it starts at offset `text_base` of its file (0 for a
    script, the string's offset for a condition read from JSON). `base` is the offset of the
    item being lowered: lark's token offsets are relative to it.

    `script(source, parsed)` lowers a whole script; it lowers each item through `block(tree,
    span)` and `rule_message(tree, span)`, which depend on nothing but the item (and `base`):
    a subclass may answer them from a cache (the language server's incremental analysis,
    `scriptc.ide.incremental`), as long as it returns what they would and adds the same
    diagnostics."""

    def __init__(self, text: str, text_base: int = 0) -> None:
        self.text = text
        self.text_base = text_base
        self.diagnostics: list[Diagnostic] = []
        self.base = text_base

    # -- leaves ---------------------------------------------------------------------------

    def span(self, token: Token) -> Span:
        start, end = token.start_pos, token.end_pos
        assert start is not None and end is not None  # the parsers' tokens have their offsets
        return _span(Span, (self.base + start, self.base + end))

    def name(self, token: Token, strip: int = 0) -> ir.Name:
        base = self.base
        start, end = token.start_pos, token.end_pos
        assert start is not None and end is not None  # the parsers' tokens have their offsets
        if strip:
            return ir.Name(token.value[strip:], _span(Span, (base + start + strip, base + end)))
        return ir.Name(token.value, _span(Span, (base + start, base + end)))

    def string(self, token: Token) -> ir.Text:
        """A string literal's value; unknown escapes are reported and kept as written."""
        raw = token.value[1:-1]
        span = self.span(token)
        if "\\" not in raw:
            return ir.Text(raw, span)

        def resolve(m: re.Match[str]) -> str:
            ch: str = m.group(1)
            if ch in STRING_ESCAPES:
                return ch
            at = span.start + 1 + m.start()
            self.diagnostics.append(
                diagnostic(
                    "P006",
                    f"unknown escape `\\{ch}` in a string",
                    Span(at, at + 2),
                    help="strings know two escapes, `\\\\` (a backslash) and `\\\"` (a quote); "
                    f"write `\\\\{ch}` for a backslash followed by `{ch}`",
                    fix=Fix("escape the backslash", (TextEdit(Span(at, at + 1), "\\\\"),)),
                )
            )
            written: str = m.group(0)
            return written

        return ir.Text(_ESCAPE.sub(resolve, raw), span)

    # -- the script -----------------------------------------------------------------------

    def script(self, source: SourceFile, parsed: ParsedScript | None = None) -> ir.Script | None:
        """Lower the items of `source`: each parsed here as it is lowered (`each_item`: one
        tree at a time), unless `parsed`, the parse of this same text, is given."""
        items: Iterable[ParsedItem]
        if parsed is None:
            scanned = scan(source.text)
            syntax = list(scanned.diagnostics)  # (`each_item` adds the parse's, as it goes)
            items = each_item(source.text, scanned, script_parser(), syntax)
        else:
            syntax, items = parsed.diagnostics, parsed.items
        # the syntax errors come first, then lowering's (they are found as items are lowered)
        at = len(self.diagnostics)
        name: ir.Name | None = None
        alfa: list[ir.RuleMessage] = []
        omega: list[ir.RuleMessage] = []
        # (id, span, actions) per goal; (span, blocks) per action
        goals: list[tuple[ir.Name, Span, list[tuple[Span, list[ir.Block]]]]] = []
        actions: list[tuple[Span, list[ir.Block]]] | None = None  # actions of the current goal
        blocks: list[ir.Block] | None = None  # blocks of the current action
        first = True
        word: Child  # the word of a name item, the id of a goal: a NAME token (or None)
        for item in items:
            self.base = item.base
            tree = item.tree
            kind = _kind(tree)
            if first:
                first = False
                word = tree.children[0]
                if kind == "name_item" and str(word) != "action":
                    name = self.name(word)
                    continue
                self.diagnostics.append(
                    diagnostic(
                        "S001",
                        "a script must start with its activity name",
                        Span(item.span.start, item.span.start),
                        help="add `[activityname]` as the first item, e.g. `[greeting]`",
                        fix=Fix("add an activity name",
                                (TextEdit(Span(0, 0), "[activity]\n"),), safe=False),
                    )
                )
            if kind == "name_item":
                word = tree.children[0]
                if str(word) == "action":
                    if actions is None:
                        self._orphan(item.span, "`[action]`", "`[goal:ID]`")
                        blocks = None
                        continue
                    blocks = []
                    actions.append((item.span, blocks))
                else:
                    self._unknown_item(word, item.span)
            elif kind == "rule_message":
                message = self.rule_message(tree, item.span)
                if message is None:
                    continue
                if goals:
                    self._misplaced(item.span, f"{message.kind} messages",
                                    "before the first goal", goals[0][1])
                elif message.kind == "alfa" and omega:
                    self._misplaced(item.span, "alfa messages", "before the omega messages",
                                    omega[0].span)
                if message.kind == "alfa":
                    alfa.append(message)
                else:
                    omega.append(message)

            elif kind == "goal_item":
                word = tree.children[0]
                if word is None:
                    self.diagnostics.append(
                        diagnostic("S007", "goal without an id", item.span,
                                   help="name the goal: `[goal:greet]`")
                    )
                    goal_id = ir.Name("", item.span)
                else:
                    goal_id = self.name(word)
                actions = []
                blocks = None
                goals.append((goal_id, item.span, actions))
            elif kind == "block":
                block = self.block(tree, item.span)
                if blocks is None:
                    if actions is None:
                        self._orphan(item.span, "a block", "`[goal:ID]` and `[action]`")
                    else:
                        self._orphan(item.span, "a block", "`[action]`", insert="[action]")
                    continue
                if block is not None:
                    blocks.append(block)
        self.diagnostics[at:at] = syntax
        # When items were lost to syntax errors, "this goal has no action" and the like would
        # report the loss again, not a mistake of the script's structure.
        lost_items = bool(syntax)
        if first:  # no item at all
            if lost_items:
                return None
            end = len(source.text)
            blank = not source.text.strip()
            self.diagnostics.append(
                diagnostic(
                    "S001",
                    "the file holds no script" if blank else "the file holds no item",
                    Span(0, 0 if blank else min(end, 1)),
                    help="a script starts with `[activityname]`, then `[goal:ID]`, `[action]` "
                    "and blocks",
                )
            )
            return None
        if name is None:
            name = ir.Name("", Span(0, 0))
        if not goals and name.text and not lost_items:
            self.diagnostics.append(
                diagnostic(
                    "S004",
                    f"script `{name.text}` has no goal",
                    name.span,
                    help="add `[goal:ID]`, `[action]` and at least one block",
                )
            )
        built_goals: list[ir.Goal] = []
        for goal_id, goal_span, goal_actions in goals:
            if not goal_actions and not lost_items:
                self.diagnostics.append(
                    diagnostic("S005", f"goal `{goal_id.text}` has no action", goal_span,
                               help="add `[action]` and its blocks after the goal")
                )
            built_actions: list[ir.Action] = []
            for action_span, action_blocks in goal_actions:
                if not action_blocks and not lost_items:
                    self.diagnostics.append(
                        diagnostic("S006", "action has no block", action_span,
                                   help="add a block, e.g. `[b##blk_terminus]`, or remove the "
                                   "action")
                    )
                built_actions.append(ir.Action(tuple(action_blocks), action_span))
            built_goals.append(ir.Goal(goal_id, tuple(built_actions), goal_span))
        return ir.Script(name, tuple(alfa), tuple(omega), tuple(built_goals),
                         Span(0, len(source.text)))

    def _orphan(self, span: Span, what: str, needs: str, insert: str | None = None) -> None:
        fix = None
        if insert:
            fix = Fix(f"add `{insert}` before it",
                      (TextEdit(Span(span.start, span.start), insert + "\n"),), safe=False)
        self.diagnostics.append(
            diagnostic("S002", f"{what} must come after {needs}", span,
                       help=f"add {needs} before it", fix=fix)
        )

    def _misplaced(self, span: Span, what: str, where: str, other: Span) -> None:
        self.diagnostics.append(
            diagnostic("S002", f"{what} must come {where}", span,
                       labels=(Label(other, "this comes first"),),
                       help="move the item up")
        )

    def _unknown_item(self, word: Token, span: Span) -> None:
        text = str(word)
        close = difflib.get_close_matches(text, ["action"], n=1, cutoff=0.6)
        fix = None
        help_ = ("the items are `[activityname]` (first), `[alfa:...]`, `[omega:...]`, "
                 "`[goal:ID]`, `[action]` and blocks `[b#LABEL#...]`")
        if close:
            help_ = f"did you mean `[{close[0]}]`?"
            fix = Fix(f"replace with `{close[0]}`", (TextEdit(self.span(word), close[0]),))
        self.diagnostics.append(
            diagnostic("S003", f"unknown item `[{text}]`", span, help=help_, fix=fix,
                       notes=("only the first item names the activity",))
        )

    # -- rule messages --------------------------------------------------------------------

    def rule_message(self, tree: ParseTree, span: Span) -> ir.RuleMessage | None:
        children: list[Child] = tree.children  # ALFA or OMEGA, then the fields (tokens)
        kind = str(children[0])
        fields = [f for f in children[1:] if f is not None]
        if len(fields) != 6:
            self.diagnostics.append(
                diagnostic(
                    "S009",
                    f"{kind} message has {len(fields)} field{'s' if len(fields) != 1 else ''}, "
                    "expected 6",
                    span,
                    notes=(f"the fields are {', '.join(RULE_FIELDS)}",),
                    help=f'write `[{kind}:RULECODE, ID, "INTOPIC", "OUTTOPIC", ACTION, MUTEX]`, '
                    f'e.g. `[{kind}:0, kick_starter, "", "", C, U]`',
                )
            )
            return None
        rulecode_t, id_t, in_t, out_t, action_t, mutex_t = fields
        ok = True
        expected_types = (("NUMBER",), ("NAME",), ("STRING",), ("STRING",), ("NAME",), ("NAME",))
        for field_name, token, types in zip(RULE_FIELDS, fields, expected_types, strict=True):
            if _kind(token) not in types:
                if field_name == "rulecode":
                    _, problem = read_number(str(token), self.span(token), "the rulecode")
                    if problem is not None:
                        self.diagnostics.append(problem)
                        ok = False
                        continue
                want = {"NUMBER": "a number", "NAME": "a name", "STRING": "a string"}[types[0]]
                self.diagnostics.append(
                    diagnostic(
                        "S009",
                        f"the {field_name} of a rule message is {want}, found `{token}`",
                        self.span(token),
                        help=('topics are quoted: `""` for none' if types[0] == "STRING"
                              else f"write the {field_name} without quotes"),
                    )
                )
                ok = False
        if not ok:
            return None
        return ir.RuleMessage(
            kind=kind,
            rulecode=ir.Number(str(rulecode_t), self.span(rulecode_t)),
            id=self.name(id_t),
            intopic=self.string(in_t),
            outtopic=self.string(out_t),
            action=self.name(action_t),
            mutex=self.name(mutex_t),
            span=span,
        )

    # -- blocks ---------------------------------------------------------------------------

    def block(self, tree: ParseTree, span: Span) -> ir.Block | None:
        children: list[Child] = tree.children  # the label (a NAME token or None), the body
        label_t, body = children
        label = self.name(label_t) if label_t is not None else None
        kind = _KINDS.get(body.data) or _kind(body)
        if kind == "inst_body":
            return self.instruction(label, body, span)
        if kind == "jump_body":
            body_children: list[Child] = body.children  # the condition, two labels or None
            cond_tree, true_t, false_t = body_children
            cond_span = self._cnd_span(span)
            condition = self.condition(cond_tree, cond_span)
            return ir.JumpBlock(
                label=label,
                condition=condition,
                true_target=self.name(true_t) if true_t is not None else None,
                false_target=self.name(false_t) if false_t is not None else None,
                span=span,
                condition_text=self._text(cond_span),
            )
        if kind == "terminus_body":
            return ir.TerminusBlock(label, span)
        # sensor_body
        payload = tuple(self.string(t) for t in body.children[1:] if t is not None)
        return ir.SensorBlock(label, payload, span)

    def instruction(self, label: ir.Name | None, body: ParseTree,
                    span: Span) -> ir.InstructionBlock:
        moves: list[ir.MoveCommand] = []
        leds: list[ir.LedCommand] = []
        audios: list[ir.AudioCommand] = []
        names: list[str] = []
        track_trees: list[Child] = body.children  # the tracks' trees
        for track in track_trees:
            children: list[Child] = track.children  # MV, LD or AO, then strings or None
            track_name = children[0].value
            names.append(track_name)
            for token in children[1:]:
                if token is None:
                    continue
                # (the command of a track is the track's kind: MV a move, LD a led, AO audio)
                command = self.command(track_name, token)
                if isinstance(command, ir.MoveCommand):
                    moves.append(command)
                elif isinstance(command, ir.LedCommand):
                    leds.append(command)
                elif command is not None:
                    audios.append(command)
        if names != _TRACK_ORDER:
            self._check_tracks(self._track_spans(track_trees), span)
        return ir.InstructionBlock(label, tuple(moves), tuple(leds), tuple(audios), span)

    def _track_spans(self, track_trees: list[Child]) -> list[tuple[str, Span]]:
        """Each track's name and span, from its name to its closing parenthesis."""
        base, text_base = self.base, self.text_base
        seen: list[tuple[str, Span]] = []
        for track in track_trees:
            children: list[Child] = track.children  # MV, LD or AO, then strings or None
            name_t = children[0]
            last = next((t for t in reversed(children) if t is not None), name_t)
            last_end = base + last.end_pos
            close = self.text.find(")", last_end - text_base)
            end = text_base + close + 1 if close != -1 else last_end
            seen.append((name_t.value, Span(base + name_t.start_pos, end)))
        return seen

    def _check_tracks(self, seen: list[tuple[str, Span]], span: Span) -> None:
        """S008 for tracks out of order, twice or missing (`seen`: each track's name and
        span, in the order written)."""
        names = [n for n, _ in seen]
        for i, (n, s) in enumerate(seen):
            if n in names[:i]:
                self.diagnostics.append(
                    diagnostic("S008", f"`{n}()` appears twice in this block", s,
                               labels=(Label(seen[names.index(n)][1], "first here"),),
                               help=f"merge the commands into one `{n}(...)`")
                )
                return
        order = [n for n in names if n in TRACKS]
        if order != sorted(order, key=TRACKS.index):
            self.diagnostics.append(
                diagnostic("S008", "tracks are written `MV() LD() AO()` in this order, found "
                           f"`{' '.join(n + '()' for n in names)}`",
                           Span(seen[0][1].start, seen[-1][1].end),
                           help="reorder the tracks")
            )
            return
        missing = [n for n in TRACKS if n not in names]
        # Insert each missing track before the first present track that follows it.
        edits: list[TextEdit] = []
        for n in missing:
            after = [s for m, s in seen if TRACKS.index(m) > TRACKS.index(n)]
            at = after[0].start if after else (seen[-1][1].end if seen else span.end - 1)
            text = f"{n}() " if after else f" {n}()"
            edits.append(TextEdit(Span(at, at), text))
        listed = " and ".join(f"`{n}()`" for n in missing)
        where = Span(span.end - 1, span.end)
        self.diagnostics.append(
            diagnostic("S008", f"instruction block without {listed}", where,
                       notes=(("every instruction block lists `MV()`, `LD()` and `AO()`, "
                               "each possibly empty"),),
                       help=f"add {listed}",
                       fix=Fix(f"add {listed}", tuple(edits)))
        )

    def command(self, track: str, token: Token) -> ir.Command | None:
        """Split a command string into its fields, each with its own span. The raw text is
        split (neither escape holds a comma), so spans are exact and blanks inside a field,
        such as an audio path's, are kept; each field is unescaped afterwards."""
        raw: str = token.value[1:-1]
        first, last = token.start_pos, token.end_pos
        assert first is not None and last is not None  # the parsers' tokens have their offsets
        start = self.base + first + 1
        split = _SPLIT[track]
        well_formed = split.get(raw, _UNSEEN)
        if well_formed is _UNSEEN:
            if len(split) >= _MAX_SPLIT:
                split.clear()
            well_formed = split[raw] = _well_formed(track, raw)
        if well_formed is not None:
            # The common case: every field there and a number (the path of an audio command,
            # text); what follows reads the same fields the same way.
            whole = _span(Span, (start - 1, self.base + last))
            numbers = [ir.Number(text, _span(Span, (start + a, start + b)))
                       for text, a, b in well_formed]
            if track != "AO":
                return _command(track, numbers, None, whole)
            path_field = numbers.pop(0)
            return _command(track, numbers, ir.Text(path_field.text, path_field.span), whole)
        self.string(token)  # reports unknown escapes once, for the whole string
        fields: list[tuple[str, Span]] = []
        pos = 0
        for part in raw.split(","):
            lead = len(part) - len(part.lstrip())
            stripped = part.strip()
            at = start + pos + lead
            fields.append((stripped, Span(at, at + len(stripped))))
            pos += len(part) + 1
        whole = self.span(token)
        names: tuple[str, ...]
        if track == "AO":
            names = AUDIO_FIELDS
            if len(fields) >= 3:
                path_fields = fields[:-2]
                p0, p1 = path_fields[0][1].start, path_fields[-1][1].end
                fields = [(self._text(Span(p0, p1)), Span(p0, p1)), *fields[-2:]]
        else:
            names = MOVE_FIELDS if track == "MV" else LED_FIELDS
        if len(fields) != len(names) or (len(fields) == 1 and not fields[0][0]):
            what = {"MV": "move", "LD": "led", "AO": "audio"}[track]
            count = 0 if len(fields) == 1 and not fields[0][0] else len(fields)
            self.diagnostics.append(
                diagnostic("V001", f"{what} command has {count} field{'s' if count != 1 else ''}, "
                           f"expected {len(names)}",
                           whole, notes=(f"a {what} command is `\"{', '.join(names)}\"`",))
            )
            return None
        numbers = []
        for (value, fspan), fname in zip(fields, names, strict=True):  # (counted above)
            if fname == "track_path":
                continue
            number, problem = read_number(value, fspan, f"`{fname}`")
            if problem is not None:
                self.diagnostics.append(problem)
                return None
            numbers.append(number)
        path = ir.Text(unescape(fields[0][0]), fields[0][1]) if track == "AO" else None
        return _command(track, numbers, path, whole)

    # -- conditions -----------------------------------------------------------------------

    def _text(self, span: Span) -> str:
        return self.text[span.start - self.text_base : span.end - self.text_base]

    def _cnd_span(self, item: Span) -> Span:
        """The condition between `CND(` and its matching `)`, trimmed (the parenthesis and the
        braces are anonymous in the grammar, so the tree does not know where they are)."""
        tb = self.text_base
        at = self.text.find("(", self.text.find("CND", item.start - tb)) + 1
        close = _closing_paren(self.text, at, item.end - tb)
        if close == -1:
            return item
        inner = self.text[at:close]
        lead = len(inner) - len(inner.lstrip())
        return _span(Span, (tb + at + lead, tb + at + len(inner.rstrip())))

    def _enclose(self, span: Span, open_: str, close: str) -> Span:
        """Widen `span` to the `open_` before it and the `close` after it (the anonymous
        punctuation around an assignment, an evaluation or a call's arguments)."""
        tb = self.text_base
        start = self.text.rfind(open_, 0, span.start - tb)
        end = self.text.find(close, span.end - tb)
        return _span(Span, (tb + start if start != -1 else span.start,
                            tb + end + 1 if end != -1 else span.end))

    def condition(self, tree: ParseTree, span: Span) -> ir.Condition:
        kind = _KINDS.get(tree.data) or _kind(tree)
        if kind == "true_condition":
            return ir.Condition((), (), span, bare_true=True)
        assignments: list[ir.Assignment] = []
        evaluations: list[ir.Evaluation] = []
        parts: list[Child] = tree.children  # the assignments' and evaluations' trees
        for child in parts:
            k = _KINDS.get(child.data) or _kind(child)
            children: list[Child] = child.children  # by the rule `k`, below
            if k == "class_assignment":
                class_t, scope_t, alias_t, *tests = children
                class_name = self.name(class_t, strip=1)
                lowered = tuple([self.test(t) for t in tests if t is not None])
                end = lowered[-1].span.end if lowered else self.span(alias_t).end
                assignments.append(
                    ir.ClassAssignment(
                        class_name=class_name,
                        scope=self.name(scope_t),
                        alias=self.alias(alias_t),
                        tests=lowered,
                        span=self._enclose(_span(Span, (class_name.span.start, end)), "{", "}"),
                    )
                )
            elif k == "var_assignment":
                var_t, scope_t, f_call = children
                var = self.var(var_t)
                call = self.call(f_call.children[0], "F")
                assignments.append(
                    ir.VarAssignment(
                        var=var,
                        scope=self.name(scope_t),
                        call=call,
                        span=self._enclose(_span(Span, (var.span.start, call.span.end)),
                                           "{", "}"),
                    )
                )
            elif k == "att_assignment":
                alias_node, att_t, scope_t, f_call = children
                alias = self.alias_of(alias_node)
                call = self.call(f_call.children[0], "F")
                assignments.append(
                    ir.AttAssignment(
                        alias=alias,
                        att=self.name(att_t),
                        scope=self.name(scope_t),
                        call=call,
                        span=self._enclose(_span(Span, (alias.span.start, call.span.end)),
                                           "{", "}"),
                    )
                )
            elif k == "e_evaluation":
                call = self.call(children[0], "E")
                evaluations.append(ir.CallEvaluation(call, self._enclose(call.span, "{", "}")))
            elif k == "true_evaluation":
                # `{TRUE}` has no token in the tree: find it after what came before it.
                after = evaluations[-1].span.end if evaluations else (
                    assignments[-1].span.end if assignments else span.start)
                evaluations.append(
                    ir.TrueEvaluation(self._find(_TRUE_EVAL, Span(after, span.end))))
        return ir.Condition(tuple(assignments), tuple(evaluations), span)

    def _find(self, pattern: re.Pattern[str], within: Span) -> Span:
        tb = self.text_base
        m = pattern.search(self.text, within.start - tb, within.end - tb)
        return Span(tb + m.start(), tb + m.end()) if m else within

    def test(self, node: ParseTree) -> ir.Test:
        k = _KINDS.get(node.data) or _kind(node)
        children: list[Child] = node.children  # by the rule `k`
        if k == "field_test":
            this_t, _access, field_t, op_t, value = children
            lowered = self.value(value)
            span = _span(Span, (self.base + this_t.start_pos, lowered.span.end))
            return ir.FieldTest(self.name(field_t), self.name(op_t), lowered, span)
        call = self.call(children[0], "B")
        start = self.text.rfind("B", 0, call.span.start - self.text_base)
        return ir.CallTest(call, _span(Span, (
            self.text_base + start if start != -1 else call.span.start, call.span.end)))

    def call(self, node: ParseTree, kind: str) -> ir.Call:
        children: list[Child] = node.children  # the name, then values' trees or None
        name_t, *args = children
        # (a list first: `tuple` of a generator costs more, and conditions hold many calls)
        values = tuple([self.value(a) for a in args if a is not None])
        name = self.name(name_t)
        last = values[-1].span.end if values else name.span.end
        end = self.text.find(")", last - self.text_base)
        span = _span(Span, (name.span.start, self.text_base + end + 1 if end != -1 else last))
        return ir.Call(kind, name, values, span)

    def alias(self, token: Token) -> ir.AliasRef:
        name = self.name(token)
        return ir.AliasRef(name, name.span)  # (the name is the whole reference: one span)

    def var(self, token: Token) -> ir.VarRef:
        name = self.name(token)
        return ir.VarRef(name, name.span)

    def alias_of(self, node: ParseTree) -> ir.AliasRef:
        """An `alias` or `this` tree (the grammar's `alias_or_this`)."""
        token: Child = node.children[0]  # ALIAS or THIS
        return self.alias(token)

    def value(self, node: ParseTree) -> ir.Value:
        k = _KINDS.get(node.data) or _kind(node)
        children: list[Child] = node.children  # by the rule `k`
        if k == "number":
            t = children[0]
            return ir.NumberValue(ir.Number(t.value, self.span(t)))  # (`value`: a plain str)
        if k == "string":
            return ir.StringValue(self.string(children[0]))
        if k in ("alias", "this"):
            return self.alias(children[0])
        if k == "field_ref":
            alias_node, _access, field_t = children
            alias = self.alias_of(alias_node)
            field = self.name(field_t)
            return ir.FieldRef(alias, field, _span(Span, (alias.span.start, field.span.end)))
        if k == "att_ref":
            alias_node, _access, att_t = children
            alias = self.alias_of(alias_node)
            att = self.name(att_t)
            return ir.AttRef(alias, att, _span(Span, (alias.span.start, att.span.end)))
        if k == "var_ref":
            return self.var(children[0])
        raise AssertionError(f"unknown value node {k}")


def _command(track: str, numbers: list[ir.Number], path: ir.Text | None,
             span: Span) -> ir.Command:
    """The command of `track` (MV, LD or AO) with its numbers, in the order of the fields (an
    audio command's path apart)."""
    if track == "MV":
        v_x, v_y, v_theta, wait_t, duration = numbers
        return ir.MoveCommand(v_x, v_y, v_theta, wait_t, duration, span)
    if track == "LD":
        r, g, b, turnas, wait_t, duration = numbers
        return ir.LedCommand(r, g, b, turnas, wait_t, duration, span)
    assert path is not None  # (an audio command's first field)
    wait_t, duration = numbers
    return ir.AudioCommand(path, wait_t, duration, span)


def lower_script(source: SourceFile) -> tuple[ir.Script | None, list[Diagnostic]]:
    """Parse and lower a whole script. The script is None only when the file holds no item."""
    lowerer = Lowerer(source.text)
    with gc_paused():
        script = lowerer.script(source)
    return script, lowerer.diagnostics


def parse_condition(text: str, base: int = 0) -> tuple[ir.Condition | None, list[Diagnostic]]:
    """Parse and lower one condition; spans are offset by `base` (where `text` starts in its
    file)."""
    tree, diagnostics = parse_condition_tree(text, base)
    if tree is None:
        return None, diagnostics
    lowerer = Lowerer(text, text_base=base)
    lead = len(text) - len(text.lstrip())
    condition = lowerer.condition(tree, Span(base + lead, base + len(text.rstrip())))
    return condition, diagnostics + lowerer.diagnostics
