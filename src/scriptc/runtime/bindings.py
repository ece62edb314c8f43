"""Aliases, VARs and ATTs with their scopes (thesis 4.3): the part of the map that conditions
write. Shared by every executor and by the rule chain.

- An alias names one entity (`?kid` -> `Human/kid1`); an entity holds at most one alias at a
  time, so an entity that already holds one is not a candidate for another.
- A VAR (`@count`) holds a text; an ATT (`?kid>$mood`) holds a text bound to the alias, not to
  the entity: it goes when the alias goes.
- Scopes: `U` lasts while the script runs (the session calls `end_script` when it unloads, and
  a rule may drop a binding), `T` until the map returns to the map producer (`end_loop`, after
  the chain pass), `L` until the owner that bound it passes the map on (`end_owner`: after
  each rule's turn, and for the block reader at the end of its reading step).
- A binding asserted again keeps the longer of its scopes (U > T > L): a rule that tests an
  alias the script bound with `U` must not shorten it to its own turn.

Every operation is O(1) but the expiries, which are O(bindings of that scope).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

from scriptc.runtime.world import Entity

SCOPE_RANK = {"L": 0, "T": 1, "U": 2}


T = TypeVar("T", Entity, str)


@dataclass(slots=True)
class Slot(Generic[T]):
    """One binding: its value (an Entity for an alias, a text for a VAR or ATT), scope and
    owner (who bound it: a rule id, or READER for the block reader)."""

    value: T
    scope: str
    owner: str


# Whether a binding outlives an expiry, judged by its scope and owner (whatever its value).
Keep = Callable[["Slot[Entity] | Slot[str]"], bool]


READER = "<block reader>"


class Bindings:
    __slots__ = ("aliases", "atts", "holder", "vars")

    def __init__(self) -> None:
        self.aliases: dict[str, Slot[Entity]] = {}
        self.holder: dict[int, str] = {}  # id(entity) -> alias (one alias per entity)
        self.vars: dict[str, Slot[str]] = {}
        self.atts: dict[tuple[str, str], Slot[str]] = {}

    # -- aliases ----------------------------------------------------------------------------

    def lookup(self, alias: str) -> Entity | None:
        slot = self.aliases.get(alias)
        return slot.value if slot is not None else None

    def alias_of(self, entity: Entity) -> str | None:
        return self.holder.get(id(entity))

    def bind(self, alias: str, entity: Entity, scope: str, owner: str) -> None:
        """Bind `alias` to `entity`. The caller has checked that the entity holds no other
        alias; binding the same alias to another entity first drops the old binding."""
        slot = self.aliases.get(alias)
        if slot is not None:
            if slot.value is entity:
                if SCOPE_RANK[scope] > SCOPE_RANK[slot.scope]:
                    slot.scope, slot.owner = scope, owner
                return
            self.unbind(alias)
        self.aliases[alias] = Slot(entity, scope, owner)
        self.holder[id(entity)] = alias

    def unbind(self, alias: str) -> None:
        slot = self.aliases.pop(alias, None)
        if slot is None:
            return
        self.holder.pop(id(slot.value), None)
        for key in [k for k in self.atts if k[0] == alias]:
            del self.atts[key]

    # -- VAR and ATT --------------------------------------------------------------------------

    def get_var(self, name: str) -> str | None:
        slot = self.vars.get(name)
        return slot.value if slot is not None else None

    def set_var(self, name: str, value: str, scope: str, owner: str) -> None:
        old = self.vars.get(name)
        if old is not None and SCOPE_RANK[old.scope] > SCOPE_RANK[scope]:
            scope, owner = old.scope, old.owner
        self.vars[name] = Slot(value, scope, owner)

    def get_att(self, alias: str, name: str) -> str | None:
        slot = self.atts.get((alias, name))
        return slot.value if slot is not None else None

    def set_att(self, alias: str, name: str, value: str, scope: str, owner: str) -> None:
        old = self.atts.get((alias, name))
        if old is not None and SCOPE_RANK[old.scope] > SCOPE_RANK[scope]:
            scope, owner = old.scope, old.owner
        self.atts[(alias, name)] = Slot(value, scope, owner)

    # -- expiry -------------------------------------------------------------------------------

    def _expire(self, keep: Keep) -> None:
        for alias in [a for a, s in self.aliases.items() if not keep(s)]:
            self.unbind(alias)
        for name in [n for n, s in self.vars.items() if not keep(s)]:
            del self.vars[name]
        for key in [k for k, s in self.atts.items() if not keep(s)]:
            del self.atts[key]

    def end_owner(self, owner: str) -> None:
        """`owner` passes the map on: its `L` bindings end."""
        if self.aliases or self.vars or self.atts:
            self._expire(lambda s: not (s.scope == "L" and s.owner == owner))

    def end_loop(self) -> None:
        """The map is back with the map producer: every `T` (and any left `L`) binding ends."""
        if self.aliases or self.vars or self.atts:
            self._expire(lambda s: s.scope == "U")

    def end_script(self) -> None:
        """The script ends: every binding ends (`U` lasts while the script runs)."""
        self.aliases.clear()
        self.holder.clear()
        self.vars.clear()
        self.atts.clear()

    def snapshot(self) -> dict[str, str]:
        """Every binding as text, for traces: `?kid` -> `Human/kid1`, `@v` -> value,
        `?kid>$mood` -> value."""
        out = {a: s.value.key for a, s in self.aliases.items()}
        out.update((n, s.value) for n, s in self.vars.items())
        out.update((f"{a}>${n}", s.value) for (a, n), s in self.atts.items())
        return out
