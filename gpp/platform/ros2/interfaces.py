"""ROS 2 interface types as the ros2 platform sees them: loading a type by name, its fields,
checking golog++ types against field types, filling messages from golog++ values (with our
own type and range checks: the generated classes do not check), and turning messages back
into plain Python data.

Only rosidl_parser (which comes with rclpy) is needed here; the message classes themselves
are imported by name when a mapping names them.

A field path names a field inside nested messages: `pose__position__x` (the form a mapping
key can take, since mapping keys are identifiers) or `pose.position.x` (also accepted in the
binding file). ROS field names never contain `__`, so the split is unambiguous.
"""

from __future__ import annotations

import importlib
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from rosidl_parser import definition as d

from gpp.base.suggest import did_you_mean
from gpp.model.types import BOOL, NUMBER, STRING, SYMBOL, CompoundType, DomainType, ListType, Sym, Type
from gpp.runtime.values import CompoundValue, Value, show

KINDS = ("action", "srv", "msg")

_INT_RANGES: dict[str, tuple[int, int]] = {
    "int8": (-(2**7), 2**7 - 1),
    "uint8": (0, 2**8 - 1),
    "char": (0, 2**8 - 1),
    "octet": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}
_FLOATS = {"float", "double", "long double"}
_FLOAT32_MAX = 3.4028234663852886e38


class InterfaceError(Exception):
    """A type name that does not name an importable ROS 2 interface."""


class FieldError(Exception):
    """A field path or a value that does not fit a message; `hint` is a did-you-mean."""

    def __init__(self, message: str, hint: str | None = None) -> None:
        super().__init__(message)
        self.hint = hint


@dataclass(frozen=True)
class Interface:
    """A loaded interface: `kind` is action, srv or msg; `cls` the generated class."""

    name: str  # pkg/kind/Name
    kind: str
    cls: Any

    @property
    def request(self) -> Any:
        """The message class the mapping fills: the goal, the request, or the message."""
        if self.kind == "action":
            return self.cls.Goal
        if self.kind == "srv":
            return self.cls.Request
        return self.cls

    @property
    def response(self) -> Any | None:
        """The message class that comes back: the result, the response, or None."""
        if self.kind == "action":
            return self.cls.Result
        if self.kind == "srv":
            return self.cls.Response
        return None


_TYPE_NAME = re.compile(r"^([A-Za-z][A-Za-z0-9_]*)/(?:(action|srv|msg)/)?([A-Z][A-Za-z0-9]*)$")


def split_type_name(name: str) -> tuple[str, str | None, str]:
    """(package, kind or None, type) of `pkg/kind/Type` or `pkg/Type`; InterfaceError otherwise."""
    m = _TYPE_NAME.match(name.strip())
    if m is None:
        raise InterfaceError(
            f"`{name}` is not a ROS 2 interface type name (write `package/action/Type`, `package/srv/Type` "
            "or `package/msg/Type`)"
        )
    return m.group(1), m.group(2), m.group(3)


def load_interface(name: str) -> Interface:
    """The interface named `pkg/kind/Type` (or `pkg/Type`: action, srv and msg are tried)."""
    package, kind, type_name = split_type_name(name)
    kinds = (kind,) if kind is not None else KINDS
    missing_package = True
    for k in kinds:
        try:
            module = importlib.import_module(f"{package}.{k}")
        except ImportError:
            continue
        missing_package = False
        cls = getattr(module, type_name, None)
        if cls is not None:
            return Interface(f"{package}/{k}/{type_name}", k, cls)
    if missing_package:
        raise InterfaceError(
            f"cannot import `{name}`: no interface package `{package}` here "
            "(install it, or source the workspace that builds it)"
        )
    known: list[str] = []
    for k in kinds:
        try:
            module = importlib.import_module(f"{package}.{k}")
        except ImportError:
            continue
        known.extend(n for n in dir(module) if n[:1].isupper())
    hint = did_you_mean(type_name, known)
    raise InterfaceError(
        f"cannot import `{name}`: package `{package}` has no such type" + (f"; {hint}" if hint else "")
    )


def message_class(t: d.NamespacedType) -> Any:
    module = importlib.import_module(".".join(t.namespaces))
    return getattr(module, t.name)


def fields(cls: Any) -> dict[str, Any]:
    """Field name -> rosidl type of a message class, in order."""
    names = list(cls.get_fields_and_field_types())
    return dict(zip(names, cls.SLOT_TYPES, strict=True))


def split_path(path: str) -> list[str]:
    """`a__b__c` or `a.b.c` as its parts."""
    return [p for p in re.split(r"__|\.", path)]


