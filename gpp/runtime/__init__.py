"""Running golog++ programs: values, state, the transition semantics and the online executor."""

from gpp.base.perf import cached_dataclass_code

# The classes of trace events, the platform contract and the semantics' steps are made when the
# package is first imported, with the compiled code of their methods from the cache (start-up:
# gpp.base.perf.cached_dataclass_code).
with cached_dataclass_code("runtime"):
    from gpp.runtime import contract, events, semantics  # noqa: F401
