"""`trans` of a program point as generated Python source, written once per semantics object and
compiled once per source text (gpp.runtime.codegen.CompileCache): the successors of a
continuation in straight-line code, for gpp.planner.fast.successors.

For a continuation (a statement with its bindings, a sequence, the rest of a block) this
module writes one function of (state, activities) that does what the specialised closures of
gpp.planner.fast.successors do, written out: the `while`/`if` conditions, `test`s, the `choose`
alternatives, the values of a `pick` over a domain (its precondition guard included), and an
action call with known arguments (its running check and precondition conjuncts, with the
action's parameters folded to constants) become nested `if`s appending constant successors
(the continuation after the step is known when the code is written: `seq` is applied once,
here). Conditions are written by gpp.runtime.codegen. Whatever is not written out (a
procedure call, an assignment, `pick ... in {...}`, a guard that reads a fluent in its
arguments, concurrency, hooks) calls the closure of gpp.planner.fast.successors for that part,
and the successors it returns are put in their place, continued the same way.

The order of evaluation is the closures' (and so the semantics'): alternatives in textual
order, for a sequence first the successors of its head, then `final` of its head and the
successors of the rest. tests/planner/test_planner_successors.py compares the generated functions
with `Semantics.trans` on random programs.
"""

from __future__ import annotations

from collections.abc import Callable

from gpp.base.source import Span
from gpp.model.symbols import SymbolKind
from gpp.model.types import Sym
from gpp.planner.fast.port import ApplyFn, Closures, FinalFn, TransFn, always, never
from gpp.runtime.codegen import ExprGen, Unit, Unsupported, build_units
from gpp.runtime.compiled import Effect, Env, Evaluator, check_domain, reads_only_variables
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import DONE, Code, Done, DoStep, Frame, Prog, Rest, Semantics, Seq, TestStep
from gpp.runtime.state import ActivityStatus, State, identical, item_hash
from gpp.runtime.values import Value, show
from gpp.syntax import ast

_EMPTY = State()
_PLAIN = (Sym, str, type(None))

# Nesting deeper than this (a long block, a deep continuation) calls the closures instead.
MAX_DEPTH = 40
# A function longer than this many lines calls the closures for the rest.
MAX_LINES = 4000


def _snippet(span: Span) -> str:
    text = span.source.text[span.start : span.end].split("\n")[0].strip()
    return text if len(text) <= 60 else text[:57] + "..."


