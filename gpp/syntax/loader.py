"""Loading a program: parse the given files and everything they `#include`.

`#include "path.gpp"` is resolved relative to the including file, then in the project's include
folders (the `include` setting of gpp.toml), then in the standard library (stdlib/). Every
file is parsed once however often it is included; an include cycle is an error that shows the
chain. Included files come before the files that include them in
`LoadResult.files` (the order the original golog++ processed them).

A file is read as UTF-8 (a byte-order mark at its start is skipped). A file that is not UTF-8
text (a NUL byte, or bytes that are not UTF-8: a binary file, or text in another encoding) is
not parsed: it gets one E0006 diagnostic, at its first bad byte, or at the `#include` that
names it, instead of one syntax error per garbage character.
"""

from __future__ import annotations

import os
import threading
from collections import Counter, OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gpp.base import diagnostics as diag
from gpp.base.resources import stdlib_dir
from gpp.base.source import NotText, Source, Span, decode_text
from gpp.codes import E0006, E0030, E0031
from gpp.syntax import ast
from gpp.syntax.incremental import Reparsed, reparse
from gpp.syntax.lexer import Token, Tokens
from gpp.syntax.parser import ParseResult, parse


@dataclass(frozen=True, slots=True)
class ParsedFile:
    path: Path  # resolved, absolute
    source: Source
    program: ast.Program
    # The tokens, made when first read (`tokens`) if the file was re-parsed incrementally.
    lazy_tokens: Tokens
    # The resolved files this one includes, in order.
    includes: tuple[Path, ...]

    @property
    def tokens(self) -> list[Token]:
        return self.lazy_tokens.as_list()


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


# A file's text and its parse.
_Parsed = tuple[str, ParseResult]


class ParseCache:
    """Parsed files by resolved path and text, for a process that checks the same files again
    and again (the language server): a file whose text did not change is not parsed again, and
    a file on disk whose size and modification time did not change is not even read again.

    Syntax trees are immutable, so one parse can serve every check that includes the file.
    At most `limit` files are kept (the least recently used go first). Thread-safe.

    A file that comes back with other text is re-parsed incrementally (`incremental.reparse`:
    only the declarations the edit touched are parsed again) unless `incremental` is off;
    `reparses` counts how each such file was parsed: "splice", "tail" or "full". Besides its
    last parse, the cache keeps a file's last parse without diagnostics: while an edit is under
    way (the last parse has an error in the declaration being written), the declaration is
    spliced into that one.
    """

    def __init__(self, limit: int = 512, *, incremental: bool = True) -> None:
        self.limit = limit
        self.incremental = incremental
        self.reparses: Counter[str] = Counter()
        # Per file: its last (text, parse), and its last one without diagnostics, if any.
        self._parsed: OrderedDict[Path, tuple[_Parsed, _Parsed | None]] = OrderedDict()
        self._disk: dict[Path, tuple[int, int, str, NotText | None]] = {}
        self._lock = threading.Lock()
        self.hits = 0
        self.misses = 0

    def read(self, path: Path) -> tuple[str, NotText | None]:
        """The text of a file on disk, and why it is not text if it is not (`decode_text`);
        OSError when it cannot be read."""
        st = path.stat()
        with self._lock:
            known = self._disk.get(path)
        if known is not None and known[:2] == (st.st_mtime_ns, st.st_size):
            return known[2], known[3]
        text, not_text = decode_text(path.read_bytes())
        with self._lock:
            self._disk[path] = (st.st_mtime_ns, st.st_size, text, not_text)
        return text, not_text

    def parse(self, path: Path, text: str) -> ParseResult:
        with self._lock:
            entry = self._parsed.get(path)
            if entry is not None and entry[0][0] == text:
                self._parsed.move_to_end(path)
                self.hits += 1
                return entry[0][1]
        source = Source(text, display_path(path), str(path))
        reparsed = self._reparse(entry, source) if entry is not None and self.incremental else None
        result = parse(source) if reparsed is None else reparsed.result
        if not result.diagnostics:
            clean: _Parsed | None = (text, result)
        else:
            clean = None if entry is None else entry[1]
        with self._lock:
            self.misses += 1
            if entry is not None:
                self.reparses["full" if reparsed is None else reparsed.how] += 1
            self._parsed[path] = ((text, result), clean)
            self._parsed.move_to_end(path)
            while len(self._parsed) > self.limit:
                old, _ = self._parsed.popitem(last=False)
                self._disk.pop(old, None)
        return result

    @staticmethod
    def _reparse(entry: tuple[_Parsed, _Parsed | None], source: Source) -> Reparsed | None:
        last, clean = entry
        if clean is not None and clean is not last:
            spliced = reparse(*clean, source, splice_only=True)
            if spliced is not None:
                return spliced
        return reparse(*last, source)


