"""What the generated source of gpp.planner.fast.codegen calls back into: the function types of
the tier, the two constant `final`s, and `Closures`, the closures per program point that
gpp.planner.fast.successors.Successors makes (codegen falls back to them for what it does not
write out)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from gpp.model.symbols import Symbol
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.semantics import Frame, Prog, Semantics, Step, Successor
from gpp.runtime.state import Activities, State
from gpp.syntax import ast

TransFn = Callable[[State, Activities], list[Successor]]
FinalFn = Callable[[State, Activities], bool]
ApplyFn = Callable[[State, Activities], tuple[State, Activities]]


def never(state: State, acts: Activities) -> bool:
    """`final` of a statement that is never final, whatever the state (nothing is evaluated)."""
    return False


def always(state: State, acts: Activities) -> bool:
    """`final` of a statement that is final whatever the state."""
    return True


class Closures(Protocol):
    """`final` and `trans` of one semantics object (planning mode) as functions per program
    point, and the bookkeeping of the generated functions."""

    @property
    def sem(self) -> Semantics: ...

    @property
    def program(self) -> CompiledProgram: ...

    def trans_fn(self, p: Prog) -> TransFn:
        """`trans` of the continuation `p`."""
        ...

    def final_fn(self, p: Prog) -> FinalFn:
        """`final` of the continuation `p`."""
        ...

    def code_trans(self, s: ast.Statement, frame: Frame, known: frozenset[int] = ...) -> TransFn:
        """`trans` of `s` with the bindings of `frame`; `known`: precondition conjuncts known
        to hold."""
        ...

    def guarded_call(self, s: ast.Pick) -> Symbol:
        """The action called inside the `pick`s of a pick guard."""
        ...

    def register_apply(self, step: Step, fn: ApplyFn | None) -> None:
        """`apply` of this step object is `fn` (None: the semantics')."""
        ...

    def unit_name(self, prefix: str) -> str:
        """A name for a generated function, unique in this planning."""
        ...
