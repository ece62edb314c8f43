"""Pass 5, the conditions of jump blocks (rule grammar, docs/rules.md, thesis 4.3):
classes (R001), fields (R002), functions against the registry (R003 unknown, R004 wrong kind,
R005 wrong arity), aliases used before they are bound (R006), scopes (R007), aliases bound
twice (R008) and `?THIS` outside the tests of a CLASS assignment (R009).

Binding (decided, see explanations/R006.md): assignments run left to right, so inside one
condition an alias is bound from the end of the CLASS assignment that binds it (its own tests
come before). Across conditions, an alias that an earlier jump block (in execution order)
binds with scope `U` counts as bound, since `U` lasts while the script runs. Fields are
checked only where the alias's class is certain: `?THIS` inside a CLASS assignment's tests,
an alias bound earlier in the same condition, or an alias that every CLASS assignment of the
script binds to the same class.
"""

from __future__ import annotations

import bisect

from scriptc.check.context import Context, closest, code_list, suggestion
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, Label, TextEdit
from scriptc.ir.builtins import CLASSES
from scriptc.ir.nodes import (
    AliasRef,
    AttAssignment,
    AttRef,
    Call,
    CallEvaluation,
    CallTest,
    ClassAssignment,
    Condition,
    FieldRef,
    FieldTest,
    Name,
    NumberValue,
    TrueEvaluation,
    VarAssignment,
)
from scriptc.ir.walk import ConditionVisitor
from scriptc.language import SCOPES

# The scopes of language.SCOPES, said short enough for a help line.
_SCOPES = {
    "U": "while the script runs",
    "L": "until the binding rule passes the map on",
    "T": "for one loop of the map",
}

_KIND_ROLE = {
    "B": "`B:` functions test the candidate entity of a CLASS assignment",
    "F": "`F:` functions give the value of a VAR or ATT assignment",
    "E": "`E:` functions evaluate the condition after the `!`",
}
_KIND_RETURNS = {
    "B": "returns a boolean about the candidate entity",
    "F": "returns a string",
    "E": "returns a boolean",
}
# The names of each class's fields, in order, and as a set (a 1 MB script checks some 10,000
# fields).
_FIELD_NAMES = {cls: tuple(f.name for f in fields) for cls, fields in CLASSES.items()}
_FIELD_SETS = {cls: frozenset(names) for cls, names in _FIELD_NAMES.items()}


def _bare(text: str, sigil: str) -> str:
    """A name without its sigil (`#Human` -> `Human`), whichever way lowering kept it."""
    return text[len(sigil):] if text.startswith(sigil) else text


def check_conditions(ctx: Context) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    if not ctx.jumps:
        return out
    sites = _binding_sites(ctx)
    classes = {alias: {_bare(a.class_name.text, "#") for _, a in where}
               for alias, where in sites.items()}
    u_bound: set[str] = set()
    for position, (_, jump) in enumerate(ctx.jumps):
        condition = jump.condition
        _ConditionChecker(ctx, out, u_bound, classes, sites, position).run(condition)
        for asg in condition.assignments:
            if isinstance(asg, ClassAssignment) and asg.scope.text == "U" and not asg.alias.is_this:
                u_bound.add(asg.alias.name.text)
    return out


def _binding_sites(ctx: Context) -> dict[str, list[tuple[int, ClassAssignment]]]:
    """Every CLASS assignment binding each alias, with the position of its jump block among
    the script's jump blocks (execution order)."""
    sites: dict[str, list[tuple[int, ClassAssignment]]] = {}
    for position, (_, jump) in enumerate(ctx.jumps):
        for asg in jump.condition.assignments:
            if isinstance(asg, ClassAssignment) and not asg.alias.is_this:
                sites.setdefault(asg.alias.name.text, []).append((position, asg))
    return sites


