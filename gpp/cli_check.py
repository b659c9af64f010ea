"""`gpp check`: parse and type-check programs and report every problem.

This command is started by editors and CI on every save, so it is kept cheap to start: its
options are parsed with argparse and nothing is imported that a check does not use (no typer,
no rich unless colour is asked for, no interpreter, planner or platform). gpp.cli hands it the
arguments after `check`; tests/test_cli.py checks the modules a check imports.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

from gpp.cli import (
    EXIT_OK,
    EXIT_PROBLEMS,
    ColorMode,
    OutputFormat,
    _did_you_mean,
    _emit_diagnostics,
    _require_readable,
    _usage_error,
)

DESCRIPTION = "Parse FILES and everything they include, and report the problems found."


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]  # argparse's is NoReturn too
        self.print_usage()
        _usage_error(message)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="gpp check", description=DESCRIPTION)
    parser.add_argument(
        "files", nargs="*", type=Path, metavar="FILE", help="the .gpp files to check (their includes are checked too)"
    )
    parser.add_argument(
        "--format",
        dest="output_format",
        choices=[f.value for f in OutputFormat],
        default=OutputFormat.TEXT.value,
        help="write diagnostics as text, one JSON document, or SARIF 2.1.0",
    )
    parser.add_argument(
        "--color",
        choices=[c.value for c in ColorMode],
        default=ColorMode.AUTO.value,
        help="colour the text output: auto (when a terminal), always, never",
    )
    parser.add_argument("--no-lint", action="store_true", help="report errors only, no lint warnings")
    parser.add_argument(
        "--allow",
        action="append",
        metavar="LINT",
        default=[],
        help="do not report this lint (a code such as W0101, or its name); repeatable",
    )
    parser.add_argument("--deny-warnings", action="store_true", help="exit with status 1 when there are warnings, too")
    parser.add_argument("--list-lints", action="store_true", help="list the lints and exit")
    return parser


def check(argv: Sequence[str]) -> int:
    """Run `gpp check` with the arguments after `check`; the exit code."""
    options = _parser().parse_args(list(argv))
    if options.list_lints:
        _print_lints()
        return EXIT_OK
    files: list[Path] = options.files
    if not files:
        _usage_error("no files to check (give one or more .gpp files, or --list-lints)")
    allowed = [_lint_code(a) for a in options.allow]
    for path in files:
        _require_readable(path)
    from gpp.check import check_paths, merged_diagnostics

    try:
        results = check_paths(files, lint=not options.no_lint, allow=allowed)
    except OSError as e:  # a root file that vanished after the check above
        _usage_error(f"cannot read '{e.filename or files[0]}': {e.strerror or e}")
    diagnostics = merged_diagnostics(results)
    _emit_diagnostics(diagnostics, OutputFormat(options.output_format), ColorMode(options.color))
    failed = any(d.is_error or options.deny_warnings for d in diagnostics)
    return EXIT_PROBLEMS if failed else EXIT_OK


def _lint_code(code_or_name: str) -> str:
    """The code of a lint given by code or name, or a usage error."""
    from gpp import codes

    info = codes.lookup(code_or_name)
    if info is None:
        _usage_error(f"unknown lint `{code_or_name}`" + _did_you_mean(codes.close_matches(code_or_name, lints=True)))
    if not info.is_lint:
        _usage_error(f"`{info.code}` is an error, not a lint: only lints can be allowed")
    return info.code


def _print_lints() -> None:
    from gpp import codes

    rows = [(c.code, c.name, c.summary) for c in codes.lints()]
    width = max(len(name) for _, name, _ in rows)
    print(f"{'code':<7}{'name':<{width + 2}}summary")
    for code, name, summary in rows:
        print(f"{code:<7}{name:<{width + 2}}{summary}")
