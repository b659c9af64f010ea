"""Did-you-mean suggestions for misspelled names, shared by every layer that reports one."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def _same_but_case(name: str, pool: list[str]) -> str | None:
    lowered = {k.lower(): k for k in pool}
    return lowered.get(name.lower())


def closest(name: str, known: Iterable[str], cutoff: float = 0.5) -> str | None:
    """The known name most like `name`, if one is close enough (case is ignored first)."""
    pool = sorted(set(known) - {name})
    hint = _same_but_case(name, pool)
    if hint is not None:
        return hint
    matches = difflib.get_close_matches(name, pool, n=1, cutoff=cutoff)
    return matches[0] if matches else None


def did_you_mean(name: str, known: Iterable[str]) -> str | None:
    """`did you mean `world`?` for a misspelled name, or None when nothing is close."""
    hint = closest(name, known)
    return f"did you mean `{hint}`?" if hint is not None else None


def suggest(name: str, candidates: Iterable[str]) -> str | None:
    """`did you mean ...?` naming up to three close names (the checker's suggestions), or None."""
    pool = sorted(set(candidates) - {name})
    hint = _same_but_case(name, pool)
    if hint is not None:
        return f"did you mean `{hint}`?"
    close = difflib.get_close_matches(name, pool, n=3, cutoff=0.6)
    if not close:
        return None
    if len(close) == 1:
        return f"did you mean `{close[0]}`?"
    return "did you mean " + ", ".join(f"`{c}`" for c in close[:-1]) + f" or `{close[-1]}`?"
