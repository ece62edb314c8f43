"""The flow graph of a script (`scriptc graph`, docs/views.md "The flow graph"): a small data
model built from the IR (`flow_graph`) and its writers, Graphviz DOT (`to_dot`), Mermaid
(`to_mermaid`, for GitHub Markdown) and SVG (`to_svg`: the DOT piped to Graphviz's `dot`).

The graph says what the block reader does (docs/runtime.md, thesis 4.2):

- a node per block, in execution order (`Script.blocks()`), id `bI` for the I-th block; an
  instruction block shows its label and a line per command of each track (a move with its
  speeds, a light with its colour, a sound with its track); a jump is a diamond, a terminus
  marked as an end, a sensor block shows its payload;
- a cluster per goal, holding its blocks;
- the start (the activity's name) with an edge to the first block, and the script's rule
  messages (alfa, then omega) in a note beside it;
- an instruction or sensor block's edge to the next block; a jump's two edges, `true` and
  `false`, each labelled with the outcome and the condition's canonical text
  (`scriptc.emit.condition.condition_text`), to the targets the runtime takes
  (`scriptc.runtime.interp.IRProgram.target`: an empty target is the next block, a label the
  first block carrying it). The `false` edge of a condition that cannot be false
  (`Condition.is_constant_true`) is kept, marked `never`;
- running past the last block ends the script: that end is a node (`script_end`) when an
  edge goes there;
- a block no path from the start reaches (F001) is marked `reachable=False`.

The writers are pure and deterministic: the same script gives the same bytes. Each escapes
text for its format (DOT strings and HTML-like labels, Mermaid's entity codes), so quotes,
angle brackets, backslashes, accented letters and emoji in a script's strings survive.
"""

from __future__ import annotations

import subprocess
from collections.abc import Iterable
from dataclasses import dataclass

from scriptc.gcpause import gc_paused
from scriptc.ir.nodes import (
    AudioCommand,
    Block,
    InstructionBlock,
    JumpBlock,
    LedCommand,
    MoveCommand,
    Number,
    RuleMessage,
    Script,
    SensorBlock,
    TerminusBlock,
    block_path,
)
from scriptc.language import quote
from scriptc.source import SourceFile

__all__ = ["CONDITION_LINES", "CONDITION_WIDTH", "Cluster", "Edge", "Graph", "GraphvizError",
           "GraphvizMissing", "Line", "Node", "condition_lines", "dot_program", "flow_graph",
           "rule_text", "to_dot", "to_mermaid", "to_svg"]

START = "start"
RULES = "rules"
END = "script_end"

# A condition on an edge is wrapped at this many characters a line, on at most this many
# lines; what is left is cut with an ellipsis (the SVG's tooltip has the whole text).
CONDITION_WIDTH = 40
CONDITION_LINES = 4


@dataclass(frozen=True, slots=True)
class Line:
    """One line of a node: a command of a track (`track` is `MV`, `LD` or `AO`; `colour` is
    the `#rrggbb` of a light that is on), or a sensor block's payload (`track` empty)."""

    track: str
    text: str
    colour: str | None = None


@dataclass(frozen=True, slots=True)
class Node:
    """A node of the graph. `kind` is `start`, `rules`, `end` (past the last block) or the
    block's: `instructions`, `jump`, `terminus`, `sensor`. A block's node has its index in
    execution order (`index`), its goal (`goal`), its thesis JSON path and its source line
    (1-based; 0 when no source was given)."""

    id: str
    kind: str
    title: str
    lines: tuple[Line, ...] = ()
    index: int | None = None
    goal: int | None = None
    path: str = ""
    line: int = 0
    reachable: bool = True


@dataclass(frozen=True, slots=True)
class Edge:
    """An edge: `kind` is `start` (to the first block), `rules` (the note to the start),
    `next` (an instruction or sensor block to the next block), `true` or `false` (a jump's
    outcomes, with the condition's canonical text). `never`: the `false` edge of a condition
    that cannot be false."""

    source: str
    target: str
    kind: str
    condition: str = ""
    never: bool = False

    @property
    def outcome(self) -> str:
        """What the edge's label starts with: `true`, `false`, `false (never)`, or ''."""
        if self.kind == "false" and self.never:
            return "false (never)"
        return self.kind if self.kind in ("true", "false") else ""


