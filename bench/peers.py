"""gpp's planner beside Fast Downward on the same blocksworld instances (gpp issue #27), for
`bench/planner.py --peers [--targets]`.

Each instance (bench/blocksworld.py: the towers of 5 to 12 blocks to reverse, random instances
of 7 to 10 blocks with three named seeds each) is written once as the golog++ program that
`solve`s it and once as PDDL. Fast Downward (the `up-fast-downward` wheel, the `bench` extra:
`make bench-peers` installs it) plans the PDDL with A* and the LM-cut heuristic, an optimal
planner, so its plan is a shortest one; gpp's plan must have the same length (and both must
reach the goal) before the two are compared: a row where they differ says so and has no ratio.

Per instance and run, one after the other (interleaved, so that both see the same load):

* Fast Downward's whole process (its driver, the translator, the search): the CPU time of the
  child and of its children (their rusage); and its own timers, the CPU time the translator
  and the search report, interpreter and driver left out: "FD own";
* gpp in-process: a fresh Python process checks the program and times the planning with
  time.process_time(): the first planning in the process (its generated code written and
  compiled), then that of the program checked anew (its generated code compiled before); the
  best counts, as `--targets` does. Its peak memory is the process's;
* gpp's whole process: `gpp run -q -p dummy` on the program, the CPU time of the child;
* gpp's start-up: the same on the instance already solved (nothing to plan); "gpp run −
  start-up" is what the planning adds to a run.

The best of --runs counts for each figure. A gpp planning past --limit CPU seconds is stopped
and shown as ">LIMIT s". Ratios are gpp / Fast Downward: below 1, gpp is faster.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from bench.blocksworld import (
    PDDL_DOMAIN,
    Instance,
    moves_of_pddl_plan,
    pddl_problem,
    program,
    random_instance,
    reaches_goal,
    tower,
)

ROOT = Path(__file__).resolve().parent.parent
FD_SEARCH = "astar(lmcut())"
TOWERS = range(5, 13)
RANDOM_SIZES = (7, 8, 9, 10)
SEEDS = (1, 2, 3)
HORIZON = 14

SOLVE = "solve"
NO_BOUND = "solve, no bound"
SEARCH_ID = "search, iterative deepening"

NOT_INSTALLED = (
    "Fast Downward is not installed: `make bench-peers` installs it (the `bench` extra, pip install -e '.[bench]')"
)


def fast_downward() -> Path | None:
    """The driver script of the installed up-fast-downward wheel, found without importing it
    (its package needs unified-planning, which the bench does not)."""
    spec = importlib.util.find_spec("up_fast_downward")
    if spec is None or not spec.submodule_search_locations:
        return None
    for folder in spec.submodule_search_locations:
        driver = Path(folder) / "downward" / "fast-downward.py"
        if driver.is_file():
            return driver
    return None


@dataclass
class ChildRun:
    """A finished child process: its CPU time (user + system, its own children included), its
    output and exit code (negative: the signal that ended it)."""

    seconds: float
    output: str
    code: int

    @property
    def ok(self) -> bool:
        return self.code == 0

    @property
    def over_limit(self) -> bool:
        return self.code in (-signal.SIGXCPU, -signal.SIGKILL)


def _cpu_of_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_child(args: list[str], cwd: Path, limit: float) -> ChildRun:
    """Run `args` with at most `limit` CPU seconds per process (and three times that of wall
    time); its CPU time is what the children reaped meanwhile used (this process runs one
    child at a time)."""

    def cap() -> None:
        seconds = max(1, math.ceil(limit))
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 1))

    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]))
    before = _cpu_of_children()
    child = subprocess.Popen(
        args,
        cwd=cwd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        preexec_fn=cap,
        start_new_session=True,
    )
    try:
        output, _ = child.communicate(timeout=3 * limit + 5)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        output, _ = child.communicate()
    return ChildRun(_cpu_of_children() - before, output, child.returncode)


@dataclass
class FdRun:
    moves: list[tuple[str, str]]
    whole: float  # CPU seconds of the whole process
    own: float  # what the translator and the search report
    expanded: int


def run_fast_downward(driver: Path, instance: Instance, folder: Path, limit: float) -> FdRun | None:
    (folder / "domain.pddl").write_text(PDDL_DOMAIN, encoding="ascii")
    (folder / "problem.pddl").write_text(pddl_problem(instance), encoding="ascii")
    plan_file = folder / "plan"
    plan_file.unlink(missing_ok=True)
    args = [sys.executable, str(driver), "--plan-file", "plan", "domain.pddl", "problem.pddl"]
    run = run_child([*args, "--search", FD_SEARCH], folder, limit)
    translator = re.search(r"^Done! \[([\d.]+)s CPU", run.output, re.MULTILINE)
    search = re.search(r"\] Total time: ([\d.]+)s", run.output)
    expanded = re.search(r"\] Expanded (\d+) state", run.output)
    if not (run.ok and translator and search and expanded and plan_file.is_file()):
        return None
    moves = moves_of_pddl_plan(plan_file.read_text(encoding="ascii"))
    return FdRun(moves, run.seconds, float(translator[1]) + float(search[1]), int(expanded[1]))


@dataclass(frozen=True)
class Case:
    """A planning problem for gpp: an instance, the horizon of its `solve`, and the planner."""

    instance: Instance
    horizon: int = HORIZON
    method: str = SOLVE

    @property
    def label(self) -> str:
        if self.method == SEARCH_ID:
            return f"{self.instance.name}, `search` (iterative deepening)"
        bound = ", no bound" if self.method == NO_BOUND else ""
        return f"{self.instance.name}, `solve({self.horizon})`{bound}"


@dataclass
class GppRun:
    moves: list[tuple[str, str]]
    nodes: int
    seconds: float  # the best of the first planning and the planning of the program checked anew
    peak_mib: float


def child_main() -> None:
    """In the child: plan the case given as JSON in argv[1] and print the figures as JSON."""
    from gpp.check import check_text
    from gpp.planner.problem import first_solve
    from gpp.planner.search import DEFAULT_STEP_BOUND, ITERATIVE_DEEPENING

    spec = json.loads(sys.argv[1])
    instance = Instance(spec["name"], tuple(spec["blocks"]), tuple(spec["start"]), tuple(spec["goal"]))
    text = program(instance, spec["horizon"])
    best = math.inf
    for _ in range(2):
        pb = first_solve(check_text(text, lint=False).model)
        started = time.process_time()
        if spec["method"] == SEARCH_ID:
            plan = pb.search(DEFAULT_STEP_BOUND, ITERATIVE_DEEPENING)
        else:
            plan = pb.production(prune=spec["method"] == SOLVE)
        best = min(best, time.process_time() - started)
        if best > 2:  # long enough not to need a second look
            break
    reached = plan.feasible and (spec["method"] == SEARCH_ID or plan.value > 0)
    moves = [m[len("stack(") : -1].split(",") for m in plan.actions()] if reached else []
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KiB on Linux
    print(json.dumps({"moves": moves, "nodes": plan.stats.nodes, "seconds": best, "peak_mib": peak}))


def run_gpp(case: Case, limit: float) -> GppRun | ChildRun:
    """gpp's figures, or the child run that did not give them."""
    instance = case.instance
    spec = {"name": instance.name, "blocks": instance.blocks, "start": instance.start, "goal": instance.goal}
    spec |= {"horizon": case.horizon, "method": case.method}
    code = "from bench.peers import child_main; child_main()"
    run = run_child([sys.executable, "-c", code, json.dumps(spec)], ROOT, limit)
    if not run.ok:
        return run
    found = json.loads(run.output.strip().splitlines()[-1])
    moves = [(block, to) for block, to in found["moves"]]
    return GppRun(moves, found["nodes"], found["seconds"], found["peak_mib"])


