"""Precedence regrouping, part of the type-checking phase: boolean `==`/`!=` (iff/xor) get
their golog++ precedence, the loosest beside `->`.

The grammar parses every `==` as a comparison, tighter than `&`. Only once the operand types
are known can a chain that mixes a boolean `==` with `&`, `|`, `->` or `!` be rebuilt; the
type checker asks `reassociate` for each unvisited `!` and binary operator, and types the
rebuilt tree instead.

Reads the operand types through the type checker (silently, `state.silent`): the type
checker is a `Regrouper`, and its `expr` is the `type_of` here. Writes
`state.reassociated` (the chains already looked at, which are not looked at again) and the
types of the parsed chain's own nodes in `model.expr_types`. The type checker records the
rebuilt expression in `model.rewritten`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from gpp.base.source import Span
from gpp.model.builder_state import BuilderState, Phase
from gpp.model.types import BOOL, DomainType, Type
from gpp.syntax import ast

Op = ast.BinaryOp

# Enum members read on every node, bound once: Python 3.11's enum class has a `__getattr__`,
# which makes reading any attribute of the class (`Op.EQ`) several times slower than reading
# a global.
_EQ, _NE, _AND, _OR, _IMPLIES = Op.EQ, Op.NE, Op.AND, Op.OR, Op.IMPLIES
_NOT = ast.UnaryOp.NOT

# Sets of operators, as tuples: an enum member's hash is computed in Python, comparing
# identities is not.
BOOL_CHAIN = (_AND, _OR, _IMPLIES)
EQUALITY = (_EQ, _NE)
# The operators of a chain.
CHAIN_OPS = BOOL_CHAIN + EQUALITY


class Regrouper(Phase):
    """The regrouping part of the type checker (gpp.model.typecheck.TypeChecker derives from
    it; a separate object holding the checker's bound `expr` would make the two a reference
    cycle)."""

    def __init__(self, state: BuilderState) -> None:
        super().__init__(state)
        self.reassociated = state.reassociated

    def type_of(self, e: ast.Expr) -> Type:
        """The type of an operand (recorded too): the type checker's `expr`."""
        raise NotImplementedError

    def reassociate(self, e: ast.Binary | ast.Unary) -> ast.Expr | None:
        """Give boolean `==`/`!=` (iff/xor) their golog++ precedence, the loosest beside `->`.

        The grammar parses every `==` as a comparison, tighter than `&`; once the operand types
        are known, an unparenthesised chain that mixes a boolean `==` with `&`, `|`, `->` or `!`
        is rebuilt: `p() == q() & r()` means `p() == (q() & r())`. Returns None when nothing
        changes (almost always, and cheaply: the operand types are only computed when the chain
        has both kinds of operator)."""
        members: list[int] = []
        equality, other = _chain_ops(e, members)
        if not (equality and other):
            # Nothing to re-associate here, nor in any sub-chain: do not look again.
            self.reassociated.update(members)
            return None
        items: list[ast.Expr | Op | _Not] = []
        operators: list[int] = []
        self.state.silent += 1
        try:
            self.flatten_chain(e, items, operators, root=True)
        finally:
            self.state.silent -= 1
        if not any(x is _EQ or x is _NE for x in items):
            # No `==`/`!=` compares booleans: the chain has only `&`, `|`, `->` and `!`, and
            # climbing it would rebuild the tree the grammar built (each left-associative, at
            # the same levels, `!` on the operand after it), which the comparison below would
            # find unchanged.
            self.reassociated.update(operators)
            return None
        rebuilt, rest = _climb(items, 0)
        assert not rest
        if rebuilt == e:
            # Each operator of the chain heads a sub-chain whose items are a run of `items`,
            # built at its own precedence level: climbed alone, that run gives the same tree.
            # So no sub-chain changes either; looking at each again (typing its operands
            # silently again, with the same results) would change nothing.
            self.reassociated.update(operators)
            return None
        if e.parenthesized:
            rebuilt = replace(rebuilt, span=e.span, parenthesized=True)
        _mark(rebuilt, self.reassociated)
        # The parsed chain's own nodes are all boolean; an editor pointing at one asks its type.
        _mark_types(e, self.model.expr_types)
        return rebuilt

    def flatten_chain(
        self, e: ast.Expr, out: list[ast.Expr | Op | _Not], operators: list[int], root: bool = False
    ) -> None:
        """The chain's operands and operators in order, into `out`; the ids of its operator
        nodes into `operators`."""
        inside = root or not e.parenthesized
        if inside and isinstance(e, ast.Binary) and e.op in BOOL_CHAIN:
            operators.append(id(e))
            self.flatten_chain(e.left, out, operators)
            out.append(e.op)
            self.flatten_chain(e.right, out, operators)
        elif inside and isinstance(e, ast.Unary) and e.op is _NOT:
            operators.append(id(e))
            out.append(_Not(e.span))
            self.flatten_chain(e.operand, out, operators)
        elif inside and isinstance(e, ast.Binary) and e.op in EQUALITY and self.is_boolean_pair(e):
            operators.append(id(e))
            self.flatten_chain(e.left, out, operators)
            out.append(e.op)
            self.flatten_chain(e.right, out, operators)
        else:
            out.append(e)

    def is_boolean_pair(self, e: ast.Binary) -> bool:
        return _is_bool(self.type_of(e.left)) and _is_bool(self.type_of(e.right))


