"""Checks of paths a command will write, made before any work starts."""

from __future__ import annotations

import os
from collections.abc import Iterable
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


def overwritten_input(output: Path, inputs: Iterable[tuple[Path, str]]) -> str | None:
    """What writing `output` would overwrite of the `inputs` (each a path and what it is: "the
    program", "the scenario file"), as "'agent.gpp' is the program", or None. The same file
    under another name (a link, `./x`, an absolute path) counts."""
    if not output.is_file():
        return None
    for path, what in inputs:
        try:
            if os.path.samefile(output, path):
                return f"'{output}' is {what}"
        except OSError:
            continue
    return None