def load(
    paths: Sequence[Path],
    overrides: dict[Path, str] | None = None,
    include_dirs: Sequence[Path] = (),
    *,
    cache: ParseCache | None = None,
) -> LoadResult:
    """Parse `paths` and their includes. `overrides` maps resolved paths to unsaved text
    (an editor's buffers), which wins over the file on disk; `include_dirs` are searched for
    includes after the including file's folder and before the standard library. With a `cache`,
    files parsed before with the same text are not parsed again. A root file that cannot be read
    raises OSError."""
    loader = _Loader(overrides or {}, include_dirs, cache)
    for p in paths:
        loader.load_root(p)
    loader.result.diagnostics.sort(key=diag.Diagnostic.sort_key)
    return loader.result


def load_text(text: str, path: Path) -> LoadResult:
    """Parse `text` as if it were the file `path` (includes resolve from its folder)."""
    return load([path], {path.resolve(): text})


def include_candidates(path: Path, name: str, include_dirs: Sequence[Path] = ()) -> list[Path]:
    """Where `#include "name"` in the file `path` is looked for, in order: beside the file, in
    the project's include folders, in the standard library."""
    return [path.parent / name, *(d / name for d in include_dirs), stdlib_dir() / name]


class _Loader:
    def __init__(
        self, overrides: dict[Path, str], include_dirs: Sequence[Path] = (), cache: ParseCache | None = None
    ) -> None:
        self.overrides = {p.resolve(): t for p, t in overrides.items()}
        self.include_dirs = list(include_dirs)
        self.cache = cache
        self.result = LoadResult()
        self.loaded: dict[Path, ParsedFile] = {}

    def read(self, path: Path) -> tuple[str, NotText | None]:
        """The file's text (an editor's buffer wins), and why it is not text, if it is not."""
        text = self.overrides.get(path)
        if text is not None:
            return text, None
        if self.cache is not None:
            return self.cache.read(path)
        return decode_text(path.read_bytes())

    def parse(self, path: Path, text: str) -> ParseResult:
        if self.cache is not None:
            return self.cache.parse(path, text)
        return parse(Source(text, display_path(path), str(path)))

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
        text, not_text = self.read(resolved)
        if not_text is not None:
            source = Source(text, display_path(resolved), str(resolved))
            at = Span(source, not_text.offset, min(not_text.offset + 1, len(source.text)))
            self.result.diagnostics.append(_not_text_error(None, source, not_text, at))
            self.skip(resolved, source)
            return
        self.visit(resolved, text, [])

    def skip(self, path: Path, source: Source) -> None:
        """Record a file that is not text as one without declarations: it is not parsed."""
        program = ast.Program(span=Span(source, 0, len(source.text)), declarations=())
        done = ParsedFile(path, source, program, Tokens([]), ())
        self.loaded[path] = done
        self.result.files.append(done)

    def visit(self, path: Path, text: str, chain: list[tuple[Path, ast.Include]]) -> None:
        parsed = self.parse(path, text)
        source = parsed.program.span.source
        self.result.diagnostics.extend(parsed.diagnostics)
        includes: list[Path] = []
        # Registered before its includes are visited, so that a cycle back to it is found.
        self.loaded[path] = ParsedFile(path, source, parsed.program, parsed.lazy_tokens, ())
        for decl in parsed.program.declarations:
            if isinstance(decl, ast.Include):
                target = self.include(path, decl, chain)
                if target is not None:
                    includes.append(target)
        done = ParsedFile(path, source, parsed.program, parsed.lazy_tokens, tuple(includes))
        self.loaded[path] = done
        self.result.files.append(done)

    def include(self, path: Path, decl: ast.Include, chain: list[tuple[Path, ast.Include]]) -> Path | None:
        name = decl.path.value
        candidates = include_candidates(path, name, self.include_dirs)
        target = next((c.resolve() for c in candidates if self.exists(c)), None)
        if target is None:
            self.result.diagnostics.append(
                diag.error(
                    E0030.not_found(name),
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
                    E0031.cycle([display_path(p) for p in cycle]),
                    decl.path.span,
                    "includes a file that is already being included",
                    secondary=[diag.Label(inc.path.span, "included from here") for p, inc in chain if p in cycle],
                )
            )
            return None
        if target in self.loaded:
            return target
        try:
            text, not_text = self.read(target)
        except OSError as e:
            self.result.diagnostics.append(diag.error(E0030.unreadable(name, e.strerror), decl.path.span))
            return None
        if not_text is not None:
            source = Source(text, display_path(target), str(target))
            error = _not_text_error(name, source, not_text, decl.path.span)
            self.result.diagnostics.append(error)
            self.skip(target, source)
            return target
        self.visit(target, text, [*chain, (path, decl)])
        return target


def _not_text_error(included: str | None, source: Source, not_text: NotText, at: Span) -> diag.Diagnostic:
    """E0006 for a file that is not text, reported at `at` (the bad byte, or an `#include`)."""
    line, col = source.line_col(not_text.offset)
    what = not_text.describe()
    return diag.error(
        E0006.not_text(what, line, col) if included is None else E0006.included_not_text(included, what, line, col),
        at,
        "not UTF-8 text",
        notes=[] if at.source is source else [f"the included file is {source.path}"],
        help="gpp reads programs as UTF-8 text: convert the file to UTF-8, or check that it is the right file",
    )
