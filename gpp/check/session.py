"""An analysis session: the programs an editor works on, checked again and again as they change.

The language server keeps one Session for its whole life; anything else that checks the same
files repeatedly can use one too. It holds

* the open documents (an editor's unsaved buffers, which win over the files on disk, also when
  another program includes them), with their LSP versions;
* a parse cache (`gpp.syntax.loader.ParseCache`): a file whose text did not change is not parsed
  again, so an edit re-parses one file, not every include;
* an include index over the open documents and the `.gpp` files of the workspace folders, so
  that a file opened alone is checked under the programs that include it;
* the latest check of each program, reused while none of its files changed, and otherwise the
  lint warnings about its declarations that did not change (gpp.check.lintmemo).

Positions: `Source.lsp_position` and `Source.lsp_offset` convert between character offsets and
the protocol's (line, UTF-16 unit) positions; `apply_edits` applies an editor's incremental
changes with them.

Every check runs on one long-lived `AnalysisThread`, which owns the process-wide settings a
check needs (a large thread stack and a high recursion limit, gpp.base.perf): they are set once,
not toggled around each check while other threads run.
"""

from __future__ import annotations

import os
import queue
import re
import threading
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from gpp.base import diagnostics as diag
from gpp.base.perf import start_deep_stack_thread
from gpp.base.source import Source
from gpp.check import CheckResult, check_loaded
from gpp.check.lintmemo import LintMemo
from gpp.syntax.directives import directives
from gpp.syntax.loader import ParseCache, include_candidates, load

if TYPE_CHECKING:
    from gpp.model.model import Model

T = TypeVar("T")

# `#include "file.gpp"` at the start of a line: enough to index which files include which
# (the check itself reads includes with the parser).
_INCLUDE = re.compile(r'^[ \t]*#include[ \t]*"([^"\r\n]*)"', re.MULTILINE)
# A file included by many programs is checked under this many of them at most (the open
# ones first): an edit in a library shared by a hundred test programs stays fast.
MAX_PROGRAMS = 4
# The workspace index reads at most this many files.
MAX_WORKSPACE_FILES = 5000


@dataclass(frozen=True, slots=True)
class Document:
    """An open document: an editor's buffer, by the resolved path of its file."""

    path: Path
    text: str
    version: int
    # Its text as a Source, for positions: the line starts are found once per version (by
    # the first edit or request that needs them), not again by each.
    source: Source = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "source", Source(self.text))

    @property
    def directives(self) -> dict[str, str]:
        """The `// key: value` directives at its top, read from the buffer (not from disk)."""
        return directives(self.text)


# An edit as the protocol sends it: a range ((line, character), (line, character)) in UTF-16
# units, or None for the whole text, and the new text.
LspEdit = tuple[tuple[tuple[int, int], tuple[int, int]] | None, str]


def apply_edits(text: str, edits: Iterable[LspEdit], source: Source | None = None) -> str:
    """The text after an editor's incremental changes, applied one after the other (`source`:
    `text` as a Source, if there is one already)."""
    for where, new in edits:
        if where is None:
            text = new
            continue
        if source is None or source.text is not text:
            source = Source(text)
        (l1, c1), (l2, c2) = where
        start = source.lsp_offset(l1, c1)
        end = max(start, source.lsp_offset(l2, c2))
        text = text[:start] + new + text[end:]
    return text


