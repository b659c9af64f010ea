"""Values from outside the program (scenario and world files, messages from a robot) as golog++
values of a declared type, shared by every platform.

Data arrives as plain Python values (what TOML, JSON or a message gives: bool, int, float, str,
lists, tables). `to_value` turns one into a golog++ value of the type the program declares:
strings become symbols where a symbol is expected, tables become compound values, lists become
list values, `{ null = true }` is null; domain membership is checked.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from gpp.base.numbers import RANGE_TEXT, describe, in_range
from gpp.model.types import BOOL, NUMBER, STRING, SYMBOL, CompoundType, DomainType, ListType, Sym, Type
from gpp.runtime.values import CompoundValue, Value, show


class ConversionError(ValueError):
    """A value that does not fit the declared type; the message says what was expected."""


def to_value(v: Any, t: Type | None) -> Value:
    """`v` as a golog++ value of type `t` (None: any plain value as it is)."""
    if isinstance(v, Mapping) and v.get("null") is True:
        return None
    element = t.element if isinstance(t, DomainType) else t
    if element is SYMBOL:
        if isinstance(v, Sym):
            value: Value = v
        elif isinstance(v, str):
            value = Sym(v)
        else:
            raise ConversionError(f"expected a symbol name, got {show_plain(v)}")
    elif element is NUMBER:
        if isinstance(v, bool) or not isinstance(v, int | float):
            raise ConversionError(f"expected a number, got {show_plain(v)}")
        value = _number(v)
    elif element is STRING:
        if not isinstance(v, str):
            raise ConversionError(f"expected a string, got {show_plain(v)}")
        value = v
    elif element is BOOL:
        if not isinstance(v, bool):
            raise ConversionError(f"expected true or false, got {show_plain(v)}")
        value = v
    elif isinstance(t, ListType):
        if not isinstance(v, list | tuple):
            raise ConversionError(f"expected a list, got {show_plain(v)}")
        value = tuple(to_value(x, t.element) for x in v)
    elif isinstance(t, CompoundType):
        if not isinstance(v, Mapping):
            raise ConversionError(f"expected a table for `{t.name}`, got {show_plain(v)}")
        value = CompoundValue(t.name, tuple((n, to_value(v.get(n, {"null": True}), ft)) for n, ft in t.fields.items()))
    elif isinstance(v, int | float) and not isinstance(v, bool):
        value = _number(v)
    else:
        value = v if isinstance(v, bool | str) else None
    if isinstance(t, DomainType) and value is not None and value not in t.values:
        raise ConversionError(f"{show(value)} is not in domain `{t.name}`")
    return value


def _number(v: int | float) -> int | float:
    """A number within the range of numbers (docs/semantics.md, "Numbers"): never NaN, an
    infinity or a whole number beyond ±1.8e308."""
    if isinstance(v, float) and math.isnan(v):
        raise ConversionError("expected a number, got NaN (not a number)")
    if not in_range(v):
        raise ConversionError(f"{describe(v)} is beyond the range of numbers ({RANGE_TEXT})")
    return v


def show_plain(v: Any) -> str:
    """`v` for a message, written as golog++ and TOML write values (`true`, `"text"`, `[1, 2]`,
    `{x = 1}`), never as Python does: short, and never failing on a whole number too long to
    write."""
    try:
        text = _plain(v)
    except ValueError:  # a whole number of thousands of digits inside
        return "a value with a huge whole number"
    return text if len(text) <= 80 else text[:77] + "..."


def _plain(v: Any) -> str:
    if v is None or isinstance(v, bool | int | float | str | Sym):
        return show(v)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_plain(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{" + ", ".join(f"{k} = {_plain(x)}" for k, x in v.items()) + "}"
    return repr(v)  # an object of a robot's message library: its own text
