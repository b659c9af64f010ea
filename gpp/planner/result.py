"""What a planner returns, and the statistics its profile shows."""

from __future__ import annotations

from dataclasses import dataclass, field

from gpp.runtime.semantics import Prog, Step

# One step of a policy: the program before it, the step, the program after it.
PolicyStep = tuple[Prog, Step, Prog]


@dataclass
class PlanStats:
    nodes: int = 0  # configurations expanded
    cache_hits: int = 0
    pruned: int = 0
    reward_evaluations: int = 0
    seconds: float = 0.0


@dataclass(frozen=True, slots=True)
class Branch:
    """The best continuation from a configuration."""

    feasible: bool
    value: float
    steps: tuple[PolicyStep, ...]


@dataclass
class Plan:
    feasible: bool
    value: float  # R(s0) + R(s1) + ... + R(sn) for solve; 0 for search
    steps: tuple[PolicyStep, ...]
    horizon: int
    stats: PlanStats = field(default_factory=PlanStats)

    def actions(self) -> list[str]:
        return [step.describe() for _, step, _ in self.steps if step.cost]
