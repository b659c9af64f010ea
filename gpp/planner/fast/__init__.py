"""The planner's speed tier: `final`, `trans` and `apply` of gpp.runtime.semantics (planning
mode) made faster per program point, with results and errors exactly the semantics' own.

Three forms of one transition semantics, each faster form falling back to the slower one for
whatever it does not cover:

1. the reference, gpp.runtime.semantics.Semantics (`final`, `trans`, `final_code`,
   `trans_code`, `apply`): the definition, one case per statement kind;
2. closures per program point (successors.py, `Successors`), made once per continuation with
   everything that does not depend on the state done in advance; the parts they do not
   specialise (procedure bodies, assignments, hooks, `during`, concurrency, `pick ... in
   {...}`) call the semantics;
3. generated Python source per continuation (codegen.py, `TransGen`, `ApplyGen`); the parts
   it does not write out call the closures of 2 (through `port.Closures`), and a nesting
   deeper than `codegen.MAX_DEPTH`, a function longer than `codegen.MAX_LINES` or a
   continuation beyond the first `successors.MAX_TRANS_UNITS` of a semantics object runs the
   closures only.

Expressions have the same two faster forms: closures (gpp.runtime.compiled) and generated
source (gpp.runtime.codegen), which calls the closure of any expression it does not write out.
Imports run one way: successors -> codegen -> port.

The switch: `gpp.planner.dp.solve_plan(..., generate=False)` (`successors_of(sem, False)`)
plans with the closures alone, no generated source (`gpp.planner.search.search_plan(...,
tier=CLOSURES)` searches so). `GPP_DUMP_CODE=1` prints the generated source as it is built.

The tests that keep the forms equal: tests/planner/test_planner_successors.py (closures and generated
functions against `Semantics.final`/`trans`/`apply` on every configuration reachable in random
programs, errors included, and a planning with and without generated source),
tests/runtime/test_compile_cache.py (compiled source reused, constants per build), and
tests/planner/test_planner.py and tests/planner/test_planner_properties.py (the production planner against
gpp.planner.reference, which runs the semantics itself), and tests/planner/test_search_fast.py
(`search`, which runs on this tier too, against the same search on the semantics, node for node).
"""
