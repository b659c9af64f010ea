"""Pathological inputs: does `gpp check` stay linear in the size of what it is given?

Run: .venv/bin/python bench/pathological.py [--quick] [--family NAME ...] [--timeout S]

Every family of inputs below (unclosed braces, deep nesting, long chains, many diagnostics on
one line, a binary file, ...) is generated at four sizes (about 1 KB, 10 KB, 100 KB and 1 MB;
`--quick`: 1, 4 and 16 KB) and checked in-process, as `gpp check` does: the file is loaded
from disk, parsed, checked with lints, and the diagnostics are rendered as text (with the
default limit of diagnostics per code and file). Each case runs in a fresh child process, so
that its peak memory is its own and a case that hangs is stopped after `--timeout` seconds
(the larger sizes of that family are then skipped).

For each case the table shows the diagnostics found (how many, the most frequent code), the
seconds to check and to render, the peak memory above the child's baseline (resident set
size), and `growth`: the exponent k in time ~ size^k between this size and the previous one
(1.0 is linear, 2.0 quadratic). Small sizes are dominated by fixed costs; read the last ratios.

Families that nest (blocks, `if`, calls, ...) are bounded by the parser's nesting limit when
there is one: their sizes are depths up to the limit, the limit itself, and one over it (which
must be refused quickly with a diagnostic). A few valid families also run with `gpp run`'s
machinery (dummy platform) at the sizes that check cleanly.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import resource
import subprocess
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

BENCH = Path(__file__).resolve().parent
sys.path.insert(0, str(BENCH))

from genprog import PICK, callers_of_a_renamed_action, chain_of_procedures, generate_program  # noqa: E402


@dataclass(frozen=True)
class Family:
    name: str
    make: Callable[[int], str | bytes]  # n repetitions of the family's unit -> the file's contents
    nesting: bool = False  # bounded by the parser's nesting limit
    run: bool = False  # also run it (a valid program with a main)


def lines_of(n: int, op: str, operand: str) -> str:
    return f"number function f() =\n    {operand}" + f"\n    {op} {operand}" * (n - 1) + "\n"


def binary(n: int) -> bytes:
    rng = random.Random(n)
    return bytes(rng.randrange(256) for _ in range(n))


FAMILIES: list[Family] = [
    Family("unclosed-braces", lambda n: "procedure main() " + "{" * n, nesting=True),
    Family("unclosed-parentheses", lambda n: "number function f() = " + "(" * n, nesting=True),
    Family("nested-if", lambda n: "action a() {}\nprocedure main() {" + "if (true) " * n + "a();}\n", True, True),
    Family(
        "nested-blocks", lambda n: "action a() {}\nprocedure main() " + "{" * n + "a();" + "}" * n + "\n", True, True
    ),
    Family("nested-while", lambda n: "procedure main() {" + "while (false) " * n + "{}}\n", nesting=True),
    Family("nested-choose", lambda n: "procedure main() " + "choose {" * n + "{}" + "}" * n + "\n", nesting=True),
    Family(
        "nested-concurrent", lambda n: "procedure main() " + "concurrent {" * n + "{}" + "}" * n + "\n", nesting=True
    ),
    Family("nested-pick", lambda n: "symbol domain D = {a}\nprocedure main() {" + "pick (D x) " * n + "{}}\n", True),
    Family("unary-minus", lambda n: "number function f() = " + "-" * n + "1\n", nesting=True),
    Family("negation", lambda n: "bool function f() = " + "!" * n + "true\n", nesting=True),
    Family("nested-calls", lambda n: "number function f(number k) = " + "f(" * n + "1" + ")" * n + "\n", True),
    Family("nested-exists", lambda n: "bool function f() = " + "exists (bool b) " * n + "b\n", nesting=True),
    Family("field-chain", lambda n: "compound P { number x }\nnumber function f(P p) = p" + ".x" * n + "\n"),
    Family(
        "sum-over-lines",
        lambda n: lines_of(n, "+", "1") + "action a(number k) {}\nprocedure main() { a(f()); }\n",
        run=True,
    ),
    Family("conjunction-over-lines", lambda n: lines_of(n, "&", "true").replace("number function", "bool function")),
    Family("unclosed-string", lambda n: 'string function s() = "' + "action a() {}\n" * n),
    Family("unclosed-comment", lambda n: "/* " + "action a() {}\n" * n),
    Family("long-domain", lambda n: "symbol domain D = {" + ", ".join(f"s{i}" for i in range(n)) + "}\n"),
    Family("long-union", lambda n: "symbol domain D = " + " | ".join(["{a}"] * n) + "\n"),
    Family(
        "many-declarations",
        lambda n: "".join(f"action a{i}() {{}}\n" for i in range(n)) + "procedure main() { a0(); }\n",
        run=True,
    ),
    Family(
        "many-statements",
        lambda n: "action a() {}\nprocedure main() {\n" + "    a();\n" * n + "}\n",
        run=True,
    ),
    Family("generated-program", lambda n: generate_program(max(1, n))),
    Family("one-line-many-diagnostics", lambda n: "procedure main() {" + " zz();" * n + "}\n"),
    Family("one-line-if-diagnostics", lambda n: "procedure main() {" + " if (true) {}" * n + "}\n"),
    # One unknown name, n errors, each with a did-you-mean among n declared names.
    Family("callers-of-renamed-action", callers_of_a_renamed_action),
    # The lints that follow calls: which procedures run only while planning (none), and which
    # reach a `pick` (all), each found one call further along the chain.
    Family("procedure-chain-online", lambda n: chain_of_procedures(n, PICK, "pn();")),
    Family(
        "procedure-chain-to-pick",
        lambda n: chain_of_procedures(n, PICK, "solve (2, r()) pn();", backwards=True),
    ),
    Family("binary-file", binary),
]

SIZES = [1_000, 10_000, 100_000, 1_000_000]
QUICK_SIZES = [1_000, 4_000, 16_000]
NESTING_DEPTHS = [100, 1_000, 10_000, 100_000]
QUICK_DEPTHS = [100, 400, 1_600]


def nesting_limit() -> int | None:
    """The front end's limit on nesting depth (gpp.syntax.depth.MAX_NESTING), if it has one."""
    try:
        from gpp.syntax import depth  # type: ignore[attr-defined, unused-ignore]
    except ImportError:
        return None
    value = getattr(depth, "MAX_NESTING", None)
    return value if isinstance(value, int) else None


