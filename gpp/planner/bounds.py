"""Branch and bound for `solve`, only where it is provably exact: a static analysis of a
`solve` (`analyse`) that gives an upper bound on what the rest of any branch can still earn
(`solve_bound`: per step, `GOAL_LOOP` when a goal ends the loop, `STEPS_TO_GOAL` from the
state), and enables it only when no step of planning in a skipped subtree could raise, so
that skipping it cannot change the result of gpp.planner.reference. Anything outside the
fragment it can prove gives no bound, and `analyse` says why and where.

The bounds and the proof that pruning with them is exact: docs/design.md, "Branch and bound".
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import cast

from gpp.base.source import Span
from gpp.model.model import Model
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import BOOL, DomainType, ListType, Sym, Type
from gpp.planner.guards import FREE_STEP_LIMIT
from gpp.runtime.codegen import ExprGen, Unit, Unsupported
from gpp.runtime.compiled import Env
from gpp.runtime.semantics import Semantics
from gpp.runtime.state import State
from gpp.runtime.values import Value
from gpp.syntax import ast
from gpp.syntax.walk import walk

# A bound on the value of the rest of a branch with h steps of horizon left.
Bound = Callable[[int], float]

# The bounds (docs/design.md, "Branch and bound").
PER_STEP = "per step"
GOAL_LOOP = "goal ends the loop"
STEPS_TO_GOAL = "steps to the goal"

# A bound on the value of the rest of a branch from a state with h steps of horizon left.
StateBound = Callable[[State, int], float]

# The bounds of goal loops (GOAL_LOOP, STEPS_TO_GOAL): see `ends_at_goal`.
_GOAL_BOUNDS: weakref.WeakSet[StateBound] = weakref.WeakSet()

# Pruning is enabled up to this horizon (docs/design.md, "Branch and bound").
MAX_HORIZON = 1000

# Sums of whole numbers below this are exact in floating point.
_EXACT = float(2**53)

# Intervals beyond this are treated as unknown (far below the largest number, so no overflow).
_LARGE = 1e300

# Rounds of the fixpoint on fluent intervals before a growing interval is given up.
_ROUNDS = 16


@dataclass(frozen=True, slots=True)
class Fact:
    """What is known of the value of an expression in every state: never `null`, and for a
    number the interval it lies in (None: unknown) and whether it is always whole."""

    nonnull: bool
    low: float = -math.inf
    high: float = math.inf
    whole: bool = False

    @property
    def bounded(self) -> bool:
        return self.nonnull and -_LARGE <= self.low <= self.high <= _LARGE

    def join(self, other: Fact) -> Fact:
        return Fact(
            self.nonnull and other.nonnull,
            min(self.low, other.low),
            max(self.high, other.high),
            self.whole and other.whole,
        )


_UNKNOWN = Fact(False)
_SOME = Fact(True)  # never null, nothing else known (a truth value, a symbol)


def _number(low: float, high: float, whole: bool) -> Fact:
    if not (-_LARGE <= low <= high <= _LARGE):
        return Fact(True)
    return Fact(True, low, high, whole)


class Unsafe(Exception):
    """Planning this part could raise an error (or the analysis cannot tell)."""

    def __init__(self, reason: str, span: Span | None) -> None:
        super().__init__(reason)
        self.reason = reason
        self.span = span


@dataclass(frozen=True)
class BoundAnalysis:
    """The result of the analysis of one `solve`: the reward's interval (if known), and the
    bound, or the reason why there is none."""

    reward_low: float | None
    reward_high: float | None
    reason: str | None  # why pruning is off (None: it is on)
    span: Span | None = None  # where the reason is
    bound: Bound | None = field(default=None, compare=False)
    kind: str | None = None  # PER_STEP, GOAL_LOOP or STEPS_TO_GOAL (None: no bound)
    # STEPS_TO_GOAL: the goal's conjuncts, the most fluent instances one step writes, and the
    # bounds of the reward at the goal and elsewhere.
    goal_atoms: tuple[ast.Expr, ...] | None = None
    writes_per_step: int = 1
    goal_values: tuple[float, float] | None = None
    # GOAL_LOOP, STEPS_TO_GOAL: every run of the loop's body makes exactly one costed step (it is
    # never final), so the loop ends only at the goal.
    always_steps: bool = False
    # STEPS_TO_GOAL: the goal's fluent F and the value of each of its instances the goal names,
    # when the not-well-placed distance holds; else why not (docs/design.md, "Branch and bound").
    placement: tuple[Symbol, dict[Sym, Sym]] | None = None
    placement_reason: str | None = None

    @property
    def enabled(self) -> bool:
        return self.bound is not None


def _values(model: Model, t: Type | None) -> tuple[object, ...] | None:
    if t is BOOL:
        return (False, True)
    if isinstance(t, DomainType) and t.defined:
        return t.values
    return None


def _hull(values: tuple[object, ...]) -> Fact:
    numbers = [v for v in values if isinstance(v, int | float) and not isinstance(v, bool)]
    if not numbers or len(numbers) < len(values):
        return _SOME
    return _number(min(numbers), max(numbers), all(float(v).is_integer() for v in numbers))


class _Analysis:
    def __init__(self, model: Model) -> None:
        self.model = model
        self.fluents: dict[str, Fact] = {}
        self.functions: list[str] = []  # the functions being analysed (a recursion is unsafe)
        # A function's fact for the facts of its arguments (forgotten when a fluent's changes).
        self.function_facts: dict[tuple[str, tuple[Fact, ...]], Fact | Unsafe] = {}
        self.procedures: list[str] = []
        self.checked_actions: set[str] = set()
        self.tests: dict[tuple[str, bool], int] = {}  # procedure's tests, per in-loop flag
        self._fluent_facts()

    # ---------------------------------------------------------------- fluents

    def _assignments(self) -> list[tuple[str, ast.Expr | None]]:
        """Every (fluent, value) stored anywhere in the program (None: a value not known)."""
        out: list[tuple[str, ast.Expr | None]] = []

        def fluent_of(target: ast.Expr) -> str | None:
            while isinstance(target, ast.FieldAccess | ast.Index):
                target = target.subject
            symbol = self.model.target(target)
            return symbol.name if symbol is not None else None

        def add(target: ast.Expr, value: ast.Expr | None) -> None:
            name = fluent_of(target)
            if name is not None:
                whole = isinstance(target, ast.Call)
                out.append((name, value if whole else None))

        for parsed in self.model.files:  # every declaration: actions (exogenous too), procedures
            for node in walk(parsed.program):
                if isinstance(node, ast.Effect | ast.Assign):
                    add(node.target, node.value)
                elif isinstance(node, ast.SensesSection | ast.ListStmt):
                    add(node.target, None)
        return out

    def _fluent_facts(self) -> None:
        for symbol in self.model.globals.values():
            decl = symbol.decl
            if symbol.kind is not SymbolKind.FLUENT or symbol.predefined or not isinstance(decl, ast.FluentDecl):
                continue
            names = [p.name for p in symbol.params]
            fact: Fact | None = None
            total = False
            for init in decl.initially or ():
                total = total or all(
                    isinstance(a, ast.Name) and i < len(names) and a.name == names[i] for i, a in enumerate(init.args)
                )
                f = self._quietly(init.value)
                fact = f if fact is None else fact.join(f)
            if fact is None or not total:
                fact = Fact(False, fact.low, fact.high, fact.whole) if fact is not None else _UNKNOWN
            self.fluents[symbol.name] = fact
        assignments = self._assignments()
        # Once intervals are given up, every further change makes a fact weaker for good (an
        # interval lost, `null` or a fraction possible): a few more rounds reach the fixpoint.
        rounds = 0
        while True:
            changed, rounds = False, rounds + 1
            for name, value in assignments:
                old = self.fluents.get(name, _UNKNOWN)
                new = old.join(self._quietly(value) if value is not None else _UNKNOWN)
                if rounds >= _ROUNDS and (new.low, new.high) != (old.low, old.high):
                    new = Fact(new.nonnull)  # still growing: give its interval up
                if new != old:
                    self.fluents[name], changed = new, True
                    self.function_facts.clear()
            if not changed:
                return

    def _quietly(self, e: ast.Expr) -> Fact:
        """The fact of `e` where it does not matter whether it can raise (an error there
        surfaces wherever it is evaluated; only the value is wanted)."""
        try:
            return self.expr(e, {})
        except Unsafe:
            return _UNKNOWN

    # ---------------------------------------------------------------- expressions

    def expr(self, e: ast.Expr, env: dict[int, Fact]) -> Fact:
        """The fact of `e` (variables of functions bound in `env`); Unsafe if it can raise."""
        e = self.model.effective(e)
        match e:
            case ast.NumberLit():
                return _number(e.value, e.value, float(e.value).is_integer())
            case ast.BoolLit() | ast.StringLit():
                return _SOME
            case ast.NullLit():
                return _UNKNOWN
            case ast.Name():
                return self._name(e, env)
            case ast.Call():
                return self._call(e, env)
            case ast.Unary(op=ast.UnaryOp.NOT):
                self.expr(e.operand, env)
                return _SOME
            case ast.Unary():
                f = self._operand(e.operand, env, e.span)
                return _number(-f.high, -f.low, f.whole)
            case ast.Binary():
                return self._binary(e, env)
            case ast.Quantified():
                target = self.model.target(e.var)
                if target is None or _values(self.model, target.type) is None:
                    raise Unsafe("a quantifier over a type that is not finite", e.span)
                self.expr(e.body, env)
                return _SOME
            case ast.Conditional():
                self.expr(e.condition, env)
                return self.expr(e.then, env).join(self.expr(e.otherwise, env))
            case _:
                raise Unsafe(f"`{type(e).__name__}` expressions are not analysed", e.span)

    def _name(self, e: ast.Name, env: dict[int, Fact]) -> Fact:
        target = self.model.target(e)
        if target is None:
            raise Unsafe(f"`{e.name}` is not resolved", e.span)
        if target.kind is SymbolKind.SYMBOL:
            return _SOME
        known = env.get(id(target))
        if known is not None:
            return known
        if target.kind is SymbolKind.VARIABLE:  # of a `pick` or a quantifier: never null
            decl = target.decl
            if isinstance(decl, ast.Pick) and decl.values is not None:
                fact = self.expr(decl.values[0], {})
                for v in decl.values[1:]:
                    fact = fact.join(self.expr(v, {}))
                return fact
            values = _values(self.model, target.type)
            return _hull(values) if values is not None else _SOME
        return _UNKNOWN  # a parameter: any value its caller passes, `null` too

    def _call(self, e: ast.Call, env: dict[int, Fact]) -> Fact:
        symbol = self.model.target(e)
        if symbol is None:
            raise Unsafe(f"`{e.name.name}` is not resolved", e.span)
        args = [self.expr(a, env) for a in e.args]
        if symbol.kind is SymbolKind.FLUENT:
            if symbol.predefined:
                raise Unsafe(f"`{symbol.name}` reads the clock", e.span)
            return self.fluents.get(symbol.name, _UNKNOWN)
        if symbol.kind is SymbolKind.FUNCTION:
            decl = symbol.decl
            if not isinstance(decl, ast.FunctionDecl) or decl.body is None:
                raise Unsafe(f"function `{symbol.name}` has no body", e.span)
            if symbol.name in self.functions:
                raise Unsafe(f"function `{symbol.name}` is recursive", e.span)
            key = (symbol.name, tuple(args))
            known = self.function_facts.get(key)
            if known is None:
                self.functions.append(symbol.name)
                try:
                    known = self.expr(decl.body, {id(p): a for p, a in zip(symbol.params, args, strict=True)})
                except Unsafe as unsafe:
                    known = unsafe
                finally:
                    self.functions.pop()
                self.function_facts[key] = known
            if isinstance(known, Unsafe):
                raise known
            return known
        raise Unsafe(f"`{symbol.name}` ({symbol.kind.value}) is not known while planning", e.span)

    def _operand(self, e: ast.Expr, env: dict[int, Fact], span: Span) -> Fact:
        f = self.expr(e, env)
        if not f.bounded:
            raise Unsafe("an operand of arithmetic that may be `null` or unbounded", span)
        return f

    def _binary(self, e: ast.Binary, env: dict[int, Fact]) -> Fact:
        op = e.op
        if op in ast.BOOLEAN_OPS or op in (ast.BinaryOp.EQ, ast.BinaryOp.NE):
            self.expr(e.left, env)
            self.expr(e.right, env)
            return _SOME
        if op in ast.COMPARISON_OPS:
            for side in (e.left, e.right):
                if not self.expr(side, env).nonnull:
                    raise Unsafe(f"`{op.value}` on a value that may be `null`", side.span)
            return _SOME
        a, b = self._operand(e.left, env, e.span), self._operand(e.right, env, e.span)
        whole = a.whole and b.whole
        if op in (ast.BinaryOp.ADD, ast.BinaryOp.SUB, ast.BinaryOp.MUL):
            if op is ast.BinaryOp.ADD:
                low, high = a.low + b.low, a.high + b.high
            elif op is ast.BinaryOp.SUB:
                low, high = a.low - b.high, a.high - b.low
            else:
                corners = [a.low * b.low, a.low * b.high, a.high * b.low, a.high * b.high]
                low, high = min(corners), max(corners)
            if not (-_LARGE <= low <= high <= _LARGE):
                raise Unsafe(f"`{op.value}` may overflow", e.span)
            return _number(low, high, whole)
        if b.low <= 0 <= b.high:
            raise Unsafe(f"`{op.value}` by a value that may be 0", e.right.span)
        if op is ast.BinaryOp.DIV:
            corners = [a.low / b.low, a.low / b.high, a.high / b.low, a.high / b.high]
            return _number(min(corners), max(corners), False)
        if op is ast.BinaryOp.MOD and whole:
            return _number(0, b.high - 1, True) if b.low > 0 else _number(b.low + 1, 0, True)
        raise Unsafe(f"`{op.value}` may fail", e.span)

    # ---------------------------------------------------------------- stored values

    def _stored(self, value: ast.Expr, target: Type | None, env: dict[int, Fact]) -> None:
        """`value` is safe, and storing it into a place of type `target` cannot fail its
        domain check."""
        self.expr(value, env)
        if isinstance(target, ListType):
            raise Unsafe("a list is stored", value.span)
        if not isinstance(target, DomainType):
            return
        possible = self._possible(value)
        if possible is None or not all(v is None or target.contains(v) for v in possible):  # type: ignore[arg-type]
            raise Unsafe(f"a value that may be outside domain `{target.name}`", value.span)

    def _possible(self, e: ast.Expr) -> tuple[object, ...] | None:
        """The values `e` can have (None: not known), `null` included as None."""
        e = self.model.effective(e)
        match e:
            case ast.NumberLit() | ast.BoolLit():
                return (e.value,)
            case ast.NullLit():
                return (None,)
            case ast.Name() | ast.Call():
                target = self.model.target(e)
                if target is not None and target.kind is SymbolKind.SYMBOL:
                    return (Sym(target.name),)
                # Values stored there passed a domain check (a fluent, a parameter of an action
                # or a procedure), or come from a domain (a `pick`, a quantifier).
                if target is None or not (
                    target.kind in (SymbolKind.VARIABLE, SymbolKind.FLUENT)
                    or (
                        target.kind is SymbolKind.PARAMETER
                        and target.owner is not None
                        and target.owner.kind in (SymbolKind.ACTION, SymbolKind.PROCEDURE)
                    )
                ):
                    return None
                if isinstance(target.decl, ast.Pick) and target.decl.values is not None:
                    out: list[object] = []
                    for v in target.decl.values:
                        more = self._possible(v)
                        if more is None:
                            return None
                        out.extend(more)
                    return tuple(out)
                values = _values(self.model, target.type)
                return None if values is None else (*values, None)
            case ast.Conditional():
                then, otherwise = self._possible(e.then), self._possible(e.otherwise)
                return None if then is None or otherwise is None else then + otherwise
            case _:
                return None

    # ---------------------------------------------------------------- statements

    def statement(self, s: ast.Statement, in_loop: bool) -> int:
        """Check `s` (Unsafe if planning it could raise); the most tests a run through it makes."""
        match s:
            case ast.Block():
                return sum(self.statement(x, in_loop) for x in s.body)
            case ast.If():
                self.expr(s.condition, {})
                then = self.statement(s.then, in_loop)
                return then + (self.statement(s.otherwise, in_loop) if s.otherwise is not None else 0)
            case ast.While():
                self.expr(s.condition, {})
                self.statement(s.body, True)
                return 0
            case ast.Test():
                if in_loop:
                    raise Unsafe("a test inside a loop (a loop of free steps is an error)", s.span)
                self.expr(s.condition, {})
                return 1
            case ast.Choose():
                return sum(self.statement(x, in_loop) for x in s.alternatives)
            case ast.Pick():
                target = self.model.target(s.var)
                if s.values is not None:
                    for v in s.values:
                        self.expr(v, {})
                elif target is None or _values(self.model, target.type) is None:
                    raise Unsafe("a `pick` over a type that is not finite", s.span)
                return self.statement(s.body, in_loop)
            case ast.CallStmt():
                return self._call_statement(s, in_loop)
            case ast.Assign():
                if not isinstance(s.target, ast.Call):
                    raise Unsafe("an assignment to a part of a fluent", s.span)
                for a in s.target.args:
                    self.expr(a, {})
                fluent = self.model.target(s.target)
                self._stored(s.value, fluent.type if fluent is not None else None, {})
                return 0
            case _:
                raise Unsafe(f"`{type(s).__name__}` statements are not analysed", s.span)

    # ---------------------------------------------------------------- the goal loop

    def goal_loop(self, solve: ast.Solve) -> tuple[ast.Expr, Fact, Fact] | None:
        """For a `solve` whose body is `while (!G) S` and whose reward is `if (G) a else b`
        (through functions without parameters) with the same G reading no variable, and S a
        statement each run of which makes at most one step, that step costed and last: the
        condition G and the facts of `a` and `b`. None if the `solve` is not of that form."""
        body = self.loop_of(solve.body)
        if body is None or not self._one_step(body.body):
            return None
        condition = self.model.effective(body.condition)
        reward = self.model.effective(solve.reward)
        while isinstance(reward, ast.Call) and not reward.args:
            symbol = self.model.target(reward)
            decl = symbol.decl if symbol is not None and symbol.kind is SymbolKind.FUNCTION else None
            if not isinstance(decl, ast.FunctionDecl) or decl.body is None:
                return None
            reward = self.model.effective(decl.body)
        if not (
            isinstance(condition, ast.Unary)
            and condition.op is ast.UnaryOp.NOT
            and isinstance(reward, ast.Conditional)
            and self._same_goal(condition.operand, reward.condition)
        ):
            return None
        return reward.condition, self.expr(reward.then, {}), self.expr(reward.otherwise, {})

    @staticmethod
    def loop_of(body: ast.Statement) -> ast.While | None:
        """`body` if it is a `while` loop (in blocks of one statement), else None."""
        while isinstance(body, ast.Block) and len(body.body) == 1:
            body = body.body[0]
        return body if isinstance(body, ast.While) else None

    def always_steps(self, body: ast.Statement) -> bool:
        """`body` is a loop whose body makes exactly one costed step on every run that is not
        stuck: the loop ends only when its condition is false."""
        loop = self.loop_of(body)
        return loop is not None and self._one_step(loop.body, exactly=True)

    def goal_atoms(self, goal: ast.Expr) -> tuple[ast.Expr, ...] | None:
        """The conjuncts of `goal` (through functions without parameters), if each reads
        fluent instances named by constants only, no two the same instance. None otherwise."""
        conjuncts: list[ast.Expr] = []

        def split(e: ast.Expr) -> bool:
            e = self.model.effective(e)
            if isinstance(e, ast.Binary) and e.op is ast.BinaryOp.AND:
                return split(e.left) and split(e.right)
            if isinstance(e, ast.Call) and not e.args:
                symbol = self.model.target(e)
                if symbol is not None and symbol.kind is SymbolKind.FUNCTION:
                    decl = symbol.decl
                    return isinstance(decl, ast.FunctionDecl) and decl.body is not None and split(decl.body)
            conjuncts.append(e)
            return True

        if not split(goal):
            return None
        seen: set[tuple[str, tuple[object, ...]]] = set()
        for conjunct in conjuncts:
            reads = self._instances(conjunct)
            if reads is None or reads & seen:
                return None
            seen |= reads
        return tuple(conjuncts)

    def _instances(self, e: ast.Expr) -> set[tuple[str, tuple[object, ...]]] | None:
        """The fluent instances `e` reads, if it reads nothing else that can change (no
        variable, no function) and names them by constants."""
        e = self.model.effective(e)
        match e:
            case ast.NumberLit() | ast.BoolLit() | ast.StringLit() | ast.NullLit():
                return set()
            case ast.Name():
                target = self.model.target(e)
                return set() if target is not None and target.kind is SymbolKind.SYMBOL else None
            case ast.Unary():
                return self._instances(e.operand)
            case ast.Binary():
                left, right = self._instances(e.left), self._instances(e.right)
                return None if left is None or right is None else left | right
            case ast.Call():
                symbol = self.model.target(e)
                if symbol is None or symbol.kind is not SymbolKind.FLUENT or symbol.predefined:
                    return None
                args: list[object] = []
                for a in e.args:
                    a = self.model.effective(a)
                    if isinstance(a, ast.NumberLit | ast.BoolLit | ast.StringLit):
                        args.append(a.value)
                        continue
                    target = self.model.target(a) if isinstance(a, ast.Name) else None
                    if target is None or target.kind is not SymbolKind.SYMBOL:
                        return None
                    args.append(Sym(target.name))
                return {(symbol.name, tuple(args))}
            case _:
                return None

    def stacking(self, atoms: tuple[ast.Expr, ...]) -> tuple[Symbol, dict[Sym, Sym]] | str:
        """For conjuncts that are all `F(b) == v` (F a unary fluent over a finite domain of
        objects, b and v symbols) where every action the analysed program calls that writes an
        instance F(p) requires `!exists(T z) F(z) == p` (nothing has p as its value: p is
        clear) and no statement assigns F: F and the goal {b: v}. Otherwise why not (the
        not-well-placed distance does not hold; docs/design.md, "Branch and bound")."""
        fluent: Symbol | None = None
        goal: dict[Sym, Sym] = {}
        for atom in atoms:
            atom = self.model.effective(atom)
            sides = self._sides(atom)
            call = next((s for s in sides if isinstance(s, ast.Call)), None) if sides is not None else None
            value = next((s for s in sides if not isinstance(s, ast.Call)), None) if sides is not None else None
            symbol = self.model.target(call) if call is not None else None
            if call is None or symbol is None or symbol.kind is not SymbolKind.FLUENT or len(call.args) != 1:
                return "a conjunct of the goal is not `F(b) == v` for a unary fluent F"
            if fluent is not None and symbol is not fluent:
                return "the goal's conjuncts are on more than one fluent"
            fluent = symbol
            b, v = self._symbol(call.args[0]), self._symbol(value) if value is not None else None
            if b is None or v is None:
                return "a conjunct of the goal is not `F(b) == v` for symbols b and v"
            goal[b] = v
        if fluent is None:
            return "the goal has no conjunct"
        objects = _values(self.model, fluent.params[0].type)
        if objects is None:
            return f"the parameter of `{fluent.name}` is not of a finite domain"
        for parsed in self.model.files:
            for node in walk(parsed.program):
                if isinstance(node, ast.Assign | ast.ListStmt) and self._writes(node.target, fluent):
                    return f"a statement assigns `{fluent.name}`"
        for name in sorted(self.checked_actions):
            decl = self.model.globals[name].decl
            assert isinstance(decl, ast.ActionDecl)
            if not self._clears_before_writing(decl, fluent):
                return f"action `{name}` writes `{fluent.name}(p)` without requiring `!exists(z) {fluent.name}(z) == p`"
        return fluent, goal

    def _sides(self, e: ast.Expr) -> tuple[ast.Expr, ast.Expr] | None:
        if isinstance(e, ast.Binary) and e.op is ast.BinaryOp.EQ:
            return self.model.effective(e.left), self.model.effective(e.right)
        return None

    def _symbol(self, e: ast.Expr) -> Sym | None:
        e = self.model.effective(e)
        target = self.model.target(e) if isinstance(e, ast.Name) else None
        return Sym(target.name) if target is not None and target.kind is SymbolKind.SYMBOL else None

    def _writes(self, target: ast.Expr, fluent: Symbol) -> bool:
        while isinstance(target, ast.FieldAccess | ast.Index):
            target = target.subject
        return self.model.target(target) is fluent

    def _clears_before_writing(self, decl: ast.ActionDecl, fluent: Symbol) -> bool:
        """Every effect of `decl` on `fluent` writes F(p) for a parameter p, and the
        precondition has the conjunct `!exists(T z) F(z) == p` with T the type of F's
        parameter."""
        conjuncts: list[ast.Expr] = []
        for section in decl.sections or ():
            if isinstance(section, ast.PreconditionSection):
                pending = [section.condition]
                while pending:
                    e = self.model.effective(pending.pop())
                    if isinstance(e, ast.Binary) and e.op is ast.BinaryOp.AND:
                        pending += [e.left, e.right]
                    else:
                        conjuncts.append(e)
        for section in decl.sections or ():
            if not isinstance(section, ast.EffectSection):
                continue
            for effect in section.effects:
                if not self._writes(effect.target, fluent):
                    continue
                target = self.model.effective(effect.target)
                if not isinstance(target, ast.Call) or len(target.args) != 1:
                    return False
                written = self.model.target(target.args[0]) if isinstance(target.args[0], ast.Name) else None
                if written is None or written.kind is not SymbolKind.PARAMETER:
                    return False
                if not any(self._requires_clear(c, fluent, written) for c in conjuncts):
                    return False
        return True

    def _requires_clear(self, e: ast.Expr, fluent: Symbol, p: Symbol) -> bool:
        """`e` is `!exists(T z) F(z) == p` (either side of `==`), T the type of F's parameter."""
        if not (isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT):
            return False
        q = self.model.effective(e.operand)
        if not (isinstance(q, ast.Quantified) and q.quantifier is ast.Quantifier.EXISTS):
            return False
        z = self.model.target(q.var)
        sides = self._sides(self.model.effective(q.body))
        if z is None or z.type != fluent.params[0].type or sides is None:
            return False
        for call, other in (sides, sides[::-1]):
            if (
                isinstance(call, ast.Call)
                and self.model.target(call) is fluent
                and len(call.args) == 1
                and isinstance(call.args[0], ast.Name)
                and self.model.target(call.args[0]) is z
                and isinstance(other, ast.Name)
                and self.model.target(other) is p
            ):
                return True
        return False

    def writes_per_step(self) -> int:
        """The most fluent instances one step of the analysed program writes: an assignment
        writes one, an action one per effect."""
        most = 1
        for name in self.checked_actions:
            decl = self.model.globals[name].decl
            if isinstance(decl, ast.ActionDecl):
                effects = sum(len(s.effects) for s in decl.sections or () if isinstance(s, ast.EffectSection))
                most = max(most, effects)
        return most

    def _same_goal(self, a: ast.Expr, b: ast.Expr) -> bool:
        """`a` and `b` are the same expression, and read no variable (so they mean the same
        in the loop's condition and in the reward)."""
        a, b = self.model.effective(a), self.model.effective(b)
        if a != b:
            return False
        for node in walk(a):
            if isinstance(node, ast.Name):
                target = self.model.target(node)
                if target is None:
                    return False
                if target.kind is not SymbolKind.SYMBOL and not (
                    target.kind is SymbolKind.VARIABLE and isinstance(target.decl, ast.Quantified)
                ):
                    return False
        return True

    def _one_step(self, s: ast.Statement, exactly: bool = False) -> bool:
        """Every run of `s` makes at most one step, a costed one, and `s` is done after it.
        `exactly`: and `s` is never final before that step (a run that cannot make it is
        stuck, not done)."""
        match s:
            case ast.Block():
                if not s.body:
                    return not exactly
                return len(s.body) == 1 and self._one_step(s.body[0], exactly)
            case ast.Assign():
                return True
            case ast.CallStmt():
                symbol = self.model.target(s.call)
                return symbol is not None and symbol.kind is SymbolKind.ACTION
            case ast.Pick():
                return self._one_step(s.body, exactly)
            case ast.Choose():
                return all(self._one_step(x, exactly) for x in s.alternatives)
            case ast.If():
                if s.otherwise is None:
                    return not exactly and self._one_step(s.then)
                return self._one_step(s.then, exactly) and self._one_step(s.otherwise, exactly)
            case _:
                return False

    def _arguments(self, call: ast.Expr, symbol: Symbol) -> None:
        assert isinstance(call, ast.Call)
        for p, a in zip(symbol.params, call.args, strict=True):
            self._stored(a, p.type, {})

    def _call_statement(self, s: ast.CallStmt, in_loop: bool) -> int:
        symbol = self.model.target(s.call)
        if symbol is None or not isinstance(s.call, ast.Call):
            raise Unsafe("a call that is not resolved", s.span)
        self._arguments(s.call, symbol)
        if symbol.kind is SymbolKind.ACTION:
            self._action(symbol, s.span)
            return 0
        if symbol.kind is not SymbolKind.PROCEDURE:
            raise Unsafe(f"a call of {symbol.kind.article} {symbol.kind.value}", s.span)
        decl = symbol.decl
        body = decl.body if isinstance(decl, ast.ProcedureDecl) else None
        if body is None:
            raise Unsafe(f"procedure `{symbol.name}` has no body", s.span)
        if symbol.name in self.procedures:
            raise Unsafe(f"procedure `{symbol.name}` is recursive", s.span)
        key = (symbol.name, in_loop)
        known = self.tests.get(key)
        if known is None:
            self.procedures.append(symbol.name)
            try:
                known = self.tests[key] = self.statement(body, in_loop)
            finally:
                self.procedures.pop()
        return known

    def _action(self, symbol: Symbol, span: Span) -> None:
        if symbol.name in self.checked_actions:
            return
        decl = symbol.decl
        if not isinstance(decl, ast.ActionDecl):
            raise Unsafe(f"action `{symbol.name}` has no declaration", span)
        for section in decl.sections or ():
            if isinstance(section, ast.PreconditionSection):
                self.expr(section.condition, {})
            elif isinstance(section, ast.EffectSection):
                written: set[str] = set()
                for effect in section.effects:
                    if effect.condition is not None:
                        self.expr(effect.condition, {})
                    if not isinstance(effect.target, ast.Call):
                        raise Unsafe("an effect on a part of a fluent", effect.span)
                    fluent = self.model.target(effect.target)
                    if fluent is None or fluent.name in written:
                        raise Unsafe("two effects of one action on one fluent", effect.span)
                    written.add(fluent.name)
                    for a in effect.target.args:
                        self.expr(a, {})
                    self._stored(effect.value, fluent.type, {})
            elif isinstance(section, ast.SensesSection):
                raise Unsafe(f"action `{symbol.name}` senses", section.span)
            elif isinstance(section, ast.StartEffectSection):
                # Two writes per call, in two states: not what the step analysis assumes.
                raise Unsafe(f"action `{symbol.name}` has start effects", section.span)
        self.checked_actions.add(symbol.name)