def run_gpp_whole(instance: Instance, horizon: int, folder: Path, limit: float) -> float | None:
    """CPU seconds of `gpp run -q -p dummy` on the instance's program (None if it failed)."""
    path = folder / "program.gpp"
    path.write_text(program(instance, horizon), encoding="utf-8")
    run = run_child([sys.executable, "-m", "gpp", "run", "-q", "-p", "dummy", str(path)], ROOT, limit)
    return run.seconds if run.ok else None


@dataclass
class Row:
    """The best figures of every run of one case (None: not measured, or it failed)."""

    case: Case
    fd: FdRun | None = None
    gpp: GppRun | None = None
    gpp_over_limit: bool = False
    whole: float | None = None
    startup: float | None = None
    problems: list[str] = field(default_factory=list)

    def comparable(self) -> bool:
        return self.fd is not None and self.gpp is not None and not self.problems


def _best(old: float | None, new: float | None) -> float | None:
    return new if old is None else old if new is None else min(old, new)


def measure(driver: Path, cases: list[Case], runs: int, limit: float, progress: Callable[[str], None]) -> list[Row]:
    """Every case, interleaved: Fast Downward (`driver`), gpp in-process, gpp's whole process
    and its start-up, then the next case; `runs` times (once for a gpp planning over a second)."""
    rows = [Row(case) for case in cases]
    with tempfile.TemporaryDirectory(prefix="gpp-peers-") as tmp:
        folder = Path(tmp)
        # One of each first, not counted: byte code written, files cached.
        warm = Case(tower(3), 4)
        run_fast_downward(driver, warm.instance, folder, limit)
        run_gpp(warm, limit)
        run_gpp_whole(warm.instance, warm.horizon, folder, limit)
        for run in range(runs):
            for row in rows:
                done = row.gpp_over_limit or (row.gpp is not None and row.gpp.seconds > 1)
                if run > 0 and (done or row.problems):
                    continue
                _measure_once(row, driver, folder, limit)
                progress(f"run {run + 1}/{runs}: {row.case.label}")
    return rows


