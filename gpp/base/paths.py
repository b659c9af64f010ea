"""Checks of paths a command will write, made before any work starts."""

from __future__ import annotations

from pathlib import Path


def output_problem(path: Path) -> str | None:
    """Why `path` cannot be written as a file (a folder, or in a folder that does not exist),
    or None when it can."""
    if path.is_dir():
        return f"'{path}' is a folder, not a file"
    parent = path.parent
    if not parent.is_dir():
        return f"the folder '{parent}' does not exist"
    return None