class Session:
    """Open documents, the include index and the checks of the programs they belong to.

    Documents change on the caller's thread; checks run wherever `check*` is called (the
    language server calls them on its AnalysisThread). A lock keeps the two consistent: a check
    sees the documents as they were when it started.
    """

    def __init__(
        self,
        folders: Sequence[Path] = (),
        lint: bool = True,
        allow: Sequence[str] = (),
        reuse_lints: bool = True,
        extra_checks: Callable[[Model], list[diag.Diagnostic]] | None = None,
    ) -> None:
        self.cache = ParseCache()
        self.lint = lint
        # Checks of a program without errors from the layers above (the language server passes
        # the platforms' static checks, gpp.platform.static, which the checker does not import).
        self.extra_checks = extra_checks
        # Whether a check reuses the lint warnings of the last one (gpp.check.lintmemo); off:
        # every check lints the whole program (to compare).
        self.reuse_lints = reuse_lints
        self.allow = tuple(allow)
        self.folders = [f.resolve() for f in folders]
        self._documents: dict[Path, Document] = {}
        self._lock = threading.Lock()
        # The includes of files on disk, by (mtime, size) when read, and of open documents, by
        # their text when all were found (both forgotten by `rescan`).
        self._disk_includes: dict[Path, tuple[tuple[int, int], tuple[Path, ...]]] = {}
        self._open_includes: dict[Path, tuple[str, tuple[Path, ...]]] = {}
        # Which files include which, for the includes it was built from.
        self._included_by: tuple[dict[Path, tuple[Path, ...]], dict[Path, list[Path]]] = ({}, {})
        self._workspace_files: list[Path] | None = None
        self._workspace_truncated = False
        # The latest check of each program: its inputs (file, parse, includes) and the result.
        self._checked: dict[Path, tuple[tuple[object, ...], CheckResult]] = {}

    # ------------------------------------------------------------ documents

    def open(self, path: Path, text: str, version: int) -> Document:
        doc = Document(path.resolve(), text, version)
        with self._lock:
            self._documents[doc.path] = doc
        return doc

    def edit(self, path: Path, edits: Iterable[LspEdit], version: int) -> Document:
        """Apply incremental changes to an open document (an unknown one starts empty)."""
        resolved = path.resolve()
        with self._lock:
            old = self._documents.get(resolved)
        text = apply_edits(old.text, edits, old.source) if old else apply_edits("", edits)
        return self.open(resolved, text, version)

    def close(self, path: Path) -> None:
        resolved = path.resolve()
        with self._lock:
            self._documents.pop(resolved, None)
        self._checked.pop(resolved, None)  # its program's check, kept no longer
        self._open_includes.pop(resolved, None)

    def document(self, path: Path) -> Document | None:
        with self._lock:
            return self._documents.get(path.resolve())

    def documents(self) -> list[Document]:
        with self._lock:
            return list(self._documents.values())

    def set_folders(self, folders: Sequence[Path]) -> None:
        self.folders = [f.resolve() for f in folders]
        self.rescan()

    def rescan(self) -> None:
        """Forget the list of workspace files and the includes read (a file was created,
        deleted or saved)."""
        self._workspace_files = None
        self._disk_includes.clear()
        self._open_includes.clear()

    # ------------------------------------------------------------ the include index

    def includes_of(self, path: Path, overrides: dict[Path, str] | None = None) -> tuple[Path, ...]:
        """The files `path` includes (resolved as the loader does: beside it, then the stdlib)."""
        opened = overrides if overrides is not None else self._texts()
        text = opened.get(path)
        if text is None:
            try:
                st = path.stat()
            except OSError:
                return ()
            stamp = (st.st_mtime_ns, st.st_size)
            known = self._disk_includes.get(path)
            if known is not None and known[0] == stamp:
                return known[1]
            try:
                text, _ = self.cache.read(path)
            except OSError:
                return ()
            found = self._resolve_includes(path, text, opened)
            self._disk_includes[path] = (stamp, found)
            return found
        cached = self._open_includes.get(path)
        if cached is not None and cached[0] == text:
            return cached[1]
        found = self._resolve_includes(path, text, opened)
        if len(found) == len(_INCLUDE.findall(text)):
            # (An include not found is looked for again next time: the file may be created.)
            self._open_includes[path] = (text, found)
        return found

    def _resolve_includes(self, path: Path, text: str, opened: dict[Path, str]) -> tuple[Path, ...]:
        found: list[Path] = []
        include_dirs = _project_settings(path)[0]
        for name in _INCLUDE.findall(text):
            for candidate in include_candidates(path, name, include_dirs):
                try:
                    target = candidate.resolve()
                    if target in opened or target.is_file():
                        found.append(target)
                        break
                except (OSError, ValueError):
                    continue
        return tuple(found)

    def workspace_files(self) -> list[Path]:
        """The `.gpp` files in the workspace folders (hidden folders such as .git and .venv left
        out), and those of the projects configured in them (a `gpp.toml` whose `paths` reach
        outside the folders); at most MAX_WORKSPACE_FILES."""
        if self._workspace_files is None:
            files: list[Path] = []
            configs: list[Path] = []
            for folder in self.folders:
                for here, dirs, names in os.walk(folder):
                    dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d != "node_modules")
                    files.extend(Path(here, n).resolve() for n in sorted(names) if n.endswith(".gpp"))
                    configs.extend(Path(here, n) for n in names if n in _CONFIG_NAMES)
                    if len(files) > MAX_WORKSPACE_FILES:
                        break
            files = list(dict.fromkeys([*files, *project_files_of(configs, self.folders)]))
            self._workspace_truncated = len(files) > MAX_WORKSPACE_FILES
            self._workspace_files = files[:MAX_WORKSPACE_FILES]
        return self._workspace_files

    def programs_seeing(self, path: Path) -> list[Path]:
        """Every program that sees the declarations of `path`: the files of the workspace, of
        its projects and of the projects of `path` and of the open documents that include
        `path` (directly or not) and are included by none of them, all of them (unlike
        `programs_of`); `path` itself when nothing includes it. Raises IncompleteSearch when
        the workspace has more files than are read."""
        path = path.resolve()
        opened = self._texts()
        configs = [found for f in (path, *opened) if (found := _config_file(f)) is not None]
        known = list(dict.fromkeys([*opened, *self.workspace_files(), *project_files_of(configs, self.folders)]))
        if self._workspace_truncated:
            raise IncompleteSearch(
                f"the workspace has more than {MAX_WORKSPACE_FILES} .gpp files, and only those were read"
            )
        included_by: dict[Path, list[Path]] = {}
        for f in known:
            for target in self.includes_of(f, opened):
                included_by.setdefault(target, []).append(f)
        return _tops(path, included_by, opened) or [path]

    def programs_of(self, path: Path, overrides: dict[Path, str] | None = None) -> list[Path]:
        """The programs `path` is checked under: the files that include it (directly or not)
        and are included by none of the known files (open documents first, then the workspace's,
        at most MAX_PROGRAMS), or `path` itself when nothing includes it."""
        path = path.resolve()
        opened = overrides if overrides is not None else self._texts()
        tops = _tops(path, self._included_by_index(opened), opened)
        return tops[:MAX_PROGRAMS] if tops else [path]

    def _included_by_index(self, opened: dict[Path, str]) -> dict[Path, list[Path]]:
        """The files that include each known file (open documents first), rebuilt only when
        the includes of some file changed."""
        known = dict.fromkeys([*opened, *self.workspace_files()])
        includes = {f: self.includes_of(f, opened) for f in known}
        if includes != self._included_by[0]:
            included_by: dict[Path, list[Path]] = {}
            for f, targets in includes.items():
                for t in targets:
                    included_by.setdefault(t, []).append(f)
            self._included_by = (includes, included_by)
        return self._included_by[1]

    # ------------------------------------------------------------ checking

    def _texts(self) -> dict[Path, str]:
        with self._lock:
            return {p: d.text for p, d in self._documents.items()}

    def snapshot(self) -> dict[Path, Document]:
        with self._lock:
            return dict(self._documents)

    def check(self, root: Path, overrides: dict[Path, str] | None = None) -> CheckResult:
        """Check the program `root` with the open documents' texts (or `overrides`). A check
        whose files, texts and includes are all as last time returns the last result."""
        root = root.resolve()
        texts = overrides if overrides is not None else self._texts()
        if root not in texts and not root.is_file():
            # A program that is no file and no open document (closed meanwhile): nothing to check.
            texts = {**texts, root: ""}
        include, disabled = _project_settings(root)
        loaded = load([root], texts, include, cache=self.cache)
        allow = (*self.allow, *disabled)
        key = (tuple((f.path, id(f.program), f.includes) for f in loaded.files), allow)
        known = self._checked.get(root)
        if known is not None and known[0] == key:
            return known[1]
        # The lints of the declarations an edit left alone are those of the last check (the
        # memo holds warnings and texts, not the last result: results do not chain).
        memo = (known[1].lint_memo if known is not None else None) or LintMemo()
        result = check_loaded(loaded, self.lint, allow, memo if self.reuse_lints else None)
        if self.extra_checks is not None and not result.errors:
            result.diagnostics.extend(self.extra_checks(result.model))
        self._checked[root] = (key, result)
        return result

    def results_for(self, path: Path, overrides: dict[Path, str] | None = None) -> list[CheckResult]:
        """The checks of the programs `path` belongs to (the first is the one features use)."""
        texts = overrides if overrides is not None else self._texts()
        return [self.check(root, texts) for root in self.programs_of(path, texts)]


