"""What the operator console costs a run: the wall time of one run without a console, with a
console attached, with a browser reading its live stream, with a slow browser (one that never
reads: its connection's buffers fill), and with browsers that vanish (connect, then drop the
connection mid-stream), each as a ratio to the run without. The issue's bound: within 5 %.

The run is the executor at full speed: a program of many short steps on the dummy platform
(virtual time: no step waits for a clock), so the console's share of each step is what shows.
Each browser is a process of its own, as a real one is. The cases take turns, `--rounds` times;
each case's figures are its best time (the least disturbed by the machine's other work) and
its median.

Run: .venv/bin/python bench/console.py [--steps N] [--rounds R] [--markdown]
"""

from __future__ import annotations

import argparse
import contextlib
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
from gpp.console.server import ConsoleServer, serve  # noqa: E402
from gpp.console.state import ConsoleState  # noqa: E402
from gpp.run.runner import RunOptions, run_program  # noqa: E402

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
# `vanishing` connect, read a little and drop the connection (a reset), one after another.
BROWSERS = ("reading", "slow", "vanishing")
CASES: dict[str, str | None] = {
    "no console": None,
    "console attached": "",
    "a browser reading": "reading",
    "three slow browsers": "slow",
    "browsers that vanish": "vanishing",
}


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
            time.sleep(0.05)


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


def one_run(path: Path, kind: str | None) -> tuple[float, float]:
    """The wall time and the CPU time (of this process: the executor and the console's server)
    of one run, in seconds, with the console and browser of the case (None: no console)."""
    checked = check_program(path)
    options = RunOptions(platform="dummy")
    listeners: list[ConsoleState] = []
    server: ConsoleServer | None = None
    if kind is not None:
        state = ConsoleState()
        control = ConsoleControl(state, checked.model, wait=False)
        server = serve(state, control, Access(Address("127.0.0.1", 0), None))
        options.control = control
        listeners.append(state)
    try:
        with browser(kind, server.port) if kind and server is not None else contextlib.nullcontext():
            started, cpu = time.perf_counter(), time.process_time()
            outcome = run_program(path, options, list(listeners), checked=checked)
            took = time.perf_counter() - started, time.process_time() - cpu
    finally:
        if server is not None:
            server.close()
    assert outcome.ok, outcome.diagnostics
    return took


def fold_share(path: Path, rounds: int) -> tuple[float, float, int]:
    """The console's own work, measured apart (one thread, so the machine's load touches both
    alike): (µs per record of folding the run's records into the page's view, µs per record
    of the run itself, records), the best of `rounds`."""
    checked = check_program(path)
    fold, run, records = float("inf"), float("inf"), 1
    for _ in range(rounds):
        state = ConsoleState()
        started = time.process_time()
        run_program(path, RunOptions(platform="dummy"), [state], checked=checked)
        took = time.process_time() - started
        records = len(state._handed)
        started = time.process_time()
        state.view()
        fold = min(fold, (time.process_time() - started) / records * 1e6)
        run = min(run, took / records * 1e6)
    return fold, run, records


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--browser", choices=BROWSERS, help=argparse.SUPPRESS)
    parser.add_argument("--port", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.browser is not None:
        browse(args.browser, args.port)
        return
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "steps.gpp"
        path.write_text(PROGRAM % args.steps, encoding="utf-8")
        one_run(path, None)  # warm: imports, caches
        shares = fold_share(path, args.rounds)
        times: dict[str, list[tuple[float, float]]] = {name: [] for name in CASES}
        for _ in range(args.rounds):
            for name, kind in CASES.items():
                times[name].append(one_run(path, kind))
    walls = {name: [wall for wall, _ in measured] for name, measured in times.items()}
    cpus = {name: [cpu for _, cpu in measured] for name, measured in times.items()}
    print(
        f"A run of {args.steps} loop turns on the dummy platform, {args.rounds} rounds: the best wall time "
        "(the least disturbed by the machine's other work), the median, and the best CPU time of the run's "
        "process (the executor and the console's server; the browsers are processes of their own)."
    )
    print()
    print("| case | wall, best | ratio | wall, median | ratio | CPU, best | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    base = {"wall": min(walls["no console"]), "median": statistics.median(walls["no console"])}
    base["cpu"] = min(cpus["no console"])
    for name in CASES:
        best, median, cpu = min(walls[name]), statistics.median(walls[name]), min(cpus[name])
        print(
            f"| {name} | {best:.3f} s | {best / base['wall']:.3f} | {median:.3f} s | {median / base['median']:.3f} "
            f"| {cpu:.3f} s | {cpu / base['cpu']:.3f} |"
        )
    fold, run, records = shares
    print()
    print(
        f"The console's work apart: folding the run's {records:,} records into the page's view takes "
        f"{fold:.2f} µs a record, against {run:.1f} µs a record for the run itself: {fold / run * 100:.1f} %."
    )
    worst_wall = max(min(walls[name]) / base["wall"] for name in CASES)
    worst_cpu = max(min(cpus[name]) / base["cpu"] for name in CASES)
    print()
    print(
        f"Worst: wall time {(worst_wall - 1) * 100:+.1f} %, CPU time {(worst_cpu - 1) * 100:+.1f} % "
        "(the bound: within 5 %)."
    )


if __name__ == "__main__":
    main()