def repetitions(family: Family, size: int) -> int:
    """How many units make a file of about `size` bytes."""
    per_unit = (len(family.make(200)) - len(family.make(100))) / 100
    return max(1, round(size / max(per_unit, 1)))


def cases(family: Family, quick: bool, limit: int | None) -> list[int]:
    """The repetition counts to measure for a family."""
    if not family.nesting:
        return [repetitions(family, s) for s in (QUICK_SIZES if quick else SIZES)]
    depths = QUICK_DEPTHS if quick else NESTING_DEPTHS
    if limit is None:
        return depths
    below = [d for d in depths if d < limit]
    return sorted({*below, limit, limit + 1, *(d for d in depths[-1:] if d > limit + 1)})


# ---------------------------------------------------------------- one case, in a child process


def measure(family_name: str, n: int, run: bool) -> dict[str, object]:
    from gpp.check import check_program
    from gpp.report.text import DEFAULT_MAX_DIAGNOSTICS, render_text

    family = next(f for f in FAMILIES if f.name == family_name)
    contents = family.make(n)
    data = contents.encode("utf-8") if isinstance(contents, str) else contents
    with tempfile.TemporaryDirectory() as folder:
        # Warm up: the parse tables and the lazily imported modules are loaded once per process.
        warm = Path(folder) / "warm.gpp"
        warm.write_text("action a() {}\nprocedure main() { if (true) a(); zz(); }\n")
        render_text(check_program(warm).diagnostics)
        path = Path(folder) / f"{family.name}.gpp"
        path.write_bytes(data)
        base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        started = time.perf_counter()
        result = check_program(path)
        checked = time.perf_counter()
        text = render_text(result.diagnostics, max_per_code=DEFAULT_MAX_DIAGNOSTICS)
        rendered = time.perf_counter()
        report: dict[str, object] = {
            "bytes": len(data),
            "check": checked - started,
            "render": rendered - checked,
            "output": len(text),
            "diagnostics": len(result.diagnostics),
            "codes": Counter(d.code for d in result.diagnostics).most_common(2),
        }
        if run and not result.errors:
            from gpp.run.runner import RunOptions, run_program

            started = time.perf_counter()
            outcome = run_program(path, RunOptions(time_limit=600.0, timeout=600.0), checked=result)
            report["run"] = time.perf_counter() - started
            report["run_status"] = outcome.result.status.value if outcome.result else "not started"
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        report["memory_mb"] = (peak - base) / 1024
    return report


