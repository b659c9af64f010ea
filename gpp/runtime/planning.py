"""The online-planning port: what the semantics and the executor need of a planner to run
`solve`/`search` online (SEMANTICS §5, §6), without depending on one.

Online, `trans` of a `solve`/`search` asks the `OnlinePlanner` for a `PlanSession` for the
statement and continues as `Planned(session, 0)` after a `PlanStep(session)`. The session
answers `final` (`exhausted`) and `trans` (`successors`) of the `Planned` continuation, and
the executor, when it performs a PlanStep or ReplanStep, asks it to `plan` or `replan` and
traces the `PlanReport` it returns. gpp.planner.policy implements the port; gpp.run.runner, above
both layers, gives the executor that implementation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from gpp.syntax import ast

if TYPE_CHECKING:
    from gpp.runtime.semantics import Frame, Planned, Semantics, Successor
    from gpp.runtime.state import Activities, State


@dataclass(frozen=True, slots=True)
class PlanReport:
    """What the trace shows of one planning attempt (a `plan` or `replan` record)."""

    kind: str  # "solve" or "search"
    feasible: bool
    value: float
    horizon: int  # the horizon (solve) or the step bound (search) it was made for
    policy: tuple[str, ...]  # the costed steps, as text: `stack(a,table)`, `loc(a) = b`
    nodes: int
    cache_hits: int
    pruned: int
    reward_evaluations: int
    seconds: float
    # A `solve` plan that uses the whole horizon and leaves the program unfinished (it pads or
    # truncates): the rest of the `solve`'s program is skipped.
    unfinished: bool = False
    # Then: the fewest costed steps that would finish the program after the plan (None: not
    # found within the search the planner allows itself for this).
    steps_left: int | None = None


class PlanSession(Protocol):
    """The plan of one `solve`/`search` being executed online: held by `Planned`, `PlanStep`
    and `ReplanStep`. It is filled (and refilled) when the executor performs those steps."""

    @property
    def stmt(self) -> ast.Solve | ast.Search: ...

    def exhausted(self, index: int) -> bool:
        """`final` of `Planned(self, index)`: the plan has been executed to its end."""
        ...

    def successors(self, sem: Semantics, p: Planned, state: State, acts: Activities) -> list[Successor]:
        """`trans` of `p` (a `Planned` of this session): the next planned step if it is still
        possible in the actual world, a ReplanStep if not."""
        ...

    def plan(self, sem: Semantics, state: State, acts: Activities) -> PlanReport:
        """Plan the statement's body from the actual state (performing the PlanStep)."""
        ...

    def replan(self, sem: Semantics, index: int, state: State, acts: Activities) -> PlanReport:
        """Plan again from the program point of `Planned(self, index)` (a ReplanStep)."""
        ...


class OnlinePlanner(Protocol):
    """What runs `solve`/`search` online: makes a session for a statement reached online."""

    def session(self, sem: Semantics, stmt: ast.Solve | ast.Search, frame: Frame, state: State) -> PlanSession: ...
