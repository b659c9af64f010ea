"""What the planners share besides the semantics: where a program point is in the source, the
error for a loop without a costed step, and the guard against unbounded recursion."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import assert_never

from gpp.base.source import Span
from gpp.codes import R0010
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import AwaitEnd, Code, Conc, Done, DuringEnd, Planned, Prog, Rest, Seq, Step, Watch
from gpp.syntax import ast

# The longest run of free steps (tests) planning follows: a longer one is taken for a recursion
# that never makes a costed step (a loop that repeats a configuration is caught exactly).
FREE_STEP_LIMIT = 1000

# Planning recurses once per step of a branch. Python's default limit (1000 frames) would stop
# a long horizon or a long run of tests with a RecursionError; this one is still far from the C
# stack (CPython 3.11 runs Python-to-Python calls without C recursion).
RECURSION_LIMIT = 20_000


def program_point_span(p: Prog) -> Span | None:
    """The span of the statement a continuation executes next."""
    match p:
        case Seq():
            return program_point_span(p.first)
        case Rest():
            body = p.block.body
            return body[p.index].span if p.index < len(body) else p.block.span
        case Code():
            return p.stmt.span
        case AwaitEnd() | DuringEnd() | Watch():
            return p.span
        case Conc():
            return program_point_span(p.branches[0]) if p.branches else None
        case Planned():
            return p.session.stmt.span
        case Done():
            return None
        case _:
            assert_never(p)


def _running_loop(p: Prog) -> Span | None:
    """The innermost `while` a continuation is in (the first one along its sequence)."""
    match p:
        case Seq():
            return _running_loop(p.first) or _running_loop(p.rest)
        case Code(stmt=ast.While() as loop):
            return loop.span
        case Rest() if p.index < len(p.block.body) and isinstance(p.block.body[p.index], ast.While):
            return p.block.body[p.index].span
        case Code() | Rest() | Done() | AwaitEnd() | DuringEnd() | Watch() | Conc() | Planned():
            return None
        case _:
            assert_never(p)


def free_loop_error(q: Prog, step: Step) -> GppRuntimeError:
    """A step without cost led back to a configuration on the way to it: planning would never end.
    The span is the loop that repeats, else the step that closed the circle."""
    span = _running_loop(q)
    if span is None:
        candidate = getattr(step, "span", None)
        span = candidate if isinstance(candidate, Span) else program_point_span(q)
    return GppRuntimeError(
        R0010.free_loop(),
        span,
        ("while planning, only actions, hooks and assignments use up the horizon; tests do not",),
    )


def free_run_error(span: Span | None) -> GppRuntimeError:
    return GppRuntimeError(
        R0010.free_run(FREE_STEP_LIMIT),
        span,
        ("a recursion or loop that never uses up the horizon: only actions, hooks and assignments do",),
    )


@contextmanager
def planning_recursion_guard(span: Span | None) -> Iterator[None]:
    """Allow deep planning recursion; if even that is exceeded, fail with the `solve`/`search`
    span instead of crashing (an unbounded recursion of free steps, e.g. a procedure that calls
    itself after a test and before any action)."""
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, RECURSION_LIMIT))
    try:
        yield
    except RecursionError:
        raise GppRuntimeError(
            R0010.too_deep(),
            span,
            (f"the planner gives up at {RECURSION_LIMIT} nested configurations",),
        ) from None
    finally:
        sys.setrecursionlimit(old)
