"""Actions as tasks: generators that command a scene for the next physics step, yield once per
step, and return an Outcome when they are done (see platform.py for the stepping loop)."""

from __future__ import annotations

from collections.abc import Generator, Iterable
from dataclasses import dataclass

from gpp.base.suggest import closest
from gpp.runtime.state import ActivityStatus


@dataclass(frozen=True)
class Outcome:
    """How a task ended: a terminal status, an optional sensing result, a reason."""

    status: ActivityStatus
    result: object = None
    has_result: bool = False
    reason: str = ""


Task = Generator[None, None, Outcome]


def final(result: object = None, has_result: bool = False, reason: str = "") -> Outcome:
    return Outcome(ActivityStatus.FINAL, result, has_result, reason)


def fail(reason: str) -> Outcome:
    return Outcome(ActivityStatus.FAILED, reason=reason)


def unknown(what: str, name: str, known: Iterable[str]) -> str:
    """`no frame `eats` on the map; did you mean `east`?` (or the known names)."""
    names = sorted(known)
    hint = closest(name, names)
    return f"no {what}" + (f"; did you mean `{hint}`?" if hint else f" (known: {', '.join(names)})")
