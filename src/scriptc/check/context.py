"""What every semantic pass reads: the script, its source, the function registry, and tables
built once per script (blocks in execution order, the label table) so that no pass loops over
the script more than a few times (a 10,000-block script must check in well under 0.3 s).

Also small helpers the passes share: the span of a block's head, a line's indentation (for
fixes that insert a line) and did-you-mean suggestions.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from functools import cached_property

from scriptc.diagnostics.model import Fix, TextEdit
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import Block, InstructionBlock, JumpBlock, Name, Script
from scriptc.robot.profile import DEFAULT_PROFILE, Profile
from scriptc.source import SourceFile, SourceKind, Span


@dataclass(frozen=True, slots=True)
class LabelTable:
    """Non-empty labels of a script. `index` maps a label to the position (in execution
    order) of the FIRST block carrying it: a jump to a duplicated label (L001) goes there,
    which is what a reader scanning the script top-down would assume."""

    index: dict[str, int]
    names: dict[str, Name]  # the first definition of each label
    duplicates: tuple[tuple[Name, Name], ...]  # (later definition, first definition)


class Context:
    """The input of every pass. Cheap to build; tables are computed on first use."""

    def __init__(
        self, script: Script, source: SourceFile, functions: FunctionRegistry = STANDARD,
        profile: Profile | None = None, kind: SourceKind = SourceKind.SCRIPT,
    ) -> None:
        self.script = script
        self.source = source
        self.functions = functions
        # "script" or "json": fixes are text edits in script syntax, so JSON sources get none.
        self.is_script_syntax = kind == SourceKind.SCRIPT
        self.profile = profile if profile is not None else DEFAULT_PROFILE

    @cached_property
    def addressed_blocks(self) -> list[tuple[tuple[int, int, int], Block]]:
        """Every block with its (goal, action, block) address, in execution order."""
        return self.script.blocks()

    @cached_property
    def blocks(self) -> list[Block]:
        return [block for _, block in self.addressed_blocks]

    @cached_property
    def labels(self) -> LabelTable:
        index: dict[str, int] = {}
        names: dict[str, Name] = {}
        duplicates: list[tuple[Name, Name]] = []
        for i, block in enumerate(self.blocks):
            label = block.label
            if label is None or not label.text:
                continue
            first = names.get(label.text)
            if first is None:
                index[label.text] = i
                names[label.text] = label
            else:
                duplicates.append((label, first))
        return LabelTable(index, names, tuple(duplicates))

    @cached_property
    def durations(self) -> list[int | None]:
        """How long each block runs, in execution order: an instruction block's
        `duration_ms` (None when a time is not a whole number), 0 for the other blocks, which
        take no time. Computed once: flow (F002) and safety (K002, K003) read it."""
        return [b.duration_ms if isinstance(b, InstructionBlock) else 0 for b in self.blocks]

    @cached_property
    def jumps(self) -> list[tuple[int, JumpBlock]]:
        return [(i, b) for i, b in enumerate(self.blocks) if isinstance(b, JumpBlock)]

    # -- presentation helpers -----------------------------------------------------------

    def block_head(self, block: Block) -> Span:
        """The span of `[b#LABEL#blk_KIND`: short, and names the block. Falls back to the
        whole block when the text there is not script syntax (IR read from thesis JSON)."""
        text = self.source.text
        start, end = block.span.start, block.span.end
        if not text.startswith("[", start):
            # Thesis JSON: the block's span starts at its key (`"blk3"`), which names it.
            if text.startswith('"', start):
                close = text.find('"', start + 1, end)
                if close != -1:
                    return Span(start, close + 1)
            return block.span
        # Search after the label, which may itself contain `blk_`.
        after = block.label.span.end if block.label is not None else start
        i = text.find("blk_", after, end)
        if i < 0:
            return block.span
        j = i + 4
        while j < end and (text[j].isalnum() or text[j] == "_"):
            j += 1
        return Span(start, j)

    def indent_at(self, offset: int) -> str:
        """The indentation of the line holding `offset`."""
        line = self.source.line_starts[self.source.line_of(offset)]
        text = self.source.text
        j = line
        while j < len(text) and text[j] in " \t":
            j += 1
        return text[line:j]

    @cached_property
    def newline(self) -> str:
        """The line break inserted lines use: the file's own (CRLF files stay CRLF)."""
        return "\r\n" if "\r\n" in self.source.text else "\n"

    def text_of(self, span: Span) -> str:
        return self.source.text[span.start : span.end]


def suggestion(ctx: Context, best: str | None, what: str, span: Span, replacement: str | None,
               verb: str, otherwise: str) -> tuple[str, Fix | None]:
    """The help line and (for script syntax) the fix of a did-you-mean: `best` is the closest
    candidate or None, `what` names it ("a label"), `replacement` is the text that replaces
    `span` (None: `best` itself), `verb` words the fix ("jump to"), `otherwise` is the help
    when nothing is close."""
    if best is None:
        return otherwise, None
    help = f"{what} with a similar name exists: `{best}`"
    if not ctx.is_script_syntax:
        return help, None
    new = best if replacement is None else replacement
    return help, Fix(f"{verb} `{best}`", (TextEdit(span, new),), safe=False)


def closest(word: str, candidates: Iterable[str], *, cutoff: float = 0.6) -> str | None:
    """The candidate most like `word`: an exact match ignoring case first, then difflib's
    best ratio above `cutoff`. difflib is imported here so `import scriptc.check` stays cheap."""
    lowered = word.lower()
    pool = list(candidates)
    for c in pool:
        if c.lower() == lowered:
            return c
    import difflib

    matches = difflib.get_close_matches(word, pool, n=1, cutoff=cutoff)
    return matches[0] if matches else None


def code_list(items: Iterable[object]) -> str:
    """`a`, `b` and `c`."""
    quoted = [f"`{i}`" for i in items]
    if not quoted:
        return "none"
    if len(quoted) == 1:
        return quoted[0]
    return ", ".join(quoted[:-1]) + " and " + quoted[-1]
