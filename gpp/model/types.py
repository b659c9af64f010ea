"""Semantic types of golog++ and the rules that relate them (LANGUAGE.md §3.5 as amended by
SEMANTICS.md §2.4)."""

from __future__ import annotations

from dataclasses import dataclass, field


class Type:
    """Base of all types. `str(t)` is the name users write."""

    def __str__(self) -> str:
        raise NotImplementedError


@dataclass(frozen=True, slots=True)
class BuiltinType(Type):
    name: str

    def __str__(self) -> str:
        return self.name


BOOL = BuiltinType("bool")
NUMBER = BuiltinType("number")
STRING = BuiltinType("string")
SYMBOL = BuiltinType("symbol")
VOID = BuiltinType("void")
BUILTIN_TYPES = {t.name: t for t in (BOOL, NUMBER, STRING, SYMBOL, VOID)}


@dataclass(frozen=True, slots=True, eq=False)
class Sym:
    """A symbol value (an element of a symbol domain). Never equal to a string."""

    name: str
    # hash((name,)), as the dataclass would compute it, computed once: symbols are hashed and
    # compared very often while planning (dict keys, states).
    _hash: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_hash", hash((self.name,)))

    def __str__(self) -> str:
        return self.name

    def __eq__(self, other: object) -> bool:
        if other.__class__ is Sym:
            return self.name == other.name
        return NotImplemented

    def __hash__(self) -> int:
        return self._hash

    def __reduce__(self) -> tuple[type[Sym], tuple[str]]:
        return (Sym, (self.name,))  # the hash of a string differs between processes


DomainValue = int | float | str | bool | Sym


@dataclass(eq=False, slots=True)
class DomainType(Type):
    """A named finite set of values of one element type; also usable as a type."""

    name: str
    element: BuiltinType
    # Members in declaration order, filled when the domain's definition is evaluated.
    values: tuple[DomainValue, ...] = ()
    defined: bool = False
    # The element type is known once a declaration of the domain has been resolved; a domain
    # whose declarations are in error is `broken` (its values are not evaluated).
    element_known: bool = False
    broken: bool = False
    # `values` as a set of `value_key`s, for `contains`; built on first use, for those values.
    _keys: tuple[tuple[DomainValue, ...], frozenset[object]] | None = field(default=None, repr=False)

    def __str__(self) -> str:
        return self.name

    def contains(self, value: DomainValue) -> bool:
        return value_key(value) in self._member_keys()

    def contains_symbol(self, name: str) -> bool:
        """`contains(Sym(name))`, without making the value."""
        return (Sym, name) in self._member_keys()  # value_key(Sym(name))

    def _member_keys(self) -> frozenset[object]:
        keys = self._keys
        if keys is None or keys[0] is not self.values:
            keys = self._keys = (self.values, frozenset(value_key(v) for v in self.values))
        return keys[1]


def same_value(a: object, b: object) -> bool:
    """golog++ `==` on values: numbers by value (2 == 2.0), everything else by type and value
    (a symbol is never a string, `true` never 1). Used for domain members and at run time."""
    ta = type(a)
    if ta is type(b):  # the common case, first: same type, compared by value
        if ta is Sym:
            return a.name == b.name  # type: ignore[attr-defined, no-any-return]  # Sym.__eq__, inline
        return a == b
    # Of two different types only an int and a float can be equal (bool is neither here).
    return (ta is int or ta is float) and (type(b) is int or type(b) is float) and a == b


def value_key(v: DomainValue) -> object:
    """A key that is equal for two values exactly when `same_value` holds, to put values in
    sets and dicts (Python compares ints and floats exactly, and hashes equal numbers alike).
    A symbol is keyed by its name: two symbols are the same value exactly when their names
    are, and a string hashes in C (a `Sym` through its Python `__hash__`)."""
    cls = v.__class__
    if cls is Sym:
        return (Sym, v.name)  # type: ignore[union-attr]
    if cls is bool:
        return (bool, v)
    if cls is int or cls is float or isinstance(v, int | float):
        return (float, v)
    return (cls, v)


