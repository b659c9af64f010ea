"""Regenerate the figures of docs/performance.md: run the benches and put what each prints
between its markers.

Run: .venv/bin/python bench/performance.py [--only NAME ...] [--quick] [--doc PATH]

Each bench's figures sit in docs/performance.md between `<!-- bench: NAME -->` and
`<!-- /bench: NAME -->`. The driver runs the bench (a fresh process, with the options of
`make bench`), and replaces the text between its two markers with what the bench printed:
verbatim for a bench with a `--markdown` mode (its tables), otherwise its whole output in a
```text block. A line under it gives the command, the date, the machine (cores, load average
before and after) and the git revision. Everything outside the markers is left byte for byte.
The file is written after each bench, so an interrupted run keeps the sections it finished; a
bench that fails leaves its section as it was (and the driver exits with 1).

Without --only it runs the benches of `make bench` in their order; `pathological` (`make
pathological`) and `peers` (`make bench-peers`, which installs Fast Downward first) run only
when named. --quick gives the benches that have one their smoke-run
options (fewer sizes or steps); the line under the table shows the command, so a quick run is
never taken for a full one.
"""

from __future__ import annotations

import argparse
import datetime
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "performance.md"


@dataclass(frozen=True)
class Bench:
    script: str
    args: tuple[str, ...] = ()
    quick: tuple[str, ...] | None = None  # the options of a smoke run, instead of `args`
    markdown: bool = False  # has a --markdown mode printing exactly its tables
    default: bool = True  # one of `make bench`


# The benches of `make bench`, in its order, with the options the Makefile gave them.
BENCHES: dict[str, Bench] = {
    "startup": Bench("startup.py", markdown=True),
    "parse_speed": Bench("parse_speed.py", quick=("--quick",), markdown=True),
    "incparse": Bench("incparse.py"),
    "lints": Bench("lints.py", ("--sizes", "1000", "10000"), quick=("--sizes", "1000")),
    "lint_reuse": Bench("lint_reuse.py"),
    "model_speed": Bench("model_speed.py"),
    "lsp": Bench("lsp.py", quick=("--quick",)),
    "dap": Bench("dap.py", quick=("--quick",), markdown=True),
    "planner": Bench("planner.py", quick=("--quick",)),
    "sim": Bench("sim.py", markdown=True),
    "ros2": Bench("ros2.py"),
    "soak": Bench("soak.py", quick=("--steps", "100000"), markdown=True),
    "console": Bench("console.py", quick=("--rounds", "3", "--steps", "2000"), markdown=True),
    "pathological": Bench("pathological.py", quick=("--quick",), markdown=True, default=False),
    "peers": Bench("planner.py", ("--targets", "--peers"), quick=("--peers", "--quick"), markdown=True, default=False),
}

# A marker is a line of its own (so that one quoted in the prose is not one).
MARKER = re.compile(r"^<!-- (/?)bench: ([\w-]+) -->[ \t]*$", re.MULTILINE)


class MarkerError(ValueError):
    pass


def sections(text: str) -> dict[str, tuple[int, int]]:
    """The bench sections of `text`: NAME -> (start, end) of the text between its markers (after
    the opening marker's line, up to the closing marker). Raises MarkerError on a marker left
    open, closed without being opened, nested, or used twice."""
    found: dict[str, tuple[int, int]] = {}
    open_name: str | None = None
    start = 0
    for m in MARKER.finditer(text):
        closing, name = m.group(1) == "/", m.group(2)
        line = text.count("\n", 0, m.start()) + 1
        if not closing:
            if open_name is not None:
                raise MarkerError(f"line {line}: bench {name} opened inside bench {open_name}")
            if name in found:
                raise MarkerError(f"line {line}: bench {name} has a second section")
            open_name = name
            end_of_line = text.find("\n", m.end())
            start = len(text) if end_of_line < 0 else end_of_line + 1
        else:
            if open_name != name:
                raise MarkerError(f"line {line}: bench {name} closed, but {open_name or 'none'} is open")
            line_start = text.rfind("\n", 0, m.start()) + 1
            found[name] = (start, line_start)
            open_name = None
    if open_name is not None:
        raise MarkerError(f"bench {open_name} is not closed")
    return found


def replace_section(text: str, name: str, body: str) -> str:
    """`text` with the text between bench NAME's markers replaced by `body` (ended by a newline);
    everything else unchanged."""
    where = sections(text)
    if name not in where:
        raise MarkerError(f"no section for bench {name}")
    start, end = where[name]
    if body and not body.endswith("\n"):
        body += "\n"
    return text[:start] + body + text[end:]


def command_line(name: str, quick: bool) -> list[str]:
    bench = BENCHES[name]
    args = bench.quick if quick and bench.quick is not None else bench.args
    return [f"bench/{bench.script}", *args, *(("--markdown",) if bench.markdown else ())]


def load() -> str:
    try:
        return " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "?"


def revision() -> str:
    def git(*args: str) -> str:
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=False).stdout.strip()

    rev = git("rev-parse", "--short", "HEAD") or "unknown"
    return rev + (" with uncommitted changes" if git("status", "--porcelain", "--untracked-files=no") else "")


def body(output: str, markdown: bool, stamp: str) -> str:
    """What goes between the markers: the bench's output (as Markdown, or in a text block) and
    the stamp line under it."""
    output = output.strip("\n")
    shown = output if markdown else f"```text\n{output}\n```"
    return f"{shown}\n\n{stamp}\n"


def run(name: str, quick: bool) -> str | None:
    """Run bench NAME (its output shown as it comes); the text for its section, or None if it
    failed."""
    args = command_line(name, quick)
    print(f"== {name}: {' '.join(args)}", flush=True)
    before = load()
    process = subprocess.Popen([sys.executable, *args], cwd=ROOT, stdout=subprocess.PIPE, text=True)
    assert process.stdout is not None
    lines = []
    for line in process.stdout:
        sys.stdout.write(line)
        sys.stdout.flush()
        lines.append(line)
    if process.wait() != 0:
        print(f"== {name} failed (exit code {process.returncode}); its section is left as it was", flush=True)
        return None
    when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    stamp = (
        f"<sub>`{' '.join(args)}`, {when}, {os.cpu_count()} cores, load average {before} before and "
        f"{load()} after, revision {revision()}</sub>"
    )
    return body("".join(lines), BENCHES[name].markdown, stamp)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=sorted(BENCHES), help="these benches only")
    ap.add_argument("--quick", action="store_true", help="smoke-run options for the benches that have them")
    ap.add_argument("--doc", type=Path, default=DOC, help="the file to update (default docs/performance.md)")
    args = ap.parse_args()
    names = args.only or [name for name, bench in BENCHES.items() if bench.default]
    missing = [name for name in names if name not in sections(args.doc.read_bytes().decode("utf-8"))]
    if missing:
        ap.error(f"{args.doc} has no section for: {', '.join(missing)}")
    failed = []
    for name in names:
        text = run(name, args.quick)
        if text is None:
            failed.append(name)
            continue
        doc = args.doc.read_bytes().decode("utf-8")  # as it is now (not as it was), line endings and all
        args.doc.write_bytes(replace_section(doc, name, text).encode("utf-8"))
        print(f"== {name}: written to {args.doc}", flush=True)
    if failed:
        print(f"failed: {', '.join(failed)}", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
