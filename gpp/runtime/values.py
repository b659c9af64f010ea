"""Runtime values (SEMANTICS §3).

* bool, int, float (numbers keep int/float), str, Sym (a symbol, never equal to a string);
* lists are tuples, compounds are CompoundValue; both immutable and hashable;
* `None` is golog++ `null`, distinct from every other value (also from `false`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Union

from gpp.model.types import Sym

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


def format_number(v: int | float) -> str:
    """Numbers as `to_string` writes them: `1`, `2.0`, `0.3`, `1e+20`."""
    if isinstance(v, bool):
        raise TypeError("a bool is not a number")
    if isinstance(v, int):
        return str(v)
    text = f"{v:.15g}"
    if "." not in text and "e" not in text and "n" not in text:
        text += ".0"
    return text


def to_string(v: Value) -> str:
    """`to_string(v)` (SEMANTICS §3): a string unchanged, anything else as `show` writes it."""
    return v if isinstance(v, str) else show(v)


def show(v: Value) -> str:
    """A value as golog++ source would write it (traces, messages): strings quoted, symbols
    bare, lists and compounds in literal form without the type prefix."""
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int | float):
        return format_number(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, Sym):
        return v.name
    if isinstance(v, tuple):
        return "[" + ",".join(show(x) for x in v) + "]"
    return v.type_name + "{" + ",".join(f"{n}={show(x)}" for n, x in v.fields) + "}"


def to_json(v: Value) -> object:
    """A value for the JSON trace: symbols and compounds become tagged objects."""
    if v is None or isinstance(v, bool | int | float | str):
        return v
    if isinstance(v, Sym):
        return {"symbol": v.name}
    if isinstance(v, tuple):
        return [to_json(x) for x in v]
    return {"compound": v.type_name, "fields": {n: to_json(x) for n, x in v.fields}}


def same(a: Value, b: Value) -> bool:
    """golog++ `==`: numbers by value (2 == 2.0), everything else by type and value."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if isinstance(a, int | float) and isinstance(b, int | float):
        return a == b
    return type(a) is type(b) and a == b
