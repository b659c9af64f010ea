"""gpp's tests: one folder per package of gpp (tests/planner for gpp/planner, ...), shared
helpers in tests/support, data beside them (golden/, programs/, ...)."""
