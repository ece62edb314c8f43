"""Mutation fuzzing of every entry point, in-process, with the laws that must hold for any input.

The inputs are the real examples (examples/*.script, examples/*.world.json, tests/data/*.json
and a configuration), mutated as hostile input mutates files: bytes flipped, text cut short or
deleted, brackets and quotes inserted, NUL, a byte order mark, CRLF and lone CR line endings,
invalid UTF-8, a 1 MB line, 10,000 nested brackets, numbers made huge or non-finite, names
made keywords. Each entry point takes the mutated bytes as its command would and holds its
laws:

- `lint`: the front end and the checks never raise; every position is inside the text; every
  renderer (text, json, sarif, github) renders, the JSON ones strict JSON (no NaN, no Infinity);
- `compile`: what passes compiles to JSON (strict) and to bytecode that loads (decoded and
  verified); compile -> decompile -> compile gives the same JSON, byte for byte;
- `fmt`: the formatter refuses or formats; formatting is idempotent and keeps the compiled JSON;
- `fix`: applying the safe fixes, re-linting after each round, reaches a fixpoint (no safe
  fix left) within `scriptc lint --fix`'s rounds;
- `run`: what passes runs (kinematic robot, a short `until`, the example's scenario) on the
  reference interpreter and on the VM with the same trace, line for line; ungoverned and
  governed; traces and the `--json` summary strict JSON;
- `check`: thesis JSON is read (J codes) or refused, never raises; what `check` accepts
  decompiles to a script that compiles to the JSON `check`'s script compiles to;
- `scenario`: a scenario file is read or refused with every problem at a line and column;
  what is read runs (both executors, the same trace);
- `config`: a configuration is read with every problem inside the file; every function it
  declares is one the run time registers (the name rule is one fact);
- `editor`: the language server's library opens the text and follows a few edits; the
  incremental analysis equals a fresh one after each, and every feature answers.

The randomness comes from one function, `pick(lo, hi)` (an integer in [lo, hi]): hypothesis
draws it in the suite (tests/test_fuzz.py, so failures shrink and replay), `random.Random` in
the long campaign (bench/fuzz.py). A broken law raises `LawBroken`; `classify` turns any
exception into a failure class (`entry: law` or `entry: crash ExcType at file:function`), which
the campaign counts.
"""

from __future__ import annotations

import json
import re
import tempfile
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

Pick = Callable[[int, int], int]


class LawBroken(AssertionError):
    """A law of an entry point does not hold for an input. `law` names it (the failure class)."""

    def __init__(self, law: str, detail: str = "") -> None:
        self.law = law
        super().__init__(f"{law}: {detail}" if detail else law)


def _law(condition: bool, law: str, detail: str = "") -> None:
    if not condition:
        raise LawBroken(law, detail)


# ---------------------------------------------------------------------------------------------
# Seeds: the real examples


def _read(paths) -> list[tuple[str, bytes]]:
    return [(p.name, p.read_bytes()) for p in sorted(paths)]


SEEDS: dict[str, list[tuple[str, bytes]]] = {
    "script": _read(EXAMPLES.glob("*.script")),
    "json": _read((ROOT / "tests" / "data").glob("*.json")),
    "scenario": _read(EXAMPLES.glob("*.world.json")),
    "config": _read([ROOT / "tests" / "cases" / "config" / "valid.toml",
                     ROOT / "tests" / "cases" / "config" / "forms.toml"]),
}


# ---------------------------------------------------------------------------------------------
# Mutations: each takes the bytes and `pick`, returns new bytes. `scale` shrinks the large
# payloads (the suite's short run uses a fraction of a megabyte).

_TOKENS = [b"[", b"]", b"(", b")", b"{", b"}", b'"', b"'", b"%", b"#", b",", b":", b"\\",
           b"\x00", b"\n", b"\r", b"\t", b" ", b"!", b"?THIS", b"@", b"$", b">&", b"OP<",
           b"\xc3\xa9", b"\xf0\x9f\x98\x80", b"\xe2\x80\xae"]
_INVALID_UTF8 = [b"\xff", b"\xc3", b"\xed\xa0\x80", b"\xe2\x82", b"\x80", b"\xf8\x88\x80\x80\x80"]
_NUMBERS = [b"9" * 5000, b"-" + b"9" * 400, b"1e999", b"-1e400", b"1e308", b"-1e308",
            b"5e-324", b"1e-400", b"NaN", b"Infinity", b"-Infinity", b"nan", b"inf", b"-inf",
            b"3.5e38", b"2147483648", b"4294967296", b"-1", b"0.0", b"1" * 20]
