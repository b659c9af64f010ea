"""The pretty-printer: turns a syntax tree back into canonical golog++ source.

`format_program` lays a whole program out (4-space indentation, declarations separated by a
blank line, one statement per line, action/fluent/component sections on their own line with
their content indented, but for the one-word `silent:` and `duration:` sections, which stay on
their keyword's line); `format_expr`, `format_stmt`, `format_type` and `format_decl` print
single nodes, e.g. for diagnostics.

The output parses back to an equal tree (`parse_text(format_program(p)).program == p`) for
every tree the parser can produce, and formatting is idempotent. To get there the printer adds
parentheses where precedence or associativity need them, and around a greedy form (a
quantifier's body, a conditional's `else` branch) when an operator it would take in follows;
parentheses the user wrote (`parenthesized=True`) are kept. A few trees the parser cannot
produce are printed as the nearest text that parses:

* a statement that would take a following `else`/`on_fail`/`on_cancel` as its own (the
  dangling `else`) is wrapped in braces, which adds a Block to the tree;
* `-` applied to a non-negative number literal prints as `-(5)`, since `-5` is a literal;
* `true`, `false` and `null` as an assignment target print in parentheses, since the lexer
  reads a keyword directly followed by `=` as a name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum, IntEnum
from typing import assert_never

from gpp.syntax import ast

INDENT = "    "


# ---------------------------------------------------------------- expressions


class _Level(IntEnum):
    """Expression precedence levels of grammar/gpp.lark, loosest first."""

    ANY = 0
    IMPLIES = 1
    OR = 2
    AND = 3
    NOT = 4  # prefix `!` and quantifiers
    COMPARE = 5
    SUM = 6
    PRODUCT = 7
    POWER = 8
    UNARY = 9  # unary `-`, negative literals and conditionals
    POSTFIX = 10  # primaries, `.f`, `[i]`


_BINARY_LEVELS: dict[ast.BinaryOp, _Level] = {
    ast.BinaryOp.IMPLIES: _Level.IMPLIES,
    ast.BinaryOp.OR: _Level.OR,
    ast.BinaryOp.AND: _Level.AND,
    ast.BinaryOp.EQ: _Level.COMPARE,
    ast.BinaryOp.NE: _Level.COMPARE,
    ast.BinaryOp.LT: _Level.COMPARE,
    ast.BinaryOp.LE: _Level.COMPARE,
    ast.BinaryOp.GT: _Level.COMPARE,
    ast.BinaryOp.GE: _Level.COMPARE,
    ast.BinaryOp.ADD: _Level.SUM,
    ast.BinaryOp.SUB: _Level.SUM,
    ast.BinaryOp.MUL: _Level.PRODUCT,
    ast.BinaryOp.DIV: _Level.PRODUCT,
    ast.BinaryOp.MOD: _Level.PRODUCT,
    ast.BinaryOp.POW: _Level.POWER,
}


@dataclass(frozen=True, slots=True)
class _Printed:
    """An expression's text with what its surroundings need to know: the grammar level it was
    produced at, and, if it ends in a greedy form, the loosest operator level that form would
    take in if one followed: any operator after a quantifier (its body is a whole expression),
    `+` and tighter after a conditional (its else branch is a sum)."""

    text: str
    level: _Level
    greedy: _Level | None = None


def _parens(p: _Printed) -> _Printed:
    return _Printed(f"({p.text})", _Level.POSTFIX)


def _sub(e: ast.Expr, at_least: _Level, followed_by: _Level | None = None, force: bool = False) -> _Printed:
    """`e` printed where the grammar wants level `at_least`, followed by an operator of level
    `followed_by` (if any), in parentheses if it needs them or the user wrote them."""
    p = _print_expr(e)
    swallows = p.greedy is not None and followed_by is not None and followed_by >= p.greedy
    # A wildcard cannot be parenthesised: `(*)` is not a constraint argument.
    if force or (e.parenthesized and type(e) is not ast.Wildcard) or p.level < at_least or swallows:
        return _parens(p)
    return p


def format_expr(e: ast.Expr) -> str:
    """An expression as source text on one line (unless it contains a multi-line string)."""
    return _sub(e, _Level.ANY).text


def _print_expr(e: ast.Expr) -> _Printed:
    """`e` without its own parentheses."""
    match e:
        case ast.NumberLit():
            text = number_literal(e.value)
            # `-5` is a unary minus folded into the literal: it binds like unary minus.
            return _Printed(text, _Level.UNARY if text.startswith("-") else _Level.POSTFIX)
        case ast.StringLit():
            return _Printed(format_string(e.value), _Level.POSTFIX)
        case ast.BoolLit():
            return _Printed("true" if e.value else "false", _Level.POSTFIX)
        case ast.NullLit():
            return _Printed("null", _Level.POSTFIX)
        case ast.Name():
            return _Printed(e.name, _Level.POSTFIX)
        case ast.Wildcard():
            return _Printed("*", _Level.POSTFIX)
        case ast.Call():
            return _Printed(f"{e.name.name}({_expr_list(e.args)})", _Level.POSTFIX)
        case ast.Unary():
            return _print_unary(e)
        case ast.Binary():
            level = _BINARY_LEVELS[e.op]
            # Left-associative: the left operand may be at the same level, the right one must
            # bind tighter (a comparison's right side is a sum, which is the next level too).
            left = _sub(e.left, level, followed_by=level)
            right = _sub(e.right, _Level(level + 1))
            return _Printed(f"{left.text} {e.op.value} {right.text}", level, right.greedy)
        case ast.Quantified():
            body = _sub(e.body, _Level.ANY)
            head = f"{e.quantifier.value}({format_type(e.var_type)} {e.var.name})"
            return _Printed(f"{head} {body.text}", _Level.NOT, greedy=_Level.IMPLIES)
        case ast.Conditional():
            condition = _sub(e.condition, _Level.ANY)
            then = _sub(e.then, _Level.ANY)
            # The else branch is a sum (grammar: `ELSE sum | ELSE sum_o`).
            otherwise = _sub(e.otherwise, _Level.SUM)
            text = f"if ({condition.text}) {then.text} else {otherwise.text}"
            return _Printed(text, _Level.UNARY, greedy=_Level.SUM)
        case ast.FieldAccess():
            # `1.x` would read as the number `1.` followed by `x`.
            subject = _sub(e.subject, _Level.POSTFIX, _Level.POSTFIX, force=type(e.subject) is ast.NumberLit)
            return _Printed(f"{subject.text}.{e.field.name}", _Level.POSTFIX)
        case ast.Index():
            subject = _sub(e.subject, _Level.POSTFIX, _Level.POSTFIX)
            return _Printed(f"{subject.text}[{format_expr(e.index)}]", _Level.POSTFIX)
        case ast.CompoundLit():
            if not e.fields:
                return _Printed(f"{e.type_name.name} {{}}", _Level.POSTFIX)
            fields = ", ".join(f"{f.name.name} = {format_expr(f.value)}" for f in e.fields)
            return _Printed(f"{e.type_name.name} {{ {fields} }}", _Level.POSTFIX)
        case ast.ListLit():
            return _Printed(f"{format_type(e.type)} [{_expr_list(e.elements)}]", _Level.POSTFIX)
        case ast.BuiltinCall():
            return _Printed(f"{e.function.value}({format_expr(e.arg)})", _Level.POSTFIX)
    raise TypeError(f"cannot format expression {type(e).__name__}")


def _print_unary(e: ast.Unary) -> _Printed:
    if e.op is ast.UnaryOp.NOT:
        operand = _sub(e.operand, _Level.NOT)
        return _Printed(f"!{operand.text}", _Level.NOT, operand.greedy)
    # The parser folds `-` into a non-negative literal (`-5`), so keep the operand apart.
    literal = isinstance(e.operand, ast.NumberLit) and e.operand.value >= 0
    operand = _sub(e.operand, _Level.UNARY, force=literal)
    # `- -4`: two minus signs in a row read fine, but keep them visibly apart.
    space = " " if operand.text.startswith("-") else ""
    return _Printed(f"-{space}{operand.text}", _Level.UNARY, operand.greedy)


def _expr_list(exprs: tuple[ast.Expr, ...]) -> str:
    return ", ".join(format_expr(x) for x in exprs)


def number_literal(value: int | float) -> str:
    """A number literal that the tokenizer reads back as the same value."""
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{value} has no golog++ literal")
        return repr(value)  # the shortest text that reads back exactly, e.g. `0.5`, `1e+16`
    return str(value)


def format_string(value: str) -> str:
    """A string literal whose value (lexer.unescape_string) is `value`.

    Only `\\"` and `\\\\` are escapes, and any other backslash is literal, so a backslash is
    doubled only where it would otherwise start an escape: before `"`, before `\\` and at the
    end of the string (where it would escape the closing quote)."""
    out: list[str] = []
    n = len(value)
    for i, c in enumerate(value):
        if c == '"':
            out.append('\\"')
        elif c == "\\" and (i + 1 == n or value[i + 1] in '"\\'):
            out.append("\\\\")
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def _target(e: ast.Expr) -> str:
    """The left side of `=` (an assignment, effect or sensing target): a postfix expression;
    a keyword literal is parenthesised because the lexer reads `true =` as a name."""
    return _sub(e, _Level.POSTFIX, force=type(e) in (ast.BoolLit, ast.NullLit)).text


def _postfix(e: ast.Expr) -> str:
    """An expression where the grammar wants a postfix expression (a called action)."""
    return _sub(e, _Level.POSTFIX).text


# ---------------------------------------------------------------- types


def format_type(t: ast.TypeExpr) -> str:
    match t:
        case ast.NamedType():
            return t.name
        case ast.ListType():
            return f"list[{format_type(t.element)}]"
    raise TypeError(f"cannot format type {type(t).__name__}")


def _params(params: tuple[ast.Param, ...]) -> str:
    return "(" + ", ".join(f"{format_type(p.type)} {p.name.name}" for p in params) + ")"


# ---------------------------------------------------------------- statements


class _Trailer(Enum):
    """A keyword that continues a statement after one of its sub-statements."""

    ELSE = "else"
    HANDLER = "on_fail/on_cancel"


def _captures(s: ast.Statement, trailer: _Trailer) -> bool:
    """Whether `s`, printed without braces and followed by `trailer`, would take the trailer as
    its own: the parser binds a dangling `else` or handler to the nearest statement."""
    match s:
        case ast.If():
            if s.otherwise is None:
                return trailer is _Trailer.ELSE or _captures(s.then, trailer)
            return _captures(s.otherwise, trailer)
        case ast.While() | ast.Pick() | ast.Solve() | ast.Search():
            return _captures(s.body, trailer)
        case ast.During():
            # `handler*`: a during takes any number of handlers, so it always takes one more.
            if trailer is _Trailer.HANDLER:
                return True
            last = s.on_cancel if s.on_cancel is not None else s.on_fail if s.on_fail is not None else s.body
            return _captures(last, trailer)
        case (
            ast.Block()
            | ast.Choose()
            | ast.Concurrent()
            | ast.Test()
            | ast.HookStmt()
            | ast.Assign()
            | ast.ListStmt()
            | ast.CallStmt()
        ):
            # Closed by their own `}` or `;`: nothing can dangle after them.
            return False
        case _:
            assert_never(s)


def _guard(s: ast.Statement, trailer: _Trailer) -> ast.Statement:
    """`s`, in braces if a following `trailer` would otherwise bind inside it."""
    return ast.Block(span=s.span, body=(s,)) if _captures(s, trailer) else s


def format_stmt(s: ast.Statement, level: int = 0) -> str:
    """A statement as source lines, indented by `level` steps (no final newline)."""
    return "\n".join(_stmt(s, level))


def _stmt(s: ast.Statement, level: int) -> list[str]:
    ind = INDENT * level
    match s:
        case ast.Block():
            return _braced(ind, s.body, level)
        case ast.Choose():
            return _braced(ind + "choose", s.alternatives, level)
        case ast.Concurrent():
            return _braced(ind + "concurrent", s.branches, level)
        case ast.If():
            head = f"{ind}if ({format_expr(s.condition)})"
            if s.otherwise is None:
                return _attach(head, s.then, level)
            then = _guard(s.then, _Trailer.ELSE)
            lines = _attach(head, then, level)
            return _continue(lines, type(then) is ast.Block, "else", s.otherwise, level)
        case ast.While():
            return _attach(f"{ind}while ({format_expr(s.condition)})", s.body, level)
        case ast.Pick():
            values = "" if s.values is None else f" in {{{_expr_list(s.values)}}}"
            return _attach(f"{ind}pick ({format_type(s.var_type)} {s.var.name}{values})", s.body, level)
        case ast.Solve():
            return _attach(f"{ind}solve({format_expr(s.horizon)}, {format_expr(s.reward)})", s.body, level)
        case ast.Search():
            return _attach(f"{ind}search", s.body, level)
        case ast.During():
            return _during(s, level)
        case ast.Test():
            return [f"{ind}test({format_expr(s.condition)});"]
        case ast.HookStmt():
            return [f"{ind}{s.hook.value}({_postfix(s.action)});"]
        case ast.Assign():
            return [f"{ind}{_target(s.target)} = {format_expr(s.value)};"]
        case ast.ListStmt():
            value = "" if s.value is None else f", {format_expr(s.value)}"
            return [f"{ind}{s.op.value}({format_expr(s.target)}{value});"]
        case ast.CallStmt():
            return [f"{ind}{_postfix(s.call)};"]
        case _:
            assert_never(s)


def _during(s: ast.During, level: int) -> list[str]:
    handlers = [(word, h) for word, h in (("on_fail", s.on_fail), ("on_cancel", s.on_cancel)) if h is not None]
    previous = _guard(s.body, _Trailer.HANDLER) if handlers else s.body
    until = "" if s.until is None else f" until ({format_expr(s.until)})"
    lines = _attach(f"{INDENT * level}during ({_postfix(s.action)}){until}", previous, level)
    for i, (word, handler) in enumerate(handlers):
        # A handler followed by another one must not take it as its own.
        current = _guard(handler, _Trailer.HANDLER) if i + 1 < len(handlers) else handler
        lines = _continue(lines, type(previous) is ast.Block, word, current, level)
        previous = current
    return lines


def _braced(head: str, body: tuple[ast.Statement, ...], level: int) -> list[str]:
    """`head {`, the statements one level deeper, `}`; `head {}` when empty."""
    opening = f"{head} {{" if head.strip() else f"{head}{{"
    if not body:
        return [opening + "}"]
    lines = [opening]
    for s in body:
        lines.extend(_stmt(s, level + 1))
    lines.append(INDENT * level + "}")
    return lines


def _attach(head: str, body: ast.Statement, level: int) -> list[str]:
    """A statement header followed by its body: a block opens on the header line, any other
    statement goes on the next lines, one level deeper."""
    if type(body) is ast.Block:
        return _braced(head, body.body, level)
    return [head, *_stmt(body, level + 1)]


def _continue(lines: list[str], after_block: bool, keyword: str, body: ast.Statement, level: int) -> list[str]:
    """`lines` continued by `keyword body` (`else`, `on_fail`, `on_cancel`): after a block on
    the closing brace's line (`} else {`), else on a new line; `else if` stays on one line."""
    ind = INDENT * level
    if after_block:
        head = f"{lines[-1]} {keyword}"
        lines = lines[:-1]
    else:
        head = ind + keyword
    if keyword == "else" and type(body) is ast.If:
        chained = _stmt(body, level)
        return [*lines, f"{head} {chained[0][len(ind) :]}", *chained[1:]]
    return [*lines, *_attach(head, body, level)]


