"""The files of the repository that repeat a fact the code states, written from the code.

A fact has one home in the code: the language's lexical facts and vocabulary
(`scriptc.language`), the robot's limits (`scriptc.robot.limits`), the diagnostic codes
(`scriptc.diagnostics.codes`), the bytecode's layout and opcodes (`scriptc.bytecode`). The
files that cannot import Python repeat some of them, and are written from those homes here:

- the editor extension's TextMate grammar (`scriptc.ide.textmate`), its word and indentation
  patterns (lsp/vscode/language-configuration.json) and first-line pattern (package.json);
- the validator of the thesis-JSON schema (`frontend/thesis_validator.py`, by fastjsonschema);
- the JSON Schemas: the name and number patterns, the function kinds, the `[robot]` table and
  the implementation pattern (`project/config/settings.py`) of the configuration's, the name
  and number patterns and the rule-message letters of the thesis script's, the robot profile
  of the trace's `session_start`;
- the generated regions of docs/*.md, each between `<!-- generated: NAME -->` and
  `<!-- end: NAME -->` (the prose around them is written by hand): the lexical facts of
  docs/language.md, the limits of docs/configuration.md and docs/robot.md, the layouts and
  opcodes of docs/bytecode.md; and docs/diagnostics.md, the catalogue of codes.

A JSON file is rewritten whole (two-space indentation), a Markdown file only inside its
regions. tests/test_generated.py fails when a file is stale;

    python -m scriptc.generate            # rewrite the stale files, name them
    python -m scriptc.generate --check    # exit 1 naming the stale files, write nothing

Run from a checkout: the files are the repository's, found from this module's place.
"""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

from scriptc import language
from scriptc.project.config.settings import IMPLEMENTATION_PATTERN
from scriptc.robot.limits import LIMITS, MISSING_LIMIT_RULE, toml_section

__all__ = ["ROOT", "TARGETS", "fill_regions", "generated", "main", "regions", "stale"]

ROOT = Path(__file__).resolve().parent.parent.parent

_REGION = re.compile(r"(<!-- generated: ([\w-]+) -->\n)(.*?)(<!-- end: \2 -->)", re.DOTALL)


def fill_regions(text: str, renderers: Mapping[str, Callable[[], str]]) -> str:
    """`text` with each region a renderer is named for rewritten (others are left alone)."""
    def fill(m: re.Match) -> str:
        render = renderers.get(m.group(2))
        if render is None:
            return m.group(0)
        return f"{m.group(1)}\n{render()}\n\n{m.group(4)}"

    return _REGION.sub(fill, text)


def regions(text: str) -> set[str]:
    """The names of the generated regions of a Markdown text."""
    return {m.group(2) for m in _REGION.finditer(text)}


def _json(data: Any) -> str:
    """JSON with two-space indentation, one value a line."""
    return json.dumps(data, indent=2, ensure_ascii=False) + "\n"


def _inline(value: Any) -> str:
    if isinstance(value, dict):
        if not value:
            return "{}"
        return "{ " + ", ".join(f"{json.dumps(k, ensure_ascii=False)}: {_inline(v)}"
                                for k, v in value.items()) + " }"
    if isinstance(value, list):
        return "[" + ", ".join(_inline(v) for v in value) + "]"
    return json.dumps(value, ensure_ascii=False)


def _nested(value: Any) -> bool:
    """Whether an object or array holds an object that holds an object or array."""
    inner = value.values() if isinstance(value, dict) else value
    return any(isinstance(v, dict) and any(isinstance(w, (dict, list)) for w in v.values())
               for v in inner)


def _compact(value: Any, indent: int = 0, prefix: int = 0, width: int = 100) -> str:
    one = _inline(value)
    if not isinstance(value, (dict, list)) or (
            indent + prefix + len(one) < width and not _nested(value)):
        return one
    pad = " " * (indent + 2)
    if isinstance(value, dict):
        items = []
        for k, v in value.items():
            key = json.dumps(k, ensure_ascii=False)
            items.append(f"{pad}{key}: {_compact(v, indent + 2, len(key) + 2, width)}")
        return "{\n" + ",\n".join(items) + "\n" + " " * indent + "}"
    return ("[\n" + ",\n".join(pad + _compact(v, indent + 2, 0, width) for v in value) + "\n"
            + " " * indent + "]")


def _compact_json(data: Any) -> str:
    """JSON as the hand-written schemas are laid out: a value on one line when it fits in 100
    columns and nests at most an object or array in an object, else one member a line."""
    return _compact(data) + "\n"


