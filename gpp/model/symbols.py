"""Symbols: everything a name can refer to, and the references to them."""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from enum import Enum
from typing import NamedTuple

from gpp.base.source import Span
from gpp.model.types import Type, show_value
from gpp.syntax import ast

_weak = weakref.ref


class SymbolKind(Enum):
    DOMAIN = "domain"
    COMPOUND = "compound type"
    BUILTIN_TYPE = "type"
    FLUENT = "fluent"
    ACTION = "action"
    EXOG_ACTION = "exogenous action"
    FUNCTION = "function"
    EXOG_FUNCTION = "exogenous function"
    PROCEDURE = "procedure"
    COMPONENT = "component"
    PARAMETER = "parameter"
    VARIABLE = "variable"
    SYMBOL = "symbol"
    FIELD = "field"
    CLOCK = "clock"
    STATE = "state"

    @property
    def article(self) -> str:
        return "an" if self.value[0] in "aeiou" else "a"


GLOBAL_KINDS = frozenset(
    {
        SymbolKind.FLUENT,
        SymbolKind.ACTION,
        SymbolKind.EXOG_ACTION,
        SymbolKind.FUNCTION,
        SymbolKind.EXOG_FUNCTION,
        SymbolKind.PROCEDURE,
        SymbolKind.COMPONENT,
    }
)
# Kinds that can be called inside an expression, and as a statement.
EXPRESSION_CALLABLE = frozenset({SymbolKind.FLUENT, SymbolKind.FUNCTION, SymbolKind.EXOG_FUNCTION})
STATEMENT_CALLABLE = frozenset({SymbolKind.ACTION, SymbolKind.PROCEDURE})


@dataclass(eq=False, slots=True, init=False, weakref_slot=True)
class Symbol:
    """A declared thing. Compared by identity: two symbols are the same only if they are.
    (Slots: the model builder makes one for every declaration, parameter and variable.)

    A member (parameter, field, clock, state) knows its `owner` through a weak reference: the
    owner lists its members, and a strong link back would make every symbol with parameters a
    reference cycle, which only the cyclic garbage collector frees. The model keeps every owner
    alive (its globals, types and references), so `owner` is None only for a member of a model
    already dropped."""

    name: str
    kind: SymbolKind
    # The name at the defining declaration (or at the first forward declaration when there is
    # no definition); None for predefined symbols.
    span: Span | None
    # The declaration that defines it (ast.FluentDecl, ast.Param, ast.Pick, ...).
    decl: ast.Node | None
    # Value type (fluents, functions, parameters, variables, fields), the type a domain or
    # compound declares, or the result type of an action/procedure (void).
    type: Type | None
    params: tuple[Symbol, ...]
    # Forward declarations and repeated symbol occurrences in domain sets (see `other_spans`).
    _other_spans: list[Span] | None
    # For parameters, fields, clocks and states: the symbol they belong to (see `owner`).
    _owner: weakref.ReferenceType[Symbol] | None
    predefined: bool
    # For components: its states and clocks by name; for compounds: its fields.
    members: dict[str, Symbol]

    def __init__(
        self,
        name: str,
        kind: SymbolKind,
        span: Span | None,
        decl: ast.Node | None = None,
        type: Type | None = None,
        owner: Symbol | None = None,
        params: tuple[Symbol, ...] = (),
        other_spans: list[Span] | None = None,
        predefined: bool = False,
        members: dict[str, Symbol] | None = None,
    ) -> None:
        # The model builder passes `decl`, `type` and `owner` by position: a class called with
        # keywords packs them into a dict for `__init__`, for every symbol it makes.
        self.name = name
        self.kind = kind
        self.span = span
        self.decl = decl
        self.type = type
        self.params = params
        self._other_spans = other_spans
        self._owner = None if owner is None else _weak(owner)
        self.predefined = predefined
        self.members = {} if members is None else members

    @property
    def other_spans(self) -> list[Span]:
        """Forward declarations and repeated symbol occurrences in domain sets. The list is
        made when first asked for (and kept, so appending to it adds a span): most symbols
        have none, and every list made is one more object for the cyclic garbage collector to
        scan after each build."""
        spans = self._other_spans
        if spans is None:
            spans = self._other_spans = []
        return spans

    @other_spans.setter
    def other_spans(self, spans: list[Span]) -> None:
        self._other_spans = spans

    @property
    def owner(self) -> Symbol | None:
        """For parameters, fields, clocks and states: the symbol they belong to."""
        ref = self._owner
        return None if ref is None else ref()

    def __repr__(self) -> str:
        return f"Symbol({self.kind.value} {self.name})"

    @property
    def is_defined(self) -> bool:
        """False for a global that has only forward declarations."""
        d = self.decl
        if isinstance(d, ast.FluentDecl):
            return d.initially is not None
        if isinstance(d, ast.ActionDecl):
            return d.sections is not None
        if isinstance(d, ast.FunctionDecl):
            return d.body is not None
        if isinstance(d, ast.ProcedureDecl):
            return d.body is not None
        if isinstance(d, ast.DomainDecl):
            return d.definition is not None
        return True

    def signature(self) -> str:
        """How hover and messages show it: `number fluent count(block b)`."""
        params = ", ".join(f"{p.type} {p.name}" for p in self.params)
        k = self.kind
        if k in (SymbolKind.FLUENT, SymbolKind.FUNCTION):
            return f"{self.type} {k.value} {self.name}({params})"
        if k is SymbolKind.EXOG_FUNCTION:
            return f"{self.type} exog_function {self.name}({params})"
        if k is SymbolKind.ACTION:
            return f"action {self.name}({params})"
        if k is SymbolKind.EXOG_ACTION:
            return f"exog_action {self.name}({params})"
        if k is SymbolKind.PROCEDURE:
            return f"procedure {self.name}({params})"
        if k is SymbolKind.DOMAIN:
            from gpp.model.types import DomainType

            t = self.type
            if isinstance(t, DomainType):
                shown = ", ".join(show_value(v) for v in t.values[:12])
                more = ", ..." if len(t.values) > 12 else ""
                return f"{t.element} domain {self.name} = {{{shown}{more}}}"
            return f"domain {self.name}"
        if k is SymbolKind.COMPOUND:
            from gpp.model.types import CompoundType

            t = self.type
            if isinstance(t, CompoundType):
                fields = ", ".join(f"{ft} {fn}" for fn, ft in t.fields.items())
                return f"compound {self.name} {{ {fields} }}"
        if k in (SymbolKind.PARAMETER, SymbolKind.VARIABLE, SymbolKind.FIELD):
            return f"{self.type} {self.name}"
        return f"{k.value} {self.name}"


class Reference(NamedTuple):
    """An occurrence of a symbol's name in the source; `declaration` marks the defining name
    or a forward declaration's name. A named tuple: the model builder makes one for every name
    of the program, and a tuple is made in a third of the time a frozen dataclass takes."""

    span: Span
    symbol: Symbol
    declaration: bool = False


class ScopeRecord(NamedTuple):
    """A local scope (a body with parameters, a pick, a quantifier) and its variables, kept so
    that completion knows what is visible where. A named tuple, as `Reference` (the type
    checker records one for every body with parameters)."""

    span: Span
    symbols: tuple[Symbol, ...]
