"""Lints after an edit (gpp.check.lintmemo): what reusing the warnings of the declarations an
edit left alone saves.

Run: .venv/bin/python bench/lint_reuse.py [--lines 1000] [--runs 30]

Two edits on bench/genprog's program, each made and undone `runs` times:
* space: a space typed at the start of the middle line, then deleted (as bench/lsp.py does);
* letter: a letter typed at the end of a name in an `if` condition of the procedure body
  nearest the middle, then deleted.
For each check, in-process and taking turns (the order alternating), with and without reuse:
* lints: `lint_again` with the memo of the check before, against `run_lints`, on the same
  code model (its reference index dropped before each, as a fresh check has none);
* whole check: `Session.check` of two sessions, one reusing lint warnings, one not (each
  with its own parse cache: the parse is incremental in both).
Times are wall-clock (the cyclic collector paused, as in a check): best and median, in ms, and
the ratio of the medians; the load average is printed beside them.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import replace
from functools import partial
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from genprog import generate_program

from gpp.base.perf import paused_gc, with_deep_stack
from gpp.base.source import Source
from gpp.check.lintmemo import LintMemo, lint_again
from gpp.check.lints import run_lints
from gpp.check.session import Session
from gpp.model.build import build_model
from gpp.model.model import Model
from gpp.syntax import ast
from gpp.syntax.loader import ParseCache, load
from gpp.syntax.parser import parse


def space_edit(text: str) -> str:
    start = Source(text).line_starts[Source(text).line_count() // 2]
    return text[:start] + " " + text[start:]


def letter_edit(text: str) -> str:
    bodies = [
        d.body.span
        for d in parse(Source(text)).program.declarations
        if isinstance(d, ast.ProcedureDecl) and d.body is not None and "if (" in d.body.span.text
    ]
    body = min(bodies, key=lambda b: abs(b.start - len(text) // 2))
    at = text.index("if (", body.start) + len("if (")
    while text[at].isalnum() or text[at] == "_":
        at += 1
    return text[:at] + "x" + text[at:]


def timed(fn: Callable[[], object]) -> float:
    with paused_gc():
        t0 = time.perf_counter()
        with_deep_stack(fn)
        return time.perf_counter() - t0


def reuse(model: Model, roots: set[Path], memo: LintMemo, out: list[LintMemo]) -> None:
    out.append(lint_again(replace(model), roots, (), memo)[1])


def lint_all(model: Model, roots: set[Path]) -> None:
    run_lints(replace(model), roots)


def measure(text: str, edited: str, runs: int, path: Path) -> dict[str, list[float]]:
    times: dict[str, list[float]] = {k: [] for k in ("lints reused", "lints all", "check reused", "check all")}
    cache = ParseCache()
    roots = {path}
    memo = LintMemo()
    sessions = {"check reused": Session(reuse_lints=True), "check all": Session(reuse_lints=False)}
    for session in sessions.values():
        session.check(path, {path: text})
    for k in range(2 * runs + 1):
        now = edited if k % 2 == 0 else text
        loaded = load([path], {path: now}, cache=cache)
        model, _ = with_deep_stack(partial(build_model, loaded.files))
        new_memo: list[LintMemo] = []
        turns: list[tuple[str, Callable[[], object]]] = [
            ("lints reused", partial(reuse, model, roots, memo, new_memo)),
            ("lints all", partial(lint_all, model, roots)),
            *((name, partial(session.check, path, {path: now})) for name, session in sessions.items()),
        ]
        if k % 2:
            turns.reverse()
        for name, fn in turns:
            seconds = timed(fn)
            if k > 0:  # the first round warms up
                times[name].append(seconds)
        memo = new_memo[0]
    assert memo.reused > 0, "no reuse: the edit changed the environment?"
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--lines", type=int, default=1000)
    parser.add_argument("--runs", type=int, default=30, help="times each edit is made and undone")
    args = parser.parse_args()
    text = generate_program(args.lines)
    path = (Path(tempfile.gettempdir()) / f"gpp-bench-reuse-{args.lines}.gpp").resolve()
    with open("/proc/loadavg", encoding="ascii") as f:
        load_before = f.read().split()[:3]
    print(f"lints after an edit, {args.lines:,} lines, {2 * args.runs} checks per edit; load {' '.join(load_before)}")
    print(f"{'edit':<8}{'what':<16}{'best ms':>9}{'median ms':>11}   median ratio")
    for name, edited in (("space", space_edit(text)), ("letter", letter_edit(text))):
        times = measure(text, edited, args.runs, path)
        for what in ("lints", "check"):
            reused, full = times[f"{what} reused"], times[f"{what} all"]
            ratio = statistics.median(full) / statistics.median(reused)
            for label, values in (("reused", reused), ("all", full)):
                best, median = min(values) * 1000, statistics.median(values) * 1000
                row = f"{name:<8}{what + ' ' + label:<16}{best:9.1f}{median:11.1f}"
                print(row + (f"   {ratio:.1f}x faster" if label == "reused" else ""))
    with open("/proc/loadavg", encoding="ascii") as f:
        print("load after:", " ".join(f.read().split()[:3]))


if __name__ == "__main__":
    main()
