"""Generic traversal of the syntax tree, through the functions per node class that
gpp.syntax.fast generates (`CHILDREN`, `PUSH_CHILDREN`)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import assert_never

from gpp.syntax import ast
from gpp.syntax.fast import CHILDREN, PUSH_CHILDREN


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
