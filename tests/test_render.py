"""The renderers over hand-made diagnostics: the text renderer is snapshot-tested against
tests/cases/render/*.txt (`pytest --bless` rewrites them), the machine formats are checked
field by field. The diagnostics are built by hand so that these tests do not depend on the
parser or the checks."""

from __future__ import annotations

import json
import re

import pytest
from harness import CASES, expect
from hypothesis import given
from hypothesis import strategies as st

from scriptc.diagnostics.model import Diagnostic, Fix, Label, Severity, TextEdit
from scriptc.diagnostics.render import (
    FORMATS,
    artifact_uri,
    render,
    render_github,
    render_json,
    render_sarif,
    render_text,
)
from scriptc.source import SourceFile, Span

RENDER = CASES / "render"

SCRIPT = (
    "[example_act]\n"
    '[alfa:16,my_rule,"\\\\in","\\\\out",A,M]\n'
    "[omega:0,my_rule,\"\",\"\",R,\n"
    "  L]\n"
    "[goal:blink]\n"
    "[action]\n"
    '[b#start#blk_inst: MV() LD("0, 0, 1, 1, 0, 100") AO()]\n'
    "[b#start#blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n"
    "[b#end#blk_terminus]\n"
)


CRLF = SCRIPT.replace("\n", "\r\n")


def span_of(text: str, needle: str, nth: int = 0) -> Span:
    """The span of the `nth` occurrence of `needle` in `text`."""
    start = -1
    for _ in range(nth + 1):
        start = text.index(needle, start + 1)
    return Span(start, start + len(needle))


def d(code: str, severity: Severity, message: str, span: Span, **kw) -> Diagnostic:
    return Diagnostic(code, severity, message, span, **kw)


def script_diagnostics(t: str = SCRIPT) -> list[Diagnostic]:
    return [
        d("M004", Severity.WARNING, "the omega list does not undo the alfa list",
          Span(t.index("[omega"), t.index("L]") + 2),
          notes=("`my_rule` is added by the alfa list and removed by the omega list",)),
        d("L001", Severity.ERROR, "the label `start` is used twice", span_of(t, "start", 1),
          labels=(Label(span_of(t, "start", 0), "first defined here"),),
          help="rename one of the blocks"),
        d("L003", Severity.ERROR, "jump target `nowhere` is not a label of this script",
          span_of(t, "nowhere"),
          labels=(Label(span_of(t, "start", 0), "a label of this script"),
                  Label(span_of(t, "end"), "another one")),
          notes=("labels exist only in the source", "a second note\nthat runs over two lines"),
          help="use `start` or `end`"),
        d("F003", Severity.INFO, "the script ends here", Span(len(t), len(t))),
    ]


UNICODE = (
    "[act]\n"
    "\t[goal:\u6b69\u304f]\t% \u6b69\u304f = walk %\n"      # tab, then two wide CJK chars
    "[b##blk_inst: MV() LD() AO(\"caf\u00e9\u0301 \U0001F600, 0, 1\")]\n"  # combining, emoji
    "[b#x\x1b[31m#blk_terminus]\n"                          # an escape char in the text
    "[b#\u202eevil#blk_terminus]\n"                         # a bidi override
)


def unicode_diagnostics() -> list[Diagnostic]:
    t = UNICODE
    return [
        d("L002", Severity.ERROR, "the goal id is wide", span_of(t, "\u6b69\u304f"),
          labels=(Label(span_of(t, "walk"), "a label after a tab and wide text"),)),
        d("A003", Severity.ERROR, "after the emoji", span_of(t, ", 0, 1")),
        d("P005", Severity.ERROR, "an escape character", span_of(t, "\x1b")),
        d("P005", Severity.ERROR, "a bidi override", span_of(t, "\u202e"),
          labels=(Label(span_of(t, "evil"), "not reordered"),)),
    ]


FAR = "".join(f"[b#l{i}#blk_terminus]\n" for i in range(12))


def far_diagnostics() -> list[Diagnostic]:
    t = FAR
    return [
        # Labels two lines apart (the line between is shown) and ten lines apart (`...`).
        d("L001", Severity.ERROR, "far apart", span_of(t, "l2"),
          labels=(Label(span_of(t, "l0"), "two lines above"),
                  Label(span_of(t, "l11"), "nine lines below"))),
    ]


LONG = "[b##blk_inst: MV(" + ", ".join(f'"{i}, 0, 0, 0, 10"' for i in range(60)) + ") LD() AO()]\n"