def _cell(text: str) -> str:
    """Text for a cell of a Markdown table (a `|`, even in code, ends a cell)."""
    return text.replace("|", "\\|")


def _code(text: str) -> str:
    return f"`{text}`"


# -- the editor extension ---------------------------------------------------------------------


def _tmgrammar(_old: str) -> str:
    from scriptc.ide.textmate import grammar

    return _json(grammar())


def _prefixed(written: str) -> Callable[[re.Match[str]], str]:
    """A replacement that keeps the match's first group (the key) and writes `written`."""
    def replace(m: re.Match[str]) -> str:
        return m.group(1) + written

    return replace


def _json_strings(values: Mapping[str, str]) -> Callable[[str], str]:
    """Rewrite the string value of each (unique) key of a JSON text, leaving its layout."""
    def rewrite(old: str) -> str:
        text = old
        for key, value in values.items():
            pattern = re.compile(rf'("{re.escape(key)}"\s*:\s*)"(?:[^"\\]|\\.)*"')
            if len(pattern.findall(text)) != 1:
                raise ValueError(f"the key `{key}` is not in the file exactly once")
            written = json.dumps(value, ensure_ascii=False)
            text = pattern.sub(_prefixed(written), text)
        return text

    return rewrite


def _language_configuration(old: str) -> str:
    from scriptc.ide import textmate

    return _json_strings({"wordPattern": textmate.word_pattern(),
                          "increaseIndentPattern": textmate.increase_indent(),
                          "decreaseIndentPattern": textmate.decrease_indent()})(old)


def _package(old: str) -> str:
    from scriptc.ide import textmate

    return _json_strings({"firstLine": textmate.first_line()})(old)


# -- the JSON Schemas ------------------------------------------------------------------------


def _anchored(pattern: str) -> str:
    return f"^{pattern}$"


def _sentence(text: str) -> str:
    return text[:1].upper() + text[1:]


def _robot_table() -> dict[str, Any]:
    """The `[robot]` table of the configuration's schema, from robot/limits.py."""
    properties = {}
    for limit in LIMITS:
        prop: dict[str, Any] = {"description": f"{_sentence(limit.doc)}. Unit: {limit.unit}; "
                                               f"default {limit.default}.",
                                "type": "number",
                                "exclusiveMinimum" if limit.exclusive else "minimum": limit.minimum}
        if limit.maximum is not None:
            prop["maximum"] = limit.maximum
        properties[limit.key] = prop
    return {
        "description": "The robot profile: the limits of the robot the activities run on, for "
                       f"the safety checks and the governor. {MISSING_LIMIT_RULE}",
        "type": "object",
        "additionalProperties": False,
        "properties": properties,
    }


def _letters_enum(table: Mapping[str, str]) -> dict[str, Any]:
    codes = [f"{letter} ({ord(letter)})" for letter in table]
    return {"description": f"ASCII code of {', '.join(codes[:-1])} or {codes[-1]}.",
            "enum": [ord(letter) for letter in table]}


def _config_schema(old: str) -> str:
    schema = json.loads(old)
    defs = schema["$defs"]
    defs["name"]["pattern"] = _anchored(language.NAME_PATTERN)
    kind = defs["function"]["properties"]["kind"]
    kind["description"] = "; ".join(f"`{k}`: {v}" for k, v in language.FUNCTION_KINDS.items()) + "."
    kind["enum"] = list(language.FUNCTION_KINDS)
    defs["robot"] = _robot_table()
    defs["implementation"]["pattern"] = _anchored(IMPLEMENTATION_PATTERN)
    return _compact_json(schema)


def _thesis_schema(old: str) -> str:
    schema = json.loads(old)
    defs = schema["$defs"]
    defs["name"]["pattern"] = _anchored(language.NAME_PATTERN)
    defs["numberText"]["pattern"] = _anchored(language.NUMBER_PATTERN)
    message = defs["ruleMessage"]["properties"]
    message["action"] = _letters_enum(language.RULE_ACTIONS)
    message["mutexcmd"] = _letters_enum(language.MUTEXES)
    return _compact_json(schema)


THESIS_SCHEMA = "schemas/thesis-script.schema.json"