class IncompleteSearch(Exception):
    """Not every file that could include a file was read; the message says why."""


_CONFIG_NAMES = frozenset({"gpp.toml", "pyproject.toml"})


def _tops(path: Path, included_by: dict[Path, list[Path]], opened: dict[Path, str]) -> list[Path]:
    """The files that include `path` (directly or not, by `included_by`) and are included by
    none of them (the open ones first); empty when nothing includes `path`."""
    ancestors: list[Path] = []
    todo = list(included_by.get(path, ()))
    while todo:
        f = todo.pop(0)
        if f not in ancestors and f != path:
            ancestors.append(f)
            todo.extend(included_by.get(f, ()))
    tops = [a for a in ancestors if not included_by.get(a)] or ancestors  # a cycle: any of them
    tops.sort(key=lambda a: (a not in opened, str(a)))
    return tops


def _config_file(path: Path) -> Path | None:
    """The configuration file of the project `path` belongs to, if any."""
    from gpp.project.config import find_config_file

    return find_config_file(path)


def project_files_of(config_files: Iterable[Path], searched: Sequence[Path] = ()) -> list[Path]:
    """The `.gpp` files of the projects these configuration files describe (their `paths`,
    minus `exclude`), but for the paths inside the folders `searched` already; a file that is
    not valid (or a pyproject.toml without gpp settings) adds none."""
    from gpp.project.config import ConfigError, config_for, find_config_file, gpp_files

    out: list[Path] = []
    for config_file in dict.fromkeys(config_files):
        if find_config_file(config_file.parent) != config_file:
            continue  # (a pyproject.toml without a [tool.gpp] table, or shadowed by a gpp.toml)
        try:
            config = config_for(config_file.parent)
            paths = [p for p in config.paths if not any(p.resolve().is_relative_to(f) for f in searched)]
            out.extend(p.resolve() for p in gpp_files(paths, config.exclude) if p.suffix == ".gpp")
        except (ConfigError, OSError):
            continue
    return out


