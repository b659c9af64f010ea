"""Directives: `// key: value` comment lines at the top of a program (before its first line of
code) that tell the tools how to run it, e.g. `// world: rescue` (the sim's world) or
`// scenario: blocks.toml` (the dummy's scenario). A directive's value is one word; a comment
with more words after the colon is an ordinary comment. The first occurrence of a key counts.

Suppressions, `// gpp: allow CODES` and `// gpp: allow-file CODES`, are comments the checker
reads too (gpp.check.suppress); `SUPPRESSION` matches their start, and the formatter keeps them
on the lines they cover.
"""

from __future__ import annotations

import re
from pathlib import Path

from gpp.base.source import BOM

# The start of a suppression comment; group 1 is `allow` or `allow-file`.
SUPPRESSION = re.compile(r"//[ \t]*gpp:[ \t]*(allow-file|allow)(?![\w-])")

_DIRECTIVE = re.compile(r"^\s*//\s*([a-z][a-z0-9_-]*)\s*:\s*(\S+)\s*$")
# Directives are read from the comment lines at the top; this many lines at most.
_HEAD_LINES = 40


def directives(text: str) -> dict[str, str]:
    """The directives at the top of a program's text (after its byte-order mark, if any)."""
    found: dict[str, str] = {}
    for line in text.removeprefix(BOM).splitlines()[:_HEAD_LINES]:
        stripped = line.strip()
        if stripped and not stripped.startswith("//"):
            break
        m = _DIRECTIVE.match(line)
        if m:
            found.setdefault(m.group(1), m.group(2))
    return found


def file_directives(path: Path) -> dict[str, str]:
    """The directives at the top of a program file (none when it cannot be read)."""
    try:
        return directives(path.read_text(encoding="utf-8", errors="replace"))
    except OSError:
        return {}
