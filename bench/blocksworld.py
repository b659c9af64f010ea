"""Blocksworld instances for the planner benches: one description of an instance (its blocks,
where each starts, where each must end), written out as the golog++ program that `solve`s it
and as PDDL (a domain and a problem) for a classical planner, so that both planners get the
same problem.

The action model is the one of examples/blocks_planning.gpp: `stack(x, y)` moves a clear block
x onto the table or onto another clear block y, one step. In PDDL it is two actions, `stack`
(onto a block, from wherever x is) and `stack-table` (from a block onto the table), so that the
table never stops being free; a plan has the same number of steps in both.

A tower of n blocks is the reversal of examples/tower5.gpp (a on b on ... on the table, to be
turned upside down: n moves at best). A random instance draws its start and its goal as random
stacks from a seed of its own name (random.Random of a string is the same on every machine).
"""

from __future__ import annotations

import random
import re
from dataclasses import dataclass

NAMES = "abcdefghijkl"
TABLE = "table"


@dataclass(frozen=True)
class Instance:
    """A blocksworld problem: `start` and `goal` give, for each block in order, the block it is
    on or the table."""

    name: str
    blocks: tuple[str, ...]
    start: tuple[str, ...]
    goal: tuple[str, ...]

    def solved(self) -> Instance:
        """The same blocks, starting where they must end (nothing to plan)."""
        return Instance(f"{self.name}, solved", self.blocks, self.goal, self.goal)


def tower(blocks: int) -> Instance:
    """blocks[0] on blocks[1] on ... on the table, to be reversed."""
    names = tuple(NAMES[:blocks])
    start = tuple(names[i + 1] if i + 1 < blocks else TABLE for i in range(blocks))
    goal = tuple(names[i - 1] if i > 0 else TABLE for i in range(blocks))
    return Instance(f"tower {blocks}", names, start, goal)


def _random_stacks(rng: random.Random, names: tuple[str, ...]) -> tuple[str, ...]:
    """Each block's support in a random arrangement: the blocks in a random order, cut into
    stacks at random places, each stack's first block on the table."""
    order = list(names)
    rng.shuffle(order)
    under = {}
    below = TABLE
    for block in order:
        under[block] = below
        below = TABLE if rng.random() < 0.3 else block
    return tuple(under[block] for block in names)


def random_instance(blocks: int, seed: int) -> Instance:
    """A random start and a different random goal over `blocks` blocks, from `seed`."""
    rng = random.Random(f"blocksworld {blocks} blocks, seed {seed}")
    names = tuple(NAMES[:blocks])
    start = _random_stacks(rng, names)
    goal = _random_stacks(rng, names)
    while goal == start:
        goal = _random_stacks(rng, names)
    return Instance(f"random {blocks} #{seed}", names, start, goal)


def program(instance: Instance, horizon: int, twice: bool = False) -> str:
    """The golog++ program planning `instance` with `solve(horizon, reward())`: every step
    costs 1 until the goal holds, the goal is worth 100, so the best plan is a shortest one.
    `twice`: a choice of two copies of the loop (the second is planned after the first)."""
    loop = "while (!goal()) pick (block x) pick (location y) stack(x, y);"
    body = f"choose {{ {loop} {loop} }}" if twice else loop
    names = instance.blocks
    initially = " ".join(f"({b}) = {on};" for b, on in zip(names, instance.start, strict=True))
    goal = " & ".join(f"loc({b}) == {on}" for b, on in zip(names, instance.goal, strict=True))
    return f"""
symbol domain block = {{{", ".join(names)}}}
symbol domain location = block | {{table}}
location fluent loc(block x) {{ initially: {initially} }}
action stack(block x, location y) {{
precondition:
    x != y & loc(x) != y & (!exists(block z) loc(z) == x) & (y == table | !exists(block z) loc(z) == y)
effect:
    loc(x) = y;
}}
bool function goal() = {goal}
number function reward() = if (goal()) 100 else -1
procedure main() {{
    solve({horizon}, reward()) {body}
}}
"""


PDDL_DOMAIN = """(define (domain gpp-blocksworld)
  (:requirements :strips :typing :equality)
  (:types location - object block - location)
  (:constants table - location)
  (:predicates (on ?x - block ?y - location) (clear ?x - location))
  (:action stack
    :parameters (?x - block ?from - location ?y - block)
    :precondition (and (on ?x ?from) (clear ?x) (clear ?y) (not (= ?x ?y)))
    :effect (and (on ?x ?y) (not (on ?x ?from)) (clear ?from) (not (clear ?y))))
  (:action stack-table
    :parameters (?x - block ?from - block)
    :precondition (and (on ?x ?from) (clear ?x))
    :effect (and (on ?x table) (not (on ?x ?from)) (clear ?from))))
"""


def pddl_problem(instance: Instance) -> str:
    """The PDDL problem of `instance` over PDDL_DOMAIN: its blocks, `on` and `clear` facts of
    the start, and the `on` facts of the goal."""
    covered = set(instance.start)
    init = [f"(on {b} {on})" for b, on in zip(instance.blocks, instance.start, strict=True)]
    init += [f"(clear {b})" for b in instance.blocks if b not in covered]
    goal = [f"(on {b} {on})" for b, on in zip(instance.blocks, instance.goal, strict=True)]
    name = re.sub(r"[^a-z0-9]+", "-", instance.name.lower()).strip("-")
    return (
        f"(define (problem {name}) (:domain gpp-blocksworld)\n"
        f"  (:objects {' '.join(instance.blocks)} - block)\n"
        f"  (:init {' '.join(init)})\n"
        f"  (:goal (and {' '.join(goal)})))\n"
    )


def moves_of_pddl_plan(text: str) -> list[tuple[str, str]]:
    """The moves (block, where to) of a plan in the format of a PDDL planner's plan file: one
    `(action arguments...)` a line, `;` comments."""
    moves = []
    for line in text.splitlines():
        line = line.split(";", 1)[0].strip()
        if not line:
            continue
        action, *args = line.strip("()").split()
        if action == "stack":
            moves.append((args[0], args[2]))
        elif action == "stack-table":
            moves.append((args[0], TABLE))
        else:
            raise ValueError(f"not an action of the domain: {line}")
    return moves


def reaches_goal(instance: Instance, moves: list[tuple[str, str]]) -> bool:
    """Whether `moves` are legal from the instance's start (each block moved is clear, and so
    is the block it goes onto) and end in its goal."""
    on = dict(zip(instance.blocks, instance.start, strict=True))
    for block, to in moves:
        occupied = set(on.values())
        if block in occupied or block == to or on[block] == to or (to != TABLE and to in occupied):
            return False
        on[block] = to
    return tuple(on[b] for b in instance.blocks) == instance.goal
