"""Python source generated from a program's expressions, compiled once: what the planner runs
instead of the closures of gpp.runtime.compiled when it evaluates a condition millions of times.

A `Unit` is one generated function: its lines, its constants (passed in as the arguments of a
factory, so the function reads them as closure cells) and a table of spans. `ExprGen` writes
the source of an expression for known values of its variables (a `pick` frame, an action's
arguments): variables and everything computed from them alone are folded to constants, a
fluent instance with known arguments becomes one dictionary lookup of its slot, a function is
inlined for known arguments, and a quantifier over a domain is unrolled (one term per value).

The generated code is exactly the closures' evaluation (SEMANTICS §3): the same reads in the
same order, `null` in a condition false, `==` as `same`. Only a part of the language is
written out (literals, variables, fluents, functions, `!`, `&`, `|`, `->`, `==`, `!=`, `<`,
`<=`, `>`, `>=`, `if`-expressions, quantifiers); an expression with anything else (arithmetic,
lists, compounds, the clock, exogenous functions, a recursive function) is evaluated by its
compiled closure, called from the generated code. The written-out part raises one error only,
an ordering comparison with `null`: the generated code raises it with the message of the
closure and the span found by index in the unit's table of spans.

`GPP_DUMP_CODE=1` in the environment prints every unit's source to stderr when it is built;
`Unit.source` gives it to a program.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from typing import Any

from gpp.base.source import Span
from gpp.codes import R0002
from gpp.model.symbols import SymbolKind
from gpp.model.types import Sym, Type
from gpp.runtime.compiled import CompiledProgram, Env, domain_values
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.values import Value, same
from gpp.syntax import ast
from gpp.syntax.walk import walk

Op = ast.BinaryOp

# Unrolled quantifiers over more values than this are evaluated by their closure.
MAX_UNROLL = 64
# Functions inlined into each other deeper than this are evaluated by their closure.
MAX_INLINE = 8

DUMP_VARIABLE = "GPP_DUMP_CODE"


class Unsupported(Exception):
    """An expression the generator does not write out (its closure evaluates it)."""


def order_error(op: str, span: Span) -> GppRuntimeError:
    """The closures' error for an ordering comparison with `null` (gpp.runtime.compiled)."""
    return GppRuntimeError(R0002.compares_null(op), span)


def _ordered(a: Value, b: Value, op: str, spans: list[Span], i: int) -> bool:
    """`a op b` for an ordering comparison: what the closure's `order` does, its span the
    unit's i-th."""
    if a is None or b is None:
        raise order_error(op, spans[i])
    if isinstance(a, Sym):
        a, b = a.name, b.name  # type: ignore[union-attr]
    if op == "<":
        return a < b  # type: ignore[operator]
    if op == "<=":
        return a <= b  # type: ignore[operator]
    if op == ">":
        return a > b  # type: ignore[operator]
    return a >= b  # type: ignore[operator]


# The names generated code finds as globals.
NAMESPACE: dict[str, object] = {
    "Env": Env,
    "GppRuntimeError": GppRuntimeError,
    "Sym": Sym,
    "_ordered": _ordered,
    "same": same,
}