# ---------------------------------------------------------------- domains


def format_domain(d: ast.DomainExpr) -> str:
    """A domain expression; the operators group to the right (`A | B \\ C` = `A | (B \\ C)`)."""
    text = _print_domain(d)
    return f"({text})" if d.parenthesized else text


def _print_domain(d: ast.DomainExpr) -> str:
    match d:
        case ast.DomainRef():
            return d.name.name
        case ast.DomainSet():
            return f"{{{_expr_list(d.elements)}}}"
        case ast.DomainBinary():
            left = format_domain(d.left)
            # Only an operand may stand on the left of an operator.
            if type(d.left) is ast.DomainBinary and not d.left.parenthesized:
                left = f"({left})"
            return f"{left} {d.op.value} {format_domain(d.right)}"
    raise TypeError(f"cannot format domain expression {type(d).__name__}")


# ---------------------------------------------------------------- platform model

# Clock formulas: `|` loosest, then `&`, then `!`, bounds and parentheses.
_CLOCK_LEVELS: dict[ast.BinaryOp, int] = {ast.BinaryOp.OR: 1, ast.BinaryOp.AND: 2}
_CLOCK_UNARY = 3


def format_clock(c: ast.ClockFormula, at_least: int = 0) -> str:
    text, level = _print_clock(c)
    return f"({text})" if c.parenthesized or level < at_least else text


