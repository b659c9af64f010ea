"""What a planner returns, and the statistics its profile shows."""

from __future__ import annotations

from dataclasses import dataclass, field

from gpp.runtime.planning import PlanReport
from gpp.runtime.semantics import EndKind, EndStep, Prog, Step

# One step of a policy: the program before it, the step, the program after it.
PolicyStep = tuple[Prog, Step, Prog]


@dataclass
class PlanStats:
    nodes: int = 0  # configurations expanded (a memo hit is not an expansion)
    cache_hits: int = 0
    pruned: int = 0  # options skipped because they provably cannot win (see gpp.planner.dp)
    bound_skips: int = 0  # of those, skipped by branch and bound (gpp.planner.bounds)
    reward_evaluations: int = 0
    seconds: float = 0.0


@dataclass(frozen=True, slots=True)
class Branch:
    """The best continuation from a configuration: feasible or not, the rewards of the states
    after its costed steps summed, and its steps."""

    feasible: bool
    value: float
    steps: tuple[PolicyStep, ...]


# Every infeasible branch is this one: what an infeasible branch did does not matter (the
# `solve` fails if nothing better exists), and one canonical value keeps the two planners
# comparable whatever they skip.
INFEASIBLE = Branch(False, 0.0, ())
# Stop here: the program may end (or the horizon is reached).
STOP = Branch(True, 0.0, ())


def better(a: Branch, b: Branch) -> bool:
    """Is `a` strictly better than `b`? (Strictly, so the earlier option wins ties.)"""
    if a.feasible != b.feasible:
        return a.feasible
    return a.value > b.value


@dataclass
class Plan:
    feasible: bool
    value: float  # R(s0) + R(s1) + ... + R(sn) for solve; 0 for search and for no plan
    steps: tuple[PolicyStep, ...]
    horizon: int  # the horizon (solve) or the step bound (search) it was made for
    stats: PlanStats = field(default_factory=PlanStats)

    def actions(self) -> list[str]:
        """The costed steps, as the trace shows them: `stack(a,table)`, `loc(a) = b`; a planned
        `during` shows as its action, like a plain call."""
        return [policy_text(step) for _, step, _ in self.steps if step.cost]

    @property
    def cost(self) -> int:
        """The horizon the policy uses."""
        return sum(step.cost for _, step, _ in self.steps)

    def report(self, kind: str) -> PlanReport:
        """What the trace shows of this plan, made for a `solve` or `search` (`kind`)."""
        stats = self.stats
        return PlanReport(
            kind=kind,
            feasible=self.feasible,
            value=self.value,
            horizon=self.horizon,
            policy=tuple(self.actions()),
            nodes=stats.nodes,
            cache_hits=stats.cache_hits,
            pruned=stats.pruned,
            reward_evaluations=stats.reward_evaluations,
            seconds=stats.seconds,
        )


def policy_text(step: Step) -> str:
    """A costed step as a plan shows it: a planned `during` shows as its action."""
    if isinstance(step, EndStep) and step.hook == EndKind.DURING:
        return step.action.text
    return step.describe()
