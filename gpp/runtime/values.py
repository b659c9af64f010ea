"""Runtime values (SEMANTICS §3).

* bool, int, float (numbers keep int/float), str, Sym (a symbol, never equal to a string);
* lists are tuples, compounds are CompoundValue; both immutable and hashable;
* `None` is golog++ `null`, distinct from every other value (also from `false`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Union

from gpp.model.types import Sym, same_value, show_value

Value = Union[None, bool, int, float, str, Sym, tuple["Value", ...], "CompoundValue"]


@dataclass(frozen=True, slots=True)
class CompoundValue:
    type_name: str
    # (field name, value) in the compound's declaration order.
    fields: tuple[tuple[str, Value], ...]

    def get(self, name: str) -> Value:
        for n, v in self.fields:
            if n == name:
                return v
        raise KeyError(name)

    def replace(self, name: str, value: Value) -> CompoundValue:
        return CompoundValue(self.type_name, tuple((n, value if n == name else v) for n, v in self.fields))


def to_string(v: Value) -> str:
    """`to_string(v)` (SEMANTICS §3): a string unchanged, anything else as `show` writes it."""
    return v if isinstance(v, str) else show(v)


def show(v: Value) -> str:
    """A value as golog++ source would write it (traces, messages): strings quoted, symbols
    bare, lists and compounds in literal form without the type prefix."""
    if isinstance(v, tuple):
        return "[" + ",".join(show(x) for x in v) + "]"
    if isinstance(v, CompoundValue):
        return v.type_name + "{" + ",".join(f"{n}={show(x)}" for n, x in v.fields) + "}"
    return show_value(v)


def to_json(v: Value) -> object:
    """A value for the JSON trace: symbols and compounds become tagged objects."""
    if v is None or isinstance(v, bool | int | float | str):
        return v
    if isinstance(v, Sym):
        return {"symbol": v.name}
    if isinstance(v, tuple):
        return [to_json(x) for x in v]
    return {"compound": v.type_name, "fields": {n: to_json(x) for n, x in v.fields}}


def from_json(obj: object) -> Value:
    """The value `to_json` wrote; ValueError for anything it cannot have written."""
    if obj is None or isinstance(obj, bool | int | float | str):
        return obj
    if isinstance(obj, list):
        return tuple(from_json(x) for x in obj)
    if isinstance(obj, dict):
        if set(obj) == {"symbol"} and isinstance(obj["symbol"], str):
            return Sym(obj["symbol"])
        fields = obj.get("fields")
        if set(obj) == {"compound", "fields"} and isinstance(obj["compound"], str) and isinstance(fields, dict):
            return CompoundValue(obj["compound"], tuple((str(n), from_json(x)) for n, x in fields.items()))
    raise ValueError(f"not a value of the trace: {obj!r}")


def show_json(obj: object) -> str:
    """A value of the trace (`to_json`'s form) as golog++ writes it (`show`); something that is
    not such a value, from a damaged or foreign trace, as JSON text."""
    try:
        return show(from_json(obj))
    except (ValueError, TypeError):
        import json

        return json.dumps(obj, ensure_ascii=False, default=str)


# golog++ `==` on runtime values: gpp.model.types.same_value itself (evaluation calls it a lot).
same: Callable[[Value, Value], bool] = same_value