def analyse(model: Model, solve: ast.Solve) -> BoundAnalysis:
    """The analysis of `solve` (its bound is for any horizon up to MAX_HORIZON)."""
    analysis = _Analysis(model)
    try:
        reward = analysis.expr(solve.reward, {})
        low, high = (reward.low, reward.high) if reward.bounded else (None, None)
        if low is None or high is None or not reward.whole:
            raise Unsafe("the reward is not a whole number in a known interval", solve.reward.span)
        tests = analysis.statement(solve.body, False)
        if tests > FREE_STEP_LIMIT:
            raise Unsafe(f"more than {FREE_STEP_LIMIT} tests in a row", solve.span)
    except Unsafe as e:
        reward = analysis._quietly(solve.reward)
        known = reward.bounded
        return BoundAnalysis(reward.low if known else None, reward.high if known else None, e.reason, e.span)
    goal = analysis.goal_loop(solve)
    if goal is not None:
        condition, reached, otherwise = goal
        at_goal, elsewhere = reached.high, otherwise.high
        last = max(at_goal, elsewhere)
        per_step = max(elsewhere, 0.0)

        def until_goal(h: int) -> float:
            return max(0.0, last + (h - 1) * per_step) if h > 0 else 0.0

        atoms = analysis.goal_atoms(condition)
        writes = analysis.writes_per_step()
        always = analysis.always_steps(solve.body)
        if always:
            # The loop ends only at the goal: a branch that never reaches it makes all h steps.
            def until_goal(h: int) -> float:
                return max(h * elsewhere, at_goal + (h - 1) * max(elsewhere, 0.0)) if h > 0 else 0.0

        values = (at_goal, elsewhere)
        if atoms is not None:
            placed = analysis.stacking(atoms)
            placement, why_not = (None, placed) if isinstance(placed, str) else (placed, None)
            return BoundAnalysis(
                low, high, None, None, until_goal, STEPS_TO_GOAL, atoms, writes, values, always, placement, why_not
            )
        return BoundAnalysis(low, high, None, None, until_goal, GOAL_LOOP, always_steps=always)
    per_step = max(high, 0.0)

    def bound(h: int) -> float:
        return per_step * h

    return BoundAnalysis(low, high, None, None, bound, PER_STEP)


