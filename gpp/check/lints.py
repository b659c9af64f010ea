"""Lints: warnings about programs that are legal but probably not what was meant.

Each lint is one small function registered under its code (gpp.codes holds its name and
summary) that reads the code model and yields warnings. Only what is declared or written in the
root files (the files asked for) is linted, never the library files they include; uses
anywhere in the program count, though.

Each lint is registered as local or global (`_lint(code, local=...)`, with the reason beside
it). A local lint finds what it looks at only through what `_Program` can restrict to some
of the declarations (`declarations`, `nodes`, `chained_expressions`, `statements_where`,
`root_globals`, `linted`): after an edit, the language server lints only the declarations
that changed with them and keeps the other warnings (gpp.check.lintmemo). A global lint reads
the whole program (`body_statements`, `call_sites`, `used`, ...) and always runs over all of it.
"""

from __future__ import annotations

import itertools
import math
from bisect import bisect_left, bisect_right
from collections import defaultdict
from collections.abc import Callable, Collection, Iterable, Iterator, Sequence
from dataclasses import dataclass
from functools import cached_property, partial
from pathlib import Path
from typing import Any, TypeVar, assert_never, get_args

from gpp import codes
from gpp.base import diagnostics as diag
from gpp.base.source import Span
from gpp.model.declarations import placeholders_in
from gpp.model.model import Model
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import BOOL, ERROR, DomainType, DomainValue, Sym, Type, base, show_value
from gpp.syntax import ast
from gpp.syntax.fast import LEAVES, PUSH_CHILDREN
from gpp.syntax.loader import ParsedFile
from gpp.syntax.printer import format_expr
from gpp.syntax.walk import children, sub_statements, walk

Op = ast.BinaryOp
# A statement, and whether it is lexically inside `solve` or `search`.
_Placed = tuple[ast.Statement, bool]
N = TypeVar("N", bound=ast.Node)
S = TypeVar("S", bound=ast.Statement)

# `pick`/quantifier variables, parameters: everything W0102 and W0111 look at. (Tuples: a
# membership test compares identities, cheaper than hashing an enum member.)
_LOCAL_KINDS = (SymbolKind.PARAMETER, SymbolKind.VARIABLE)
# W0101 looks at these kinds of globals.
_USABLE_KINDS = (
    SymbolKind.FLUENT,
    SymbolKind.ACTION,
    SymbolKind.FUNCTION,
    SymbolKind.EXOG_FUNCTION,
    SymbolKind.PROCEDURE,
)
# Called by the runtime, not by the program.
_ENTRY_POINTS = frozenset({"main", "postcond"})
# W0103 enumerates at most this many instances of a fluent (and skips larger fluents).
MAX_INSTANCES = 10_000
# Every kind of statement (for `_Program.statements_where`).
_ALL_STATEMENTS: tuple[type[ast.Statement], ...] = get_args(ast.Statement)
# W0110 analyses operator chains up to this many operators.
MAX_CHAIN = 100


def run_lints(model: Model, roots: Collection[Path], allow: Collection[str] = ()) -> list[diag.Diagnostic]:
    """All lint warnings about the declarations and code of the files in `roots`; `allow`
    names lints to skip, by code (`W0101`) or name (`unused`)."""
    program = _Program(model, roots)
    skipped = skipped_lints(allow)
    found: list[diag.Diagnostic] = []
    for code, lint in LINTS.items():
        if code not in skipped:
            found.extend(lint(program))
    return found


def run_lints_split(
    model: Model, roots: Collection[Path], allow: Collection[str], relint: Collection[ast.Decl] | None
) -> tuple[list[diag.Diagnostic], list[diag.Diagnostic]]:
    """The warnings of `run_lints`, split: those of the global lints (over the whole program),
    and those of the local lints about the declarations `relint` of the root files only (all of
    them when None). Each list in `run_lints`' order, the other list's warnings left out."""
    program = _Program(model, roots, relint)
    skipped = skipped_lints(allow)
    global_: list[diag.Diagnostic] = []
    local: list[diag.Diagnostic] = []
    for code, lint in LINTS.items():
        if code not in skipped and (code not in LOCAL or relint is None or relint):
            (local if code in LOCAL else global_).extend(lint(program))
    return global_, local


def skipped_lints(allow: Collection[str]) -> frozenset[str]:
    """The codes of the lints `allow` names (by code or name)."""
    return frozenset(info.code for info in map(codes.lookup, allow) if info is not None)


# ---------------------------------------------------------------- the program as lints see it


@dataclass(frozen=True, slots=True)
class _CallSite:
    caller: Symbol | None  # the procedure whose body holds the call
    callee: Symbol
    planning: bool  # lexically inside `solve` or `search`


