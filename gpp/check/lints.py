"""Lints: warnings about programs that are legal but probably not what was meant.
(Placeholder until the lint pass lands: reports nothing.)"""

from __future__ import annotations

from collections.abc import Collection
from pathlib import Path

from gpp import diagnostics as diag
from gpp.model.model import Model


def run_lints(model: Model, roots: Collection[Path], allow: Collection[str] = ()) -> list[diag.Diagnostic]:
    return []
