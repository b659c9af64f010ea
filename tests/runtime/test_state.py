"""The planner's state update `State.updated_one` against the general `State.updated`."""

from __future__ import annotations

import sys

from gpp.model.types import Sym
from gpp.runtime.state import State, item_hash
from gpp.runtime.values import Value

INITIAL: Value = Sym("table")


def initial(slot: int) -> Value:
    return INITIAL


def one(state: State, slot: int, value: Value) -> State:
    """`updated_one` with its arguments worked out as the generated code works them out."""
    return state.updated_one(slot, value, item_hash(slot, value), value == INITIAL, True)


def five_held() -> State:
    return State().updated({slot: Sym(f"b{slot}") for slot in range(5)}, initial)


def test_overwriting_a_held_instance_is_the_state_updated_makes() -> None:
    before = five_held()
    after = one(before, 2, Sym("b9"))
    expected = before.updated({2: Sym("b9")}, initial)
    assert after == expected and hash(after) == hash(expected) == hash(State(dict(expected.held())))
    assert dict(after.held()) == {0: Sym("b0"), 1: Sym("b1"), 2: Sym("b9"), 3: Sym("b3"), 4: Sym("b4")}
    assert before.held()[2] == Sym("b2")  # the state updated is left as it was


def test_an_instance_set_back_to_its_initial_value_is_dropped() -> None:
    after = one(five_held(), 2, INITIAL)
    assert 2 not in after.held() and after == five_held().updated({2: INITIAL}, initial)
    assert hash(after) == hash(State(dict(after.held())))
    assert one(five_held(), 7, INITIAL) == five_held()  # not held, initial: nothing changes


def test_overwriting_a_held_instance_does_not_grow_the_copy() -> None:
    # Deleting the slot and adding it again would need a free entry the copy lacks and grow
    # its table (docs/design.md, "Packed states"): the planner keeps one state per configuration.
    before = five_held()
    assert sys.getsizeof(one(before, 2, Sym("b9")).held()) == sys.getsizeof(before.held())


def test_dropping_an_instance_leaves_the_table_of_a_state_built_without_it() -> None:
    six = five_held().updated({5: Sym("b5")}, initial)
    dropped = one(six, 5, INITIAL)
    assert dropped == five_held() and hash(dropped) == hash(five_held())
    assert sys.getsizeof(dropped.held()) == sys.getsizeof(five_held().held())