def describe(t: Any) -> str:
    """A rosidl type as the message definition writes it."""
    if isinstance(t, d.BasicType):
        return "bool" if t.typename == "boolean" else "byte" if t.typename == "octet" else str(t.typename)
    if isinstance(t, d.BoundedString | d.BoundedWString):
        return f"string<={t.maximum_size}"
    if isinstance(t, d.AbstractString | d.AbstractWString):
        return "string"
    if isinstance(t, d.NamespacedType):
        return f"{next(iter(t.namespaces))}/{t.name}"
    if isinstance(t, d.Array):
        return f"{describe(t.value_type)}[{t.size}]"
    if isinstance(t, d.BoundedSequence):
        return f"{describe(t.value_type)}[<={t.maximum_size}]"
    if isinstance(t, d.UnboundedSequence):
        return f"{describe(t.value_type)}[]"
    return str(t)


def field_at(cls: Any, path: str) -> Any:
    """The rosidl type of the field at `path` in message class `cls`; FieldError (with a
    did-you-mean and the fields there) when there is none."""
    parts = split_path(path)
    current = cls
    t: Any = None
    for i, part in enumerate(parts):
        if current is None:
            inside = "__".join(parts[:i])
            raise FieldError(f"`{inside}` is a {describe(t)}, not a message: it has no field `{part}`")
        known = fields(current)
        if part not in known:
            where = "__".join(parts[:i])
            listing = ", ".join(known) if known else "none"
            raise FieldError(
                f"{_type_label(current)}{' field `' + where + '`' if where else ''} has no field `{part}` "
                f"(its fields: {listing})",
                did_you_mean(part, known),
            )
        t = known[part]
        current = message_class(t) if isinstance(t, d.NamespacedType) else None
    return t


def _type_label(cls: Any) -> str:
    module = str(getattr(cls, "__module__", ""))
    package = module.split(".")[0]
    return f"`{package}/{cls.__name__}`" if package else f"`{cls.__name__}`"


# ---------------------------------------------------------------- golog++ types against field types


def type_problem(t: Any, g: Type) -> str | None:
    """Why a golog++ value of type `g` cannot fill a field of rosidl type `t` (None: it can)."""
    element = g.element if isinstance(g, DomainType) else g
    if not isinstance(element, CompoundType | ListType) and element not in (BOOL, NUMBER, STRING, SYMBOL):
        return None  # null, or a type the checker could not settle: checked when sent
    if isinstance(t, d.BasicType):
        if t.typename == "boolean":
            return None if element is BOOL else f"a {describe(t)} field needs a bool, not {g}"
        return None if element is NUMBER else f"a {describe(t)} field needs a number, not {g}"
    if isinstance(t, d.AbstractString | d.AbstractWString):
        return None if element in (STRING, SYMBOL) else f"a string field needs a string or a symbol, not {g}"
    if isinstance(t, d.AbstractNestedType):
        if not isinstance(element, ListType):
            return f"a {describe(t)} field needs a list, not {g}"
        inner = type_problem(t.value_type, element.element)
        return f"an element of {describe(t)}: {inner}" if inner else None
    if isinstance(t, d.NamespacedType):
        if _is_time(t) and element is NUMBER:
            return None  # seconds
        return message_problem(message_class(t), g)
    return None


def message_problem(cls: Any, g: Type) -> str | None:
    """Why a golog++ value of type `g` cannot stand for a message of class `cls` (None: it
    can): it must be a compound type whose fields are fields of the message, of fitting types."""
    element = g.element if isinstance(g, DomainType) else g
    if not isinstance(element, CompoundType):
        return f"a {_type_label(cls)} needs a compound value with its field names, not {g}"
    known = fields(cls)
    for name, ft in element.fields.items():
        if name not in known:
            hint = did_you_mean(name, known)
            return (
                f"compound type `{element.name}` has field `{name}`, which {_type_label(cls)} lacks "
                f"(its fields: {', '.join(known)})" + (f"; {hint}" if hint else "")
            )
        inner = type_problem(known[name], ft)
        if inner:
            return f"field `{name}`: {inner}"
    return None


def _is_time(t: d.NamespacedType) -> bool:
    return next(iter(t.namespaces)) == "builtin_interfaces" and t.name in ("Time", "Duration")


# ---------------------------------------------------------------- golog++ values into messages


