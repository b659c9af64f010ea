"""Small performance helpers shared by the phases."""

from __future__ import annotations

import gc
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TypeVar

T = TypeVar("T")


@contextmanager
def cached_dataclass_code(name: str) -> Iterator[None]:
    """Dataclasses defined inside reuse the compiled code of their generated methods
    (`__init__`, `__eq__`, `__hash__`, ...) from the user's cache, instead of compiling it again.

    A speed trick for start-up, in this one place: on Python 3.11 `dataclasses` compiles the
    source of every generated method with `exec` (six per frozen class: the syntax tree's 85
    classes took 40 ms, a third of `gpp check`'s start-up). Here `dataclasses` finds an `exec`
    of its own that runs the same source's code object, compiled once and kept with `marshal`
    (keyed by the source text and the Python version). The plain version is `dataclasses`
    itself: without a cache file, or for a source not in it, the code is compiled as before,
    and the result is the same code object (tests/base/test_perf.py holds them equal).
    """
    import dataclasses
    import marshal
    import types

    from gpp.base.resources import cache_dir, write_cache_file

    path = cache_dir() / f"dataclasses-{name}-{sys.implementation.cache_tag}.marshal"
    try:
        stored = marshal.loads(path.read_bytes())
    except (OSError, ValueError, EOFError, TypeError):
        stored = None
    known: dict[str, types.CodeType] = stored if isinstance(stored, dict) and stored.get("") == sys.version else {}
    used: dict[str, object] = {"": sys.version}

    def exec_cached(source: object, globals: dict[str, object] | None = None, locals: object = None) -> None:
        if isinstance(source, str):
            code = known.get(source)
            if not isinstance(code, types.CodeType):
                code = compile(source, "<string>", "exec")
            used[source] = code
            source = code
        exec(source, globals, locals)  # type: ignore[arg-type]

    outer = vars(dataclasses).get("exec")  # a cache of a package being imported around this one
    dataclasses.exec = exec_cached  # type: ignore[attr-defined]
    try:
        yield
    finally:
        if outer is None:
            del dataclasses.exec  # type: ignore[attr-defined]
        else:
            dataclasses.exec = outer  # type: ignore[attr-defined]
    if used.keys() != known.keys():
        write_cache_file(path, marshal.dumps(used))


@contextmanager
def paused_gc() -> Iterator[None]:
    """Pause the cyclic garbage collector while a phase builds a large tree.

    A phase allocates hundreds of thousands of objects that stay alive; the collector would only
    rescan the growing heap again and again (it made parsing 50,000 lines twice as slow).
    Nothing is lost: cycles are collected once the collector runs again.
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


_DEEP_STACK_BYTES = 512 * 1024 * 1024
_DEEP_RECURSION_LIMIT = 250_000
# Set on the threads started here: code already running on a deep stack runs in place.
_deep = threading.local()


def with_deep_stack(fn: Callable[[], T]) -> T:
    """Run `fn` on a thread with a large stack and a high recursion limit.

    The parser is iterative, but the checker, the printer and the interpreter recurse over the
    tree; a generated program with thousands of nested parentheses would exhaust Python's
    default limit of 1,000 frames. The thread's stack is reserved virtual memory, only the
    pages touched are used. On a thread that already has the deep stack (one started by
    `start_deep_stack_thread`, such as the language server's analysis thread), `fn` runs in place.
    """
    if getattr(_deep, "active", False):
        return fn()
    result: list[T] = []
    error: list[BaseException] = []

    def run() -> None:
        _deep.active = True
        try:
            result.append(fn())
        except BaseException as e:  # handed to the calling thread
            error.append(e)

    old_limit = sys.getrecursionlimit()
    old_size = threading.stack_size()
    try:
        threading.stack_size(_DEEP_STACK_BYTES)
        sys.setrecursionlimit(max(old_limit, _DEEP_RECURSION_LIMIT))
        # A daemon: Ctrl-C (delivered to the main thread) ends the process without waiting.
        worker = threading.Thread(target=run, name="gpp-deep-stack", daemon=True)
        worker.start()
    finally:
        threading.stack_size(old_size)
    worker.join()
    sys.setrecursionlimit(old_limit)
    if error:
        raise error[0]
    return result[0]


def start_deep_stack_thread(target: Callable[[], None], name: str) -> threading.Thread:
    """Start a long-lived daemon thread with the large stack, and raise the process's recursion
    limit for good: the thread owns what `with_deep_stack` sets and resets around each call,
    so that a process checking again and again (the language server) does not change
    process-wide settings while its other threads run."""
    old_size = threading.stack_size()
    sys.setrecursionlimit(max(sys.getrecursionlimit(), _DEEP_RECURSION_LIMIT))

    def run() -> None:
        _deep.active = True
        target()

    try:
        threading.stack_size(_DEEP_STACK_BYTES)
        thread = threading.Thread(target=run, name=name, daemon=True)
        thread.start()
    finally:
        threading.stack_size(old_size)
    return thread