# What the generated validator raises: fastjsonschema's exception, declared in the module itself
# so that reading thesis JSON needs neither fastjsonschema nor its compile at run time.
_VALIDATOR_EXCEPTION = '''

class JsonSchemaValueException(ValueError):
    """The document is not valid (the first error met; jsonschema's messages say more)."""

    def __init__(self, message, value=None, name=None, definition=None, rule=None):
        super().__init__(message)
        self.message = message
        self.value = value
        self.name = name
        self.definition = definition
        self.rule = rule


JsonSchemaValuesException = JsonSchemaValueException
'''


def _thesis_validator(_old: str) -> str:
    """The thesis-JSON schema compiled to Python by fastjsonschema (`compile_to_code`), as the
    schema file will be written: the yes or no of `frontend/thesis_json.py`. Compiling at run
    time cost a cold `scriptc check` about 50 ms, importing fastjsonschema 20 more."""
    import fastjsonschema

    schema = json.loads(_thesis_schema((ROOT / THESIS_SCHEMA).read_text(encoding="utf-8")))
    code = fastjsonschema.compile_to_code(schema)
    imports = "from fastjsonschema import JsonSchemaValueException, JsonSchemaValuesException\n"
    if imports not in code:
        raise RuntimeError("fastjsonschema's generated code changed its imports: update "
                           "scriptc.generate._thesis_validator")
    code = code.replace(imports, "", 1)
    body_at = code.index("\n\n")
    header = ('"""The validator of schemas/thesis-script.schema.json, generated by `python -m '
              "scriptc.generate`\n"
              f"(fastjsonschema {fastjsonschema.VERSION}, `compile_to_code`): do not edit.\n"
              "\n"
              "`validate(data)` returns the data or raises `JsonSchemaValueException` at the "
              "first error.\n"
              '"""\n'
              "# ruff: noqa\n"
              "# mypy: ignore-errors\n"
              "\n")
    entry = re.search(r"^def (\w+)\(", code, re.MULTILINE)
    if entry is None:
        raise RuntimeError("fastjsonschema's generated code has no function")
    return (header + code[:body_at] + _VALIDATOR_EXCEPTION + code[body_at:].rstrip("\n")
            + f"\n\n\n# The schema's own validator (the first function fastjsonschema writes).\n"
              f"validate = {entry.group(1)}\n")


def _dicts(node: Any) -> Iterator[dict[str, Any]]:
    stack = [node]
    while stack:
        item = stack.pop()
        if isinstance(item, dict):
            yield item
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)


def _trace_schema(old: str) -> str:
    schema = json.loads(old)
    (start,) = [d for d in _dicts(schema)
                if isinstance(d.get("properties"), dict) and "profile" in d["properties"]]
    start["properties"]["profile"] = {
        "description": "The robot profile the governor keeps (docs/robot.md), in the units of "
                       "the `[robot]` table.",
        "type": "object",
        "properties": {limit.field: {"description": limit.unit, "type": "number"}
                       for limit in LIMITS},
        "required": [limit.field for limit in LIMITS],
        "additionalProperties": False,
    }
    return _json(schema)


# -- the docs' regions ------------------------------------------------------------------------


def render_lexical() -> str:
    """docs/language.md: the tokens, as regular expressions read from the grammar."""
    sigils = language.SIGILS
    rows = [
        ("comment", "`% ... %`, may span lines", language.COMMENT_PATTERN),
        ("string", "`\"...\"` on one line; escapes "
         + " and ".join(_code("\\" + e) for e in sorted(language.STRING_ESCAPES)),
         language.STRING_PATTERN),
        ("name", "letters, digits, `_` and `-`; not a digit or `-` first",
         language.NAME_PATTERN),
        ("number", "decimal: sign, fraction and exponent optional (`-0.25`, `10`, `.5`, `1e3`)",
         language.NUMBER_PATTERN),
        ("alias", (f"`{sigils['ALIAS']}` and a name (`?kid`); `{language.THIS}` is the "
                   "candidate of a CLASS test"), language.sigiled("ALIAS")),
        ("class", f"`{sigils['CLASS_REF']}` and a name (`#Human`)",
         language.sigiled("CLASS_REF")),
        ("variable", f"`{sigils['VAR_REF']}` and a name (`@count`)",
         language.sigiled("VAR_REF")),
        ("attribute", f"`{sigils['ATT_REF']}` and a name (`$mood`)",
         language.sigiled("ATT_REF")),
        ("comparison", ", ".join(f"`{op}` ({word})" for op, word in language.OPERATORS.items()),
         language.OPERATOR_PATTERN),
    ]
    lines = ["| token | written | as a regular expression |", "|---|---|---|"]
    lines += [f"| {t} | {_cell(w)} | {_cell(_code(r))} |" for t, w, r in rows]
    words = [
        ("items", (*language.ITEM_KEYWORDS, "b")),
        ("blocks", language.BLOCK_KINDS),
        ("tracks", language.TRACKS),
        ("jumps", language.JUMP_WORDS),
        ("conditions", (*language.ASSIGNMENTS, language.TRUE, *language.FUNCTION_KINDS)),
    ]
    lines += ["", "Keywords (a keyword where the grammar expects it, a name elsewhere: a label "
                  "may be `goal`): " + "; ".join(f"{what} " + ", ".join(map(_code, group))
                                                 for what, group in words) + "."]
    letters = [("ACTION of a rule message", language.RULE_ACTIONS),
               ("MUTEX of a rule message", language.MUTEXES),
               ("scope of an assignment", language.SCOPES),
               ("kind of a function call", language.FUNCTION_KINDS)]
    lines += ["", "| letter | of | meaning |", "|---|---|---|"]
    lines += [f"| `{k}` | {what} | {_cell(v)} |" for what, table in letters
              for k, v in table.items()]
    return "\n".join(lines)