def _is_bool(t: Type) -> bool:
    """`base(t) is BOOL`."""
    return t is BOOL or (t.__class__ is DomainType and t.element is BOOL)


def continues_chain(e: ast.Expr) -> bool:
    """Whether the operand `e` belongs to the chain of the operator above it (`_chain_ops`):
    an unparenthesised `&`, `|`, `->`, `==`, `!=` or `!`. An operator whose operands both do
    not is a chain of one operator, which `reassociate` always leaves as it is (it needs an
    `==`/`!=` and another operator): the type checker asks it only about longer chains."""
    if e.parenthesized:
        return False
    kind = e.__class__
    if kind is ast.Binary:
        return e.op in CHAIN_OPS  # type: ignore[attr-defined]
    return kind is ast.Unary and e.op is _NOT  # type: ignore[attr-defined]


def _chain_ops(e: ast.Expr, members: list[int]) -> tuple[bool, bool]:
    """Whether the unparenthesised boolean/equality chain rooted at `e` (parentheses around
    the whole chain do not end it) has an `==`/`!=`, and whether it has another operator
    (`&`, `|`, `->`, `!`); adds the ids of the chain's nodes to `members`. Iterative: a chain
    of thousands of `&` is a deep tree."""
    equality = other = False
    stack = [e]
    while stack:
        node = stack.pop()
        if node.parenthesized and node is not e:
            continue
        if isinstance(node, ast.Binary):
            op = node.op
            if op is _EQ or op is _NE:
                equality = True
            elif op is _AND or op is _OR or op is _IMPLIES:
                other = True
            else:
                continue
            members.append(id(node))
            stack.append(node.left)
            stack.append(node.right)
        elif isinstance(node, ast.Unary) and node.op is _NOT:
            other = True
            members.append(id(node))
            stack.append(node.operand)
    return equality, other


_LEVELS: tuple[tuple[Op, ...], ...] = (
    (Op.IMPLIES, Op.EQ, Op.NE),
    (Op.OR,),
    (Op.AND,),
)


@dataclass(frozen=True, slots=True)
class _Not:
    """A prefix `!` in a flattened chain (it applies to the next operand)."""

    span: Span


def _climb(items: list[ast.Expr | Op | _Not], level: int) -> tuple[ast.Expr, list[ast.Expr | Op | _Not]]:
    """Precedence climbing over a flattened chain; returns the tree and the unread items."""
    if level == len(_LEVELS):
        head = items[0]
        if isinstance(head, _Not):
            operand, rest = _climb(items[1:], level)
            span = Span(head.span.source, head.span.start, operand.span.end)
            return ast.Unary(span=span, op=_NOT, operand=operand), rest
        assert isinstance(head, ast.Expr)
        return head, items[1:]
    left, rest = _climb(items, level + 1)
    while rest and isinstance(rest[0], Op) and rest[0] in _LEVELS[level]:
        op = rest[0]
        right, rest = _climb(rest[1:], level + 1)
        span = Span(left.span.source, left.span.start, right.span.end)
        left = ast.Binary(span=span, op=op, left=left, right=right)
    return left, rest


def _mark(e: ast.Expr, done: set[int]) -> None:
    if isinstance(e, ast.Binary) and (e.op in BOOL_CHAIN or e.op in EQUALITY):
        done.add(id(e))
        _mark(e.left, done)
        _mark(e.right, done)
    elif isinstance(e, ast.Unary):
        done.add(id(e))
        _mark(e.operand, done)


def _mark_types(e: ast.Expr, types: dict[int, Type]) -> None:
    if e.parenthesized and id(e) in types:
        return
    if isinstance(e, ast.Binary) and (e.op in BOOL_CHAIN or e.op in EQUALITY):
        types.setdefault(id(e), BOOL)
        _mark_types(e.left, types)
        _mark_types(e.right, types)
    elif isinstance(e, ast.Unary) and e.op is _NOT:
        types.setdefault(id(e), BOOL)
        _mark_types(e.operand, types)
