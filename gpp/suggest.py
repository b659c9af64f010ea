"""Did-you-mean suggestions for misspelled names, shared by every layer that reports one."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def closest(name: str, known: Iterable[str], cutoff: float = 0.5) -> str | None:
    """The known name most like `name`, if one is close enough (case is ignored first)."""
    pool = sorted(set(known) - {name})
    lowered = {k.lower(): k for k in pool}
    if name.lower() in lowered:
        return lowered[name.lower()]
    matches = difflib.get_close_matches(name, pool, n=1, cutoff=cutoff)
    return matches[0] if matches else None


def did_you_mean(name: str, known: Iterable[str]) -> str | None:
    """`did you mean `world`?` for a misspelled name, or None when nothing is close."""
    hint = closest(name, known)
    return f"did you mean `{hint}`?" if hint is not None else None