def long_diagnostics() -> list[Diagnostic]:
    return [d("V004", Severity.ERROR, "in the middle of a long line", span_of(LONG, '"30, 0'),
              labels=(Label(span_of(LONG, '"58, 0'), "also far to the right"),))]


GAP = ("[b#x#blk_terminus]\n"
       "[b##blk_inst: MV(" + ", ".join(['"0, 0, 0, 0, 10"'] * 12) + ") LD() AO()]\n"
       "[b#x#blk_terminus]\n")


def gap_diagnostics() -> list[Diagnostic]:
    # The two annotated lines are two apart, so the line between is shown, annotation-less;
    # it is longer than MAX_LINE, so it is cut (this crashed the renderer: issue 12).
    return [d("L001", Severity.ERROR, "the label `x` is used twice", span_of(GAP, "x", 1),
              labels=(Label(span_of(GAP, "x", 0), "first defined here"),))]


JSON_SOURCE = '{\n  "activityname": "a",\n  "goal0": {"goalid": 7}\n}\n'


def json_diagnostics() -> list[Diagnostic]:
    t = JSON_SOURCE
    return [d("J002", Severity.ERROR, "`goalid` must be a string", span_of(t, "7"),
              path="goal0/goalid",
              fix=Fix("quote the number", (TextEdit(span_of(t, "7"), '"7"'),)))]


SNAPSHOTS = {
    "labels": lambda: [(SourceFile("example.script", SCRIPT), script_diagnostics())],
    "unicode": lambda: [(SourceFile("wide.script", UNICODE), unicode_diagnostics())],
    "far": lambda: [(SourceFile("far.script", FAR), far_diagnostics())],
    "long_line": lambda: [(SourceFile("long.script", LONG), long_diagnostics())],
    "json_path_fix": lambda: [(SourceFile("a.json", JSON_SOURCE), json_diagnostics())],
    "gap_long_line": lambda: [(SourceFile("gap.script", GAP), gap_diagnostics())],
    "crlf": lambda: [(SourceFile("crlf.script", CRLF), script_diagnostics(CRLF)[1:])],
    "two_files": lambda: [(SourceFile("example.script", SCRIPT), script_diagnostics()[:1]),
                          (SourceFile("clean.script", "[clean]\n"), []),
                          (SourceFile("far.script", FAR), far_diagnostics())],
}


@pytest.mark.parametrize("name", sorted(SNAPSHOTS))
def test_text_snapshot(name: str) -> None:
    expect(RENDER / f"{name}.txt", render_text(SNAPSHOTS[name]()))


@pytest.mark.parametrize("name", ["labels", "json_path_fix"])
def test_github_snapshot(name: str) -> None:
    expect(RENDER / f"{name}.github.txt", render_github(SNAPSHOTS[name]()))


def test_clean_results_render_nothing_in_text_and_github() -> None:
    clean = [(SourceFile("clean.script", "[clean]\n"), [])]
    assert render_text(clean) == ""
    assert render_text([]) == ""
    assert render_github(clean) == ""
    assert json.loads(render_json(clean)) == []
    assert json.loads(render_sarif(clean))["runs"][0]["results"] == []


def test_carets_sit_under_the_text_they_mark() -> None:
    """Wide characters take two columns, tabs four, combining marks none: the caret row
    lines up with the displayed source row (checked in terminal columns)."""
    import unicodedata

    def columns(s: str) -> int:
        return sum(0 if unicodedata.combining(c) else
                   2 if unicodedata.east_asian_width(c) in "WF" else 1 for c in s)

    out = render_text(SNAPSHOTS["unicode"]()).splitlines()
    source_row = next(line for line in out if line.startswith("2 |"))
    caret_row = out[out.index(source_row) + 1]
    label_row = out[out.index(source_row) + 2]
    assert "\t" not in source_row
    wide = source_row.index("\u6b69")
    assert columns(caret_row[: caret_row.index("^")]) == columns(source_row[:wide])
    assert caret_row.count("^") == 4  # two wide characters
    walk = source_row.index("walk")
    assert columns(label_row[: label_row.index("-")]) == columns(source_row[:walk])


def test_control_and_bidi_characters_are_made_visible() -> None:
    out = render_text(SNAPSHOTS["unicode"]())
    assert "\x1b" not in out and "\u202e" not in out
    assert "\u241b" in out  # the control picture of ESC


def test_colour_is_the_plain_text_with_ansi_codes() -> None:
    results = SNAPSHOTS["labels"]()
    coloured = render_text(results, color=True)
    assert "\x1b[" in coloured
    assert re.sub(r"\x1b\[[0-9;]*m", "", coloured) == render_text(results)


