"""What the map asks of the script queue (thesis 4.2 step 5, table 4.2; docs/runtime.md
"Overrides" and "`Script/script_vect`"): compulsory script switches that rules raise, and
`Script/script_vect` updates that replace the LIFO.

- A switch (`Overrides.apply`, step 5) names a script (an activity name, or a path the
  catalogue's loader can read) and a block (goal index or id, action, block). Another script
  replaces the running one, which is not resumed later: unloaded (`override`), the target
  loaded (`override`) and read from that block. The running script itself is a seek: its goal
  is interrupted, its block dropped, its bindings kept. An unknown script, goal or block is
  reported (code `override`) and nothing switches (a block the target lacks: it starts at its
  first block).
- `script_vect` (`Overrides.script_vect`, when step 4 applies the update): the LIFO becomes
  the update's list, in the order the scripts will run (a name that cannot be found or loaded
  is reported, code `script_vect`, and left out); with `restart` `s_true` the running script
  stops and the first of the list starts at once.
"""

from __future__ import annotations

from scriptc.numbers import whole_number
from scriptc.runtime.actuators import Actuators
from scriptc.runtime.commands import BlockAddress
from scriptc.runtime.executor import SeekError
from scriptc.runtime.goals import Goals
from scriptc.runtime.loading import LoadError
from scriptc.runtime.scripts import Scripts
from scriptc.runtime.status import OVERRIDE, SCRIPT_VECT, RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import Record, World


class Overrides:
    """Switches and `script_vect` (see the module's docstring)."""

    __slots__ = ("actuators", "goals", "scripts", "status", "trace", "world")

    def __init__(self, world: World, trace: Trace, status: RunStatus, scripts: Scripts,
                 goals: Goals, actuators: Actuators) -> None:
        self.world = world
        self.trace = trace
        self.status = status
        self.scripts = scripts
        self.goals = goals
        self.actuators = actuators

    def apply(self, now: int) -> None:
        """Step 5: the switch a rule raised (`ScriptInfo.override`), taken from the map."""
        request = self.world.script.override
        assert request is not None  # the loop calls this only when a rule raised one
        self.world.script.override = None
        status, scripts = self.status, self.scripts
        try:
            program = scripts.find(request.script)
        except LoadError as exc:
            program, problem = None, str(exc)
        else:
            problem = f"no script named `{request.script}`"
        if program is None:
            status.report(now, OVERRIDE, f"override by `{request.by}`: {problem}")
            return
        goal = request.goal
        executor = scripts.executor
        # The running script itself: a seek (its executor), not a switch.
        same = executor if executor is not None and scripts.program is program else None
        goal_ids = (same if same is not None else program.executor()).goal_ids
        if isinstance(goal, str):
            # (A number of hundreds of digits, beyond the number policy, names no goal.)
            index = whole_number(goal) if goal.isascii() and goal.isdigit() else None
            if index is not None:
                goal = index
            elif goal in goal_ids:
                goal = goal_ids.index(goal)
            else:
                status.report(now, OVERRIDE, f"override by `{request.by}`: `{program.name}` "
                                             f"has no goal `{goal}`")
                return
        position = BlockAddress(goal, request.action, request.block)
        self.trace.emit(now, "override", by=request.by,
                        script=executor.name if executor is not None else None,
                        to=program.name, at=position.path)
        if same is not None:
            try:
                same.seek(position)
            except SeekError as exc:
                status.report(now, OVERRIDE, str(exc))
                return
            self.goals.interrupt()
            self.actuators.cancel(now)
            scripts.reread()
            return
        scripts.unload(now, "override")
        scripts.load(now, program, "override")
        target = scripts.executor
        assert target is not None  # just loaded
        try:
            target.seek(position)
        except SeekError as exc:
            status.report(now, OVERRIDE, f"{exc}: it starts at its first block")

    def script_vect(self, now: int, value: Record) -> None:
        """Table 4.2's `Script/script_vect`, applied at step 4 (see the module's docstring)."""
        scripts = self.scripts
        programs = []
        for name in value["update"]:
            try:
                program = scripts.find(name)
            except LoadError as exc:
                self.status.report(now, SCRIPT_VECT, str(exc))
                continue
            if program is None:
                self.status.report(now, SCRIPT_VECT, f"no script named `{name}`")
                continue
            programs.append(program)
        scripts.queue(programs)
        self.world.script.script_vect = [p.name for p in programs]
        if value.get("restart") == "s_true" and scripts.executor is not None \
                and scripts.program is not scripts.idle:
            scripts.unload(now, "restart")
            scripts.next(now)
