"""Planning for `solve` (decision-theoretic, SEMANTICS §5) and `search` (SEMANTICS §6)."""