def _project_settings(root: Path) -> tuple[tuple[Path, ...], tuple[str, ...]]:
    """The include folders and the disabled lints of the project `root` belongs to (its gpp.toml
    or [tool.gpp]), as `gpp check` uses them; the defaults while the file is not valid (`gpp
    check` reports what is wrong with it)."""
    from gpp.project.config import ConfigError, config_for

    try:
        config = config_for(root)
    except ConfigError:
        return (), ()
    return config.include, tuple(config.disabled_lints())


def diagnostics_in(results: Sequence[CheckResult], path: Path) -> list[diag.Diagnostic]:
    """The problems the checks found in one file, each once (a file shared by several programs
    may get the same report from each)."""
    identity = str(path.resolve())
    seen: set[tuple[str, int, int, str]] = set()
    found: list[diag.Diagnostic] = []
    for result in results:
        for d in result.diagnostics:
            key = (d.code, d.span.start, d.span.end, d.message)
            if d.span.source.identity == identity and key not in seen:
                seen.add(key)
                found.append(d)
    return found


class AnalysisThread:
    """One long-lived thread that runs every check, one at a time, with the deep stack the
    checker needs (see gpp.base.perf.start_deep_stack_thread)."""

    def __init__(self, name: str = "gpp-analysis") -> None:
        self._jobs: queue.SimpleQueue[Callable[[], None] | None] = queue.SimpleQueue()
        self._thread = start_deep_stack_thread(self._run, name)

    def submit(self, fn: Callable[[], T]) -> Future[T]:
        future: Future[T] = Future()

        def job() -> None:
            if not future.set_running_or_notify_cancel():
                return
            try:
                future.set_result(fn())
            except BaseException as e:  # handed to whoever waits for the future
                future.set_exception(e)

        self._jobs.put(job)
        return future

    def close(self, timeout: float = 5.0) -> None:
        self._jobs.put(None)
        self._thread.join(timeout)

    def _run(self) -> None:
        while True:
            job = self._jobs.get()
            if job is None:
                return
            job()
