"""`scriptc graph` (docs/views.md "The flow graph"): the graph's nodes and edges against the IR
on every example and on generated scripts (every block a node, every jump two edges to the
blocks the runtime goes to, every other block one edge to the next, clusters the goals, the
marks of reachability); the DOT and Mermaid writers write that graph and nothing else, with
text escaped for each; the SVG drawn by the real Graphviz (`graphviz` tier: .ci/run installs
it) keeps accented letters and emoji; the command line (formats, outputs, a folder into a
folder, scripts with errors, the missing `dot`); the pictures of docs/views.md are what the
code draws. The exact bytes of each format are the case files' (tests/cases/graph/)."""

from __future__ import annotations

import os
import re
import shutil
import threading
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from strategies import scripts
from test_cli import process

from scriptc.analysis.analyze import Analysis, analyze_file, analyze_script
from scriptc.cli.main import cli
from scriptc.emit.condition import condition_text
from scriptc.ir import nodes as ir
from scriptc.source import SourceFile
from scriptc.views.graph import (
    END,
    RULES,
    START,
    Graph,
    colour_name,
    condition_lines,
    dot_string,
    flow_graph,
    html_text,
    mermaid_text,
    rule_text,
    to_dot,
    to_mermaid,
    to_svg,
)

ROOT = Path(__file__).parent.parent
EXAMPLES = sorted((ROOT / "examples").glob("*.script"))
CASES = sorted((ROOT / "tests" / "cases" / "graph").glob("*.script"))
DOCS = ROOT / "docs"


def run(*args: str, input: str | bytes | None = None, env: dict | None = None):
    return CliRunner().invoke(cli, list(args), input=input, env=env, catch_exceptions=False)


def analysed(path: Path) -> Analysis:
    analysis = analyze_file(path)
    assert analysis.script is not None
    return analysis


# -- the graph is the IR's flow ----------------------------------------------------------------

def expected_target(script: ir.Script, name: ir.Name | None, i: int) -> str:
    """Where a jump at block `i` goes, worked out here from the language's rule (an empty
    target is the next block; a label, the first block carrying it; past the last block,
    the end)."""
    blocks = [b for _address, b in script.blocks()]
    if name is None or not name.text:
        j = i + 1
    else:
        j = next(k for k, b in enumerate(blocks) if b.label is not None
                 and b.label.text == name.text)
    return f"b{j}" if j < len(blocks) else END


def check_graph(script: ir.Script, graph: Graph) -> None:
    blocks = script.blocks()
    nodes = {node.id: node for node in graph.nodes}
    assert len(nodes) == len(graph.nodes), "node ids are unique"
    out: dict[str, list] = {}
    for edge in graph.edges:
        assert edge.source in nodes and edge.target in nodes, edge
        out.setdefault(edge.source, []).append(edge)
    kinds = {ir.InstructionBlock: "instructions", ir.JumpBlock: "jump",
             ir.TerminusBlock: "terminus", ir.SensorBlock: "sensor"}
    for i, ((g, a, b), block) in enumerate(blocks):
        node = nodes[f"b{i}"]
        assert (node.kind, node.index, node.goal, node.path) == (
            kinds[type(block)], i, g, ir.block_path((g, a, b)))
        if block.label is not None and block.label.text:
            assert node.title == block.label.text
        edges = out.get(node.id, [])
        if isinstance(block, ir.JumpBlock):
            condition = condition_text(block.condition)
            assert [(e.kind, e.target, e.condition, e.never) for e in edges] == [
                ("true", expected_target(script, block.true_target, i), condition, False),
                ("false", expected_target(script, block.false_target, i), condition,
                 block.condition.is_constant_true)]
        elif isinstance(block, ir.TerminusBlock):
            assert edges == []
        else:
            assert [(e.kind, e.target) for e in edges] == [
                ("next", f"b{i + 1}" if i + 1 < len(blocks) else END)]
    # The goals are the clusters, their blocks in order; every block is in its goal's.
    assert [c.title for c in graph.clusters] == [goal.id.text for goal in script.goals]
    assert [list(c.nodes) for c in graph.clusters] == [
        [f"b{i}" for i, ((g, _a, _b), _block) in enumerate(blocks) if g == n]
        for n in range(len(script.goals))]
    # The start goes to the first block; the rules' note holds the messages, alfa first.
    assert nodes[START].title == script.name.text
    assert [(e.kind, e.target) for e in out[START]] == [("start", "b0")]
    messages = [*script.alfa, *script.omega]
    assert graph.rules == tuple(rule_text(m) for m in messages)
    assert (RULES in nodes) == bool(messages)
    # The end past the last block is there exactly when an edge goes to it.
    assert (END in nodes) == any(e.target == END for e in graph.edges)
    # Reachable: what a walk from the start finds, never through a `never` edge.
    seen, todo = {START}, [START]
    while todo:
        for e in out.get(todo.pop(), []):
            if not e.never and e.target not in seen:
                seen.add(e.target)
                todo.append(e.target)
    assert {n.id for n in graph.nodes if n.index is not None and n.reachable} == {
        f"b{i}" for i in range(len(blocks)) if f"b{i}" in seen}


