"""Speed of the sim platform: physics steps per second and how much faster than real time the
example agents run.

Run: .venv/bin/python bench/sim.py [--repeat N] [--markdown]

For each sim example it runs the whole program (check, plan, execute with physics) and
prints the physics steps, steps per second while stepping, sim time, wall time (the whole
run_program call, best of N) and the ratio sim time / wall time. Then it times the raw
scenes: the workbench (iterations 30, a tower of three blocks and the gripper) and the map
(the robot driving, iterations 10).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from gpp.platform.sim import SimPlatform, World
from gpp.platform.sim.platform import run_action
from gpp.run.runner import RunOptions, run_program

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ["blocksworld.gpp", "blocksworld_faults.gpp", "rescue.gpp"]


def run_example(name: str, repeat: int) -> tuple[float, float, int, float, bool]:
    """Best wall time of `repeat` runs, with the sim time, steps and stepping speed."""
    best = float("inf")
    sim_time, steps, rate, ok = 0.0, 0, 0.0, True
    for _ in range(repeat):
        started = time.perf_counter()
        outcome = run_program(ROOT / "examples" / name, RunOptions(platform="sim"))
        wall = time.perf_counter() - started
        stats = SimPlatform.last_run
        assert stats is not None
        ok = ok and outcome.ok
        if wall < best:
            best, sim_time, steps, rate = wall, stats.sim_time, stats.steps, stats.steps_per_second
    return best, sim_time, steps, rate, ok


def raw_scene(world: str, moves: list[tuple[str, dict[str, str]]], rounds: int) -> float:
    """Steps per second while the sim performs `moves` (mapped name, arguments) `rounds` times."""
    sim = SimPlatform(World.load(world))
    for _ in range(rounds):
        for mapped, args in moves:
            update, _ = run_action(sim, mapped, **args)
            assert update.status.value == "final", update.reason
    return sim.stats().steps_per_second


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per example (the best counts)")
    parser.add_argument("--markdown", action="store_true", help="print the tables as Markdown (docs/performance.md)")
    options = parser.parse_args()
    if options.markdown:
        print(f"Examples (best wall time of {options.repeat} runs):")
        print()
        print("| example | physics steps | steps/s | sim time | wall time | × real time | postcond |")
        print("|---|---:|---:|---:|---:|---:|---|")
    else:
        print(f"{'example':<24} {'steps':>6} {'steps/s':>9} {'sim s':>7} {'wall s':>7} {'sim/wall':>9}  postcond")
    for name in EXAMPLES:
        wall, sim_time, steps, rate, ok = run_example(name, options.repeat)
        holds = "holds" if ok else "FAILS"
        if options.markdown:
            print(
                f"| {name.removesuffix('.gpp')} | {steps:,} | {rate:,.0f} | {sim_time:.1f} s | {wall:.3f} s "
                f"| {sim_time / wall:.0f}× | {holds} |"
            )
        else:
            times = f"{sim_time:>7.1f} {wall:>7.3f} {sim_time / wall:>8.0f}x"
            print(f"{name:<24} {steps:>6} {rate:>9,.0f} {times}  {holds}")
    print()
    print("Raw scenes (dt = 1/60 s, stepping only):" if options.markdown else "raw scenes (dt = 1/60 s, stepping only)")
    shuffle = [("/stack", {"block": "a", "location": "t3"}), ("/stack", {"block": "a", "location": "b"})]
    bench_rate = raw_scene("blocksworld", [("/navigate_to_frame", {"frame": "table"}), *shuffle * 5], 1)
    if options.markdown:
        print()
        print("| scene | steps/s | × real time |")
        print("|---|---:|---:|")
        print(f"| workbench, 10 stacks, iterations 30 | {bench_rate:,.0f} | {bench_rate / 60:.0f}× |")
    else:
        rate = f"{bench_rate:>9,.0f} steps/s = {bench_rate / 60:>5.0f}x real time"
        print(f"  workbench, 10 stacks, iterations 30: {rate}")
    rooms = [("/navigate_to_frame", {"frame": room}) for room in ("room3", "room4", "home")]
    nav_rate = raw_scene("rescue", rooms, 1)
    if options.markdown:
        print(f"| map, 3 drives, iterations 10 | {nav_rate:,.0f} | {nav_rate / 60:.0f}× |")
    else:
        print(f"  map, 3 drives, iterations 10:        {nav_rate:>9,.0f} steps/s = {nav_rate / 60:>5.0f}x real time")


if __name__ == "__main__":
    main()
