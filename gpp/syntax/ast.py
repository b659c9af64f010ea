"""The golog++ syntax tree: frozen dataclasses, every node with a Span.

Spans, and the `parenthesized` flag of expressions, are excluded from equality, so two trees
compare equal when they mean the same program text up to layout and redundant parentheses.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING, TypeAlias

from gpp.base.source import Span

if TYPE_CHECKING:
    from gpp.base.source import Source


@dataclass(frozen=True, slots=True, kw_only=True)
class Node:
    span: Span = field(compare=False, repr=False)


@dataclass(frozen=True, slots=True, kw_only=True)
class Ident(Node):
    """An identifier where it is written (a declaration's name or a reference)."""

    name: str


# ---------------------------------------------------------------- types


@dataclass(frozen=True, slots=True, kw_only=True)
class NamedType(Node):
    """A type by name: a builtin (`number`, `bool`, ...), a compound type or a domain."""

    name: str


@dataclass(frozen=True, slots=True, kw_only=True)
class ListType(Node):
    element: TypeExpr


TypeExpr = NamedType | ListType


@dataclass(frozen=True, slots=True, kw_only=True)
class Param(Node):
    type: TypeExpr
    name: Ident


# ---------------------------------------------------------------- expressions


class UnaryOp(Enum):
    NOT = "!"
    NEG = "-"


class BinaryOp(Enum):
    IMPLIES = "->"
    OR = "|"
    AND = "&"
    EQ = "=="
    NE = "!="
    LT = "<"
    LE = "<="
    GT = ">"
    GE = ">="
    ADD = "+"
    SUB = "-"
    MUL = "*"
    DIV = "/"
    MOD = "%"
    POW = "**"


COMPARISON_OPS = frozenset({BinaryOp.EQ, BinaryOp.NE, BinaryOp.LT, BinaryOp.LE, BinaryOp.GT, BinaryOp.GE})
BOOLEAN_OPS = frozenset({BinaryOp.IMPLIES, BinaryOp.OR, BinaryOp.AND})
ARITHMETIC_OPS = frozenset({BinaryOp.ADD, BinaryOp.SUB, BinaryOp.MUL, BinaryOp.DIV, BinaryOp.MOD, BinaryOp.POW})


class Quantifier(Enum):
    EXISTS = "exists"
    FORALL = "forall"


class Builtin(Enum):
    LENGTH = "length"
    TO_STRING = "to_string"


@dataclass(frozen=True, slots=True, kw_only=True)
class Expr(Node):
    parenthesized: bool = field(default=False, compare=False, repr=False)


@dataclass(frozen=True, slots=True, kw_only=True)
class NumberLit(Expr):
    value: int | float


@dataclass(frozen=True, slots=True, kw_only=True)
class StringLit(Expr):
    value: str


@dataclass(frozen=True, slots=True, kw_only=True)
class BoolLit(Expr):
    value: bool


@dataclass(frozen=True, slots=True, kw_only=True)
class NullLit(Expr):
    pass


@dataclass(frozen=True, slots=True, kw_only=True)
class Name(Expr):
    """A bare identifier in an expression: a variable, else a symbol (resolved later)."""

    name: str


@dataclass(frozen=True, slots=True, kw_only=True)
class Call(Expr):
    """`name(args)`: a fluent, function or exog function in an expression; an action or
    procedure as a statement."""

    name: Ident
    args: tuple[Expr, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class Unary(Expr):
    op: UnaryOp
    operand: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class Binary(Expr):
    op: BinaryOp
    left: Expr
    right: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class Quantified(Expr):
    quantifier: Quantifier
    var_type: TypeExpr
    var: Ident
    body: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class Conditional(Expr):
    condition: Expr
    then: Expr
    otherwise: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class FieldAccess(Expr):
    subject: Expr
    field: Ident


@dataclass(frozen=True, slots=True, kw_only=True)
class Index(Expr):
    subject: Expr
    index: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class FieldInit(Node):
    name: Ident
    value: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class CompoundLit(Expr):
    type_name: Ident
    fields: tuple[FieldInit, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class ListLit(Expr):
    type: ListType
    elements: tuple[Expr, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class BuiltinCall(Expr):
    function: Builtin
    arg: Expr


# ---------------------------------------------------------------- statements


class Hook(Enum):
    START = "start"
    END = "end"
    FINISH = "finish"
    FAIL = "fail"
    CANCEL = "cancel"


class ListOp(Enum):
    PUSH_BACK = "push_back"
    PUSH_FRONT = "push_front"
    POP_BACK = "pop_back"
    POP_FRONT = "pop_front"


@dataclass(frozen=True, slots=True, kw_only=True)
class StmtNode(Node):
    """The base class of the statement classes below. Annotate with `Statement`, the closed
    union, so that a `match` over a statement ending in `assert_never` is checked by mypy."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Block(StmtNode):
    body: tuple[Statement, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class If(StmtNode):
    condition: Expr
    then: Statement
    otherwise: Statement | None


@dataclass(frozen=True, slots=True, kw_only=True)
class While(StmtNode):
    condition: Expr
    body: Statement


@dataclass(frozen=True, slots=True, kw_only=True)
class Test(StmtNode):
    condition: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class Choose(StmtNode):
    alternatives: tuple[Statement, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class Concurrent(StmtNode):
    branches: tuple[Statement, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class Pick(StmtNode):
    var_type: TypeExpr
    var: Ident
    values: tuple[Expr, ...] | None
    body: Statement


@dataclass(frozen=True, slots=True, kw_only=True)
class Solve(StmtNode):
    horizon: Expr
    reward: Expr
    body: Statement


@dataclass(frozen=True, slots=True, kw_only=True)
class Search(StmtNode):
    body: Statement


@dataclass(frozen=True, slots=True, kw_only=True)
class During(StmtNode):
    action: Expr
    # `during (a) until (e) ...`: the activity is cancelled when `e` holds while it runs, and
    # the body is left when the activity ends (docs/semantics.md, "Watching an activity").
    until: Expr | None = None
    body: Statement
    on_fail: Statement | None
    on_cancel: Statement | None


@dataclass(frozen=True, slots=True, kw_only=True)
class HookStmt(StmtNode):
    hook: Hook
    action: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class Assign(StmtNode):
    target: Expr
    value: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class ListStmt(StmtNode):
    op: ListOp
    target: Expr
    value: Expr | None


@dataclass(frozen=True, slots=True, kw_only=True)
class CallStmt(StmtNode):
    call: Expr


# Every statement kind. Adding one here makes mypy name every `match` over statements that
# must handle it (they end in `assert_never`); see docs/design.md, "Adding a statement kind".
Statement: TypeAlias = (
    Block
    | If
    | While
    | Test
    | Choose
    | Concurrent
    | Pick
    | Solve
    | Search
    | During
    | HookStmt
    | Assign
    | ListStmt
    | CallStmt
)
STATEMENT_KINDS: tuple[type[StmtNode], ...] = (
    Block,
    If,
    While,
    Test,
    Choose,
    Concurrent,
    Pick,
    Solve,
    Search,
    During,
    HookStmt,
    Assign,
    ListStmt,
    CallStmt,
)


# ---------------------------------------------------------------- declarations


@dataclass(frozen=True, slots=True, kw_only=True)
class Decl(Node):
    pass


@dataclass(frozen=True, slots=True, kw_only=True)
class Include(Decl):
    path: StringLit


class DomainOp(Enum):
    UNION = "|"
    DIFFERENCE = "\\"
    INTERSECTION = "&"


@dataclass(frozen=True, slots=True, kw_only=True)
class DomainExpr(Node):
    parenthesized: bool = field(default=False, compare=False, repr=False)


@dataclass(frozen=True, slots=True, kw_only=True)
class DomainRef(DomainExpr):
    name: Ident


@dataclass(frozen=True, slots=True, kw_only=True)
class DomainSet(DomainExpr):
    elements: tuple[Expr, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class DomainBinary(DomainExpr):
    op: DomainOp
    left: DomainExpr
    right: DomainExpr


@dataclass(frozen=True, slots=True, kw_only=True)
class DomainDecl(Decl):
    element_type: TypeExpr
    name: Ident
    definition: DomainExpr | None


@dataclass(frozen=True, slots=True, kw_only=True)
class CompoundDecl(Decl):
    name: Ident
    fields: tuple[Param, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class ListTypeDecl(Decl):
    type: ListType


@dataclass(frozen=True, slots=True, kw_only=True)
class InitialValue(Node):
    args: tuple[Expr, ...]
    value: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class FluentDecl(Decl):
    type: TypeExpr
    name: Ident
    params: tuple[Param, ...]
    initially: tuple[InitialValue, ...] | None


@dataclass(frozen=True, slots=True, kw_only=True)
class Effect(Node):
    condition: Expr | None
    target: Expr
    value: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class MappingArg(Node):
    name: Ident
    value: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class Mapping(Node):
    name: StringLit
    args: tuple[MappingArg, ...]


class SectionKind(Enum):
    PRECONDITION = "precondition"
    EFFECT = "effect"
    START_EFFECT = "start_effect"
    SENSES = "senses"
    MAPPING = "mapping"
    SILENT = "silent"
    DURATION = "duration"


@dataclass(frozen=True, slots=True, kw_only=True)
class ActionSection(Node):
    """One `keyword:` section of an action body; `keyword` spans the section keyword."""

    keyword: Span = field(compare=False, repr=False)


@dataclass(frozen=True, slots=True, kw_only=True)
class PreconditionSection(ActionSection):
    condition: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class EffectSection(ActionSection):
    effects: tuple[Effect, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class StartEffectSection(ActionSection):
    """`start_effect:`: effects applied when the action's activity starts (docs/semantics.md)."""

    effects: tuple[Effect, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class SensesSection(ActionSection):
    target: Expr
    value: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class MappingSection(ActionSection):
    mapping: Mapping


@dataclass(frozen=True, slots=True, kw_only=True)
class SilentSection(ActionSection):
    value: Expr


@dataclass(frozen=True, slots=True, kw_only=True)
class DurationSection(ActionSection):
    low: Expr
    high: Expr


SECTION_KINDS: dict[type[ActionSection], SectionKind] = {
    PreconditionSection: SectionKind.PRECONDITION,
    EffectSection: SectionKind.EFFECT,
    StartEffectSection: SectionKind.START_EFFECT,
    SensesSection: SectionKind.SENSES,
    MappingSection: SectionKind.MAPPING,
    SilentSection: SectionKind.SILENT,
    DurationSection: SectionKind.DURATION,
}


@dataclass(frozen=True, slots=True, kw_only=True)
class ActionDecl(Decl):
    """`action` or `exog_action`; `sections` is None for a forward declaration."""

    exogenous: bool
    name: Ident
    params: tuple[Param, ...]
    sections: tuple[ActionSection, ...] | None

    def section(self, kind: type[ActionSection]) -> ActionSection | None:
        for s in self.sections or ():
            if type(s) is kind:
                return s
        return None


@dataclass(frozen=True, slots=True, kw_only=True)
class FunctionDecl(Decl):
    type: TypeExpr
    name: Ident
    params: tuple[Param, ...]
    body: Expr | None


@dataclass(frozen=True, slots=True, kw_only=True)
class ExogFunctionDecl(Decl):
    type: TypeExpr
    name: Ident
    params: tuple[Param, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class ProcedureDecl(Decl):
    name: Ident
    params: tuple[Param, ...]
    body: Statement | None


@dataclass(frozen=True, slots=True, kw_only=True)
class MainBlock(Decl):
    """The legacy trailing anonymous block, meaning `procedure main()`."""

    body: Block


# ---------------------------------------------------------------- platform model


@dataclass(frozen=True, slots=True, kw_only=True)
class ClockFormula(Node):
    parenthesized: bool = field(default=False, compare=False, repr=False)


@dataclass(frozen=True, slots=True, kw_only=True)
class ClockBound(ClockFormula):
    clock: Ident
    op: BinaryOp
    bound: NumberLit


@dataclass(frozen=True, slots=True, kw_only=True)
class ClockNot(ClockFormula):
    operand: ClockFormula


@dataclass(frozen=True, slots=True, kw_only=True)
class ClockBinary(ClockFormula):
    op: BinaryOp  # AND or OR
    left: ClockFormula
    right: ClockFormula


@dataclass(frozen=True, slots=True, kw_only=True)
class StateDef(Node):
    name: Ident
    invariant: ClockFormula | None


@dataclass(frozen=True, slots=True, kw_only=True)
class Transition(Node):
    source: Ident
    controllable: bool
    guard: ClockFormula | None
    target: Ident
    resets: tuple[Ident, ...] | None


@dataclass(frozen=True, slots=True, kw_only=True)
class ComponentSection(Node):
    keyword: Span = field(compare=False, repr=False)


@dataclass(frozen=True, slots=True, kw_only=True)
class ClocksSection(ComponentSection):
    clocks: tuple[Ident, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class StatesSection(ComponentSection):
    states: tuple[StateDef, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class TransitionsSection(ComponentSection):
    transitions: tuple[Transition, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class ComponentDecl(Decl):
    name: Ident
    sections: tuple[ComponentSection, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class Bound(Node):
    low: NumberLit | None
    high: NumberLit | None


@dataclass(frozen=True, slots=True, kw_only=True)
class Wildcard(Expr):
    """`*` as an argument of a constraint's action pattern."""


@dataclass(frozen=True, slots=True, kw_only=True)
class GroundAction(Node):
    name: Ident
    args: tuple[Expr, ...]


class SpecOp(Enum):
    AND = "&"
    OR = "|"
    UNTIL = "until"
    SINCE = "since"


class TemporalOp(Enum):
    NEXT = "next"
    PREVIOUS = "previous"
    FUTURE = "future"
    PAST = "past"


@dataclass(frozen=True, slots=True, kw_only=True)
class Spec(Node):
    parenthesized: bool = field(default=False, compare=False, repr=False)


@dataclass(frozen=True, slots=True, kw_only=True)
class SpecBinary(Spec):
    op: SpecOp
    bound: Bound | None
    left: Spec
    right: Spec


@dataclass(frozen=True, slots=True, kw_only=True)
class SpecUnary(Spec):
    op: TemporalOp
    bound: Bound | None
    operand: Spec


@dataclass(frozen=True, slots=True, kw_only=True)
class ActionAtom(Spec):
    """`start(a(..))`, `end(..)`, `finish(..)`, `fail(..)`, `cancel(..)` or `during(..)`."""

    hook: str
    action: GroundAction


@dataclass(frozen=True, slots=True, kw_only=True)
class StateAtom(Spec):
    component: Ident
    state: Ident


@dataclass(frozen=True, slots=True, kw_only=True)
class Constraint(Node):
    condition: Spec
    requirement: Spec


@dataclass(frozen=True, slots=True, kw_only=True)
class ConstraintsDecl(Decl):
    constraints: tuple[Constraint, ...]


# ---------------------------------------------------------------- program


@dataclass(frozen=True, slots=True, kw_only=True)
class Program(Node):
    declarations: tuple[Decl, ...]

    @property
    def source(self) -> Source:
        return self.span.source
