"""Loading a program: parse the given files and everything they `#include`.

`#include "path.gpp"` is resolved relative to the including file, then in the project's include
folders (the `include` setting of gpp.toml), then in the standard library (stdlib/). Every
file is parsed once however often it is included; an include cycle is an error that shows the
chain. Included files come before the files that include them in
`LoadResult.files` (the order the original golog++ processed them).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gpp import diagnostics as diag
from gpp.resources import stdlib_dir
from gpp.source import Source
from gpp.syntax import ast
from gpp.syntax.lexer import Token
from gpp.syntax.parser import parse


@dataclass(frozen=True, slots=True)
class ParsedFile:
    path: Path  # resolved, absolute
    source: Source
    program: ast.Program
    tokens: list[Token]
    # The resolved files this one includes, in order.
    includes: tuple[Path, ...]


@dataclass
class LoadResult:
    files: list[ParsedFile] = field(default_factory=list)
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    # The resolved paths of the files asked for (not reached only through `#include`).
    roots: list[Path] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)

    def file(self, path: Path) -> ParsedFile | None:
        resolved = path.resolve()
        return next((f for f in self.files if f.path == resolved), None)


def display_path(path: Path) -> str:
    """A path as diagnostics show it: relative to the working directory when below it."""
    try:
        rel = os.path.relpath(path)
    except ValueError:
        return str(path)
    return str(path) if rel.startswith("..") else rel


def load(
    paths: Sequence[Path], overrides: dict[Path, str] | None = None, include_dirs: Sequence[Path] = ()
) -> LoadResult:
    """Parse `paths` and their includes. `overrides` maps resolved paths to unsaved text
    (an editor's buffers); `include_dirs` are searched for includes after the including file's
    folder and before the standard library. A root file that cannot be read raises OSError."""
    loader = _Loader(overrides or {}, include_dirs)
    for p in paths:
        loader.load_root(p)
    loader.result.diagnostics.sort(key=diag.Diagnostic.sort_key)
    return loader.result


def load_text(text: str, path: Path) -> LoadResult:
    """Parse `text` as if it were the file `path` (includes resolve from its folder)."""
    return load([path], {path.resolve(): text})


class _Loader:
    def __init__(self, overrides: dict[Path, str], include_dirs: Sequence[Path] = ()) -> None:
        self.overrides = {p.resolve(): t for p, t in overrides.items()}
        self.include_dirs = list(include_dirs)
        self.result = LoadResult()
        self.loaded: dict[Path, ParsedFile] = {}

    def read(self, path: Path) -> Source:
        text = self.overrides.get(path)
        if text is not None:
            return Source(text, display_path(path))
        raw = path.read_bytes()
        return Source(raw.decode("utf-8", errors="replace"), display_path(path))

    def exists(self, candidate: Path) -> bool:
        """Is there a file (or an editor buffer) at `candidate`? A path the OS cannot even look
        up (a NUL byte, a name too long) is simply not there."""
        try:
            return candidate.resolve() in self.overrides or candidate.is_file()
        except (OSError, ValueError):
            return False

    def load_root(self, path: Path) -> None:
        resolved = path.resolve()
        if resolved not in self.result.roots:
            self.result.roots.append(resolved)
        if resolved in self.loaded:
            return
        source = self.read(resolved)
        self.visit(resolved, source, [])

    def visit(self, path: Path, source: Source, chain: list[tuple[Path, ast.Include]]) -> None:
        parsed = parse(source)
        self.result.diagnostics.extend(parsed.diagnostics)
        includes: list[Path] = []
        # Registered before its includes are visited, so that a cycle back to it is found.
        self.loaded[path] = ParsedFile(path, source, parsed.program, parsed.tokens, ())
        for decl in parsed.program.declarations:
            if isinstance(decl, ast.Include):
                target = self.include(path, decl, chain)
                if target is not None:
                    includes.append(target)
        done = ParsedFile(path, source, parsed.program, parsed.tokens, tuple(includes))
        self.loaded[path] = done
        self.result.files.append(done)

    def include(self, path: Path, decl: ast.Include, chain: list[tuple[Path, ast.Include]]) -> Path | None:
        name = decl.path.value
        candidates = [path.parent / name, *(d / name for d in self.include_dirs), stdlib_dir() / name]
        target = next((c.resolve() for c in candidates if self.exists(c)), None)
        if target is None:
            self.result.diagnostics.append(
                diag.error(
                    "E0030",
                    f"cannot find included file `{name}`",
                    decl.path.span,
                    "no such file",
                    notes=[f"looked in {display_path(c.parent)}/" for c in candidates],
                )
            )
            return None
        in_chain = [p for p, _ in chain] + [path]
        if target in in_chain:
            cycle = [*in_chain[in_chain.index(target) :], target]
            self.result.diagnostics.append(
                diag.error(
                    "E0031",
                    "include cycle: " + " -> ".join(display_path(p) for p in cycle),
                    decl.path.span,
                    "includes a file that is already being included",
                    secondary=[diag.Label(inc.path.span, "included from here") for p, inc in chain if p in cycle],
                )
            )
            return None
        if target in self.loaded:
            return target
        try:
            source = self.read(target)
        except OSError as e:
            self.result.diagnostics.append(
                diag.error("E0030", f"cannot read included file `{name}`: {e.strerror}", decl.path.span)
            )
            return None
        self.visit(target, source, [*chain, (path, decl)])
        return target
