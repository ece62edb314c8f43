"""Map updates during a run (thesis 4.5; docs/runtime.md "The map"): posted as they arrive
(a scenario's timed updates, simulated sensing, a rule's `post_update`), applied together at
the loop's step 4.

Posting follows the policies (`World.post`): an `R` update drops the pending updates of the
same object's attribute posted before it (an `update` event with `status` `dropped`), an `A`
update queues behind them. Applying writes an `update` event with `status` `applied` for each,
and hands a `Script/script_vect` update to whoever keeps the script queue
(`on_script_vect`: overrides.Overrides.script_vect). A rule's update is checked against the
map's tables first; one the map cannot take is reported (code `update`) and dropped.
"""

from __future__ import annotations

from collections.abc import Callable

from scriptc.numbers import JSONValue
from scriptc.runtime.status import UPDATE, RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import MapUpdate, Record, UpdateError, World, parse_update


class Updates:
    """Posting and applying map updates (see the module's docstring)."""

    __slots__ = ("on_script_vect", "status", "trace", "world")

    def __init__(self, world: World, trace: Trace, status: RunStatus,
                 on_script_vect: Callable[[int, Record], None] | None = None) -> None:
        self.world = world
        self.trace = trace
        self.status = status
        self.on_script_vect = on_script_vect

    def post(self, now: int, update: MapUpdate) -> None:
        """An update arrives (applied at the next step 4)."""
        for dropped in self.world.post(update):
            self.trace.emit(now, "update", **dropped.as_dict(), status="dropped")

    def post_message(self, objectid: str, attributename: str, policy: str, jsonmsg: JSONValue,
                     source: str = "") -> None:
        """An update from inside the run (a rule, named by `source`), as a sensor sends it;
        one the map cannot take is reported and dropped."""
        now = self.status.now
        try:
            update = parse_update(objectid, attributename, policy, jsonmsg)
        except UpdateError as exc:
            self.status.report(now, UPDATE, f"{source or 'update'}: {exc}")
            return
        self.post(now, update)

    def apply(self, now: int) -> None:
        """Step 4: every pending update, in the order posted."""
        world = self.world
        for update in world.take_pending():
            world.apply(update, now)
            self.trace.emit(now, "update", **update.as_dict(), status="applied")
            if update.attributename == "script_vect" and self.on_script_vect is not None:
                self.on_script_vect(now, update.value)