def convert(t: Any, v: Value | Any, where: str) -> Any:
    """The Python value for a field of rosidl type `t` from a golog++ value (or from plain
    data: bool, int, float, str, list, dict, as the binding file gives); FieldError when it
    does not fit. Numbers must be integral for integer fields and within their range."""
    if isinstance(t, d.BasicType):
        name = t.typename
        if name == "boolean":
            if not isinstance(v, bool):
                raise FieldError(f"{where}: expected a bool, got {_show(v)}")
            return v
        if isinstance(v, bool) or not isinstance(v, int | float):
            raise FieldError(f"{where}: expected a number ({describe(t)}), got {_show(v)}")
        if name in _FLOATS:
            x = float(v)
            if name == "float" and math.isfinite(x) and abs(x) > _FLOAT32_MAX:
                raise FieldError(f"{where}: {_show(v)} is out of range for float32")
            return x
        if isinstance(v, float):
            if not v.is_integer():
                raise FieldError(f"{where}: expected a whole number ({describe(t)}), got {_show(v)}")
            v = int(v)
        low, high = _INT_RANGES.get(name, (-(2**63), 2**64 - 1))
        if not low <= v <= high:
            raise FieldError(f"{where}: {v} is out of range for {describe(t)} ({low}..{high})")
        return bytes([v]) if name == "octet" else v
    if isinstance(t, d.AbstractString | d.AbstractWString):
        if isinstance(v, Sym):
            v = v.name
        if not isinstance(v, str):
            raise FieldError(f"{where}: expected a string or a symbol, got {_show(v)}")
        if isinstance(t, d.BoundedString | d.BoundedWString) and len(v) > int(t.maximum_size):
            raise FieldError(f"{where}: the string is {len(v)} characters long, more than {describe(t)} allows")
        return v
    if isinstance(t, d.AbstractNestedType):
        if not isinstance(v, tuple | list):
            raise FieldError(f"{where}: expected a list ({describe(t)}), got {_show(v)}")
        if isinstance(t, d.Array) and len(v) != t.size:
            raise FieldError(f"{where}: expected a list of exactly {t.size} elements, got {len(v)}")
        if isinstance(t, d.BoundedSequence) and len(v) > int(t.maximum_size):
            raise FieldError(f"{where}: expected at most {t.maximum_size} elements, got {len(v)}")
        return [convert(t.value_type, x, f"{where}[{i}]") for i, x in enumerate(v)]
    if isinstance(t, d.NamespacedType):
        cls = message_class(t)
        if _is_time(t) and isinstance(v, int | float) and not isinstance(v, bool):
            sec = math.floor(v)
            return cls(sec=int(sec), nanosec=round((v - sec) * 1e9) % 1_000_000_000)
        if isinstance(v, CompoundValue):
            items: Mapping[str, Any] = {n: x for n, x in v.fields if x is not None}
        elif isinstance(v, Mapping):
            items = v
        else:
            raise FieldError(f"{where}: expected a compound value ({describe(t)}), got {_show(v)}")
        msg = cls()
        fill_fields(msg, [(name, x) for name, x in items.items()], where)
        return msg
    raise FieldError(f"{where}: fields of type {describe(t)} are not supported")


def fill_fields(msg: Any, entries: Sequence[tuple[str, Any]], where: str = "") -> None:
    """Set the fields at the given paths of `msg` (nested messages are reached through their
    paths and filled in place); FieldError names the first entry that does not fit."""
    for path, value in entries:
        parts = split_path(path)
        target = msg
        for part in parts[:-1]:
            known = fields(type(target))
            if part not in known or not isinstance(known[part], d.NamespacedType):
                field_at(type(msg), path)  # raises with the precise reason
                raise FieldError(f"{where}{path}: not a nested message")
            target = getattr(target, part)
        known = fields(type(target))
        last = parts[-1]
        if last not in known:
            field_at(type(msg), path)
            raise FieldError(f"{where}{path}: no such field")
        setattr(target, last, convert(known[last], value, f"{where}{path}"))


def make_message(cls: Any, entries: Sequence[tuple[str, Any]]) -> Any:
    msg = cls()
    fill_fields(msg, entries)
    return msg


# ---------------------------------------------------------------- messages back into plain data


def to_plain(v: Any) -> Any:
    """A message (or field value) as plain Python data: dicts, lists, bool, int, float, str."""
    if hasattr(v, "get_fields_and_field_types"):
        return {name: to_plain(getattr(v, name)) for name in v.get_fields_and_field_types()}
    if isinstance(v, bytes):
        return v[0] if len(v) == 1 else list(v)
    if isinstance(v, str | bool | int | float):
        return v
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        return to_plain(v.tolist())
    if isinstance(v, list | tuple) or hasattr(v, "__iter__"):
        return [to_plain(x) for x in v]
    return v


def pick(plain: Any, path: str) -> Any:
    """The value at a field path of plain message data; KeyError when there is none."""
    for part in split_path(path):
        if not isinstance(plain, dict) or part not in plain:
            raise KeyError(part)
        plain = plain[part]
    return plain


def _show(v: Any) -> str:
    if isinstance(v, bool | int | float | str | Sym | tuple | CompoundValue) or v is None:
        return show(v)
    return repr(v)
