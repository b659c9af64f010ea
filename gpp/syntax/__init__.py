"""The syntax of golog++: tokens, the parser with recovery, the syntax tree, the printer and the
formatter."""

from gpp.base.perf import cached_dataclass_code

# The syntax tree's classes are made when the package is first imported, with the compiled code
# of their methods from the cache (start-up: gpp.base.perf.cached_dataclass_code).
with cached_dataclass_code("syntax-ast"):
    from gpp.syntax import ast  # noqa: F401
