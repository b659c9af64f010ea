"""The breakpoint table of a session: line breakpoints (moved to the nearest statement, with a
condition, a hit count, a log message), function breakpoints (an action or procedure name:
the run stops when a call of it starts) and the exception filters. The server fills it from
the editor's requests; a backend asks it at each transition (`line_hits`, `function_hits`)."""

from __future__ import annotations

import re
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from gpp.base.source import Span
from gpp.base.suggest import did_you_mean
from gpp.dap.program import CheckedExpression, DebugProgram, ExpressionError
from gpp.model.symbols import SymbolKind
from gpp.model.types import BOOL
from gpp.runtime.compiled import Env
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.values import show
from gpp.syntax import ast

# Filter -> (label, description, on by default).
EXCEPTION_FILTERS: dict[str, tuple[str, str, bool]] = {
    "failed": ("Action failed", "Stop when an activity fails", False),
    "blocked": ("Program blocked", "Stop when the program can neither step nor wait for anything", True),
    "error": ("Run-time error", "Stop at a run-time error before the run ends", True),
    "no-plan": ("No plan", "Stop when `solve` or `search` finds no plan", True),
}

_INTERPOLATION = re.compile(r"\{([^{}]*)\}")


@dataclass
class HitCondition:
    """`N` (stop at the Nth hit), `>= N`, `> N`, `% N` (every Nth), `== N`."""

    op: str
    count: int

    @classmethod
    def parse(cls, text: str) -> HitCondition:
        found = re.fullmatch(r"\s*(>=|>|==|=|%)?\s*(\d+)\s*", text)
        if found is None:
            raise ExpressionError("a hit count is a number, or `>= N`, `> N`, `% N`", 1)
        return cls(found.group(1) or "==", int(found.group(2)))

    def holds(self, hits: int) -> bool:
        match self.op:
            case ">=":
                return hits >= self.count
            case ">":
                return hits > self.count
            case "%":
                return self.count > 0 and hits % self.count == 0
            case _:
                return hits == self.count


@dataclass
class Breakpoint:
    id: int
    verified: bool = False
    message: str | None = None
    condition: CheckedExpression | None = None
    hit_condition: HitCondition | None = None
    # A logpoint: the text and the expressions of its `{...}` parts.
    log: str | None = None
    log_parts: list[CheckedExpression | str] = field(default_factory=list)
    hits: int = 0

    def reported(self) -> dict[str, Any]:
        out: dict[str, Any] = {"id": self.id, "verified": self.verified}
        if self.message is not None:
            out["message"] = self.message
        return out


@dataclass
class LineBreakpoint(Breakpoint):
    path: str = ""
    line: int = 0
    stmt: ast.Statement | None = None

    def reported(self) -> dict[str, Any]:
        out = Breakpoint.reported(self)
        out["line"] = self.line
        if self.stmt is not None:
            out |= {"column": self.stmt.span.col, "endLine": self.stmt.span.end_line}
        return out


@dataclass
class FunctionBreakpoint(Breakpoint):
    name: str = ""


