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