@dataclass(frozen=True, slots=True)
class Cluster:
    """A goal: its id (`gI` for the I-th goal), its goal id as written and its blocks' nodes."""

    id: str
    title: str
    nodes: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Graph:
    """The flow of one script: its name, its rule messages as written (`rule_text`), every
    node (the start, the rules' note, the blocks in execution order, the end), every edge
    (in the order of their sources) and the goals."""

    name: str
    rules: tuple[str, ...]
    nodes: tuple[Node, ...]
    edges: tuple[Edge, ...]
    clusters: tuple[Cluster, ...]

    def node(self, node_id: str) -> Node:
        for node in self.nodes:
            if node.id == node_id:
                return node
        raise KeyError(node_id)


# -- the model -------------------------------------------------------------------------------

def flow_graph(script: Script, source: SourceFile | None = None) -> Graph:
    """The flow graph of a script whose jump targets are labels it has (a checked script: an
    unknown label, L003, raises `scriptc.runtime.interp.JumpTargetError`). `source` gives the
    nodes their source lines."""
    with gc_paused():  # many small objects, none in a cycle
        return _flow_graph(script, source)


def _flow_graph(script: Script, source: SourceFile | None) -> Graph:
    from scriptc.runtime.interp import IRProgram

    program = IRProgram(script)
    blocks = program.blocks
    count = len(blocks)

    def node_id(i: int) -> str:
        return f"b{i}" if i < count else END

    edges: list[Edge] = []
    if count:
        edges.append(Edge(START, node_id(0), "start"))
    for i, (_address, block) in enumerate(blocks):
        here = node_id(i)
        if isinstance(block, JumpBlock):
            condition = program.conditions[i]
            edges.append(Edge(here, node_id(program.target(block.true_target, i)), "true",
                              condition))
            edges.append(Edge(here, node_id(program.target(block.false_target, i)), "false",
                              condition, never=block.condition.is_constant_true))
        elif not isinstance(block, TerminusBlock):
            edges.append(Edge(here, node_id(i + 1), "next"))
    reached = _reached(edges)

    nodes = [Node(START, "start", script.name.text)]
    rules = tuple(rule_text(m) for m in (*script.alfa, *script.omega))
    if rules:
        nodes.append(Node(RULES, "rules", "rules", tuple(Line("", r) for r in rules)))
        edges.insert(0, Edge(RULES, START, "rules"))
    members: list[list[str]] = [[] for _ in script.goals]
    for i, ((g, a, b), block) in enumerate(blocks):
        members[g].append(node_id(i))
        kind, title, lines = _block_view(block)
        line = source.position(block.span.start).line if source is not None else 0
        nodes.append(Node(node_id(i), kind, title, lines, i, g, block_path((g, a, b)), line,
                          node_id(i) in reached))
    if any(e.target == END for e in edges):
        nodes.append(Node(END, "end", "end of script"))
    clusters = tuple(Cluster(f"g{g}", goal.id.text, tuple(members[g]))
                     for g, goal in enumerate(script.goals))
    return Graph(script.name.text, rules, tuple(nodes), tuple(edges), clusters)


def _reached(edges: list[Edge]) -> set[str]:
    """The nodes a path from the start reaches, never taking a `never` edge."""
    out: dict[str, list[str]] = {}
    for e in edges:
        if not e.never:
            out.setdefault(e.source, []).append(e.target)
    seen = {START}
    todo = [START]
    while todo:
        for target in out.get(todo.pop(), ()):
            if target not in seen:
                seen.add(target)
                todo.append(target)
    return seen


