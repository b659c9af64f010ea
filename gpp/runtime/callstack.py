"""The procedure calls a continuation is in, for the trace's `step` records (`--trace-steps`).

A continuation keeps no call stack: a call becomes its procedure's body, with the parameters
bound, in front of what remains of the caller (`Seq(body, rest)`). The calls are read back from
that shape: along the path to the statement that steps next, each part's statements belong to
a procedure (the one whose body holds them), and a part in another procedure, or in the same
one with other arguments (a recursion), is another call. A call that was its caller's last
statement leaves nothing of the caller behind, so that caller is not shown (as a tail call).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import assert_never

from gpp.base.source import Span
from gpp.model.symbols import Symbol, SymbolKind
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.events import JsonValue, json_value
from gpp.runtime.semantics import (
    AwaitEnd,
    Code,
    Conc,
    Done,
    DuringEnd,
    Frame,
    Planned,
    Prog,
    Rest,
    Seq,
    Watch,
)
from gpp.runtime.values import Value
from gpp.syntax import ast

# A `step` record lists at most this many calls: the innermost ones and the entry procedure
# (a deep recursion would make each record as long as the recursion is deep).
MAX_FRAMES = 32


@dataclass(frozen=True, slots=True)
class Call:
    """One procedure call of a continuation: the procedure, the bindings its part sees (None:
    not known there), the call statement in its caller (when the caller's rest shows it),
    whether the transition read began it, and its arguments and other bound variables as the
    trace writes them."""

    procedure: Symbol
    frame: Frame | None
    at: ast.Statement | None
    args: dict[str, JsonValue]
    locals: dict[str, JsonValue]
    entered: bool = False

    def record(self) -> dict[str, JsonValue]:
        """The call as a `step` record lists it: `procedure`, `args`, `at` and `locals`."""
        out: dict[str, JsonValue] = {
            "procedure": self.procedure.name,
            "args": self.args,
            "at": str(self.at.span) if self.at is not None else None,
        }
        if self.locals:
            out["locals"] = self.locals
        return out


@dataclass(frozen=True, slots=True)
class _Part:
    """One piece of the path to the next statement: where it is and the bindings it sees."""

    span: Span | None
    frame: Frame | None
    # The statement before it in its block (the call it resumes after), if it is a block's rest.
    before: ast.Statement | None


class CallStacks:
    """Reads the procedure calls of continuations of one program."""

    def __init__(self, program: CompiledProgram) -> None:
        self.program = program
        model = program.model
        # (source path, start, end, procedure symbol) of each procedure body.
        self.bodies: list[tuple[str, int, int, Symbol]] = []
        for symbol in model.globals.values():
            if symbol.kind is not SymbolKind.PROCEDURE:
                continue
            _, body = program.procedure(symbol.name)
            if body is not None:
                self.bodies.append((str(body.span.source.path), body.span.start, body.span.end, symbol))
        # The innermost body first when bodies nest (they do not in golog++, but a wider one
        # must never hide a narrower one).
        self.bodies.sort(key=lambda b: b[2] - b[1])
        self._variables: dict[int, Symbol] | None = None
        # (id of the source, offset) -> the procedure there (the program's sources live as long).
        self._procedures: dict[tuple[int, int], Symbol | None] = {}

    def procedure_at(self, span: Span | None) -> Symbol | None:
        """The procedure whose body holds `span`."""
        if span is None:
            return None
        key = (id(span.source), span.start)
        if key in self._procedures:
            return self._procedures[key]
        path = str(span.source.path)
        found = next(
            (symbol for file, start, end, symbol in self.bodies if file == path and start <= span.start < end), None
        )
        self._procedures[key] = found
        return found

    def step_frames(self, prog: Prog, next_prog: Prog, span: Span) -> tuple[dict[str, JsonValue], ...]:
        """The calls of the statement at `span` that takes the transition from `prog` to
        `next_prog`, as the `step` record lists them (see `step_calls`)."""
        return tuple(call.record() for call in self.step_calls(prog, next_prog, span))

    def step_calls(self, prog: Prog, next_prog: Prog, span: Span) -> tuple[Call, ...]:
        """The calls of the statement at `span` that takes the transition from `prog` to
        `next_prog`, innermost first. The part of `prog` that stepped is the outermost one
        `next_prog` does not share (the parts before it were finished and skipped): when the
        statement is one of that part's own, the calls are that part's and those outside it;
        when the transition entered a procedure from there, they are read after it (the
        callee's rest), and a procedure entered and left in one transition is listed without
        its arguments. The calls the transition began are marked `entered`."""
        procedure = self.procedure_at(span)
        before, after = _chain(prog), _chain(next_prog)
        shared = 0
        while shared < min(len(before), len(after)) and before[-1 - shared] is after[-1 - shared]:
            shared += 1
        stepped = before[: len(before) - shared]
        outside = self._calls(_parts(before[len(stepped) - 1 :])) if stepped else ()
        if stepped and self._holds(stepped[-1], span):
            return outside
        entered = self.calls(next_prog)
        if entered and procedure is not None and entered[0].procedure is procedure:
            # The calls this transition entered, on the calls it was made in (which the rest
            # after it may have lost: a call that was its caller's last statement).
            top = outside[0] if outside else None
            cut = next(
                (
                    i
                    for i, c in enumerate(entered)
                    if top is not None and (c.procedure, c.args) == (top.procedure, top.args)
                ),
                len(entered),
            )
            new = [replace(c, entered=True) for c in entered[:cut]]
            call = _head_statement(stepped[-1]) if stepped else None
            if new and new[-1].at is None and isinstance(call, ast.CallStmt):
                new[-1] = replace(new[-1], at=call)
            return (*new, *outside)
        if procedure is None or (outside and outside[0].procedure is procedure):
            return outside
        return (Call(procedure, None, None, {}, {}, entered=True), *outside)

    def frames(self, prog: Prog) -> tuple[dict[str, JsonValue], ...]:
        """The calls `prog`'s next statement is in (see `_calls`), as records."""
        return tuple(call.record() for call in self.calls(prog))

    def calls(self, prog: Prog) -> tuple[Call, ...]:
        """The calls `prog`'s next statement is in (see `_calls`)."""
        return self._calls(_path(prog))

    def _calls(self, path: list[_Part]) -> tuple[Call, ...]:
        """The calls of the parts `path` (innermost first), innermost first, each with its
        arguments, the call statement (when the caller's rest shows it) and the other
        variables bound there (a `pick`'s)."""
        calls: list[Call] = []
        last: tuple[str, tuple[JsonValue, ...]] | None = None
        parts = [(part, self.procedure_at(part.span)) for part in path]
        for index, (part, symbol) in enumerate(parts):
            if symbol is None:
                continue
            if part.frame is None and any(s is symbol for _, s in parts[index + 1 :]):
                continue  # a wait for an activity: its bindings are in its procedure's rest
            params, _ = self.program.procedure(symbol.name)
            bound = part.frame.vars if part.frame is not None else {}
            args = {p.name: json_value(bound[i]) for p, i in zip(symbol.params, params, strict=True) if i in bound}
            key = (symbol.name, tuple(args.values()))
            if last == key:
                continue
            if calls and isinstance(part.before, ast.CallStmt):
                # The caller goes on after the call that made the call before (inner) this one.
                callee = self.program.model.target(part.before.call)
                if callee is not None and callee.name == calls[-1].procedure.name:
                    calls[-1] = replace(calls[-1], at=part.before)
            last = key
            calls.append(Call(symbol, part.frame, None, args, self._locals(bound, set(params))))
        return tuple(calls)

    def _holds(self, item: Prog, span: Span) -> bool:
        """Is the statement at `span` one of `item`'s own (a statement it will run, or one
        inside such a statement), not one of a procedure a call of it enters?"""
        match item:
            case Rest():
                statements: tuple[ast.Statement, ...] = tuple(item.block.body[item.index :])
            case Code():
                statements = (item.stmt,)
            case _:
                return False
        for stmt in statements:
            if stmt.span.source is span.source and stmt.span.start <= span.start and span.end <= stmt.span.end:
                if not isinstance(stmt, ast.CallStmt):
                    return True
                callee = self.program.model.target(stmt.call)
                return callee is None or callee.kind is not SymbolKind.PROCEDURE
        return False

    def _locals(self, bound: dict[int, Value], params: set[int]) -> dict[str, JsonValue]:
        """The variables of `bound` that are not the procedure's parameters, by name."""
        others = {k: v for k, v in bound.items() if k not in params}
        if not others:
            return {}
        if self._variables is None:
            self._variables = {id(s): s for s in self.program.model.targets.values()}
        named: dict[str, JsonValue] = {}
        for key, value in others.items():
            symbol = self._variables.get(key)
            if symbol is not None:
                named[symbol.name] = json_value(value)
        return named


def _path(prog: Prog) -> list[_Part]:
    """The parts of `prog` from the statement that steps next outwards: the head, then where
    each enclosing block or caller goes on after it (a `Seq`'s rest is outside its first)."""
    parts: list[_Part] = []
    todo: list[Prog | _Part] = [prog]
    while todo:
        p = todo.pop()
        match p:
            case _Part():
                parts.append(p)
            case Seq():
                todo.append(p.rest)
                todo.append(p.first)
            case Conc():
                if p.branches:
                    todo.append(p.branches[0])
            case Watch():
                todo.append(_Part(p.stmt.span, p.frame, None))
                todo.append(p.body)
            case Rest():
                if p.index < len(p.block.body):
                    before = p.block.body[p.index - 1] if p.index > 0 else None
                    parts.append(_Part(p.block.body[p.index].span, p.frame, before))
            case Code():
                parts.append(_Part(p.stmt.span, p.frame, None))
            case AwaitEnd() | DuringEnd():
                parts.append(_Part(p.span, None, None))
            case Planned():
                parts.append(_Part(p.session.stmt.span, None, None))
            case Done():
                pass
            case _:
                assert_never(p)
    return parts


def _chain(prog: Prog) -> list[Prog]:
    """The parts of a continuation in the order they run: `a; b; c` as [a, b, c]."""
    items: list[Prog] = []
    while isinstance(prog, Seq):
        items.append(prog.first)
        prog = prog.rest
    if not isinstance(prog, Done):
        items.append(prog)
    return items


def _parts(items: list[Prog]) -> list[_Part]:
    """The parts of each of `items` (innermost first), one after the other."""
    return [part for item in items for part in _path(item)]


def _head_statement(item: Prog) -> ast.Statement | None:
    """The statement a part of a continuation runs next."""
    match item:
        case Rest() if item.index < len(item.block.body):
            return item.block.body[item.index]
        case Code():
            return item.stmt
        case _:
            return None