_WORDS = [b"action", b"alfa", b"omega", b"goal", b"b", b"TRUE", b"CLASS", b"E", b"MV", b"x-y",
          b"9lives", b"", b"wave-hands", b"kick_starter", b"a b", b"\xc3\xa9t\xc3\xa9"]
_NUMBER_RE = re.compile(rb"-?[0-9]+(?:\.[0-9]+)?(?:[eE][+-]?[0-9]+)?")
_WORD_RE = re.compile(rb"[A-Za-z_][A-Za-z0-9_-]*")


def _at(data: bytes, pick: Pick) -> int:
    return pick(0, len(data))


def _flip(data: bytes, pick: Pick, scale: float) -> bytes:
    if not data:
        return data
    i = pick(0, len(data) - 1)
    return data[:i] + bytes([data[i] ^ (1 << pick(0, 7))]) + data[i + 1:]


def _truncate(data: bytes, pick: Pick, scale: float) -> bytes:
    return data[:_at(data, pick)]


def _delete(data: bytes, pick: Pick, scale: float) -> bytes:
    i = _at(data, pick)
    return data[:i] + data[i + pick(1, 64):]


def _duplicate(data: bytes, pick: Pick, scale: float) -> bytes:
    i = _at(data, pick)
    j = min(len(data), i + pick(1, 200))
    return data[:j] + data[i:j] + data[j:]


def _insert_token(data: bytes, pick: Pick, scale: float) -> bytes:
    i = _at(data, pick)
    return data[:i] + _TOKENS[pick(0, len(_TOKENS) - 1)] * pick(1, 3) + data[i:]


def _bom(data: bytes, pick: Pick, scale: float) -> bytes:
    return b"\xef\xbb\xbf" + data


def _line_endings(data: bytes, pick: Pick, scale: float) -> bytes:
    return data.replace(b"\n", [b"\r\n", b"\r", b"\n\r"][pick(0, 2)])


def _invalid_utf8(data: bytes, pick: Pick, scale: float) -> bytes:
    i = _at(data, pick)
    return data[:i] + _INVALID_UTF8[pick(0, len(_INVALID_UTF8) - 1)] + data[i:]


def _long_line(data: bytes, pick: Pick, scale: float) -> bytes:
    i = _at(data, pick)
    filler = [b"x", b"0", b" ", b"[", b"%"][pick(0, 4)]
    return data[:i] + filler * max(1, int(1_000_000 * scale)) + data[i:]


def _nested(data: bytes, pick: Pick, scale: float) -> bytes:
    i = _at(data, pick)
    opener, closer = [(b"[", b"]"), (b"{", b"}"), (b"(", b")")][pick(0, 2)]
    depth = 10_000
    closed = pick(0, 1)
    return data[:i] + opener * depth + (closer * depth if closed else b"") + data[i:]


def _replace_match(data: bytes, pick: Pick, pattern: re.Pattern, choices: list[bytes]) -> bytes:
    matches = list(pattern.finditer(data))
    if not matches:
        i = _at(data, pick)
        return data[:i] + choices[pick(0, len(choices) - 1)] + data[i:]
    m = matches[pick(0, len(matches) - 1)]
    return data[:m.start()] + choices[pick(0, len(choices) - 1)] + data[m.end():]


def _number(data: bytes, pick: Pick, scale: float) -> bytes:
    return _replace_match(data, pick, _NUMBER_RE, _NUMBERS)


def _word(data: bytes, pick: Pick, scale: float) -> bytes:
    return _replace_match(data, pick, _WORD_RE, _WORDS)


MUTATIONS: dict[str, Callable[[bytes, Pick, float], bytes]] = {
    "flip": _flip, "truncate": _truncate, "delete": _delete, "duplicate": _duplicate,
    "token": _insert_token, "bom": _bom, "line-endings": _line_endings,
    "invalid-utf8": _invalid_utf8, "long-line": _long_line, "nested": _nested,
    "number": _number, "word": _word,
}
# The cheap mutations come up more often: most inputs stay near a real file.
_WEIGHTED = (["flip", "token", "delete", "number", "word", "duplicate", "truncate"] * 3
             + ["bom", "line-endings", "invalid-utf8", "long-line", "nested"])


def mutate(data: bytes, pick: Pick, scale: float = 1.0) -> bytes:
    """One to three mutations of `data`."""
    for _ in range(pick(1, 3)):
        data = MUTATIONS[_WEIGHTED[pick(0, len(_WEIGHTED) - 1)]](data, pick, scale)
    return data


# ---------------------------------------------------------------------------------------------
# Laws shared by the entry points


