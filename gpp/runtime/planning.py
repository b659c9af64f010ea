"""What an online planning reports: the `PlanReport` of one `plan` or `replan` of a
`PlanSession` (the port of gpp.runtime.semantics), which the executor traces."""

from __future__ import annotations

from dataclasses import dataclass


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
    # A `solve`'s horizon as written; `horizon` is what is left of it after the steps of the
    # `solve` already executed (`spent`, as text: progress only, not failed attempts).
    written: int | None = None
    spent: tuple[str, ...] = ()
    # Why the `solve`/`search` is planned again (a `replan`): a planned step no longer possible,
    # an activity that failed, ...
    reason: str | None = None