def child(family_name: str, n: int, run: bool, timeout: float) -> dict[str, object] | None:
    """Measure one case in a fresh interpreter; None when it took longer than `timeout`."""
    args = [sys.executable, str(Path(__file__)), "--child", family_name, str(n)] + (["--run"] if run else [])
    try:
        proc = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None
    if proc.returncode != 0:
        return {"failed": (proc.stderr.strip().splitlines() or [f"exit code {proc.returncode}"])[-1]}
    report: dict[str, object] = json.loads(proc.stdout)
    return report


# ---------------------------------------------------------------- the table


def growth(seconds: float, size: int, previous: tuple[float, int] | None) -> str:
    """The exponent k in seconds ~ size^k since the previous size (blank when the sizes are
    too close for it to mean anything, as at the nesting limit and one over it)."""
    if previous is None or previous[0] <= 0 or seconds <= 0 or size < 1.5 * previous[1]:
        return ""
    return f"{math.log(seconds / previous[0]) / math.log(size / previous[1]):.2f}"


def codes_text(codes: object) -> str:
    assert isinstance(codes, list)
    return " ".join(f"{code}×{count}" for code, count in codes)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="sizes of 1, 4 and 16 KB, for a smoke run")
    ap.add_argument("--family", action="append", help="only this family (repeatable)")
    ap.add_argument("--timeout", type=float, help="seconds a case may take (default 120, quick 30)")
    ap.add_argument("--markdown", action="store_true", help="print the table as Markdown (docs/performance.md)")
    ap.add_argument("--child", nargs=2, metavar=("FAMILY", "N"), help=argparse.SUPPRESS)
    ap.add_argument("--run", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))  # as the gpp command does
        print(json.dumps(measure(args.child[0], int(args.child[1]), args.run)))
        return
    timeout = args.timeout or (30.0 if args.quick else 120.0)
    unknown = set(args.family or ()) - {f.name for f in FAMILIES}
    if unknown:
        ap.error(f"unknown family: {', '.join(sorted(unknown))} (families: {', '.join(f.name for f in FAMILIES)})")
    families = [f for f in FAMILIES if not args.family or f.name in args.family]
    limit = nesting_limit()
    print(f"nesting limit of the parser: {limit if limit is not None else 'none'}; timeout {timeout:g} s per case")
    header = ["family", "n", "KB", "diagnostics", "check s", "growth", "render s", "run s", "peak MB"]
    if args.markdown:
        print()  # a table after a paragraph needs the blank line
        print("| " + " | ".join(header) + " |")
        print("|" + "|".join("---" for _ in header) + "|")
    else:
        print(
            f"{'family':<26} {'n':>8} {'KB':>7}  {'diagnostics':<24} {'check s':>8} {'growth':>6} "
            f"{'render s':>8} {'run s':>7} {'peak MB':>8}"
        )
    for family in families:
        previous: tuple[float, int] | None = None
        stopped = False
        for n in cases(family, args.quick, limit):
            if stopped:
                row = [family.name, f"{n:,}", "", "skipped (a smaller size timed out)", "", "", "", "", ""]
            else:
                report = child(family.name, n, family.run, timeout)
                if report is None:
                    stopped = True
                    row = [family.name, f"{n:,}", "", f"> {timeout:g} s: stopped", "", "", "", "", ""]
                elif "failed" in report:
                    row = [family.name, f"{n:,}", "", f"FAILED: {report['failed']}", "", "", "", "", ""]
                else:
                    seconds = float(report["check"])  # type: ignore[arg-type]
                    size = int(report["bytes"])  # type: ignore[call-overload]
                    diagnostics = f"{report['diagnostics']:,} {codes_text(report['codes'])}".strip()
                    run = f"{report['run']:.3f}" if "run" in report else ""
                    row = [
                        family.name,
                        f"{n:,}",
                        f"{size / 1024:,.1f}",
                        diagnostics,
                        f"{seconds:.3f}",
                        growth(seconds, size, previous),
                        f"{report['render']:.3f}",
                        run,
                        f"{report['memory_mb']:.0f}",
                    ]
                    previous = (seconds, size)
            if args.markdown:
                print("| " + " | ".join(row) + " |")
            else:
                print(
                    f"{row[0]:<26} {row[1]:>8} {row[2]:>7}  {row[3]:<24} {row[4]:>8} {row[5]:>6} "
                    f"{row[6]:>8} {row[7]:>7} {row[8]:>8}"
                )
            sys.stdout.flush()


if __name__ == "__main__":
    main()