class _Program:
    """The model plus the facts several lints share, computed on first use."""

    def __init__(self, model: Model, roots: Collection[Path], relint: Collection[ast.Decl] | None = None) -> None:
        self.model = model
        self.root_files = [f for f in model.files if f.path in roots]
        self._root_sources = {id(f.source) for f in self.root_files}
        self._statements: dict[int, list[_Placed]] = {}
        # The declarations the local lints look at (`declarations`): all of the root files',
        # or those `relint` names; the starts and ends of the latter per source.
        asked = None if relint is None else {id(d) for d in relint}
        self._relint = None if asked is None else [d for d in self.all_declarations() if id(d) in asked]
        self._relint_spans: dict[int, tuple[list[int], list[int]]] = {}
        for d in self._relint or ():
            starts, ends = self._relint_spans.setdefault(id(d.span.source), ([], []))
            starts.append(d.span.start)
            ends.append(d.span.end)

    def in_root(self, span: Span | None) -> bool:
        return span is not None and id(span.source) in self._root_sources

    def all_declarations(self) -> Iterator[ast.Decl]:
        """The declarations of the root files."""
        for f in self.root_files:
            yield from f.program.declarations

    # What the local lints read: the declarations of the root files to lint (`relint`), the
    # nodes and statements in them.

    def declarations(self) -> Iterator[ast.Decl]:
        """The declarations to lint: those of the root files, or those asked for."""
        return self.all_declarations() if self._relint is None else iter(self._relint)

    def linted(self, span: Span | None) -> bool:
        """Is `span` in one of the declarations to lint (anywhere, when all are)? A local lint
        that does not go by `nodes` asks it of where it would warn."""
        if self._relint is None:
            return True
        if span is None:
            return False
        starts, ends = self._relint_spans.get(id(span.source), ([], []))
        k = bisect_right(starts, span.start) - 1
        return k >= 0 and span.end <= ends[k]

    def root_globals(self) -> Iterator[Symbol]:
        """The globals declared in the root files; when not all declarations are linted, only
        those whose declaration (the defining one: its parameters are the symbol's) is."""
        relint = None if self._relint is None else {id(d) for d in self._relint}
        for g in self.model.globals.values():
            if self.in_root(g.span) and (relint is None or id(g.decl) in relint):
                yield g

    @cached_property
    def _nodes(self) -> _Nodes:
        if self._relint is None:
            return _index_nodes([f.program for f in self.root_files], self.model.rewritten)
        return _index_nodes(self._relint, self.model.rewritten)

    def nodes(self, kind: type[N]) -> list[N]:
        """The syntax nodes of one class in the declarations to lint, in source order per file."""
        return self._nodes.by_type.get(kind, [])  # type: ignore[return-value]

    def chained_expressions(self) -> list[ast.Expr]:
        """The outermost expressions of the declarations to lint in which an operator has
        another one as its operand (or that the model regrouped), in source order: the others
        hold no chain of two operators."""
        return self._nodes.chained

    def statements_where(self, kinds: tuple[type[ast.Statement], ...], test: Callable[[Any], bool]) -> _Within:
        """The statements of the declarations to lint of `kinds` that pass `test`, to ask
        which of them a statement holds (without walking its body: nested loops would make
        that quadratic)."""
        classes = frozenset(kinds)
        return self._all_statements.where(lambda s: type(s) in classes and test(s))

    def root_statements(self, kind: type[S]) -> Iterator[S]:
        """The statements of one class in the root files, in source order per file (as
        `nodes` without a list of `relint`)."""
        for _, found in self.body_statements(self.root_files):
            for s, _ in found:
                if type(s) is kind:
                    yield s

    @cached_property
    def _all_statements(self) -> _Within:
        """Every statement of the declarations to lint: those of their bodies, the only place
        for one. (Listed now, sorted when first asked about; the index refers to the lists, not
        to the program, which keeps the `_Within`: no reference cycle.)"""
        listed: dict[int, list[ast.Statement]] = {id(f.source): [] for f in self.root_files}
        for decl in self.declarations():
            for _, found in self._statements_of(self._bodies_in([decl])):
                listed[id(decl.span.source)].extend(s for s, _ in found)
        return _Within(partial(_by_start, listed))

    def used(self, symbol: Symbol) -> bool:
        """Is `symbol` named anywhere but in its declarations (and, for a global, its own body)?"""
        return id(symbol) in self._used

    @cached_property
    def _used(self) -> set[int]:
        """The symbols (by id) that `used` says yes to, from one pass over the references."""
        found: set[int] = set()
        for r in self.model.references:
            symbol = r.symbol
            if r.declaration or id(symbol) in found:
                continue
            if symbol.decl is not None and symbol.kind in _USABLE_KINDS:
                own, at = symbol.decl.span, r.span
                if at.source is own.source and own.start <= at.start < own.end:
                    continue  # in its own declaration
            found.add(id(symbol))
        return found

    def bodies(self, files: Sequence[ParsedFile]) -> Iterator[tuple[Symbol | None, ast.Statement]]:
        """The statement bodies of the procedures (and legacy main block) in `files`."""
        for f in files:
            yield from self._bodies_in(f.program.declarations)

    def _bodies_in(self, decls: Iterable[ast.Decl]) -> Iterator[tuple[Symbol | None, ast.Statement]]:
        for decl in decls:
            if isinstance(decl, ast.ProcedureDecl) and decl.body is not None:
                yield self.model.target(decl.name), decl.body
            elif isinstance(decl, ast.MainBlock):
                main = self.model.main
                yield (main if main is not None and main.decl is decl else None), decl.body

    def body_statements(self, files: Sequence[ParsedFile]) -> Iterator[tuple[Symbol | None, list[_Placed]]]:
        """The `statements` of each body in `files` (as `bodies`), listed once per program."""
        return self._statements_of(self.bodies(files))

    def _statements_of(
        self, bodies: Iterable[tuple[Symbol | None, ast.Statement]]
    ) -> Iterator[tuple[Symbol | None, list[_Placed]]]:
        for owner, body in bodies:
            found = self._statements.get(id(body))
            if found is None:
                found = self._statements[id(body)] = statements(body)
            yield owner, found

    @cached_property
    def call_sites(self) -> list[_CallSite]:
        """Every procedure call of the whole program (included files too)."""
        sites: list[_CallSite] = []
        for caller, found in self.body_statements(self.model.files):
            for s, planning in found:
                if isinstance(s, ast.CallStmt):
                    callee = self.model.target(s.call)
                    if callee is not None and callee.kind is SymbolKind.PROCEDURE:
                        sites.append(_CallSite(caller, callee, planning))
        return sites

    @cached_property
    def planning_only(self) -> set[int]:
        """Procedures (by id) that run only while planning: called, and every call is inside
        `solve` or `search`, or in a procedure that itself runs only while planning."""
        called = {id(site.callee) for site in self.call_sites}
        # The calls outside `solve` and `search`, by caller; a procedure they reach runs online.
        online_calls: dict[int, list[int]] = {}
        online: set[int] = set()
        for site in self.call_sites:
            if site.planning:
                continue
            if site.caller is None or id(site.caller) not in called:
                online.add(id(site.callee))  # called from where nothing calls
            else:
                online_calls.setdefault(id(site.caller), []).append(id(site.callee))
        _reach(online, online_calls)
        return called - online

    @cached_property
    def choosing(self) -> set[int]:
        """Procedures (by id) whose body, following calls, contains a `pick` or `choose`."""
        found: set[int] = set()
        for caller, statements_ in self.body_statements(self.model.files):
            if caller is not None and any(isinstance(s, ast.Pick | ast.Choose) for s, _ in statements_):
                found.add(id(caller))
        callers: dict[int, list[int]] = {}
        for site in self.call_sites:
            if site.caller is not None:
                callers.setdefault(id(site.callee), []).append(id(site.caller))
        _reach(found, callers)
        return found


def _reach(reached: set[int], edges: dict[int, list[int]]) -> None:
    """Add to `reached` everything its members lead to along `edges` (each edge read once)."""
    pending = list(reached)
    while pending:
        for target in edges.get(pending.pop(), ()):
            if target not in reached:
                reached.add(target)
                pending.append(target)


@dataclass(frozen=True, slots=True)
class _Nodes:
    """What one walk of the root files finds (`_index_nodes`)."""

    by_type: dict[type[ast.Node], list[ast.Node]]
    chained: list[ast.Expr]  # see `_Program.chained_expressions`


def _index_nodes(tops: Sequence[ast.Node], rewritten: dict[int, ast.Expr]) -> _Nodes:
    """The nodes of the trees `tops` (files' programs, or declarations) by class, in one walk
    (parents before children, as `walk`), and the outermost expressions that hold an operator
    chain."""
    by_type: defaultdict[type[ast.Node], list[ast.Node]] = defaultdict(list)
    chained: list[ast.Expr] = []
    # The loop runs once per node of the program: its names are local.
    push, leaves, expr, binary = PUSH_CHILDREN, LEAVES, ast.Expr, ast.Binary
    for tree in tops:
        stack: list[ast.Node] = [tree]
        while stack:
            top = stack.pop()
            cls = type(top)
            if not isinstance(top, expr):
                by_type[cls].append(top)
                if cls not in leaves:
                    push[cls](top, stack)
                continue
            # An outermost expression: all its nodes now, noting whether an operator has another
            # one as its operand, or the model regrouped one of them.
            has_chain = False
            inner: list[ast.Node] = [top]
            while inner:
                node = inner.pop()
                cls = type(node)
                by_type[cls].append(node)
                if rewritten and id(node) in rewritten:
                    has_chain = True
                if cls in leaves:
                    continue
                push[cls](node, inner)
                if cls is binary and not has_chain:
                    has_chain = _operand_is_operator(node.left) or _operand_is_operator(node.right)  # type: ignore[attr-defined]
            if has_chain:
                chained.append(top)
    return _Nodes(dict(by_type), chained)


def _operand_is_operator(e: ast.Expr) -> bool:
    return isinstance(e, ast.Binary) and not e.parenthesized


_Starts = tuple[list[int], list[ast.Statement]]


def _by_start(listed: dict[int, list[ast.Statement]]) -> dict[int, _Starts]:
    """Per source, its statements sorted by where they start, and those starts."""
    out: dict[int, _Starts] = {}
    for key, found in listed.items():
        starts = [s.span.start for s in found]
        order = sorted(range(len(found)), key=starts.__getitem__)  # stable: ties keep their order
        out[key] = ([starts[k] for k in order], [found[k] for k in order])
    return out


class _Within:
    """Statements by where they start, per file. The statements inside another one (`statements`
    of it, itself included) are those that start within its span: spans nest like the tree.
    They are listed when first asked about: a lint with nothing to ask never pays for it."""

    def __init__(self, index: Callable[[], dict[int, _Starts]]) -> None:
        self._index = index

    def where(self, test: Callable[[ast.Statement], bool]) -> _Within:
        """The statements of these that pass `test` (kept in order: no sorting again)."""

        def index() -> dict[int, _Starts]:
            out: dict[int, _Starts] = {}
            for key, (starts, found) in self._by_source.items():
                kept = [k for k, s in enumerate(found) if test(s)]
                out[key] = ([starts[k] for k in kept], [found[k] for k in kept])
            return out

        return _Within(index)

    @cached_property
    def _by_source(self) -> dict[int, _Starts]:
        """Per source (by id), the starts of its statements and the statements, in order."""
        return self._index()

    def inside(self, s: ast.Statement) -> list[ast.Statement]:
        starts, found = self._by_source.get(id(s.span.source), ([], []))
        first = bisect_left(starts, s.span.start)
        return found[first : bisect_left(starts, s.span.end, first)]

    def any_inside(self, s: ast.Statement) -> bool:
        starts, _ = self._by_source.get(id(s.span.source), ([], []))
        first = bisect_left(starts, s.span.start)
        return first < len(starts) and starts[first] < s.span.end