def number_to_string(v: int | float) -> str:
    """Numbers as `to_string` writes them: `1`, `2.0`, `0.3`, `1e+20`."""
    if isinstance(v, bool):
        raise TypeError("a bool is not a number")
    if isinstance(v, int):
        return str(v)
    text = f"{v:.15g}"
    if "." not in text and "e" not in text and "n" not in text:
        text += ".0"
    return text


def show_value(v: DomainValue | None) -> str:
    """A scalar value as golog++ source writes it: strings quoted (and escaped), symbols bare."""
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int | float):
        return number_to_string(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return v.name


@dataclass(eq=False, slots=True)
class CompoundType(Type):
    """A nominal record type."""

    name: str
    # Field name -> type, in declaration order; filled when the declaration is resolved.
    fields: dict[str, Type] = field(default_factory=dict)

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True, slots=True)
class ListType(Type):
    element: Type

    def __str__(self) -> str:
        return f"list[{self.element}]"


@dataclass(frozen=True, slots=True)
class _SpecialType(Type):
    name: str

    def __str__(self) -> str:
        return self.name


# The type of `null`: fits every slot.
NULL = _SpecialType("null")
# The type of an expression that already has an error: fits everything, so one mistake is
# reported once and not again by every expression around it.
ERROR = _SpecialType("{error}")


def base(t: Type) -> Type:
    """A domain's element type; any other type itself."""
    return t.element if isinstance(t, DomainType) else t


_SCALARS = (BOOL, NUMBER, STRING, SYMBOL)
_SCALAR_IDS = frozenset(id(t) for t in _SCALARS)


def is_error(t: Type) -> bool:
    return t is ERROR


def assignable(target: Type, source: Type) -> bool:
    """Does a slot of type `target` accept a value of type `source`?

    Domain membership of computed values is checked at run time (SEMANTICS §2.4), so a domain
    accepts any value of its element type here; literals are checked by the caller.
    """
    if source is NULL or source is ERROR or target is ERROR or target is source:
        return True
    if target.__class__ is source.__class__ and target == source:  # same_type(target, source)
        return True
    if isinstance(target, BuiltinType):
        return isinstance(source, DomainType) and same_type(source.element, target)
    if isinstance(target, DomainType):
        b = source.element if isinstance(source, DomainType) else source  # base(source)
        return b is target.element or same_type(b, target.element)
    if isinstance(target, ListType) and isinstance(source, ListType):
        return assignable(target.element, source.element)
    return False


def same_type(a: Type, b: Type) -> bool:
    """`a == b`, asking a type's `__eq__` (a dataclass's, in Python) only when it can say yes:
    types of two classes are never equal, and an object is equal to itself."""
    return a is b or (a.__class__ is b.__class__ and a == b)


def equatable(a: Type, b: Type) -> bool:
    """May `a == b` compare values of these types?"""
    if a is NULL or b is NULL or a is ERROR or b is ERROR:
        return True
    # base(a), base(b), inline:
    ba = a.element if isinstance(a, DomainType) else a
    bb = b.element if isinstance(b, DomainType) else b
    # (`is` first: a dataclass's `==` is a call into Python even for the same object.)
    return (ba is bb or same_type(ba, bb)) and (id(ba) in _SCALAR_IDS or ba in _SCALARS)


def ordered(t: Type) -> bool:
    """May values of this type be compared with `<`?"""
    b = base(t)
    return t is ERROR or b is NUMBER or b is STRING or b is SYMBOL or b in (NUMBER, STRING, SYMBOL)


def is_finite(t: Type) -> bool:
    """Can a quantifier or `pick` enumerate this type? `symbol` ranges over the symbols the
    program declares (Model.declared_symbols)."""
    return t is ERROR or t is BOOL or t is SYMBOL or isinstance(t, DomainType)


def common_type(a: Type, b: Type) -> Type | None:
    """The type of `if (c) a else b`, or None when the branches do not fit together."""
    if a is ERROR or b is ERROR:
        return ERROR
    if a is NULL:
        return b
    if b is NULL or same_type(a, b):
        return a
    if assignable(a, b) and not isinstance(a, DomainType):
        return a
    if assignable(b, a) and not isinstance(b, DomainType):
        return b
    if same_type(base(a), base(b)):
        return base(a)
    return None
