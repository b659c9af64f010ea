"""Did-you-mean suggestions for misspelled names, shared by every layer that reports one."""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass

from gpp.base.diagnostics import Applicability, Edit, Fix
from gpp.base.source import Span


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


@dataclass(frozen=True, slots=True)
class Suggestion:
    """Up to three close names for a misspelled one, best first."""

    names: tuple[str, ...]

    @property
    def help(self) -> str:
        shown = [f"`{n}`" for n in self.names]
        if len(shown) == 1:
            return f"did you mean {shown[0]}?"
        return "did you mean " + ", ".join(shown[:-1]) + f" or {shown[-1]}?"

    def fix(self, span: Span) -> Fix:
        """Replace the misspelled name at `span` by the best candidate: safe when it is the only
        one. The fix's message is the help line (the text output shows it once, as the help)."""
        applicability = Applicability.SAFE if len(self.names) == 1 else Applicability.UNSAFE
        return Fix(self.help, (Edit(span, self.names[0]),), applicability)


def suggestion(name: str, candidates: Iterable[str]) -> Suggestion | None:
    """The checker's suggestions for a misspelled name: the same name but for case, else up to
    three close names; None when nothing is close."""
    pool = sorted(set(candidates) - {name})
    hint = _same_but_case(name, pool)
    if hint is not None:
        return Suggestion((hint,))
    close = difflib.get_close_matches(name, pool, n=3, cutoff=0.6)
    return Suggestion(tuple(close)) if close else None


def suggest(name: str, candidates: Iterable[str]) -> str | None:
    """`did you mean ...?` naming up to three close names (the checker's suggestions), or None."""
    found = suggestion(name, candidates)
    return found.help if found is not None else None