class TransGen:
    """Writes the `trans` function of one continuation."""

    def __init__(self, successors: Closures, name: str) -> None:
        self.successors = successors
        self.sem = successors.sem
        self.program = successors.program
        self.unit = Unit(name, "state, acts")
        self.exprs = ExprGen(self.program, self.unit)
        self.seq = Semantics.seq
        # The action steps the function returns, with their `apply` written (None: not).
        self.applies: list[tuple[DoStep, ApplyGen | None]] = []
        self.sources: list[str] = []

    def build(self, p: Prog) -> TransFn:
        """The function, compiled together with `apply` of the action steps it returns."""
        unit = self.unit
        unit.emit(0, "_status = acts.status")
        unit.emit(0, "_idle = not len(acts)  # no activity: none is running")
        unit.emit(0, "out = []")
        self.prog(0, p, DONE)
        unit.emit(0, "return out")
        written = [(step, gen) for step, gen in self.applies if gen is not None]
        fns = build_units([unit, *(gen.unit for _, gen in written)])
        for step, gen in self.applies:
            if gen is None:
                self.successors.register_apply(step, None)
        for (step, _), fn in zip(written, fns[1:], strict=True):
            self.successors.register_apply(step, fn)
        self.sources = [unit.source, *(gen.unit.source for _, gen in written)]
        trans: TransFn = fns[0]
        return trans

    # ---------------------------------------------------------------- continuations

    def prog(self, d: int, p: Prog, wrap: Prog) -> None:
        """Append the successors of `p`, each continued by `wrap` (`seq(q, wrap)`)."""
        if d > MAX_DEPTH or len(self.unit.lines) > MAX_LINES:
            self.leaf(d, self.successors.trans_fn(p), wrap)
            return
        match p:
            case Done():
                return
            case Code():
                self.code(d, p.stmt, p.frame, wrap, frozenset())
            case Rest():
                body = p.block.body
                if p.index >= len(body):
                    return
                tail: Prog = Rest(p.block, p.index + 1, p.frame) if p.index + 1 < len(body) else DONE
                self.prog(d, Seq(Code(body[p.index], p.frame), tail), wrap)
            case Seq():
                # seq(seq(q, rest), wrap) == seq(q, seq(rest, wrap)): `seq` keeps sequences
                # right-nested, so the continuation is the same whichever way it is built.
                self.prog(d, p.first, self.seq(p.rest, wrap))
                self.then_final(d, self.successors.final_fn(p.first), p.rest, wrap)
            case _:
                self.leaf(d, self.successors.trans_fn(p), wrap)

    def then_final(self, d: int, final: FinalFn, rest: Prog, wrap: Prog) -> None:
        """If `final` holds, the successors of `rest` too (the tail of a sequence)."""
        if final is never:
            return
        if final is always:
            self.prog(d, rest, wrap)
            return
        self.unit.emit(d, f"if {self.unit.const(final, 'final of the head')}(state, acts):")
        mark = len(self.unit.lines)
        self.prog(d + 1, rest, wrap)
        self.unit.close(d + 1, mark)

    def leaf(self, d: int, fn: TransFn, wrap: Prog) -> None:
        """The successors a closure returns, continued by `wrap`."""
        call = f"{self.unit.const(fn, 'a closure of gpp.planner.fast.successors')}(state, acts)"
        if isinstance(wrap, Done):
            self.unit.emit(d, f"out.extend({call})")
            return
        seq, w = self.unit.const(self.seq, "Semantics.seq"), self.unit.const(wrap, "the continuation after it")
        self.unit.emit(d, f"for _q, _step in {call}:")
        self.unit.emit(d + 1, f"out.append(({seq}(_q, {w}), _step))")

    def append(self, d: int, q: Prog, step: object, wrap: Prog, note: str) -> None:
        pair = (self.seq(q, wrap), step)
        self.unit.emit(d, f"out.append({self.unit.const(pair, note)})")

    # ---------------------------------------------------------------- statements

    def condition(self, e: ast.Expr, variables: dict[int, Value]) -> tuple[str, bool]:
        """The source of `e is True` with these variables, and whether it can raise. What
        the generator does not write out, the expression's closure evaluates."""
        spans = len(self.unit.spans)
        try:
            v = self.exprs.condition(e, variables)
        except Unsupported:
            closure = self.unit.const(self.program.expr(e), "a compiled expression")
            env = f"Env(state, {self.unit.const(variables, 'variables')}, {self.unit.const(self.sem.ctx, 'context')})"
            return f"({closure}({env}) is True)", True
        return (repr(v.value is True) if v.const else v.text), len(self.unit.spans) > spans

    def code(self, d: int, s: ast.Statement, frame: Frame, wrap: Prog, known: frozenset[int]) -> None:
        unit = self.unit
        if d > MAX_DEPTH or len(unit.lines) > MAX_LINES:
            self.leaf(d, self.successors.code_trans(s, frame, known), wrap)
            return
        match s:
            case ast.Block():
                if s.body:
                    self.prog(d, Rest(s, 0, frame), wrap)
            case ast.While():
                test, _ = self.condition(s.condition, frame.vars)
                unit.emit(d, f"# while ({_snippet(s.condition.span)})")
                self.guarded(
                    d, test, lambda d: self.code(d, s.body, frame, self.seq(Code(s, frame), wrap), frozenset())
                )
            case ast.If():
                test, _ = self.condition(s.condition, frame.vars)
                unit.emit(d, f"# if ({_snippet(s.condition.span)})")
                otherwise = s.otherwise
                if otherwise is None:
                    self.guarded(d, test, lambda d: self.code(d, s.then, frame, wrap, frozenset()))
                else:
                    self.branch(
                        d,
                        test,
                        lambda d: self.code(d, s.then, frame, wrap, frozenset()),
                        lambda d: self.code(d, otherwise, frame, wrap, frozenset()),
                    )
            case ast.Test():
                test, _ = self.condition(s.condition, frame.vars)
                unit.emit(d, f"# test ({_snippet(s.condition.span)})")
                self.guarded(d, test, lambda d: self.append(d, DONE, TestStep(s.span), wrap, "a test step"))
            case ast.Choose():
                for alternative in s.alternatives:
                    self.code(d, alternative, frame, wrap, frozenset())
            case ast.Pick() if s.values is None or all(reads_only_variables(self.sem.model, v) for v in s.values):
                # `pick (x in {...})`: values that read only variables are the same every time.
                self.pick(d, s, frame, wrap, known)
            case ast.Solve() | ast.Search():
                self.code(d, s.body, frame, wrap, frozenset())
            case ast.CallStmt() if self.sem.callee(s).kind is not SymbolKind.PROCEDURE:
                self.action(d, s, frame, wrap, known)
            case _:
                self.leaf(d, self.successors.code_trans(s, frame, known), wrap)

    def guarded(self, d: int, test: str, body: Callable[[int], None]) -> None:
        if test == "False":
            return
        if test == "True":
            body(d)
            return
        self.unit.emit(d, f"if {test}:")
        mark = len(self.unit.lines)
        body(d + 1)
        self.unit.close(d + 1, mark)

    def branch(self, d: int, test: str, then: Callable[[int], None], otherwise: Callable[[int], None]) -> None:
        if test in ("True", "False"):
            (then if test == "True" else otherwise)(d)
            return
        self.unit.emit(d, f"if {test}:")
        mark = len(self.unit.lines)
        then(d + 1)
        self.unit.close(d + 1, mark)
        self.unit.emit(d, "else:")
        mark = len(self.unit.lines)
        otherwise(d + 1)
        self.unit.close(d + 1, mark)

    def pick(self, d: int, s: ast.Pick, frame: Frame, wrap: Prog, known: frozenset[int]) -> None:
        successors, program = self.successors, self.program
        guard = program.pick_guard(s)
        if guard is not None and not guard.static:
            self.leaf(d, successors.code_trans(s, frame, known), wrap)
            return
        try:
            frames = self.sem.pick_frames(s, frame)
        except GppRuntimeError:  # raised again, where the semantics raises it
            self.leaf(d, successors.code_trans(s, frame, known), wrap)
            return
        if guard is None:
            for f in frames:
                self.code(d, s.body, f, wrap, known)
            return
        # As gpp.planner.fast.successors does: once the guard found its conjuncts true, the action's
        # precondition need not evaluate those that read only fluents again.
        action = program.action(successors.guarded_call(s).name)
        conjuncts = [(check, expr) for check, expr in action.precondition if check in guard.conjuncts]
        pure = frozenset(id(check) for check, expr in conjuncts if program.reads_only_fluents(expr))
        pruned = f"{self.unit.const(self.sem, 'the semantics')}.pruned_bindings += 1"
        variable = self.sem.model.target(s.var)
        for f in frames:
            shown = "?" if variable is None else show(f.vars.get(id(variable)))
            self.unit.emit(d, f"# pick {s.var.name} = {shown}")
            try:
                bindings = guard.bind(Env(_EMPTY, f.vars, self.sem.ctx))
            except GppRuntimeError:
                bindings = None
            if bindings is None:
                self.code(d, s.body, f, wrap, known)
                continue
            tests = [self.condition(expr, bindings) for _, expr in conjuncts]
            holds = _conjunction([t for t, _ in tests])
            passed = self._emitter(s.body, f, wrap, known | pure)
            if not any(raises for _, raises in tests):
                self.branch(d, holds, passed, lambda d: self.unit.emit(d, pruned))
                continue
            # An error in the guard: the value is not rejected, and nothing is known.
            g = self.unit.temp("guard")
            self.unit.emit(d, "try:")
            self.unit.emit(d + 1, f"{g} = {holds}")
            self.unit.emit(d, "except GppRuntimeError:")
            self.unit.emit(d + 1, f"{g} = None")
            self.unit.emit(d, f"if {g} is None:")
            mark = len(self.unit.lines)
            self.code(d + 1, s.body, f, wrap, known)
            self.unit.close(d + 1, mark)
            self.unit.emit(d, f"elif {g}:")
            mark = len(self.unit.lines)
            passed(d + 1)
            self.unit.close(d + 1, mark)
            self.unit.emit(d, "else:")
            self.unit.emit(d + 1, pruned)

    def _emitter(self, s: ast.Statement, frame: Frame, wrap: Prog, known: frozenset[int]) -> Callable[[int], None]:
        return lambda d: self.code(d, s, frame, wrap, known)

    def action(self, d: int, s: ast.CallStmt, frame: Frame, wrap: Prog, known: frozenset[int]) -> None:
        """An action call with arguments that read only variables: its ground action is known."""
        sem, call = self.sem, s.call
        if not isinstance(call, ast.Call) or not all(reads_only_variables(sem.model, a) for a in call.args):
            self.leaf(d, self.successors.code_trans(s, frame, known), wrap)
            return
        try:
            action, g = sem.ground_call(call, frame, _EMPTY)
        except GppRuntimeError:  # raised again, where the semantics raises it
            self.leaf(d, self.successors.code_trans(s, frame, known), wrap)
            return
        bindings = dict(zip(action.param_ids, g.args, strict=True))
        tests: list[str] = []
        raises = False  # a conjunct before this one can raise
        for check, expr in action.precondition:
            if id(check) in known:
                continue  # true whenever this runs
            test, can_raise = self.condition(expr, bindings)
            if test == "True":
                continue
            if test == "False" and not raises:
                self.unit.emit(d, f"# {g.text}: its precondition never holds")
                return
            tests.append(test)
            if test == "False":
                break
            raises = raises or can_raise
        self.unit.emit(d, f"# {g.text}")
        step = DoStep(g, s.span)
        running = self.unit.const(ActivityStatus.RUNNING, "ActivityStatus.RUNNING")
        test = _conjunction([f"(_idle or _status({self.unit.const(g, g.text)}) is not {running})", *tests])
        if test != "False":
            gen = ApplyGen(self.successors, self.successors.unit_name("apply"))
            self.applies.append((step, gen if gen.write(step) else None))
        self.guarded(d, test, lambda d: self.append(d, DONE, step, wrap, g.text))


