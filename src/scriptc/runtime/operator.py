"""The operator's joystick (thesis 5.3; docs/runtime.md "The operator"): a scenario's operator
events, replayed with the fake actuator's semantics.

- `safety_lock` (`held`): every other command is ignored unless the lock is held (an
  `operator` event with `ignored`); releasing it ends a drive;
- `drive` (`v_x`, `v_y`, `v_theta`, optional `duration`): the operator's velocity;
- `interrupt` (optional `on`; without it the button toggles): freezes or resumes the block.

What each does to the wheels and the tracks is the actuators' (runtime/actuators.py); this
module says which command reaches them and writes the `operator` events.
"""

from __future__ import annotations

from scriptc.runtime.actuators import Actuators
from scriptc.runtime.scenario import OperatorEvent
from scriptc.runtime.status import RunStatus
from scriptc.runtime.trace import Trace


class Operator:
    """The joystick between a scenario's operator events and the actuators."""

    __slots__ = ("actuators", "status", "trace")

    def __init__(self, trace: Trace, actuators: Actuators, status: RunStatus) -> None:
        self.trace = trace
        self.actuators = actuators
        self.status = status

    def on_event(self, now: int, event: OperatorEvent) -> bool:
        """The event queue's handler: an operator event is due (it always makes an instant)."""
        self.status.now = now
        self.press(now, event)
        return True

    def press(self, now: int, event: OperatorEvent) -> None:
        """One command of the joystick."""
        act = self.actuators
        p = event.params
        if event.command == "safety_lock":
            self.trace.emit(now, "operator", command="safety_lock", held=p["held"])
            act.set_safety(now, p["held"])
            return
        if not act.safety_held:
            self.trace.emit(now, "operator", command=event.command, ignored=True,
                            reason="the safety lock is not held")
            return
        if event.command == "drive":
            v = (float(p.get("v_x", 0)), float(p.get("v_y", 0)), float(p.get("v_theta", 0)))
            self.trace.emit(now, "operator", command="drive", v_x=v[0], v_y=v[1], v_theta=v[2],
                            duration=p.get("duration"))
            act.drive(now, v, p.get("duration"))
        else:  # interrupt
            on = p.get("on", not act.frozen)
            self.trace.emit(now, "operator", command="interrupt", on=on)
            act.freeze(now, on)
