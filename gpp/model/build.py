"""Builds the code model from parsed files, reporting every name, type and declaration error.

Phases, each over all files, so declaration order never matters (SEMANTICS §2.1); they share
one gpp.model.builder_state.BuilderState:

1. collect (gpp.model.collect): every global, type and domain by name; forward declarations
   merged with their definitions; clashes and second definitions reported;
2. resolve (gpp.model.resolve, gpp.model.domains): parameter, field and value types; domains
   evaluated to their member sets (which also declares the symbols); forward declarations
   compared with their definitions;
3. declarations (gpp.model.declarations): one typed walk over every declaration's expressions
   and statements by the type checker (gpp.model.typecheck), which records each reference and
   each expression's type and reports what does not fit, regrouping boolean `==`/`!=` by type
   as it goes (gpp.model.regroup). An expression that already has an error gets the type
   ERROR, which fits everywhere, so a mistake is reported once.
"""

from __future__ import annotations

from collections.abc import Sequence

from gpp.base import diagnostics as diag
from gpp.base.perf import paused_gc
from gpp.model.builder_state import BuilderState
from gpp.model.collect import Collector
from gpp.model.declarations import DeclarationChecker
from gpp.model.domains import DomainEvaluator
from gpp.model.model import Model
from gpp.model.resolve import TypeResolver
from gpp.model.symbols import Reference
from gpp.model.typecheck import TypeChecker
from gpp.syntax.loader import ParsedFile


def build_model(files: Sequence[ParsedFile]) -> tuple[Model, list[diag.Diagnostic]]:
    with paused_gc():
        builder = ModelBuilder(files)
        builder.run()
        built = builder.model, builder.diagnostics
        # Freed here, before the collector runs again when the pause ends: it would scan the
        # builder's tables (declarations by symbol, parameters by declaration, ...) once more.
        del builder
    return built


class ModelBuilder:
    """Runs the phases in order over one shared state."""

    def __init__(self, files: Sequence[ParsedFile]) -> None:
        self.state = BuilderState(files)
        self.model = self.state.model
        self.diagnostics = self.state.diagnostics

    def run(self) -> None:
        state = self.state
        resolver = TypeResolver(state)
        checker = TypeChecker(state, resolver)
        Collector(state).run()
        resolver.run()
        DomainEvaluator(state, checker).run()
        resolver.resolve_compound_fields()
        resolver.check_forward_declarations()
        DeclarationChecker(state, resolver, checker).run()
        self.redirect_merged_parameters()

    def redirect_merged_parameters(self) -> None:
        """References to a forward declaration's parameters go to the definition's."""
        merged = self.state.merged
        if not merged:
            return
        self.model.references = [
            Reference(r.span, merged.get(id(r.symbol), r.symbol), r.declaration) for r in self.model.references
        ]
        for key, symbol in list(self.model.targets.items()):
            if id(symbol) in merged:
                self.model.targets[key] = merged[id(symbol)]
