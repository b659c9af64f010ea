"""The nesting limit: a declaration whose syntax tree nests deeper than MAX_NESTING is rejected.

Parsing is iterative and takes any depth, but the phases after it (resolution, type checking,
lints, the printer, the interpreter and the planner) follow the tree by recursion. Checking
the depth once here, where the tree is built, lets every later phase rely on it: a program
either nests at most MAX_NESTING levels or gets one located error (E0014) per declaration that
nests deeper, and that declaration is left out of the program.
"""

from __future__ import annotations

from bisect import bisect_left
from collections.abc import Sequence

from gpp.base import diagnostics as diag
from gpp.base.source import Span
from gpp.codes import E0014
from gpp.syntax import ast
from gpp.syntax.lexer import Token
from gpp.syntax.walk import children

# How many levels deep a declaration's syntax tree may nest. Each statement inside another,
# each operand of an operator chain (`a + b + c` is `(a + b) + c`), each call, field access,
# index, `!`, `-`, quantifier and domain operator adds a level. Far beyond what anyone
# writes, and far within what the recursive phases can follow on Python's stack (with the
# recursion limit `gpp` sets for them).
MAX_NESTING = 2_000
# How many constructs may be open at once while parsing (the parser's stack). An open
# statement or operator takes at most a few entries (`pick (T x)` takes five), so no
# declaration within MAX_NESTING comes near; deeper ones stop here, before their tree is built,
# and so do parentheses around parentheses (which add no level to the tree).
MAX_OPEN = 10 * MAX_NESTING


_NOTES = [
    "each statement inside another, each operand of an operator chain such as `a + b + c`, "
    "and each call, field access, index, `!`, `-` or quantifier adds a level"
]
_HELP = "move the inner part into a function or procedure of its own, or split the chain"


def limit_nesting(program: ast.Program, tokens: Sequence[Token]) -> tuple[ast.Program, list[diag.Diagnostic]]:
    """`program` without the declarations that nest deeper than MAX_NESTING, and an error for
    each of them."""
    found: list[diag.Diagnostic] = []
    kept: list[ast.Decl] = []
    starts = [t.start for t in tokens]
    for decl in program.declarations:
        # A node with children owns at least one token of its own (an operator, a bracket, a
        # keyword), so a tree cannot be much deeper than its tokens are many: only a
        # declaration with about MAX_NESTING tokens or more needs a look.
        first = bisect_left(starts, decl.span.start)
        count = bisect_left(starts, decl.span.end, lo=first) - first
        deep = _too_deep(decl) if 2 * count + 8 > MAX_NESTING else None
        if deep is None:
            kept.append(decl)
        else:
            found.append(nesting_error(deep))
    if not found:
        return program, found
    return ast.Program(span=program.span, declarations=tuple(kept)), found


def _too_deep(root: ast.Node) -> ast.Node | None:
    """Where `root` nests more than MAX_NESTING levels deep: the innermost expression,
    statement (or domain expression, type, formula) around the first node (leftmost, in
    source order) at level MAX_NESTING + 1, or None."""
    stack: list[tuple[ast.Node, int]] = [(root, 0)]
    path: list[ast.Node] = []  # the nodes from `root` down to the current one
    while stack:
        node, depth = stack.pop()
        del path[depth:]
        path.append(node)
        if depth > MAX_NESTING:
            return next((n for n in reversed(path) if _what(n)), node)
        below = [(child, depth + 1) for child in children(node)]
        below.reverse()
        stack.extend(below)
    return None


def nesting_error(node: ast.Node) -> diag.Diagnostic:
    """E0014 at `node` (shown up to the end of its first line: the node of a long chain spans
    most of the chain)."""
    span = node.span
    text = span.source.text
    line_end = text.find("\n", span.start, span.end)
    at = Span(span.source, span.start, span.end if line_end < 0 else line_end)
    return diag.error(
        E0014.too_deep(_what(node) or "declaration", MAX_NESTING),
        at,
        f"more than {MAX_NESTING} levels deep",
        notes=_NOTES,
        help=_HELP,
    )


def too_deep_error(at: Span) -> diag.Diagnostic:
    """E0014 where the parser found more than MAX_OPEN constructs open."""
    return diag.error(
        E0014.too_deep("declaration", MAX_NESTING),
        at,
        f"more than {MAX_OPEN} brackets, operators and statements open here",
        notes=_NOTES,
        help=_HELP,
    )


def _what(node: ast.Node) -> str:
    """What `node` is, in words, if it is a part that nests."""
    if isinstance(node, ast.Expr):
        return "expression"
    if isinstance(node, ast.Statement):
        return "statement"
    if isinstance(node, ast.DomainExpr):
        return "domain expression"
    if isinstance(node, ast.ListType):
        return "type"
    if isinstance(node, ast.ClockFormula):
        return "clock formula"
    if isinstance(node, ast.Spec):
        return "constraint"
    return ""
