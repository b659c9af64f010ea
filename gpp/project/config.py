"""Project configuration: a `gpp.toml`, or the `[tool.gpp]` table of a `pyproject.toml`.

The configuration of a file is the nearest one found going up from the file's folder (in each
folder a `gpp.toml` first, then a `pyproject.toml` with a `[tool.gpp]` table); the nearest file
wins as a whole, its paths are relative to its folder, and options given on the command line
override it. The keys: docs/config.md. An unknown key (with a did-you-mean), a value of the
wrong type or an unknown lint is a diagnostic located in the file; the commands exit with
status 2.
"""

from __future__ import annotations

import fnmatch
import math
import os
import re
import tomllib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gpp import codes
from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.base.suggest import did_you_mean

CONFIG_NAME = "gpp.toml"
PYPROJECT = "pyproject.toml"
DEFAULT_TEST_PATHS = ("tests/programs",)
ALL = "all"


class ConfigError(Exception):
    """A configuration file that cannot be used; `diagnostic` says where and why."""

    def __init__(self, diagnostic: diag.Diagnostic) -> None:
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic


@dataclass
class Config:
    """The settings of one project: the file's values, the defaults for the rest."""

    file: Path | None = None  # the file the settings come from (None: defaults only)
    table: str = ""  # "" for a gpp.toml, "tool.gpp" in a pyproject.toml
    root: Path = field(default_factory=Path.cwd)  # the folder paths are relative to
    paths: tuple[Path, ...] = ()
    exclude: tuple[str, ...] = ()
    include: tuple[Path, ...] = ()
    lint_enable: tuple[str, ...] | None = None  # codes; None: every lint
    lint_disable: tuple[str, ...] = ()
    deny_warnings: bool = False
    run_platform: str | None = None
    run_world: str | None = None
    # The bounds of a run (SEMANTICS §4): `timeout` in wall-clock seconds, `time_limit` in
    # seconds of platform time.
    run_timeout: float | None = None
    run_time_limit: float | None = None
    test_paths: tuple[Path, ...] = ()
    test_timeout: float | None = None
    test_time_limit: float | None = None
    given: set[str] = field(default_factory=set)  # the dotted keys the file sets

    def __post_init__(self) -> None:
        if not self.paths:
            self.paths = (self.root,)
        if not self.test_paths:
            self.test_paths = tuple(self.root / p for p in DEFAULT_TEST_PATHS)

    def disabled_lints(self) -> list[str]:
        """The codes of the lints not reported."""
        enabled = {c.code for c in codes.lints()} if self.lint_enable is None else set(self.lint_enable)
        return sorted({c.code for c in codes.lints() if c.code not in enabled} | set(self.lint_disable))


# ---------------------------------------------------------------- finding the file


def find_config_file(start: Path) -> Path | None:
    """The nearest `gpp.toml`, or `pyproject.toml` with a `[tool.gpp]` table, from `start` (a file
    or a folder) upwards."""
    try:
        folder = start.resolve()
    except RuntimeError:  # a symbolic link that loops: its folder is where it is written
        folder = Path(os.path.abspath(start))
    if not folder.is_dir():
        folder = folder.parent
    for candidate in (folder, *folder.parents):
        own = candidate / CONFIG_NAME
        if own.exists():  # a folder named gpp.toml is an error when it is read, not passed over
            return own
        pyproject = candidate / PYPROJECT
        if pyproject.is_file() and _has_gpp_table(pyproject):
            return pyproject
    return None


