"""A complete, deterministic text description of a code model and its diagnostics, for
tests/model/test_model_identical.py and bench/model_speed.py: two builds of the model are the same
exactly when their descriptions are.

Described: every symbol table (globals, types, symbols, with each symbol's kind, span, type,
signature, parameters, members, other spans), every reference in order, every scope, the type
of every expression, the target of every node, every rewritten expression (its whole rebuilt
tree) and every diagnostic with all its parts. Nodes are named by their position in a walk of
the files (parents first), and nodes that are not in the files (the rebuilt trees) by their
place under the expression they replace; symbols by kind, name, span and owner.

Types and targets recorded for nodes that no longer exist are left out: while regrouping
boolean chains the type checker types trees it then throws away, and their entries, keyed by
the ids of freed objects, depend on how memory was reused (no node of the model has them)."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path

from gpp.base import diagnostics as diag
from gpp.base.source import Span
from gpp.model.model import Model
from gpp.model.symbols import Symbol
from gpp.syntax import ast
from gpp.syntax.walk import walk

ROOT = Path(__file__).resolve().parents[2]


def _where(identity: str) -> str:
    path = Path(identity)
    try:
        return path.resolve().relative_to(ROOT).as_posix()
    except ValueError:
        return path.name


class _Describer:
    def __init__(self, model: Model) -> None:
        self.model = model
        self.files: dict[int, str] = {}
        self.nodes: dict[int, str] = {}
        for pf in model.files:
            self.files[id(pf.source)] = _where(pf.source.identity)
            for k, node in enumerate(walk(pf.program)):
                self.nodes[id(node)] = f"{self.files[id(pf.source)]}#{k}"
        for key in sorted(model.rewritten, key=lambda i: self.nodes.get(i, "?")):
            for k, node in enumerate(walk(model.rewritten[key])):
                self.nodes.setdefault(id(node), f"{self.nodes.get(key, '?')}>{k}")

    def span(self, span: Span | None) -> str:
        if span is None:
            return "-"
        where = self.files.get(id(span.source)) or _where(span.source.identity)
        return f"{where}:{span.start}-{span.end}"

    def symbol(self, s: Symbol | None) -> str:
        if s is None:
            return "-"
        owner = f" of {s.owner.kind.value} {s.owner.name}" if s.owner is not None else ""
        return f"{s.kind.value} {s.name}@{self.span(s.span)}{owner}"

    def symbol_details(self, s: Symbol) -> str:
        params = ", ".join(self.symbol(p) + f": {p.type}" for p in s.params)
        members = ", ".join(f"{n}={self.symbol(m)}" for n, m in s.members.items())
        others = ", ".join(self.span(x) for x in s.other_spans)
        decl = self.nodes.get(id(s.decl), type(s.decl).__name__) if s.decl is not None else "-"
        return (
            f"{self.symbol(s)} type={s.type} sig={s.signature()} params=[{params}] members=[{members}]"
            f" others=[{others}] decl={decl} predefined={s.predefined} defined={s.is_defined}"
        )

    def node(self, i: int) -> str:
        return self.nodes.get(i, "?")

    def tree(self, e: ast.Node) -> str:
        """A rebuilt expression, structurally (its leaves are nodes of the files)."""
        if isinstance(e, ast.Binary):
            return f"({self.tree(e.left)} {e.op.value} {self.tree(e.right)})@{self.span(e.span)}{e.parenthesized}"
        if isinstance(e, ast.Unary):
            return f"({e.op.value}{self.tree(e.operand)})@{self.span(e.span)}{e.parenthesized}"
        return self.node(id(e))

    def diagnostic(self, d: diag.Diagnostic) -> str:
        parts = [d.code, d.severity.value, d.message, self.span(d.span), d.label]
        parts += [f"label {self.span(x.span)} {x.message}" for x in d.secondary]
        parts += [f"note {n}" for n in d.notes]
        parts.append(f"help {d.help}")
        if d.fix is not None:
            edits = "; ".join(f"{self.span(e.span)}={e.text!r}" for e in d.fix.edits)
            parts.append(f"fix {d.fix.message} [{edits}] {d.fix.applicability.value}")
        return " | ".join(parts)

    def lines(self, diagnostics: Sequence[diag.Diagnostic]) -> list[str]:
        m = self.model
        out: list[str] = []
        for table_name, table in (("global", m.globals), ("type", m.types), ("symbol", m.symbols)):
            for name, s in table.items():
                out.append(f"{table_name} {name}: {self.symbol_details(s)}")
        out.append(f"main: {self.symbol(m.main)}")
        out += [f"ref {self.span(r.span)} -> {self.symbol(r.symbol)} {r.declaration}" for r in m.references]
        for scope in m.scopes:
            out.append(f"scope {self.span(scope.span)}: " + ", ".join(self.symbol(s) for s in scope.symbols))
        out += sorted(f"type {self.node(i)} {t}" for i, t in m.expr_types.items() if i in self.nodes)
        out += sorted(f"target {self.node(i)} -> {self.symbol(s)}" for i, s in m.targets.items() if i in self.nodes)
        out += sorted(f"rewritten {self.node(i)} = {self.tree(e)}" for i, e in m.rewritten.items())
        out += [f"diagnostic {self.diagnostic(d)}" for d in diagnostics]
        return out


def describe(model: Model, diagnostics: Sequence[diag.Diagnostic]) -> list[str]:
    """The model and the diagnostics, one fact a line."""
    return _Describer(model).lines(diagnostics)


def fingerprint(model: Model, diagnostics: Sequence[diag.Diagnostic]) -> dict[str, object]:
    """What the goldens keep: counts a reader can compare, and the digest of the description."""
    lines = describe(model, diagnostics)
    digest = hashlib.sha256("\n".join(lines).encode()).hexdigest()
    return {
        "references": len(model.references),
        "types": sum(1 for line in lines if line.startswith("type ")),
        "targets": sum(1 for line in lines if line.startswith("target ")),
        "scopes": len(model.scopes),
        "rewritten": len(model.rewritten),
        "diagnostics": len(diagnostics),
        "sha256": digest,
    }
