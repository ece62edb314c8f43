"""The JSON Schemas in schemas/: valid draft 2020-12, found through `schema_path`, and true of
what scriptc reads and writes (the thesis's files, every JSON the back end emits, and the
output of `scriptc lint --format json`)."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from scriptc.analysis.analyze import analyze_json, analyze_script
from scriptc.emit.json import emit_json
from scriptc.resources import schema_path
from scriptc.source import SourceFile

TESTS = Path(__file__).parent
SCHEMAS = ["thesis-script.schema.json", "lint-output.schema.json"]


def source(path: Path) -> SourceFile | None:
    """The case file as text, or None for the cases that are not UTF-8 on purpose (P007)."""
    try:
        return SourceFile(str(path), path.read_bytes().decode("utf-8"))
    except UnicodeDecodeError:
        return None


def validator(name: str) -> jsonschema.Draft202012Validator:
    schema = json.loads(schema_path(name).read_text(encoding="utf-8"))
    return jsonschema.Draft202012Validator(schema)


def errors(name: str, instance) -> list[str]:
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message}"
            for e in validator(name).iter_errors(instance)]


@pytest.mark.parametrize("name", SCHEMAS)
def test_schema_is_valid_draft_2020_12(name: str) -> None:
    schema = json.loads(schema_path(name).read_text(encoding="utf-8"))
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    jsonschema.Draft202012Validator.check_schema(schema)


@pytest.mark.parametrize("path", sorted((TESTS / "data").glob("*.json")), ids=lambda p: p.name)
def test_thesis_files_are_valid(path: Path) -> None:
    assert errors("thesis-script.schema.json", json.loads(path.read_text(encoding="utf-8"))) == []


EMITTED = sorted((TESTS / "cases").rglob("*.out.json"))
SCRIPTS = sorted(p for p in (TESTS / "cases").rglob("*.script")
                 if not p.name.endswith(".out.script"))


@pytest.mark.parametrize("path", EMITTED, ids=lambda p: str(p.relative_to(TESTS)))
def test_golden_json_files_are_valid(path: Path) -> None:
    assert errors("thesis-script.schema.json", json.loads(path.read_text(encoding="utf-8"))) == []


def test_every_compilable_case_emits_valid_json() -> None:
    """Every script case without errors, compiled, satisfies the schema."""
    compiled = 0
    for path in SCRIPTS:
        text = source(path)
        if text is None:
            continue
        analysis = analyze_script(text)
        if analysis.ok:
            out = emit_json(analysis.script)
            assert errors("thesis-script.schema.json", json.loads(out)) == [], path
            compiled += 1
    assert compiled >= 5


@pytest.mark.parametrize("bad, where", [
    ({"activityname": "a"}, ""),
    ({"activityname": "a", "alfarulemessages": [], "omegarulemessages": [],
      "goal0": {"goalid": "g", "act0": {
          "blk0": {"type": "instruction", "flagged": "flag", "move": [], "led": [], "audioout": [],
                   "extra": 1}}}}, "goal0/act0/blk0"),
    ({"activityname": "a", "alfarulemessages": [{"rulecode": 0, "id": "r", "intopic": "",
                                                 "outtopic": "", "action": 90, "mutexcmd": 85}],
      "omegarulemessages": [], "goal0": {"goalid": "g", "act0": {"blk0": {"type": "terminus"}}}},
     "alfarulemessages/0/action"),
    ({"activityname": "a", "alfarulemessages": [], "omegarulemessages": [],
      "goal0": {"goalid": "g", "act0": {"blk0": {"type": "sensor"}}}}, "goal0/act0/blk0"),
])
def test_thesis_schema_rejects(bad, where: str) -> None:
    found = errors("thesis-script.schema.json", bad)
    assert found and all(e.startswith(where) for e in found), found


def lint_records(*analyses) -> list:
    from scriptc.diagnostics.render import render_json

    return json.loads(render_json(list(analyses)))


def test_lint_output_of_scripts_and_json_is_valid() -> None:
    cases = TESTS / "cases"
    analyses = [analyze_script(s) for s in map(source, SCRIPTS) if s is not None]
    analyses += [analyze_json(s) for s in map(source, sorted((cases / "json").rglob("*.json")))
                 if s is not None]
    records = lint_records(*analyses)
    assert len(records) > 50
    assert any(r.get("fix") for r in records) and any(r.get("labels") for r in records)
    assert any(r.get("path") for r in records)
    assert errors("lint-output.schema.json", records) == []


def test_lint_output_schema_rejects() -> None:
    good = {"code": "L003", "severity": "error", "message": "m", "file": "a.script",
            "line": 1, "column": 1, "end_line": 1, "end_column": 2}
    assert errors("lint-output.schema.json", [good]) == []
    assert errors("lint-output.schema.json", [{**good, "severity": "fatal"}])
    assert errors("lint-output.schema.json", [{**good, "line": 0}])
    assert errors("lint-output.schema.json", [{**good, "unknown": 1}])
    assert errors("lint-output.schema.json", [{k: v for k, v in good.items() if k != "end_column"}])
    assert errors("lint-output.schema.json", {"not": "an array"})
