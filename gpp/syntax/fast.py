"""The syntax side's speed tricks, in one place. Each makes exactly what a plain version makes,
faster, and a test holds the two equal:

* twin classes and fast constructors (`twin`, `make_span`, `fast_constructor`, `node_lines`,
  `span_lines`): a span or a node is made as an instance of the twin of its class (same base,
  same slots, so the same layout), its slots set by plain assignment, then given its real
  class by setting `__class__`. Plain version: `Span(source, start, end)`, `cls(**fields)`.
  Held equal by tests/syntax/test_parse_fingerprints.py (the fingerprints of every parse, and
  test_a_fast_constructor_makes_the_node_the_dataclass_makes);
* generated walkers (`CHILDREN`, `PUSH_CHILDREN`, `LEAVES`): per node class, on first use, a
  function that lists its children, written from the field annotations as `dataclasses`
  writes methods, so that visiting a node costs one call. Plain version: testing the value of
  every dataclass field (`_nodes_in`, also the fallback for an annotation that mixes nodes
  with other values). Held equal by tests/syntax/test_walk.py
  (test_children_and_walk_agree_with_the_fields);
* relocators (`relocators`, `relocate`): per node class, generated code that copies a node
  with every span moved by a delta into another source, made of the statements of the fast
  constructors. Plain version: parsing the moved text again. Held equal by
  tests/syntax/test_incremental.py (test_relocate_*, which compare with that parse, and the
  re-parse tests).

gpp.syntax.build, gpp.syntax.walk and gpp.syntax.incremental use them; no other module of the
syntax package generates code.
"""

from __future__ import annotations

import dataclasses
import threading
import types
import typing
from collections.abc import Callable
from dataclasses import fields
from enum import Enum
from typing import Any, TypeVar

from gpp.base.source import Source, Span
from gpp.syntax import ast

N = TypeVar("N", bound=ast.Node)

# ---------------------------------------------------------------- twins and fast constructors

# A parse makes a Span for about every token, and a node for most. `Span(...)` runs the frozen
# dataclass's `__init__`, which sets each field through `object.__setattr__`; each field set
# through its slot's `__set__` (a call) costs about twice a plain assignment. So spans and nodes
# are made as an instance of the `twin` of their class (same base, same slots, so of the same
# layout: calling it costs less than `object.__new__(cls)`), their slots set by plain
# assignment, then turned into the real class by setting `__class__` (allowed between classes
# of the same layout): the same object with less than half of the work.
_TWINS: dict[type, type] = {}


def twin(cls: type) -> type:
    """The class of the same layout as the slotted (frozen) dataclass `cls` whose instances
    take plain assignments to the slots (neither frozen nor with the dataclass's `__init__`)."""
    made = _TWINS.get(cls)
    if made is None:
        namespace = {
            "__slots__": vars(cls)["__slots__"],
            # Both of the base's, or attribute assignment would not take the plain path.
            "__setattr__": object.__setattr__,
            "__delattr__": object.__delattr__,
            "__init__": object.__init__,
        }
        made = _TWINS.setdefault(cls, type(f"_{cls.__name__}Slots", cls.__bases__, namespace))
    return made


SpanTwin = twin(Span)


def make_span(source: Source, start: int, end: int) -> Span:
    """`Span(source, start, end)`, made faster."""
    span: Any = SpanTwin()
    span.source = source
    span.start = start
    span.end = end
    span.__class__ = Span
    made: Span = span
    return made


def span_lines(out: str, source: str, start: str, end: str, indent: str, names: dict[str, Any]) -> list[str]:
    """Python statements that set the variable `out` to `Span(source, start, end)` (each an
    expression), made as `make_span` makes it; `names` receives the globals they use."""
    names["_SpanTwin"] = SpanTwin
    names["_Span"] = Span
    return [
        f"{indent}{out} = _SpanTwin()",
        f"{indent}{out}.source = {source}",
        f"{indent}{out}.start = {start}",
        f"{indent}{out}.end = {end}",
        f"{indent}{out}.__class__ = _Span",
    ]


