"""When the cyclic garbage collector runs in the language server, which checks again and again."""

from __future__ import annotations

import gc


class GcPolicy:
    """When the cyclic garbage collector runs in a process that checks again and again.

    A check allocates a tree, a model and results (hundreds of thousands of objects for a
    large program) that live until the next check replaces them. They hold no reference
    cycles, so they die by reference counting; the collector is only needed for the few cycles
    other code makes (asyncio, the protocol, exceptions). Left to itself it would scan the
    new objects again and again in the middle of a check (tens of milliseconds), and every
    full collection would scan all the live results too. So:

    * `pause` (before a round of checks): the collector stops; the first time, what the
      process holds then (its modules, the stable part of the heap) is collected and frozen
      (`gc.freeze`: left out of every later scan);
    * `settle` (after the round's checks): what the round made is frozen too, without a scan
      (the new results, and whatever garbage the round left), and the collector runs again as
      it did before `pause`, over the objects made since: its collections between rounds stay
      small, whatever the size of the checked programs;
    * `collect` (when the typing has paused for a while): everything is unfrozen, collected
      once (the cycles left by the rounds since the last `collect` are freed) and frozen again.
      Only then does a collection scan the whole heap.

    The frozen part grows only by the cyclic garbage of the rounds (the results of a round die
    by reference counting when the next replaces them): a few objects a round (the language
    server's first collection after 240 rounds found 470, the next ones none), and a full
    collection costs 70 ms to seconds. So a `collect` is `pending` only after `min_rounds`
    rounds, twice as many after each `collect` that freed fewer objects than there were rounds
    (up to `max_rounds`, back to the first `min_rounds` after one that freed more), and `due`
    (not to wait for a pause) after `max_rounds`: a burst of typing that long collects once its
    diagnostics are out, rather than pile up garbage for ever. (Counting the frozen objects
    instead walks them all: 13 ms for the 1,000-line program.)
    """

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