def _rich_colour(lines) -> str:
    """The lines coloured by rich, as the renderer did before it wrote ANSI codes itself."""
    import io

    from rich.console import Console
    from rich.text import Text

    buffer = io.StringIO()
    console = Console(file=buffer, force_terminal=True, color_system="standard", no_color=False,
                      width=1_000_000, soft_wrap=True, highlight=False, markup=False, emoji=False,
                      legacy_windows=False)
    for line in lines:
        text = Text(no_wrap=True)
        for piece, style in line:
            text.append(piece, style)
        console.print(text)
    return buffer.getvalue()


@pytest.mark.parametrize("name", sorted(SNAPSHOTS))
def test_colour_is_what_rich_wrote(name: str) -> None:
    """The renderer writes its colours without rich (diagnostics/ imports no third-party
    package), byte for byte as rich did."""
    from scriptc.diagnostics import render as module

    results = SNAPSHOTS[name]()
    assert render_text(results, color=True) == _rich_colour(module._text_lines(results))


_PIECE_TEXT = st.text(st.characters(blacklist_categories=("Cc", "Cs", "Zl", "Zp", "Cf")),
                      max_size=12)


@given(st.lists(st.lists(st.tuples(_PIECE_TEXT, st.sampled_from(
    [None, "bold", "bold red", "bold yellow", "bold cyan", "bold blue"])), max_size=6),
    max_size=5))
def test_any_styled_lines_colour_as_rich_coloured_them(lines) -> None:
    from scriptc.diagnostics import render as module

    assert module._colour(lines) == _rich_colour(lines)


def test_summary_counts_every_severity() -> None:
    last = render_text(SNAPSHOTS["labels"]()).splitlines()[-1]
    assert last == "error: 2 errors, 1 warning, 1 info message emitted"
    warning_only = [(SourceFile("w.script", SCRIPT), script_diagnostics()[:1])]
    assert render_text(warning_only).splitlines()[-1] == "warning: 1 warning emitted"


def test_json_records() -> None:
    records = json.loads(render_json(SNAPSHOTS["labels"]() + SNAPSHOTS["json_path_fix"]()))
    assert [r["code"] for r in records] == ["M004", "L001", "L003", "F003", "J002"]
    m004, l001, l003, f003, j002 = records
    assert m004 == {
        "code": "M004", "name": "omega-leak", "severity": "warning",
        "message": "the omega list does not undo the alfa list", "file": "example.script",
        "line": 3, "column": 1, "end_line": 4, "end_column": 5, "labels": [],
        "notes": ["`my_rule` is added by the alfa list and removed by the omega list"],
        "help": None, "fix": None,
    }
    assert l001["labels"] == [{"message": "first defined here", "line": 7, "column": 4,
                               "end_line": 7, "end_column": 9}]
    assert (l001["line"], l001["column"], l001["end_column"]) == (8, 4, 9)
    assert l003["help"] == "use `start` or `end`"
    assert (f003["line"], f003["column"], f003["end_line"], f003["end_column"]) == (10, 1, 10, 1)
    assert f003["severity"] == "info"
    assert j002["path"] == "goal0/goalid" and "path" not in l001
    assert j002["fix"] == {"message": "quote the number", "safe": True, "edits": [
        {"line": 3, "column": 23, "end_line": 3, "end_column": 24, "new_text": '"7"'}]}


def test_json_columns_count_code_points() -> None:
    records = json.loads(render_json(SNAPSHOTS["unicode"]()))
    # `, 0, 1` follows `"caf\u00e9\u0301 \U0001F600` on line 3: columns count each code point
    # once.
    line = UNICODE.splitlines()[2]
    assert records[1]["line"] == 3
    assert records[1]["column"] == line.index(", 0, 1") + 1


def test_json_output_validates_against_the_schema() -> None:
    import jsonschema

    from scriptc.resources import schema_path

    schema = json.loads(schema_path("lint-output.schema.json").read_text(encoding="utf-8"))
    for name in SNAPSHOTS:
        jsonschema.validate(json.loads(render_json(SNAPSHOTS[name]())), schema)