class Breakpoints:
    """The table. Set from the protocol loop's thread, read from the run's."""

    def __init__(self) -> None:
        self.program: DebugProgram | None = None
        self.lines: dict[str, list[LineBreakpoint]] = {}
        self.by_statement: dict[int, list[LineBreakpoint]] = {}
        self.functions: dict[str, FunctionBreakpoint] = {}
        self.exceptions: frozenset[str] = frozenset(f for f, (_, _, on) in EXCEPTION_FILTERS.items() if on)
        self._next_id = 0
        self.lock = threading.Lock()

    def new_id(self) -> int:
        self._next_id += 1
        return self._next_id

    def set_lines(self, path: str, wanted: list[dict[str, Any]]) -> list[LineBreakpoint]:
        """Replace the breakpoints of file `path` (DAP's setBreakpoints)."""
        placed: list[LineBreakpoint] = []
        program = self.program
        for w in wanted:
            line = w.get("line")
            b = LineBreakpoint(self.new_id(), path=path, line=line if isinstance(line, int) else 0)
            placed.append(b)
            if not isinstance(line, int) or line < 1:
                b.message = "a breakpoint needs a line number from 1 on"
                continue
            if program is None:
                b.message = "nothing is launched yet"
                continue
            if not program.has_file(path):
                b.message = "this file is not part of the program being debugged"
                continue
            stmt = program.statement_at(path, line)
            if stmt is None:
                b.message = "there is no statement on or after this line"
                continue
            b.stmt, b.line = stmt, stmt.span.line
            self.prepare(b, w, program, stmt)
        with self.lock:
            self.lines[path] = placed
            self.by_statement = {}
            for bs in self.lines.values():
                for b in bs:
                    if b.verified and b.stmt is not None:
                        self.by_statement.setdefault(id(b.stmt), []).append(b)
        return placed

    def set_functions(self, wanted: list[dict[str, Any]]) -> list[FunctionBreakpoint]:
        placed: list[FunctionBreakpoint] = []
        program = self.program
        for w in wanted:
            name = w.get("name")
            b = FunctionBreakpoint(self.new_id(), name=name if isinstance(name, str) else "")
            placed.append(b)
            if program is None:
                b.message = "nothing is launched yet"
                continue
            symbol = program.model.globals.get(b.name.strip())
            callable_kinds = (SymbolKind.ACTION, SymbolKind.PROCEDURE)
            if symbol is None or symbol.kind not in callable_kinds:
                names = [s.name for s in program.model.globals.values() if s.kind in callable_kinds]
                hint = did_you_mean(b.name, names)
                b.message = f"`{b.name}` is not an action or procedure of the program" + (f"; {hint}" if hint else "")
                continue
            b.name = symbol.name
            at = None
            if symbol.kind is SymbolKind.PROCEDURE and isinstance(symbol.decl, ast.ProcedureDecl):
                at = symbol.decl.body
            self.prepare(b, w, program, at)
        with self.lock:
            self.functions = {b.name: b for b in placed if b.verified}
        return placed

    @staticmethod
    def prepare(b: Breakpoint, wanted: dict[str, Any], program: DebugProgram, at: ast.Statement | None) -> None:
        """Check the breakpoint's condition, hit count and log message in the scope of `at`;
        a breakpoint with one that does not check is not verified, its message says why."""
        try:
            condition = wanted.get("condition")
            if isinstance(condition, str) and condition.strip():
                b.condition = program.expression(condition, at)
                if b.condition.type is not BOOL:
                    raise ExpressionError(f"a condition is a `bool`, not a `{b.condition.type}`", 1)
            hit = wanted.get("hitCondition")
            if isinstance(hit, str) and hit.strip():
                b.hit_condition = HitCondition.parse(hit)
            log = wanted.get("logMessage")
            if isinstance(log, str):
                b.log = log
                b.log_parts = log_parts(log, program, at)
        except ExpressionError as e:
            b.message = f"{_what(wanted)} does not check: {e}"
            return
        b.verified = True

    def at_statement(self, stmt: ast.Statement) -> list[LineBreakpoint]:
        return self.by_statement.get(id(stmt), [])


def _what(wanted: dict[str, Any]) -> str:
    if isinstance(wanted.get("condition"), str) and wanted["condition"].strip():
        return "the condition"
    if isinstance(wanted.get("hitCondition"), str) and wanted["hitCondition"].strip():
        return "the hit count"
    return "the log message"


def log_parts(text: str, program: DebugProgram, at: ast.Statement | None) -> list[CheckedExpression | str]:
    """A log message's text and `{expression}` parts (each checked)."""
    parts: list[CheckedExpression | str] = []
    last = 0
    for m in _INTERPOLATION.finditer(text):
        parts.append(text[last : m.start()])
        try:
            parts.append(program.expression(m.group(1), at))
        except ExpressionError as e:
            raise ExpressionError(f"in `{{{m.group(1)}}}`: {e.message}", m.start(1) + e.column) from None
        last = m.end()
    parts.append(text[last:])
    return [p for p in parts if p != ""]


def stops(b: Breakpoint, env: Env, output: Callable[[str, str, Span | None], None], span: Span | None) -> bool:
    """Does breakpoint `b` stop where `env` evaluates: its condition (one that cannot be
    evaluated stops, saying why), then its hit count; a logpoint prints its message through
    `output` and does not stop."""
    if b.condition is not None:
        try:
            if b.condition.evaluate(env) is not True:
                return False
        except GppRuntimeError as e:
            output(f"breakpoint condition `{b.condition.text}`: {e.message}\n", "stderr", span)
            return True
        except KeyError:  # a variable the trace or the transition has not bound
            output(f"breakpoint condition `{b.condition.text}`: a variable has no value here\n", "stderr", span)
            return True
    b.hits += 1
    if b.hit_condition is not None and not b.hit_condition.holds(b.hits):
        return False
    if b.log is not None:
        text = []
        for part in b.log_parts:
            try:
                text.append(part if isinstance(part, str) else show(part.evaluate(env)))
            except GppRuntimeError as e:
                text.append(f"<{e.message}>")
            except KeyError:
                text.append("<no value here>")
        output("".join(text) + "\n", "console", span)
        return False
    return True
