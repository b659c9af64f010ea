"""LALR tables for grammar/gpp.lark, built by lark and cached on disk.

lark builds the tables (about 0.3 s); gpp drives them with its own loop (gpp.syntax.parser)
so that it can lex with its own tokenizer, build the AST directly and recover from errors.
The compiled tables are cached in the user's cache directory, keyed by the grammar's hash.
"""

from __future__ import annotations

import hashlib
import marshal
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from typing import Any

from gpp.base.resources import cache_dir, grammar_path, write_cache_file

_FORMAT = 4  # bump when the layout of the cached tables changes


@dataclass(frozen=True, slots=True)
class Rule:
    size: int  # number of symbols on the right-hand side
    origin: str  # the nonterminal it produces
    builder: str  # AstBuilder method; "" for a pass-through or splice rule
    unit: bool  # a `?rule` with one child: passes its child through
    splice: bool  # an inlined helper rule (`_name`, repetitions): its children join the parent's
    has_splices: bool  # some child comes from a splice rule
    last: str  # the last symbol of the right-hand side ("" when empty)
    symbols: tuple[str, ...]  # the right-hand side (terminals are upper case)


@dataclass(frozen=True, slots=True)
class Tables:
    start_state: int
    end_state: int
    # actions[state][terminal]: >= 0 shift to that state; < 0 reduce by rule -1 - value
    actions: list[dict[str, int]]
    gotos: list[dict[str, int]]
    rules: list[Rule]
    # shift/reduce conflicts lark resolved as shift: (terminal, rule text)
    conflicts: list[tuple[str, str]]


def build_tables(grammar: str) -> Tables:
    """Compile the grammar with lark and extract the LALR tables."""
    import logging

    import lark as lark_package

    from gpp.base.resources import check_lark

    check_lark(lark_package.__version__)
    from lark import Lark, logger
    from lark.parsers.lalr_analysis import IntParseTable, Shift

    conflicts: list[tuple[str, str]] = []

    class _Collect(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            msg = record.getMessage()
            if msg.startswith("Shift/Reduce conflict"):
                terminal = msg.split("terminal ", 1)[1].split(":", 1)[0]
                conflicts.append((terminal, ""))
            elif msg.startswith(" * ") and conflicts and not conflicts[-1][1]:
                conflicts[-1] = (conflicts[-1][0], msg[3:].strip())

    handler = _Collect()
    old_level, old_handlers = logger.level, list(logger.handlers)
    for h in old_handlers:
        logger.removeHandler(h)
    logger.addHandler(handler)
    logger.setLevel(logging.DEBUG)
    # lark's annotations lag behind lark (they lack `lexer="basic"` and the attributes read
    # below), so its parser object is used untyped.
    make_parser: Any = Lark
    try:
        lark = make_parser(grammar, parser="lalr", lexer="basic", keep_all_tokens=True, debug=True)
    finally:
        logger.removeHandler(handler)
        for h in old_handlers:
            logger.addHandler(h)
        logger.setLevel(old_level)

    table = IntParseTable.from_ParseTable(lark.parser.parser.parser.parse_table)
    rule_index: dict[object, int] = {}
    rules: list[Rule] = []
    for r in lark.rules:
        rule_index[r] = len(rules)
        origin = str(r.origin.name)
        symbols = [str(s.name) for s in r.expansion]
        unit = bool(r.options.expand1) and len(symbols) == 1 and not r.alias
        splice = origin.startswith("_")
        builder = "" if unit or splice else str(r.alias or origin)
        rules.append(
            Rule(
                size=len(symbols),
                origin=origin,
                builder=builder,
                unit=unit,
                splice=splice,
                has_splices=any(s.startswith("_") and not s.isupper() for s in symbols),
                last=symbols[-1] if symbols else "",
                symbols=tuple(symbols),
            )
        )
    n_states = max(table.states) + 1
    actions: list[dict[str, int]] = [{} for _ in range(n_states)]
    gotos: list[dict[str, int]] = [{} for _ in range(n_states)]
    for state, row in table.states.items():
        for symbol, (action, arg) in row.items():
            if is_terminal(symbol):
                actions[state][symbol] = arg if action is Shift else -1 - rule_index[arg]
            else:
                gotos[state][symbol] = arg
    return Tables(
        start_state=table.start_states["start"],
        end_state=table.end_states["start"],
        actions=actions,
        gotos=gotos,
        rules=rules,
        conflicts=sorted(set(conflicts)),
    )


def _to_plain(t: Tables) -> Any:
    return (
        t.start_state,
        t.end_state,
        t.actions,
        t.gotos,
        [(r.size, r.origin, r.builder, r.unit, r.splice, r.has_splices, r.last, r.symbols) for r in t.rules],
        t.conflicts,
    )


def _from_plain(p: Any) -> Tables:
    start, end, actions, gotos, rules, conflicts = p
    return Tables(
        start_state=start,
        end_state=end,
        actions=actions,
        gotos=gotos,
        rules=[Rule(*r) for r in rules],
        conflicts=[tuple(c) for c in conflicts],
    )


def is_terminal(symbol: str) -> bool:
    return symbol.isupper() or symbol == "$END"


def first_sets(rules: Sequence[Rule]) -> dict[str, frozenset[str]]:
    """FIRST(X) for every nonterminal X of `rules`: the terminals a phrase derived from X can
    begin with (the usual fixpoint over the rules, with the nonterminals that derive the empty
    phrase)."""
    first: dict[str, set[str]] = {r.origin: set() for r in rules}
    nullable: set[str] = set()
    changed = True
    while changed:
        changed = False
        for r in rules:
            into = first[r.origin]
            before = len(into)
            for symbol in r.symbols:
                if is_terminal(symbol):
                    into.add(symbol)
                    break
                into |= first[symbol]
                if symbol not in nullable:
                    break
            else:
                if r.origin not in nullable:
                    nullable.add(r.origin)
                    changed = True
            changed = changed or len(into) != before
    return {name: frozenset(terminals) for name, terminals in first.items()}


@cache
def load_tables() -> Tables:
    """The tables for the installed grammar, from the disk cache when it is current.

    The cache is keyed by the grammar text alone: the cached tables carry their own rules, so
    they stay self-consistent whichever lark version built them (and importing lark costs
    more than loading them).
    """
    grammar = grammar_path().read_text(encoding="utf-8")
    key = hashlib.sha256(f"{_FORMAT}|{grammar}".encode()).hexdigest()[:20]
    path = cache_dir() / f"tables-{key}.marshal"
    try:
        return _from_plain(marshal.loads(path.read_bytes()))
    except (OSError, ValueError, EOFError, TypeError):
        pass
    tables = build_tables(grammar)
    write_cache_file(path, marshal.dumps(_to_plain(tables)))
    return tables
