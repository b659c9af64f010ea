"""What the operator console costs a run: the wall time of one run without a console, with a
console attached, with a browser reading its live stream, with three slow browsers (that never
read: their connections' buffers fill), with browsers that vanish (connect, then the connection
is reset mid-stream), and with a browser reconnecting twenty times a second (a stress case),
each as a ratio to the run without. The bound: within 5 %.

The run is the executor at full speed: a program of many short steps on the dummy platform
(virtual time: no step waits for a clock), about 30,000 records a second, so the console's
share of each step is what shows. Each browser is a process of its own on another core (as a
tablet is another machine); the run and the console's thread share one core. The cases take
turns, `--rounds` times, each round starting one case later; each case's ratio is the median
over the rounds of its time against the run without a console of the same round, with the
quartiles, so the machine's other work, which moves single runs by more than the console does,
cancels out. The console's thread's own CPU time is measured apart (to the nanosecond, from
Linux's schedstat): what the console adds to the process, free of that noise.

Run: .venv/bin/python bench/console.py [--steps N] [--rounds R] [--markdown]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from gpp.check import check_program  # noqa: E402
from gpp.console.access import Access, Address  # noqa: E402
from gpp.console.control import ConsoleControl  # noqa: E402
from gpp.console.server import PUSHES_PER_SECOND, ConsoleServer, serve  # noqa: E402
from gpp.console.state import ConsoleState  # noqa: E402
from gpp.run.runner import RunOptions, run_program  # noqa: E402
from gpp.runtime.trace import Trace, TraceListener  # noqa: E402

PROGRAM = """symbol domain Block = {a, b, c, d}

number fluent steps() {
initially:
    () = 0;
}

Block fluent held() {
initially:
    () = a;
}

exog_action nudge() {
effect:
    held() = b;
}

action move(Block x) {
effect:
    held() = x;
duration: [0.01, 0.01]
}

procedure main() {
    while (steps() < %d) {
        steps() = steps() + 1;
        pick (Block x in {a, b, c, d})
            if (x != held()) move(x);
    }
}
"""

# How a browser behaves (run in a process of its own, as a browser is): `reading` reads every
# view the stream sends; `slow` is three that never read (tiny receive buffers, soon full);
# `vanishing` connect, read the first view and vanish (the connection reset, as by a tablet
# gone out of reach or a page closed), a new one every half second (a page's EventSource tries
# again every few seconds); `storm` does the same twenty times a second: not a browser that
# vanished but one that hammers the console, a stress case beside the bound.
BROWSERS = ("reading", "slow", "vanishing", "storm")
CASES: dict[str, str | None] = {
    "no console": None,
    "console attached": "",
    "a browser reading": "reading",
    "three slow browsers": "slow",
    "browsers that vanish": "vanishing",
    "a browser reconnecting 20 times a second": "storm",
}
# The cases the bound (within 5 %) is about.
BOUND = ("console attached", "a browser reading", "three slow browsers", "browsers that vanish")
BOUND_RATIO = 1.05
# Seconds between a browser's start and the run (and as long before a run without one).
SETTLE = 0.3


def _connect(port: int, receive_buffer: int | None = None) -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    if receive_buffer is not None:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, receive_buffer)
    sock.connect(("127.0.0.1", port))
    sock.sendall(b"GET /events HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n")
    return sock


def browse(kind: str, port: int) -> None:
    """Behave as a browser of `kind` until killed (first saying so on stdout)."""
    if kind == "reading":
        answer = urllib.request.urlopen(f"http://127.0.0.1:{port}/events", timeout=60)
        print("ready", flush=True)
        while answer.readline():
            pass
    elif kind == "slow":
        socks = [_connect(port, receive_buffer=1024) for _ in range(3)]
        print("ready", flush=True)
        time.sleep(3600)
        del socks
    else:
        print("ready", flush=True)
        while True:
            sock = _connect(port)
            with contextlib.suppress(OSError):
                sock.recv(4096)
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
            sock.close()  # a reset, as from a tablet gone out of reach
            time.sleep(0.5 if kind == "vanishing" else 0.05)


@contextlib.contextmanager
def browser(kind: str, port: int) -> Iterator[None]:
    if not kind:
        yield
        return
    process = subprocess.Popen(
        [sys.executable, __file__, "--browser", kind, "--port", str(port)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert process.stdout is not None and process.stdout.readline().strip() == "ready"
        yield
    finally:
        process.kill()
        process.wait()


def thread_cpu(native_id: int) -> float | None:
    """The CPU time so far of this process's thread `native_id`, in seconds (None where the
    system does not say: Linux's schedstat gives it to the nanosecond)."""
    try:
        with open(f"/proc/self/task/{native_id}/schedstat", encoding="ascii") as file:
            return int(file.read().split()[0]) / 1e9
    except (OSError, ValueError, IndexError):
        return None