def _print_clock(c: ast.ClockFormula) -> tuple[str, int]:
    match c:
        case ast.ClockBound():
            return f"{c.clock.name} {c.op.value} {number_literal(c.bound.value)}", _CLOCK_UNARY
        case ast.ClockNot():
            return f"!{format_clock(c.operand, _CLOCK_UNARY)}", _CLOCK_UNARY
        case ast.ClockBinary():
            level = _CLOCK_LEVELS[c.op]
            left = format_clock(c.left, level)
            right = format_clock(c.right, level + 1)
            return f"{left} {c.op.value} {right}", level
    raise TypeError(f"cannot format clock formula {type(c).__name__}")


# Constraint specs: `until`/`since` loosest, then `|`, then `&`, then prefix operators and atoms.
_SPEC_LEVELS: dict[ast.SpecOp, int] = {ast.SpecOp.UNTIL: 1, ast.SpecOp.SINCE: 1, ast.SpecOp.OR: 2, ast.SpecOp.AND: 3}
_SPEC_UNARY = 4


def format_spec(s: ast.Spec, at_least: int = 0) -> str:
    text, level = _print_spec(s)
    return f"({text})" if s.parenthesized or level < at_least else text


def _bound(b: ast.Bound | None) -> str:
    if b is None:
        return ""
    low = "" if b.low is None else number_literal(b.low.value)
    high = "" if b.high is None else number_literal(b.high.value)
    return f"[{low}, {high}]"