DOT_NODE = re.compile(r'^\s*"([^"]+)" \[', re.MULTILINE)
DOT_EDGE = re.compile(r'^\s*"([^"]+)" -> "([^"]+)" \[', re.MULTILINE)
MERMAID_NODE = re.compile(r'^\s*(\w+)(?:\(\[|\[/|\(\(\(|\[|\{)"[^"]*"', re.MULTILINE)
MERMAID_EDGE = re.compile(r'^\s*(\w+) (?:-->|-\.->|-\.-)(?:\|"[^"]*"\|)? (\w+)$', re.MULTILINE)


def check_writers(graph: Graph) -> None:
    """The DOT and Mermaid texts define each node once and draw each edge, in order, with
    every label a well-formed quoted string (nothing unescaped ends one early)."""
    ids = [node.id for node in graph.nodes]
    pairs = [(e.source, e.target) for e in graph.edges]
    dot = to_dot(graph)
    assert sorted(DOT_NODE.findall(dot)) == sorted(ids)
    assert DOT_EDGE.findall(dot) == pairs
    assert dot.count("cluster_g") == len(graph.clusters)
    mermaid = to_mermaid(graph)
    assert sorted(MERMAID_NODE.findall(mermaid)) == sorted(ids)
    assert MERMAID_EDGE.findall(mermaid) == pairs
    assert re.findall(r"^  subgraph (g\d+)\[", mermaid, re.MULTILINE) == [
        c.id for c in graph.clusters]
    # The same graph, the same bytes.
    assert to_dot(graph) == dot and to_mermaid(graph) == mermaid


@pytest.mark.parametrize("path", EXAMPLES + CASES, ids=lambda p: p.name)
def test_the_graph_of_every_example_is_its_flow(path: Path) -> None:
    analysis = analysed(path)
    assert analysis.script is not None
    graph = flow_graph(analysis.script, analysis.source)
    check_graph(analysis.script, graph)
    check_writers(graph)
    lines = {n.id: n.line for n in graph.nodes if n.index is not None}
    assert all(line > 0 for line in lines.values())
    assert flow_graph(analysis.script, analysis.source) == graph


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scripts())
def test_the_graph_of_every_generated_script_is_its_flow(text: str) -> None:
    """Scripts with every kind of block and condition, labels jumped to from anywhere; those
    the checks refuse (a cycle without time) have their flow too."""
    analysis = analyze_script(SourceFile("gen.script", text))
    assert analysis.script is not None
    graph = flow_graph(analysis.script)
    check_graph(analysis.script, graph)
    check_writers(graph)


def test_a_jump_to_a_label_carried_twice_goes_to_the_first() -> None:
    text = ("[twice]\n[goal:g]\n[action]\n[b##blk_jump: CND({TRUE}) TRJMP(x) FLSJMP()]\n"
            "[b#x#blk_inst: MV() LD() AO()]\n[b#x#blk_terminus]\n")
    analysis = analyze_script(SourceFile("twice.script", text))
    assert analysis.script is not None  # (L001: the checks refuse it; the graph reads it)
    graph = flow_graph(analysis.script)
    assert [(e.kind, e.target) for e in graph.edges if e.source == "b0"] == [
        ("true", "b1"), ("false", "b1")]


# -- what the nodes and edges say --------------------------------------------------------------

