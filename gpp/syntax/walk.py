"""Generic traversal of the syntax tree."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import fields
from typing import assert_never

from gpp.syntax import ast

_CHILD_FIELDS: dict[type, tuple[str, ...]] = {}


def _child_fields(cls: type[ast.Node]) -> tuple[str, ...]:
    names = _CHILD_FIELDS.get(cls)
    if names is None:
        names = tuple(f.name for f in fields(cls) if f.name not in ("span", "parenthesized", "keyword"))
        _CHILD_FIELDS[cls] = names
    return names


def children(node: ast.Node) -> Iterator[ast.Node]:
    """The direct child nodes of `node`, in source order."""
    for name in _child_fields(type(node)):
        value = getattr(node, name)
        if isinstance(value, ast.Node):
            yield value
        elif isinstance(value, tuple):
            for item in value:
                if isinstance(item, ast.Node):
                    yield item


def sub_statements(s: ast.Statement) -> tuple[ast.Statement, ...]:
    """The statements directly inside `s`, in source order (a `during`'s handlers after its
    body, `on_fail` first)."""
    match s:
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
        case ast.Test() | ast.HookStmt() | ast.Assign() | ast.ListStmt() | ast.CallStmt():
            return ()
        case _:
            assert_never(s)


def walk(node: ast.Node) -> Iterator[ast.Node]:
    """`node` and all nodes below it, parents before children (iterative: no recursion limit)."""
    stack = [node]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(reversed(list(children(n))))


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