def _print_spec(s: ast.Spec) -> tuple[str, int]:
    match s:
        case ast.SpecBinary():
            level = _SPEC_LEVELS[s.op]
            left = format_spec(s.left, level)
            right = format_spec(s.right, level + 1)
            # Only `until` and `since` take a bound (`a until[, 3] b`).
            bound = _bound(s.bound) if level == 1 else ""
            return f"{left} {s.op.value}{bound} {right}", level
        case ast.SpecUnary():
            return f"{s.op.value}{_bound(s.bound)} {format_spec(s.operand, _SPEC_UNARY)}", _SPEC_UNARY
        case ast.ActionAtom():
            args = ", ".join(format_expr(a) for a in s.action.args)
            return f"{s.hook}({s.action.name.name}({args}))", _SPEC_UNARY
        case ast.StateAtom():
            return f"state({s.component.name}) = {s.state.name}", _SPEC_UNARY
    raise TypeError(f"cannot format constraint spec {type(s).__name__}")


def _state_def(s: ast.StateDef) -> str:
    return s.name.name if s.invariant is None else f"{s.name.name}({format_clock(s.invariant)})"


def _transition(t: ast.Transition) -> str:
    arrow = "=>" if t.controllable else "->"
    guard = "" if t.guard is None else f" ({format_clock(t.guard)})"
    resets = "" if t.resets is None else " resets(" + ", ".join(r.name for r in t.resets) + ")"
    return f"{t.source.name} {arrow}{guard} {t.target.name}{resets}"


