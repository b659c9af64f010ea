"""`gpp fmt`: format golog++ files in place, check that they are formatted, or show the diff.
Registered on the app by gpp.cli.app; the formatting itself is gpp.syntax.format.

Exit codes as for every command: 0 done (or everything already formatted), 1 files that would
change under --check/--diff, or files with syntax errors (those are left unchanged and their
errors reported on stderr), 2 usage errors (a missing or unreadable file, `-` mixed with files).
"""

from __future__ import annotations

import difflib
import sys
from pathlib import Path
from typing import Annotated

import typer

STDIN = "-"


def register(app: typer.Typer) -> None:
    app.command(name="fmt")(fmt)


def fmt(
    paths: Annotated[
        list[Path] | None,
        typer.Argument(
            metavar="PATH",
            help="The .gpp files to format; a folder means every .gpp file in it; none: the project's paths "
            "(gpp.toml); `-` reads standard input and writes the result to standard output.",
        ),
    ] = None,
    check: Annotated[
        bool, typer.Option("--check", help="Change nothing; list the files that would change and exit 1 if any.")
    ] = False,
    diff: Annotated[
        bool, typer.Option("--diff", help="Change nothing; print a unified diff of the changes and exit 1 if any.")
    ] = False,
) -> None:
    """Format golog++ files in the canonical layout, keeping their comments."""
    from gpp.cli.common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, files_to_check, require_writable, usage_error

    paths = paths or []
    if any(str(p) == STDIN for p in paths):
        if len(paths) > 1:
            usage_error("`-` (standard input) cannot be combined with other paths")
        raise typer.Exit(_format_stdin(check, diff))
    files = files_to_check(paths)
    # Every file is read and formatted, and every file to change is checked to be writable,
    # before any is written: an unreadable or unwritable one stops the command with nothing changed.
    texts = [(path, _read(path)) for path in files]
    changed: list[tuple[Path, str]] = []
    failed = 0
    for path, text in texts:
        formatted = _format(text, str(path))
        if formatted is None:
            failed += 1
        elif formatted != text:
            changed.append((path, formatted))
            if diff:
                sys.stdout.writelines(_diff(text, formatted, str(path)))
            if check:
                print(f"would reformat: {path}")
    unwritten: list[Path] = []
    if not (check or diff):
        require_writable([path for path, _ in changed])
        unwritten = [path for path, formatted in changed if not _write(path, formatted)]
    unchanged = len(files) - len(changed) - failed
    if check or diff:
        summary = [f"{_count(len(changed), 'file')} would be reformatted", f"{unchanged} already formatted"]
    else:
        summary = [f"{_count(len(changed) - len(unwritten), 'file')} reformatted", f"{unchanged} left unchanged"]
    if failed:
        summary.append(f"{_count(failed, 'file')} with syntax errors left unchanged")
    if unwritten:
        summary.append(f"{_count(len(unwritten), 'file')} could not be written (left as they were)")
    print(", ".join(summary), file=sys.stderr if diff else sys.stdout)
    if unwritten:
        raise typer.Exit(EXIT_USAGE)
    raise typer.Exit(EXIT_PROBLEMS if failed or ((check or diff) and changed) else EXIT_OK)


def _format_stdin(check: bool, diff: bool) -> int:
    from gpp.cli.common import EXIT_OK, EXIT_PROBLEMS

    text = _read_stdin()
    formatted = _format(text, "<stdin>")
    if formatted is None:
        return EXIT_PROBLEMS
    if diff:
        sys.stdout.writelines(_diff(text, formatted, STDIN))
    if check and formatted != text:
        print(f"would reformat: {STDIN}")
    if not (check or diff):
        sys.stdout.write(formatted)
    return EXIT_PROBLEMS if (check or diff) and formatted != text else EXIT_OK


def _read_stdin() -> str:
    """Standard input as it is, line endings included (text mode would turn `\r\n` into `\n`)."""
    from gpp.cli.common import usage_error

    raw = sys.stdin.buffer.read() if hasattr(sys.stdin, "buffer") else sys.stdin.read().encode("utf-8")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        usage_error("cannot read standard input: it is not UTF-8 text")


def _format(text: str, path: str) -> str | None:
    """The formatted text, or None after reporting the syntax errors on stderr."""
    from gpp.report.text import render_text
    from gpp.syntax.format import FormatError, format_text

    try:
        return format_text(text, path)
    except FormatError as e:
        sys.stderr.write(render_text(e.diagnostics, summary=False))
        return None


def _read(path: Path) -> str:
    from gpp.cli.common import require_readable, usage_error

    require_readable(path)
    try:
        return path.read_bytes().decode("utf-8")
    except OSError as e:
        usage_error(f"cannot read '{path}': {e.strerror or e}")
    except UnicodeDecodeError:
        usage_error(f"cannot read '{path}': it is not UTF-8 text")


def _write(path: Path, text: str) -> bool:
    """Replace the file's text atomically (a full disk leaves it as it was); False, after saying
    why on stderr, when it could not be written."""
    from gpp.base.paths import write_atomically

    try:
        write_atomically(path, text)
    except OSError as e:
        print(f"error: cannot write '{path}': {e.strerror or e}", file=sys.stderr)
        return False
    return True


def _diff(before: str, after: str, name: str) -> list[str]:
    lines = difflib.unified_diff(
        before.splitlines(keepends=True), after.splitlines(keepends=True), f"{name} (before)", f"{name} (formatted)"
    )
    return [line if line.endswith("\n") else line + "\n\\ No newline at end of file\n" for line in lines]


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"
