"""Soak: does a long run stay the same size and speed? 1,000,000 steps of a one-action loop on
the dummy platform, without a trace file and with one (split into 10 MB parts).

Run: .venv/bin/python bench/soak.py [--steps N] [--keep-trace] [--markdown]

A step is a step of the executor (`steps` in the summary of `gpp run`): each round of the loop
is two, the action's start and its end. Each run is a fresh process, so that its peak memory is
its own: memory is the peak resident set size (`ru_maxrss`) of that process, read when the run
reaches 10k, 100k and 1M steps (a peak: it never goes down, and stays flat when nothing grows).
Time per step is CPU time of the process (time.process_time: user and system, so that other
programs on the machine count less) over the first and the last 10% of the steps.

Targets (issue 25): memory at 1M steps within 10 MB of memory at 10k steps; time per step in
the last 10% within 1.2x of the first 10%.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from gpp.run.runner import RunOptions, run_program  # noqa: E402
from gpp.runtime.events import EndEvent, TraceEvent  # noqa: E402
from gpp.runtime.trace import TraceSplit, trace_parts  # noqa: E402

# Rounds of `tick()` until `done()` reaches `steps`: two executor steps a round.
PROGRAM = """\
number fluent done() {
initially:
    () = 0;
}

action tick() {
effect:
    done() = done() + 1;
}

procedure main(number rounds) {
    while (done() < rounds)
        tick();
}
"""
STEPS_PER_ROUND = 2
CHECKPOINTS = (10_000, 100_000, 1_000_000)
PART_SIZE = 10_000_000
MEMORY_TARGET_MB = 10.0
TIME_TARGET = 1.2


class Probe:
    """A trace listener that notes peak memory at the checkpoints and the time at the 10%
    marks, counting rounds by their `end` records."""

    def __init__(self, steps: int) -> None:
        self.rounds = steps // STEPS_PER_ROUND
        self.memory: dict[int, float] = {}
        # Rounds ended when the clock is read: the first (the program is compiled and running),
        # the 10% marks, the last.
        tenth = self.rounds // 10
        self.marks = {1, 1 + tenth, self.rounds - tenth, self.rounds}
        self.times: dict[int, float] = {}
        self.ended = 0

    def __call__(self, event: TraceEvent) -> None:
        if not isinstance(event, EndEvent):
            return
        self.ended += 1
        steps = self.ended * STEPS_PER_ROUND
        if steps in CHECKPOINTS:
            self.memory[steps] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KB on Linux
        if self.ended in self.marks:
            self.times[self.ended] = time.process_time()


def one_run(steps: int, trace: Path | None) -> dict[str, object]:
    """Run the loop for `steps` steps in this process; what the probe saw."""
    with tempfile.TemporaryDirectory() as folder:
        program = Path(folder) / "soak.gpp"
        program.write_text(PROGRAM, encoding="utf-8")
        probe = Probe(steps)
        options = RunOptions(
            args={"rounds": steps // STEPS_PER_ROUND},
            trace=trace,
            trace_split=TraceSplit(max_bytes=PART_SIZE) if trace is not None else None,
        )
        outcome = run_program(program, options, listeners=[probe])
    assert outcome.ok and outcome.result is not None, outcome.diagnostics
    rounds = probe.rounds
    tenth = rounds // 10
    first = (probe.times[1 + tenth] - probe.times[1]) / (tenth * STEPS_PER_ROUND)
    last = (probe.times[rounds] - probe.times[rounds - tenth]) / (tenth * STEPS_PER_ROUND)
    parts = trace_parts(trace) if trace is not None else []
    return {
        "steps": outcome.result.steps,
        "memory": {str(k): v for k, v in probe.memory.items()},
        "first_us": first * 1e6,
        "last_us": last * 1e6,
        "parts": len(parts),
        "bytes": sum(p.stat().st_size for p in parts),
    }


def in_process(steps: int, trace: Path | None) -> dict[str, object]:
    """`one_run` in a fresh Python process (its peak memory is its own)."""
    command = [sys.executable, __file__, "--one", "--steps", str(steps)]
    if trace is not None:
        command += ["--trace", str(trace)]
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"the soak run failed:\n{done.stderr}")
    result: dict[str, object] = json.loads(done.stdout)
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1_000_000, help="executor steps per run (default 1,000,000)")
    parser.add_argument("--keep-trace", action="store_true", help="keep the trace parts (in a temporary folder)")
    parser.add_argument("--markdown", action="store_true", help="print the table as Markdown (docs/performance.md)")
    parser.add_argument("--one", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--trace", type=Path, help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.one:
        print(json.dumps(one_run(options.steps, options.trace)))
        return
    checkpoints = [c for c in CHECKPOINTS if c <= options.steps]
    md = options.markdown
    if md:
        print(f"{options.steps:,} steps of a one-action loop on the dummy platform; memory is the peak resident set")
        print("size of the run's own process, time per step its CPU time over the first and the last 10% of the steps:")
        print()
        steps = " | ".join(f"{c // 10**6}M steps" if c % 10**6 == 0 else f"{c // 1000}k steps" for c in checkpoints)
        print(f"| run | {steps} | growth | first 10% | last 10% | ratio |")
        print("|---|" + "---:|" * (len(checkpoints) + 4))
    else:
        print(f"soak: {options.steps:,} steps of a one-action loop on the dummy platform")
        print("memory: peak resident set size (ru_maxrss) of the run's own process, MB")
        header = "".join(f"{f'{c // 1000}k steps':>12}" for c in checkpoints)
        print(f"{'run':<22}{header}{'growth':>10}{'first 10%':>12}{'last 10%':>11}{'ratio':>7}  trace")
    folder = Path(tempfile.mkdtemp(prefix="gpp-soak-"))
    ok = True
    for name, trace in (("no trace", None), ("--trace (10 MB parts)", folder / "soak.jsonl")):
        found = in_process(options.steps, trace)
        memory = found["memory"]
        assert isinstance(memory, dict)
        mb = [memory[str(c)] / 1024 for c in checkpoints]
        growth = mb[-1] - mb[0]
        first, last = float(str(found["first_us"])), float(str(found["last_us"]))
        ratio = last / first
        ok = ok and growth <= MEMORY_TARGET_MB and ratio <= TIME_TARGET
        written = f"{found['parts']} parts, {int(str(found['bytes'])) / 1e6:,.0f} MB" if trace else "-"
        if md:
            label = "no trace file" if trace is None else f"`--trace` split into 10 MB parts ({written})"
            cells = " | ".join(f"{m:.1f} MB" for m in mb)
            print(f"| {label} | {cells} | {growth:+.1f} MB | {first:.1f} µs | {last:.1f} µs | {ratio:.2f} |")
        else:
            cells = "".join(f"{m:>12.1f}" for m in mb)
            print(f"{name:<22}{cells}{growth:>+10.1f}{first:>10.1f}us{last:>9.1f}us{ratio:>7.2f}  {written}")
        if trace is not None and not options.keep_trace:
            for part in trace_parts(trace):
                part.unlink()
    if options.keep_trace:
        print(f"trace parts kept in {folder}")
    else:
        folder.rmdir()
    if md:
        print()
    print(
        f"{'Targets' if md else 'targets'}: growth from {checkpoints[0] // 1000}k to {checkpoints[-1] // 1000}k steps "
        f"<= {MEMORY_TARGET_MB:g} MB, "
        f"last/first 10% time per step <= {TIME_TARGET:g}: {'met' if ok else 'NOT met'}"
    )


if __name__ == "__main__":
    main()