def rule_text(message: RuleMessage) -> str:
    """A rule message as the script writes it, without its brackets:
    `alfa:1, guard, "distance=0.5", "", A, U`."""
    return (f"{message.kind}:{message.rulecode.text}, {message.id.text}, "
            f"{quote(message.intopic.value)}, {quote(message.outtopic.value)}, "
            f"{message.action.text}, {message.mutex.text}")


def _block_view(block: Block) -> tuple[str, str, tuple[Line, ...]]:
    """A block's node: its kind, its title (the label; for an unlabelled jump, sensor block
    or terminus the kind's word) and its lines."""
    label = block.label.text if block.label is not None else ""
    if isinstance(block, InstructionBlock):
        lines = (*(Line("MV", _move(m)) for m in block.moves),
                 *(_led(c) for c in block.leds),
                 *(Line("AO", _audio(a)) for a in block.audios))
        return "instructions", label, lines or (Line("", "no command"),)
    if isinstance(block, JumpBlock):
        return "jump", label or "jump", ()
    if isinstance(block, TerminusBlock):
        return "terminus", label or "end", ()
    assert isinstance(block, SensorBlock)
    return "sensor", label or "sensor", tuple(Line("", quote(p.value)) for p in block.payload)


def _value(number: Number) -> float:
    value = number.value
    return value if value is not None and value == value else 0.0  # (NaN: not a number)


def _magnitude(number: Number) -> str:
    """The number as written, without its sign."""
    return number.text.lstrip("+-")


def _timed(what: str, wait: Number, duration: Number) -> str:
    text = f"{what} for {duration.text} ms"
    return f"after {wait.text} ms, {text}" if _value(wait) != 0 else text


def _move(move: MoveCommand) -> str:
    """`forward 0.2 m/s, turn left 0.5 rad/s for 850 ms` (body frame: x forward, y left,
    theta counter-clockwise), `still for 1000 ms`."""
    parts = []
    for number, positive, negative, unit in ((move.v_x, "forward", "backward", "m/s"),
                                             (move.v_y, "left", "right", "m/s"),
                                             (move.v_theta, "turn left", "turn right", "rad/s")):
        value = _value(number)
        if value != 0:
            parts.append(f"{positive if value > 0 else negative} {_magnitude(number)} {unit}")
    return _timed(", ".join(parts) or "still", move.wait_t, move.duration)


def _led(led: LedCommand) -> Line:
    """`green (0.2, 0.8, 0.3) for 2000 ms` with the colour's `#rrggbb`, or `off for 500 ms`."""
    if _value(led.turnas) != 1:
        return Line("LD", _timed("off", led.wait_t, led.duration))
    rgb = tuple(min(1.0, max(0.0, _value(n))) for n in (led.r, led.g, led.b))
    colour = "#" + "".join(f"{round(c * 255):02x}" for c in rgb)
    written = f"{colour_name(*rgb)} ({led.r.text}, {led.g.text}, {led.b.text})"
    return Line("LD", _timed(written, led.wait_t, led.duration), colour)


def colour_name(r: float, g: float, b: float) -> str:
    """A word for a colour of channels in [0, 1]: its hue (red, orange, yellow, green, cyan,
    blue, purple, pink), `white`, `grey` or `black`, `dim` before it when it is dark."""
    high, low = max(r, g, b), min(r, g, b)
    if high < 0.1:
        return "black"
    if (high - low) / high < 0.2:
        return "white" if high > 0.7 else "grey"
    spread = high - low
    if high == r:
        hue = (60 * (g - b) / spread) % 360
    elif high == g:
        hue = 60 * (b - r) / spread + 120
    else:
        hue = 60 * (r - g) / spread + 240
    bounds = ((15, "red"), (45, "orange"), (70, "yellow"), (165, "green"), (195, "cyan"),
              (255, "blue"), (285, "purple"), (340, "pink"), (360, "red"))
    name = next(word for bound, word in bounds if hue < bound or bound == 360)
    return f"dim {name}" if high < 0.45 else name