def _strict_json(text: str, law: str) -> object:
    def refuse(word: str) -> object:
        raise LawBroken(law, f"{word} in JSON output")

    try:
        return json.loads(text, parse_constant=refuse)
    except ValueError as exc:
        raise LawBroken(law, f"not JSON: {exc}") from None


def _positions(source, diagnostics, entry: str) -> None:
    n = len(source.text)
    for d in diagnostics:
        spans = [d.span, *(label.span for label in d.labels)]
        for span in spans:
            _law(0 <= span.start <= span.end <= n, f"{entry}: a position outside the text",
                 f"{d.code} {span}")
        _law(bool(d.message) and bool(d.code), f"{entry}: a diagnostic without message")


def _render_all(source, diagnostics, entry: str) -> None:
    from scriptc.diagnostics.render import render

    results = [(source, diagnostics)]
    render("text", results)
    render("text", results, color=True)
    render("github", results)
    _strict_json(render("json", results), f"{entry}: the json renderer writes strict JSON")
    _strict_json(render("sarif", results), f"{entry}: the sarif renderer writes strict JSON")


def _analysis(data: bytes, kind: str = "script"):
    from scriptc.analysis.analyze import analyze_bytes

    analysis = analyze_bytes(f"fuzz.{'script' if kind == 'script' else 'json'}", data, kind)
    entry = "lint" if kind == "script" else "check"
    _positions(analysis.source, analysis.diagnostics, entry)
    return analysis


def _compiled(text: str) -> str | None:
    from scriptc.analysis.analyze import analyze_script
    from scriptc.emit.json import emit_json
    from scriptc.source import SourceFile

    analysis = analyze_script(SourceFile("again.script", text))
    return emit_json(analysis.script) if analysis.ok else None


# ---------------------------------------------------------------------------------------------
# Entry points: each takes the bytes of one file


def lint(data: bytes) -> None:
    analysis = _analysis(data)
    _render_all(analysis.source, analysis.diagnostics, "lint")


def compile_(data: bytes) -> None:
    from scriptc import bytecode
    from scriptc.emit.script import format_script
    from scriptc.frontend.thesis_json import script_from_json
    from scriptc.ops.build import emit
    from scriptc.source import SourceFile

    analysis = _analysis(data)
    if not analysis.ok:
        return
    first = emit(analysis.script, "json")
    _strict_json(first, "compile: strict JSON")
    bytecode.load(emit(analysis.script, "bytecode", analysis.source))
    read, problems = script_from_json(SourceFile("compiled.json", first))
    _law(read is not None and not [p for p in problems if p.severity.value == "error"],
         "compile: its JSON is read back", str([p.message for p in problems][:3]))
    second = _compiled(format_script(read))
    _law(second == first, "compile: compile -> decompile -> compile is the identity")


def fmt(data: bytes) -> None:
    from scriptc.formatter import format_text

    analysis = _analysis(data)
    if analysis.script is None and any(d.code == "P007" for d in analysis.diagnostics):
        return  # not UTF-8: `scriptc fmt` refuses to read it
    text = analysis.source.text
    result = format_text(text)
    if result.refused:
        _law(bool(result.diagnostics), "fmt: a refusal says why")
        return
    again = format_text(result.text)
    _law(again.text == result.text, "fmt: formatting is idempotent")
    if analysis.ok:
        _law(_compiled(result.text) == _compiled(text),
             "fmt: formatting keeps the compiled JSON")


def fix(data: bytes) -> None:
    from scriptc.analysis.analyze import analyze_script
    from scriptc.diagnostics.edits import apply_fixes
    from scriptc.ops.lint import MAX_FIX_ROUNDS
    from scriptc.source import SourceFile

    analysis = _analysis(data)
    if analysis.script is None and any(d.code == "P007" for d in analysis.diagnostics):
        return
    text, diagnostics = analysis.source.text, analysis.diagnostics
    for _round in range(MAX_FIX_ROUNDS):
        fixes = [d.fix for d in diagnostics if d.fix is not None and d.fix.safe]
        if not fixes:
            return
        new_text, applied = apply_fixes(text, fixes)
        if not applied or new_text == text:
            return
        text = new_text
        diagnostics = analyze_script(SourceFile("fixed.script", text)).diagnostics
        _positions(SourceFile("fixed.script", text), diagnostics, "fix")
    left = [d.code for d in diagnostics if d.fix is not None and d.fix.safe]
    _law(not left, "fix: --fix reaches a fixpoint", f"safe fixes left after "
         f"{MAX_FIX_ROUNDS} rounds: {left[:5]}")


