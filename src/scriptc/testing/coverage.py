"""What the runs of tests reached of their scripts (docs/testing.md, "Coverage"): per script,
the instruction blocks issued, the outcomes of jump blocks taken (two per jump: true and
false), the goals reached and the rules fired.

A script's points come from its IR (`shape`: every block, jump, goal and rule of the script
with the line its span starts on), its hits from the runs' traces (`count`): a `block` event
is an instruction block issued, a `jump` event an outcome taken, a `goal` event recorded
`reached` a goal reached, a `rule_fire` event a rule fired. Events name their script by name;
the script's file is the one its last `script_load` names (the path a run loaded it by, as
`scriptc.paths.shown_path` shows it). Nothing is simulated again.

`Coverage` is plain data: it merges (`merge`: hits add up; a script measured in two versions
does not merge), and it round-trips through JSON (`as_data`, `from_data`: the coverage data
file of `scriptc test --coverage-data`, `schemas/coverage.schema.json`), so the coverage of a
run's shards merged is the coverage of one run of all the tests. The renderers are here too:
the summary of `--coverage` (`summary`), the points never reached (`never_reached`), the
`--fail-under` verdict (`below`) and the LCOV tracefile of `--lcov` (`lcov`). Nothing here
prints or reads a script.
"""

from __future__ import annotations

import copy
import hashlib
import json
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from scriptc.diagnostics.render import plural
from scriptc.ir import nodes as ir
from scriptc.numbers import json_dumps
from scriptc.paths import shown_path
from scriptc.runtime.interp import message_of
from scriptc.runtime.trace import Event
from scriptc.source import SourceFile

__all__ = [
    "FORMAT",
    "KINDS",
    "Block",
    "Coverage",
    "Goal",
    "Jump",
    "Rule",
    "ScriptCoverage",
    "below",
    "count",
    "digest",
    "from_data",
    "is_data",
    "lcov",
    "loaded_paths",
    "merge",
    "merge_data",
    "merge_lcov",
    "never_reached",
    "read_data",
    "script_key",
    "shape",
    "summary",
]

# What a coverage data file says it is (its `format`), and the version of its layout.
FORMAT = "scriptc-coverage"
VERSION = 1
# The kinds of point, in the order the summary shows them, with their names for people.
KINDS = ("blocks", "outcomes", "goals", "rules")
KIND_NAMES = {"blocks": "blocks", "outcomes": "jump outcomes", "goals": "goals",
              "rules": "rules"}
# The message actions that put a rule in the chain: a script's rules are those it names so.
_JOINING = ("A", "B", "C")


@dataclass(slots=True)
class Block:
    """An instruction block: its path (`goal0/act0/blk0`), label ("" without one), line and
    how many times it was issued."""

    path: str
    label: str
    line: int
    hits: int = 0

    def named(self) -> str:
        return f"block `{self.label}`" if self.label else f"block {self.path}"


@dataclass(slots=True)
class Jump:
    """A jump block: its path, label, line, and how many times each outcome was taken."""

    path: str
    label: str
    line: int
    true: int = 0
    false: int = 0

    def named(self) -> str:
        return f"jump `{self.label}`" if self.label else f"jump {self.path}"


@dataclass(slots=True)
class Goal:
    """A goal: its id, line (its `[goal:ID]`) and how many times it was recorded reached."""

    id: str
    line: int
    hits: int = 0


@dataclass(slots=True)
class Rule:
    """A rule the script puts in the chain (an `A`, `B` or `C` message): its id, rulecode,
    line (its first such message) and how many times it fired."""

    id: str
    rulecode: int
    line: int
    hits: int = 0