class Unit:
    """One generated function: `def name(params): body`, with constants and spans."""

    def __init__(self, name: str, params: str, state: str = "state") -> None:
        self.name = name
        self.state = state
        # The fluent instances the code reads (slot -> the source of its initial value), read
        # once at the start into `_s<slot>` (a read neither raises nor changes anything), and
        # those compared with symbols, whose symbol name is kept in `_n<slot>` (None: not a symbol).
        self.reads: dict[int, str] = {}
        self.symbol_reads: set[int] = set()
        # Quantifiers that only compare fluents (they neither raise nor change anything),
        # evaluated once at the start into `_q<n>` (their source -> the name).
        self.hoisted: dict[str, str] = {}
        self.params = params
        self.lines: list[str] = []
        self.consts: list[object] = []
        self.notes: list[str] = []
        self._const_names: dict[int, str] = {}
        self.spans: list[Span] = []
        self._temps = 0
        self.source = ""

    def const(self, value: object, note: str = "") -> str:
        """The name of a constant (the same object, the same name)."""
        name = self._const_names.get(id(value))
        if name is None:
            name = self._const_names[id(value)] = f"k{len(self.consts)}"
            self.consts.append(value)
            self.notes.append(note or _short(repr(value)))
        return name

    def hoist(self, text: str) -> str:
        """The name of a local holding the value of `text`, computed at the start."""
        name = self.hoisted.get(text)
        if name is None:
            name = self.hoisted[text] = f"_q{len(self.hoisted) + 1}"
        return name

    def span(self, span: Span) -> int:
        self.spans.append(span)
        return len(self.spans) - 1

    def temp(self, prefix: str = "t") -> str:
        self._temps += 1
        return f"_{prefix}{self._temps}"

    def emit(self, depth: int, text: str) -> None:
        self.lines.append("    " * (depth + 2) + text)

    def close(self, depth: int, mark: int) -> None:
        """End a block opened when the unit had `mark` lines: `pass` if it has no statement."""
        if all(line.lstrip().startswith("#") for line in self.lines[mark:]):
            self.emit(depth, "pass")

    def build(self) -> Callable[..., Any]:
        """Compile the unit once and return the function."""
        return build_units([self])[0]

    def write(self) -> str:
        """The unit's source: a factory `_make_<name>` taking the constants, returning the function."""
        header = [f"# {name} = {note}" for name, note in zip(self._names(), self.notes, strict=True)]
        args = ", ".join(self._names())
        body = self._prologue() + (self.lines or ["        pass"])
        self.source = "\n".join(
            [
                *header,
                f"def _make_{self.name}({args}):",
                f"    def {self.name}({self.params}):",
                *body,
                f"    return {self.name}",
            ]
        )
        return self.source

    def _prologue(self) -> list[str]:
        if not self.reads:
            return []
        lines = [f"_held = {self.state}.held()"]
        lines += [f"_s{slot} = _held.get({slot}, {initial})" for slot, initial in self.reads.items()]
        lines += [f"_n{slot} = _s{slot}.name if type(_s{slot}) is Sym else None" for slot in sorted(self.symbol_reads)]
        lines += [f"{name} = {text}" for text, name in self.hoisted.items()]
        return ["        " + line for line in lines]

    def _names(self) -> list[str]:
        return [f"k{i}" for i in range(len(self.consts))]


class CompileCache:
    """The factories of generated source, by the source's exact text: a planning that writes
    the same source as an earlier one (the same program planned again, online re-planning,
    a repeated `solve`, a program checked again) skips `compile` and `exec`. The text is the
    whole of what is compiled (the constants are not in it: they are the factory's arguments,
    given anew to every build), so equal texts give equal code. At most `limit` sources are
    kept, the least recently used dropped first."""

    def __init__(self, limit: int = 1024) -> None:
        self.limit = limit
        self._factories: dict[str, list[Callable[..., Any]]] = {}
        self.hits = 0
        self.misses = 0

    def factories(self, units: list[Unit]) -> list[Callable[..., Any]]:
        """The factories of `units` (written by now), compiled together on a miss."""
        source = "\n\n".join(unit.source for unit in units)
        known = self._factories.pop(source, None)
        if known is not None:
            self.hits += 1
        else:
            self.misses += 1
            namespace = dict(NAMESPACE)
            exec(compile(source, f"<gpp generated {units[0].name}>", "exec"), namespace)
            known = [namespace[f"_make_{unit.name}"] for unit in units]  # type: ignore[misc]
            if len(self._factories) >= self.limit:
                del self._factories[next(iter(self._factories))]
        self._factories[source] = known  # the most recently used last
        return known

    def __len__(self) -> int:
        return len(self._factories)

    def clear(self) -> None:
        self._factories.clear()
        self.hits = self.misses = 0


COMPILE_CACHE = CompileCache()


def build_units(units: list[Unit]) -> list[Callable[..., Any]]:
    """Compile units together (one call of `compile`, the costly part for small ones; once per
    source text in the process, see `CompileCache`) and return their functions, in order.
    Unit names must differ."""
    for unit in units:
        unit.write()
    if os.environ.get(DUMP_VARIABLE):
        print("\n\n".join(unit.source for unit in units), end="\n\n", file=sys.stderr)
    factories = COMPILE_CACHE.factories(units)
    return [make(*unit.consts) for make, unit in zip(factories, units, strict=True)]


def _short(text: str) -> str:
    text = text.replace("\n", " ")
    return text if len(text) <= 60 else text[:57] + "..."


class Val:
    """An expression's generated value: a constant (folded), or source text. Never changed
    once made (a plain class: thousands are made per program point)."""

    __slots__ = ("boolean", "const", "slot", "text", "value")

    def __init__(
        self, const: bool, value: Value = None, text: str = "", boolean: bool = False, slot: int | None = None
    ) -> None:
        self.const = const
        self.value = value
        self.text = text
        self.boolean = boolean  # the text's value is always a bool
        self.slot = slot  # the text reads this fluent instance (`_s<slot>`)


def _constant(v: Value) -> Val:
    return Val(True, v)