def solve_bound(sem: Semantics, solve: ast.Solve, horizon: int) -> StateBound | None:
    """The bound the production planner may prune with for `solve` at `horizon`, or None."""
    if not 0 <= horizon <= MAX_HORIZON:
        return None
    result = analyse(sem.model, solve)
    bound = result.bound
    if bound is None or result.reward_low is None or result.reward_high is None:
        return None
    if max(abs(result.reward_low), abs(result.reward_high)) * (horizon + 1) >= _EXACT:
        return None  # sums of rewards might not be exact
    table = [bound(h) for h in range(horizon + 1)]
    if result.goal_atoms is None or result.goal_values is None:

        def by_horizon(state: State, h: int) -> float:
            return table[h]

        if result.kind == GOAL_LOOP:
            _GOAL_BOUNDS.add(by_horizon)
        return by_horizon
    distance = _distance(sem, result.goal_atoms, result.writes_per_step, result.placement)
    by_state = _steps_to_goal(distance, *result.goal_values, result.always_steps)
    _GOAL_BOUNDS.add(by_state)
    return by_state


def ends_at_goal(bound: StateBound) -> bool:
    """Is `bound` that of a goal loop (GOAL_LOOP, STEPS_TO_GOAL)? Its values are close to the
    best plan's, so a search may start from the root's bound and lower it (IDA*); a bound per
    step is far above it (docs/design.md, "Global pruning")."""
    return bound in _GOAL_BOUNDS