UNTIL = 1500  # ms of simulated time: long enough for the examples' first blocks and updates


def _traces(script, source, scenario, profile=None) -> tuple[list[str], list[str], object]:
    from scriptc import bytecode
    from scriptc.ops.build import emit
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.session import Session
    from scriptc.runtime.trace import Trace
    from scriptc.runtime.vm import VMProgram

    texts, result = [], None
    programs = [IRProgram(script, "fuzz.script"),
                VMProgram(bytecode.load(emit(script, "bytecode", source)), "fuzz.script")]
    for program in programs:
        trace = Trace()
        result = Session([program], scenario=scenario, trace=trace, robot="kinematic",
                         profile=profile).run(UNTIL)
        texts.append(trace.text().splitlines())
    return texts[0], texts[1], result


def _run_law(script, source, scenario, entry: str) -> None:
    from scriptc.project.config import Settings
    from scriptc.runtime.summary import summary_json

    for profile in (None, Settings().robot):
        ir_trace, vm_trace, result = _traces(script, source, scenario, profile)
        _law(ir_trace == vm_trace, f"{entry}: VM = interpreter",
             # Not strict: past the shorter trace, the message says the lengths differ.
             next((f"{a}\n!=\n{b}" for a, b in zip(ir_trace, vm_trace, strict=False) if a != b),
                  "traces of different lengths"))
        for line in ir_trace:
            _strict_json(line, f"{entry}: traces are strict JSON")
        _strict_json(summary_json(result), f"{entry}: --json is strict JSON")


def _world_of(name: str) -> bytes | None:
    world = EXAMPLES / name.replace(".script", ".world.json")
    return world.read_bytes() if world.exists() else None


def run(data: bytes, world: bytes | None = None) -> None:
    from scriptc.runtime.scenario import scenario_from_text

    analysis = _analysis(data)
    if not analysis.ok:
        return
    scenario = scenario_from_text(world.decode("utf-8"), "w.json") if world else None
    _run_law(analysis.script, analysis.source, scenario, "run")


def check(data: bytes) -> None:
    from scriptc.emit.json import emit_json
    from scriptc.emit.script import format_script

    analysis = _analysis(data, "json")
    _render_all(analysis.source, analysis.diagnostics, "check")
    if analysis.script is None:
        return
    text = format_script(analysis.script)  # `decompile` writes it even with errors
    if analysis.ok:
        _law(_compiled(text) == emit_json(analysis.script),
             "check: what check accepts decompiles to a script that compiles to its JSON")


_SCENARIO_SCRIPT = EXAMPLES / "approach.script"


def scenario(data: bytes) -> None:
    from scriptc.analysis.analyze import analyze_file
    from scriptc.runtime.scenario import ScenarioError, scenario_from_text
    from scriptc.source import SourceFile

    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return  # load_scenario refuses it, with the byte's place (tests/test_runtime.py)
    try:
        world = scenario_from_text(text, "fuzz.world.json")
    except ScenarioError as exc:
        _law(bool(exc.problems) and all(p is not None for p in exc.positions),
             "scenario: every problem has a line and a column", str(exc.lines()[:3]))
        lines = len(SourceFile("w.json", text).line_starts)
        _law(all(1 <= p[0] <= lines for p in exc.positions if p is not None),
             "scenario: positions are in the file")
        return
    analysis = analyze_file(_SCENARIO_SCRIPT)
    _run_law(analysis.script, analysis.source, world, "scenario")


def config(data: bytes) -> None:
    from scriptc.project.config import load_config
    from scriptc.project.setup import Setup
    from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "scriptc.toml"
        path.write_bytes(data)
        loaded = load_config(str(path))
    _positions(loaded.source, loaded.diagnostics, "config")
    _render_all(loaded.source, loaded.diagnostics, "config")
    impls = STANDARD_IMPLEMENTATIONS.extended()
    for function in loaded.settings.functions:
        try:
            impls.register(function.name, function.kind, function.arity, lambda call, *a: True,
                           params=tuple(function.params))
        except ValueError as exc:
            raise LawBroken("config: what the configuration accepts, the run time registers",
                            str(exc)) from None
    Setup(loaded.settings)  # building the setup (the registry, the profile) must not raise


# Text an editor types: tokens of both grammars, line ends, non-ASCII (two-unit emoji too),
# lone surrogates and NUL (what a UTF-16 client that split a pair sends).
_TYPED = ["[", "]", "#", "(", ")", "{", "}", '"', "%", ",", ":", "!", "?", " ", "\n", "\r\n",
          "\r", "a", "0", ".5", "1e999", "é", "😀", "\ud83d", "\x00", "b##", "blk_jump",
          "TRJMP(", "CND(! {TRUE})", "MV() LD() AO()", "[b##blk_terminus]", "[action]",
          "[goal:g]", "?THIS>&positionrho", "% scriptc: ignore[F001] %"]