def test_sarif_log() -> None:
    log = json.loads(render_sarif(SNAPSHOTS["labels"]() + SNAPSHOTS["json_path_fix"]()))
    assert log["version"] == "2.1.0" and log["$schema"].endswith("sarif-2.1.0.json")
    (run,) = log["runs"]
    driver = run["tool"]["driver"]
    assert driver["name"] == "scriptc" and driver["version"]
    assert [r["id"] for r in driver["rules"]] == ["F003", "J002", "L001", "L003", "M004"]
    rule = driver["rules"][2]
    assert rule["name"] == "duplicate-label"
    assert rule["shortDescription"]["text"] == "two blocks carry the same label"
    assert rule["fullDescription"]["text"]
    assert rule["defaultConfiguration"] == {"level": "error"}
    assert run["columnKind"] == "unicodeCodePoints"
    results = run["results"]
    assert [r["level"] for r in results] == ["warning", "error", "error", "note", "error"]
    for r in results:
        assert driver["rules"][r["ruleIndex"]]["id"] == r["ruleId"]
    l003 = results[2]
    assert l003["message"]["text"] == "jump target `nowhere` is not a label of this script"
    location = l003["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"] == "example.script"
    assert location["region"] == {"startLine": 8, "startColumn": 40, "endLine": 8,
                                  "endColumn": 47}
    assert [x["message"]["text"] for x in l003["relatedLocations"]] == [
        "a label of this script", "another one"]
    assert l003["properties"]["help"] == "use `start` or `end`"
    j002 = results[4]
    assert j002["fixes"][0]["artifactChanges"][0]["replacements"] == [{
        "deletedRegion": {"startLine": 3, "startColumn": 23, "endLine": 3, "endColumn": 24},
        "insertedContent": {"text": '"7"'}}]
    assert j002["locations"][0]["logicalLocations"][0]["fullyQualifiedName"] == "goal0/goalid"


def test_sarif_rule_help_comes_from_the_explanation() -> None:
    from scriptc.diagnostics.codes import explanation

    source = SourceFile("x.script", "\xff")
    diag = d("P007", Severity.ERROR, "not UTF-8", Span(0, 1))
    (rule,) = json.loads(render_sarif([(source, [diag])]))["runs"][0]["tool"]["driver"]["rules"]
    assert rule["help"]["markdown"] == explanation("P007")
    assert rule["fullDescription"]["text"].startswith("The file could not be read as text.")


@pytest.mark.parametrize("path, uri", [
    ("examples/dance.script", "examples/dance.script"),
    ("examples\\dance.script", "examples/dance.script"),
    ("my folder/a b.script", "my%20folder/a%20b.script"),
])
def test_sarif_uris_are_relative_with_forward_slashes(path: str, uri: str) -> None:
    assert artifact_uri(path) == uri