# A lower bound on the costed steps any run of a goal loop needs from a state to its goal
# (0: the goal holds there).
GoalDistance = Callable[[State], int]


@dataclass(frozen=True)
class DistanceAnalysis:
    """`goal_distance` of a program: the distance function, or the reason why there is none."""

    distance: GoalDistance | None
    reason: str | None  # why there is no distance (None: there is one)
    span: Span | None = None


def goal_distance(sem: Semantics, body: ast.Statement) -> DistanceAnalysis:
    """For `body` = `while (!G) S` (in blocks of one statement) where every run of S that is not
    stuck makes exactly one costed step (so the loop, and `body`, end exactly when G holds), G
    reads no variable and is a conjunction of conjuncts on distinct fluent instances named by
    constants (through functions without parameters), and no step of planning `body` can raise:
    a lower bound on the costed steps from a state to an end of `body` (docs/design.md, "Branch
    and bound"). Otherwise no distance, and the reason."""
    analysis = _Analysis(sem.model)
    loop = analysis.loop_of(body)
    try:
        analysis.statement(body, False)
    except Unsafe as e:
        return DistanceAnalysis(None, e.reason, e.span)
    if loop is None:
        return DistanceAnalysis(None, "not a `while` loop", body.span)
    condition = sem.model.effective(loop.condition)
    if not (isinstance(condition, ast.Unary) and condition.op is ast.UnaryOp.NOT):
        return DistanceAnalysis(None, "the loop's condition is not `!G`", loop.condition.span)
    goal = condition.operand
    if not analysis.always_steps(body):
        return DistanceAnalysis(None, "a run of the loop's body may end without a costed step", loop.body.span)
    atoms = analysis.goal_atoms(goal) if analysis._same_goal(goal, goal) else None
    if atoms is None:
        return DistanceAnalysis(None, "the goal is not a conjunction on distinct fluent instances", goal.span)
    placed = analysis.stacking(atoms)
    placement = None if isinstance(placed, str) else placed
    return DistanceAnalysis(_distance(sem, atoms, analysis.writes_per_step(), placement), None)