def editor(data: bytes) -> None:
    """The language server's library (`scriptc.ide`), as a session drives it: the mutated text
    opened as a document, then edited a few times (insertions, deletions, replacements drawn
    from the bytes themselves, so an input replays); after each edit the incremental analysis
    equals a fresh one of the document's text, and every feature answers at several offsets
    (hover, completion, definition, references, rename, symbols, folding, semantic tokens,
    inlay hints, code actions, formatting) without raising."""
    import random
    import zlib

    from scriptc.analysis.analyze import analyze_script
    from scriptc.ide.document import Document
    from scriptc.source import SourceFile, Span

    rng = random.Random(zlib.crc32(data))
    doc = Document("file:///fuzz.script", data.decode("utf-8", errors="replace"),
                   path="fuzz.script")
    # A megabyte of text costs seconds per analysis (linear, but a million items): fewer
    # edits keep such an input under the campaign's `--slow`.
    for step in range(5 if len(data) < 100_000 else 2):
        if step:
            n = len(doc.text)
            start = rng.randint(0, n)
            end = min(n, start + rng.choice((0, 0, 1, 3, 20)))
            doc.replace(start, end, rng.choice(_TYPED) if rng.random() < 0.8 else "")
        snapshot = doc.snapshot()
        layout = snapshot.layout
        real = [(d.code, layout.to_real(d.span.start), layout.to_real(d.span.end))
                for d in snapshot.diagnostics]
        fresh = [(d.code, d.span.start, d.span.end)
                 for d in analyze_script(SourceFile(doc.path, doc.text)).diagnostics]
        _law(real == fresh, "editor: incremental analysis equals a fresh one",
             f"after {step} edits")
        _features(snapshot, rng, Span)


def _features(snapshot, rng, Span) -> None:
    from scriptc.ide import (
        actions,
        completion,
        formatting,
        hints,
        hover,
        navigation,
        outline,
        tokens,
    )
    from scriptc.ide.answers import RenameError

    text = snapshot.text
    whole = Span(0, len(text))
    outline.document_symbols(snapshot)
    outline.folding_ranges(snapshot)
    tokens.semantic_tokens(snapshot)
    hints.inlay_hints(snapshot, whole)
    actions.code_actions(snapshot, whole)
    actions.fix_all(snapshot)
    if len(text) < 200_000:  # formatting a 1 MB line is the fmt entry's (and slow)
        formatting.format_document(text)
    for _ in range(4):
        offset = rng.randint(0, len(text))
        hover.hover(snapshot, offset)
        completion.complete(snapshot, offset)
        navigation.definition(snapshot, offset)
        navigation.references(snapshot, offset)
        try:
            navigation.prepare_rename(snapshot, offset)
            navigation.rename(snapshot, offset, rng.choice(("renamed", "x-y", "a b", "")))
        except RenameError:
            pass  # a refusal the editor shows: the answer for a name that cannot be renamed


@dataclass(frozen=True)
class Entry:
    name: str
    kind: str  # which seeds it takes
    call: Callable[..., None]


ENTRIES: dict[str, Entry] = {e.name: e for e in (
    Entry("lint", "script", lint),
    Entry("compile", "script", compile_),
    Entry("fmt", "script", fmt),
    Entry("fix", "script", fix),
    Entry("run", "script", run),
    Entry("check", "json", check),
    Entry("scenario", "scenario", scenario),
    Entry("config", "config", config),
    Entry("editor", "script", editor),
)}


def drive(entry: str, seed_name: str, data: bytes) -> None:
    """Run one entry point on one input (raises on a broken law or a crash)."""
    spec = ENTRIES[entry]
    if entry == "run":
        spec.call(data, _world_of(seed_name))
    else:
        spec.call(data)


def classify(entry: str, exc: BaseException) -> str:
    """The failure class of an exception: the law, or the crash and where it was raised."""
    if isinstance(exc, LawBroken):
        return exc.law
    frames = traceback.extract_tb(exc.__traceback__)
    ours = [f for f in frames if "/scriptc/" in f.filename.replace("\\", "/")]
    where = ours[-1] if ours else (frames[-1] if frames else None)
    place = (f" at {Path(where.filename).parent.name}/{Path(where.filename).name}:{where.name}"
             if where else "")
    return f"{entry}: crash {type(exc).__name__}{place}"
