"""Pass 1, structure of the rule messages: the letters (M005), the mutex order of the alfa and
omega lists (M001, M002, thesis 4.4), both lists present together (M003), and whether the
omega list undoes what the alfa list did (M004).
"""

from __future__ import annotations

from scriptc.check.context import Context
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, TextEdit
from scriptc.ir.nodes import RuleMessage
from scriptc.language import MUTEXES, RULE_ACTIONS, quote
from scriptc.source import Span

# What an omega message must do to undo an alfa action on the same rule id. `D` is exempt:
# thesis 3.2 lets a script load (heavy) rules ahead of time for the scripts that follow it,
# so a delayed rule is meant to outlive the script that loaded it.
UNDO = {"A": "R", "B": "R", "C": "R", "R": "C"}

_ALFA_HELP = "alfa messages are all `M` except the last, which is `U`; never `L` (thesis 4.4)"
_OMEGA_HELP = "omega messages start with `L`, then are all `M`; never `U` (thesis 4.4)"


def check_messages(ctx: Context) -> list[Diagnostic]:
    script = ctx.script
    out: list[Diagnostic] = []
    for msg in (*script.alfa, *script.omega):
        _letters(ctx, msg, out)
    _alfa_order(ctx, out)
    _omega_order(ctx, out)
    _balance(ctx, out)
    _leaks(ctx, out)
    return out


def _letters(ctx: Context, msg: RuleMessage, out: list[Diagnostic]) -> None:
    for name, table, what in ((msg.action, RULE_ACTIONS, "rule action"),
                              (msg.mutex, MUTEXES, "mutex command")):
        if name.text in table:
            continue
        shown = f"`{name.text}`" if name.text else "nothing"
        valid = ", ".join(f"`{k}` ({v})" for k, v in table.items())
        fix = None
        upper = name.text.upper()
        if upper in table and ctx.is_script_syntax:
            fix = Fix(f"write `{upper}`", (TextEdit(name.span, upper),))
        out.append(
            diagnostic(
                "M005",
                f"unknown {what} {shown} in {msg.kind} message",
                name.span,
                help=f"the {what}s are {valid}",
                fix=fix,
            )
        )


def _mutex_fix(ctx: Context, msg: RuleMessage, letter: str) -> Fix | None:
    if not ctx.is_script_syntax:
        return None
    return Fix(f"write `{letter}`", (TextEdit(msg.mutex.span, letter),))


def _alfa_order(ctx: Context, out: list[Diagnostic]) -> None:
    alfa = ctx.script.alfa
    last = len(alfa) - 1
    for i, msg in enumerate(alfa):
        letter = msg.mutex.text
        if letter not in MUTEXES:
            continue  # M005
        expected = "U" if i == last else "M"
        if letter == expected:
            continue
        if i == last:
            message = f"the last alfa message must unlock the map with `U`, found `{letter}`"
        elif letter == "U":
            message = "only the last alfa message may unlock the map with `U`"
        else:
            message = "alfa messages must never lock the map with `L`"
        notes: tuple[str, ...] = ()
        if letter == "U":
            notes = (("unlocking before the last message lets the map run through a half-built "
                      "chain of rules"),)
        out.append(
            diagnostic("M001", message, msg.mutex.span, notes=notes, help=_ALFA_HELP,
                       fix=_mutex_fix(ctx, msg, expected))
        )


def _omega_order(ctx: Context, out: list[Diagnostic]) -> None:
    for i, msg in enumerate(ctx.script.omega):
        letter = msg.mutex.text
        if letter not in MUTEXES:
            continue  # M005
        expected = "L" if i == 0 else "M"
        if letter == expected:
            continue
        if i == 0:
            message = f"the first omega message must lock the map with `L`, found `{letter}`"
        elif letter == "L":
            message = "only the first omega message may lock the map with `L`"
        else:
            message = "omega messages must never unlock the map with `U`"
        out.append(
            diagnostic("M002", message, msg.mutex.span, help=_OMEGA_HELP,
                       fix=_mutex_fix(ctx, msg, expected))
        )


def message_text(kind: str, like: RuleMessage, action: str, mutex: str) -> str:
    """A rule message in script syntax on the same rule as `like`."""
    return (
        f'[{kind}:{like.rulecode.text},{like.id.text},{quote(like.intopic.value)},'
        f'{quote(like.outtopic.value)},{action},{mutex}]'
    )


def _undo(msg: RuleMessage) -> str | None:
    return UNDO.get(msg.action.text)


def _balance(ctx: Context, out: list[Diagnostic]) -> None:
    alfa, omega = ctx.script.alfa, ctx.script.omega
    if bool(alfa) == bool(omega):
        return
    if alfa:
        last = alfa[-1]
        undo = [(m, letter) for m in alfa if (letter := _undo(m))]
        fix = None
        if undo and ctx.is_script_syntax:
            indent = ctx.indent_at(last.span.start)
            lines = [
                message_text("omega", m, letter, "L" if k == 0 else "M")
                for k, (m, letter) in enumerate(undo)
            ]
            fix = Fix(
                "add omega messages that undo the alfa list",
                (TextEdit(Span(last.span.end, last.span.end),
                          "".join(ctx.newline + indent + line for line in lines)),),
                safe=False,
            )
        out.append(
            diagnostic(
                "M003",
                "the script has alfa messages but no omega message",
                last.span,
                notes=(("the alfa list changes the chain of rules when the script is loaded; "
                        "nothing restores it, or locks the map, when the script is unloaded"),),
                help="add omega messages after the alfa list, the first with `L`, that undo what "
                     "the alfa messages did",
                fix=fix,
            )
        )
    else:
        first = omega[0]
        out.append(
            diagnostic(
                "M003",
                "the script has omega messages but no alfa message",
                first.span,
                notes=(("the omega list locks the map when the script is unloaded, but no alfa "
                        "message of this script unlocks it with `U` when the script is loaded"),),
                help="add alfa messages before the omega list, the last with `U`",
            )
        )


def _leaks(ctx: Context, out: list[Diagnostic]) -> None:
    alfa, omega = ctx.script.alfa, ctx.script.omega
    if not alfa or not omega:
        return  # M003 covers a missing list, with a fix that undoes the whole alfa list
    done = {(m.id.text, m.action.text) for m in omega}
    last = omega[-1]
    indent = ctx.indent_at(last.span.start)
    for msg in alfa:
        letter = _undo(msg)
        if letter is None or (msg.id.text, letter) in done:
            continue
        line = message_text("omega", msg, letter, "M")
        fix = None
        if ctx.is_script_syntax:
            at = Span(last.span.end, last.span.end)
            fix = Fix(f"add `{line}` to the omega list",
                      (TextEdit(at, ctx.newline + indent + line),), safe=False)
        out.append(
            diagnostic(
                "M004",
                f"the omega messages do not undo alfa `{msg.action.text}` on rule "
                f"`{msg.id.text}`",
                msg.id.span,
                notes=((f"alfa `{msg.action.text}` ({RULE_ACTIONS[msg.action.text]}) is undone "
                        f"by omega `{letter}` ({RULE_ACTIONS[letter]}); without it the change "
                        "outlives the script"),),
                help=f"add `{line}` to the omega list",
                fix=fix,
            )
        )
