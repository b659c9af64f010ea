"""`final` and `trans` specialised to a program point, once per semantics object (reused by its
later plannings, see `successors_of`): what the production planner calls instead of
gpp.runtime.semantics on every configuration.

`trans` of a statement, a sequence or the rest of a block is generated Python source
(gpp.planner.fast.codegen, compiled with `apply` of the action steps it returns), as is a `while`
condition in `final`; the closures below are what that source calls for the parts it does
not write out, and what runs with `generate=False`. Each closure does exactly what the
semantics does for its program point, with what does not depend on the state done in advance
(docs/design.md, "The speed tier"); the parts it does not specialise call the semantics.
"""

from __future__ import annotations

from collections.abc import Callable
from weakref import WeakKeyDictionary

from gpp.model.symbols import Symbol, SymbolKind
from gpp.planner.fast.codegen import ApplyGen, TransGen
from gpp.planner.fast.port import ApplyFn, FinalFn, TransFn, always, never
from gpp.runtime.codegen import ExprGen, Unit, Unsupported
from gpp.runtime.compiled import Env, Evaluator, PickGuard, reads_only_variables
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import (
    DONE,
    Code,
    Done,
    DoStep,
    Frame,
    Prog,
    Rest,
    Semantics,
    Seq,
    Step,
    Successor,
    TestStep,
)
from gpp.runtime.state import Activities, ActivityStatus, GroundAction, State
from gpp.runtime.values import Value
from gpp.syntax import ast

_EMPTY = State()

# At most this many continuations get generated source per semantics object (its plannings
# share them, see `successors_of`); the others run the closures. Writing and compiling a
# function costs a millisecond or more, which a planning that meets thousands of
# continuations once each (a deep recursion) would not earn back.
MAX_TRANS_UNITS = 200


# By semantics object: its Successors, with and without generated source (see successors_of).
_SHARED: WeakKeyDictionary[Semantics, dict[bool, Successors]] = WeakKeyDictionary()


def _nothing(state: State, acts: Activities) -> list[Successor]:
    return []


def successors_of(sem: Semantics, generate: bool = True) -> Successors:
    """The `Successors` of `sem`, made by its first planning and reused by every later one
    with the same semantics object (the same problem planned again, a repeated `solve`): what
    it specialised and generated depends on nothing but `sem` (its program, context and the
    frames met), so it stays exact, and is not written again. Kept as long as `sem` lives."""
    made = _SHARED.get(sem)
    if made is None:
        made = _SHARED[sem] = {}
    successors = made.get(generate)
    if successors is None:
        successors = made[generate] = Successors(sem, generate)
    return successors