def _measure_once(row: Row, driver: Path, folder: Path, limit: float) -> None:
    case = row.case
    if case.method != NO_BOUND:
        fd = run_fast_downward(driver, case.instance, folder, limit)
        if fd is None:
            row.problems.append("Fast Downward failed")
        elif not reaches_goal(case.instance, fd.moves):
            row.problems.append("Fast Downward's plan does not reach the goal")
        elif row.fd is None or fd.whole < row.fd.whole:
            row.fd = FdRun(fd.moves, fd.whole, min(fd.own, row.fd.own if row.fd else math.inf), fd.expanded)
        elif fd.own < row.fd.own:
            row.fd.own = fd.own
    gpp = run_gpp(case, limit)
    if isinstance(gpp, ChildRun):
        if gpp.over_limit:
            row.gpp_over_limit = True
        else:
            last = (gpp.output.strip().splitlines() or ["no output"])[-1]
            row.problems.append(f"gpp failed with exit code {gpp.code}: {last}")
        return
    if not reaches_goal(case.instance, gpp.moves):
        row.problems.append(f"gpp's plan does not reach the goal within {case.horizon} steps")
    if row.fd is not None and len(row.fd.moves) != len(gpp.moves):
        row.problems.append(f"plan lengths differ: gpp {len(gpp.moves)}, Fast Downward {len(row.fd.moves)}")
    if row.gpp is None or gpp.seconds < row.gpp.seconds:
        row.gpp = gpp
    if case.method == SOLVE:
        row.whole = _best(row.whole, run_gpp_whole(case.instance, case.horizon, folder, limit))
        row.startup = _best(row.startup, run_gpp_whole(case.instance.solved(), case.horizon, folder, limit))
    row.problems = list(dict.fromkeys(row.problems))


def peer_cases() -> list[Case]:
    """The towers of 5 to 12 blocks and the random instances, `solve(14)`."""
    cases = [Case(tower(n)) for n in TOWERS]
    return cases + [Case(random_instance(n, seed)) for n in RANDOM_SIZES for seed in SEEDS]


def target_cases() -> list[Case]:
    """The problems of the issue's table that the peer cases do not already hold."""
    return [Case(tower(10), 10), Case(tower(10), method=SEARCH_ID), Case(tower(8), method=NO_BOUND)]


def _s(seconds: float | None) -> str:
    if seconds is None:
        return ""
    return f"{seconds * 1000:.1f} ms" if seconds < 0.1 else f"{seconds:.2f} s"


def _ratio(a: float | None, b: float | None) -> str:
    return "" if a is None or b is None or b <= 0 else f"{a / b:.2f}"


def gpp_seconds(row: Row, limit: float) -> str:
    if row.gpp_over_limit:
        return f">{limit:g} s"
    return _s(row.gpp.seconds) if row.gpp else ""


def peers_table(rows: list[Row], limit: float) -> Iterator[str]:
    header = ["problem", "moves", "gpp nodes", "gpp in-process", "FD own", "gpp/FD in-process", "FD expanded"]
    header += ["gpp run", "start-up", "gpp run − start-up", "FD whole", "gpp run/FD", "(run − start-up)/FD"]
    yield "| " + " | ".join(header) + " |"
    yield "|---|" + "---:|" * (len(header) - 1)
    for row in rows:
        fd, gpp, ok = row.fd, row.gpp, row.comparable()
        planning = None if row.whole is None or row.startup is None else row.whole - row.startup
        cells = [
            row.case.label + "".join(f" **({p})**" for p in row.problems),
            str(len(fd.moves)) if fd else str(len(gpp.moves)) if gpp else "",
            f"{gpp.nodes:,}" if gpp else "",
            gpp_seconds(row, limit),
            _s(fd.own) if fd else "",
            _ratio(gpp.seconds if gpp and ok else None, fd.own if fd else None),
            f"{fd.expanded:,}" if fd else "",
            _s(row.whole),
            _s(row.startup),
            _s(planning),
            _s(fd.whole) if fd else "",
            _ratio(row.whole if ok else None, fd.whole if fd else None),
            _ratio(planning if ok else None, fd.whole if fd else None),
        ]
        yield "| " + " | ".join(cells) + " |"


