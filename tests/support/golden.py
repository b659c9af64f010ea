"""Golden files: text recorded from a known-good version, which a test compares with what the
code gives now. `GPP_UPDATE_GOLDEN=1` rewrites them instead (after an intended change: review
the diff of the files before committing it)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

UPDATE = os.environ.get("GPP_UPDATE_GOLDEN") == "1"


def recorded(path: Path, text: str) -> str:
    """The text recorded in `path` to compare `text` with (first written there when updating)."""
    if UPDATE:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    if not path.exists():
        pytest.fail(f"no golden file {path}; create it with GPP_UPDATE_GOLDEN=1")
    return path.read_text(encoding="utf-8")
