"""Modules of gpp as they are at another git revision, importable beside this tree's: the
benches that time a change against the code before it (`--against`, `--ref`, `--baseline`)
load the old modules with `modules_at` and run both in one process, taking turns.

The copies form a package of their own in a temporary folder; their imports of each other are
rewritten to the copy, and everything else they import is this tree's.
"""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parent.parent


def git_text(rev: str, path: str) -> str:
    """The text of the repository file `path` at revision `rev` (CalledProcessError if git
    cannot read it)."""
    return subprocess.run(["git", "show", f"{rev}:{path}"], cwd=ROOT, capture_output=True, text=True, check=True).stdout


def python_files_at(rev: str, folder: str) -> list[str]:
    """The repository paths of the `.py` files directly in `folder` at revision `rev`."""
    names = subprocess.run(
        ["git", "ls-tree", "--name-only", f"{rev}:{folder}"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.split()
    return [f"{folder}/{name}" for name in names if name.endswith(".py")]


def modules_at(rev: str, paths: Sequence[str], into: Path, package: str) -> dict[str, ModuleType]:
    """The modules `paths` (repository paths such as `gpp/syntax/walk.py`) as they are at `rev`,
    copied into `into/package` and imported as `package.NAME`, by their file names."""
    folder = into / package
    folder.mkdir()
    (folder / "__init__.py").write_text("", encoding="utf-8")
    dotted = {p.removesuffix(".py").replace("/", "."): Path(p).stem for p in paths}
    own = re.compile(r"\b(" + "|".join(re.escape(d) for d in dotted) + r")\b")
    for path in paths:
        text = own.sub(lambda m: f"{package}.{dotted[m.group(1)]}", git_text(rev, path))
        (folder / Path(path).name).write_text(text, encoding="utf-8")
    sys.path.insert(0, str(into))
    return {Path(p).stem: importlib.import_module(f"{package}.{Path(p).stem}") for p in paths}