def render_robot_limits() -> str:
    """docs/configuration.md: the keys of `[robot]`."""
    lines = ["| key | unit | default | range | what it limits |", "|---|---|---|---|---|"]
    lines += [f"| `{limit.key}` | {limit.unit} | {limit.default} | {limit.range} | "
              f"{_cell(limit.doc)} |" for limit in LIMITS]
    return "\n".join(lines)


def render_robot_example() -> str:
    return f"```toml\n{toml_section()}```"


def render_robot_profile() -> str:
    """docs/robot.md: the profile, its defaults and who keeps each limit."""
    lines = ["| key (`[robot]` of `scriptc.toml`) | default | used by |", "|---|---|---|"]
    lines += [f"| `{limit.key}` | {limit.default} {limit.unit} | {_cell(limit.used_by)} |"
              for limit in LIMITS]
    return "\n".join(lines)


def _markdown(renderers: Mapping[str, Callable[[], str]]) -> Callable[[str], str]:
    def rewrite(old: str) -> str:
        found = regions(old)
        if found != set(renderers):
            raise ValueError(f"the file's generated regions are {sorted(found)}, the code "
                             f"writes {sorted(renderers)}")
        return fill_regions(old, renderers)

    return rewrite


def _bytecode_docs(old: str) -> str:
    from scriptc.bytecode.docs import GENERATED

    return _markdown(GENERATED)(old)


def _catalogue(_old: str) -> str:
    from scriptc.diagnostics.catalogue import render_catalogue

    return render_catalogue()


# Each generated file (relative to the repository) and how it is written from its old text.
TARGETS: dict[str, Callable[[str], str]] = {
    "lsp/vscode/syntaxes/scriptc.tmLanguage.json": _tmgrammar,
    "lsp/vscode/language-configuration.json": _language_configuration,
    "lsp/vscode/package.json": _package,
    "schemas/config.schema.json": _config_schema,
    THESIS_SCHEMA: _thesis_schema,
    "src/scriptc/frontend/thesis_validator.py": _thesis_validator,
    "schemas/trace.schema.json": _trace_schema,
    "docs/language.md": _markdown({"lexical": render_lexical}),
    "docs/configuration.md": _markdown({"robot-limits": render_robot_limits,
                                        "robot-example": render_robot_example}),
    "docs/robot.md": _markdown({"robot-profile": render_robot_profile}),
    "docs/bytecode.md": _bytecode_docs,
    "docs/diagnostics.md": _catalogue,
}


def generated(target: str, root: Path = ROOT) -> tuple[str, str]:
    """(the file's text, what it should be) for one of `TARGETS`."""
    old = (root / target).read_text(encoding="utf-8")
    return old, TARGETS[target](old)


def stale(root: Path = ROOT) -> list[str]:
    """The targets whose text is not what the code writes."""
    out = []
    for target in TARGETS:
        old, new = generated(target, root)
        if old != new:
            out.append(target)
    return out


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    check = "--check" in args
    from scriptc.writing import write_file

    out = stale()
    for target in out:
        if not check:
            write_file(str(ROOT / target), generated(target)[1])
        print(f"{'stale' if check else 'written'}: {target}")
    return 1 if check and out else 0


if __name__ == "__main__":
    sys.exit(main())