def node_lines(cls: type[ast.Node], values: dict[str, str], out: str, indent: str, names: dict[str, Any]) -> list[str]:
    """Python statements that set the variable `out` to a node of class `cls` whose fields are
    the expressions `values[field]`: an instance of its `twin`, each slot set by plain
    assignment, then its class set (the frozen dataclass's `__init__` calls
    `object.__setattr__` for each field, at several times the cost). `names` receives the
    globals they use. `fast_constructor` and the relocators of gpp.syntax.incremental are made
    of these statements."""
    assert not hasattr(cls, "__post_init__"), cls
    name = cls.__name__
    names[f"_T_{name}"] = twin(cls)
    names[f"_C_{name}"] = cls
    lines = [f"{indent}{out} = _T_{name}()"]
    lines += [f"{indent}{out}.{f.name} = {values[f.name]}" for f in dataclasses.fields(cls)]
    lines.append(f"{indent}{out}.__class__ = _C_{name}")
    return lines


def fast_constructor(cls: type[N]) -> Callable[..., N]:
    """A constructor of the node class `cls` that takes the keyword arguments `cls(...)` takes
    and makes an equal node, about twice as fast (`node_lines`). Generated from the class's
    fields, as dataclasses generates `__init__`."""
    namespace: dict[str, Any] = {}
    params: list[str] = []
    for f in dataclasses.fields(cls):
        assert f.init and f.default_factory is dataclasses.MISSING, (cls, f.name)
        if f.default is dataclasses.MISSING:
            params.append(f.name)
        else:
            params.append(f"{f.name}=_default_{f.name}")
            namespace[f"_default_{f.name}"] = f.default
    lines = node_lines(cls, {f.name: f.name for f in dataclasses.fields(cls)}, "node", "    ", namespace)
    code = f"def {cls.__name__}(*, {', '.join(params)}):\n" + "\n".join(lines) + "\n    return node\n"
    exec(code, namespace)
    made: Callable[..., N] = namespace[cls.__name__]
    return made


# ---------------------------------------------------------------- generated walkers

Children = Callable[[ast.Node], tuple[ast.Node, ...]]
PushChildren = Callable[[ast.Node, list[ast.Node]], None]
T = TypeVar("T")

# How a field holds nodes, by its annotation.
_ONE, _MANY, _UNKNOWN = "one", "many", "unknown"


def _options(hint: object) -> tuple[object, ...]:
    """The alternatives of a union annotation (`A | B`, `Optional[A]`), or the annotation itself."""
    if isinstance(hint, types.UnionType) or typing.get_origin(hint) is typing.Union:
        return typing.get_args(hint)
    return (hint,)


def _all_nodes(options: tuple[object, ...]) -> bool:
    return all(isinstance(o, type) and issubclass(o, ast.Node) for o in options)


def _holds(hint: object) -> tuple[str | None, bool]:
    """What a field with annotation `hint` holds (one node, a tuple of nodes, no node: None, or
    unknown) and whether it may be None."""
    options = _options(hint)
    values = tuple(o for o in options if o is not type(None))
    optional = len(values) < len(options)
    if _all_nodes(values):
        return _ONE, optional
    items = [a for o in values for a in typing.get_args(o) if a is not Ellipsis]
    if all(typing.get_origin(o) is tuple for o in values) and all(_all_nodes(_options(a)) for a in items):
        return _MANY, optional
    if all(_plain(o) for o in values):
        return None, optional
    return _UNKNOWN, optional


def _plain(option: object) -> bool:
    """Is `option` a class of values that are not nodes and hold none (str, bool, an enum, Span)?"""
    return isinstance(option, type) and not issubclass(option, ast.Node | tuple)


def _nodes_in(value: object) -> tuple[ast.Node, ...]:
    """The nodes in a field's value, found by testing it (for annotations `_holds` cannot read)."""
    if isinstance(value, ast.Node):
        return (value,)
    if isinstance(value, tuple):
        return tuple(item for item in value if isinstance(item, ast.Node))
    return ()


def _generate(cls: type[ast.Node]) -> None:
    """Write the functions of `cls` into the tables: its children as one tuple display over its
    node fields in field order, and the pushing of them onto a stack, last field first."""
    try:
        hints = typing.get_type_hints(cls)
    except (NameError, TypeError):  # an annotation that cannot be evaluated: test every value
        hints = {}
    parts: list[str] = []
    pushes: list[str] = []
    for f in fields(cls):
        holds, optional = _holds(hints[f.name]) if f.name in hints else (_UNKNOWN, True)
        value = f"n.{f.name}"
        if holds == _UNKNOWN:
            parts.append(f"*_nodes_in({value})")
            pushes.append(f"stack.extend(_nodes_in({value})[::-1])")
        elif holds == _MANY:
            parts.append(f"*({value} or ())" if optional else f"*{value}")
            pushes.append(f"stack.extend(({value} or ())[::-1])" if optional else f"stack.extend({value}[::-1])")
        elif holds == _ONE:
            parts.append(f"*(() if {value} is None else ({value},))" if optional else value)
            pushes.append(f"if {value} is not None: stack.append({value})" if optional else f"stack.append({value})")
    source = [
        "def children(n):",
        f"    return ({''.join(p + ', ' for p in parts)})",
        "def push(n, stack):",
        *(f"    {p}" for p in reversed(pushes)),
        "    pass",
    ]
    namespace: dict[str, object] = {"_nodes_in": _nodes_in}
    exec("\n".join(source), namespace)
    CHILDREN[cls] = typing.cast(Children, namespace["children"])
    PUSH_CHILDREN[cls] = typing.cast(PushChildren, namespace["push"])
    if not parts:
        LEAVES.add(cls)