def one_run(path: Path, kind: str | None) -> tuple[float, float, float | None]:
    """The wall time and the CPU time (of this process: the executor and the console's server)
    of one run, in seconds, with the console and browser of the case (None: no console), and
    the CPU time of the console's server thread alone (None: no console, or not known)."""
    checked = check_program(path)
    options = RunOptions(platform="dummy")
    listeners: list[TraceListener] = []
    server: ConsoleServer | None = None
    if kind is not None:
        state = ConsoleState()
        control = ConsoleControl(state, checked.model, wait=False)
        server = serve(state, control, Access(Address("127.0.0.1", 0), None))
        options.control = control
        listeners.extend(state.listeners())
    thread = server.thread_id if server is not None else None
    try:
        with browser(kind, server.port) if kind and server is not None else contextlib.nullcontext():
            time.sleep(SETTLE)  # in every case: what the browser's start stirred up settles
            before = thread_cpu(thread) if thread is not None else None
            started, cpu = time.perf_counter(), time.process_time()
            outcome = run_program(path, options, list(listeners), checked=checked)
            wall, cpu = time.perf_counter() - started, time.process_time() - cpu
            after = thread_cpu(thread) if thread is not None else None
    finally:
        if server is not None:
            server.close()
    assert outcome.ok, outcome.diagnostics
    return wall, cpu, None if before is None or after is None else after - before