def _has_gpp_table(pyproject: Path) -> bool:
    try:
        data = tomllib.loads(pyproject.read_text(encoding="utf-8").removeprefix("\ufeff"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False  # not ours to judge: a broken pyproject.toml without gpp settings is passed over
    tool = data.get("tool")
    return isinstance(tool, dict) and "gpp" in tool


# Read files by path, as long as they do not change (a long-lived process, such as the
# language server, sees edits).
_CACHE: dict[Path, tuple[tuple[int, int], Config]] = {}


def config_for(start: Path) -> Config:
    """The settings for a file or folder: from the nearest configuration file, else the
    defaults (relative to the working directory). Raises ConfigError for a bad file."""
    found = find_config_file(start)
    if found is None:
        return Config()
    stat = found.stat()
    stamp = (stat.st_mtime_ns, stat.st_size)
    cached = _CACHE.get(found)
    if cached is None or cached[0] != stamp:
        cached = _CACHE[found] = (stamp, load_config(found))
    return cached[1]


# ---------------------------------------------------------------- reading and checking the file


def load_config(path: Path) -> Config:
    """The settings in a `gpp.toml` or a `pyproject.toml`; ConfigError when the file is not
    readable TOML or has unknown keys or values of the wrong type."""
    shown = _display(path)
    try:
        # A byte-order mark is read as gpp check reads one in a program: as nothing.
        text = path.read_text(encoding="utf-8").removeprefix("\ufeff")
    except (OSError, UnicodeDecodeError) as e:
        reason = e.strerror if isinstance(e, OSError) else "not UTF-8 text"
        if path.is_dir():
            reason = "it is a folder, not a file"
        raise ConfigError(
            diag.error(diag.Message("", f"cannot read {shown}: {reason}"), Span(Source("", shown), 0, 0))
        ) from None
    source = Source(text, shown)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(
            diag.error(diag.Message("", f"{shown} is not valid TOML: {e}"), _toml_error_span(source, str(e)))
        ) from None
    prefix: tuple[str, ...] = ()
    if path.name == PYPROJECT:
        prefix = ("tool", "gpp")
        data = data.get("tool", {}).get("gpp", {})
    reader = _Reader(source, prefix)
    return reader.config(data, path)


def _display(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def _toml_error_span(source: Source, message: str) -> Span:
    m = re.search(r"at line (\d+), column (\d+)", message)
    if not m:
        return Span(source, 0, 0)
    starts = source.line_starts
    line = min(int(m.group(1)), len(starts)) - 1
    at = min(starts[line] + int(m.group(2)) - 1, len(source.text))
    return Span(source, at, at)


# Reads the value of one key into what the Config holds; raises _Bad when it does not fit.
_KeyReader = Callable[[Any], object]


class _Bad(Exception):
    def __init__(self, message: str, help: str | None = None) -> None:
        super().__init__(message)
        self.help = help


def _strings(value: Any) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise _Bad("must be a list of strings")
    return tuple(value)


def _string(value: Any) -> str:
    if not isinstance(value, str):
        raise _Bad("must be a string")
    return value


def _boolean(value: Any) -> bool:
    if not isinstance(value, bool):
        raise _Bad("must be true or false")
    return value


def _seconds(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not (value > 0 and math.isfinite(value)):
        raise _Bad("must be a number of seconds greater than 0")
    return float(value)


def _lints(value: Any) -> tuple[str, ...]:
    found: list[str] = []
    for name in _strings(value):
        if name == ALL:
            found.extend(c.code for c in codes.lints())
            continue
        info = codes.lookup(name)
        if info is None or not info.is_lint:
            what = f"`{name}` is an error, not a lint" if info is not None else f"unknown lint `{name}`"
            close = codes.close_matches(name, lints=True)
            raise _Bad(what, f"did you mean `{close[0]}`?" if close and info is None else None)
        found.append(info.code)
    return tuple(found)


# dotted key -> (reader, Config field)
_KEYS: dict[str, tuple[_KeyReader, str]] = {
    "paths": (_strings, "paths"),
    "exclude": (_strings, "exclude"),
    "include": (_strings, "include"),
    "lint.enable": (_lints, "lint_enable"),
    "lint.disable": (_lints, "lint_disable"),
    "lint.deny_warnings": (_boolean, "deny_warnings"),
    "run.platform": (_string, "run_platform"),
    "run.world": (_string, "run_world"),
    "run.timeout": (_seconds, "run_timeout"),
    "run.time_limit": (_seconds, "run_time_limit"),
    "test.paths": (_strings, "test_paths"),
    "test.timeout": (_seconds, "test_timeout"),
    "test.time_limit": (_seconds, "test_time_limit"),
}
_TABLES = {key.partition(".")[0] for key in _KEYS if "." in key}
_PATH_KEYS = {"paths", "include", "test.paths"}


class _Reader:
    def __init__(self, source: Source, prefix: tuple[str, ...]) -> None:
        self.source = source
        self.prefix = prefix
        self.places = _key_places(source)

    def config(self, data: dict[str, Any], path: Path) -> Config:
        root = path.resolve().parent
        values: dict[str, object] = {}
        for key, value in _flatten(data):
            if key not in _KEYS:
                self.unknown(key)
            reader, name = _KEYS[key]
            try:
                read = reader(value)
            except _Bad as e:
                text = str(e)
                message = f"`{self.shown(key)}` {text}" if text.startswith("must") else f"`{self.shown(key)}`: {text}"
                raise ConfigError(self.error(key, message, "this value", help=e.help)) from None
            if key in _PATH_KEYS:
                assert isinstance(read, tuple)
                read = tuple(root / p for p in read)
            elif key == "run.world" and isinstance(read, str) and read.endswith(".toml"):
                read = str(root / read)  # a world file, relative to the configuration's folder
            values[name] = read
        config = Config(file=path.resolve(), table=".".join(self.prefix), root=root)
        for name, value in values.items():
            setattr(config, name, value)
        config.given = {key for key, _ in _flatten(data)}
        return config

    def shown(self, key: str) -> str:
        return ".".join([*self.prefix, key]) if self.prefix else key

    def unknown(self, key: str) -> None:
        head, _, rest = key.partition(".")
        if head in _TABLES and not rest:
            raise ConfigError(self.error(head, f"`{self.shown(head)}` must be a table", "not a table"))
        if rest and head in _TABLES:
            name = rest.partition(".")[0]
            known = [k.partition(".")[2] for k in _KEYS if k.startswith(head + ".")]
            table = f"[{self.shown(head)}]"
            place = f"{head}.{name}"
        else:
            name = place = head
            known = sorted({k.partition(".")[0] for k in _KEYS})
            table = f"[{'.'.join(self.prefix)}]" if self.prefix else CONFIG_NAME
        note = f"the keys of {table}: " + ", ".join(f"`{k}`" for k in known) + " (docs/config.md)"
        message = f"unknown key `{name}` in {table}"
        raise ConfigError(self.error(place, message, "unknown key", help=did_you_mean(name, known), notes=[note]))

    def error(
        self, key: str, message: str, label: str, *, help: str | None = None, notes: Sequence[str] = ()
    ) -> diag.Diagnostic:
        span = self.places.get((*self.prefix, *key.split(".")))
        if span is None:  # a key written in an inline table: point at the table
            span = self.places.get((*self.prefix, key.partition(".")[0])) or Span(self.source, 0, 0)
        return diag.error(diag.Message("", message), span, label, notes=notes, help=help)


def _flatten(data: dict[str, Any], prefix: str = "") -> list[tuple[str, Any]]:
    """(dotted key, value) for each key; the tables gpp knows are entered."""
    out: list[tuple[str, Any]] = []
    for key, value in data.items():
        dotted = f"{prefix}{key}"
        if not prefix and key in _TABLES and isinstance(value, dict):
            out.extend(_flatten(value, dotted + "."))
        else:
            out.append((dotted, value))
    return out


_HEADER = re.compile(r"^\s*\[\s*([^\[\]]+?)\s*\]\s*(?:#.*)?$")
_ASSIGN = re.compile(r"^\s*([A-Za-z0-9_\-.\"' ]+?)\s*=")


def _key_places(source: Source) -> dict[tuple[str, ...], Span]:
    """Where each key and table is written: the dotted path of names -> the span of its name.
    A line-based reading of TOML that is good enough to point at a key."""
    places: dict[tuple[str, ...], Span] = {}
    table: tuple[str, ...] = ()
    for number, line in enumerate(source.text.splitlines()):
        start = source.line_starts[number]
        header = _HEADER.match(line)
        if header:
            table = _split_key(header.group(1))
            at = start + header.start(1)
            places.setdefault(table, Span(source, at, at + len(header.group(1))))
            continue
        assign = _ASSIGN.match(line)
        if assign:
            path = (*table, *_split_key(assign.group(1)))
            at = start + assign.start(1)
            places.setdefault(path, Span(source, at, at + len(assign.group(1))))
    return places


def _split_key(text: str) -> tuple[str, ...]:
    return tuple(part.strip().strip("\"'") for part in text.split("."))


# ---------------------------------------------------------------- files of a project


def gpp_files(paths: Sequence[Path], exclude: Sequence[str] = ()) -> list[Path]:
    """The files to work on: a file as given, a folder's `*.gpp` files recursively (skipping
    hidden folders and what `exclude` matches), in order, each once."""
    found: list[Path] = []
    for p in paths:
        if p.is_dir():
            found.extend(sorted(q for q in p.rglob("*.gpp") if q.is_file() and not _skipped(q, p, exclude)))
        else:
            found.append(p)
    seen: set[Path] = set()
    unique: list[Path] = []
    for f in found:
        key = f.resolve()
        if key not in seen:
            seen.add(key)
            unique.append(f)
    return unique


def _skipped(path: Path, folder: Path, exclude: Sequence[str]) -> bool:
    parts = path.relative_to(folder).parts
    if any(part.startswith(".") for part in parts[:-1]):
        return True
    relative = "/".join(parts)
    return any(
        fnmatch.fnmatch(relative, pattern) or any(fnmatch.fnmatch(part, pattern) for part in parts)
        for pattern in exclude
    )


def _below_cwd(path: Path) -> Path:
    """A path relative to the working directory when it is below it (as the user would write it)."""
    try:
        return path.relative_to(Path.cwd())
    except ValueError:
        return path


def project_files(paths: Sequence[Path], cwd: Path | None = None) -> list[Path]:
    """What `gpp check` and `gpp fmt` work on: the given files and folders, or, given none, the
    `paths` of the configuration found from the working directory (default: that folder).
    Folders are searched for `*.gpp` files, minus the configuration's `exclude` patterns.
    Raises ConfigError for a bad configuration file."""
    if not paths:
        config = config_for(cwd or Path.cwd())
        return [_below_cwd(p) for p in gpp_files(config.paths, config.exclude)]
    found: list[Path] = []
    for p in paths:
        exclude = config_for(p).exclude if p.is_dir() else ()
        found.extend(gpp_files([p], exclude))
    return gpp_files(found)


# ---------------------------------------------------------------- `gpp config`


def describe(config: Config) -> str:
    """The resolved settings as TOML, each marked with where it comes from."""
    origin = "defaults (no gpp.toml or [tool.gpp] found)" if config.file is None else _display(config.file)
    if config.file is not None and config.table:
        origin += f" [{config.table}]"
    lines = [f"# settings from {origin}", f"# paths are relative to {config.root}", ""]

    def value(key: str, shown: str) -> None:
        mark = "from file" if key in config.given else "default"
        lines.append(f"{key.rpartition('.')[2]} = {shown}".ljust(40) + f"  # {mark}")

    def paths(items: Iterable[Path]) -> str:
        return _toml_list(_relative(p, config.root) for p in items)

    value("paths", paths(config.paths))
    value("exclude", _toml_list(config.exclude))
    value("include", paths(config.include))
    lines += ["", "[lint]"]
    enable = _toml_list([ALL]) if config.lint_enable is None else _toml_list(config.lint_enable)
    value("lint.enable", enable)
    value("lint.disable", _toml_list(config.lint_disable))
    value("lint.deny_warnings", "true" if config.deny_warnings else "false")
    lines += ["", "[run]"]
    optional = {
        "run.platform": config.run_platform,
        "run.world": config.run_world,
        "run.timeout": config.run_timeout,
        "run.time_limit": config.run_time_limit,
    }
    for key, setting in optional.items():
        if setting is None:
            lines.append(f"# {key.rpartition('.')[2]} is not set".ljust(40) + "  # default")
        else:
            value(key, _toml_value(setting))
    lines += ["", "[test]"]
    value("test.paths", paths(config.test_paths))
    if config.test_timeout is None:
        lines.append("# timeout is not set".ljust(40) + "  # default: 120 s of wall-clock time per program")
    else:
        value("test.timeout", _toml_value(config.test_timeout))
    if config.test_time_limit is None:
        lines.append("# time_limit is not set".ljust(40) + "  # default: none")
    else:
        value("test.time_limit", _toml_value(config.test_time_limit))
    return "\n".join(lines) + "\n"


def _relative(path: Path, root: Path) -> str:
    try:
        rel = path.relative_to(root).as_posix()
    except ValueError:
        return str(path)
    return rel if rel != "." and rel else "."


def _toml_value(value: object) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def _toml_list(items: Iterable[str]) -> str:
    return "[" + ", ".join(_toml_value(i) for i in items) + "]"