class _Table(dict[type, T]):
    """A function of each node class, generated when a class is first seen."""

    def __missing__(self, cls: type) -> T:
        _generate(cls)
        return self[cls]


# The children of a node, in source order.
CHILDREN: dict[type, Children] = _Table()
# Push the children of a node onto a stack, so that popping gives them in source order.
PUSH_CHILDREN: dict[type, PushChildren] = _Table()
# The node classes seen so far that have no child fields: a walk need not ask for their children.
LEAVES: set[type] = set()


# ---------------------------------------------------------------- relocators

Relocator = Callable[[Any, Source, int], Any]
# Made on first use (generating each table takes about a tenth of a second, which a command
# that parses each file once need not pay), complete before any thread sees them: by whether
# they move the spans (those that do not, for the declarations before an edit, add nothing).
_RELOCATORS: dict[bool, dict[type, Relocator]] = {True: {}, False: {}}
_GENERATING = threading.Lock()


def relocators(moved: bool = True) -> dict[type, Relocator]:
    """The relocator of each syntax node class: (node, source, delta) -> a copy of the node with
    every span moved by `delta` into `source`; with `moved` false, for a delta of 0 only."""
    table = _RELOCATORS[moved]
    if not table:
        with _GENERATING:
            if not table:
                table.update(_generate_relocators(moved))
    return table


def relocate(node: ast.Node, source: Source, delta: int) -> Any:
    """A copy of `node` with every span moved by `delta` into `source`."""
    return relocators(delta != 0)[type(node)](node, source, delta)


def _node_classes() -> list[type[ast.Node]]:
    """The syntax node classes (those of gpp.syntax.ast; `__subclasses__` would also list the
    classes that `dataclass(slots=True)` replaced)."""
    return [c for c in vars(ast).values() if isinstance(c, type) and issubclass(c, ast.Node) and c is not ast.Node]


def _is_node(tp: Any) -> bool:
    return isinstance(tp, type) and issubclass(tp, ast.Node)


# The leaf classes (a span and plain values) that their parents' relocators copy themselves,
# tested in this order (the most frequent first); any other node is copied by the relocator of
# its class (a call and a look-up in the table less for about half of the nodes of a program).
_INLINED: tuple[type[ast.Node], ...] = (ast.Ident, ast.Name, ast.NumberLit, ast.NamedType, ast.StringLit)


# The node classes whose child (the field named) has the parent's span object itself, as the
# builder makes them (a main block and its body): the relocated child shares the relocated span.
_SHARED_SPAN: dict[type[ast.Node], str] = {ast.MainBlock: "body"}