@dataclass(slots=True)
class ScriptCoverage:
    """One script's points and hits: `path` as shown (relative to the working folder, with
    forward slashes), its `name`, the `digest` of its text (two versions of a script never
    merge), and its points in the file's order."""

    path: str
    name: str
    digest: str
    blocks: list[Block] = field(default_factory=list)
    jumps: list[Jump] = field(default_factory=list)
    goals: list[Goal] = field(default_factory=list)
    rules: list[Rule] = field(default_factory=list)

    def totals(self) -> dict[str, tuple[int, int]]:
        """(reached, total) of each kind of point (`KINDS`)."""
        outcomes = sum((j.true > 0) + (j.false > 0) for j in self.jumps)
        return {"blocks": (sum(b.hits > 0 for b in self.blocks), len(self.blocks)),
                "outcomes": (outcomes, 2 * len(self.jumps)),
                "goals": (sum(g.hits > 0 for g in self.goals), len(self.goals)),
                "rules": (sum(r.hits > 0 for r in self.rules), len(self.rules))}

    def add(self, other: ScriptCoverage) -> None:
        """Add the hits of `other`, the same script measured elsewhere."""
        for block, theirs in zip(self.blocks, other.blocks, strict=True):
            block.hits += theirs.hits
        for goal, their_goal in zip(self.goals, other.goals, strict=True):
            goal.hits += their_goal.hits
        for rule, their_rule in zip(self.rules, other.rules, strict=True):
            rule.hits += their_rule.hits
        for j, k in zip(self.jumps, other.jumps, strict=True):
            j.true += k.true
            j.false += k.false


@dataclass(slots=True)
class Coverage:
    """The coverage of a run: each script's (by `path`, in order of the paths) and how many
    tests ran to measure it."""

    scripts: dict[str, ScriptCoverage] = field(default_factory=dict)
    tests: int = 0

    def totals(self) -> dict[str, tuple[int, int]]:
        """(reached, total) of each kind of point over every script."""
        out = dict.fromkeys(KINDS, (0, 0))
        for script in self.scripts.values():
            for kind, (reached, total) in script.totals().items():
                out[kind] = (out[kind][0] + reached, out[kind][1] + total)
        return out

    def as_data(self) -> dict[str, Any]:
        """The coverage data file's content (`schemas/coverage.schema.json`)."""
        return {"format": FORMAT, "version": VERSION, "tests": self.tests, "scripts": [
            {"path": s.path, "name": s.name, "digest": s.digest,
             "blocks": [{"path": b.path, "label": b.label, "line": b.line, "hits": b.hits}
                        for b in s.blocks],
             "jumps": [{"path": j.path, "label": j.label, "line": j.line, "true": j.true,
                        "false": j.false} for j in s.jumps],
             "goals": [{"id": g.id, "line": g.line, "hits": g.hits} for g in s.goals],
             "rules": [{"id": r.id, "rulecode": r.rulecode, "line": r.line, "hits": r.hits}
                       for r in s.rules]}
            for s in (self.scripts[p] for p in sorted(self.scripts))]}

    def text(self) -> str:
        """The coverage data file's text: JSON, indented, ending with a newline; the same
        coverage gives the same bytes."""
        return json_dumps(self.as_data(), indent=1, ensure_ascii=False) + "\n"


# -- measuring -----------------------------------------------------------------------------------


def script_key(path: str) -> str:
    """The name of a script's file in coverage: as shown (`shown_path`: relative to the
    working folder when inside it), with forward slashes, as LCOV readers take it."""
    shown = shown_path(path)
    return shown.replace(os.sep, "/") if os.sep != "/" else shown


def digest(text: str) -> str:
    return "sha256:" + hashlib.sha256(text.encode("utf-8")).hexdigest()


def shape(script: ir.Script, source: SourceFile, path: str) -> ScriptCoverage:
    """The points of `script` (read from `source`) with no hits, named by `path`."""

    def line(span_start: int) -> int:
        return source.line_of(span_start) + 1

    out = ScriptCoverage(script_key(path), script.name.text, digest(source.text))
    for address, block in script.blocks():
        where = ir.block_path(address)
        label = block.label.text if block.label is not None else ""
        if isinstance(block, ir.InstructionBlock):
            out.blocks.append(Block(where, label, line(block.span.start)))
        elif isinstance(block, ir.JumpBlock):
            out.jumps.append(Jump(where, label, line(block.span.start)))
    seen: set[str] = set()
    for goal in script.goals:
        if goal.id.text not in seen:  # goal records are by id: one point an id
            seen.add(goal.id.text)
            out.goals.append(Goal(goal.id.text, line(goal.span.start)))
    seen.clear()
    for message in (*script.alfa, *script.omega):
        if message.action.text in _JOINING and message.id.text not in seen:
            seen.add(message.id.text)
            # The rulecode as the run reads it.
            out.rules.append(Rule(message.id.text, message_of(message).rulecode,
                                  line(message.span.start)))
    return out