def test_sarif_uri_of_an_absolute_path(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert artifact_uri(str(tmp_path / "sub" / "x.script")) == "sub/x.script"
    outside = tmp_path.parent / "elsewhere.script"
    assert artifact_uri(str(outside)) == outside.as_uri()


def test_github_escaping() -> None:
    source = SourceFile("dir\\we,ird:name%.script", "[a]\n")
    diag = d("S003", Severity.WARNING, "100% bad:\r\nsecond, line", Span(1, 2),
             notes=("a note",))
    info = d("F003", Severity.INFO, "info", Span(0, 0))
    out = render_github([(source, [diag, info])])
    assert out == (
        "::warning file=dir/we%2Cird%3Aname%25.script,line=1,col=2,endLine=1,endColumn=3,"
        "title=S003::100%25 bad:%0D%0Asecond, line%0Anote: a note\n"
        "::notice file=dir/we%2Cird%3Aname%25.script,line=1,col=1,endLine=1,endColumn=1,"
        "title=F003::info\n"
    )


def test_render_dispatches_every_format() -> None:
    results = SNAPSHOTS["labels"]()
    assert FORMATS == ("text", "json", "sarif", "github")
    assert render("text", results) == render_text(results)
    assert render("json", results) == render_json(results)
    assert render("sarif", results) == render_sarif(results)
    assert render("github", results) == render_github(results)


def test_renderers_accept_analysis_objects() -> None:
    class Result:
        def __init__(self, source, diagnostics):
            self.source, self.diagnostics = source, diagnostics

    pair = SNAPSHOTS["labels"]()[0]
    assert render_text([Result(*pair)]) == render_text([pair])


# The property names SARIF 2.1.0 defines for the objects the renderer writes (OASIS SARIF
# 2.1.0, section 3): a misspelt key would be silently ignored by code-scanning services.
SARIF_KEYS = {
    "log": {"$schema", "version", "runs", "inlineExternalProperties", "properties"},
    "run": {"tool", "invocations", "conversion", "language", "versionControlProvenance",
            "originalUriBaseIds", "artifacts", "logicalLocations", "graphs", "results",
            "automationDetails", "runAggregates", "baselineGuid", "redactionTokens",
            "defaultEncoding", "defaultSourceLanguage", "newlineSequences", "columnKind",
            "externalPropertyFileReferences", "threadFlowLocations", "taxonomies", "addresses",
            "translations", "policies", "webRequests", "webResponses", "specialLocations",
            "properties"},
    "driver": {"guid", "name", "organization", "product", "productSuite", "shortDescription",
               "fullDescription", "fullName", "version", "semanticVersion", "dottedQuadFileVersion",
               "releaseDateUtc", "downloadUri", "informationUri", "globalMessageStrings",
               "notifications", "rules", "taxa", "locations", "language", "contents",
               "isComprehensive", "localizedDataSemanticVersion",
               "minimumRequiredLocalizedDataSemanticVersion", "associatedComponent",
               "translationMetadata", "supportedTaxonomies", "properties"},
    "rule": {"id", "deprecatedIds", "guid", "deprecatedGuids", "name", "deprecatedNames",
             "shortDescription", "fullDescription", "messageStrings", "defaultConfiguration",
             "helpUri", "help", "relationships", "properties"},
    "result": {"ruleId", "ruleIndex", "rule", "kind", "level", "message", "analysisTarget",
               "locations", "guid", "correlationGuid", "occurrenceCount", "partialFingerprints",
               "fingerprints", "stacks", "codeFlows", "graphs", "graphTraversals",
               "relatedLocations", "suppressions", "baselineState", "rank", "attachments",
               "hostedViewerUri", "workItemUris", "provenance", "fixes", "taxa", "webRequest",
               "webResponse", "properties"},
    "location": {"id", "physicalLocation", "logicalLocations", "message", "annotations",
                 "relationships", "properties"},
    "physicalLocation": {"address", "artifactLocation", "region", "contextRegion", "properties"},
    "region": {"startLine", "startColumn", "endLine", "endColumn", "charOffset", "charLength",
               "byteOffset", "byteLength", "snippet", "message", "sourceLanguage", "properties"},
    "fix": {"description", "artifactChanges", "properties"},
    "artifactChange": {"artifactLocation", "replacements", "properties"},
    "replacement": {"deletedRegion", "insertedContent", "properties"},
}


def test_sarif_uses_only_sarif_property_names() -> None:
    log = json.loads(render_sarif(SNAPSHOTS["labels"]() + SNAPSHOTS["json_path_fix"]()))

    def keys(kind: str, obj: dict) -> None:
        assert set(obj) <= SARIF_KEYS[kind], f"{kind}: {set(obj) - SARIF_KEYS[kind]}"

    def location(loc: dict) -> None:
        keys("location", loc)
        keys("physicalLocation", loc["physicalLocation"])
        keys("region", loc["physicalLocation"]["region"])

    keys("log", log)
    run = log["runs"][0]
    keys("run", run)
    keys("driver", run["tool"]["driver"])
    for rule in run["tool"]["driver"]["rules"]:
        keys("rule", rule)
    for result in run["results"]:
        keys("result", result)
        assert result["level"] in ("none", "note", "warning", "error")
        for loc in result["locations"] + result.get("relatedLocations", []):
            location(loc)
        for fix in result.get("fixes", []):
            keys("fix", fix)
            for change in fix["artifactChanges"]:
                keys("artifactChange", change)
                for replacement in change["replacements"]:
                    keys("replacement", replacement)
                    keys("region", replacement["deletedRegion"])


def test_github_paths_are_relative_to_the_working_folder(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    source = SourceFile(str(tmp_path / "sub" / "x.script"), "[a]\n")
    out = render_github([(source, [d("S003", Severity.ERROR, "m", Span(0, 1))])])
    assert out.startswith("::error file=sub/x.script,line=1,")


def test_messages_cannot_drive_the_terminal() -> None:
    source = SourceFile("a\x1b.script", "[a]\n")
    diag = d("A001", Severity.WARNING, "the path `/x\x1b[2J` is absolute", Span(0, 1),
             labels=(Label(Span(1, 2), "here\x07"),), notes=("one\nline\x1b two",),
             help="\u202edone")
    out = render_text([(source, [diag])])
    assert not any(ch in out for ch in "\x1b\x07\u202e")
    assert "the path `/x\u241b[2J` is absolute" in out
    assert "          line\u241b two\n" in out
