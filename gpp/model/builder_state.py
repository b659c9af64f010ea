"""The state the model builder's phases share, and how they report into it.

gpp.model.build runs the phases in order (collect, resolve, domains, declarations with the
type checker and the precedence regrouping); each phase is a `Phase` over one `BuilderState`:

* `model`: the code model being built (globals, types, symbols, references, targets, scopes,
  expression types, rewritten expressions); every phase adds to it;
* `diagnostics`: every error, in the order found (`report`/`error`), unless `silent`;
* `declarations`, `decl_symbol`: written by collect (each global's declaration nodes, and the
  symbol of each declaration node), read by the later phases;
* `decl_params`: written by resolve (the parameter symbols of each declaration node), read by
  the declaration checks;
* `merged`: written by resolve (a forward declaration's parameter -> the same parameter of the
  definition); the builder redirects references to them at the end;
* `silent`: while above zero, nothing is reported or recorded (a phase that only wants an
  answer, such as a type, raises it around the question);
* `reassociated`: ids of the boolean chains the regrouping has looked at (see
  gpp.model.regroup), written by it and read by the type checker.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Sequence, Sized

from gpp.base import diagnostics as diag
from gpp.base.source import Span
from gpp.base.suggest import NameIndex, Suggestion
from gpp.model.model import Model
from gpp.model.symbols import Reference, Symbol
from gpp.syntax import ast
from gpp.syntax.loader import ParsedFile

# `Reference(...)` without the call of the named tuple's generated `__new__`.
new_tuple = tuple.__new__


class BuilderState:
    """What the phases of the model builder share (see the module docstring)."""

    def __init__(self, files: Sequence[ParsedFile]) -> None:
        self.model = Model(list(files))
        # Bound once: `refer` runs for every name (the builder replaces `model.references`
        # only after the phases).
        self._add_reference = self.model.references.append
        self._targets = self.model.targets
        self.diagnostics: list[diag.Diagnostic] = []
        # Every declaration node of a global (forward ones included), in source order.
        self.declarations: dict[int, list[ast.Decl]] = {}
        # Parameters per declaration node (forward declarations have their own).
        self.decl_params: dict[int, tuple[Symbol, ...]] = {}
        self.decl_symbol: dict[int, Symbol] = {}
        self.silent = 0
        self.reassociated: set[int] = set()
        # Parameters of forward declarations -> the same parameter of the definition.
        self.merged: dict[int, Symbol] = {}
        # The did-you-mean indexes of the program-wide name tables (`name_index`).
        self._name_indexes: dict[Hashable, tuple[int, NameIndex]] = {}

    # ---------------------------------------------------------------- reporting

    def report(self, d: diag.Diagnostic) -> None:
        if not self.silent:
            self.diagnostics.append(d)

    def error(
        self,
        message: diag.Message,
        span: Span,
        label: str = "",
        *,
        secondary: Iterable[diag.Label] = (),
        notes: Iterable[str] = (),
        help: str | None = None,
        suggested: Suggestion | None = None,
        fix: diag.Fix | None = None,
    ) -> None:
        """Report an error; `suggested` names close names for the one at `span` (the help line,
        and a fix replacing it)."""
        if suggested is not None:
            help, fix = suggested.help, suggested.fix(span)
        self.report(diag.error(message, span, label, secondary=secondary, notes=notes, help=help, fix=fix))

    def name_index(self, key: Hashable, table: Sized, names: Callable[[], Iterable[str]]) -> NameIndex:
        """The did-you-mean index of the names `names()` lists from `table` (the model's globals,
        types or symbols; `key` says which of its names): built on first use, and again only
        if the table, which only grows, has grown since."""
        kept = self._name_indexes.get(key)
        if kept is None or kept[0] != len(table):
            kept = self._name_indexes[key] = (len(table), NameIndex(names()))
        return kept[1]

    def refer(self, span: Span, symbol: Symbol, node: ast.Node | None = None, declaration: bool = False) -> None:
        if self.silent:
            return
        self._add_reference(new_tuple(Reference, (span, symbol, declaration)))  # Reference(...), faster
        if node is not None:
            self._targets[id(node)] = symbol

    def given_twice(self, message: diag.Message, span: Span, first: Span) -> None:
        self.error(message, span, "given again", secondary=[diag.Label(first, "first given here")])

    def declared_here(self, symbol: Symbol, what: str = "declared here") -> list[diag.Label]:
        return [diag.Label(symbol.span, what)] if symbol.span is not None else []


class Phase:
    """One phase of the builder: the shared state, with its model and reporting at hand."""

    def __init__(self, state: BuilderState) -> None:
        self.state = state
        self.model = state.model
        # Bound once: the phases call these for every name and every error.
        self.error = state.error
        self.refer = state.refer
        self.given_twice = state.given_twice
        self.declared_here = state.declared_here