# The issue's figures for the problems it names (before its work), and its targets.
ISSUE_BEFORE = {
    "tower 9, `solve(14)`": "19,147 nodes, 1.19 s",
    "tower 10, `solve(10)`": "19,129 nodes, 1.21 s",
    "tower 10, `search` (iterative deepening)": "234,477 nodes, 67.8 s, 1.3 GB",
    "tower 8, `solve(14)`, no bound": "1,139,700 nodes, 15.9 s, 1.5 GB",
}
UNBOUNDED_TOWER_8_NODES = 1_139_700
TARGET_SECONDS = {
    "tower 10, `solve(10)`": 0.05,
    "tower 10, `solve(14)`": 0.05,
    "tower 12, `solve(14)`": 0.5,
    **{f"random 8 #{seed}, `solve(14)`": 0.2 for seed in SEEDS},
    **{f"random 10 #{seed}, `solve(14)`": 2.0 for seed in SEEDS},
    "tower 10, `search` (iterative deepening)": 0.5,
}
SEARCH_PEAK_MIB = 200
TARGET_ROWS = ["tower 9, `solve(14)`", *TARGET_SECONDS, "tower 8, `solve(14)`, no bound"]


def targets_table(rows: list[Row], limit: float) -> Iterator[str]:
    """The issue's table: its problems with the figures before (from the issue), gpp's now,
    Fast Downward's, the target and pass or miss."""
    yield "| problem | before (issue #27) | gpp now (in-process) | Fast Downward | target | met |"
    yield "|---|---|---|---|---|:---:|"
    by_label = {row.case.label: row for row in rows}
    for label in TARGET_ROWS:
        row = by_label.get(label)
        if row is None:  # not measured (--quick)
            continue
        gpp, fd = row.gpp, row.fd
        now = "" if gpp is None else f"{gpp.nodes:,} nodes, {_s(gpp.seconds)}"
        if row.gpp_over_limit:
            now = f">{limit:g} s"
        elif gpp is not None and row.case.method != SOLVE:
            now += f", {gpp.peak_mib:,.0f} MiB"
        peer = "" if fd is None else f"{fd.expanded:,} expansions; whole process {_s(fd.whole)}, own {_s(fd.own)}"
        target, met = "", ""
        if label in TARGET_SECONDS:
            limit_s = TARGET_SECONDS[label]
            target = f"< {_s(limit_s)}"
            passed = gpp is not None and gpp.seconds < limit_s and not row.problems
            if row.case.method == SEARCH_ID:
                target += f", < {SEARCH_PEAK_MIB} MB"
                passed = passed and gpp is not None and gpp.peak_mib < SEARCH_PEAK_MIB
            met = "pass" if passed else "miss"
        elif row.case.method == NO_BOUND:
            target, met = "same nodes as before", "pass" if gpp and gpp.nodes == UNBOUNDED_TOWER_8_NODES else "miss"
        problems = "".join(f" **({p})**" for p in row.problems)
        yield f"| {label}{problems} | {ISSUE_BEFORE.get(label, '')} | {now} | {peer} | {target} | {met} |"
    for row in rows:
        if row.case.method != SOLVE or not row.case.instance.name.startswith("tower"):
            continue
        label = f"whole process, {row.case.label}: `gpp run` − start-up"
        fd_whole = "" if row.fd is None else f"whole process {_s(row.fd.whole)}"
        if row.whole is None or row.startup is None or row.fd is None:
            # over the limit in-process (then its whole process is not run), or failed
            now = gpp_seconds(row, limit) if row.gpp_over_limit else "not measured"
            yield f"| {label} | | {now} | {fd_whole} | below Fast Downward's | miss |"
            continue
        planning = row.whole - row.startup
        yield (
            f"| {label} | | {_s(row.whole)} − {_s(row.startup)} = {_s(planning)} | {fd_whole} | "
            f"below Fast Downward's | {'pass' if planning < row.fd.whole and not row.problems else 'miss'} |"
        )


def report(rows: list[Row], limit: float, targets: bool, print_line: Callable[[str], None]) -> None:
    peers = [row for row in rows if row.case in set(peer_cases())]
    for line in peers_table(peers, limit):
        print_line(line)
    if targets:
        print_line("")
        for line in targets_table(rows, limit):
            print_line(line)
    with open("/proc/loadavg", encoding="ascii") as load:
        print_line("")
        print_line(f"Load average at the end: {load.read().split()[0]}; {os.cpu_count()} cores.")