def statements(body: ast.Statement, planning: bool = False) -> list[_Placed]:
    """Every statement in `body` (parents first, in source order), with whether it is
    lexically inside `solve` or `search`."""
    found: list[_Placed] = []
    stack = [(body, planning)]
    while stack:
        placed = stack.pop()
        found.append(placed)
        s, inside = placed
        inner = sub_statements(s)
        if inner:
            planned = inside or isinstance(s, ast.Solve | ast.Search)
            stack.extend([(c, planned) for c in reversed(inner)])
    return found


def keyword_span(node: ast.Node, keyword: str) -> Span:
    """The leading keyword of a statement (`pick`, `solve`, `while`...)."""
    span = node.span
    if span.text.startswith(keyword):
        return Span(span.source, span.start, span.start + len(keyword))
    return span


# ---------------------------------------------------------------- the registry

Lint = Callable[[_Program], Iterator[diag.Diagnostic]]
LINTS: dict[str, Lint] = {}
# The local lints (see `run_lints_split`, gpp.check.lintmemo): whether and what one warns
# about a node depends only on the top-level declaration holding the node and on the program's
# environment (the declarations but the bodies of procedures, the included files), and it
# warns inside that declaration. The others are global: they read facts across declarations.
LOCAL: set[str] = set()


def _lint(lint: type[codes.Code], local: bool) -> Callable[[Lint], Lint]:
    code = lint.code

    def register(f: Lint) -> Lint:
        assert code in codes.CODES and codes.CODES[code].is_lint, code
        LINTS[code] = f
        if local:
            LOCAL.add(code)
        return f

    return register


# ---------------------------------------------------------------- W0101 unused


# Global: a global counts as used by a reference in any declaration.
@_lint(codes.W0101, local=False)
def unused_declaration(program: _Program) -> Iterator[diag.Diagnostic]:
    for symbol in program.model.globals.values():
        if (
            symbol.kind not in _USABLE_KINDS
            or symbol.predefined
            or symbol.name in _ENTRY_POINTS
            or symbol is program.model.main
            or not program.in_root(symbol.span)
            or program.used(symbol)
        ):
            continue
        assert symbol.span is not None
        yield diag.warning(codes.W0101.unused(symbol.kind, symbol.name), symbol.span)


# ---------------------------------------------------------------- W0102 unused parameter / variable


# Local: a parameter or `pick`/quantifier variable is named only inside the declaration that declares it.
@_lint(codes.W0102, local=True)
def unused_variable(program: _Program) -> Iterator[diag.Diagnostic]:
    for symbol in _params_with_body(program):
        if not program.used(symbol):
            assert symbol.span is not None and symbol.owner is not None
            owner = symbol.owner
            yield diag.warning(
                codes.W0102.parameter(symbol.name, owner.kind, owner.name),
                symbol.span,
            )
    for symbol in _variables(program):
        if not program.used(symbol):
            assert symbol.span is not None
            yield diag.warning(codes.W0102.variable(symbol.name), symbol.span)


def _params_with_body(program: _Program) -> Iterator[Symbol]:
    """Parameters of the functions, procedures and actions defined in the root files whose
    use can be judged: an action without `mapping:` passes every parameter to the platform,
    and an exogenous action's parameters are set by its events. A parameter named as a
    placeholder in the mapped name (`"/{r}/navigate"`) is used by it."""
    for symbol in program.root_globals():
        decl = symbol.decl
        if symbol.predefined or not symbol.is_defined:
            continue
        in_name: set[str] = set()
        if isinstance(decl, ast.ActionDecl):
            section = decl.section(ast.MappingSection)
            if decl.exogenous or not isinstance(section, ast.MappingSection):
                continue
            in_name = set(placeholders_in(section.mapping.name.value))
        elif not isinstance(decl, ast.FunctionDecl | ast.ProcedureDecl):
            continue
        yield from (p for p in symbol.params if p.name not in in_name and program.linted(p.span))


def _variables(program: _Program) -> Iterator[Symbol]:
    """The `pick` and quantifier variables of the root files."""
    nodes: list[ast.Pick | ast.Quantified] = [*program.nodes(ast.Pick), *program.nodes(ast.Quantified)]
    for node in nodes:
        symbol = program.model.target(node.var)
        if symbol is not None and symbol.kind is SymbolKind.VARIABLE:
            yield symbol


# ---------------------------------------------------------------- W0103 uninitialised fluent instances


@dataclass(frozen=True, slots=True)
class _Wildcard:
    """A parameter name in an `initially:` entry: every value in its position."""


_ANY = _Wildcard()
_Key = tuple[str, object]


def _key(v: DomainValue) -> _Key:
    """Values compared as domain members are (2 == 2.0, a symbol is never a string)."""
    if isinstance(v, bool):
        return ("bool", v)
    if isinstance(v, int | float):
        return ("number", float(v))
    if isinstance(v, Sym):
        return ("symbol", v.name)
    return ("string", v)


def _finite_values(t: Type | None) -> tuple[DomainValue, ...] | None:
    """The values of a finite parameter type, or None for an infinite one."""
    if t is BOOL:
        return (False, True)
    if isinstance(t, DomainType):
        return t.values
    return None


