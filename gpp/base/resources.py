"""Where the grammar and the golog++ standard library are.

In a source checkout they sit at the top of the repository (grammar/, stdlib/); an
installed wheel carries them inside the package (gpp/_data/). Both layouts are supported.
"""

from __future__ import annotations

import os
from functools import cache
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent.parent  # gpp/


class InstallationError(Exception):
    """gpp's installation is broken (a file missing, a dependency replaced by another version);
    the message says how to repair it."""


def _find(name: str) -> Path:
    for candidate in (_PACKAGE / "_data" / name, _PACKAGE.parent / name):
        if candidate.exists():
            return candidate
    raise InstallationError(f"gpp installation is incomplete: no {name}/ beside the package")


def cache_dir() -> Path:
    """gpp's folder in the user's cache directory (`$XDG_CACHE_HOME/gpp`, else `~/.cache/gpp`):
    the parser tables, the generated code of the syntax tree's classes, the codes page."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "gpp"


def write_cache_file(path: Path, data: bytes) -> None:
    """Write a cache file atomically (a reader never sees half of it); a cache that cannot be
    written (a read-only home) is left alone: it only costs the time to build it again."""
    from gpp.base.paths import write_atomically

    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(path, data)
    except OSError:
        pass


@cache
def grammar_path() -> Path:
    return _find("grammar") / "gpp.lark"


@cache
def stdlib_dir() -> Path:
    return _find("stdlib")


def check_lark(version: str) -> None:
    """gpp builds its parser tables with lark 1.x. The ROS 2 wheels depend on lark-parser 0.12,
    which installs into the same `lark` package and can replace lark 1.x."""
    major = version.split(".", 1)[0]
    if not major.isdigit() or int(major) < 1:
        raise InstallationError(
            f"gpp needs lark 1.x, but lark {version} is installed (lark-parser 0.12, which the ROS 2 wheels "
            "depend on, replaces it); repair with: pip uninstall -y lark-parser && "
            "pip install --force-reinstall --no-deps 'lark>=1.3.1,<2'"
        )