class Successors:
    """`final` and `trans` of `sem` (planning mode), specialised per program point on first use."""

    def __init__(self, sem: Semantics, generate: bool = True) -> None:
        assert sem.planning
        self.sem = sem
        self.program = sem.program
        self.model = sem.model
        self._trans: dict[Prog, TransFn] = {}
        self._final: dict[Prog, FinalFn] = {}
        self._code_trans: dict[tuple[int, Frame, frozenset[int]], TransFn] = {}
        self._code_final: dict[tuple[int, Frame], FinalFn] = {}
        # Generate the source of `trans` per program point (False: the closures only).
        self.generate = generate
        self.sources: list[str] = []  # the generated functions' source, in the order made
        self._units = 0
        self._trans_units = 0
        # Step object id -> (the step, its generated `apply` or None: the semantics applies it).
        self._apply: dict[int, tuple[Step, ApplyFn | None]] = {}
        self._apply_by_action: dict[GroundAction, ApplyFn | None] = {}

    def apply(self, step: Step, state: State, acts: Activities) -> tuple[State, Activities]:
        """`Semantics.apply`; for an action step, generated source made once per step object
        (gpp.planner.fast.codegen.ApplyGen) when the action's effects allow it."""
        return self.apply_fn(step)(state, acts)

    def apply_fn(self, step: Step) -> ApplyFn:
        """`apply` of `step` as a function of (state, activities) (see `apply`)."""
        known = self._apply.get(id(step))
        if known is not None and known[0] is step:
            fn = known[1]
        elif isinstance(step, DoStep) and self.generate:
            # A step the generated code did not make (the closures make a new one each time):
            # found by its action, generated once per action.
            if step.action in self._apply_by_action:
                fn = self._apply_by_action[step.action]
            else:
                gen = ApplyGen(self, self.unit_name("apply"))
                fn = self._apply_by_action[step.action] = gen.build(step)
                if fn is not None:
                    self.sources.append(gen.unit.source)
        else:
            fn = None
        if fn is None:
            sem_apply = self.sem.apply
            return lambda state, acts: sem_apply(step, state, acts)
        return fn

    def register_apply(self, step: Step, fn: ApplyFn | None) -> None:
        """`apply` of this step object is `fn` (None: the semantics')."""
        self._apply[id(step)] = (step, fn)

    def unit_name(self, prefix: str) -> str:
        """A name for a generated function, unique in this planning."""
        self._units += 1
        return f"{prefix}_{self._units}"

    def trans(self, p: Prog, state: State, acts: Activities) -> list[Successor]:
        return self.trans_of(p)(state, acts)

    def final(self, p: Prog, state: State, acts: Activities) -> bool:
        return self.final_of(p)(state, acts)

    def trans_of(self, p: Prog) -> TransFn:
        """`trans` of `p` as a function of (state, activities), made once per continuation."""
        f = self._trans.get(p)
        if f is None:
            f = self._trans[p] = self.trans_fn(p)
        return f

    def final_of(self, p: Prog) -> FinalFn:
        """`final` of `p` as a function of (state, activities), made once per continuation."""
        f = self._final.get(p)
        if f is None:
            f = self._final[p] = self.final_fn(p)
        return f

    # ---------------------------------------------------------------- continuations

    def trans_fn(self, p: Prog) -> TransFn:
        """`trans` of `p`: generated source for a statement, a sequence or the rest of a block
        (gpp.planner.fast.codegen), else the closures below."""
        if self.generate and isinstance(p, Code | Seq | Rest) and self._trans_units < MAX_TRANS_UNITS:
            self._trans_units += 1
            gen = TransGen(self, self.unit_name("trans"))
            fn = gen.build(p)
            self.sources.extend(gen.sources)
            return fn
        return self.closure_trans_fn(p)

    def closure_trans_fn(self, p: Prog) -> TransFn:
        sem = self.sem
        match p:
            case Done():
                return _nothing
            case Code():
                return self.code_trans(p.stmt, p.frame)
            case Rest():
                body = p.block.body
                if p.index >= len(body):
                    return _nothing
                tail: Prog = Rest(p.block, p.index + 1, p.frame) if p.index + 1 < len(body) else DONE
                return self.trans_fn(Seq(Code(body[p.index], p.frame), tail))
            case Seq():
                first, first_final, rest = self.trans_fn(p.first), self.final_fn(p.first), p.rest
                seq = Semantics.seq
                rest_trans: list[TransFn] = []  # built on first use (a recursion comes back here)

                def trans_seq(state: State, acts: Activities) -> list[Successor]:
                    out = [(seq(q, rest), step) for q, step in first(state, acts)]
                    if first_final(state, acts):
                        if not rest_trans:
                            rest_trans.append(self.trans_fn(rest))
                        out.extend(rest_trans[0](state, acts))
                    return out

                return trans_seq
            case _:
                return lambda state, acts: sem.trans(p, state, acts)

    def final_fn(self, p: Prog) -> FinalFn:
        sem = self.sem
        match p:
            case Done():
                return always
            case Code():
                return self.code_final(p.stmt, p.frame)
            case Rest():
                return self._all([self.code_final(s, p.frame) for s in p.block.body[p.index :]])
            case Seq():
                return self._all([self.final_fn(p.first), self.final_fn(p.rest)])
            case _:
                return lambda state, acts: sem.final(p, state, acts)

    def _static_values(self, s: ast.Pick, frame: Frame) -> bool:
        """The values of a `pick` are the same whenever it is reached: those of a domain, or
        `{...}` of values that read only variables (and do not raise)."""
        if s.values is None:
            return True
        if not all(reads_only_variables(self.model, v) for v in s.values):
            return False
        try:
            self.sem.pick_frames(s, frame)
        except GppRuntimeError:
            return False
        return True

    @staticmethod
    def _all(parts: list[FinalFn]) -> FinalFn:
        """All of `parts`, in order, stopping at the first false one (as `all` does)."""
        if not parts:
            return always
        if parts[0] is never:
            return never
        if len(parts) == 1:
            return parts[0]

        def final_all(state: State, acts: Activities) -> bool:
            return all(f(state, acts) for f in parts)

        return final_all

    # ---------------------------------------------------------------- statements: final

    def code_final(self, s: ast.Statement, frame: Frame) -> FinalFn:
        key = (id(s), frame)
        f = self._code_final.get(key)
        if f is None:
            f = self._code_final[key] = self._make_code_final(s, frame)
        return f

    def _make_code_final(self, s: ast.Statement, frame: Frame) -> FinalFn:
        sem = self.sem
        match s:
            case ast.Test() | ast.Assign() | ast.ListStmt() | ast.HookStmt() | ast.During():
                return never
            case ast.CallStmt() if sem.callee(s).kind is not SymbolKind.PROCEDURE:
                return never
            case ast.Block():
                return self._all([self.code_final(x, frame) for x in s.body])
            case ast.Choose():
                parts = [self.code_final(x, frame) for x in s.alternatives]
                if all(f is never for f in parts):
                    return never
                return lambda state, acts: any(f(state, acts) for f in parts)
            case ast.Pick() if self._static_values(s, frame):
                bodies = [self.code_final(s.body, f) for f in sem.pick_frames(s, frame)]
                if all(f is never for f in bodies):
                    return never
                return lambda state, acts: any(f(state, acts) for f in bodies)
            case ast.Solve() | ast.Search():
                return self.code_final(s.body, frame)
            case ast.While():
                holds, body = self.condition_fn(s.condition, frame), s.body
                body_final: list[FinalFn] = []  # built on first use

                def final_while(state: State, acts: Activities) -> bool:
                    if not holds(state):
                        return True
                    if not body_final:
                        body_final.append(self.code_final(body, frame))
                    return body_final[0](state, acts)

                return final_while
            case _:
                return lambda state, acts: sem.final_code(s, frame, state, acts)

    # ---------------------------------------------------------------- statements: trans

    def code_trans(self, s: ast.Statement, frame: Frame, known: frozenset[int] = frozenset()) -> TransFn:
        """`trans` of `s` with the bindings of `frame`. `known`: (the ids of) precondition
        conjuncts known to hold whenever this function is called, for an action call directly
        inside `pick`s (a pick guard has just found them true)."""
        key = (id(s), frame, known)
        f = self._code_trans.get(key)
        if f is None:
            f = self._code_trans[key] = self._make_code_trans(s, frame, known)
        return f

    def _condition(self, e: ast.Expr) -> Evaluator:
        return self.program.expr(e)

    def condition_fn(self, e: ast.Expr, frame: Frame) -> Callable[[State], bool]:
        """`e is True` in a state, with the bindings of `frame`: generated source
        (gpp.runtime.codegen), or the compiled closure for what that does not write out."""
        condition, variables, ctx = self._condition(e), frame.vars, self.sem.ctx
        if self.generate:
            unit = Unit(self.unit_name("condition"), "state")
            try:
                test = ExprGen(self.program, unit).condition(e, variables)
            except Unsupported:
                pass
            else:
                unit.emit(0, f"return {test.value is True!r}" if test.const else f"return {test.text}")
                fn: Callable[[State], bool] = unit.build()
                self.sources.append(unit.source)
                return fn
        return lambda state: condition(Env(state, variables, ctx)) is True

    def _make_code_trans(self, s: ast.Statement, frame: Frame, known: frozenset[int]) -> TransFn:
        sem = self.sem
        variables, ctx = frame.vars, sem.ctx
        match s:
            case ast.Block():
                if not s.body:
                    return _nothing
                return self.trans_fn(Rest(s, 0, frame))
            case ast.While():
                condition, loop, seq = self._condition(s.condition), Code(s, frame), Semantics.seq
                body = self.code_trans(s.body, frame)

                def trans_while(state: State, acts: Activities) -> list[Successor]:
                    if condition(Env(state, variables, ctx)) is not True:
                        return []
                    return [(seq(q, loop), step) for q, step in body(state, acts)]

                return trans_while
            case ast.If():
                condition = self._condition(s.condition)
                then = self.code_trans(s.then, frame)
                otherwise = self.code_trans(s.otherwise, frame) if s.otherwise is not None else _nothing

                def trans_if(state: State, acts: Activities) -> list[Successor]:
                    if condition(Env(state, variables, ctx)) is True:
                        return then(state, acts)
                    return otherwise(state, acts)

                return trans_if
            case ast.Test():
                condition, test = self._condition(s.condition), TestStep(s.span)

                def trans_test(state: State, acts: Activities) -> list[Successor]:
                    return [(DONE, test)] if condition(Env(state, variables, ctx)) is True else []

                return trans_test
            case ast.Choose():
                alternatives = [self.code_trans(x, frame) for x in s.alternatives]

                def trans_choose(state: State, acts: Activities) -> list[Successor]:
                    out: list[Successor] = []
                    for alternative in alternatives:
                        out.extend(alternative(state, acts))
                    return out

                return trans_choose
            case ast.Pick() if s.values is None:
                return self._pick(s, frame, known)
            case ast.Solve() | ast.Search():
                return self.code_trans(s.body, frame)
            case ast.CallStmt():
                if sem.callee(s).kind is SymbolKind.PROCEDURE:
                    return self._procedure_call(s, frame)
                return self._action_call(s, frame, known)
            case _:
                return lambda state, acts: sem.trans_code(s, frame, state, acts)

    def _pick(self, s: ast.Pick, frame: Frame, known: frozenset[int]) -> TransFn:
        sem = self.sem
        guard = self.program.pick_guard(s)
        ctx = sem.ctx
        frames = sem.pick_frames(s, frame)
        branches = [(f.vars, self.code_trans(s.body, f, known)) for f in frames]
        if guard is None:

            def trans_pick(state: State, acts: Activities) -> list[Successor]:
                out: list[Successor] = []
                for _, body in branches:
                    out.extend(body(state, acts))
                return out

            return trans_pick
        if guard.static:
            # Once the guard found its conjuncts true, the action's precondition need not
            # evaluate them again (those that read only fluents: they have the same value).
            action = self.program.action(self.guarded_call(s).name)
            pure = frozenset(
                id(check)
                for check, expr in action.precondition
                if check in guard.conjuncts and self.program.reads_only_fluents(expr)
            )
            passed = [self.code_trans(s.body, f, known | pure) for f in frames]
            return self._statically_guarded_pick(guard, branches, passed)
        rejects = guard.rejects

        def trans_guarded_pick(state: State, acts: Activities) -> list[Successor]:
            out: list[Successor] = []
            for variables, body in branches:
                if rejects(state, variables, ctx):
                    sem.pruned_bindings += 1
                    continue
                out.extend(body(state, acts))
            return out

        return trans_guarded_pick

    def guarded_call(self, s: ast.Pick) -> Symbol:
        """The action called inside the `pick`s of a pick guard."""
        body: ast.Statement = s
        while isinstance(body, ast.Pick):
            body = body.body
        assert isinstance(body, ast.CallStmt)
        return self.sem.callee(body)

    def _statically_guarded_pick(
        self, guard: PickGuard, branches: list[tuple[dict[int, Value], TransFn]], passed: list[TransFn]
    ) -> TransFn:
        """A guarded `pick` whose guard arguments read only variables: the guard's bindings
        for every value are made once (`PickGuard.rejects` = `bind`, then `rejects_bound`, an
        error in either meaning "not rejected")."""
        sem, ctx = self.sem, self.sem.ctx
        bound: list[tuple[dict[int, Value] | None, TransFn, TransFn]] = []
        for (variables, body), body_passed in zip(branches, passed, strict=True):
            try:
                bindings = guard.bind(Env(_EMPTY, variables, ctx))
            except GppRuntimeError:
                bindings = None
            bound.append((bindings, body, body_passed))
        rejects_bound = guard.rejects_bound

        def trans_guarded_pick(state: State, acts: Activities) -> list[Successor]:
            out: list[Successor] = []
            for bindings, body, body_passed in bound:
                if bindings is not None:
                    try:
                        rejected = rejects_bound(state, bindings, ctx)
                    except GppRuntimeError:
                        out.extend(body(state, acts))  # not rejected, nothing known
                        continue
                    if rejected:
                        sem.pruned_bindings += 1
                        continue
                    out.extend(body_passed(state, acts))  # the guard's conjuncts hold
                    continue
                out.extend(body(state, acts))
            return out

        return trans_guarded_pick

    def _procedure_call(self, s: ast.CallStmt, frame: Frame) -> TransFn:
        sem = self.sem
        name = sem.callee(s).name

        def trans_call(state: State, acts: Activities) -> list[Successor]:
            body, inner = sem.procedure_body(s, name, state, frame)
            return self.code_trans(body, inner)(state, acts)

        return trans_call

    def _static(self, e: ast.Expr) -> bool:
        return reads_only_variables(self.model, e)

    def _action_call(self, s: ast.CallStmt, frame: Frame, known: frozenset[int]) -> TransFn:
        sem = self.sem
        call = s.call
        generic: TransFn = lambda state, acts: sem.trans_code(s, frame, state, acts)  # noqa: E731
        if not isinstance(call, ast.Call) or not all(self._static(a) for a in call.args):
            return generic
        try:
            action, g = sem.ground_call(call, frame, _EMPTY)
        except GppRuntimeError:
            return generic  # raised again, where the semantics raises it
        ctx = sem.ctx
        bindings = dict(zip(action.param_ids, g.args, strict=True))
        checks: list[Evaluator] = []
        ends_false = False
        for check, expr in action.precondition:
            if id(check) in known:
                continue  # true whenever this is called: `all` goes on to the next conjunct
            if self._static(expr):
                try:
                    value = check(Env(_EMPTY, bindings, ctx))
                except GppRuntimeError:
                    checks.append(check)  # raises when it is reached, as the semantics' does
                    continue
                if value is True:
                    continue  # true in every state: `all` goes on to the next conjunct
                ends_false = True  # false in every state: `all` stops here
                break
            checks.append(check)
        done = [(DONE, DoStep(g, s.span))]
        running = ActivityStatus.RUNNING

        def trans_action(state: State, acts: Activities) -> list[Successor]:
            if acts.status(g) is running:
                return []
            env = Env(state, bindings, ctx)
            for check in checks:
                if check(env) is not True:
                    return []
            return [] if ends_false else list(done)

        return trans_action
