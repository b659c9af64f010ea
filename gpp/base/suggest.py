"""Did-you-mean suggestions for misspelled names, shared by every layer that reports one."""

from __future__ import annotations

import difflib
import heapq
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass

from gpp.base.diagnostics import Applicability, Edit, Fix
from gpp.base.source import Span

# How close a name must be to be suggested by the checker (difflib's ratio).
CUTOFF = 0.6


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
    close = difflib.get_close_matches(name, pool, n=3, cutoff=CUTOFF)
    return Suggestion(tuple(close)) if close else None


def _ratio(matches: int, length: int) -> float:
    """difflib's ratio of `matches` in sequences of total `length` (the same float)."""
    return 2.0 * matches / length if length else 1.0


class NameIndex:
    """Candidate names, indexed to answer did-you-mean questions about many misspelled names:
    by lowercase form, and by character (which names hold it, how often) with each name's
    length, so that a question compares the misspelled name only with the names that share
    enough characters with it; each name's answer is computed once. The answers are those of
    `suggestion` over the same names."""

    __slots__ = ("_by_lower", "_lengths", "_names", "_postings", "_scored")

    def __init__(self, names: Iterable[str]) -> None:
        self._names = sorted(set(names))
        self._lengths = [len(n) for n in self._names]
        # Each lowercase form's names, in sorted order.
        self._by_lower: dict[str, list[str]] = {}
        # Each character's names (by position in `_names`) and how often each holds it.
        self._postings: dict[str, list[tuple[int, int]]] = {}
        for i, n in enumerate(self._names):
            self._by_lower.setdefault(n.lower(), []).append(n)
            for char, count in Counter(n).items():
                self._postings.setdefault(char, []).append((i, count))
        self._scored: dict[str, list[tuple[float, str]]] = {}

    def __len__(self) -> int:
        return len(self._names)

    def same_but_case(self, name: str) -> str | None:
        """Another name that differs from `name` only in case (the last in sorted order)."""
        for other in reversed(self._by_lower.get(name.lower(), ())):
            if other != name:
                return other
        return None

    def scored(self, name: str) -> list[tuple[float, str]]:
        """Every other name close to `name` (by difflib's ratio, at least the checker's cutoff),
        with its ratio: what difflib.get_close_matches ranks."""
        found = self._scored.get(name)
        if found is None:
            found = self._scored[name] = self._close(name)
        return found

    def _close(self, name: str) -> list[tuple[float, str]]:
        # The characters both names hold, counted with multiplicity (difflib's quick_ratio):
        # a name sharing none cannot reach the cutoff, and is never read.
        shared: dict[int, int] = {}
        get = shared.get
        for char, count in Counter(name).items():
            for i, held in self._postings.get(char, ()):
                shared[i] = get(i, 0) + (held if held < count else count)
        matcher = difflib.SequenceMatcher()
        matcher.set_seq2(name)
        width, names, lengths = len(name), self._names, self._lengths
        found: list[tuple[float, str]] = []
        for i, matches in shared.items():
            other, length = names[i], lengths[i]
            total = length + width
            # get_close_matches' three tests, in its order: the same floats, the same answers.
            if other == name or _ratio(min(length, width), total) < CUTOFF or _ratio(matches, total) < CUTOFF:
                continue
            matcher.set_seq1(other)
            score = matcher.ratio()
            if score >= CUTOFF:
                found.append((score, other))
        return found

    def suggestion(self, name: str) -> Suggestion | None:
        """`suggestion(name, names)`, from the index."""
        return suggestion_among(name, (self,))


def suggestion_among(name: str, indexes: Iterable[NameIndex]) -> Suggestion | None:
    """`suggestion` for a name among the names of several indexes together (a scope's
    variables and the program's symbols, say)."""
    indexes = list(indexes)
    variants = [v for v in (index.same_but_case(name) for index in indexes) if v is not None]
    if variants:
        return Suggestion((max(variants),))
    scored = {pair for index in indexes for pair in index.scored(name)}
    close = [other for _, other in heapq.nlargest(3, scored)]
    return Suggestion(tuple(close)) if close else None


def suggest(name: str, candidates: Iterable[str]) -> str | None:
    """`did you mean ...?` naming up to three close names (the checker's suggestions), or None."""
    found = suggestion(name, candidates)
    return found.help if found is not None else None