def _component_section(s: ast.ComponentSection) -> list[str]:
    match s:
        case ast.ClocksSection():
            return ["clocks:", INDENT + ", ".join(c.name for c in s.clocks)]
        case ast.StatesSection():
            return ["states:", INDENT + ", ".join(_state_def(d) for d in s.states)]
        case ast.TransitionsSection():
            n = len(s.transitions)
            lines = [INDENT + _transition(t) + ("," if i + 1 < n else "") for i, t in enumerate(s.transitions)]
            return ["transitions:", *lines]
    raise TypeError(f"cannot format component section {type(s).__name__}")


# ---------------------------------------------------------------- declarations


def _action_section(s: ast.ActionSection) -> list[str]:
    match s:
        case ast.PreconditionSection():
            return ["precondition:", INDENT + format_expr(s.condition)]
        case ast.EffectSection():
            return ["effect:", *(INDENT + _effect(e) for e in s.effects)]
        case ast.StartEffectSection():
            return ["start_effect:", *(INDENT + _effect(e) for e in s.effects)]
        case ast.SensesSection():
            return ["senses:", f"{INDENT}{_target(s.target)} = {format_expr(s.value)};"]
        case ast.MappingSection():
            return ["mapping:", INDENT + _mapping(s.mapping)]
        case ast.SilentSection():
            return [f"silent: {format_expr(s.value)}"]
        case ast.DurationSection():
            return [f"duration: [{format_expr(s.low)}, {format_expr(s.high)}]"]
    raise TypeError(f"cannot format action section {type(s).__name__}")


