"""Where the grammar and the golog++ standard library are.

In a source checkout they sit at the top of the repository (grammar/, stdlib/); an
installed wheel carries them inside the package (gpp/_data/). Both layouts are supported.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def _find(name: str) -> Path:
    for candidate in (_PACKAGE / "_data" / name, _PACKAGE.parent / name):
        if candidate.exists():
            return candidate
    raise FileNotFoundError(f"gpp installation is incomplete: no {name}/ beside the package")


@cache
def grammar_path() -> Path:
    return _find("grammar") / "gpp.lark"


@cache
def stdlib_dir() -> Path:
    return _find("stdlib")