# Local: the fluent's own `initially:` entries, against its parameter types (environment).
@_lint(codes.W0103, local=True)
def uninitialized_fluent(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    for decl in program.declarations():
        if not isinstance(decl, ast.FluentDecl):
            continue
        symbol = model.target(decl.name)
        if symbol is None or symbol.decl is not decl or symbol.span is None:
            continue
        if decl.initially is None:
            names = ", ".join(p.name for p in symbol.params)
            yield diag.warning(
                codes.W0103.no_initial_values(symbol.name),
                symbol.span,
                "declared, but never defined with `initially:`",
                notes=["every instance of it starts as `null`"],
                help=f"define it: `{symbol.type} fluent {symbol.name}(...) {{ initially: ({names}) = ...; }}`",
            )
            continue
        missing = _missing_instances(program, symbol, decl.initially)
        if missing is None or not missing[0]:
            continue
        patterns, count, open_params = missing
        names = ", ".join(p.name for p in symbol.params)
        instances = [f"`{symbol.name}({', '.join(p)})`" for p in patterns]
        if count > len(instances):
            instances.append(f"{count - len(instances)} more instance{'s' * (count - len(instances) > 1)}")
        shown = instances[0] if len(instances) == 1 else ", ".join(instances[:-1]) + " and " + instances[-1]
        yield diag.warning(
            codes.W0103.missing_instances(symbol.name, shown, open_params),
            symbol.span,
            "some instances start as `null`",
            notes=["instances that no `initially:` entry covers start as `null`"],
            help=f"add a default entry `({names}) = ...;` before the others (later entries override earlier ones)",
        )


def _missing_instances(
    program: _Program, fluent: Symbol, entries: Sequence[ast.InitialValue]
) -> tuple[list[list[str]], int, list[str]] | None:
    """The instances no entry covers: up to a few of them as argument texts (an infinite
    parameter shown by its name), how many there are, and the infinite parameters among
    them; None when it cannot be told (errors, too many instances)."""
    params = fluent.params
    domains = [_finite_values(p.type) for p in params]
    if any(p.type is None or p.type is ERROR for p in params):
        return None
    patterns: list[tuple[object, ...]] = []
    for entry in entries:
        if len(entry.args) != len(params):
            return None
        pattern: list[object] = []
        for arg, param in zip(entry.args, params, strict=True):
            if isinstance(arg, ast.Name) and program.model.target(arg) is param:
                pattern.append(_ANY)
                continue
            value = _literal(program.model, arg)
            if value is None:
                return None
            pattern.append(_key(value))
        patterns.append(tuple(pattern))
    infinite = [i for i, d in enumerate(domains) if d is None]
    finite = [i for i, d in enumerate(domains) if d is not None]
    # An infinite parameter has values no entry lists; an instance with such values is covered
    # only by entries with a wildcard in every infinite position.
    relevant = [p for p in patterns if all(p[i] is _ANY for i in infinite)]
    exact = {tuple(p[i] for i in finite) for p in relevant if all(p[i] is not _ANY for i in finite)}
    partial = [p for p in relevant if any(p[i] is _ANY for i in finite)]
    size = math.prod(len(d) for d in domains if d is not None)
    if size > MAX_INSTANCES or size * max(1, len(partial)) > 50 * MAX_INSTANCES:
        return None
    if any(all(x is _ANY for x in p) for p in relevant):
        return [], 0, []  # a default entry, `(p1, ..., pn) = ...`, covers every instance
    shown: list[list[str]] = []
    count = 0
    finite_domains = [domains[i] or () for i in finite]
    domain_keys = [[_key(v) for v in d] for d in finite_domains]
    for combo, keys in zip(itertools.product(*finite_domains), itertools.product(*domain_keys), strict=True):
        if keys in exact:
            continue
        at = dict(zip(finite, keys, strict=True))
        if any(all(p[i] is _ANY or p[i] == at[i] for i in finite) for p in partial):
            continue
        count += 1
        if len(shown) < 3:
            values = dict(zip(finite, combo, strict=True))
            shown.append([show_value(values[i]) if i in values else params[i].name for i in range(len(params))])
    return shown, count, [params[i].name for i in infinite] if count else []


def _literal(model: Model, e: ast.Expr) -> DomainValue | None:
    """The value of a literal number, string, bool or domain symbol."""
    if isinstance(e, ast.NumberLit | ast.StringLit | ast.BoolLit):
        return e.value
    if isinstance(e, ast.Name):
        target = model.target(e)
        if target is not None and target.kind is SymbolKind.SYMBOL:
            return Sym(e.name)
    return None


# ---------------------------------------------------------------- W0104 double effect


# Local: the effects of one action.
@_lint(codes.W0104, local=True)
def double_effect(program: _Program) -> Iterator[diag.Diagnostic]:
    for decl in program.declarations():
        if not isinstance(decl, ast.ActionDecl):
            continue
        for section in decl.sections or ():
            if not isinstance(section, ast.EffectSection | ast.StartEffectSection):
                continue  # the start effects and the end effects are applied at different times
            seen: list[ast.Effect] = []
            for effect in section.effects:
                if effect.condition is not None:
                    continue
                first = next((e for e in seen if e.target == effect.target), None)
                if first is None:
                    seen.append(effect)
                    continue
                target = format_expr(effect.target)
                yield diag.warning(
                    codes.W0104.twice(decl.name.name, target),
                    effect.target.span,
                    "assigned again here",
                    secondary=[diag.Label(first.target.span, "first assigned here")],
                    notes=["the effects of an action are applied together; two different values are a run-time error"],
                    help="remove one of the assignments",
                )


# ---------------------------------------------------------------- W0105 pick/choose online


# Global: `planning_only` follows the calls of every procedure body.
@_lint(codes.W0105, local=False)
def online_nondeterminism(program: _Program) -> Iterator[diag.Diagnostic]:
    for owner, found in program.body_statements(program.root_files):
        if owner is not None and id(owner) in program.planning_only:
            continue
        for s, planning in found:
            if planning:
                continue
            if isinstance(s, ast.Pick):
                yield diag.warning(
                    codes.W0105.pick(),
                    keyword_span(s, "pick"),
                    "chosen greedily, without looking ahead",
                    notes=[
                        "online, `pick` commits to the first value (in the order of its `in {...}` list or of "
                        "the domain) that can make a step; it never comes back to try another"
                    ],
                    help="put it inside `search` or `solve(...)` to plan the choice, or write the value",
                )
            elif isinstance(s, ast.Choose) and not all(_guarded(a) for a in s.alternatives):
                yield diag.warning(
                    codes.W0105.choose(),
                    keyword_span(s, "choose"),
                    "chosen greedily, without looking ahead",
                    notes=[
                        "online, `choose` commits to the first alternative that can make a step; "
                        "it never comes back to try another"
                    ],
                    help="put it inside `search` or `solve(...)` to plan the choice, or start every "
                    "alternative with the `test(...)` or hook it waits for",
                )


# Statements that wait for the world: a `choose` whose alternatives all start with one selects
# by what happens (`choose { {finish(a); ...} {fail(a); ...} }`) and is not a blind guess.
_WAITING_HOOKS = frozenset({ast.Hook.END, ast.Hook.FINISH, ast.Hook.FAIL})


def _guarded(s: ast.Statement) -> bool:
    while isinstance(s, ast.Block):
        if not s.body:
            return False
        s = s.body[0]
    return isinstance(s, ast.Test) or (isinstance(s, ast.HookStmt) and s.hook in _WAITING_HOOKS)


# ---------------------------------------------------------------- W0106 busy loop


def _effectful(s: ast.Statement) -> bool:
    """Does `s` itself act, wait or change the state (not counting the statements inside it)?"""
    match s:
        case ast.CallStmt() | ast.HookStmt() | ast.During() | ast.Test() | ast.Assign() | ast.ListStmt():
            return True
        case (
            ast.Block()
            | ast.If()
            | ast.While()
            | ast.Choose()
            | ast.Concurrent()
            | ast.Pick()
            | ast.Solve()
            | ast.Search()
        ):
            # Only the statements inside them can (`statements` visits those).
            return False
        case _:
            assert_never(s)


# Local: the loop and the statements in its body.
@_lint(codes.W0106, local=True)
def busy_loop(program: _Program) -> Iterator[diag.Diagnostic]:
    effectful = program.statements_where(_ALL_STATEMENTS, _effectful)
    for node in program.nodes(ast.While):
        if not _is_true(node.condition):
            continue
        if effectful.any_inside(node.body):
            continue
        yield diag.warning(
            codes.W0106.busy_loop(),
            _while_head(node),
            "loops forever without doing anything",
            notes=["the program can never get past this loop, and nothing in it can change the world"],
            help="call an action or wait with `test(...)` in the body, or give the loop a real condition",
        )


def _is_true(e: ast.Expr) -> bool:
    return isinstance(e, ast.BoolLit) and e.value


def _while_head(s: ast.While) -> Span:
    """`while (cond)`, with the closing parenthesis when it is there."""
    source = s.span.source
    end = s.condition.span.end
    rest = source.text[end : s.body.span.start]
    close = rest.find(")")
    return Span(source, s.span.start, end + close + 1 if close >= 0 else end)


# ---------------------------------------------------------------- W0107 / W0108 constant conditions


@dataclass(frozen=True, slots=True)
class _Condition:
    """A condition a lint looks at, with what its being always true / always false means."""

    expr: ast.Expr
    what: str
    if_true: str
    if_false: str
    help_if_true: str | None = None


def _conditions(program: _Program) -> Iterator[_Condition]:
    """The conditions W0107 judges; `while (true)`, `test(true)` and `precondition: true` are
    idioms, and an `if` with an `else` is W0108's."""
    for s in program.nodes(ast.If):
        if s.otherwise is None:
            yield _Condition(s.condition, "`if` condition", "its body always runs", "its body never runs")
    for w in program.nodes(ast.While):
        if not _is_true(w.condition):
            yield _Condition(
                w.condition,
                "`while` condition",
                "the loop never ends by itself",
                "the loop body never runs",
                "write `while (true)` if an endless loop is meant",
            )
    for t in program.nodes(ast.Test):
        if not _is_true(t.condition):
            blocked = "the test never passes: the program blocks here"
            yield _Condition(t.condition, "`test` condition", "the test always passes", blocked)
    for p in program.nodes(ast.PreconditionSection):
        if not _is_true(p.condition):
            never = "the action can never be executed"
            yield _Condition(p.condition, "precondition", "the action is always possible", never)
    for e in program.nodes(ast.Effect):
        if e.condition is not None:
            yield _Condition(e.condition, "effect condition", "the effect always applies", "the effect never applies")
    for d in program.nodes(ast.During):
        if d.until is not None:
            cancelled = "the activity is cancelled as soon as it starts"
            yield _Condition(d.until, "`until` condition", cancelled, "it never cancels the activity")


# Local: one condition; its names and types come from the environment.
@_lint(codes.W0107, local=True)
def constant_condition(program: _Program) -> Iterator[diag.Diagnostic]:
    for c in _conditions(program):
        value = _constant(program.model, c.expr)
        if value is not None:
            yield diag.warning(
                codes.W0107.constant(c.what, value),
                c.expr.span,
                c.if_true if value else c.if_false,
                help=c.help_if_true if value else None,
            )


# Local: one `if` and its condition.
@_lint(codes.W0108, local=True)
def unreachable_else(program: _Program) -> Iterator[diag.Diagnostic]:
    for node in program.nodes(ast.If):
        if node.otherwise is None:
            continue
        value = _constant(program.model, node.condition)
        if value is True:
            yield diag.warning(
                codes.W0108.else_never_runs(),
                _else_keyword(program, node),
                "unreachable",
                secondary=[diag.Label(node.condition.span, "this condition is always true")],
                help="remove the `else` branch, or fix the condition",
            )
        elif value is False:
            yield diag.warning(
                codes.W0108.if_never_runs(),
                node.condition.span,
                "this condition is always false",
                help="remove the `if` branch, or fix the condition",
            )


def _else_keyword(program: _Program, s: ast.If) -> Span:
    assert s.otherwise is not None
    pf = program.model.file_of(s.span.source)
    tokens = pf.tokens if pf is not None else []
    k = bisect_left(tokens, s.then.span.end, key=lambda t: t.start)
    while k < len(tokens) and tokens[k].start < s.otherwise.span.start:
        if tokens[k].type == "ELSE":
            return Span(s.span.source, tokens[k].start, tokens[k].end)
        k += 1
    return s.otherwise.span


def _constant(model: Model, e: ast.Expr) -> bool | None:
    """The value of a condition that does not depend on the state, or None."""
    e = model.effective(e)
    if isinstance(e, ast.BoolLit):
        return e.value
    if isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT:
        v = _constant(model, e.operand)
        return None if v is None else not v
    if not isinstance(e, ast.Binary):
        return None
    if e.op in (Op.AND, Op.OR, Op.IMPLIES) or (e.op in (Op.EQ, Op.NE) and _is_bool(model, e.left, e.right)):
        p = _constant(model, e.left)
        q = None if p is None else _constant(model, e.right)
        if p is None or q is None:
            return None
        return {Op.AND: p and q, Op.OR: p or q, Op.IMPLIES: not p or q, Op.EQ: p == q, Op.NE: p != q}[e.op]
    if e.op in ast.COMPARISON_OPS:
        x, y = _literal(model, e.left), _literal(model, e.right)
        if x is None or y is None:
            return None
        kx, ky = _key(x), _key(y)
        if kx[0] != ky[0]:
            return None
        if e.op is Op.EQ:
            return kx == ky
        if e.op is Op.NE:
            return kx != ky
        a, b = kx[1], ky[1]
        if isinstance(a, float) and isinstance(b, float):  # noqa: SIM114 (the arms compare different types)
            order = (a > b) - (a < b)
        elif isinstance(a, str) and isinstance(b, str):
            order = (a > b) - (a < b)
        else:
            return None
        return {Op.LT: order < 0, Op.LE: order <= 0, Op.GT: order > 0, Op.GE: order >= 0}[e.op]
    return None


def _is_bool(model: Model, *operands: ast.Expr) -> bool:
    return all(base(model.type_of(x)) is BOOL for x in operands)


# ---------------------------------------------------------------- W0109 solve without choice


# Global: `choosing` follows calls into other procedure bodies.
@_lint(codes.W0109, local=False)
def solve_without_choice(program: _Program) -> Iterator[diag.Diagnostic]:
    for _, found in program.body_statements(program.root_files):
        solves = [s for s, _ in found if isinstance(s, ast.Solve)]
        if not solves:
            continue
        # The statements of this body that choose, to ask which of them a `solve` holds.
        listed = {id(solves[0].span.source): [s for s, _ in found if _chooses(program, s)]}
        choosing = _Within(partial(_by_start, listed))
        for node in solves:
            if choosing.any_inside(node.body):
                continue
            yield diag.warning(
                codes.W0109.no_choice(),
                keyword_span(node, "solve"),
                "no choice to plan",
                notes=["`solve` plans the choices of `pick` and `choose`; without them it only runs the program"],
                help="add the `pick` or `choose` that `solve` should decide, or remove `solve`",
            )


def _chooses(program: _Program, s: ast.Statement) -> bool:
    if isinstance(s, ast.Pick | ast.Choose):
        return True
    if isinstance(s, ast.CallStmt):
        callee = program.model.target(s.call)
        return callee is not None and id(callee) in program.choosing
    return False


# ---------------------------------------------------------------- W0110 mixed precedence

# The precedences the original golog++ gives (LANGUAGE.md §2.6.2); within a family they are also
# the standard levels, loosest first.
_GOLOG_PRECEDENCE: dict[Op, int] = {
    Op.IMPLIES: 0,
    Op.EQ: 0,
    Op.NE: 0,
    Op.OR: 1,
    Op.AND: 2,
    Op.ADD: 1,
    Op.SUB: 1,
    Op.MUL: 2,
    Op.DIV: 2,
    Op.MOD: 2,
    Op.POW: 3,
}

# The operators that always chain, by family (`==` and `!=` do between booleans).
_FAMILIES: dict[Op, str] = {
    **dict.fromkeys(ast.ARITHMETIC_OPS, "arithmetic"),
    **dict.fromkeys(ast.BOOLEAN_OPS, "boolean"),
}

# A chain's tree: a leaf (operand index) or (operator, left, right).
Shape = int | tuple[Op, "Shape", "Shape"]


# Local: one expression; its operand types come from the environment.
@_lint(codes.W0110, local=True)
def mixed_precedence(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    for top in program.chained_expressions():
        yield from _mixed_chains(model, top)


def _mixed_chains(model: Model, top: ast.Expr) -> Iterator[diag.Diagnostic]:
    """W0110's warnings about the chains in the expression `top`."""
    stack = [top]
    while stack:
        e = model.effective(stack.pop())
        if type(e) in LEAVES:
            continue  # a name or a literal: no chain, nothing below
        family = _family(model, e)
        if family is None:
            stack.extend(_sub_expressions(e))
            continue
        operands, operators = _flatten(model, e, family)
        stack.extend(operands)
        if len(operators) < 2 or len(operators) > MAX_CHAIN:
            continue
        if len({_GOLOG_PRECEDENCE[op] for op in operators}) < 2:
            continue
        golog = golog_tree(operators)
        ours = _shape(model, e, family, iter(range(len(operands))))
        if golog != ours:
            yield _precedence_warning(e, operands, golog, ours)


def _precedence_warning(chain: ast.Expr, operands: list[ast.Expr], golog: Shape, ours: Shape) -> diag.Diagnostic:
    texts = [format_expr(x) for x in operands]
    insertions: dict[int, str] = {}
    for start, end in _grouped(ours):
        a, b = operands[start].span.start, operands[end].span.end
        insertions[a] = insertions.get(a, "") + "("
        insertions[b] = ")" + insertions.get(b, "")
    source = chain.span.source
    edits = tuple(diag.Edit(Span(source, at, at), text) for at, text in sorted(insertions.items()))
    return diag.warning(
        codes.W0110.reads_as(render_shape(golog, texts)),
        chain.span,
        "mixes operators of different precedence",
        notes=[f"gpp uses standard precedence: `{render_shape(ours, texts)}`"],
        # gpp already reads it this way: the parentheses change nothing.
        fix=diag.Fix("add parentheses to make it unambiguous", edits, diag.Applicability.SAFE),
    )


def _family(model: Model, e: ast.Expr) -> str | None:
    """`arithmetic` or `boolean` when `e` is an operator of that chain family."""
    if not isinstance(e, ast.Binary):
        return None
    family = _FAMILIES.get(e.op)
    if family is None and e.op in (Op.EQ, Op.NE) and _is_bool(model, e.left, e.right):
        return "boolean"
    return family


def _in_chain(model: Model, e: ast.Expr, family: str) -> bool:
    return not e.parenthesized and _family(model, e) == family


def _flatten(model: Model, root: ast.Expr, family: str) -> tuple[list[ast.Expr], list[Op]]:
    """The operands and operators of the maximal unparenthesised chain at `root`, in order."""
    operands: list[ast.Expr] = []
    operators: list[Op] = []
    stack: list[ast.Expr | Op] = [root]
    while stack:
        item = stack.pop()
        if isinstance(item, Op):
            operators.append(item)
        elif isinstance(item, ast.Binary) and (item is root or _in_chain(model, item, family)):
            stack.extend((item.right, item.op, item.left))
        else:
            operands.append(item)
    return operands, operators


def _shape(model: Model, e: ast.Expr, family: str, leaves: Iterator[int], root: bool = True) -> Shape:
    """The tree gpp built for the chain at `e`, over operand indices."""
    if isinstance(e, ast.Binary) and (root or _in_chain(model, e, family)):
        left = _shape(model, e.left, family, leaves, False)
        return (e.op, left, _shape(model, e.right, family, leaves, False))
    return next(leaves)


def golog_tree(operators: Sequence[Op]) -> Shape:
    """The tree the original golog++ builds for a flat chain `e0 op0 e1 ... en` (LANGUAGE.md
    §2.6.2): the tail is built first, and its root stays below `op0` only if it binds tighter;
    otherwise the chain is split before the last operand."""
    prec = [_GOLOG_PRECEDENCE[op] for op in operators]
    return _golog_build(operators, prec, 0, len(operators))


# The helpers of the shape functions are module functions, not closures: a closure that calls
# itself is a reference cycle (function -> cell -> function), left for the cyclic collector.


def _golog_root(prec: Sequence[int], i: int, j: int) -> int:
    """Index of the root operator of the tree of operands i..j: that of i+1..j, built first, if
    it binds tighter than operator i, working back from j-1..j."""
    r = j - 1
    for k in range(j - 2, i - 1, -1):
        r = k if prec[r] > prec[k] else j - 1
    return r


def _golog_build(operators: Sequence[Op], prec: Sequence[int], i: int, j: int) -> Shape:
    if i == j:
        return i
    if _golog_root(prec, i, j) == i:
        return (operators[i], i, _golog_build(operators, prec, i + 1, j))
    return (operators[j - 1], _golog_build(operators, prec, i, j - 1), j)


def render_shape(shape: Shape, texts: Sequence[str]) -> str:
    """A chain's tree as text, with parentheses wherever precedence changes."""
    return _show_shape(shape, texts, None, False)


def _show_shape(s: Shape, texts: Sequence[str], parent: Op | None, right: bool) -> str:
    if isinstance(s, int):
        return texts[s]
    op, left, rhs = s
    text = f"{_show_shape(left, texts, op, False)} {op.value} {_show_shape(rhs, texts, op, True)}"
    return f"({text})" if _needs_parentheses(op, parent, right) else text


def _needs_parentheses(op: Op, parent: Op | None, right: bool) -> bool:
    return parent is not None and (right or _GOLOG_PRECEDENCE[op] != _GOLOG_PRECEDENCE[parent])


def _grouped(shape: Shape) -> list[tuple[int, int]]:
    """The operand ranges that `render_shape` puts in parentheses."""
    out: list[tuple[int, int]] = []
    _visit_grouped(shape, None, False, out)
    return out


def _visit_grouped(s: Shape, parent: Op | None, right: bool, out: list[tuple[int, int]]) -> tuple[int, int]:
    """The operand range of `s`; adds the ranges in parentheses below it (and its own) to `out`."""
    if isinstance(s, int):
        return s, s
    op, left, rhs = s
    first, _ = _visit_grouped(left, op, False, out)
    _, last = _visit_grouped(rhs, op, True, out)
    if _needs_parentheses(op, parent, right):
        out.append((first, last))
    return first, last


def _sub_expressions(e: ast.Node) -> list[ast.Expr]:
    """The outermost expressions below `e` (its operands, a compound literal's field values...)."""
    found: list[ast.Expr] = []
    stack = list(reversed(children(e)))
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Expr):
            found.append(node)
        else:
            stack.extend(reversed(children(node)))
    return found


# ---------------------------------------------------------------- W0111 shadowed symbol


# Local: the declaration's locals against the domain symbols, declared in the environment.
@_lint(codes.W0111, local=True)
def shadowed_symbol(program: _Program) -> Iterator[diag.Diagnostic]:
    symbols = program.model.symbols
    locals_: list[Symbol] = list(_variables(program))
    for g in program.root_globals():
        if g.kind is not SymbolKind.EXOG_FUNCTION and not g.predefined:
            locals_.extend(p for p in g.params if program.linted(p.span))
    for local in locals_:
        shadowed = symbols.get(local.name)
        if shadowed is None or local.span is None or local.kind not in _LOCAL_KINDS:
            continue
        what = "parameter" if local.kind is SymbolKind.PARAMETER else "variable"
        yield diag.warning(
            codes.W0111.shadows(what, local.name),
            local.span,
            f"in its scope, `{local.name}` means this {what}",
            secondary=[diag.Label(shadowed.span, "the symbol is declared here")] if shadowed.span else [],
            help=f"rename the {what}",
        )


# ---------------------------------------------------------------- W0112 quantifier scope

_CONNECTIVES = frozenset({Op.AND, Op.OR, Op.IMPLIES})


# Local: one quantifier.
@_lint(codes.W0112, local=True)
def quantifier_scope(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    for node in program.nodes(ast.Quantified):
        variable = model.target(node.var)
        body = model.effective(node.body)
        if variable is None or body.parenthesized or not _is_connective(body):
            continue
        operands = _connective_operands(body)
        using = [i for i, x in enumerate(operands) if _mentions(model, x, variable)]
        if not using or using[-1] == len(operands) - 1:
            continue
        last = using[-1]
        source = node.span.source
        outside = Span(source, operands[last + 1].span.start, operands[-1].span.end)
        head_span = _quantifier_head(node)
        head, rest = head_span.text, _one_line(outside.text)
        q, var = node.quantifier.value, node.var.name
        edits = (
            diag.Edit(Span(source, head_span.start, head_span.start), "("),
            diag.Edit(Span(source, operands[last].span.end, operands[last].span.end), ")"),
        )
        yield diag.warning(
            codes.W0112.runs_on(rest, head, var),
            outside,
            f"inside the `{q}`",
            notes=[
                f"a quantifier's body extends as far right as it can: this reads `{head} ({_one_line(body.span.text)})`"
            ],
            help=f"put the quantifier in parentheses, `({head} ...)`, to end it before `{rest}`",
            fix=diag.Fix(f"end the `{q}` before `{rest}`", edits) if _prefix_subtree(body, last) else None,
        )


def _is_connective(e: ast.Expr) -> bool:
    return isinstance(e, ast.Binary) and e.op in _CONNECTIVES


def _connective_operands(root: ast.Expr) -> list[ast.Expr]:
    """The operands of the unparenthesised `&`/`|`/`->` chain at `root`, in order."""
    out: list[ast.Expr] = []
    stack = [root]
    while stack:
        e = stack.pop()
        if isinstance(e, ast.Binary) and _is_connective(e) and (e is root or not e.parenthesized):
            stack.extend((e.right, e.left))
        else:
            out.append(e)
    return out


def _prefix_subtree(root: ast.Expr, last: int) -> bool:
    """Do the chain's operands 0..last form one subtree of it (on its left spine)?"""
    e = root
    while True:
        size = len(_connective_operands(e))
        if size <= last + 1:
            return size == last + 1
        assert isinstance(e, ast.Binary)
        if not _is_connective(e.left) or e.left.parenthesized:
            return last == 0
        e = e.left


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _mentions(model: Model, e: ast.Node, symbol: Symbol) -> bool:
    return any(isinstance(n, ast.Name) and model.target(n) is symbol for n in walk(e))


def _quantifier_head(node: ast.Quantified) -> Span:
    """`exists(T v)`, without the parentheses around the whole quantifier."""
    source = node.span.source
    before = source.text[node.span.start : node.var_type.span.start]
    start = node.span.start + before.rfind(node.quantifier.value)
    close = source.text.find(")", node.var.span.end)
    return Span(source, start, close + 1 if close >= 0 else node.var.span.end)


# ---------------------------------------------------------------- W0113 shared sensing result


# Local: one `senses:` section; the exogenous functions are declared in the environment.
@_lint(codes.W0113, local=True)
def shared_sensing_result(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    for section in program.nodes(ast.SensesSection):
        calls = [
            n
            for n in walk(section)
            if isinstance(n, ast.Call) and (s := model.target(n)) is not None and s.kind is SymbolKind.EXOG_FUNCTION
        ]
        calls.sort(key=lambda c: c.span.start)
        if not calls:
            continue
        first = format_expr(calls[0])
        for call in calls[1:]:
            if format_expr(call) == first:
                continue
            yield diag.warning(
                codes.W0113.shared(format_expr(call), first),
                call.span,
                f"answered with the same result as `{first}`",
                secondary=[diag.Label(calls[0].span, "the first exogenous function here")],
                notes=[
                    "when the activity ends with a result, that result answers every exogenous function "
                    "evaluated in its `senses:` section, whatever its name"
                ],
                help="sense one compound value and take its fields, or sense the other value in another action",
            )


# ---------------------------------------------------------------- W0114 unended activity

_ENDING_HOOKS = frozenset({ast.Hook.END, ast.Hook.FINISH, ast.Hook.FAIL, ast.Hook.CANCEL})


# Global: an activity may be ended in any procedure body.
@_lint(codes.W0114, local=False)
def unended_activity(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    ended: set[int] = set()
    for _, found in program.body_statements(model.files):
        for s, _ in found:
            if isinstance(s, ast.HookStmt) and s.hook in _ENDING_HOOKS:
                action = model.target(s.action)
                if action is not None:
                    ended.add(id(action))
    for s in program.root_statements(ast.HookStmt):
        action = model.target(s.action)
        if s.hook is not ast.Hook.START or action is None or id(action) in ended:
            continue
        started = format_expr(s.action)
        yield diag.warning(
            codes.W0114.never_ended(started, action.name),
            s.span,
            "started here, never ended",
            notes=[
                "`end` or `finish` applies the action's effects and `fail` sees a failure; without them the "
                "activity runs unobserved and is cancelled if it still runs when the program ends"
            ],
            help=f"wait for it with `end({started});`, or call `{started};` to start it and wait in one step",
        )


# ---------------------------------------------------------------- W0115 busy wait


# Local: the loop, and the function bodies (environment) its condition calls.
@_lint(codes.W0115, local=True)
def busy_wait(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    moving = program.statements_where(_ALL_STATEMENTS, lambda s: not _still(model, s))
    assigning = program.statements_where((ast.Assign, ast.ListStmt), lambda s: True)
    stepping = program.statements_where((ast.Test, ast.Assign, ast.ListStmt), lambda s: True)
    for node in program.nodes(ast.While):
        if _constant(model, node.condition) is not None:
            continue  # `while (true)` is W0106's, other constant conditions W0107's
        if moving.any_inside(node.body):
            continue
        read = _fluents_read(program, node.condition)
        changed = [_assigned_fluent(model, s) for s in assigning.inside(node.body)]  # type: ignore[arg-type]
        if any(f is None or id(f) in read for f in changed):
            continue
        waited = _negated(node.condition)
        steps = stepping.any_inside(node.body)
        replacement = f"test({waited});"
        fix = diag.Fix(f"wait with `{replacement}`", (diag.Edit(node.span, replacement),)) if not changed else None
        if steps:
            yield diag.warning(
                codes.W0115.busy_waits(),
                _while_head(node),
                "repeats its body without changing its condition",
                notes=[
                    "only something outside the loop (an exogenous event, the clock, another `concurrent` branch) "
                    "can end it"
                ],
                help=f"to wait until `{waited}` holds, write `{replacement}`",
                fix=fix,
            )
        else:
            yield diag.warning(
                codes.W0115.does_not_wait(),
                _while_head(node),
                "ends at once, whatever the condition",
                notes=["a loop whose body has nothing to do is finished, whether or not its condition holds"],
                help=f"to wait until `{waited}` holds, write `{replacement}`",
                fix=fix,
            )


def _still(model: Model, s: ast.Statement) -> bool:
    """Does `s` neither act, call, plan nor wait for the world (looking only at `s`, not inside
    it)? `test(true)` never waits."""
    if isinstance(s, ast.Test):
        return _constant(model, s.condition) is True
    return not isinstance(s, _ACTING)


# The statements that act, call, plan or wait by themselves (a tuple: isinstance is quicker
# with it than with a union).
_ACTING = (ast.CallStmt, ast.HookStmt, ast.During, ast.Solve, ast.Search)


def _assigned_fluent(model: Model, s: ast.Assign | ast.ListStmt) -> Symbol | None:
    """The fluent an assignment or list statement changes, or None when it is not clear."""
    e = s.target
    while isinstance(e, ast.FieldAccess | ast.Index):
        e = e.subject
    symbol = model.target(e) if isinstance(e, ast.Call) else None
    return symbol if symbol is not None and symbol.kind is SymbolKind.FLUENT else None


def _fluents_read(program: _Program, e: ast.Expr) -> set[int]:
    """The fluents (by id) `e` reads, directly or through the functions it calls."""
    model = program.model
    read: set[int] = set()
    seen: set[int] = set()
    stack: list[ast.Node] = [e]
    while stack:
        for n in walk(stack.pop()):
            symbol = model.target(n) if isinstance(n, ast.Call) else None
            if symbol is None or id(symbol) in seen:
                continue
            seen.add(id(symbol))
            if symbol.kind is SymbolKind.FLUENT:
                read.add(id(symbol))
            elif isinstance(symbol.decl, ast.FunctionDecl) and symbol.decl.body is not None:
                stack.append(symbol.decl.body)
    return read


def _negated(e: ast.Expr) -> str:
    """The source text of the negation of a condition."""
    if isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT and not e.parenthesized:
        text = e.operand.span.text
        return text[1:-1] if e.operand.parenthesized and text[:1] + text[-1:] == "()" else text
    atomic = e.parenthesized or isinstance(e, ast.Call | ast.Name | ast.FieldAccess | ast.Index | ast.BoolLit)
    return f"!{e.span.text}" if atomic else f"!({e.span.text})"


# ---------------------------------------------------------------- W0118 goal paid again


# Global: the reward's functions, the actions' effects and the procedures the `solve` calls are
# read wherever they are declared.
@_lint(codes.W0118, local=False)
def goal_paid_again(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    for solve in program.root_statements(ast.Solve):
        for goal, bonus in _goal_bonuses(model, solve.reward, set()):
            read = _fluents_read(program, goal)
            if not read:
                continue
            goal_text, bonus_text = format_expr(goal), format_expr(bonus)
            for writer, after in _steps_after_goal(program, solve.body, read):
                yield _goal_paid_again(solve, goal_text, bonus_text, writer, after)


def _steps_after_goal(
    program: _Program, body: ast.Statement, goal_fluents: set[int]
) -> Iterator[tuple[ast.Statement, ast.Statement]]:
    """In each sequence of statements of `body` (its own, and each block inside it): the last
    statement that can assign a fluent the goal reads, and the first statement after it that
    makes a costed step, when there is one (it cannot assign them)."""
    sequences = [n for n in walk(body) if isinstance(n, ast.Block)]
    if not isinstance(body, ast.Block):
        sequences.insert(0, ast.Block(span=body.span, body=(body,)))
    seen: set[int] = set()
    for block in sequences:
        steps = _sequence(block)
        writers = [i for i, s in enumerate(steps) if _may_write(program, s, goal_fluents, set())]
        if not writers:
            continue
        after = next((s for s in steps[writers[-1] + 1 :] if _costs(program, s, set())), None)
        if after is not None and id(after) not in seen:  # a nested block is also part of its parent's
            seen.add(id(after))
            yield steps[writers[-1]], after


def _goal_paid_again(
    solve: ast.Solve, goal_text: str, bonus_text: str, writer: ast.Statement, after: ast.Statement
) -> diag.Diagnostic:
    return diag.warning(
        codes.W0118.paid_again(goal_text, bonus_text),
        after.span,
        f"a step after `{goal_text}` may have become true",
        secondary=[
            diag.Label(writer.span, f"can make `{goal_text}` true"),
            diag.Label(solve.reward.span, "paid in the state before every step and after each one"),
        ],
        notes=[
            "the value of a plan adds up the reward of every state it passes through, so a goal that "
            f"still holds pays `{bonus_text}` once per step made after it was reached"
        ],
        help="make this step before the one that reaches the goal, or after the `solve`, if the goal should count once",
    )


def _goal_bonuses(model: Model, e: ast.Expr, seen: set[int]) -> Iterator[tuple[ast.Expr, ast.Expr]]:
    """The `if (goal) bonus else ...` terms of a reward expression, through the functions
    without parameters it calls: a bonus that is (or starts from, as `1000 - cost()`) a
    constant above 0, and above the other branch when that is a constant."""
    e = model.effective(e)
    match e:
        case ast.Conditional():
            bonus = _constant_part(e.then)
            other = _number_constant(e.otherwise)
            if bonus is not None and bonus > 0 and (other is None or bonus > other):
                yield e.condition, e.then
        case ast.Binary() if e.op in (Op.ADD, Op.SUB):
            yield from _goal_bonuses(model, e.left, seen)
            if e.op is Op.ADD:
                yield from _goal_bonuses(model, e.right, seen)
        case ast.Call() if not e.args:
            symbol = model.target(e)
            decl = symbol.decl if symbol is not None else None
            if isinstance(decl, ast.FunctionDecl) and decl.body is not None and id(decl) not in seen:
                seen.add(id(decl))
                yield from _goal_bonuses(model, decl.body, seen)
        case _:
            pass


def _constant_part(e: ast.Expr) -> float | None:
    """The number a reward term starts from: a constant, or the constant of `1000 - cost()`,
    `cost() + 10`."""
    if isinstance(e, ast.Binary) and e.op in (Op.ADD, Op.SUB) and not e.parenthesized:
        left = _number_constant(e.left)
        if left is not None:
            return left
        return _number_constant(e.right) if e.op is Op.ADD else None
    return _number_constant(e)


def _number_constant(e: ast.Expr) -> float | None:
    if isinstance(e, ast.NumberLit):
        return e.value
    if isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NEG and isinstance(e.operand, ast.NumberLit):
        return -e.operand.value
    return None


def _sequence(s: ast.Statement) -> list[ast.Statement]:
    """The statements `s` runs one after the other (nested blocks flattened)."""
    if not isinstance(s, ast.Block):
        return [s]
    return [x for b in s.body for x in _sequence(b)]


def _may_write(program: _Program, s: ast.Statement, fluents: set[int], seen: set[int]) -> bool:
    """Can `s` (or an action or procedure it calls) assign one of `fluents` (ids)? An
    assignment whose fluent is not clear may."""
    model = program.model
    for node in walk(s):
        if isinstance(node, ast.Assign | ast.ListStmt):
            fluent = _assigned_fluent(model, node)
            if fluent is None or id(fluent) in fluents:
                return True
        elif isinstance(node, ast.Call):
            symbol = model.target(node)
            decl = symbol.decl if symbol is not None else None
            if decl is None or id(decl) in seen:
                continue
            seen.add(id(decl))
            if isinstance(decl, ast.ActionDecl):
                sections = (n for n in walk(decl) if isinstance(n, ast.Effect | ast.SensesSection))
                written = {_written_fluent(model, n) for n in sections}
                if -1 in written or written & fluents:
                    return True
            elif (
                isinstance(decl, ast.ProcedureDecl)
                and decl.body is not None
                and _may_write(program, decl.body, fluents, seen)
            ):
                return True
    return False


def _written_fluent(model: Model, node: ast.Effect | ast.SensesSection) -> int:
    """The id of the fluent an effect or a sensing section assigns; -1 when it is not clear."""
    e = node.target
    while isinstance(e, ast.FieldAccess | ast.Index):
        e = e.subject
    symbol = model.target(e) if isinstance(e, ast.Call) else None
    return id(symbol) if symbol is not None and symbol.kind is SymbolKind.FLUENT else -1


def _costs(program: _Program, s: ast.Statement, seen: set[int]) -> bool:
    """Can `s` make a step that uses up the horizon (an action, a hook, an assignment)?"""
    model = program.model
    for node in walk(s):
        if isinstance(node, ast.Assign | ast.ListStmt | ast.HookStmt | ast.During):
            return True
        if isinstance(node, ast.CallStmt):
            symbol = model.target(node.call)
            if symbol is None or symbol.kind is SymbolKind.ACTION:
                return True
            decl = symbol.decl
            if isinstance(decl, ast.ProcedureDecl) and decl.body is not None and id(decl) not in seen:
                seen.add(id(decl))
                if _costs(program, decl.body, seen):
                    return True
    return False


# ---------------------------------------------------------------- W0119 unwatched activity


# Global: whether the fix is safe depends on the `start`s of the activity anywhere (see below).
@_lint(codes.W0119, local=False)
def unwatched_activity(program: _Program) -> Iterator[diag.Diagnostic]:
    model = program.model
    started: set[int] | None = None  # the actions some `start(...)` starts, found on first use
    for node in program.root_statements(ast.During):
        if node.until is not None:
            continue
        body = node.body.body if isinstance(node.body, ast.Block) else (node.body,)
        if len(body) < 2:
            continue
        *before, test, cancel = body
        if not (
            isinstance(test, ast.Test)
            and isinstance(cancel, ast.HookStmt)
            and cancel.hook is ast.Hook.CANCEL
            and format_expr(cancel.action) == format_expr(node.action)
        ):
            continue
        action, condition = node.action.span.text, test.condition.span.text
        replacement = f"during ({action}) until ({condition}) {{}}"
        if started is None:
            started = _started_actions(program)
        action_symbol = model.target(node.action)
        fix = None
        # No fix when the result would get a warning the hanging form does not: a constant
        # condition is W0107's as an `until` (not as `test(true)`), and without the `cancel` a
        # `start` of the activity elsewhere could be left without any end (W0114).
        if (
            not before
            and _constant(model, test.condition) is None
            and (action_symbol is None or id(action_symbol) not in started)
        ):
            head = Span(node.span.source, node.span.start, node.body.span.end)
            fix = diag.Fix(f"write `{replacement}`", (diag.Edit(head, replacement),), diag.Applicability.SAFE)
        yield diag.warning(
            codes.W0119.hangs(format_expr(test.condition), format_expr(node.action)),
            test.span,
            "waits here after the activity ended",
            secondary=[diag.Label(cancel.span, "needs the activity still running")],
            notes=[
                "the body of a `during` is not interrupted when its activity ends, and its handlers run only "
                "after the body ended"
            ],
            help=f"watch the activity with `until`: `{replacement}` cancels it when the condition holds while "
            "it runs, and leaves the body when it ends, so a handler always runs",
            fix=fix,
        )


# ---------------------------------------------------------------- W0120 unrun watch body


# Global: a procedure runs only while planning when every call to it is planned.
@_lint(codes.W0120, local=False)
def unrun_watch_body(program: _Program) -> Iterator[diag.Diagnostic]:
    for owner, found in program.body_statements(program.root_files):
        planned_procedure = owner is not None and id(owner) in program.planning_only
        for s, planning in found:
            if not isinstance(s, ast.During) or s.until is None or not (planning or planned_procedure):
                continue
            if not _costs(program, s.body, set()) and not any(isinstance(n, ast.Test) for n in walk(s.body)):
                continue
            yield diag.warning(
                codes.W0120.never_runs(),
                s.body.span,
                "never runs: the plan lets the activity end first",
                notes=[
                    "while planning, an activity ends the moment it starts, so a watched `during` leaves its body "
                    "before the body's first step; the plan, and its execution, have none of its steps"
                ],
                help="make these steps before or after the `during`, or in its handlers",
            )


def _started_actions(program: _Program) -> set[int]:
    """The actions (symbol ids) a `start(...)` of the program starts."""
    model = program.model
    started: set[int] = set()
    for _, found in program.body_statements(model.files):
        for s, _ in found:
            if isinstance(s, ast.HookStmt) and s.hook is ast.Hook.START:
                action = model.target(s.action)
                if action is not None:
                    started.add(id(action))
    return started