def loaded_paths(events: Iterable[Event]) -> list[str]:
    """The files a run loaded scripts from (its `script_load` events), in order, once each;
    the built-in idle activity has none."""
    seen: dict[str, None] = {}
    for e in events:
        if e["event"] == "script_load" and e["path"]:
            seen.setdefault(str(e["path"]), None)
    return list(seen)


def count(coverage: Coverage, events: Iterable[Event]) -> None:
    """Add the hits of one run's trace to the scripts of `coverage` it loaded (a script
    `coverage` does not have is not measured)."""
    files: dict[str, ScriptCoverage | None] = {}  # script name -> its coverage
    blocks: dict[tuple[int, str], Block] = {}
    jumps: dict[tuple[int, str], Jump] = {}
    goals: dict[tuple[int, str], Goal] = {}
    rules: dict[tuple[int, str], Rule] = {}
    indexed: set[int] = set()

    def index(script: ScriptCoverage) -> None:
        key = id(script)
        if key not in indexed:
            indexed.add(key)
            blocks.update(((key, b.path), b) for b in script.blocks)
            jumps.update(((key, j.path), j) for j in script.jumps)
            goals.update(((key, g.id), g) for g in script.goals)
            rules.update(((key, r.id), r) for r in script.rules)

    for e in events:
        kind = e["event"]
        if kind == "script_load":
            script = coverage.scripts.get(script_key(str(e["path"]))) if e["path"] else None
            files[str(e["script"])] = script
            if script is not None:
                index(script)
            continue
        if kind not in ("block", "jump", "goal", "rule_fire"):
            continue
        script = files.get(str(e["script"]))
        if script is None:
            continue
        key = id(script)
        if kind == "block":
            block = blocks.get((key, str(e["path"])))
            if block is not None:
                block.hits += 1
        elif kind == "jump":
            jump = jumps.get((key, str(e["path"])))
            if jump is not None:
                if e["value"]:
                    jump.true += 1
                else:
                    jump.false += 1
        elif kind == "goal":
            goal = goals.get((key, str(e["goalid"])))
            if goal is not None and e["record"] == "reached":
                goal.hits += 1
        else:
            rule = rules.get((key, str(e["id"])))
            if rule is not None:
                rule.hits += 1


# -- merging and the data file ---------------------------------------------------------------------


def merge(parts: Iterable[tuple[str, Coverage]]) -> Coverage:
    """The coverage of every part together (`(name, coverage)`: the name for messages): the
    hits of a script measured in several add up, and so do the tests. Raises ValueError when
    two parts measured different versions of a script."""
    out = Coverage()
    first: dict[str, str] = {}
    for name, part in parts:
        out.tests += part.tests
        for path, script in part.scripts.items():
            mine = out.scripts.get(path)
            if mine is None:
                out.scripts[path] = copy.deepcopy(script)
                first[path] = name
            elif mine.digest != script.digest or not _same_points(mine, script):
                raise ValueError(f"`{first[path]}` and `{name}` measured different versions of "
                                 f"`{path}`: merge the coverage of runs of the same scripts")
            else:
                mine.add(script)
    out.scripts = {p: out.scripts[p] for p in sorted(out.scripts)}
    return out


def _same_points(a: ScriptCoverage, b: ScriptCoverage) -> bool:
    return ([(x.path, x.line) for x in a.blocks] == [(x.path, x.line) for x in b.blocks]
            and [(x.path, x.line) for x in a.jumps] == [(x.path, x.line) for x in b.jumps]
            and [x.id for x in a.goals] == [x.id for x in b.goals]
            and [x.id for x in a.rules] == [x.id for x in b.rules])


def is_data(data: bytes) -> bool:
    """Whether a file's bytes are coverage data (JSON whose `format` is ours)."""
    try:
        value = json.loads(data)
    except (ValueError, RecursionError):
        return False
    return isinstance(value, dict) and value.get("format") == FORMAT