def test_each_track_in_words() -> None:
    graph = flow_graph(analysed(ROOT / "examples" / "greeting.script").script)
    hello = graph.node("b3")
    assert [(line.track, line.text, line.colour) for line in hello.lines] == [
        ("MV", "after 150 ms, turn left 0.5 rad/s for 850 ms", None),
        ("MV", "turn right 0.5 rad/s for 850 ms", None),
        ("LD", "green (0.2, 0.8, 0.3) for 2000 ms", "#33cc4c"),
        ("AO", "songs/hello.wav for 2000 ms", None)]


@pytest.mark.parametrize(("rgb", "name"), [
    ((0, 0.3, 0.8), "blue"), ((0.2, 0.8, 0.3), "green"), ((0.9, 0.6, 0.3), "orange"),
    ((1, 0, 0), "red"), ((1, 1, 0), "yellow"), ((0, 1, 1), "cyan"), ((0.6, 0, 1), "purple"),
    ((1, 0.2, 0.6), "pink"), ((1, 1, 1), "white"), ((0.5, 0.5, 0.5), "grey"),
    ((0, 0, 0), "black"), ((0.1, 0.2, 0.4), "dim blue"), ((1, 0, 0.1), "red")])
def test_a_light_is_named_by_its_hue(rgb: tuple[float, float, float], name: str) -> None:
    assert colour_name(*rgb) == name


def test_a_condition_is_wrapped_and_cut() -> None:
    text = ("{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.5)} ! "
            "{E: gt(?kid>&permanencetime, 2000)}")
    lines = condition_lines(text, width=20, most=10)
    assert " ".join(lines) == text and all(len(line) <= 25 for line in lines)
    cut = condition_lines(text, width=20, most=2)
    assert len(cut) == 2 and cut[-1].endswith("…") and len(cut[-1]) <= 20
    assert condition_lines("{TRUE}") == ["{TRUE}"]


def test_text_is_escaped_for_each_format() -> None:
    nasty = 'a "b" \\ <c> & #d; %% e | `f` è 👋'
    assert dot_string(nasty) == '"a \\"b\\" \\\\ <c> & #d; %% e | `f` è 👋"'
    assert html_text(nasty) == 'a &quot;b&quot; \\ &lt;c&gt; &amp; #d; %% e | `f` è 👋'
    escaped = mermaid_text(nasty)
    assert not set('"<>&%|`\\') & set(escaped.replace("#", ""))  # only entity codes left
    names = {"quot": '"', "amp": "&", "lt": "<", "gt": ">"}
    decoded = re.sub(r"#(\d+|[a-z]+);", lambda m: names.get(m.group(1)) or chr(int(m.group(1))),
                     escaped)
    assert decoded == nasty


# -- SVG: the real Graphviz --------------------------------------------------------------------

def need_dot() -> None:
    assert shutil.which("dot"), ("Graphviz's `dot` is needed for the graphviz tier: "
                                 "`apt-get install graphviz`, as .ci/run does (or leave the "
                                 "tier out: -m 'not graphviz')")


def svg_texts(svg: bytes) -> list[str]:
    tree = ET.fromstring(svg)
    return ["".join(t.itertext()) for t in tree.iter("{http://www.w3.org/2000/svg}text")]


@pytest.mark.graphviz
@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES + CASES, ids=lambda p: p.name)
def test_graphviz_draws_every_example(path: Path) -> None:
    need_dot()
    analysis = analysed(path)
    assert analysis.script is not None
    graph = flow_graph(analysis.script, analysis.source)
    svg = to_svg(graph)
    texts = svg_texts(svg)
    for node in graph.nodes:
        if node.title and node.kind != "rules":
            assert node.title in texts, node.title
        for line in node.lines:
            assert line.text in texts or any(line.text in t for t in texts), line.text


