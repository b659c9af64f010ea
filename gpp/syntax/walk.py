"""Generic traversal of the syntax tree.

Every node class gets, on first use, a function listing its children. It is generated from the
class's field annotations (which fields hold a node, a tuple of nodes, possibly None, or no node
at all), like the methods `dataclasses` writes, so visiting a node costs one call: no `fields()`
and no isinstance test per field. A field whose annotation mixes nodes with other values is
read by testing its value, as a fallback.
"""

from __future__ import annotations

import types
import typing
from collections.abc import Callable, Iterator
from dataclasses import fields
from typing import TypeVar, assert_never

from gpp.syntax import ast

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


def children(node: ast.Node) -> tuple[ast.Node, ...]:
    """The direct child nodes of `node`, in source order."""
    return CHILDREN[type(node)](node)


def sub_statements(s: ast.Statement) -> tuple[ast.Statement, ...]:
    """The statements directly inside `s`, in source order (a `during`'s handlers after its
    body, `on_fail` first)."""
    match s:
        # The simple statements first: they are the most frequent.
        case ast.CallStmt() | ast.Assign() | ast.Test() | ast.HookStmt() | ast.ListStmt():
            return ()
        case ast.Block():
            return s.body
        case ast.Choose():
            return s.alternatives
        case ast.Concurrent():
            return s.branches
        case ast.If():
            return (s.then,) if s.otherwise is None else (s.then, s.otherwise)
        case ast.While() | ast.Pick() | ast.Solve() | ast.Search():
            return (s.body,)
        case ast.During():
            return (s.body, *(h for h in (s.on_fail, s.on_cancel) if h is not None))
        case _:
            assert_never(s)


def walk(node: ast.Node) -> Iterator[ast.Node]:
    """`node` and all nodes below it, parents before children (iterative: no recursion limit)."""
    push = PUSH_CHILDREN
    stack = [node]
    while stack:
        n = stack.pop()
        yield n
        push[type(n)](n, stack)


def path_to(node: ast.Node, offset: int) -> list[ast.Node]:
    """The chain of nodes from `node` down to the innermost one whose span contains `offset`."""
    chain = [node]
    current = node
    while True:
        for child in children(current):
            if child.span.start <= offset <= child.span.end and child.span.source is node.span.source:
                chain.append(child)
                current = child
                break
        else:
            return chain
