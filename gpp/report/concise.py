"""The one-line output formats of `gpp check`: `concise` (a line per diagnostic and a summary,
as ruff's concise output) and `github` (workflow commands that GitHub Actions shows as
annotations on the changed lines).

    agent.gpp:26:10: error[E0101] unknown name `kitchn` [*]
    agent.gpp:29:28: error[E0204] cannot add `string` and `number`
    Found 2 errors.
    [*] 1 fixable with `gpp check --fix`.

`[*]` marks a diagnostic whose fix `gpp check --fix` applies (a safe fix). Lines and columns
are 1-based and count characters; a GitHub annotation's end column is exclusive.
"""

from __future__ import annotations

from collections.abc import Sequence

from gpp.base.diagnostics import Diagnostic, Severity
from gpp.base.source import Span


def span_range(span: Span) -> tuple[int, int, int, int]:
    """Line and column of the start, and of the (exclusive) end, of a span clamped to its source."""
    n = len(span.source.text)
    start = max(0, min(span.start, n))
    end = max(start, min(span.end, n))
    return (*span.source.line_col(start), *span.source.line_col(end))


def _one_line(text: str) -> str:
    return " ".join(part.strip() for part in text.splitlines() if part.strip())


def concise_line(d: Diagnostic) -> str:
    """`file:line:col: severity[code] message`, with ` [*]` when `--fix` would fix it."""
    line, col, _, _ = span_range(d.span)
    code = f"[{d.code}]" if d.code else ""
    fixable = " [*]" if d.fix is not None and d.fix.is_safe else ""
    return f"{d.span.source.path}:{line}:{col}: {d.severity.value}{code} {_one_line(d.message)}{fixable}"


def concise_summary(diagnostics: Sequence[Diagnostic]) -> list[str]:
    """`Found 2 errors and 1 warning.` and how many are fixable, or `All checks passed!`."""
    errors = sum(1 for d in diagnostics if d.severity is Severity.ERROR)
    warnings = sum(1 for d in diagnostics if d.severity is Severity.WARNING)
    if not errors and not warnings:
        return ["All checks passed!"]
    counts = [_plural(n, word) for n, word in ((errors, "error"), (warnings, "warning")) if n]
    lines = [f"Found {' and '.join(counts)}."]
    fixable = sum(1 for d in diagnostics if d.fix is not None and d.fix.is_safe)
    if fixable:
        lines.append(f"[*] {fixable} fixable with `gpp check --fix`.")
    return lines


def render_concise(diagnostics: Sequence[Diagnostic]) -> str:
    return "".join(f"{line}\n" for line in [*map(concise_line, diagnostics), *concise_summary(diagnostics)])


_COMMANDS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.NOTE: "notice"}


def _escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(text: str) -> str:
    return _escape_data(text).replace(":", "%3A").replace(",", "%2C")


def github_line(d: Diagnostic) -> str:
    """`::error file=F,line=L,col=C,endLine=L2,endColumn=C2,title=gpp (CODE)::message`."""
    line, col, end_line, end_col = span_range(d.span)
    title = f"gpp ({d.code})" if d.code else "gpp"
    properties = {
        "file": d.span.source.path,
        "line": str(line),
        "col": str(col),
        "endLine": str(end_line),
        "endColumn": str(end_col),
        "title": title,
    }
    message = d.message + (f"\nhelp: {d.help}" if d.help else "")
    props = ",".join(f"{key}={_escape_property(value)}" for key, value in properties.items())
    return f"::{_COMMANDS[d.severity]} {props}::{_escape_data(message)}"


def render_github(diagnostics: Sequence[Diagnostic]) -> str:
    return "".join(github_line(d) + "\n" for d in diagnostics)


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"
