"""Planning for `solve` (decision-theoretic, SEMANTICS §5) and `search` (SEMANTICS §6).

One algorithm per module, all on top of the one transition semantics (gpp.runtime.semantics):

* reference — the plain recursive definition of `solve`: the oracle the tests compare with;
* dp — the production `solve` planner: the reference's result, memoised and pruned;
* search — depth-first `search` with visited configurations pruned and a step bound;
* policy — executing a plan online, re-planning when the world deviates;
* problem — a `solve` as a stand-alone problem (tests, benchmarks, tools);
* profile — the `gpp run --profile` table, rendered from the trace;
* result, guards — what planners return, and what they share.
"""
