"""What the debugger knows of a checked program: where its statements are (for breakpoints and
the stack), which procedure each belongs to, and golog++ expressions typed in the editor
(conditions, logpoints, evaluate) checked by the real front end in the scope of a statement.

An expression is parsed by the parser as the condition of a `test` in a procedure of its own,
and type-checked by the type checker of gpp.model with the variables visible at the statement
opened as a scope, recording into the program's model (so that the compiled program of the run
compiles and evaluates it as it does the program's own expressions). Each checked expression
is kept for the session: the model's tables are keyed by node identity."""

from __future__ import annotations

from bisect import bisect_left
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.check import CheckResult
from gpp.model.builder_state import BuilderState
from gpp.model.resolve import TypeResolver
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.typecheck import TypeChecker
from gpp.model.types import ERROR, Type
from gpp.runtime.compiled import CompiledProgram, Evaluator
from gpp.syntax import ast
from gpp.syntax.parser import parse
from gpp.syntax.walk import sub_statements

# The text around an expression typed in the editor, so that the parser reads it as one.
_BEFORE = "procedure gpp_debugger_expression() { test("
_AFTER = "\n); }\n"


class ExpressionError(Exception):
    """An expression that does not parse or check: one line with its 1-based column in the
    expression."""

    def __init__(self, message: str, column: int) -> None:
        super().__init__(f"column {column}: {message}")
        self.message = message
        self.column = column


@dataclass(frozen=True, slots=True)
class CheckedExpression:
    text: str
    expr: ast.Expr
    type: Type
    evaluate: Evaluator


@dataclass(frozen=True, slots=True)
class Located:
    """A statement and the procedure whose body holds it."""

    stmt: ast.Statement
    procedure: Symbol


class DebugProgram:
    """A checked program and its compiled form, indexed for the debugger."""

    def __init__(self, check: CheckResult, compiled: CompiledProgram) -> None:
        self.check = check
        self.model = check.model
        self.compiled = compiled
        # id(statement) -> where it is; per file (resolved path), the statements by first line.
        self.located: dict[int, Located] = {}
        self.by_file: dict[str, list[tuple[int, int, ast.Statement]]] = {}
        self.procedures: dict[int, Symbol] = {}  # id(body) -> procedure
        self.by_span: dict[tuple[int, int, int], ast.Statement] = {}
        for symbol in self.model.globals.values():
            decl = symbol.decl
            if symbol.kind is not SymbolKind.PROCEDURE or not isinstance(decl, ast.ProcedureDecl | ast.MainBlock):
                continue
            if decl.body is None:
                continue
            self.procedures[id(decl.body)] = symbol
            for s in _statements(decl.body):
                self.located[id(s)] = Located(s, symbol)
                self.by_span.setdefault((id(s.span.source), s.span.start, s.span.end), s)
                if not isinstance(s, ast.Block):
                    key = _file_key(s.span.source.path)
                    self.by_file.setdefault(key, []).append((s.span.line, s.span.start, s))
        for entries in self.by_file.values():
            entries.sort(key=lambda e: (e[0], e[1]))
        self._expressions: dict[tuple[str, int], CheckedExpression] = {}

    # ---------------------------------------------------------------- statements

    def procedure_of(self, stmt: ast.Statement) -> Symbol | None:
        found = self.located.get(id(stmt))
        return found.procedure if found is not None else None

    def statement_of(self, span: Span) -> ast.Statement | None:
        """The statement with exactly this span (what a continuation that keeps only a span is at)."""
        return self.by_span.get((id(span.source), span.start, span.end))

    def statement_at(self, path: str, line: int) -> ast.Statement | None:
        """The first statement that begins on `line`, or on the nearest line after it with one
        (a breakpoint is moved there, as debuggers do); None past the last statement."""
        entries = self.by_file.get(_file_key(path))
        if not entries:
            return None
        i = bisect_left(entries, (line, -1))
        return entries[i][2] if i < len(entries) else None

    def has_file(self, path: str) -> bool:
        return _file_key(path) in {_file_key(f.source.path) for f in self.check.loaded.files}

    # ---------------------------------------------------------------- expressions

    def visible(self, at: ast.Statement | None) -> list[Symbol]:
        """The parameters and variables visible at statement `at` (none at None)."""
        if at is None:
            return []
        return [
            s
            for s in self.model.visible_at(at.span.source, at.span.start)
            if s.kind in (SymbolKind.PARAMETER, SymbolKind.VARIABLE)
        ]

    def expression(self, text: str, at: ast.Statement | None) -> CheckedExpression:
        """`text` parsed and type-checked in the scope of statement `at` (globals only at None);
        ExpressionError, located in `text`, when it does not."""
        key = (text, id(at))
        found = self._expressions.get(key)
        if found is not None:
            return found
        if not text.strip():
            raise ExpressionError("an expression is expected", 1)
        source = Source(_BEFORE + text + _AFTER, path="<expression>")
        parsed = parse(source)
        errors = [d for d in parsed.diagnostics if d.is_error]
        if errors:
            raise _located(errors[0], len(text))
        expr = _only_test_condition(parsed.program, len(text))
        state = BuilderState(self.check.loaded.files)
        state.model = self.model
        state._add_reference = lambda reference: None  # the editor's typing is not a reference
        state._targets = self.model.targets
        checker = TypeChecker(state, TypeResolver(state))
        with checker.scope(expr.span, self.visible(at)):
            t = checker.expr(expr)
        errors = [d for d in state.diagnostics if d.is_error]
        if errors or t is ERROR:
            if errors:
                raise _located(errors[0], len(text))
            raise ExpressionError("this expression has no value", 1)
        checked = CheckedExpression(text, expr, t, self.compiled.expr(expr))
        self._expressions[key] = checked
        return checked


def _statements(s: ast.Statement) -> Iterator[ast.Statement]:
    yield s
    for inner in sub_statements(s):
        yield from _statements(inner)


def _file_key(path: str) -> str:
    if path.startswith("<"):
        return path
    try:
        return str(Path(path).resolve())
    except OSError:
        return path


def _column(offset: int, length: int) -> int:
    """The 1-based column in the typed expression of an offset in the wrapped text."""
    return min(max(offset - len(_BEFORE), 0), length) + 1


def _located(d: diag.Diagnostic, length: int) -> ExpressionError:
    message = d.message + (f": {d.label}" if d.label else "")
    return ExpressionError(message, _column(d.span.start, length) if d.span is not None else 1)


def _only_test_condition(program: ast.Program, length: int) -> ast.Expr:
    """The one expression the editor's text parsed to (text that closes the `test(` and goes
    on is not one expression)."""
    decls = program.declarations
    decl = decls[0] if len(decls) == 1 else None
    body = decl.body if isinstance(decl, ast.ProcedureDecl) else None
    stmts = body.body if isinstance(body, ast.Block) else ()
    if len(stmts) == 1 and isinstance(stmts[0], ast.Test):
        expr = stmts[0].condition
        if len(_BEFORE) <= expr.span.start and expr.span.end <= len(_BEFORE) + length:
            return expr
    raise ExpressionError("one expression is expected", 1)