def _effect(e: ast.Effect) -> str:
    condition = "" if e.condition is None else f"if ({format_expr(e.condition)}) "
    return f"{condition}{_target(e.target)} = {format_expr(e.value)};"


def _mapping(m: ast.Mapping) -> str:
    name = format_string(m.name.value)
    if not m.args:
        return f"{name} {{}}"
    args = ", ".join(f"{a.name.name} = {format_expr(a.value)}" for a in m.args)
    return f"{name} {{ {args} }}"


def _sectioned(head: str, sections: list[list[str]]) -> list[str]:
    """`head {`, section keywords at the declaration's indentation with their content one
    level deeper, `}`."""
    if not sections:
        return [head + " {}"]
    return [head + " {", *(line for section in sections for line in section), "}"]


def format_decl(d: ast.Decl) -> str:
    """A top-level declaration as source lines (no final newline)."""
    return "\n".join(_decl(d))


def _decl(d: ast.Decl) -> list[str]:
    match d:
        case ast.Include():
            return [f"#include {format_string(d.path.value)}"]
        case ast.DomainDecl():
            head = f"{format_type(d.element_type)} domain {d.name.name}"
            return [f"{head};" if d.definition is None else f"{head} = {format_domain(d.definition)}"]
        case ast.CompoundDecl():
            fields = ", ".join(f"{format_type(p.type)} {p.name.name}" for p in d.fields)
            return [f"compound {d.name.name} {{ {fields} }}"]
        case ast.ListTypeDecl():
            return [format_type(d.type)]
        case ast.FluentDecl():
            head = f"{format_type(d.type)} fluent {d.name.name}{_params(d.params)}"
            if d.initially is None:
                return [head + ";"]
            values = [f"{INDENT}({_expr_list(v.args)}) = {format_expr(v.value)};" for v in d.initially]
            return [head + " {", "initially:", *values, "}"]
        case ast.ActionDecl():
            head = f"{'exog_action' if d.exogenous else 'action'} {d.name.name}{_params(d.params)}"
            if d.sections is None:
                return [head + ";"]
            return _sectioned(head, [_action_section(s) for s in d.sections])
        case ast.FunctionDecl():
            head = f"{format_type(d.type)} function {d.name.name}{_params(d.params)}"
            return [head + ";" if d.body is None else f"{head} = {format_expr(d.body)}"]
        case ast.ExogFunctionDecl():
            return [f"{format_type(d.type)} exog_function {d.name.name}{_params(d.params)};"]
        case ast.ProcedureDecl():
            head = f"procedure {d.name.name}{_params(d.params)}"
            return [head + ";"] if d.body is None else _attach(head, d.body, 0)
        case ast.MainBlock():
            return _braced("", d.body.body, 0)
        case ast.ComponentDecl():
            return _sectioned(f"component {d.name.name}", [_component_section(s) for s in d.sections])
        case ast.ConstraintsDecl():
            lines = [f"{INDENT}{format_spec(c.condition)}: {format_spec(c.requirement)};" for c in d.constraints]
            return ["constraints {", *lines, "}"]
    raise TypeError(f"cannot format declaration {type(d).__name__}")


def format_program(program: ast.Program) -> str:
    """The whole program: declarations separated by a blank line, ending in a newline."""
    if not program.declarations:
        return ""
    return "\n\n".join(format_decl(d) for d in program.declarations) + "\n"
