"""Phase 3 of the model builder, declarations: what each declaration says, checked.

Runs after collect, resolve and domains, over every declaration of every file: fluents'
initial values (literals, each parameter in its own position), action sections (precondition,
effects at the end and at the start, sensing, mapping, `silent:` and `duration:`, and what an exogenous action may not
have), function bodies against the function's type, procedure and legacy main bodies,
components (clock formulas, transitions between its states) and constraints (components,
states, actions and argument patterns). Expressions and statements go to the type checker
(gpp.model.typecheck), with the declaration's parameters in scope.

Reads `state.decl_symbol`, `state.decl_params` and the resolved symbols; writes what the type
checker writes, and the references of component members and constraint atoms.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from typing import Any

from gpp.base.suggest import suggestion
from gpp.codes import E0103, E0107, E0204, E0213, E0305, E0307, E0308, E0309, E0312
from gpp.model.builder_state import BuilderState, Phase
from gpp.model.resolve import TypeResolver
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.typecheck import TypeChecker
from gpp.model.types import BOOL, ERROR, Sym, Type
from gpp.syntax import ast

Op = ast.BinaryOp

_INITIAL_LITERAL = E0213.INITIAL_VALUES

# Read for every mapping entry of an exogenous action, bound once: Python 3.11's enum class has
# a `__getattr__`, which makes reading any attribute of the class several times slower than
# reading a global.
_PARAMETER = SymbolKind.PARAMETER


class DeclarationChecker(Phase):
    def __init__(self, state: BuilderState, resolver: TypeResolver, checker: TypeChecker) -> None:
        super().__init__(state)
        self.resolver = resolver
        self.checker = checker

    def run(self) -> None:
        # One method per kind of declaration (the others say nothing to check here).
        kinds: dict[type[ast.Decl], Callable[[Any], None]] = {
            ast.FluentDecl: self.fluent,
            ast.ActionDecl: self.action,
            ast.FunctionDecl: self.function,
            ast.ProcedureDecl: self.procedure,
            ast.MainBlock: self.main_block,
            ast.ComponentDecl: self.component,
            ast.ConstraintsDecl: self.constraints,
        }
        for pf in self.model.files:
            for decl in pf.program.declarations:
                check = kinds.get(type(decl))
                if check is not None:
                    check(decl)

    def fluent(self, decl: ast.FluentDecl) -> None:
        symbol = self.state.decl_symbol.get(id(decl))
        if decl.initially is not None and symbol is not None:
            params = self.state.decl_params.get(id(decl), ())
            with self.checker.scope(decl.span, params):
                for init in decl.initially:
                    self.check_initial_value(symbol, params, init)

    def action(self, decl: ast.ActionDecl) -> None:
        symbol = self.state.decl_symbol.get(id(decl))
        if decl.sections is not None and symbol is not None:
            params = self.state.decl_params.get(id(decl), ())
            with self.checker.scope(decl.span, params):
                for section in decl.sections:
                    self.check_section(symbol, decl, params, section)

    def function(self, decl: ast.FunctionDecl) -> None:
        symbol = self.state.decl_symbol.get(id(decl))
        if decl.body is not None and symbol is not None:
            with self.checker.scope(decl.span, self.state.decl_params.get(id(decl), ())):
                assert symbol.type is not None
                value_type = self.decl_value_type(decl, symbol)
                self.checker.expect(decl.body, value_type, "the function's type", decl.type.span)

    def procedure(self, decl: ast.ProcedureDecl) -> None:
        if decl.body is not None:
            with self.checker.scope(decl.span, self.state.decl_params.get(id(decl), ())):
                self.checker.stmt(decl.body)

    def main_block(self, decl: ast.MainBlock) -> None:
        self.checker.stmt(decl.body)

    def component(self, decl: ast.ComponentDecl) -> None:
        symbol = self.state.decl_symbol.get(id(decl))
        if symbol is not None:
            self.check_component(symbol, decl)

    def constraints(self, decl: ast.ConstraintsDecl) -> None:
        for c in decl.constraints:
            self.spec(c.condition)
            self.spec(c.requirement)

    def decl_value_type(self, decl: ast.FunctionDecl | ast.FluentDecl, symbol: Symbol) -> Type:
        if symbol.decl is decl and symbol.type is not None:
            return symbol.type
        return self.resolver.resolve_type_quiet(decl.type)

    def check_initial_value(self, fluent: Symbol, params: tuple[Symbol, ...], init: ast.InitialValue) -> None:
        if len(init.args) != len(params):
            self.error(
                E0307.argument_count(fluent.name, len(params), len(init.args)),
                init.span,
                secondary=self.declared_here(fluent),
            )
        for i, arg in enumerate(init.args):
            param = params[i] if i < len(params) else None
            if isinstance(arg, ast.Name) and not arg.parenthesized:
                by_name = _parameter_named(params, arg.name)
                if by_name is not None and by_name is param:
                    self.refer(arg.span, by_name, arg)
                    self.model.expr_types[id(arg)] = by_name.type or ERROR
                    continue
                if by_name is not None:
                    position = params.index(by_name) + 1
                    self.error(
                        E0307.parameter_position(arg.name, position, param.name if param else "?"),
                        arg.span,
                        "parameter in the wrong position",
                        help="a parameter name stands for every value, and only in its own position",
                    )
                    continue
            if param is not None and param.type is not None:
                self.checker.expect_literal(arg, param.type, _INITIAL_LITERAL, f"parameter `{param.name}`", param.span)
            else:
                self.checker.expect_literal(arg, None, _INITIAL_LITERAL, "", None)
        self.checker.expect_literal(
            init.value,
            fluent.type,
            _INITIAL_LITERAL,
            f"the type of `{fluent.name}`",
            fluent.span,
            help="compute the value in a procedure and assign it there",
        )

    def check_section(
        self, action: Symbol, decl: ast.ActionDecl, params: tuple[Symbol, ...], section: ast.ActionSection
    ) -> None:
        if decl.exogenous and isinstance(section, ast.SensesSection | ast.DurationSection | ast.StartEffectSection):
            word = ast.SECTION_KINDS[type(section)].value
            self.error(
                E0309.exogenous(word),
                section.keyword,
                help="exogenous actions are events the platform reports; they are not executed",
            )
        if isinstance(section, ast.PreconditionSection):
            self.checker.expect(section.condition, BOOL, "a precondition")
        elif isinstance(section, ast.EffectSection | ast.StartEffectSection):
            for effect in section.effects:
                if effect.condition is not None:
                    self.checker.expect(effect.condition, BOOL, "an effect's condition")
                target = self.checker.assign_target(effect.target)
                self.checker.expect(effect.value, target, "the assigned fluent")
        elif isinstance(section, ast.SensesSection):
            target = self.checker.assign_target(section.target)
            self.checker.expect(section.value, target, "the sensed fluent")
        elif isinstance(section, ast.MappingSection):
            self.check_mapping(action, decl, params, section.mapping)
        elif isinstance(section, ast.SilentSection):
            v = section.value
            if not isinstance(v, ast.BoolLit | ast.NullLit):
                self.error(E0312.silent(), v.span)
        elif isinstance(section, ast.DurationSection):
            values: list[float] = []
            for v in (section.low, section.high):
                if isinstance(v, ast.NumberLit) and v.value >= 0:
                    values.append(float(v.value))
                else:
                    self.error(E0312.bound(), v.span)
            if len(values) == 2 and values[0] > values[1]:
                self.error(E0312.bounds_order(), section.span)

    def check_mapping(
        self, action: Symbol, decl: ast.ActionDecl, params: tuple[Symbol, ...], mapping: ast.Mapping
    ) -> None:
        seen: dict[str, ast.MappingArg] = {}
        bound: set[str] = set()
        for arg in mapping.args:
            first = seen.get(arg.name.name)
            if first is not None:
                self.given_twice(E0305.mapping_argument(arg.name.name), arg.name.span, first.name.span)
            else:
                seen[arg.name.name] = arg
            self.checker.expr(arg.value)
            if decl.exogenous:
                v = arg.value
                target = self.model.target(v) if isinstance(v, ast.Name) else None
                if target is not None and target.kind is _PARAMETER and not v.parenthesized:
                    bound.add(target.name)
                else:
                    self.error(
                        E0308.not_a_parameter(),
                        v.span,
                        "not a parameter",
                        notes=["the mapping is read backwards: incoming event fields set the parameters"],
                    )
        if decl.exogenous:
            bound.update(placeholders_in(mapping.name.value))  # filled from the event's name
            missing = [p.name for p in params if p.name not in bound]
            if missing:
                self.error(
                    E0308.unbound(action.name, missing),
                    mapping.span,
                    help="add " + ", ".join(f"`{m} = {m}`" for m in missing),
                )

    def check_component(self, component: Symbol, decl: ast.ComponentDecl) -> None:
        for section in decl.sections:
            if isinstance(section, ast.StatesSection):
                for s in section.states:
                    if s.invariant is not None:
                        self.clock_formula(component, s.invariant)
            elif isinstance(section, ast.TransitionsSection):
                for t in section.transitions:
                    for state in (t.source, t.target):
                        self.component_member(component, state, SymbolKind.STATE)
                    if t.guard is not None:
                        self.clock_formula(component, t.guard)
                    for c in t.resets or ():
                        self.component_member(component, c, SymbolKind.CLOCK)

    def component_member(self, component: Symbol, name: ast.Ident, kind: SymbolKind) -> Symbol | None:
        member = component.members.get(name.name)
        if member is None or member.kind is not kind:
            names = [m.name for m in component.members.values() if m.kind is kind]
            self.error(
                E0107.no_member(component.name, kind, name.name),
                name.span,
                suggested=suggestion(name.name, names),
            )
            return None
        self.refer(name.span, member, name)
        return member

    def clock_formula(self, component: Symbol, f: ast.ClockFormula) -> None:
        if isinstance(f, ast.ClockBound):
            self.component_member(component, f.clock, SymbolKind.CLOCK)
            if f.op not in (Op.LE, Op.GE):
                self.error(E0204.clock_bound(), f.span)
        elif isinstance(f, ast.ClockNot):
            self.clock_formula(component, f.operand)
        elif isinstance(f, ast.ClockBinary):
            self.clock_formula(component, f.left)
            self.clock_formula(component, f.right)

    def spec(self, s: ast.Spec) -> None:
        if isinstance(s, ast.SpecBinary):
            self.spec(s.left)
            self.spec(s.right)
        elif isinstance(s, ast.SpecUnary):
            self.spec(s.operand)
        elif isinstance(s, ast.StateAtom):
            component = self.model.globals.get(s.component.name)
            if component is None or component.kind is not SymbolKind.COMPONENT:
                globals_ = self.model.globals
                components = self.state.name_index(
                    ("globals", frozenset({SymbolKind.COMPONENT})),
                    globals_,
                    lambda: (g.name for g in globals_.values() if g.kind is SymbolKind.COMPONENT),
                )
                self.error(
                    E0107.unknown_component(s.component.name),
                    s.component.span,
                    suggested=components.suggestion(s.component.name),
                )
                return
            self.refer(s.component.span, component, s.component)
            self.component_member(component, s.state, SymbolKind.STATE)
        elif isinstance(s, ast.ActionAtom):
            g = s.action
            action = self.model.globals.get(g.name.name)
            if action is None or action.kind is not SymbolKind.ACTION:
                globals_ = self.model.globals
                actions = self.state.name_index(
                    ("globals", frozenset({SymbolKind.ACTION})),
                    globals_,
                    lambda: (x.name for x in globals_.values() if x.kind is SymbolKind.ACTION),
                )
                self.error(E0103.unknown("action", g.name.name), g.name.span, suggested=actions.suggestion(g.name.name))
                return
            self.refer(g.name.span, action, g.name)
            if len(g.args) != len(action.params):
                self.checker.arity_error(action, g.span, len(g.args))
                return
            for arg, p in zip(g.args, action.params, strict=True):
                if isinstance(arg, ast.Wildcard):
                    continue
                self.checker.expect_literal(arg, p.type, E0213.CONSTRAINT_PATTERNS, f"parameter `{p.name}`", p.span)


def _parameter_named(params: tuple[Symbol, ...], name: str) -> Symbol | None:
    """The first of `params` called `name` (a loop: no generator for a list of one or two)."""
    for p in params:
        if p.name == name:
            return p
    return None


# A placeholder in a mapped name: `"/{r}/navigate"` names parameter `r`, whose value makes the
# name (gpp.platform.ros2.placeholders).
PLACEHOLDER = re.compile(r"\{([A-Za-z_][A-Za-z0-9_]*)\}")


def placeholders_in(mapped_name: str) -> tuple[str, ...]:
    """The parameters a mapped name has as placeholders (`{r}`), each once, in order; only in
    the name, not in a type after `:`."""
    return tuple(dict.fromkeys(PLACEHOLDER.findall(mapped_name.partition(":")[0])))


def fill_placeholders(mapped_name: str, values: Mapping[str, object]) -> str:
    """`mapped_name` with each placeholder of a parameter in `values` replaced by its value: a
    symbol by its name, a whole number without a fraction, a string as it is."""

    def text(m: re.Match[str]) -> str:
        if m.group(1) not in values:
            return m.group(0)
        value = values[m.group(1)]
        if isinstance(value, Sym):
            return value.name
        if isinstance(value, float) and value.is_integer():
            return str(int(value))
        return str(value)

    name, sep, rest = mapped_name.partition(":")
    return PLACEHOLDER.sub(text, name) + sep + rest