def _distance(
    sem: Semantics, atoms: tuple[ast.Expr, ...], writes: int, placement: tuple[Symbol, dict[Sym, Sym]] | None
) -> GoalDistance:
    """The not-well-placed distance where it holds, else the misplaced one; remembered per
    state."""
    count = _not_well_placed(sem, *placement) if placement is not None else _misplaced(sem, atoms)
    needed: dict[State, int] = {}

    def distance(state: State) -> int:
        n = needed.get(state)
        if n is None:
            n = needed[state] = -(-count(state) // writes)
        return n

    return distance


def _not_well_placed(sem: Semantics, fluent: Symbol, goal: dict[Sym, Sym]) -> Callable[[State], int]:
    """The writes of F's instances any run needs to reach the goal {b: v} of F (the analysis
    proved that F(p) is written only while nothing is on p): an object must move if its goal
    instance is false, or if it is on an object that must move (which cannot move before it
    leaves); one that must move costs 2 if its goal instance holds now (it leaves and comes
    back), else 1 (docs/design.md, "Branch and bound")."""
    program = sem.program
    objects = _values(sem.model, fluent.params[0].type)
    assert objects is not None
    slots = [(x, program.slot(fluent.name, (cast(Value, x),))) for x in objects]
    initial = program.initial
    goals = list(goal.items())

    def count(state: State) -> int:
        on = {x: state.get(s, initial) for x, s in slots}
        above: dict[object, list[object]] = {}
        for x, y in on.items():
            if y is not None:
                above.setdefault(y, []).append(x)
        moving: list[object] = [b for b, v in goals if on.get(b) != v]
        total = len(moving)
        must: set[object] = set(moving)
        none: list[object] = []
        while moving:
            for x in above.get(moving.pop(), none):
                if x not in must:
                    must.add(x)
                    moving.append(x)
                    total += 2 if x in goal else 1  # x in goal here: its goal instance holds now
        return total

    return count


def _misplaced(sem: Semantics, atoms: tuple[ast.Expr, ...]) -> Callable[[State], int]:
    """How many of the conjuncts `atoms` are not true in a state: generated code
    (gpp.runtime.codegen) where the generator writes them out."""
    count = _generated_count(sem, atoms)
    if count is not None:
        return count
    evaluators = [sem.program.expr(atom) for atom in atoms]
    ctx = sem.ctx

    def evaluated(state: State) -> int:
        env = Env(state, {}, ctx)
        return sum(1 for evaluate in evaluators if evaluate(env) is not True)

    return evaluated


def _generated_count(sem: Semantics, atoms: tuple[ast.Expr, ...]) -> Callable[[State], int] | None:
    """`def misplaced(state)`: how many of `atoms` are not true in the state; None when the
    generator does not write one of them out."""
    unit = Unit("misplaced", "state")
    generate = ExprGen(sem.program, unit)
    try:
        terms = [f"(0 if {generate.text(generate.expr(atom, {}))} is True else 1)" for atom in atoms]
    except Unsupported:
        return None
    unit.emit(0, "return " + (" + ".join(terms) if terms else "0"))
    built: Callable[[State], int] = unit.build()
    return built


def _steps_to_goal(distance: GoalDistance, at_goal: float, elsewhere: float, always: bool) -> StateBound:
    """U(s, h) of the goal loop with the steps the goal still needs from s (docs/design.md);
    `always`: the loop ends only at the goal."""

    def bound(state: State, h: int) -> float:
        if h <= 0:
            return 0.0
        n = distance(state)
        if n == 0:
            return 0.0  # the goal holds: the loop is over, no further step
        # A branch that does not reach the goal: at most h steps (exactly h if `always`).
        never = h * elsewhere if always or elsewhere > 0 else 0.0
        if n > h:
            return never
        reach = (h - 1 if elsewhere > 0 else n - 1) * elsewhere + at_goal
        return max(never, reach)

    return bound
