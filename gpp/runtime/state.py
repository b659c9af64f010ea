"""The explicit, hashable world state: fluent instances interned to slots, and activities.

A State stores only the instances whose value differs from their initial value, so two states
describing the same world are equal and hash alike (the planner memoises on them). Updates
return a new State; nothing is ever changed in place.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from enum import Enum
from typing import cast

from gpp.model.types import Sym
from gpp.runtime.values import Value, same, show


class State:
    __slots__ = ("_hash", "_plain", "_values")

    def __init__(
        self, values: dict[int, Value] | None = None, _hash: int | None = None, _plain: bool | None = None
    ) -> None:
        self._values: dict[int, Value] = values or {}
        # The hash is the XOR of the hashes of the (slot, value) items, so that an update can
        # change it item by item instead of hashing the whole state again. gpp.planner.dp
        # reads it directly (None: not computed yet), sparing a call of `__hash__`.
        self._hash: int | None = _hash
        # Every value is a symbol, a string or null (None: not known yet): then Python's `==`
        # on two values is `_identical`, and two such states compare as dicts (see __eq__).
        # (An empty state is plain: the states an update makes from it keep knowing it.)
        self._plain: bool | None = True if _plain is None and not self._values else _plain

    def get(self, slot: int, initial: Callable[[int], Value]) -> Value:
        v = self._values.get(slot, _ABSENT)
        return initial(slot) if v is _ABSENT else v

    def held(self) -> Mapping[int, Value]:
        """The instances whose value is not their initial value (read only)."""
        return self._values

    def updated(self, updates: Mapping[int, Value], initial: Callable[[int], Value]) -> State:
        """A new state with `updates` applied (instances set back to their initial value are
        dropped, to keep the representation canonical)."""
        values = dict(self._values)
        h = self._hash
        plain = self._plain
        for slot, value in updates.items():
            old = values.get(slot, _ABSENT)
            if old is not _ABSENT:
                if _identical(value, old):
                    continue
                del values[slot]
                if h is not None:
                    h ^= _item_hash(slot, old)
            if not _identical(value, initial(slot)):
                values[slot] = value
                if h is not None:
                    h ^= _item_hash(slot, value)
                if plain and type(value) not in _PLAIN_TYPES:
                    plain = False
        return State(values, h, plain)

    def updated_one(self, slot: int, value: Value, item_hash: int, initial: bool, plain: bool) -> State:
        """`updated({slot: value}, ...)` with what does not depend on the state worked out in
        advance (by generated code): `item_hash` is `_item_hash(slot, value)`, `initial` says
        whether `value` is the slot's initial value, `plain` whether it is a symbol, a string
        or null."""
        held = self._values
        h = self._hash
        old = held.get(slot, _ABSENT)
        if old is not _ABSENT:
            if old is value or (type(old) is type(value) and old == value):  # _identical, inline
                return self  # unchanged (states are never changed: no copy needed)
            if h is not None:
                h ^= hash((slot, type(old).__name__, old))  # _item_hash, inline
            if initial:
                # Dropped by a copy without it, not deleted from a full copy: a deletion
                # leaves its entry used, and the copies of this state's copies would keep the
                # larger table (docs/design.md, "Packed states").
                return State({k: v for k, v in held.items() if k != slot}, h, self._plain)
        elif initial:
            return self  # not held, and not to be
        # A held slot is overwritten in place, not deleted and added again: the copy has no
        # free entry for a new key, and the addition would grow its table though the state
        # holds no more instances (docs/design.md, "Packed states").
        values = dict(held)
        values[slot] = value
        if h is not None:
            h ^= item_hash
        return State(values, h, self._plain and plain)

    def is_plain(self) -> bool:
        """Is every held value a symbol, a string or null?"""
        plain = self._plain
        if plain is None:
            plain = self._plain = all(type(v) in _PLAIN_TYPES for v in self._values.values())
        return plain

    def changed_slots(self) -> Iterator[tuple[int, Value]]:
        return iter(self._values.items())

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, State):
            return NotImplemented
        if self._hash is not None and other._hash is not None and self._hash != other._hash:
            return False
        mine, theirs = self._plain, other._plain
        if mine and theirs:
            return self._values == other._values  # the case below, the planner's usual one
        if self.is_plain() and other.is_plain():
            # A symbol equals only a symbol of its name, a string only a string, null only
            # null: `==` is `_identical` on these, and dicts compare without Python code.
            return self._values == other._values
        return self._values.keys() == other._values.keys() and all(
            _identical(v, other._values[k]) for k, v in self._values.items()
        )

    def __hash__(self) -> int:
        h = self._hash
        if h is None:
            h = 0
            for k, v in self._values.items():
                h ^= _item_hash(k, v)
            self._hash = h
        return h

    def __repr__(self) -> str:
        return f"State({self._values})"


_PLAIN_TYPES = (Sym, str, type(None))

# Marks a slot the state does not hold (its value is the initial one); never a value.
_ABSENT: Value = cast(Value, object())


def item_hash(slot: int, v: Value) -> int:
    """The share of (slot, v) in the hash of a state that holds it."""
    return _item_hash(slot, v)


def identical(a: Value, b: Value) -> bool:
    """Same value, also in type (1 and 1.0 are equal in golog++ but stored distinctly)."""
    return _identical(a, b)


def _item_hash(slot: int, v: Value) -> int:
    # bool and int hash alike in Python; keep them apart in state hashes.
    return hash((slot, type(v).__name__, v))


def _identical(a: Value, b: Value) -> bool:
    """Same value, also in type (1 and 1.0 are equal in golog++ but stored distinctly)."""
    return a is b or (type(a) is type(b) and a == b)


@dataclass(frozen=True, slots=True)
class GroundAction:
    """An action with argument values: what an activity executes."""

    name: str
    args: tuple[Value, ...]

    @property
    def text(self) -> str:
        """`name(arg1,arg2)`: symbols by name, no spaces (the trace's `action` field)."""
        return f"{self.name}({','.join(show(a) for a in self.args)})"

    def __str__(self) -> str:
        return self.text


class ActivityStatus(Enum):
    RUNNING = "running"
    FINAL = "final"
    FAILED = "failed"
    CANCELLED = "cancelled"

    @property
    def terminal(self) -> bool:
        return self is not ActivityStatus.RUNNING


class Activities:
    """Activities that started and were not yet consumed by `end`/`finish`/`fail`."""

    __slots__ = ("_hash", "_items")

    def __init__(self, items: dict[GroundAction, ActivityStatus] | None = None) -> None:
        self._items: dict[GroundAction, ActivityStatus] = items or {}
        self._hash: int | None = None

    def status(self, action: GroundAction) -> ActivityStatus | None:
        return self._items.get(action)

    def with_status(self, action: GroundAction, status: ActivityStatus | None) -> Activities:
        items = dict(self._items)
        if status is None:
            items.pop(action, None)
        else:
            items[action] = status
        return Activities(items)

    def running(self) -> list[GroundAction]:
        return [a for a, s in self._items.items() if s is ActivityStatus.RUNNING]

    def items(self) -> list[tuple[GroundAction, ActivityStatus]]:
        return list(self._items.items())

    def __len__(self) -> int:
        return len(self._items)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Activities) and self._items == other._items

    def __hash__(self) -> int:
        if self._hash is None:
            self._hash = hash(frozenset(self._items.items()))
        return self._hash


__all__ = ["Activities", "ActivityStatus", "GroundAction", "State", "same"]