@pytest.mark.graphviz
@pytest.mark.slow
def test_the_svg_keeps_quotes_brackets_accents_and_emoji() -> None:
    need_dot()
    analysis = analysed(ROOT / "tests" / "cases" / "graph" / "escaping.script")
    assert analysis.script is not None
    svg = to_svg(flow_graph(analysis.script, analysis.source))
    texts = svg_texts(svg)
    assert 'canzoni/ciao 👋 <è> & "tutti" | 100% #1 `x`.wav for 1000 ms' in texts
    assert '"perché? 🤖 <ok> & \\"sì\\" | 50% #2"' in texts
    assert '"a\\\\b"' in texts
    # An edge's tooltip has the whole condition (Graphviz 2.43 shows `\\\\` as one backslash
    # in a tooltip, though the DOT escapes it as it does in labels).
    links = ET.fromstring(svg).iter("{http://www.w3.org/2000/svg}a")
    tooltips = [a.get("{http://www.w3.org/1999/xlink}title") or "" for a in links]
    assert any(t.startswith('true: {CLASS #Object U ?o (?THIS>&category OP= "palla <rossa> & '
                            '\\"blu\\" \\') and t.endswith(' ⚽")} ! {TRUE}') for t in tooltips)


@pytest.mark.graphviz
@pytest.mark.slow
def test_graph_svg_on_the_command_line(tmp_path: Path) -> None:
    need_dot()
    target = tmp_path / "flow.svg"
    result = run("graph", str(ROOT / "examples" / "greeting.script"), "-o", str(target))
    assert result.exit_code == 0, result.output
    assert ET.fromstring(target.read_bytes()).tag == "{http://www.w3.org/2000/svg}svg"
    result = run("graph", str(ROOT / "examples" / "greeting.script"), "--format", "svg")
    assert result.stdout_bytes == target.read_bytes()