class _ConditionChecker(ConditionVisitor):
    """Checks one condition; `u_bound` holds the aliases bound with `U` by earlier blocks.
    Each kind of node is checked by its `visit_` method; a test or a value is checked with
    the CLASS assignment whose tests hold it, if any (`tests_of`), and that assignment's class
    if it is known (`this_class`)."""

    def __init__(self, ctx: Context, out: list[Diagnostic], u_bound: set[str],
                 script_classes: dict[str, set[str]],
                 sites: dict[str, list[tuple[int, ClassAssignment]]], position: int) -> None:
        self.ctx = ctx
        self.out = out
        self.u_bound = u_bound
        self.script_classes = script_classes
        self.sites = sites
        self.position = position
        # alias -> the CLASS assignment that bound it most recently in this condition
        self.bound: dict[str, ClassAssignment] = {}
        self.first_binding: dict[str, ClassAssignment] = {}
        self.reported_unbound: set[str] = set()
        self.binding_here: dict[str, ClassAssignment] = {}

    def run(self, condition: Condition) -> None:
        for asg in condition.assignments:
            if isinstance(asg, ClassAssignment):
                self.binding_here.setdefault(asg.alias.name.text, asg)
        methods = self.methods  # (the visitor's dispatch without `visit`'s call: `ir/walk.py`)
        for node in (*condition.assignments, *condition.evaluations):
            methods[type(node)](self, node)

    # -- assignments and evaluations ------------------------------------------------------

    def visit_var_assignment(self, asg: VarAssignment) -> None:
        self.scope(asg.scope)
        self.call(asg.call, None)

    def visit_att_assignment(self, asg: AttAssignment) -> None:
        self.use(asg.alias, None)
        self.scope(asg.scope)
        self.call(asg.call, None)

    def visit_call_evaluation(self, ev: CallEvaluation) -> None:
        self.call(ev.call, None)

    def visit_true_evaluation(self, ev: TrueEvaluation) -> None:
        pass  # nothing to check

    def visit_field_test(self, test: FieldTest, asg: ClassAssignment, cls: str | None) -> None:
        if cls is not None:
            self.field(test.field, cls, None)
        self.methods[type(test.value)](self, test.value, asg, cls)

    def visit_call_test(self, test: CallTest, asg: ClassAssignment, cls: str | None) -> None:
        self.call(test.call, (asg, cls))

    def visit_class_assignment(self, asg: ClassAssignment) -> None:
        self.scope(asg.scope)
        cls = self.class_name(asg.class_name)
        for test in asg.tests:
            self.methods[type(test)](self, test, asg, cls)
        alias = asg.alias
        if alias.is_this:
            self.this_outside(alias)
            return
        text = alias.name.text
        first = self.first_binding.get(text)
        if first is not None:
            self.out.append(
                diagnostic(
                    "R008",
                    f"the alias `{text}` is bound twice in one condition",
                    alias.span,
                    labels=(Label(first.alias.span, "first bound here"),),
                    notes=(("an entity holds one alias at a time (thesis 4.3); the second "
                            "assignment rebinds the alias and the first entity is lost"),),
                    help="give the second entity its own alias",
                )
            )
        else:
            self.first_binding[text] = asg
        self.bound[text] = asg

    def scope(self, scope: Name) -> None:
        if scope.text in SCOPES:
            return
        valid = ", ".join(f"`{k}` ({_SCOPES.get(k, v)})" for k, v in SCOPES.items())
        fix = None
        if scope.text.upper() in SCOPES and self.ctx.is_script_syntax:
            fix = Fix(f"write `{scope.text.upper()}`", (TextEdit(scope.span, scope.text.upper()),))
        shown = f"`{scope.text}`" if scope.text else "nothing"
        self.out.append(
            diagnostic("R007", f"unknown scope {shown}", scope.span,
                       help=f"the scopes are {valid}", fix=fix)
        )

    def class_name(self, name: Name) -> str | None:
        cls = _bare(name.text, "#")
        if cls in CLASSES:
            return cls
        best = closest(cls, CLASSES)
        help, fix = suggestion(
            self.ctx, best, "a class", name.span,
            None if best is None else name.text[: len(name.text) - len(cls)] + best,
            "write", f"the classes of the map are {code_list(CLASSES)}",
        )
        self.out.append(
            diagnostic("R001", f"unknown class `{cls}`", name.span, help=help, fix=fix)
        )
        return None

    # -- uses -----------------------------------------------------------------------------

    def use(self, alias: AliasRef, tests_of: ClassAssignment | None) -> None:
        """An alias read by a value, or named by an ATT assignment."""
        if alias.is_this:
            if tests_of is None:
                self.this_outside(alias)
            return
        text = alias.name.text
        if text in self.bound or text in self.u_bound or text in self.reported_unbound:
            return
        self.reported_unbound.add(text)
        labels = []
        later = self.binding_here.get(text)
        elsewhere = self._other_block_binding(text)
        if later is not None:
            labels.append(Label(later.alias.span, f"`{text}` is bound here, after this use"))
            help = f"move the CLASS assignment that binds `{text}` before its first use"
        elif elsewhere is not None and elsewhere[0] < self.position:
            asg = elsewhere[1]
            labels.append(Label(asg.scope.span,
                                f"an earlier block binds `{text}` with scope "
                                f"`{asg.scope.text}`, which does not last until here"))
            help = f"bind `{text}` with scope `U` there, or bind it again in this condition"
        elif elsewhere is not None:
            labels.append(Label(elsewhere[1].alias.span,
                                f"`{text}` is bound only in a later block"))
            help = f"bind `{text}` in this condition or in an earlier jump block with scope `U`"
        else:
            help = (f"bind it first, e.g. `{{CLASS #Human U {text} (B: near(1.5))}}` before "
                    "this use, or in an earlier jump block with scope `U`")
        self.out.append(
            diagnostic(
                "R006",
                f"the alias `{text}` is used before it is bound",
                alias.span,
                labels=labels,
                notes=(("assignments run left to right; only CLASS assignments bind aliases, "
                        "and only earlier ones in this condition or earlier jump blocks with "
                        "scope `U` count"),),
                help=help,
            )
        )

    def _other_block_binding(self, alias: str) -> tuple[int, ClassAssignment] | None:
        """The binding of `alias` in another block nearest before this one (its scope is
        not `U`, or the alias would count as bound), else the first after it."""
        where = self.sites.get(alias, ())
        # Sites are in block order: bisect keeps this linear overall even when every block
        # binds the alias and every other one uses it unbound.
        i = bisect.bisect_left(where, self.position, key=lambda site: site[0])
        before = where[i - 1] if i > 0 else None
        while i < len(where) and where[i][0] == self.position:
            i += 1
        after = where[i] if i < len(where) else None
        return before or after

    def this_outside(self, alias: AliasRef) -> None:
        self.out.append(
            diagnostic(
                "R009",
                "`?THIS` used outside the tests of a CLASS assignment",
                alias.span,
                notes=(("`?THIS` is the candidate entity a CLASS assignment is testing; "
                        "elsewhere there is no candidate"),),
                help="name the entity by the alias a CLASS assignment bound it to",
            )
        )

    # -- values ---------------------------------------------------------------------------

    def visit_alias(self, value: AliasRef, tests_of: ClassAssignment | None,
                    this_class: str | None) -> None:
        self.use(value, tests_of)

    def visit_field(self, value: FieldRef, tests_of: ClassAssignment | None,
                    this_class: str | None) -> None:
        alias = value.alias
        self.use(alias, tests_of)
        if alias.is_this:
            if tests_of is not None and this_class is not None:
                self.field(value.field, this_class, None)
            return
        cls, binding = self.class_of(alias.name.text)
        if cls is not None:
            self.field(value.field, cls, (alias.name.text, binding))

    def visit_att(self, value: AttRef, tests_of: ClassAssignment | None,
                  this_class: str | None) -> None:
        self.use(value.alias, tests_of)

    def visit_number(self, value: NumberValue, *_context: object) -> None:
        pass  # a literal binds and names nothing

    visit_string = visit_var = visit_number  # a VAR is set at run time, by any rule

    def class_of(self, alias: str) -> tuple[str | None, ClassAssignment | None]:
        """The class an alias certainly holds here, and the assignment that says so."""
        asg = self.bound.get(alias)
        if asg is not None:
            cls = _bare(asg.class_name.text, "#")
            return (cls if cls in CLASSES else None), asg
        if alias not in self.u_bound:
            return None, None  # unbound: R006 was reported
        classes = self.script_classes.get(alias, set())
        if len(classes) == 1:
            (cls,) = classes
            if cls in CLASSES:
                return cls, None
        return None, None

    def field(self, name: Name, cls: str, via: tuple[str, ClassAssignment | None] | None) -> None:
        field = _bare(_bare(name.text, ">"), "&")
        if field in _FIELD_SETS[cls]:
            return
        fields = _FIELD_NAMES[cls]
        labels = []
        if via is not None and via[1] is not None:
            labels.append(Label(via[1].class_name.span,
                                f"`{via[0]}` is bound to {_a(cls)} `{cls}` here"))
        best = closest(field, fields)
        help, fix = suggestion(
            self.ctx, best, "a field", name.span,
            None if best is None else name.text[: len(name.text) - len(field)] + best,
            "write", f"the fields of `{cls}` are {code_list(fields)}",
        )
        owners = [c for c, fs in CLASSES.items() if any(f.name == field for f in fs)]
        notes = (f"`{field}` is a field of {code_list(owners)}",) if owners else ()
        self.out.append(
            diagnostic("R002", f"`{cls}` has no field `{field}`", name.span,
                       labels=labels, notes=notes, help=help, fix=fix)
        )

    # -- calls ----------------------------------------------------------------------------

    def call(self, call: Call, test: tuple[ClassAssignment, str | None] | None) -> None:
        tests_of, this_class = test if test is not None else (None, None)
        for arg in call.args:
            self.methods[type(arg)](self, arg, tests_of, this_class)
        registry = self.ctx.functions
        name = call.name.text
        function = registry.get(name)
        kind = call.kind
        if function is None:
            same_kind = registry.names(kind)
            help, fix = suggestion(
                self.ctx, closest(name, same_kind), f"{_article(kind)} {kind} function",
                call.name.span, None, "call", f"the {kind} functions are {code_list(same_kind)}",
            )
            self.out.append(
                diagnostic("R003", f"unknown {kind} function `{name}`", call.name.span,
                           notes=(("functions come from the function registry: the standard "
                                   "set and those the activity repository declares"),),
                           help=help, fix=fix)
            )
            return
        if function.kind != kind:
            self.out.append(
                diagnostic(
                    "R004",
                    f"`{name}` is {_article(function.kind)} {function.kind} function, "
                    f"used as {_article(kind)} {kind} function",
                    call.name.span,
                    notes=((f"{_KIND_ROLE[kind]}; `{function.signature}` "
                            f"{_KIND_RETURNS[function.kind]}"),),
                    help=f"the {kind} functions are {code_list(registry.names(kind))}",
                )
            )
            return
        if function.arity != len(call.args):
            given = len(call.args)
            self.out.append(
                diagnostic(
                    "R005",
                    f"`{name}` takes {_count(function.arity)} but {_count(given, verb=True)}",
                    call.span,
                    notes=(f"the signature is `{function.signature}`",),
                    help=f"call it as `{function.signature}`",
                )
            )


def _a(word: str) -> str:
    return "an" if word[:1].lower() in "aeiou" else "a"


def _article(kind: str) -> str:
    return "an" if kind in "EF" else "a"


def _count(n: int, verb: bool = False) -> str:
    word = "argument" if n == 1 else "arguments"
    if not verb:
        return f"{n} {word}"
    return f"{n} {'was' if n == 1 else 'were'} given"