def _conjunction(tests: list[str]) -> str:
    """`a and b and ...`, in order (a constant False stays in place: what comes before it is
    still evaluated)."""
    tests = [t for t in tests if t != "True"]
    if not tests:
        return "True"
    if tests == ["False"]:
        return "False"
    return " and ".join(tests)


class ApplyGen:
    """Writes `apply` of one action step (planning: its effects at once), when every effect
    assigns a whole fluent instance whose arguments read only the action's parameters and no
    two assign the same instance: what `Semantics.apply` does for it then (the semantics'
    "effect plan"), step for step, with the slots, the parameters and the values known in
    advance folded in. None for any other action (the semantics applies it)."""

    def __init__(self, successors: Closures, name: str) -> None:
        self.sem = successors.sem
        self.program = successors.program
        self.unit = Unit(name, "state, acts")
        self.exprs = ExprGen(self.program, self.unit)

    def build(self, step: DoStep) -> ApplyFn | None:
        """The function, or None (the semantics applies the step)."""
        if not self.write(step):
            return None
        fn: ApplyFn = self.unit.build()
        return fn

    def write(self, step: DoStep) -> bool:
        """Write the function; False if this action is left to the semantics. An action with
        a `start_effect:` section: its start effects are written out (they read the state
        before the step, which the function reads at its start), then its end effects, which
        read the state after the start effects, are evaluated by the semantics."""
        program, unit, g = self.program, self.unit, step.action
        action = program.action(g.name)
        decl = action.decl
        at_start = bool(action.start_effects)
        effects = action.start_effects if at_start else action.effects
        written = [e for section in decl.sections or () for e in _effects_of(section, at_start)] if decl else []
        if len(written) != len(effects) or not all(effect.static_target for effect in effects):
            return False
        bindings = dict(zip(action.param_ids, g.args, strict=True))
        env = Env(_EMPTY, bindings, self.sem.ctx)
        try:
            slots = [program.slot(e.target.fluent, tuple(a(env) for a in e.target.args)) for e in effects]
        except GppRuntimeError:
            return False
        if len(set(slots)) < len(slots):
            return False
        unit.emit(0, f"# {g.text}")
        one = None if at_start else self._one_constant(effects, written, slots, bindings)
        if one is not None:
            slot, value = one
            # `updated` of one constant value: its hash and its comparisons worked out here.
            v = unit.const(value, show(value))
            known = f"{item_hash(slot, value)}, {identical(value, program.initial(slot))}, {type(value) in _PLAIN}"
            unit.emit(0, f"# {_snippet(effects[0].span)}")
            unit.emit(0, f"return state.updated_one({slot}, {v}, {known}), acts")
            return True
        unit.emit(0, "_pending = {}")
        initial = unit.const(program.initial, "CompiledProgram.initial")
        for effect, e, slot in zip(effects, written, slots, strict=True):
            span = effect.value_span if effect.value_span is not None else effect.target.span
            unit.emit(0, f"# {_snippet(effect.span)}")
            d = 0
            if effect.condition is not None:
                assert e.condition is not None
                test, _ = self.condition(e.condition, bindings, effect.condition)
                if test == "False":
                    continue
                if test != "True":
                    unit.emit(0, f"if {test}:")
                    d = 1
            value = self.value(e.value, bindings, effect.value)
            domain_ok = False
            if value[1]:
                try:
                    check_domain(value[2], effect.target.value_type, span)
                    domain_ok = True
                except GppRuntimeError:
                    pass
            unit.emit(d, f"_value = {value[0]}")
            if not domain_ok:
                check = unit.const(check_domain, "check_domain")
                unit.emit(d, f"{check}(_value, {unit.const(effect.target.value_type)}, {unit.const(span, 'its span')})")
            unit.emit(d, f"_pending[{slot}] = _value")
        if at_start:
            end = unit.const(self.sem.effects, "Semantics.effects")
            unit.emit(0, "# the end effects, in the state after the start effects")
            unit.emit(0, f"state = state.updated(_pending, {initial})")
            unit.emit(0, f"return state.updated({end}({unit.const(g, g.text)}, state), {initial}), acts")
            return True
        unit.emit(0, f"return state.updated(_pending, {initial}), acts")
        return True

    def _one_constant(
        self, effects: tuple[Effect, ...], written: list[ast.Effect], slots: list[int], bindings: dict[int, Value]
    ) -> tuple[int, Value] | None:
        """The slot and value of the one effect, when it is unconditional and its value a
        constant in the target's domain."""
        if len(effects) != 1 or effects[0].condition is not None:
            return None
        effect = effects[0]
        try:
            v = self.exprs.expr(written[0].value, bindings)
        except Unsupported:
            return None
        if not v.const:
            return None
        span = effect.value_span if effect.value_span is not None else effect.target.span
        try:
            check_domain(v.value, effect.target.value_type, span)
        except GppRuntimeError:
            return None
        return slots[0], v.value

    def _env(self, bindings: dict[int, Value]) -> str:
        return f"Env(state, {self.unit.const(bindings, 'the parameters')}, {self.unit.const(self.sem.ctx, 'context')})"

    def condition(self, e: ast.Expr, bindings: dict[int, Value], closure: Evaluator) -> tuple[str, bool]:
        try:
            v = self.exprs.condition(e, bindings)
        except Unsupported:
            return f"({self.unit.const(closure, 'a compiled expression')}({self._env(bindings)}) is True)", True
        return (repr(v.value is True) if v.const else v.text), False

    def value(self, e: ast.Expr, bindings: dict[int, Value], closure: Evaluator) -> tuple[str, bool, Value]:
        """The source of the value, whether it is a constant, and the constant."""
        try:
            v = self.exprs.expr(e, bindings)
        except Unsupported:
            return f"{self.unit.const(closure, 'a compiled expression')}({self._env(bindings)})", False, None
        return self.exprs.text(v), v.const, v.value


def _effects_of(section: ast.ActionSection, at_start: bool) -> tuple[ast.Effect, ...]:
    kind = ast.StartEffectSection if at_start else ast.EffectSection
    return section.effects if isinstance(section, kind) else ()