class _Generator:
    """Writes the relocators: per class, statements made of `node_lines` and
    `span_lines` (as `fast_constructor` makes its nodes), the fields that hold spans
    relocated first, into local variables."""

    def __init__(self, moved: bool) -> None:
        self.moved = moved  # whether the spans are moved by `d` (else `d` is 0)
        self.table: dict[type, Relocator] = {}
        self.names: dict[str, Any] = {"R": self.table}
        self.hints: dict[type, dict[str, Any]] = {}
        self.count = 0

    def fields(self, cls: type) -> dict[str, Any]:
        if cls not in self.hints:
            self.hints[cls] = typing.get_type_hints(cls, vars(ast), {"Source": Source, "Span": Span})
        return self.hints[cls]

    def fresh(self) -> str:
        self.count += 1
        return f"v{self.count}"

    def holds_span(self, tp: Any) -> bool:
        """Does a value of type `tp` hold a span (it is copied as it is if not)?"""
        if tp is Span or _is_node(tp):
            return True
        origin = typing.get_origin(tp)
        if origin in (types.UnionType, typing.Union, tuple):
            return any(self.holds_span(a) for a in typing.get_args(tp) if a is not Ellipsis)
        if tp is type(None) or (isinstance(tp, type) and issubclass(tp, (str, int, float, Enum))):
            return False
        raise TypeError(f"cannot relocate a field of type {tp}")

    def node(self, cls: type[ast.Node], value: str, out: str, indent: str) -> list[str]:
        """Statements that set `out` to the relocated node `value` of class `cls`."""
        lines: list[str] = []
        values: dict[str, str] = {}
        shared = _SHARED_SPAN.get(cls)
        for name, tp in self.fields(cls).items():
            if self.holds_span(tp):
                part, moved = self.fresh(), self.fresh()
                lines.append(f"{indent}{part} = {value}.{name}")
                lines += self.value(tp, part, moved, indent)
                values[name] = moved
                if name == shared:
                    # The child, just made, takes the parent's new span if it had its span.
                    self.names[f"_set_{cls.__name__}_shared"] = getattr(ast.Node, "span").__set__  # noqa: B009
                    lines += [
                        f"{indent}if {part}.span is {value}.span:",
                        f"{indent}    _set_{cls.__name__}_shared({moved}, {values['span']})",
                    ]
            else:
                values[name] = f"{value}.{name}"
        return lines + node_lines(cls, values, out, indent, self.names)

    def value(self, tp: Any, value: str, out: str, indent: str) -> list[str]:
        """Statements that set `out` to the relocated `value` of type `tp` (a span, a node, a
        tuple of nodes, either or None)."""
        if tp is Span:
            plus = " + d" if self.moved else ""
            return span_lines(out, "src", f"{value}.start{plus}", f"{value}.end{plus}", indent, self.names)
        if _is_node(tp):
            return self.dispatch((tp,), value, out, indent)
        args = typing.get_args(tp)
        if typing.get_origin(tp) in (types.UnionType, typing.Union):
            present = tuple(a for a in args if a is not type(None))
            if all(_is_node(a) for a in present):
                lines = self.dispatch(present, value, out, indent + "    ")
            elif len(present) == 1:
                lines = self.value(present[0], value, out, indent + "    ")
            else:
                raise TypeError(f"cannot relocate a field of type {tp}")
            if len(present) == len(args):
                return [line[4:] for line in lines]
            return [f"{indent}if {value} is None:", f"{indent}    {out} = None", f"{indent}else:", *lines]
        if typing.get_origin(tp) is tuple and len(args) == 2 and args[1] is Ellipsis:
            items, item, moved = self.fresh(), self.fresh(), self.fresh()
            return [
                f"{indent}if {value}:",
                f"{indent}    {items} = []",
                f"{indent}    for {item} in {value}:",
                *self.value(args[0], item, moved, indent + "        "),
                f"{indent}        {items}.append({moved})",
                f"{indent}    {out} = tuple({items})",
                f"{indent}else:",
                f"{indent}    {out} = {value}",
            ]
        raise TypeError(f"cannot relocate a field of type {tp}")

    def dispatch(self, kinds: tuple[type, ...], value: str, out: str, indent: str) -> list[str]:
        """Statements that set `out` to the relocated node `value`, one of the classes `kinds`
        or their subclasses (the builder's children are untyped: the class is tested)."""
        lines: list[str] = []
        for cls in _INLINED:
            if issubclass(cls, kinds):
                lines.append(f"{indent}{'elif' if lines else 'if'} type({value}) is _C_{cls.__name__}:")
                lines += self.node(cls, value, out, indent + "    ")
        call = f"R[type({value})]({value}, src, d)"
        if not lines:
            return [f"{indent}{out} = {call}"]
        return [*lines, f"{indent}else:", f"{indent}    {out} = {call}"]

    def generate(self) -> dict[type, Relocator]:
        lines: list[str] = []
        for cls in _node_classes():
            name = cls.__name__
            lines += [f"def r_{name}(n, src, d):", *self.node(cls, "n", "o", "    "), "    return o"]
            lines.append(f"R[_C_{name}] = r_{name}")
        exec(compile("\n".join(lines), "<gpp.syntax.fast relocators>", "exec"), self.names)
        return self.table


def _generate_relocators(moved: bool) -> dict[type, Relocator]:
    """One function per syntax node class (`_Generator`)."""
    generator = _Generator(moved)
    for cls in _INLINED:  # leaves: a span and plain values
        assert not any(_is_node(tp) for tp in generator.fields(cls).values()), cls
    return generator.generate()
