"""`gpp check`: parse and type-check programs and report every problem; also the project's
files and settings, `--fix` and `--diff`.

Editors and CI start this command on every save, so it stays cheap to start: nothing is
imported that a check does not use (no rich unless colour is asked for, no interpreter,
planner or platform: only the platforms' static checks, gpp.platform.static, which import
more only for a program they have something to check in); tests/cli/test_cli.py checks the
modules a check imports.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from gpp.cli.common import (
    EXIT_OK,
    EXIT_PROBLEMS,
    ColorMode,
    OutputFormat,
    did_you_mean,
    emit_diagnostics,
    files_to_check,
    load_config,
    require_readable,
    require_writable,
    usage_error,
)

if TYPE_CHECKING:
    from gpp.base.diagnostics import Diagnostic
    from gpp.check import CheckResult
    from gpp.check.fixes import Checker, FixOutcome
    from gpp.project.config import Config


def register(app: typer.Typer) -> None:
    app.command(name="check")(check)


def check(
    files: Annotated[
        list[Path] | None,
        typer.Argument(
            metavar="PATH",
            help="The .gpp files or folders (searched for *.gpp) to check, with their includes "
            "(default: the project's `paths`, else the working directory).",
            show_default=False,
        ),
    ] = None,
    output_format: Annotated[
        OutputFormat,
        typer.Option(
            "--format",
            help="Write diagnostics as text, a line each (concise), GitHub annotations, one JSON document, "
            "or SARIF 2.1.0.",
        ),
    ] = OutputFormat.TEXT,
    color: Annotated[
        ColorMode, typer.Option("--color", help="Colour the text output: auto (when a terminal), always, never.")
    ] = ColorMode.AUTO,
    no_lint: Annotated[bool, typer.Option("--no-lint", help="Report errors only, no lint warnings.")] = False,
    allow: Annotated[
        list[str] | None,
        typer.Option(
            "--allow",
            metavar="LINT",
            help="Do not report this lint (a code such as W0101, or its name); repeatable.",
            show_default=False,
        ),
    ] = None,
    deny_warnings: Annotated[
        bool, typer.Option("--deny-warnings", help="Exit with status 1 when there are warnings, too.")
    ] = False,
    list_lints: Annotated[bool, typer.Option("--list-lints", help="List the lints and exit.")] = False,
    max_diagnostics: Annotated[
        int | None,
        typer.Option(
            "--max-diagnostics",
            metavar="N",
            help="Text output: show at most N diagnostics of one code in one file and count the rest in one "
            "line (default 50); 0 shows all.",
            show_default=False,
        ),
    ] = None,
    fix: Annotated[
        bool, typer.Option("--fix", help="Apply every safe fix to the files, then report what remains.")
    ] = False,
    diff: Annotated[
        bool,
        typer.Option("--diff", help="Show the safe fixes as a unified diff without writing (exit 1 if any)."),
    ] = False,
) -> None:
    """Parse PATHs and everything they include, and report the problems found.

    Settings come from the nearest gpp.toml, or the `[tool.gpp]` table of pyproject.toml (see
    `gpp config`).

    Exit code 0 when there are no errors (and no warnings with --deny-warnings), 1 otherwise,
    2 for a usage error."""
    if list_lints:
        _print_lints()
        raise typer.Exit(EXIT_OK)
    if max_diagnostics is not None and max_diagnostics < 0:
        usage_error(f"--max-diagnostics takes a whole number of 0 or more, not {max_diagnostics}")
    allowed = [_lint_code(a) for a in allow or []]
    raise typer.Exit(
        run_check(
            files or [],
            output_format,
            color,
            lint=not no_lint,
            allowed=allowed,
            deny_warnings=deny_warnings,
            fix=fix,
            diff=diff,
            max_diagnostics=max_diagnostics,
        )
    )


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
    max_diagnostics: int | None = None,
) -> int:
    """Check the files (or the project), fixing first with `fix`/`diff`; the exit code."""
    from gpp.check import check_loaded, merged_diagnostics
    from gpp.syntax.loader import load

    if max_diagnostics is not None and output_format is not OutputFormat.TEXT:
        usage_error(f"--max-diagnostics applies to the text output only ({output_format.value} holds every diagnostic)")
    if diff and output_format is not OutputFormat.TEXT:
        usage_error(f"--diff writes a unified diff; --format {output_format.value} does not apply to it")
    paths = files_to_check(files, "; give .gpp files or folders, or --list-lints")
    for path in paths:
        require_readable(path)
    configs = {path: load_config(path) for path in paths}

    plan = _plan(paths, configs)

    def checker(path: Path, overrides: dict[Path, str]) -> CheckResult:
        config = configs.get(path) or load_config(path)
        allow = [*allowed, *config.disabled_lints()]
        roots = [path, *plan.libraries.get(path, ())]
        result = check_loaded(load(roots, overrides, config.include), lint, allow)
        if not result.errors:
            # What a platform would refuse of the mappings, where that needs no robot.
            from gpp.platform.static import static_diagnostics

            result.diagnostics.extend(static_diagnostics(result.model))
        return result

    fixed = ""
    try:
        if fix or diff:
            results, fixed = _fix(plan.programs, checker, write=not diff)
        else:
            results = [checker(p, {}) for p in plan.programs]
    except OSError as e:  # a file that vanished after the check above
        usage_error(f"cannot read '{e.filename or paths[0]}': {e.strerror or e}")
    results = plan.agreed(results)
    diagnostics = merged_diagnostics(results)
    emit_diagnostics(diagnostics, output_format, color, max_per_code=max_diagnostics)
    if fixed:
        to_stdout = output_format in (OutputFormat.TEXT, OutputFormat.CONCISE)
        print(fixed, file=sys.stdout if to_stdout else sys.stderr, flush=True)
    strict = deny_warnings or any(c.deny_warnings for c in configs.values())
    failed = any(d.is_error or strict for d in diagnostics)
    return EXIT_PROBLEMS if failed else EXIT_OK


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

        from gpp.codes import W0101, W0116

        if not self.users:
            return results
        # Lints about what a program uses of a library: each program sees its own part of the library.
        use_lints = {W0101.code, W0116.code}

        def key(d: Diagnostic) -> tuple[str, int, str]:
            return (d.span.source.path, d.span.start, d.message)

        def library(r: CheckResult, d: Diagnostic) -> Path | None:
            f = next((f for f in r.loaded.files if f.source is d.span.source), None)
            return f.path if f is not None and f.path in self.users else None

        counts = Counter(key(d) for r in results for d in r.diagnostics if d.code in use_lints and library(r, d))
        for r in results:
            r.diagnostics = [
                d
                for d in r.diagnostics
                if d.code not in use_lints or (lib := library(r, d)) is None or counts[key(d)] == self.users[lib]
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
    from gpp.base.paths import write_atomically
    from gpp.check import merged_diagnostics
    from gpp.check.fixes import fix_programs, unified_diff
    from gpp.syntax.loader import display_path

    outcome = fix_programs(paths, checker)
    changed = outcome.changed()
    files = f"{len(changed)} file" + ("" if len(changed) == 1 else "s")
    fixed = _problems(outcome.fixed_problems) + _found_later(outcome)
    if not write:
        sys.stdout.write(unified_diff(outcome))
        sys.stdout.flush()
        print(f"would fix {fixed} in {files}", file=sys.stderr)
        raise SystemExit(EXIT_PROBLEMS if changed else EXIT_OK)
    require_writable([Path(display_path(path)) for path in changed])
    for path in changed:
        try:
            write_atomically(path, outcome.fixed[path])
        except OSError as e:  # a full disk: this file stays as it was, the others are fixed
            usage_error(f"cannot write '{display_path(path)}': {e.strerror or e} (it was left as it was)")
    remaining = len(merged_diagnostics(outcome.results))
    if not outcome.applied:
        return outcome.results, f"nothing to fix, {_problems(remaining)} remaining"
    return outcome.results, f"fixed {fixed} in {files}, {remaining} remaining"


def _problems(n: int) -> str:
    return f"{n} problem" + ("" if n == 1 else "s")


def _found_later(outcome: FixOutcome) -> str:
    """What the count holds that the check did not show: ` (1 of them hidden by a syntax
    error)`, or nothing."""
    n = outcome.found_later
    if not n:
        return ""
    them = "" if n == outcome.fixed_problems == 1 else f"{n} of them "
    why = "hidden by a syntax error" if outcome.hidden_by_syntax_errors else "found after the first fixes"
    return f" ({them}{why})"


def _lint_code(code_or_name: str) -> str:
    """The code of a lint given by code or name, or a usage error."""
    from gpp import codes

    info = codes.lookup(code_or_name)
    if info is None:
        usage_error(f"unknown lint `{code_or_name}`" + did_you_mean(codes.close_matches(code_or_name, lints=True)))
    if not info.is_lint:
        usage_error(f"`{info.code}` is an error, not a lint: only lints can be allowed")
    return info.code


def _print_lints() -> None:
    from gpp import codes

    rows = [(c.code, c.name, c.summary) for c in codes.lints()]
    width = max(len(name) for _, name, _ in rows)
    print(f"{'code':<7}{'name':<{width + 2}}summary")
    for code, name, summary in rows:
        print(f"{code:<7}{name:<{width + 2}}{summary}")
