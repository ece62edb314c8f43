"""Hypothesis strategies that write scripts in the script syntax.

`scripts()` draws well-formed scripts: every construct of the language (rule messages, goals,
actions, the four block kinds, every form of condition) with labels that jumps may target.
The scripts parse; the checks may still warn (an unreachable block) or refuse (a jump cycle),
which is what the property tests want to exercise too.
"""

from __future__ import annotations

from hypothesis import strategies as st

NAMES = st.from_regex(r"[a-z][a-z0-9_]{0,6}", fullmatch=True).filter(
    lambda s: s not in {"action", "goal", "alfa", "omega", "b"}
)
NUMBERS = st.one_of(
    st.integers(0, 3000).map(str),
    st.decimals(min_value=-2, max_value=2, places=2, allow_nan=False,
                allow_infinity=False).map(str),
)
UNIT = st.sampled_from(["0", "1", "0.5", "0.25", "1.0", ".5"])
TIMES = st.integers(0, 5000).map(str)
STRINGS = st.lists(st.sampled_from(list("abz09 _./-") + ["\\\\", '\\"', "é"]),
                   max_size=12).map("".join)
CLASSES = {
    "Human": ["id", "positionrho", "positiontheta", "permanencetime", "appearanceon"],
    "Obstacle": ["positionrho", "isfixed"],
    "Object": ["positionrho", "istarget", "category"],
}


@st.composite
def values(draw, aliases: list[str]):
    kinds = ["num", "str", "var"] + (["alias", "field"] if aliases else [])
    kind = draw(st.sampled_from(kinds))
    if kind == "num":
        return draw(NUMBERS)
    if kind == "str":
        return '"' + draw(STRINGS) + '"'
    if kind == "var":
        return "@" + draw(NAMES)
    alias = draw(st.sampled_from(aliases))
    if kind == "alias":
        return alias
    return f"{alias}>&positionrho"


@st.composite
def conditions(draw):
    if draw(st.integers(0, 5)) == 0:
        return "{TRUE}"
    parts = []
    aliases: list[str] = []
    for _ in range(draw(st.integers(0, 2))):
        kind = draw(st.sampled_from(["CLASS", "VAR", "ATT"] if aliases else ["CLASS", "VAR"]))
        scope = draw(st.sampled_from("ULT"))
        if kind == "CLASS":
            cls = draw(st.sampled_from(sorted(CLASSES)))
            alias = "?" + draw(NAMES)
            while alias in aliases:
                alias += "x"
            tests = []
            for _ in range(draw(st.integers(1, 2))):
                if draw(st.booleans()):
                    field = draw(st.sampled_from(CLASSES[cls]))
                    op = draw(st.sampled_from(["OP<", "OP>", "OP="]))
                    tests.append(f"?THIS>&{field} {op} {draw(values(aliases))}")
                else:
                    tests.append(f"B: near({draw(NUMBERS)})")
            parts.append(f"{{CLASS #{cls} {scope} {alias} ({', '.join(tests)})}}")
            aliases.append(alias)
        elif kind == "VAR":
            parts.append(f"{{VAR @{draw(NAMES)} {scope} F: str({draw(values(aliases))})}}")
        else:
            alias = draw(st.sampled_from(aliases))
            parts.append(f"{{ATT {alias} ${draw(NAMES)} {scope} F: now()}}")
    parts.append("!")
    for _ in range(draw(st.integers(0, 2))):
        if draw(st.integers(0, 4)) == 0:
            parts.append("{TRUE}")
        else:
            fn = draw(st.sampled_from(["eq", "neq", "lt", "gt", "le", "ge"]))
            parts.append(f"{{E: {fn}({draw(values(aliases))}, {draw(values(aliases))})}}")
    return " ".join(parts)


def _commands(draw, kind: str) -> str:
    out = []
    for _ in range(draw(st.integers(0, 2))):
        if kind == "MV":
            fields = [draw(NUMBERS), draw(NUMBERS), draw(NUMBERS), draw(TIMES), draw(TIMES)]
        elif kind == "LD":
            fields = [draw(UNIT), draw(UNIT), draw(UNIT), draw(st.sampled_from("01")),
                      draw(TIMES), draw(TIMES)]
        else:
            path = draw(st.sampled_from(["Silence", "songs/a.wav", "songs/b, c.wav", "x/y z.wav"]))
            fields = [path, draw(TIMES), draw(TIMES)]
        out.append('"' + ", ".join(fields) + '"')
    return f"{kind}({', '.join(out)})"


@st.composite
def scripts(draw, max_blocks: int = 12):
    n_blocks = draw(st.integers(1, max_blocks))
    labels = [f"l{i}" for i in range(n_blocks)]
    labelled = [draw(st.booleans()) for _ in range(n_blocks)]
    targets = [lbl for lbl, has in zip(labels, labelled, strict=True) if has]
    lines = [f"[{draw(NAMES)}]"]
    rules = draw(st.lists(NAMES, max_size=3, unique=True))
    for i, rule in enumerate(rules):
        mutex = "U" if i == len(rules) - 1 else "M"
        rulecode = draw(st.integers(0, 2**32 - 1))
        lines.append(f'[alfa:{rulecode}, {rule}, "{draw(STRINGS)}", "", A, {mutex}]')
    for i, rule in enumerate(rules):
        mutex = "L" if i == 0 else "M"
        lines.append(f'[omega:{draw(st.integers(0, 99))}, {rule}, "", "", R, {mutex}]')
    # Split the blocks into goals and actions.
    block = 0
    goal = 0
    while block < n_blocks:
        lines.append(f"[goal:g{goal}]")
        goal += 1
        for _ in range(draw(st.integers(1, 2))):
            if block >= n_blocks:
                break
            lines.append("  [action]")
            for _ in range(draw(st.integers(1, 3))):
                if block >= n_blocks:
                    break
                label = labels[block] if labelled[block] else ""
                kind = draw(st.sampled_from(["inst", "inst", "jump", "terminus", "sens"]))
                if kind == "inst":
                    moves, leds = _commands(draw, "MV"), _commands(draw, "LD")
                    body = f"blk_inst: {moves} {leds} {_commands(draw, 'AO')}"
                elif kind == "jump":
                    t = draw(st.sampled_from([""] + targets))
                    f = draw(st.sampled_from([""] + targets))
                    body = f"blk_jump: CND({draw(conditions())}) TRJMP({t}) FLSJMP({f})"
                elif kind == "terminus":
                    body = "blk_terminus"
                else:
                    payload = draw(st.lists(STRINGS, max_size=2))
                    body = "blk_sens" + (": " + ", ".join(f'"{p}"' for p in payload)
                                         if payload else "")
                lines.append(f"    [b#{label}#{body}]")
                block += 1
    return "\n".join(lines) + "\n"