class ExprGen:
    """Expressions of `program` written into `unit`."""

    def __init__(self, program: CompiledProgram, unit: Unit) -> None:
        self.program = program
        self.model = program.model
        self.unit = unit
        self._inlining: list[str] = []
        # Quantifiers written, by (expression, variables): the same text for the same values.
        self._quantifiers: dict[tuple[int, frozenset[tuple[int, type, Value]]], Val] = {}
        self._free: dict[int, tuple[int, ...] | None] = {}  # a quantifier's id -> the variables it reads

    def _variables_read(self, e: ast.Quantified, bound: int) -> tuple[int, ...] | None:
        """The variables (and parameters) `e` reads, but its own; None if the checker
        rewrote a part of it (then it is not cached)."""
        found: set[int] = set()
        for node in walk(e):
            if self.model.effective(node) is not node:  # type: ignore[arg-type]
                return None
            if isinstance(node, ast.Name):
                target = self.model.target(node)
                if target is not None and target.kind in (SymbolKind.VARIABLE, SymbolKind.PARAMETER):
                    found.add(id(target))
        found.discard(bound)
        return tuple(sorted(found))

    # ---------------------------------------------------------------- conditions

    def condition(self, e: ast.Expr, scope: dict[int, Value]) -> Val:
        """`e is True` (a condition), as a constant or a bool-valued text. Raises Unsupported."""
        return self._truth(self.expr(e, scope))

    def _truth(self, v: Val) -> Val:
        if v.const:
            return _constant(v.value is True)
        if v.boolean:
            return v
        return Val(False, text=f"({v.text} is True)", boolean=True)

    def text(self, v: Val) -> str:
        if not v.const:
            return v.text
        value = v.value
        if value is None or type(value) in (bool, int, str) or (type(value) is float and value - value == 0.0):
            return repr(value)
        return self.unit.const(value)

    # ---------------------------------------------------------------- expressions

    def expr(self, e: ast.Expr, scope: dict[int, Value]) -> Val:
        e = self.model.effective(e)
        if isinstance(e, ast.NumberLit | ast.StringLit | ast.BoolLit):
            return _constant(e.value)
        if isinstance(e, ast.NullLit):
            return _constant(None)
        if isinstance(e, ast.Name):
            target = self.model.target(e)
            if target is not None and target.kind is SymbolKind.SYMBOL:
                return _constant(Sym(e.name))
            if target is None or id(target) not in scope:
                raise Unsupported
            return _constant(scope[id(target)])
        if isinstance(e, ast.Call):
            return self._call(e, scope)
        if isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT:
            operand = self._truth(self.expr(e.operand, scope))
            if operand.const:
                return _constant(not operand.value)
            return Val(False, text=f"(not {operand.text})", boolean=True)
        if isinstance(e, ast.Binary):
            return self._binary(e, scope)
        if isinstance(e, ast.Conditional):
            condition = self._truth(self.expr(e.condition, scope))
            if condition.const:
                return self.expr(e.then if condition.value else e.otherwise, scope)
            then, otherwise = self.expr(e.then, scope), self.expr(e.otherwise, scope)
            return Val(
                False,
                text=f"({self.text(then)} if {condition.text} else {self.text(otherwise)})",
                boolean=_is_bool(then) and _is_bool(otherwise),
            )
        if isinstance(e, ast.Quantified):
            return self._quantifier(e, scope)
        raise Unsupported

    def _call(self, e: ast.Call, scope: dict[int, Value]) -> Val:
        symbol = self.model.target(e)
        if symbol is None:
            raise Unsupported
        args = [self.expr(a, scope) for a in e.args]
        if not all(a.const for a in args):
            raise Unsupported
        values = tuple(a.value for a in args)
        if symbol.kind is SymbolKind.FLUENT:
            if symbol.predefined and symbol.name == "context_time":
                raise Unsupported
            slot = self.program.slot(symbol.name, values)
            if slot not in self.unit.reads:
                self.unit.reads[slot] = self.text(_constant(self.program.initial(slot)))
            return Val(False, text=f"_s{slot}", slot=slot)
        if symbol.kind is SymbolKind.FUNCTION:
            decl = symbol.decl
            if (
                not isinstance(decl, ast.FunctionDecl)
                or decl.body is None
                or symbol.name in self._inlining
                or len(self._inlining) >= MAX_INLINE
            ):
                raise Unsupported
            params, _ = self.program.function(symbol.name)
            self._inlining.append(symbol.name)
            try:
                return self.expr(decl.body, dict(zip(params, values, strict=True)))
            finally:
                self._inlining.pop()
        raise Unsupported

    def _binary(self, e: ast.Binary, scope: dict[int, Value]) -> Val:
        op = e.op
        if op in (Op.AND, Op.OR, Op.IMPLIES):
            left = self._truth(self.expr(e.left, scope))
            if op is Op.IMPLIES:
                left = _constant(not left.value) if left.const else Val(False, text=f"(not {left.text})", boolean=True)
            # `a & b`: b only when a holds; `a | b` (and `!a | b`): b only when a does not.
            decided = op is Op.AND
            if left.const:
                if left.value is not decided:
                    return _constant(left.value)
                return self._truth(self.expr(e.right, scope))
            right = self._truth(self.expr(e.right, scope))
            word = "and" if op is Op.AND else "or"
            return Val(False, text=f"({left.text} {word} {self.text(right)})", boolean=True)
        if op in (Op.EQ, Op.NE):
            return self._equal(e, scope, negate=op is Op.NE)
        if op in (Op.LT, Op.LE, Op.GT, Op.GE):
            left, right = self.expr(e.left, scope), self.expr(e.right, scope)
            # The spans of the errors the generated code raises, found by index.
            spans = self.unit.const(self.unit.spans, "the unit's spans")
            index = self.unit.span(e.span)
            return Val(
                False,
                text=f"_ordered({self.text(left)}, {self.text(right)}, {op.value!r}, {spans}, {index})",
                boolean=True,
            )
        raise Unsupported

    def _equal(self, e: ast.Binary, scope: dict[int, Value], negate: bool) -> Val:
        left, right = self.expr(e.left, scope), self.expr(e.right, scope)
        if left.const and right.const:
            return _constant(same(left.value, right.value) is not negate)
        if left.const or right.const:
            known, other = (left, right) if left.const else (right, left)
            value = known.value
            if value is None or value is True or value is False:
                # same(x, null) is `x is None`; same(x, true) is `x is True`.
                return Val(False, text=f"({other.text} is {'not ' if negate else ''}{value!r})", boolean=True)
            if type(value) is Sym and other.slot is not None:
                self.unit.symbol_reads.add(other.slot)
                return Val(False, text=f"(_n{other.slot} {'!=' if negate else '=='} {value.name!r})", boolean=True)
            if type(value) is Sym:
                t = self.unit.temp()
                test = f"(type({t} := {other.text}) is Sym and {t}.name == {value.name!r})"
                return Val(False, text=f"(not {test})" if negate else test, boolean=True)
        test = f"same({self.text(left)}, {self.text(right)})"
        return Val(False, text=f"(not {test})" if negate else test, boolean=True)

    def _quantifier(self, e: ast.Quantified, scope: dict[int, Value]) -> Val:
        variable = self.model.target(e.var)
        if variable is None:
            raise Unsupported
        values = domain_values(variable.type, self.model)
        if len(values) > MAX_UNROLL:
            raise Unsupported
        # Values told apart by type too (1, 1.0 and true are one dict key); others not kept.
        key = None
        if id(e) not in self._free:
            self._free[id(e)] = self._variables_read(e, id(variable))
        free = self._free[id(e)]
        if free is not None and all(k in scope and type(scope[k]) in _KEYED for k in free):
            key = (id(e), frozenset((k, type(scope[k]), scope[k]) for k in free))
            known = self._quantifiers.get(key)
            if known is not None:
                return known
        made = self._unrolled(e, scope, variable.type)
        if key is not None:
            self._quantifiers[key] = made
        return made

    def _unrolled(self, e: ast.Quantified, scope: dict[int, Value], domain: Type | None) -> Val:
        variable = self.model.target(e.var)
        assert variable is not None
        values = domain_values(domain, self.model)
        exists = e.quantifier is ast.Quantifier.EXISTS
        spans = len(self.unit.spans)
        # exists: the first value whose body holds decides; forall: the first that does not.
        terms: list[str] = []
        for v in values:
            body = self._truth(self.expr(e.body, {**scope, id(variable): v}))
            if body.const:
                if body.value is exists:
                    if not terms:
                        return _constant(exists)
                    terms.append(repr(exists))
                    break
                continue
            terms.append(body.text)
        if not terms:
            return _constant(not exists)
        text = terms[0] if len(terms) == 1 else "(" + (" or " if exists else " and ").join(terms) + ")"
        if len(self.unit.spans) == spans:
            # Nothing in it can raise: computed once, at the start (the same quantifier is
            # often read for many bindings: `clear(y)` for every `x`).
            text = self.unit.hoist(text)
        return Val(False, text=text, boolean=True)


# Types whose values are keys of the quantifier cache as they are (with their type).
_KEYED = (Sym, str, type(None), bool, int, float)


def _is_bool(v: Val) -> bool:
    return v.boolean if not v.const else type(v.value) is bool


def state_function(program: CompiledProgram, e: ast.Expr, variables: dict[int, Value], name: str) -> Unit | None:
    """A unit computing the value of `e` in a state (`def name(state)`), with these values of
    its variables; None when the generator does not write `e` out (its closure evaluates it)."""
    unit = Unit(name, "state")
    try:
        v = ExprGen(program, unit).expr(e, variables)
    except Unsupported:
        return None
    unit.emit(0, f"return {ExprGen(program, unit).text(v)}")
    return unit