def test_without_graphviz_svg_is_a_clear_error(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setenv("PATH", str(tmp_path))  # a PATH without `dot`
    result = CliRunner().invoke(cli, ["graph", str(ROOT / "examples" / "greeting.script"),
                                      "--format", "svg"])
    assert result.exit_code == 2
    # The VS Code extension shows Mermaid instead when it reads this (extension.js).
    assert "apt-get install graphviz" in result.stderr
    assert "--format dot" in result.stderr and "--format mermaid" in result.stderr
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert result.stdout == ""
    result = CliRunner().invoke(cli, ["graph", str(ROOT / "examples"), "--format", "svg",
                                      "-o", str(tmp_path / "out")])
    assert result.exit_code == 2 and "apt-get install graphviz" in result.stderr
    assert not (tmp_path / "out").exists()  # refused before any work
    # DOT and Mermaid need nothing.
    assert run("graph", str(ROOT / "examples" / "greeting.script")).exit_code == 0


@pytest.mark.slow
def test_without_graphviz_no_traceback_in_a_real_process(tmp_path: Path) -> None:
    python_only = tmp_path / "bin"
    python_only.mkdir()
    done = process("graph", str(ROOT / "examples" / "greeting.script"), "--format", "svg",
                   env={"PATH": str(python_only)})
    assert done.returncode == 2
    assert b"Traceback" not in done.stderr
    assert done.stderr.decode().startswith("error: drawing SVG needs Graphviz's `dot`")


# -- the command line --------------------------------------------------------------------------

def test_formats_and_outputs(tmp_path: Path) -> None:
    greeting = str(ROOT / "examples" / "greeting.script")
    graph = flow_graph(analysed(ROOT / "examples" / "greeting.script").script,
                       analysed(ROOT / "examples" / "greeting.script").source)
    dot = run("graph", greeting)
    assert dot.exit_code == 0 and dot.stdout.startswith('digraph "greeting" {')
    mermaid = run("graph", greeting, "--format", "mermaid")
    assert mermaid.stdout.startswith("flowchart TD\n")
    # The output's suffix chooses when --format is not given.
    assert run("graph", greeting, "-o", str(tmp_path / "g.mmd")).exit_code == 0
    assert (tmp_path / "g.mmd").read_text(encoding="utf-8") == mermaid.stdout
    assert run("graph", greeting, "-o", str(tmp_path / "g.gv")).exit_code == 0
    assert (tmp_path / "g.gv").read_text(encoding="utf-8") == dot.stdout
    assert run("graph", greeting, "--format", "dot", "-o", str(tmp_path / "g.mmd")).exit_code == 0
    assert (tmp_path / "g.mmd").read_text(encoding="utf-8") == dot.stdout
    # From stdin, named for the configuration and the messages.
    text = (ROOT / "examples" / "greeting.script").read_text(encoding="utf-8")
    piped = run("graph", "-", "--stdin-filename", "greeting.script", input=text)
    assert piped.exit_code == 0 and piped.stdout == dot.stdout
    # The same as the library draws (the start's source lines included).
    assert dot.stdout.replace(greeting, "") == to_dot(graph)


def test_thesis_json_has_a_graph_and_bytecode_has_none(tmp_path: Path) -> None:
    json_file = ROOT / "tests" / "data" / "test_act.json"
    result = run("graph", str(json_file))
    assert result.exit_code == 0 and 'digraph "test_act"' in result.stdout
    (tmp_path / "a.scb").write_bytes(b"SCB")
    result = run("graph", str(tmp_path / "a.scb"))
    assert result.exit_code == 2 and "bytecode" in result.stderr


def test_a_script_with_errors_has_no_graph(tmp_path: Path) -> None:
    bad = tmp_path / "bad.script"
    bad.write_text("[bad]\n[goal:g]\n[action]\n[b##blk_jump: CND({TRUE}) TRJMP(nowhere) "
                   "FLSJMP()]\n[b##blk_terminus]\n", encoding="utf-8")
    out = tmp_path / "bad.dot"
    result = run("graph", str(bad), "-o", str(out))
    assert result.exit_code == 1
    assert "error[L003]: no block has the label `nowhere`" in result.stderr
    assert "bad.script:4:" in result.stderr  # file, line and column
    assert not out.exists() and result.stdout == ""


def test_bad_paths_are_clear_errors(tmp_path: Path) -> None:
    greeting = str(ROOT / "examples" / "greeting.script")
    result = run("graph", str(tmp_path / "missing.script"))
    assert result.exit_code == 2 and "missing.script" in result.stderr
    copy = tmp_path / "g.script"
    shutil.copy(greeting, copy)
    result = run("graph", str(copy), "-o", str(copy))
    assert result.exit_code == 2 and "refusing to overwrite" in result.stderr
    assert copy.read_bytes() == Path(greeting).read_bytes()
    result = run("graph", greeting, "-o", str(tmp_path / "no" / "such" / "g.dot"))
    assert result.exit_code == 2 and "does not exist" in result.stderr


def test_links_fifos_and_devices(tmp_path: Path) -> None:
    greeting = ROOT / "examples" / "greeting.script"
    expected = run("graph", str(greeting)).stdout
    # A link as input, and as output: its target is written, the link stays.
    link = tmp_path / "link.script"
    link.symlink_to(greeting)
    (tmp_path / "real.dot").write_text("old", encoding="utf-8")
    (tmp_path / "out.dot").symlink_to(tmp_path / "real.dot")
    assert run("graph", str(link), "-o", str(tmp_path / "out.dot")).exit_code == 0
    assert (tmp_path / "out.dot").is_symlink()
    assert (tmp_path / "real.dot").read_text(encoding="utf-8") == expected
    # A FIFO as input (what a shell's <(...) gives), a device as output.
    fifo = tmp_path / "in.script"
    os.mkfifo(fifo)

    def feed() -> None:
        with open(fifo, "wb") as f:
            f.write(greeting.read_bytes())

    writer = threading.Thread(target=feed)
    writer.start()
    result = run("graph", str(fifo))
    writer.join(timeout=10)
    assert result.exit_code == 0 and result.stdout == expected
    assert run("graph", str(greeting), "-o", os.devnull).exit_code == 0


def test_a_folder_into_a_folder(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    repo = tmp_path / "activities"
    (repo / "first" / "deep").mkdir(parents=True)
    (repo / ".hidden").mkdir()
    shutil.copy(ROOT / "examples" / "greeting.script", repo / "greeting.script")
    shutil.copy(ROOT / "examples" / "approach.script", repo / "first" / "deep" / "approach.script")
    shutil.copy(ROOT / "examples" / "approach.script", repo / ".hidden" / "skipped.script")
    (repo / "first" / "bad.script").write_text(
        "[bad]\n[goal:g]\n[action]\n[b##blk_jump: CND({TRUE}) TRJMP(nowhere) FLSJMP()]\n",
        encoding="utf-8")
    (repo / "notes.txt").write_text("not a script", encoding="utf-8")
    result = run("graph", "activities", "-o", "site/graphs", "--format", "mermaid")
    assert result.exit_code == 1  # one script has errors; the others are drawn
    drawn = sorted(p.relative_to(tmp_path / "site" / "graphs").as_posix()
                   for p in (tmp_path / "site" / "graphs").rglob("*") if p.is_file())
    assert drawn == ["first/deep/approach.mmd", "greeting.mmd"]
    assert (tmp_path / "site" / "graphs" / "greeting.mmd").read_text(encoding="utf-8") == run(
        "graph", "activities/greeting.script", "--format", "mermaid").stdout
    assert "error[L003]" in result.stderr and "first/bad.script" in result.stderr
    assert "wrote 2 graphs to `site/graphs` (1 not drawn)" in result.stderr
    # Again, over what is there: the same files.
    again = run("graph", "activities", "-o", "site/graphs", "--format", "mermaid")
    assert again.exit_code == 1
    # A folder needs -o, to a folder.
    result = run("graph", "activities")
    assert result.exit_code == 2 and "-o OUTDIR" in result.stderr
    (tmp_path / "file").write_text("", encoding="utf-8")
    result = run("graph", "activities", "-o", "file")
    assert result.exit_code == 2 and "not a folder" in result.stderr
    # Nothing found is said.
    (tmp_path / "empty").mkdir()
    result = run("graph", "empty", "-o", "out")
    assert result.exit_code == 0 and "no script files found" in result.stderr


def test_a_folders_graph_never_overwrites_a_script(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "in").mkdir()
    shutil.copy(ROOT / "examples" / "greeting.script", tmp_path / "in" / "greeting.script")
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "greeting.dot").symlink_to(tmp_path / "in" / "greeting.script")
    result = run("graph", "in", "-o", "out")
    assert result.exit_code == 2 and "would overwrite a script being read" in result.stderr
    assert (tmp_path / "in" / "greeting.script").read_bytes() == (
        ROOT / "examples" / "greeting.script").read_bytes()


# -- the pictures of docs/views.md -------------------------------------------------------------

def test_the_docs_picture_is_what_the_code_draws() -> None:
    """docs/img/graph-greeting.svg is Graphviz's drawing of docs/img/graph-greeting.dot (its
    bytes depend on Graphviz's version: `scriptc graph examples/greeting.script -o
    docs/img/graph-greeting.svg` redraws it), and that DOT is what the code writes now."""
    analysis = analysed(ROOT / "examples" / "greeting.script")
    assert analysis.script is not None
    dot = to_dot(flow_graph(analysis.script, analysis.source))
    assert (DOCS / "img" / "graph-greeting.dot").read_text(encoding="utf-8") == dot, (
        "docs/img/graph-greeting.dot is stale: scriptc graph examples/greeting.script "
        "-o docs/img/graph-greeting.dot, and the .svg beside it")
    svg = (DOCS / "img" / "graph-greeting.svg").read_bytes()
    assert ET.fromstring(svg).tag == "{http://www.w3.org/2000/svg}svg"
    assert b"<!-- Title: greeting" in svg
    views = (DOCS / "views.md").read_text(encoding="utf-8")
    assert "](img/graph-greeting.svg)" in views


def test_the_docs_mermaid_block_is_what_the_code_writes() -> None:
    views = (DOCS / "views.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```mermaid\n(.*?)^```", views, re.MULTILINE | re.DOTALL)
    assert blocks, "docs/views.md shows a Mermaid graph"
    analysis = analysed(ROOT / "examples" / "greeting.script")
    assert analysis.script is not None
    assert blocks[0] == to_mermaid(flow_graph(analysis.script, analysis.source))


# -- the VS Code command (its behaviour: lsp/vscode/tests/graph.test.js, run by check.sh) ------

VSCODE = ROOT / "lsp" / "vscode"


def test_the_extension_declares_and_registers_the_graph_command() -> None:
    import json

    manifest = json.loads((VSCODE / "package.json").read_text(encoding="utf-8"))
    (command,) = [c for c in manifest["contributes"]["commands"]
                  if c["command"] == "scriptc.showGraph"]
    assert command["title"] == "scriptc: Show the flow graph"
    assert manifest["scripts"]["vscode:prepublish"] == "node scripts/vendor-mermaid.js"
    code = (VSCODE / "extension.js").read_text(encoding="utf-8")
    assert 'const GRAPH_COMMAND = "scriptc.showGraph";' in code
    assert "registerCommand(GRAPH_COMMAND," in code
    # The words it reads as "Graphviz is missing" are the CLI's (tested above).
    assert "/apt-get install graphviz/.test(" in code
    # Mermaid comes from the extension's own media/, never from the network.
    assert not re.search(r"https?://[^\s\"']*mermaid", code)
    assert 'const MERMAID = ["media", "mermaid.min.js"];' in code


def _extension_pages(views: list[dict], folder: Path) -> list[Path]:
    """The extension's webview page (`graphHtml` of extension.js, run by node) for each view,
    written into `folder`, the webview's own source being `file:`."""
    import json
    import subprocess

    program = """
const Module = require("node:module");
const resolve = Module._resolveFilename;
Module._resolveFilename = function (request, ...rest) {
  if (request === "vscode" || request === "vscode-languageclient/node") return request;
  return resolve.call(this, request, ...rest);
};
for (const name of ["vscode", "vscode-languageclient/node"]) {
  require.cache[name] = { id: name, filename: name, loaded: true, exports: {} };
}
const { graphHtml } = require(process.argv[1]);
const fs = require("node:fs");
const [views, folder] = JSON.parse(fs.readFileSync(0, "utf8"));
views.forEach((view, i) => {
  fs.writeFileSync(`${folder}/page${i}.html`, graphHtml(view, "file:", "n0nce"));
});
"""
    assert shutil.which("node"), "Node.js is needed (docs/editors.md)"
    subprocess.run(["node", "-e", program, str(VSCODE / "extension.js")],
                   input=json.dumps([views, str(folder)]).encode(), check=True, timeout=60)
    return [folder / f"page{i}.html" for i in range(len(views))]


@pytest.mark.browser
@pytest.mark.packaging
def test_mermaid_draws_every_graph_in_the_extensions_page_offline(tmp_path: Path) -> None:
    """The Mermaid of every example and case, in the page the extension shows without
    Graphviz, drawn by the Mermaid it ships (fetched once by scripts/vendor-mermaid.js, as
    packaging the extension does) in headless Chromium: every node drawn, nothing asked of
    the network, no problem in the page (a Content-Security-Policy violation included)."""
    import subprocess

    from chromium import Chromium

    assert shutil.which("node"), "Node.js is needed (docs/editors.md)"
    subprocess.run(["node", str(VSCODE / "scripts" / "vendor-mermaid.js")], check=True,
                   timeout=300, stdin=subprocess.DEVNULL)
    bundle = (VSCODE / "media" / "mermaid.min.js").as_uri()
    graphs = []
    for path in EXAMPLES + CASES:
        analysis = analysed(path)
        assert analysis.script is not None
        graphs.append(flow_graph(analysis.script, analysis.source))
    views = [{"kind": "mermaid", "mermaid": to_mermaid(g), "mermaidSrc": bundle,
              "title": g.name} for g in graphs]
    pages = _extension_pages(views, tmp_path)
    with Chromium() as browser:
        for graph, page in zip(graphs, pages, strict=True):
            browser.open(page.as_uri())
            browser.wait_for("document.querySelector('.graph svg') !== null")
            drawn = browser.evaluate(
                "[...document.querySelectorAll('.graph svg [id^=\"flowchart-\"]')]"
                ".map(e => e.id.replace(/^flowchart-/, '').replace(/-\\d+$/, ''))")
            assert sorted(set(drawn)) == sorted(n.id for n in graph.nodes), graph.name
            text = browser.evaluate("document.querySelector('.graph svg').textContent")
            assert "Syntax error" not in text
            # Every text as the script has it: quotes, backslashes, brackets, emoji.
            for node in graph.nodes:
                for line in [node.title, *(line.text for line in node.lines)]:
                    assert line in text, (graph.name, line)
            for edge in graph.edges:
                if edge.outcome and "…" not in "".join(
                        condition_lines(f"{edge.outcome}: {edge.condition}")):
                    assert f"{edge.outcome}: {edge.condition}" in text, (graph.name, edge)
        assert browser.problems == []
        assert all(url.startswith("file:") for url in browser.requests), browser.requests
