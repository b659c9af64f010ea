"""What a stopped run shows under Variables: values as golog++ literals (compounds and lists
expandable), the fluents grouped by fluent, the activities, the plan of a `solve`. Each
expandable thing gets a handle (a DAP `variablesReference`) that lasts until the run goes on."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from gpp.dap.backend import Scope, Variable
from gpp.model.symbols import SymbolKind
from gpp.model.types import CompoundType, ListType, Type
from gpp.runtime.compiled import CompiledProgram, domain_values
from gpp.runtime.semantics import Planned
from gpp.runtime.state import Activities, State
from gpp.runtime.values import CompoundValue, Value, show

# A fluent with more instances than this shows those the run has read or written only.
ALL_INSTANCES_UP_TO = 256


class Handles:
    """variablesReference -> how to list the children."""

    def __init__(self) -> None:
        self._children: list[Callable[[], list[Variable]]] = []

    def reset(self) -> None:
        self._children = []

    def add(self, children: Callable[[], list[Variable]]) -> int:
        self._children.append(children)
        return len(self._children)

    def expand(self, reference: int) -> list[Variable]:
        if not 0 < reference <= len(self._children):
            from gpp.dap.protocol import DapError

            raise DapError(f"no variables under reference {reference} (the run went on since)")
        return self._children[reference - 1]()


def type_text(t: Type | None, value: Value) -> str:
    if t is not None:
        return str(t)
    if isinstance(value, CompoundValue):
        return value.type_name
    if isinstance(value, tuple):
        return "list"
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int | float):
        return "number"
    if isinstance(value, str):
        return "string"
    return "symbol" if value is not None else ""


def value_variable(handles: Handles, name: str, value: Value, t: Type | None, expression: str | None) -> Variable:
    """A value, expandable when it is a non-empty compound or list."""
    reference = 0
    if isinstance(value, CompoundValue) and value.fields:
        fields = dict(t.fields) if isinstance(t, CompoundType) else {}

        def compound_children(v: CompoundValue = value) -> list[Variable]:
            return [
                value_variable(handles, n, x, fields.get(n), f"{expression}.{n}" if expression else None)
                for n, x in v.fields
            ]

        reference = handles.add(compound_children)
    elif isinstance(value, tuple) and value:
        element = t.element if isinstance(t, ListType) else None

        def list_children(v: tuple[Value, ...] = value) -> list[Variable]:
            return [
                value_variable(handles, f"[{i}]", x, element, f"{expression}[{i}]" if expression else None)
                for i, x in enumerate(v)
            ]

        reference = handles.add(list_children)
    return Variable(name, show(value), type_text(t, value), reference, expression)


def values_scope(handles: Handles, name: str, values: Sequence[tuple[str, Value]], hint: str | None) -> Scope:
    def children() -> list[Variable]:
        return [value_variable(handles, n, v, None, n if hint is not None else None) for n, v in values]

    return Scope(name, handles.add(children), hint, count=len(values))


def fluent_scope(handles: Handles, program: CompiledProgram, state: State) -> Scope:
    """One entry per fluent: its value, or (with parameters) its instances to expand."""
    model = program.model
    fluents = sorted(
        (s for s in model.globals.values() if s.kind is SymbolKind.FLUENT and not s.predefined), key=lambda s: s.name
    )

    def instances(name: str) -> list[tuple[tuple[Value, ...], int]]:
        symbol = model.globals[name]
        domains = [domain_values(p.type, model) for p in symbol.params]
        size = 1
        for d in domains:
            size *= len(d)
        if all(domains) and size <= ALL_INSTANCES_UP_TO:
            return [(args, program.slot(name, args)) for args in itertools.product(*domains)]
        return [(args, slot) for slot, (n, args) in enumerate(program.instances) if n == name]

    def fluent_children() -> list[Variable]:
        out: list[Variable] = []
        for symbol in fluents:
            if not symbol.params:
                value = state.get(program.slot(symbol.name, ()), program.initial)
                out.append(value_variable(handles, symbol.name + "()", value, symbol.type, f"{symbol.name}()"))
                continue

            def instance_children(name: str = symbol.name, t: Type | None = symbol.type) -> list[Variable]:
                rows = []
                for args, slot in instances(name):
                    call = f"{name}({', '.join(show(a) for a in args)})"
                    rows.append(value_variable(handles, call, state.get(slot, program.initial), t, call))
                return rows

            count = len(instances(symbol.name))
            out.append(
                Variable(
                    f"{symbol.name}({', '.join(p.name for p in symbol.params)})",
                    f"{count} instance{'s' if count != 1 else ''}",
                    str(symbol.type),
                    handles.add(instance_children),
                )
            )
        return out

    return Scope("Fluents", handles.add(fluent_children), count=len(fluents))


def activity_scope(
    handles: Handles, acts: Activities, records: Mapping[Any, Any], started_at: Mapping[int, float]
) -> Scope:
    """The activities not yet consumed: their state and start time."""
    items = acts.items()

    def children() -> list[Variable]:
        out: list[Variable] = []
        for g, status in items:
            record = records.get(g)
            started = started_at.get(record.id) if record is not None else None
            when = f", started at {started:.3f} s" if started is not None else ""
            out.append(Variable(g.text, f"{status.value}{when}", "activity"))
        return out

    return Scope("Activities", handles.add(children), count=len(items))


def plan_scope(handles: Handles, planned: Planned) -> Scope:
    """The plan of the `solve`/`search` being executed: its policy, the step it is at."""
    session: Any = planned.session
    policy = getattr(session, "policy", None) or ()
    base = getattr(session, "base", 0)
    step = planned.index - base

    def children() -> list[Variable]:
        out = [
            Variable("kind", str(getattr(session, "kind", "solve"))),
            Variable("step", f"{step + 1} of {len(policy)}" if step < len(policy) else "done"),
        ]
        if getattr(session, "kind", "") == "solve":
            out.append(Variable("horizon", str(getattr(session, "horizon", ""))))
        for i, (_, s, _) in enumerate(policy):
            mark = "→ " if i == step else ("✓ " if i < step else "  ")
            out.append(Variable(f"{mark}{i + 1}", s.describe(), "step"))
        return out

    return Scope("Plan", handles.add(children), count=len(policy) + 3)
