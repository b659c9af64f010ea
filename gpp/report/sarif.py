"""SARIF 2.1.0 output (`gpp check --format sarif`), the format GitHub code scanning reads.

One run of the tool `gpp`: a rule per diagnostic code that occurs (its name, summary and
`gpp explain` text) and a result per diagnostic, located by a path relative to the working
directory (`uriBaseId` `%SRCROOT%`) and a 1-based line/column region whose end column is
exclusive; secondary labels become related locations, fixes become SARIF fixes. Columns count
characters (`columnKind` `unicodeCodePoints`), as everywhere in gpp.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path, PurePath
from typing import Any
from urllib.parse import quote

from gpp import __version__
from gpp.base.diagnostics import Diagnostic, Severity
from gpp.base.source import Span
from gpp.codes import CODES

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
SARIF_VERSION = "2.1.0"
SOURCE_ROOT = "%SRCROOT%"
# gpp has no web page of its own yet: point at the golog++ language it implements.

_LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.NOTE: "note"}

Json = dict[str, Any]


def to_sarif(diagnostics: Sequence[Diagnostic], root: Path | None = None) -> Json:
    """The SARIF log of `diagnostics`; relative paths are relative to `root` (default: the
    working directory, which is what diagnostics' paths are relative to)."""
    codes = sorted({d.code for d in diagnostics if d.code})
    index = {code: i for i, code in enumerate(codes)}
    base = (root or Path.cwd()).resolve()
    return {
        "$schema": SARIF_SCHEMA,
        "version": SARIF_VERSION,
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "gpp",
                        "version": __version__,
                        "semanticVersion": __version__,
                        "rules": [_rule(code) for code in codes],
                    }
                },
                "originalUriBaseIds": {SOURCE_ROOT: {"uri": base.as_uri() + "/"}},
                "columnKind": "unicodeCodePoints",
                "results": [_result(d, index) for d in diagnostics],
            }
        ],
    }


def render_sarif(diagnostics: Sequence[Diagnostic], root: Path | None = None) -> str:
    """The SARIF log as JSON text, ending with a newline."""
    return json.dumps(to_sarif(diagnostics, root), indent=2, ensure_ascii=False) + "\n"


def _rule(code: str) -> Json:
    info = CODES.get(code)
    if info is None:
        return {"id": code, "shortDescription": {"text": code}}
    level = "warning" if info.is_lint else "error"
    explanation = info.explanation or info.summary
    first_paragraph = explanation.split("\n\n", 1)[0].replace("\n", " ")
    return {
        "id": code,
        "name": info.name,
        "shortDescription": {"text": _sentence(info.summary)},
        "fullDescription": {"text": first_paragraph},
        # The explanation is plain text whose examples are indented by 4 spaces: that is
        # already Markdown (indented code blocks).
        "help": {"text": explanation, "markdown": explanation},
        "defaultConfiguration": {"level": level},
        "properties": {"tags": ["lint" if info.is_lint else "error"]},
    }


def _sentence(text: str) -> str:
    return text[:1].upper() + text[1:] + ("" if text.endswith(".") else ".")


def _result(d: Diagnostic, index: dict[str, int]) -> Json:
    lines = [d.message]
    lines += [f"note: {n}" for n in d.notes]
    if d.help:
        lines.append(f"help: {d.help}")
    result: Json = {}
    if d.code:
        result["ruleId"] = d.code
        result["ruleIndex"] = index[d.code]
    result["level"] = _LEVELS[d.severity]
    result["message"] = {"text": "\n".join(lines)}
    result["locations"] = [{"physicalLocation": _physical_location(d.span)}]
    if d.secondary:
        result["relatedLocations"] = [
            {"id": i, "physicalLocation": _physical_location(label.span), "message": {"text": label.message or "here"}}
            for i, label in enumerate(d.secondary, start=1)
        ]
    if d.fix is not None and d.fix.edits:
        changes: dict[str, Json] = {}
        for edit in d.fix.edits:
            location = _artifact_location(edit.span.source.path)
            change = changes.setdefault(edit.span.source.path, {"artifactLocation": location, "replacements": []})
            change["replacements"].append({"deletedRegion": _region(edit.span), "insertedContent": {"text": edit.text}})
        result["fixes"] = [
            {
                "description": {"text": d.fix.message or "apply the fix"},
                "artifactChanges": list(changes.values()),
                "properties": {"applicability": d.fix.applicability.value},
            }
        ]
    return result


def _physical_location(span: Span) -> Json:
    return {"artifactLocation": _artifact_location(span.source.path), "region": _region(span)}


def _artifact_location(path: str) -> Json:
    """A path as diagnostics show it (relative to the working directory when below it) as a
    SARIF artifact location."""
    p = PurePath(path)
    if p.is_absolute():
        return {"uri": Path(path).as_uri()}
    return {"uri": quote(p.as_posix()), "uriBaseId": SOURCE_ROOT}


def _region(span: Span) -> Json:
    """1-based start line and column, and the line and (exclusive) column of the end."""
    n = len(span.source.text)
    start = max(0, min(span.start, n))
    end = max(start, min(span.end, n))
    line, column = span.source.line_col(start)
    end_line, end_column = span.source.line_col(end)
    return {"startLine": line, "startColumn": column, "endLine": end_line, "endColumn": end_column}
