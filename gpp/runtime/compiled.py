"""A checked program prepared for execution: fluent slots and initial values, actions,
functions and procedures, and expressions compiled to closures.

Expressions are compiled once into Python closures (`Evaluator = Callable[[Env], Value]`):
the planner evaluates the same conditions millions of times, and a closure does no dispatch
on node types at run time. Evaluation follows SEMANTICS §3; every runtime error carries the
span of the expression that caused it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol, cast

from gpp.base.numbers import MAX_WHOLE, RANGE_TEXT
from gpp.base.source import Span
from gpp.codes import R0001, R0002, R0003, R0004, R0008, R0099
from gpp.model.model import Model
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import BOOL, SYMBOL, CompoundType, DomainType, ListType, Sym, Type
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.state import Activities, GroundAction, State
from gpp.runtime.values import CompoundValue, Value, same, show, to_string
from gpp.syntax import ast
from gpp.syntax.walk import walk

Op = ast.BinaryOp


class Context(Protocol):
    """What evaluation needs from outside the program: exog functions and the clock."""

    def exog_function(self, name: str, args: dict[str, Value], return_type: Type, span: Span) -> Value: ...

    def now(self) -> float: ...

    def wake_at(self, t: float) -> None:
        """A comparison with the clock that was just evaluated changes its truth value at time
        `t` (in the future): the executor wakes a blocked program then (SEMANTICS, "Time")."""


class Env:
    """Everything an expression is evaluated in."""

    __slots__ = ("ctx", "state", "vars")

    def __init__(self, state: State, variables: dict[int, Value], ctx: Context) -> None:
        self.state = state
        self.vars = variables
        self.ctx = ctx

    def bind(self, variables: dict[int, Value]) -> Env:
        return Env(self.state, variables, self.ctx)


Evaluator = Callable[[Env], Value]


@dataclass(frozen=True, slots=True)
class PathStep:
    """One `.field` or `[index]` step of an assignment target below a fluent."""

    field: str | None
    index: Evaluator | None
    span: Span


@dataclass(frozen=True, slots=True)
class Target:
    """A compiled assignment target: a fluent instance and a path inside its value."""

    fluent: str
    args: tuple[Evaluator, ...]
    path: tuple[PathStep, ...]
    value_type: Type
    span: Span


@dataclass(frozen=True, slots=True)
class Effect:
    condition: Evaluator | None
    target: Target
    value: Evaluator
    span: Span
    value_span: Span | None = None
    # The target is a whole fluent instance (no field or element) whose arguments read only
    # variables: for a ground action, its slot is known in advance.
    static_target: bool = False


@dataclass(frozen=True, slots=True)
class PickGuard:
    """Precondition conjuncts decidable once an outer `pick` variable is bound (see
    CompiledProgram.pick_guard)."""

    # (action parameter id, the argument's evaluator, the parameter's type) for the
    # parameters the conjuncts read.
    args: tuple[tuple[int, Evaluator, Type | None], ...]
    conjuncts: tuple[Evaluator, ...]

    # The arguments read no fluent, function or clock: the bindings depend on the variables only.
    static: bool = False

    def rejects(self, state: State, variables: dict[int, Value], ctx: Context) -> bool:
        """True when a conjunct is false for these bindings, so no inner value can make the
        action possible. Anything unusual (an error, a value outside its parameter's domain)
        is left to the normal evaluation, which reports it as it always does."""
        try:
            bindings = self.bind(Env(state, variables, ctx))
            return bindings is not None and self.rejects_bound(state, bindings, ctx)
        except GppRuntimeError:
            return False

    def bind(self, env: Env) -> dict[int, Value] | None:
        """The action parameters the conjuncts read, bound to their arguments' values; None
        when a value is outside its parameter's domain."""
        bindings: dict[int, Value] = {}
        for param, argument, param_type in self.args:
            value = argument(env)
            if isinstance(param_type, DomainType) and not _member(value, param_type):
                return None
            bindings[param] = value
        return bindings

    def rejects_bound(self, state: State, bindings: dict[int, Value], ctx: Context) -> bool:
        """Is a conjunct false in `state` for these parameter bindings (errors are raised)?"""
        inner = Env(state, bindings, ctx)
        return not all(check(inner) is True for check in self.conjuncts)


@dataclass(frozen=True, slots=True)
class ActionInfo:
    symbol: Symbol
    exogenous: bool
    param_ids: tuple[int, ...]
    param_names: tuple[str, ...]
    # The conjuncts of the precondition (top-level `&` split), to say which one is false.
    precondition: tuple[tuple[Evaluator, ast.Expr], ...]
    # `effect:`, applied when the activity ends `final`.
    effects: tuple[Effect, ...]
    # `start_effect:`, applied when the activity starts.
    start_effects: tuple[Effect, ...]
    senses: Effect | None
    mapped_name: str
    mapped_args: tuple[tuple[str, Evaluator], ...]
    # Mapped argument name -> the parameter it is (`""` when it is another expression): how an
    # exogenous event's fields feed its parameters.
    mapped_params: tuple[tuple[str, str], ...]
    # `duration: [min, max]` in seconds, if given.
    duration: tuple[float, float] | None
    decl: ast.ActionDecl | None


@dataclass
class FluentInfo:
    symbol: Symbol
    # `initially:` entries, later ones override earlier ones: (pattern, value); None in a
    # pattern is a wildcard (the parameter's own name).
    initially: list[tuple[tuple[Value | _Wildcard, ...], Value]] = field(default_factory=list)


class _Wildcard:
    def __repr__(self) -> str:
        return "*"


WILDCARD = _Wildcard()


class CompiledProgram:
    def __init__(self, model: Model) -> None:
        self.model = model
        self._slots: dict[tuple[str, tuple[Value, ...]], int] = {}
        self.instances: list[tuple[str, tuple[Value, ...]]] = []
        self._initials: list[Value] = []
        self._compiled: dict[int, Evaluator] = {}
        self._functions: dict[str, tuple[tuple[int, ...], Evaluator | None]] = {}
        self._actions: dict[str, ActionInfo] = {}
        self.fluents: dict[str, FluentInfo] = {}
        self._pick_guards: dict[int, PickGuard | None] = {}
        self._empty_state = State()
        for symbol in model.globals.values():
            if symbol.kind is SymbolKind.FLUENT:
                self.fluents[symbol.name] = self._fluent_info(symbol)

    # ---------------------------------------------------------------- fluent slots

    def slot(self, fluent: str, args: tuple[Value, ...]) -> int:
        key = (fluent, args)
        s = self._slots.get(key)
        if s is None:
            s = len(self.instances)
            self._slots[key] = s
            self.instances.append(key)
            self._initials.append(self._initial_value(fluent, args))
        return s

    def initial(self, slot: int) -> Value:
        return self._initials[slot]

    def instance_text(self, slot: int) -> str:
        name, args = self.instances[slot]
        return f"{name}({','.join(show(a) for a in args)})"

    def read(self, state: State, fluent: str, args: tuple[Value, ...]) -> Value:
        return state.get(self.slot(fluent, args), self.initial)

    def _fluent_info(self, symbol: Symbol) -> FluentInfo:
        info = FluentInfo(symbol)
        decl = symbol.decl
        if not isinstance(decl, ast.FluentDecl) or decl.initially is None:
            return info
        env = Env(self._empty_state, {}, _NO_CONTEXT)
        names = [p.name for p in symbol.params]
        for init in decl.initially:
            pattern: list[Value | _Wildcard] = []
            for i, arg in enumerate(init.args):
                if isinstance(arg, ast.Name) and i < len(names) and arg.name == names[i]:
                    pattern.append(WILDCARD)
                else:
                    pattern.append(self.expr(arg)(env))
            info.initially.append((tuple(pattern), self.expr(init.value)(env)))
        return info

    def _initial_value(self, fluent: str, args: tuple[Value, ...]) -> Value:
        info = self.fluents.get(fluent)
        if info is None:
            return None
        for pattern, value in reversed(info.initially):
            if all(p is WILDCARD or same(p, a) for p, a in zip(pattern, args, strict=False)):  # type: ignore[arg-type]
                return value
        return None

    # ---------------------------------------------------------------- declarations

    def action(self, name: str) -> ActionInfo:
        info = self._actions.get(name)
        if info is None:
            info = self._action_info(self.model.globals[name])
            self._actions[name] = info
        return info

    def _action_info(self, symbol: Symbol) -> ActionInfo:
        decl = symbol.decl if isinstance(symbol.decl, ast.ActionDecl) else None
        precondition: list[tuple[Evaluator, ast.Expr]] = []
        effects: list[Effect] = []
        start_effects: list[Effect] = []
        senses: Effect | None = None
        mapped_name = symbol.name
        mapped: list[tuple[str, Evaluator]] | None = None
        mapped_params: list[tuple[str, str]] = [(p.name, p.name) for p in symbol.params]
        duration: tuple[float, float] | None = None
        for section in (decl.sections or ()) if decl else ():
            if isinstance(section, ast.PreconditionSection):
                for conjunct in _conjuncts(self.model.effective(section.condition)):
                    precondition.append((self.expr(conjunct), conjunct))
            elif isinstance(section, ast.EffectSection):
                effects.extend(self._effect(e) for e in section.effects)
            elif isinstance(section, ast.StartEffectSection):
                start_effects.extend(self._effect(e) for e in section.effects)
            elif isinstance(section, ast.SensesSection):
                senses = Effect(
                    None, self.target(section.target), self.expr(section.value), section.span, section.value.span
                )
            elif isinstance(section, ast.MappingSection):
                mapped_name = section.mapping.name.value
                mapped = [(a.name.name, self.expr(a.value)) for a in section.mapping.args]
                mapped_params = [
                    (a.name.name, a.value.name if isinstance(a.value, ast.Name) else "") for a in section.mapping.args
                ]
            elif isinstance(section, ast.DurationSection):
                low, high = section.low, section.high
                if isinstance(low, ast.NumberLit) and isinstance(high, ast.NumberLit):
                    duration = (float(low.value), float(high.value))
        if mapped is None:
            mapped = [(p.name, _variable(id(p))) for p in symbol.params]
        return ActionInfo(
            symbol=symbol,
            exogenous=symbol.kind is SymbolKind.EXOG_ACTION,
            param_ids=tuple(id(p) for p in symbol.params),
            param_names=tuple(p.name for p in symbol.params),
            precondition=tuple(precondition),
            effects=tuple(effects),
            start_effects=tuple(start_effects),
            senses=senses,
            mapped_name=mapped_name,
            mapped_args=tuple(mapped),
            mapped_params=tuple(mapped_params),
            duration=duration,
            decl=decl,
        )

    def _effect(self, e: ast.Effect) -> Effect:
        condition = self.expr(e.condition) if e.condition is not None else None
        target, value = self.target(e.target), self.expr(e.value)
        static = (
            not target.path
            and isinstance(e.target, ast.Call)
            and all(reads_only_variables(self.model, a) for a in e.target.args)
        )
        return Effect(condition, target, value, e.span, e.value.span, static)

    def procedure(self, name: str) -> tuple[tuple[int, ...], ast.Statement | None]:
        symbol = self.model.globals[name]
        decl = symbol.decl
        body = decl.body if isinstance(decl, ast.ProcedureDecl | ast.MainBlock) else None
        return tuple(id(p) for p in symbol.params), body

    def function(self, name: str) -> tuple[tuple[int, ...], Evaluator | None]:
        entry = self._functions.get(name)
        if entry is None or entry[1] is None:
            symbol = self.model.globals[name]
            params = tuple(id(p) for p in symbol.params)
            # Registered before compiling the body, so that recursion finds it.
            self._functions[name] = (params, None)
            decl = symbol.decl
            body = self.expr(decl.body) if isinstance(decl, ast.FunctionDecl) and decl.body is not None else None
            entry = (params, body)
            self._functions[name] = entry
        return entry

    # ---------------------------------------------------------------- expressions

    def expr(self, e: ast.Expr) -> Evaluator:
        key = id(e)
        compiled = self._compiled.get(key)
        if compiled is None:
            compiled = self._compile(self.model.effective(e))
            self._compiled[key] = compiled
        return compiled

    def _compile(self, e: ast.Expr) -> Evaluator:
        if isinstance(e, ast.NumberLit | ast.StringLit | ast.BoolLit):
            value = e.value
            return lambda env: value
        if isinstance(e, ast.NullLit):
            return lambda env: None
        if isinstance(e, ast.Name):
            target = self.model.target(e)
            if target is not None and target.kind is SymbolKind.SYMBOL:
                sym = Sym(e.name)
                return lambda env: sym
            if target is None:
                raise _internal(e.span, f"unresolved name `{e.name}`")
            return _variable(id(target))
        if isinstance(e, ast.Call):
            return self._call(e)
        if isinstance(e, ast.Unary):
            operand = self.expr(e.operand)
            if e.op is ast.UnaryOp.NOT:
                return lambda env: not _truth(operand(env))
            span = e.span

            def negate(env: Env) -> Value:
                v = operand(env)
                if v is None:
                    raise GppRuntimeError(R0002.applied_to_null("-"), span)
                return -v  # type: ignore[operator]

            return negate
        if isinstance(e, ast.Binary):
            return self._binary(e)
        if isinstance(e, ast.Quantified):
            return self._quantifier(e)
        if isinstance(e, ast.Conditional):
            cond, then, otherwise = self.expr(e.condition), self.expr(e.then), self.expr(e.otherwise)
            return lambda env: then(env) if _truth(cond(env)) else otherwise(env)
        if isinstance(e, ast.FieldAccess):
            subject = self.expr(e.subject)
            name, span = e.field.name, e.span

            def get_field(env: Env) -> Value:
                v = subject(env)
                if v is None:
                    raise GppRuntimeError(R0002.field_of_null(name), span)
                assert isinstance(v, CompoundValue)
                return v.get(name)

            return get_field
        if isinstance(e, ast.Index):
            subject, index, span = self.expr(e.subject), self.expr(e.index), e.span
            return lambda env: _element(subject(env), index(env), span)
        if isinstance(e, ast.CompoundLit):
            ctype = self.model.type_of(e)
            assert isinstance(ctype, CompoundType)
            given = {f.name.name: self.expr(f.value) for f in e.fields}
            order = tuple((name, given[name]) for name in ctype.fields if name in given)
            type_name = ctype.name
            return lambda env: CompoundValue(type_name, tuple((n, f(env)) for n, f in order))
        if isinstance(e, ast.ListLit):
            elements = tuple(self.expr(x) for x in e.elements)
            return lambda env: tuple(x(env) for x in elements)
        if isinstance(e, ast.BuiltinCall):
            arg, span = self.expr(e.arg), e.span
            if e.function is ast.Builtin.LENGTH:

                def length(env: Env) -> Value:
                    v = arg(env)
                    if v is None:
                        raise GppRuntimeError(R0002.length_of_null(), span)
                    assert isinstance(v, tuple)
                    return len(v)

                return length
            return lambda env: to_string(arg(env))
        raise _internal(e.span, f"cannot evaluate {type(e).__name__}")

    def _call(self, e: ast.Call) -> Evaluator:
        symbol = self.model.target(e)
        if symbol is None:
            raise _internal(e.span, f"unresolved call `{e.name.name}`")
        args = tuple(self.expr(a) for a in e.args)
        name = symbol.name
        if symbol.kind is SymbolKind.FLUENT:
            if symbol.predefined and name == "context_time":
                return lambda env: env.ctx.now()
            return self._fluent_read(name, args)
        if symbol.kind is SymbolKind.FUNCTION:
            program = self

            compiled: list[tuple[tuple[int, ...], Evaluator]] = []  # the body, once it is compiled

            def function(env: Env) -> Value:
                if compiled:
                    params, body = compiled[0]
                else:
                    params, maybe = program.function(name)
                    if maybe is None:
                        raise GppRuntimeError(R0008.function(name), e.span)
                    body = maybe
                    compiled.append((params, body))
                if not args:
                    return body(env.bind({}))
                values = [a(env) for a in args]
                return body(env.bind(dict(zip(params, values, strict=True))))

            return function
        if symbol.kind is SymbolKind.EXOG_FUNCTION:
            names = tuple(p.name for p in symbol.params)
            rtype = symbol.type
            assert rtype is not None
            span = e.span

            def exog(env: Env) -> Value:
                values = {n: a(env) for n, a in zip(names, args, strict=True)}
                return env.ctx.exog_function(name, values, rtype, span)

            return exog
        raise _internal(e.span, f"`{name}` cannot be evaluated")

    def _fluent_read(self, name: str, args: tuple[Evaluator, ...]) -> Evaluator:
        """Reading a fluent instance: its slot is looked up by the argument values in a table
        of the fluent's own (one lookup, no key with the fluent's name in it)."""
        slots: dict[tuple[Value, ...], int] = {}
        slot_of, initial = self.slot, self.initial

        def slot(key: tuple[Value, ...]) -> int:
            s = slots[key] = slot_of(name, key)
            return s

        if not args:

            def fluent0(env: Env) -> Value:
                s = slots.get(())
                return env.state.get(slot(()) if s is None else s, initial)

            return fluent0
        if len(args) == 1:
            (arg,) = args

            def fluent1(env: Env) -> Value:
                key = (arg(env),)
                s = slots.get(key)
                return env.state.get(slot(key) if s is None else s, initial)

            return fluent1

        def fluent(env: Env) -> Value:
            key = tuple([a(env) for a in args])
            s = slots.get(key)
            return env.state.get(slot(key) if s is None else s, initial)

        return fluent

    def _binary(self, e: ast.Binary) -> Evaluator:
        op, span = e.op, e.span
        left, right = self.expr(e.left), self.expr(e.right)
        if op is Op.AND:
            return lambda env: _truth(left(env)) and _truth(right(env))
        if op is Op.OR:
            return lambda env: _truth(left(env)) or _truth(right(env))
        if op is Op.IMPLIES:
            return lambda env: (not _truth(left(env))) or _truth(right(env))
        if op is Op.EQ:
            return self._compare(e, left, right, same)
        if op is Op.NE:
            return self._compare(e, left, right, lambda a, b: not same(a, b))
        if op in (Op.LT, Op.LE, Op.GT, Op.GE):
            compare = _ORDER[op]

            def order(a: Value, b: Value) -> Value:
                if a is None or b is None:
                    raise GppRuntimeError(R0002.compares_null(op.value), span)
                if isinstance(a, Sym):
                    return compare(a.name, b.name)  # type: ignore[union-attr]
                return compare(a, b)

            return self._compare(e, left, right, order)
        arithmetic = _ARITHMETIC[op]

        def calculate(env: Env) -> Value:
            a, b = left(env), right(env)
            if a is None or b is None:
                raise GppRuntimeError(R0002.applied_to_null(op.value), span)
            try:
                result = arithmetic(a, b, span)
            except OverflowError:
                raise _too_large(op, span) from None
            if isinstance(result, float):
                if result - result != 0.0:  # infinite or NaN
                    raise _too_large(op, span)
            elif isinstance(result, int) and not -MAX_WHOLE <= result <= MAX_WHOLE:
                raise _too_large(op, span)
            return result

        return calculate

    # ---------------------------------------------------------------- comparisons with the clock

    def _compare(
        self, e: ast.Binary, left: Evaluator, right: Evaluator, test: Callable[[Value, Value], Value]
    ) -> Evaluator:
        """A comparison. When it compares the clock with a value (`context_time() >= t0 + 5`), it
        also tells the context when its truth value changes next, so that a program blocked on it
        wakes up then. For that, one side must be `context_time()` plus or minus amounts that do
        not read the clock, and the other side must not read the clock; any other comparison is
        just evaluated."""
        left_clock, right_clock = self._reads_clock(e.left), self._reads_clock(e.right)
        sign = self._clock_sign(e.left if left_clock else e.right) if left_clock != right_clock else None
        if sign is None:
            return lambda env: test(left(env), right(env))

        def clocked(env: Env) -> Value:
            a, b = left(env), right(env)
            result = test(a, b)
            clock, other = (a, b) if left_clock else (b, a)
            if _is_number(clock) and _is_number(other):
                # clock = sign * now + shift, so it equals other at now + sign * (other - clock);
                # a strict comparison changes just after that moment.
                now = env.ctx.now()
                try:
                    crossing = now + float(sign * (other - clock))  # type: ignore[operator]
                except OverflowError:  # beyond any clock
                    return result
                for t in (crossing, math.nextafter(crossing, math.inf)):
                    if now < t < math.inf:
                        env.ctx.wake_at(t)
            return result

        return clocked

    def _reads_clock(self, e: ast.Expr) -> bool:
        return any(isinstance(n, ast.Call) and self._is_clock(n) for n in walk(e))

    def _is_clock(self, e: ast.Expr) -> bool:
        if not isinstance(e, ast.Call):
            return False
        symbol = self.model.target(e)
        return symbol is not None and symbol.predefined and symbol.name == "context_time"

    def _clock_sign(self, e: ast.Expr) -> int | None:
        """1 or -1 when `e` is `sign * context_time()` plus or minus amounts that do not read the
        clock, else None."""
        if self._is_clock(e):
            return 1
        if not isinstance(e, ast.Binary) or e.op not in (Op.ADD, Op.SUB):
            return None
        left_clock = self._reads_clock(e.left)
        if left_clock == self._reads_clock(e.right):
            return None
        sign = self._clock_sign(e.left if left_clock else e.right)
        if sign is None:
            return None
        # `other - (clock ...)` turns the clock's sign; `+` and `(clock ...) - other` keep it.
        return -sign if e.op is Op.SUB and not left_clock else sign

    def _quantifier(self, e: ast.Quantified) -> Evaluator:
        variable = self.model.target(e.var)
        assert variable is not None
        values = domain_values(variable.type, self.model)
        var_id = id(variable)
        body = self.expr(e.body)
        exists = e.quantifier is ast.Quantifier.EXISTS
        comparison = self._quantified_comparison(e, var_id, values, exists)

        def quantify(env: Env) -> Value:
            bindings = dict(env.vars)
            inner = env.bind(bindings)
            for v in values:
                bindings[var_id] = v
                if _truth(body(inner)) == exists:
                    return exists
            return not exists

        evaluate: Evaluator = quantify if comparison is None else comparison
        free = self._state_function_of(e)
        if free is None:
            return evaluate
        # The body reads only fluents and the variables in `free`: in one state, its value is a
        # function of their values. The planner asks the same quantifier for the same values
        # many times in one state (a precondition for every binding of a `pick`), so the values
        # of the last state are remembered.
        ids, typed = free
        results: dict[object, Value] = {}
        last: list[State] = [self._empty_state]

        def remembered(env: Env) -> Value:
            if env.state is not last[0]:
                results.clear()
                last[0] = env.state
            variables = env.vars
            # 1, 1.0 and true are one dict key; with a type in the key they stay apart.
            key = tuple([(type(variables[i]), variables[i]) for i in ids] if typed else [variables[i] for i in ids])
            v = results.get(key, _UNKNOWN)
            if v is _UNKNOWN:
                v = results[key] = evaluate(env)
            return v

        if len(ids) == 1 and not typed:
            (only,) = ids

            def remembered_by_one_symbol(env: Env) -> Value:
                # The same, keyed by the value of the one variable (a symbol or null).
                if env.state is not last[0]:
                    results.clear()
                    last[0] = env.state
                key = env.vars[only]
                v = results.get(key, _UNKNOWN)
                if v is _UNKNOWN:
                    v = results[key] = evaluate(env)
                return v

            return remembered_by_one_symbol
        return remembered

    def _quantified_comparison(
        self, e: ast.Quantified, var_id: int, values: tuple[Value, ...], exists: bool
    ) -> Evaluator | None:
        """`exists/forall (x) f(x) == v` (or `!=`, either side), with `f` a fluent and `v` a
        variable or literal: the quantifier as a loop over the slots of f(value) for the
        domain's values, compared with v (evaluated once: it reads no fluent). The same reads
        and comparisons in the same order as the quantifier over the compiled body, without
        evaluating the body for every value. None for any other body."""
        body = e.body
        model = self.model
        if model.effective(body) is not body or not isinstance(body, ast.Binary) or body.op not in (Op.EQ, Op.NE):
            return None
        sides = (body.left, body.right)
        if any(model.effective(side) is not side for side in sides):
            return None
        read = next((side for side in sides if self._reads_variable(side, var_id)), None)
        other = body.right if read is body.left else body.left
        if (
            read is None
            or not isinstance(read, ast.Call)
            or self._is_clock(read)
            or len(read.args) != 1
            or not isinstance(read.args[0], ast.Name)
            or model.effective(read.args[0]) is not read.args[0]
            or not isinstance(other, ast.Name | ast.NumberLit | ast.StringLit | ast.BoolLit | ast.NullLit)
            or self._reads_variable(other, var_id)
        ):
            return None
        fluent = model.target(read)
        if fluent is None or fluent.kind is not SymbolKind.FLUENT:
            return None
        name, value_of, negate = fluent.name, self.expr(other), body.op is Op.NE
        slots: list[int | None] = [None] * len(values)
        slot_of, initial = self.slot, self.initial

        def quantified_comparison(env: Env) -> Value:
            target = value_of(env)
            held = env.state.held()
            symbol = target.name if type(target) is Sym else None
            for i, v in enumerate(values):
                s = slots[i]
                if s is None:
                    s = slots[i] = slot_of(name, (v,))
                current = held.get(s, _UNKNOWN)
                if current is _UNKNOWN:
                    current = initial(s)
                # same(current, target); for a symbol: a symbol of the same name.
                if symbol is not None:
                    equal = type(current) is Sym and current.name == symbol
                else:
                    equal = same(current, target)
                if (equal is not negate) is exists:
                    return exists
            return not exists

        return quantified_comparison

    def _reads_variable(self, e: ast.Expr, var_id: int) -> bool:
        return any(isinstance(n, ast.Name) and id(self.model.target(n)) == var_id for n in walk(e))

    def reads_only_fluents(self, e: ast.Expr) -> bool:
        """In one state, `e` has one value for given values of its variables: it reads no
        function, exogenous function or clock (see `_state_function_of`)."""
        return self._state_function_of(e) is not None

    def _state_function_of(self, e: ast.Expr) -> tuple[tuple[int, ...], bool] | None:
        """The variables `e` reads besides those it binds itself (and whether their values need
        their type in a key: all but symbols do), if `e` reads nothing of the world but fluents
        (no function, exogenous function or clock, whose values are not a function of the state
        alone as far as this check can tell) and no part of it is rewritten by the checker;
        else None."""
        bound: set[int] = set()
        names: list[Symbol] = []
        for node in walk(e):
            if self.model.effective(node) is not node:  # type: ignore[arg-type]
                return None
            if isinstance(node, ast.Call):
                target = self.model.target(node)
                if target is None or target.kind is not SymbolKind.FLUENT or self._is_clock(node):
                    return None
            elif isinstance(node, ast.Quantified):
                variable = self.model.target(node.var)
                if variable is None:
                    return None
                bound.add(id(variable))
            elif isinstance(node, ast.Name):
                target = self.model.target(node)
                if target is None:
                    return None
                if target.kind in (SymbolKind.VARIABLE, SymbolKind.PARAMETER):
                    names.append(target)
        free: dict[int, Symbol] = {id(s): s for s in names if id(s) not in bound}
        typed = not all(isinstance(s.type, DomainType) and _symbols_only(s.type) for s in free.values())
        return tuple(free), typed

    # ---------------------------------------------------------------- pruning `pick`

    def pick_guard(self, pick: ast.Pick) -> PickGuard | None:
        """For `pick (x) pick (y) ... a(args);`: the precondition conjuncts of `a` that read no
        variable of the inner picks, so that a value of `x` they reject is skipped before any
        inner value is tried. None when there is nothing to decide early."""
        key = id(pick)
        if key not in self._pick_guards:
            self._pick_guards[key] = self._make_pick_guard(pick)
        return self._pick_guards[key]

    def _make_pick_guard(self, pick: ast.Pick) -> PickGuard | None:
        from gpp.syntax.walk import walk

        inner: set[int] = set()
        body = pick.body
        while isinstance(body, ast.Pick):
            variable = self.model.target(body.var)
            if variable is None:
                return None
            inner.add(id(variable))
            body = body.body
        if not inner or not isinstance(body, ast.CallStmt) or not isinstance(body.call, ast.Call):
            return None
        symbol = self.model.target(body.call)
        if symbol is None or symbol.kind is not SymbolKind.ACTION:
            return None
        action = self.action(symbol.name)

        def variables(e: ast.Expr, kinds: tuple[SymbolKind, ...]) -> set[int]:
            found: set[int] = set()
            for node in walk(e):
                if isinstance(node, ast.Name):
                    target = self.model.target(node)
                    if target is not None and target.kind in kinds:
                        found.add(id(target))
            return found

        late = {
            id(p)
            for p, arg in zip(symbol.params, body.call.args, strict=True)
            if variables(arg, (SymbolKind.VARIABLE, SymbolKind.PARAMETER)) & inner
        }
        # A conjunction is false when any conjunct is, whatever the order; only which error a
        # faulty conjunct raises could depend on it, and a conjunct that raises here is left to
        # the normal evaluation (see PickGuard.rejects).
        conjuncts: list[Evaluator] = []
        read: set[int] = set()
        for check, expr in action.precondition:
            reads = variables(expr, (SymbolKind.PARAMETER,))
            if not reads & late:
                conjuncts.append(check)
                read |= reads
        if not conjuncts:
            return None
        args = tuple(
            (id(p), self.expr(arg), p.type)
            for p, arg in zip(symbol.params, body.call.args, strict=True)
            if id(p) in read
        )
        static = all(reads_only_variables(self.model, arg) for arg in body.call.args)
        return PickGuard(args, tuple(conjuncts), static)

    # ---------------------------------------------------------------- assignment targets

    def target(self, e: ast.Expr) -> Target:
        path: list[PathStep] = []
        node = e
        while isinstance(node, ast.FieldAccess | ast.Index):
            if isinstance(node, ast.FieldAccess):
                path.append(PathStep(node.field.name, None, node.span))
            else:
                path.append(PathStep(None, self.expr(node.index), node.span))
            node = node.subject
        assert isinstance(node, ast.Call)
        symbol = self.model.target(node)
        assert symbol is not None
        return Target(
            fluent=symbol.name,
            args=tuple(self.expr(a) for a in node.args),
            path=tuple(reversed(path)),
            value_type=self.model.type_of(e),
            span=e.span,
        )

    def assignment(
        self, target: Target, value: Value, env: Env, pending: dict[int, Value], value_span: Span | None = None
    ) -> int:
        """Compute the new value of the target's fluent instance after `target = value`
        (a functional update along the path) and record it in `pending`; returns the slot.
        `pending` holds the values already assigned by the same step (effects of one action).
        A value outside the target's domain is an error at `value_span` (else the target's)."""
        check_domain(value, target.value_type, value_span if value_span is not None else target.span)
        slot = self.slot(target.fluent, tuple(a(env) for a in target.args))
        if not target.path:
            pending[slot] = value
            return slot
        current = pending[slot] if slot in pending else env.state.get(slot, self.initial)
        pending[slot] = _update_path(current, [(p, p.index(env) if p.index else None) for p in target.path], value)
        return slot


def _update_path(current: Value, path: Sequence[tuple[PathStep, Value]], value: Value) -> Value:
    (step, index), rest = path[0], path[1:]
    if current is None:
        raise GppRuntimeError(R0002.assignment_into_null(), step.span)
    if step.field is not None:
        assert isinstance(current, CompoundValue)
        inner = current.get(step.field)
        return current.replace(step.field, _update_path(inner, rest, value) if rest else value)
    assert isinstance(current, tuple)
    i = _index(index, len(current), step.span)
    new = _update_path(current[i], rest, value) if rest else value
    return (*current[:i], new, *current[i + 1 :])


def check_domain(value: Value, t: Type, span: Span) -> None:
    """Domain membership of a computed value, checked when it is stored (SEMANTICS §2.4)."""
    if isinstance(t, DomainType) and value is not None and not _member(value, t):
        shown = ", ".join(show(v) for v in t.values[:10])
        raise GppRuntimeError(R0004.not_in_domain(show(value), t.name), span, (f"`{t.name}` = {{{shown}}}",))
    if isinstance(t, ListType) and isinstance(value, tuple) and isinstance(t.element, DomainType):
        for v in value:
            check_domain(v, t.element, span)


# For each symbol domain met: the domain and its members as a set (keyed by the domain's id,
# with the domain kept, so that an id reused by a later domain is never mistaken for it).
# Emptied when it holds _SYMBOL_SETS_SIZE domains, so that programs checked and run one after
# the other in one process are not all kept alive by it.
_SYMBOL_SETS: dict[int, tuple[DomainType, frozenset[Value]]] = {}
_SYMBOL_SETS_SIZE = 1024


def _member(value: Value, t: DomainType) -> bool:
    """`value` is in domain `t` (golog++ `==` with a member). A domain of symbols is a set: a
    symbol equals only a symbol of the same name, so set membership is exactly that."""
    known = _SYMBOL_SETS.get(id(t))
    if known is None or known[0] is not t:
        members = frozenset(t.values) if t.defined and all(type(v) is Sym for v in t.values) else None
        if members is None:
            return any(same(value, v) for v in t.values)
        if len(_SYMBOL_SETS) >= _SYMBOL_SETS_SIZE:
            _SYMBOL_SETS.clear()
        known = _SYMBOL_SETS[id(t)] = (t, members)
    return type(value) is Sym and value in known[1]


def reads_only_variables(model: Model, e: ast.Expr) -> bool:
    """`e` reads nothing of the world (no fluent, function, exogenous function or clock), and
    the checker rewrote no part of it: its value depends on the variables alone."""
    effective = model.effective
    return all(not isinstance(n, ast.Call) and effective(n) is n for n in walk(effective(e)))  # type: ignore[arg-type]


def _symbols_only(t: DomainType) -> bool:
    return t.defined and all(type(v) is Sym for v in t.values)


# Not yet computed (never a value).
_UNKNOWN: Value = cast(Value, object())


def domain_values(t: Type | None, model: Model) -> tuple[Value, ...]:
    """The values a quantifier or `pick` over type `t` tries, in order."""
    if t is BOOL:
        return (False, True)
    if t is SYMBOL:
        return model.declared_symbols()
    if isinstance(t, DomainType):
        return t.values
    raise AssertionError(f"not a finite type: {t}")


def ground(action: ActionInfo, args: Sequence[Value]) -> GroundAction:
    return GroundAction(action.symbol.name, tuple(args))


def _conjuncts(e: ast.Expr) -> list[ast.Expr]:
    if isinstance(e, ast.Binary) and e.op is Op.AND:
        return _conjuncts(e.left) + _conjuncts(e.right)
    return [e]


def _variable(var_id: int) -> Evaluator:
    return lambda env: env.vars[var_id]


def _truth(v: Value) -> bool:
    # `null` in a condition is false (LANGUAGE.md §6.4).
    return v is True


def _index(i: Value, n: int, span: Span) -> int:
    if isinstance(i, float) and i.is_integer():
        i = int(i)
    if not isinstance(i, int) or isinstance(i, bool):
        raise GppRuntimeError(R0003.not_whole(show(i)), span)
    if not 0 <= i < n:
        raise GppRuntimeError(R0003.out_of_range(i, n), span)
    return i


def _element(v: Value, i: Value, span: Span) -> Value:
    if v is None:
        raise GppRuntimeError(R0002.indexing_null(), span)
    assert isinstance(v, tuple)
    return v[_index(i, len(v), span)]


def _add(a: Value, b: Value, span: Span) -> Value:
    return a + b  # type: ignore[operator]


def _sub(a: Value, b: Value, span: Span) -> Value:
    return a - b  # type: ignore[operator]


def _mul(a: Value, b: Value, span: Span) -> Value:
    return a * b  # type: ignore[operator]


def _div(a: Value, b: Value, span: Span) -> Value:
    if b == 0:
        raise GppRuntimeError(R0001.division_by_zero(), span)
    return a / b  # type: ignore[operator]


def _mod(a: Value, b: Value, span: Span) -> Value:
    # Whole-valued floats (`16 / 2` is 8.0) count as whole numbers, as list indexes do.
    a, b = _whole(a), _whole(b)
    if not isinstance(a, int) or not isinstance(b, int):
        raise GppRuntimeError(R0001.modulo_not_whole(show(a), show(b)), span)
    if b == 0:
        raise GppRuntimeError(R0001.modulo_by_zero(), span)
    return a % b


def _whole(v: Value) -> Value:
    return int(v) if isinstance(v, float) and v.is_integer() else v


def _operand(v: Value) -> str:
    """A number as the left operand of `**` in a message: `(-8) ** 0.5`, not `-8 ** 0.5`."""
    text = show(v)
    return f"({text})" if text.startswith("-") else text


def _pow(a: Value, b: Value, span: Span) -> Value:
    assert isinstance(a, int | float) and isinstance(b, int | float)
    if a == 0 and b < 0:
        raise GppRuntimeError(R0001.power_divides_by_zero(_operand(a), show(b)), span)
    if isinstance(a, int) and isinstance(b, int) and b >= 0:
        if abs(a) > 1 and b * math.log2(abs(a)) > _MAX_POWER_BITS:
            raise GppRuntimeError(R0001.power_too_large(_operand(a), show(b)), span, (RANGE_TEXT,))
        power: int = a**b
        if not -MAX_WHOLE <= power <= MAX_WHOLE:
            raise GppRuntimeError(R0001.power_too_large(_operand(a), show(b)), span, (RANGE_TEXT,))
        return power
    try:
        return math.pow(a, b)
    except ZeroDivisionError:
        raise GppRuntimeError(R0001.power_divides_by_zero(_operand(a), show(b)), span) from None
    except OverflowError:
        raise GppRuntimeError(R0001.power_too_large(_operand(a), show(b)), span, (RANGE_TEXT,)) from None
    except ValueError:
        raise GppRuntimeError(R0001.power_not_real(_operand(a), show(b)), span) from None


# Whole-number powers beyond this many bits are beyond the range of numbers (MAX_WHOLE has 1024
# bits); the margin leaves the exact check to the caller.
_MAX_POWER_BITS = 1100

_ARITHMETIC: dict[Op, Callable[[Value, Value, Span], Value]] = {
    Op.ADD: _add,
    Op.SUB: _sub,
    Op.MUL: _mul,
    Op.DIV: _div,
    Op.MOD: _mod,
    Op.POW: _pow,
}

_ORDER: dict[Op, Callable[[object, object], bool]] = {
    Op.LT: lambda a, b: a < b,  # type: ignore[operator]
    Op.LE: lambda a, b: a <= b,  # type: ignore[operator]
    Op.GT: lambda a, b: a > b,  # type: ignore[operator]
    Op.GE: lambda a, b: a >= b,  # type: ignore[operator]
}


def _is_number(v: Value) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _too_large(op: Op, span: Span) -> GppRuntimeError:
    """A result beyond the range of numbers (docs/semantics.md, "Numbers")."""
    return GppRuntimeError(R0001.too_large(op.value), span, (RANGE_TEXT,))


def _internal(span: Span, message: str) -> GppRuntimeError:
    return GppRuntimeError(R0099.unchecked(message), span)


class _NoContext:
    """Initial values are literals: they never call the platform."""

    def exog_function(self, name: str, args: dict[str, Value], return_type: Type, span: Span) -> Value:
        raise GppRuntimeError(R0099.exog_in_initial_value(), span)

    def now(self) -> float:
        return 0.0

    def wake_at(self, t: float) -> None:
        pass


_NO_CONTEXT = _NoContext()

__all__ = ["Activities", "CompiledProgram", "Context", "Env", "Evaluator"]
