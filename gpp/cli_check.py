"""The work of `gpp check` (the options are declared in gpp.cli): the project's files and
settings, checking, `--fix` and `--diff`. Also the shared handling of a bad configuration file."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

import typer

if TYPE_CHECKING:
    from gpp.check import CheckResult
    from gpp.check.fixes import Checker
    from gpp.cli import ColorMode, OutputFormat
    from gpp.config import Config, ConfigError
    from gpp.diagnostics import Diagnostic


def config_error(e: ConfigError) -> NoReturn:
    """A bad configuration file: its diagnostic on stderr, exit status 2."""
    from gpp.cli import EXIT_USAGE
    from gpp.render import render_text

    sys.stderr.write(render_text([e.diagnostic], summary=False))
    raise typer.Exit(EXIT_USAGE)


def load_config(start: Path) -> Config:
    """The settings for a file or folder (a bad configuration file ends the command)."""
    from gpp.config import ConfigError, config_for

    try:
        return config_for(start)
    except ConfigError as e:
        config_error(e)


def run_check(
    files: Sequence[Path],
    output_format: OutputFormat,
    color: ColorMode,
    *,
    lint: bool,
    allowed: Sequence[str],
    deny_warnings: bool,
    fix: bool,
    diff: bool,
) -> NoReturn:
    from gpp.check import check_loaded, merged_diagnostics
    from gpp.cli import EXIT_OK, EXIT_PROBLEMS, OutputFormat, _emit_diagnostics, _require_readable, _usage_error
    from gpp.config import ConfigError, project_files
    from gpp.syntax.loader import load

    if diff and output_format is not OutputFormat.TEXT:
        _usage_error(f"--diff writes a unified diff; --format {output_format.value} does not apply to it")
    for given in files:
        if not given.exists():
            _usage_error(f"cannot read '{given}': No such file or directory")
    try:
        paths = project_files(files)
    except ConfigError as e:
        config_error(e)
    if not paths:
        where = ", ".join(f"'{p}'" for p in files) if files else "the project (the working directory)"
        _usage_error(f"no .gpp files found in {where}; give .gpp files or folders, or --list-lints")
    for path in paths:
        _require_readable(path)
    configs = {path: load_config(path) for path in paths}

    plan = _plan(paths, configs)

    def checker(path: Path, overrides: dict[Path, str]) -> CheckResult:
        config = configs.get(path) or load_config(path)
        allow = [*allowed, *config.disabled_lints()]
        roots = [path, *plan.libraries.get(path, ())]
        return check_loaded(load(roots, overrides, config.include), lint, allow)

    fixed = ""
    try:
        if fix or diff:
            results, fixed = _fix(plan.programs, checker, write=not diff)
        else:
            results = [checker(p, {}) for p in plan.programs]
    except OSError as e:  # a file that vanished after the check above
        _usage_error(f"cannot read '{e.filename or paths[0]}': {e.strerror or e}")
    results = plan.agreed(results)
    diagnostics = merged_diagnostics(results)
    _emit_diagnostics(diagnostics, output_format, color)
    if fixed:
        to_stdout = output_format in (OutputFormat.TEXT, OutputFormat.CONCISE)
        print(fixed, file=sys.stdout if to_stdout else sys.stderr, flush=True)
    strict = deny_warnings or any(c.deny_warnings for c in configs.values())
    failed = any(d.is_error or strict for d in diagnostics)
    raise typer.Exit(EXIT_PROBLEMS if failed else EXIT_OK)


# Lints about what a program uses of a library: each program sees its own part of the library.
_USE_LINTS = frozenset({"W0101", "W0116"})


@dataclass
class _Plan:
    """How the files of a project are checked. A file that another file of the set includes (a
    library) is checked as a root together with each program that includes it, so that it is
    linted and what the program uses of it counts as used; its `unused` warnings stand only
    when every program that includes it agrees."""

    programs: list[Path]
    libraries: dict[Path, list[Path]] = field(default_factory=dict)  # program -> its libraries
    users: dict[Path, int] = field(default_factory=dict)  # resolved library -> programs including it

    def agreed(self, results: list[CheckResult]) -> list[CheckResult]:
        """The results without a library's `unused` warnings that not every user reports."""
        from collections import Counter

        if not self.users:
            return results

        def key(d: Diagnostic) -> tuple[str, int, str]:
            return (d.span.source.path, d.span.start, d.message)

        def library(r: CheckResult, d: Diagnostic) -> Path | None:
            f = next((f for f in r.loaded.files if f.source is d.span.source), None)
            return f.path if f is not None and f.path in self.users else None

        counts = Counter(key(d) for r in results for d in r.diagnostics if d.code in _USE_LINTS and library(r, d))
        for r in results:
            r.diagnostics = [
                d
                for d in r.diagnostics
                if d.code not in _USE_LINTS or (lib := library(r, d)) is None or counts[key(d)] == self.users[lib]
            ]
        return results


def _plan(paths: Sequence[Path], configs: dict[Path, Config]) -> _Plan:
    from gpp.syntax.loader import load

    if len(paths) < 2:
        return _Plan(list(paths))
    reaches: dict[Path, set[Path]] = {}
    for path in paths:
        try:
            loaded = load([path], include_dirs=configs[path].include)
        except OSError:
            continue
        reaches[path] = {f.path for f in loaded.files} - {path.resolve()}
    included = set().union(*reaches.values())
    plan = _Plan([p for p in paths if p.resolve() not in included])
    if not plan.programs:  # files that include each other (an include cycle): each on its own
        return _Plan(list(paths))
    for program in plan.programs:
        libraries = [q for q in paths if q.resolve() in reaches.get(program, set())]
        plan.libraries[program] = libraries
        for q in libraries:
            plan.users[q.resolve()] = plan.users.get(q.resolve(), 0) + 1
    return plan


def _fix(paths: Sequence[Path], checker: Checker, *, write: bool) -> tuple[list[CheckResult], str]:
    """Fix in memory; write the files (`write`) or print the diff and exit (1 when it is not
    empty). The final check, and the line that says what was fixed."""
    from gpp.check import merged_diagnostics
    from gpp.check.fixes import fix_programs, unified_diff, write_atomically
    from gpp.cli import EXIT_OK, EXIT_PROBLEMS

    outcome = fix_programs(paths, checker)
    changed = outcome.changed()
    files = f"{len(changed)} file" + ("" if len(changed) == 1 else "s")
    if not write:
        sys.stdout.write(unified_diff(outcome))
        sys.stdout.flush()
        print(f"would fix {_problems(outcome.applied)} in {files}", file=sys.stderr)
        raise typer.Exit(EXIT_PROBLEMS if changed else EXIT_OK)
    for path in changed:
        write_atomically(path, outcome.fixed[path])
    remaining = len(merged_diagnostics(outcome.results))
    if not outcome.applied:
        return outcome.results, f"nothing to fix, {_problems(remaining)} remaining"
    return outcome.results, f"fixed {_problems(outcome.applied)} in {files}, {remaining} remaining"


def _problems(n: int) -> str:
    return f"{n} problem" + ("" if n == 1 else "s")