def _audio(audio: AudioCommand) -> str:
    path = audio.track_path.value
    return _timed("silence" if path == "Silence" else path, audio.wait_t, audio.duration)


def condition_lines(condition: str, width: int = CONDITION_WIDTH,
                    most: int = CONDITION_LINES) -> list[str]:
    """The condition's text in lines of about `width` characters, broken at spaces (a word
    longer than a line is a line of its own), at most `most` of them: the last one ends with
    `…` when the text goes on."""
    lines: list[str] = []
    for word in condition.split(" "):
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += " " + word
        else:
            lines.append(word)
    if len(lines) > most:
        lines = lines[:most]
        lines[-1] = lines[-1][: width - 1].rstrip() + "…"
    return lines


def _edge_lines(edge: Edge) -> list[str]:
    """An edge's label: the outcome and the condition (wrapped), or nothing."""
    if not edge.outcome:
        return []
    return condition_lines(f"{edge.outcome}: {edge.condition}")


def _tooltip(node: Node) -> str:
    where = f"{node.path}, line {node.line}" if node.line else node.path
    if not node.reachable:
        where += " (never reached)"
    return where


# -- DOT -------------------------------------------------------------------------------------

_FONT = "Helvetica,Arial,sans-serif"
# Colours: the same meaning in both formats (docs/views.md says what each means).
INK = "#37474f"
TRUE_COLOUR = "#2e7d32"
FALSE_COLOUR = "#c62828"
NEVER_COLOUR = "#9e9e9e"
GOAL_FILL = "#eef3f8"
GOAL_BORDER = "#90a4ae"
JUMP_FILL = "#fff8e1"
JUMP_BORDER = "#f9a825"
SENSOR_FILL = "#e8eaf6"
SENSOR_BORDER = "#3949ab"
RULES_FILL = "#fffde7"
RULES_BORDER = "#fbc02d"
UNREACHED = "#9e9e9e"