def from_data(data: Any, name: str) -> Coverage:
    """Coverage from a coverage data file's JSON value; ValueError (naming `name` and what is
    wrong where) when it is not coverage data of this version."""

    def fail(where: str, what: str) -> ValueError:
        return ValueError(f"`{name}` is not scriptc coverage data: {where} {what}")

    def whole(value: Any, where: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise fail(where, "must be a whole number, 0 or more")
        return value

    def text(value: Any, where: str) -> str:
        if not isinstance(value, str):
            raise fail(where, "must be a text")
        return value

    def items(value: Any, where: str) -> list[dict[str, Any]]:
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise fail(where, "must be a list of tables")
        return value

    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise fail("its `format`", f"must be \"{FORMAT}\"")
    if data.get("version") != VERSION:
        raise ValueError(f"`{name}` is scriptc coverage data of version {data.get('version')}"
                         f", and this scriptc reads version {VERSION}: write it again with this "
                         "scriptc")
    out = Coverage(tests=whole(data.get("tests"), "`tests`"))
    for i, s in enumerate(items(data.get("scripts"), "`scripts`")):
        at = f"`scripts[{i}]"
        script = ScriptCoverage(text(s.get("path"), at + ".path`"),
                                text(s.get("name"), at + ".name`"),
                                text(s.get("digest"), at + ".digest`"))
        for k, b in enumerate(items(s.get("blocks"), at + ".blocks`")):
            w = f"{at}.blocks[{k}]"
            script.blocks.append(Block(text(b.get("path"), w + ".path`"),
                                       text(b.get("label"), w + ".label`"),
                                       whole(b.get("line"), w + ".line`"),
                                       whole(b.get("hits"), w + ".hits`")))
        for k, j in enumerate(items(s.get("jumps"), at + ".jumps`")):
            w = f"{at}.jumps[{k}]"
            script.jumps.append(Jump(text(j.get("path"), w + ".path`"),
                                     text(j.get("label"), w + ".label`"),
                                     whole(j.get("line"), w + ".line`"),
                                     whole(j.get("true"), w + ".true`"),
                                     whole(j.get("false"), w + ".false`")))
        for k, g in enumerate(items(s.get("goals"), at + ".goals`")):
            w = f"{at}.goals[{k}]"
            script.goals.append(Goal(text(g.get("id"), w + ".id`"),
                                     whole(g.get("line"), w + ".line`"),
                                     whole(g.get("hits"), w + ".hits`")))
        for k, r in enumerate(items(s.get("rules"), at + ".rules`")):
            w = f"{at}.rules[{k}]"
            script.rules.append(Rule(text(r.get("id"), w + ".id`"),
                                     whole(r.get("rulecode"), w + ".rulecode`"),
                                     whole(r.get("line"), w + ".line`"),
                                     whole(r.get("hits"), w + ".hits`")))
        if script.path in out.scripts:
            raise fail(at + "`", f"names `{script.path}` a second time")
        out.scripts[script.path] = script
    return out


def read_data(inputs: Sequence[tuple[str, bytes]]) -> list[tuple[str, Coverage]]:
    """Coverage data files' contents (`(name, bytes)`) as coverage; ValueError for one that
    is not."""
    out = []
    for name, data in inputs:
        try:
            value = json.loads(data)
        except (ValueError, RecursionError) as exc:
            raise ValueError(f"`{name}` is not scriptc coverage data: not JSON ({exc})") \
                from None
        out.append((name, from_data(value, name)))
    return out


def merge_data(inputs: Sequence[tuple[str, bytes]]) -> tuple[str, list[str]]:
    """`scriptc merge OUT.json DATA...`: coverage data files merged into one (the text to
    write, and no notes); ValueError for an input that is not coverage data, or for inputs
    that measured different versions of a script."""
    return merge(read_data(inputs)).text(), []


def merge_lcov(inputs: Sequence[tuple[str, bytes]]) -> tuple[str, list[str]]:
    """`scriptc merge OUT.info DATA...`: coverage data files merged into an LCOV tracefile."""
    return lcov(merge(read_data(inputs))), []


# -- what people and tools read ------------------------------------------------------------------


def _percent(reached: int, total: int) -> str:
    """`83.3%`, rounded down (100.0% only when everything was reached); `-` for nothing."""
    if total == 0:
        return "-"
    tenths = reached * 1000 // total
    return f"{tenths // 10}.{tenths % 10}%"


def summary(coverage: Coverage) -> str:
    """The table of `--coverage`: each script's share of each kind of point, and the total,
    then the points never reached."""
    header = ["script", *(KIND_NAMES[k] for k in KINDS)]
    rows = [header]
    for script in coverage.scripts.values():
        totals = script.totals()
        rows.append([script.path, *(_cell(*totals[k]) for k in KINDS)])
    if len(coverage.scripts) > 1:
        totals = coverage.totals()
        rows.append(["total", *(_cell(*totals[k]) for k in KINDS)])
    widths = [max(len(row[i]) for row in rows) for i in range(len(header))]
    scripts, tests = plural(len(coverage.scripts), "script"), plural(coverage.tests, "test")
    lines = [f"coverage of {scripts} by {tests}:"]
    for row in rows:
        cells = [row[0].ljust(widths[0])] + [c.rjust(w) for c, w in zip(row[1:], widths[1:],
                                                                          strict=True)]
        lines.append("  " + "  ".join(cells).rstrip())
    lines += never_reached(coverage)
    return "\n".join(lines) + "\n"


def _cell(reached: int, total: int) -> str:
    return f"{reached}/{total} {_percent(reached, total)}" if total else "-"


def never_reached(coverage: Coverage) -> list[str]:
    """`never reached: block `hello` (greeting.script:12)`: every point no run reached, by
    script and line."""
    out = []
    for s in coverage.scripts.values():
        found: list[tuple[int, str]] = []
        found += [(b.line, f"never reached: {b.named()}") for b in s.blocks if not b.hits]
        for j in s.jumps:
            if not j.true and not j.false:
                found.append((j.line, f"never reached: {j.named()}"))
            elif not j.true or not j.false:
                outcome = "true" if not j.true else "false"
                found.append((j.line, f"never taken: the {outcome} outcome of {j.named()}"))
        found += [(g.line, f"never reached: goal `{g.id}`") for g in s.goals if not g.hits]
        found += [(r.line, f"never fired: rule `{r.id}`") for r in s.rules if not r.hits]
        out += [f"{what} ({s.path}:{line})" for line, what in sorted(found,
                                                                      key=lambda f: f[0])]
    return out


def below(coverage: Coverage, percent: float) -> list[str]:
    """What is under `percent` of the blocks and of the jump outcomes, over every script
    (`--fail-under`); nothing when both reach it. A kind with nothing to reach is complete."""
    out = []
    totals = coverage.totals()
    for kind in ("blocks", "outcomes"):
        reached, total = totals[kind]
        if total and reached * 100 < percent * total:
            out.append(f"{KIND_NAMES[kind]} {_percent(reached, total)} ({reached} of {total})")
    return out


def lcov(coverage: Coverage) -> str:
    """The LCOV tracefile of `--lcov`, a record per script (`SF`): its goals as functions
    (`FN`, `FNDA`, `FNF`, `FNH`), each jump block's two outcomes as branches (`BRDA:line,jump,
    0 true / 1 false,taken`, `-` for a jump never reached; `BRF`, `BRH`), its instruction
    blocks by line (`DA`, the hits of every block on the line; `LF`, `LH`)."""
    out = ["TN:"]
    for s in coverage.scripts.values():
        out.append(f"SF:{s.path}")
        for g in s.goals:
            out.append(f"FN:{g.line},{g.id}")
        for g in s.goals:
            out.append(f"FNDA:{g.hits},{g.id}")
        out += [f"FNF:{len(s.goals)}", f"FNH:{sum(g.hits > 0 for g in s.goals)}"]
        taken = 0
        for i, j in enumerate(s.jumps):
            reached = j.true or j.false
            for branch, hits in ((0, j.true), (1, j.false)):
                out.append(f"BRDA:{j.line},{i},{branch},{hits if reached else '-'}")
                taken += hits > 0
        out += [f"BRF:{2 * len(s.jumps)}", f"BRH:{taken}"]
        lines: dict[int, int] = {}
        for b in s.blocks:
            lines[b.line] = lines.get(b.line, 0) + b.hits
        out += [f"DA:{line},{hits}" for line, hits in sorted(lines.items())]
        out += [f"LF:{len(lines)}", f"LH:{sum(h > 0 for h in lines.values())}", "end_of_record"]
    return "\n".join(out) + "\n"
