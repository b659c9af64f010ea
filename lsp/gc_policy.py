"""When the cyclic garbage collector runs in the language server, which checks again and again."""

from __future__ import annotations

import gc


class GcPolicy:
    """When the cyclic garbage collector runs in a process that checks again and again: off
    during a round of checks (`pause`), what a round made frozen after it (`settle`), and a
    full collection (`collect`) only when one is `pending` and the typing has paused, or `due`
    (docs/design.md, "Garbage")."""

    def __init__(self, min_rounds: int = 32, max_rounds: int = 1000) -> None:
        self.first_min_rounds = self.min_rounds = min_rounds
        self.max_rounds = max_rounds
        self.collections = 0
        self.freed = 0  # the unreachable objects the last `collect` found
        self.rounds = 0  # settled since the last `collect`
        self._resume: bool | None = None  # while paused: whether the collector ran before
        self._frozen = False

    @property
    def paused(self) -> bool:
        return self._resume is not None

    @property
    def pending(self) -> bool:
        """Whether `min_rounds` rounds have run since the last `collect` (their cycles, if
        any, wait for it)."""
        return self.rounds >= self.min_rounds

    @property
    def due(self) -> bool:
        """Whether `max_rounds` rounds have run since the last `collect`: the next should not
        wait for a pause."""
        return self.rounds >= self.max_rounds

    def pause(self) -> None:
        """Before a round of checks."""
        if self._resume is not None:
            return
        self._resume = gc.isenabled()
        gc.disable()
        if not self._frozen:
            gc.collect()
            gc.freeze()
            self._frozen = True

    def settle(self) -> None:
        """After a round's checks: freeze what it made, let the collector run again."""
        if self._resume is None:
            return
        self.rounds += 1
        gc.freeze()
        self._frozen = True
        if self._resume:
            gc.enable()
        self._resume = None

    def collect(self) -> None:
        """The full collection the rounds left for later (when the typing pauses)."""
        self.settle()
        if self._frozen:
            gc.unfreeze()
        self.freed = gc.collect()
        self.collections += 1
        if self.freed < self.rounds:
            self.min_rounds = min(2 * self.min_rounds, self.max_rounds)
        else:
            self.min_rounds = self.first_min_rounds
        self.rounds = 0
        if self._frozen:
            gc.freeze()

    def release(self) -> None:
        """Collect, and unfreeze what `pause` and `settle` froze (when the session ends)."""
        self.settle()
        if self._frozen:
            gc.unfreeze()
            self._frozen = False
        self.freed = gc.collect()
        self.collections += 1
        self.rounds = 0