def dot_string(text: str) -> str:
    """A DOT quoted string (an escString: `\\\\` and `\\"` escaped, a line break `\\n`)."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _dot_left(lines: Iterable[str]) -> str:
    """A DOT quoted string of left-justified lines (each ends with `\\l`)."""
    return '"' + "".join(line.replace("\\", "\\\\").replace('"', '\\"') + "\\l"
                         for line in lines) + '"'


def html_text(text: str) -> str:
    """Text inside a Graphviz HTML-like label (XML): `&`, `<`, `>`, `"` as entities."""
    return (text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace('"', "&quot;"))


def _attributes(pairs: Iterable[tuple[str, str]]) -> str:
    """`[name=value, ...]`; a value is written as given (quoted by the caller, or `<...>`)."""
    return "[" + ", ".join(f"{name}={value}" for name, value in pairs) + "]"


def _dot_block_label(node: Node) -> str:
    """An instruction block's HTML-like label: its title in bold, then a row per command
    (track, the light's colour as a swatch, what it does)."""
    rows = []
    if node.title:
        rows.append(f'<TR><TD COLSPAN="3"><B>{html_text(node.title)}</B></TD></TR>')
    for line in node.lines:
        swatch = (f'<TD BGCOLOR="{line.colour}" WIDTH="10"></TD>' if line.colour
                  else '<TD WIDTH="10"></TD>')
        track = f'<FONT POINT-SIZE="9">{html_text(line.track)}</FONT>' if line.track else ""
        rows.append(f'<TR><TD ALIGN="LEFT">{track}</TD>{swatch}'
                    f'<TD ALIGN="LEFT">{html_text(line.text)}</TD></TR>')
    return ('<<TABLE BORDER="0" CELLBORDER="0" CELLSPACING="0" CELLPADDING="2">'
            + "".join(rows) + "</TABLE>>")


def _dot_node(node: Node) -> str:
    grey = not node.reachable
    attrs: list[tuple[str, str]]
    if node.kind == "start":
        attrs = [("shape", "box"), ("style", '"rounded,filled"'), ("fillcolor", f'"{INK}"'),
                 ("fontcolor", '"white"'), ("label", dot_string(node.title))]
    elif node.kind == "rules":
        text = _dot_left(line.text for line in node.lines)
        attrs = [("shape", "note"), ("style", "filled"), ("fillcolor", f'"{RULES_FILL}"'),
                 ("color", f'"{RULES_BORDER}"'), ("fontsize", "9"), ("label", text),
                 ("tooltip", _RULES_TOOLTIP)]
    elif node.kind == "end":
        attrs = [("shape", "doublecircle"), ("style", "filled"), ("fillcolor", f'"{INK}"'),
                 ("fontcolor", '"white"'), ("fontsize", "9"), ("label", dot_string(node.title)),
                 ("tooltip", '"past the last block: the script ends"')]
    elif node.kind == "instructions":
        attrs = [("shape", "box"),
                 ("style", '"rounded,filled,dashed"' if grey else '"rounded,filled"'),
                 ("fillcolor", '"white"'),
                 ("label", _dot_block_label(node))]
    elif node.kind == "jump":
        attrs = [("shape", "diamond"),
                 ("style", '"filled,dashed"' if grey else "filled"),
                 ("fillcolor", f'"{JUMP_FILL}"'), ("color", f'"{JUMP_BORDER}"'),
                 ("fontsize", "10"), ("label", dot_string(node.title))]
    elif node.kind == "terminus":
        attrs = [("shape", "doublecircle"),
                 ("style", '"filled,dashed"' if grey else "filled"),
                 ("fillcolor", f'"{INK}"'), ("fontcolor", '"white"'), ("fontsize", "10"),
                 ("label", dot_string(node.title))]
    else:
        assert node.kind == "sensor", node.kind
        attrs = [("shape", "parallelogram"),
                 ("style", '"filled,dashed"' if grey else "filled"),
                 ("fillcolor", f'"{SENSOR_FILL}"'), ("color", f'"{SENSOR_BORDER}"'),
                 ("label", dot_string("\n".join([node.title, *(ln.text for ln in node.lines)])))]
    if node.index is not None:
        if grey:
            attrs += [("color", f'"{UNREACHED}"'), ("fontcolor", f'"{UNREACHED}"')]
        attrs.append(("tooltip", dot_string(_tooltip(node))))
    return f"{dot_string(node.id)} {_attributes(attrs)};"


def _dot_edge(edge: Edge) -> str:
    attrs: list[tuple[str, str]] = []
    if edge.kind == "rules":
        attrs = [("style", "dotted"), ("arrowhead", "none"), ("color", f'"{RULES_BORDER}"')]
    elif edge.kind in ("true", "false"):
        colour = (NEVER_COLOUR if edge.never
                  else TRUE_COLOUR if edge.kind == "true" else FALSE_COLOUR)
        attrs = [("label", _dot_left(_edge_lines(edge))), ("color", f'"{colour}"'),
                 ("fontcolor", f'"{colour}"'),
                 ("tooltip", dot_string(f"{edge.outcome}: {edge.condition}"))]
        if edge.kind == "false":
            attrs.insert(1, ("style", "dotted" if edge.never else "dashed"))
    else:
        attrs = [("color", f'"{INK}"')]
    return f"{dot_string(edge.source)} -> {dot_string(edge.target)} {_attributes(attrs)};"


_DOT_DEFAULTS = (
    f'  graph [fontname="{_FONT}", rankdir=TB, newrank=true, nodesep=0.35, ranksep=0.4];',
    f'  node [fontname="{_FONT}", fontsize=11, color="{INK}"];',
    f'  edge [fontname="{_FONT}", fontsize=9, arrowsize=0.7];',
)
_DOT_CLUSTER = (f'    style="rounded,filled"; fillcolor="{GOAL_FILL}"; color="{GOAL_BORDER}"; '
                "fontsize=10; labeljust=l;")
_RULES_TOOLTIP = ('"the rule messages: alfa when the script is loaded, omega when it is '
                  'unloaded"')


def to_dot(graph: Graph) -> str:
    """The graph in Graphviz's DOT language (UTF-8 text, ends with a newline)."""
    by_id = {node.id: node for node in graph.nodes}
    out = [f"digraph {dot_string(graph.name)} {{", *_DOT_DEFAULTS]
    clustered = {node_id for cluster in graph.clusters for node_id in cluster.nodes}
    out += [f"  {_dot_node(node)}" for node in graph.nodes if node.id not in clustered]
    if RULES in by_id:
        out.append(f"  {{ rank=same; {dot_string(RULES)}; {dot_string(START)}; }}")
    for cluster in graph.clusters:
        out += [f"  subgraph {dot_string('cluster_' + cluster.id)} {{",
                f"    label={dot_string('goal: ' + cluster.title)};",
                _DOT_CLUSTER]
        out += [f"    {_dot_node(by_id[node_id])}" for node_id in cluster.nodes]
        out.append("  }")
    out += [f"  {_dot_edge(edge)}" for edge in graph.edges]
    out.append("}")
    return "\n".join(out) + "\n"


# -- Mermaid ---------------------------------------------------------------------------------

# Mermaid's entity codes (`#name;`, `#35;`) for what its parser or the HTML it writes would
# read as syntax: quotes end a label, `#` starts an entity code, `<`, `>` and `&` are HTML,
# `%%` a comment, `|` ends an edge's label, a backtick starts a Markdown string.
_MERMAID = str.maketrans({'"': "#quot;", "#": "#35;", "&": "#amp;", "<": "#lt;",
                          ">": "#gt;", "%": "#37;", "|": "#124;", "`": "#96;",
                          "\\": "#92;"})


def mermaid_text(text: str) -> str:
    """Text inside a quoted Mermaid label (see `_MERMAID`)."""
    return text.translate(_MERMAID)


def _mermaid_lines(lines: Iterable[str]) -> str:
    """A quoted Mermaid label of several lines, `<br>` between them; but on one line, ` · `
    between them, when one holds a backslash: Mermaid 11 reads a label of several lines as
    Markdown, where a backslash escapes the character after it (`\\"` would lose its
    backslash), and a label of one line as it is."""
    texts = list(lines)
    glue = " · " if any("\\" in text for text in texts) else "<br>"
    return '"' + glue.join(mermaid_text(text) for text in texts) + '"'


def _mermaid_node(node: Node) -> str:
    if node.kind == "instructions":
        lines = [node.title] if node.title else []
        lines += [f"{line.track}: {line.text}" if line.track else line.text
                  for line in node.lines]
        shape = "[{}]"
    elif node.kind == "sensor":
        lines = [node.title, *(line.text for line in node.lines)]
        shape = "[/{}/]"
    elif node.kind == "rules":
        lines = [line.text for line in node.lines]
        shape = "[{}]"
    else:
        lines = [node.title]
        shape = {"start": "([{}])", "jump": "{{{}}}", "terminus": "((({})))",
                 "end": "((({})))"}[node.kind]
    css = _MERMAID_CSS.get(node.kind, node.kind)
    return f"{node.id}{shape.format(_mermaid_lines(lines))}:::{css}"


# The class of each kind of node (and of a block no path reaches): its Mermaid style.
_MERMAID_CLASSES = {
    "start": f"fill:{INK},stroke:{INK},color:#ffffff",
    "inst": f"fill:#ffffff,stroke:{INK}",
    "jump": f"fill:{JUMP_FILL},stroke:{JUMP_BORDER}",
    "terminus": f"fill:{INK},stroke:{INK},color:#ffffff",
    "scriptend": f"fill:{INK},stroke:{INK},color:#ffffff",
    "sensor": f"fill:{SENSOR_FILL},stroke:{SENSOR_BORDER}",
    "rules": f"fill:{RULES_FILL},stroke:{RULES_BORDER}",
    "unreached": f"fill:#fafafa,stroke:{UNREACHED},color:{UNREACHED},stroke-dasharray:4 3",
}
_MERMAID_CSS = {"instructions": "inst", "end": "scriptend"}


def to_mermaid(graph: Graph) -> str:
    """The graph as a Mermaid flowchart (the text of a ```mermaid block, which GitHub renders;
    ends with a newline)."""
    by_id = {node.id: node for node in graph.nodes}
    clustered = {node_id for cluster in graph.clusters for node_id in cluster.nodes}
    out = ["flowchart TD"]
    out += [f"  {_mermaid_node(node)}" for node in graph.nodes if node.id not in clustered]
    for cluster in graph.clusters:
        out.append(f"  subgraph {cluster.id}[{_mermaid_lines(['goal: ' + cluster.title])}]")
        out += [f"    {_mermaid_node(by_id[node_id])}" for node_id in cluster.nodes]
        out.append("  end")
        out.append(f"  style {cluster.id} fill:{GOAL_FILL},stroke:{GOAL_BORDER}")
    styles: dict[str, list[int]] = {}
    for number, edge in enumerate(graph.edges):
        if edge.kind == "rules":
            arrow = "-.-"
        elif edge.kind == "false":
            arrow = "-.->"
        else:
            arrow = "-->"
        # On one line: Mermaid wraps an edge's label itself.
        lines = _edge_lines(edge)
        label = f"|{_mermaid_lines([' '.join(lines)])}|" if lines else ""
        out.append(f"  {edge.source} {arrow}{label} {edge.target}")
        colour = (RULES_BORDER if edge.kind == "rules" else NEVER_COLOUR if edge.never
                  else TRUE_COLOUR if edge.kind == "true"
                  else FALSE_COLOUR if edge.kind == "false" else INK)
        styles.setdefault(colour, []).append(number)
    unreached = [node.id for node in graph.nodes if not node.reachable]
    used = {_MERMAID_CSS.get(node.kind, node.kind) for node in graph.nodes}
    if unreached:
        used.add("unreached")
    out += [f"  classDef {name} {style}" for name, style in _MERMAID_CLASSES.items()
            if name in used]
    if unreached:
        out.append(f"  class {','.join(unreached)} unreached")
    for colour, numbers in sorted(styles.items()):
        out.append(f"  linkStyle {','.join(map(str, numbers))} stroke:{colour},color:{colour}")
    return "\n".join(out) + "\n"


# -- SVG -------------------------------------------------------------------------------------

GRAPHVIZ_HELP = ("install Graphviz (Debian and Ubuntu: `apt-get install graphviz`; macOS: "
                 "`brew install graphviz`; others: https://graphviz.org/download/), or use "
                 "`--format dot` or `--format mermaid`, which need nothing")


class GraphvizError(Exception):
    """Graphviz's `dot` could not draw the graph; the message says why and what to do."""


class GraphvizMissing(GraphvizError):
    """`dot` is not on PATH."""


def dot_program() -> str:
    """The path of Graphviz's `dot` on PATH; GraphvizMissing when there is none."""
    import shutil

    found = shutil.which("dot")
    if found is None:
        raise GraphvizMissing("drawing SVG needs Graphviz's `dot` program, which is not on "
                              f"PATH: {GRAPHVIZ_HELP}")
    return found


def to_svg(graph: Graph) -> bytes:
    """The graph drawn as SVG by Graphviz (`dot -Tsvg`, the DOT of `to_dot` on its stdin).
    Raises GraphvizMissing without `dot`, GraphvizError when it fails."""
    program = dot_program()
    try:
        done = subprocess.run([program, "-Tsvg"], input=to_dot(graph).encode("utf-8"),
                              capture_output=True, check=False)
    except OSError as exc:
        raise GraphvizError(f"cannot run `{program}`: {exc.strerror or exc}") from None
    if done.returncode != 0 or not done.stdout:
        said = done.stderr.decode("utf-8", "replace").strip()
        raise GraphvizError(f"`{program} -Tsvg` failed (status {done.returncode})"
                            + (f": {said}" if said else ""))
    return done.stdout
