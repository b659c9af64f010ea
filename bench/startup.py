"""Start-up time of `gpp check` and `gpp run` on a small program, as a whole process.

Run: .venv/bin/python bench/startup.py [--repeat N] [--markdown]

Each command runs N times as a fresh process (`python -m gpp ...` with this interpreter); the
minimum wall time counts (the least disturbed by other work on the machine). Byte code is
written to a private cache first, as an installed gpp has it, so source compilation is not
counted. Printed: the time of `python -c pass` (the interpreter's own start-up), of each gpp
command, the difference (what gpp itself costs), the ratio to `python -c pass`, and the
target where there is one (`gpp check` <= 0.15 s, `gpp run` on the dummy <= 0.2 s).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SMALL = ROOT / "examples" / "blocks_planning.gpp"
# (name, arguments, target in seconds or None)
COMMANDS: list[tuple[str, list[str], float | None]] = [
    ("python -c pass", ["-c", "pass"], None),
    ("gpp --version", ["-m", "gpp", "--version"], None),
    ("gpp check (small file)", ["-m", "gpp", "check", str(SMALL)], 0.15),
    ("gpp check --no-lint", ["-m", "gpp", "check", "--no-lint", str(SMALL)], 0.15),
    ("gpp explain E0101", ["-m", "gpp", "explain", "E0101"], None),
    ("gpp run -p dummy (small program)", ["-m", "gpp", "run", "-q", "-p", "dummy", str(SMALL)], 0.2),
]


def best_of(args: list[str], repeat: int, env: dict[str, str]) -> float:
    best = float("inf")
    for _ in range(repeat):
        started = time.perf_counter()
        subprocess.run([sys.executable, *args], env=env, cwd=ROOT, stdout=subprocess.DEVNULL, check=False)
        best = min(best, time.perf_counter() - started)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15, help="runs per command (the minimum counts)")
    parser.add_argument("--markdown", action="store_true", help="(the table is Markdown anyway)")
    options = parser.parse_args()
    with tempfile.TemporaryDirectory() as cache:
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        env["PYTHONPYCACHEPREFIX"] = cache
        for _, args, _ in COMMANDS:  # fill the byte-code cache
            subprocess.run([sys.executable, *args], env=env, cwd=ROOT, stdout=subprocess.DEVNULL, check=False)
        times = [(name, best_of(args, options.repeat, env), target) for name, args, target in COMMANDS]
    baseline = times[0][1]
    print(f"| command | whole process (min of {options.repeat}) | minus `python -c pass` | ratio | target |")
    print("|---|---:|---:|---:|---|")
    for name, seconds, target in times:
        met = "" if target is None else f"<= {target * 1000:.0f} ms: {'met' if seconds <= target else 'MISSED'}"
        print(
            f"| {name} | {seconds * 1000:.0f} ms | {(seconds - baseline) * 1000:+.0f} ms "
            f"| {seconds / baseline:.1f}x | {met} |"
        )


if __name__ == "__main__":
    main()