def work_apart(path: Path, rounds: int) -> tuple[float, float, float, int]:
    """The console's own work, measured apart (one thread, so the machine's load touches each
    alike): (µs per record of the console's listener, µs per record of the run itself, ms per
    view of the page, records), each the best of `rounds`."""
    checked = check_program(path)
    listener, run, view, records = float("inf"), float("inf"), float("inf"), 1
    for _ in range(rounds):
        kept: list[object] = []
        run_program(path, RunOptions(platform="dummy"), [kept.append], checked=checked)
        records = len(kept)
        started = time.process_time()
        run_program(path, RunOptions(platform="dummy"), [], checked=checked)
        run = min(run, (time.process_time() - started) / records * 1e6)
        # The listeners over the same records (the run's other work left out), told by a trace.
        state = ConsoleState()
        control = ConsoleControl(state, checked.model, wait=False)
        options = RunOptions(platform="dummy", control=control)
        run_program(path, options, state.listeners(), checked=checked)  # attached: the view reads its end
        bare, told = Trace(None, []), Trace(None, ConsoleState().listeners())
        started = time.process_time()
        for record in kept:
            bare.emit(record)  # type: ignore[arg-type]
        alone = time.process_time() - started
        started = time.process_time()
        for record in kept:
            told.emit(record)  # type: ignore[arg-type]
        listener = min(listener, max(0.0, time.process_time() - started - alone) / records * 1e6)
        started = time.process_time()
        for _ in range(20):
            state.view()
        view = min(view, (time.process_time() - started) / 20 * 1e3)
    return listener, run, view, records


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=4000)
    parser.add_argument("--rounds", type=int, default=25)
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--browser", choices=BROWSERS, help=argparse.SUPPRESS)
    parser.add_argument("--port", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    # The machine's cores (not this process's: a browser inherits the run's one core).
    cores = list(range(os.cpu_count() or 1)) if hasattr(os, "sched_setaffinity") else []
    if args.browser is not None:
        if len(cores) > 1:
            os.sched_setaffinity(0, cores[1:])  # the browsers on other cores, as on a tablet
        browse(args.browser, args.port)
        return
    if len(cores) > 1:
        # The run and the console's thread (started later: it inherits this) share one core: the
        # console's work comes out of the run's own time, as on a robot's busy computer.
        os.sched_setaffinity(0, cores[:1])
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "steps.gpp"
        path.write_text(PROGRAM % args.steps, encoding="utf-8")
        one_run(path, None)  # warm: imports, caches
        shares = work_apart(path, args.rounds)
        times: dict[str, list[tuple[float, float, float | None]]] = {name: [] for name in CASES}
        names = list(CASES)
        for round_ in range(args.rounds):
            # Each round runs every case once, starting one case later than the round before:
            # no case always follows the same one (the machine's state after a case differs).
            for name in names[round_ % len(names) :] + names[: round_ % len(names)]:
                times[name].append(one_run(path, CASES[name]))
    table(args.steps, args.rounds, times)
    listener, run, view, records = shares
    print()
    print(
        f"The console's work apart: its listeners take {listener:.2f} µs a record of the run's {records:,}, "
        f"against {run:.1f} µs a record for the run itself ({listener / run * 100:.1f} %); a view of the page "
        f"takes {view:.2f} ms, made only while a browser looks (at most {PUSHES_PER_SECOND} a second) or when "
        "one asks."
    )


def quartiles(values: list[float]) -> tuple[float, float, float]:
    ordered = sorted(values)
    q1, median, q3 = statistics.quantiles(ordered, n=4) if len(ordered) > 1 else (ordered[0],) * 3
    return q1, median, q3


def table(steps: int, rounds: int, times: dict[str, list[tuple[float, float, float | None]]]) -> None:
    """The cases' wall and CPU times, each as the median over the rounds of its ratio to the run
    without a console of the same round (a pair run one after the other: the machine's load
    changes slowly), with the quartiles of those ratios; each case's median wall time; and the
    CPU time of the console's own thread (its server: what it adds to the process, measured
    apart from the machine's noise), as a share of the run's wall time."""
    base = times["no console"]
    print(
        f"A run of {steps} loop turns on the dummy platform, {rounds} rounds. Ratios to the run without a "
        "console in the same round: the median over the rounds, with the quartiles (the middle half of the "
        "rounds lies between them); CPU: of the run's process (the executor and the console's server; the "
        "browsers are processes of their own); the console's thread: the CPU time of its server during the "
        "run, as a share of the run's wall time (median)."
    )
    print()
    print("| case | wall, median | wall ratio | quartiles | CPU ratio | quartiles | the console's thread |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    worst: list[tuple[float, str]] = []
    for name, measured in times.items():
        wall = [w / b for (w, _, _), (b, _, _) in zip(measured, base, strict=True)]
        cpu = [c / b for (_, c, _), (_, b, _) in zip(measured, base, strict=True)]
        w1, wm, w3 = quartiles(wall)
        c1, cm, c3 = quartiles(cpu)
        median = statistics.median(w for w, _, _ in measured)
        shares = [t / w for w, _, t in measured if t is not None]
        thread = f"{statistics.median(shares) * 100:.1f} %" if shares else "-"
        print(f"| {name} | {median:.3f} s | {wm:.3f} | {w1:.3f}-{w3:.3f} | {cm:.3f} | {c1:.3f}-{c3:.3f} | {thread} |")
        if name in BOUND:
            worst.append((wm, name))
    ratio, name = max(worst)
    print()
    verdict = "within" if ratio <= BOUND_RATIO else "NOT within"
    print(
        f"Worst of the cases the bound is about: {name}, wall time {(ratio - 1) * 100:+.1f} % ({verdict} 5 %); "
        "the reconnection storm is a stress case beside it."
    )


if __name__ == "__main__":
    main()
