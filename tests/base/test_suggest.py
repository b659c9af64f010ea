"""The indexed did-you-mean (`NameIndex`, `suggestion_among`) answers exactly as the plain one
(`suggestion`, difflib over every name), on random names and candidate sets."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from gpp.base.suggest import NameIndex, Suggestion, suggestion, suggestion_among

# Few letters, both cases, `_` and digits: names often share characters, differ only in case,
# tie in score, or are empty.
letters = st.sampled_from("abcAB_1é")
names = st.text(letters, max_size=9)

# Pools with names that differ only in case: their variants, upper, lower and swapped.
pools = st.lists(names, max_size=30).map(lambda ns: ns + [f(n) for n in ns[:4] for f in (str.upper, str.swapcase)])


@settings(max_examples=400, deadline=None)
@given(pools, st.lists(names, min_size=1, max_size=8))
def test_the_index_suggests_what_difflib_over_every_name_suggests(pool: list[str], asked: list[str]) -> None:
    index = NameIndex(pool)
    # Pool names are asked too (the answer leaves the name itself out).
    for name in [*asked, *pool[:3], *(n.swapcase() for n in pool[:3]), *(n.lower() for n in pool[:3])]:
        assert index.suggestion(name) == suggestion(name, pool), name
        assert index.suggestion(name) == suggestion(name, pool), name  # the cached answer


@settings(max_examples=300, deadline=None)
@given(pools, pools, names)
def test_several_indexes_suggest_what_their_union_suggests(first: list[str], second: list[str], name: str) -> None:
    assert suggestion_among(name, [NameIndex(first), NameIndex(second)]) == suggestion(name, first + second)


def test_a_large_set_of_similar_names() -> None:
    pool = [f"caller_{i}" for i in range(2_000)] + ["move_to"]
    index = NameIndex(pool)
    assert index.suggestion("move_ot") == Suggestion(("move_to",))
    assert index.suggestion("Move_to") == Suggestion(("move_to",))
    assert index.suggestion("goto") is None
    # A name of the pool is not suggested for itself; its neighbours are.
    found = index.suggestion("caller_12")
    assert found is not None and "caller_12" not in found.names
    assert found == suggestion("caller_12", pool)


def test_of_the_names_that_differ_only_in_case_the_last_in_sorted_order_is_suggested() -> None:
    pool = ["Ab", "AB", "ab", "aB"]
    for name in ["ab", "AB", "aB", "Ab"]:
        assert NameIndex(pool).suggestion(name) == suggestion(name, pool) is not None, name
    assert suggestion_among("ab", [NameIndex(["AB"]), NameIndex(["aB"])]) == Suggestion(("aB",))


def test_ties_and_the_cutoff_itself_are_as_difflib_has_them() -> None:
    pool = ["ab", "ba", "bb", "aa", "abc", "abcxy", "xabcy"]
    for name in ["a", "b", "ab", "abb", "AB", "abcde"]:
        assert NameIndex(pool).suggestion(name) == suggestion(name, pool), name
    # 3 of 10 characters match: a ratio of 0.6, exactly the cutoff.
    assert NameIndex(["abcxy"]).suggestion("abcde") == Suggestion(("abcxy",))
