"""The planner's fast tier: the transition semantics as closures per program point
(successors) and as generated Python source (codegen)."""
