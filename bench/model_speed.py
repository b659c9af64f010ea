"""How fast the code model and type check are, against another revision, in one process.

    python bench/model_speed.py [--baseline REV (default HEAD)] [--lines 1000 10000] [--runs 15]

Copies gpp/model of the baseline revision (`git show REV:gpp/model/...`) into a temporary
package, so that both builders run in this process on the same parsed files, interleaved
(baseline, this tree, baseline, ...): the machine's load touches both alike. Prints the best
and the median CPU time of each, the ratio of the best times and the median of the ratios of
each pair of runs (one of each, one after the other: the steadier figure while the load of the
machine changes), and checks that both give the same model and diagnostics
(tests/support/model_fingerprint.py describes them completely). Times vary with the load of the
machine; the ratios are what to read.
"""

from __future__ import annotations

import argparse
import gc
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from genprog import generate_program  # noqa: E402
from revision import modules_at, python_files_at  # noqa: E402

from gpp.base.perf import with_deep_stack  # noqa: E402
from gpp.model.build import build_model  # noqa: E402
from gpp.syntax.loader import LoadResult, load  # noqa: E402
from tests.support.model_fingerprint import describe  # noqa: E402

BASELINE_PACKAGE = "gpp_model_baseline"
# The oldest revision whose gpp/model runs on this tree's other packages: the diagnostic
# messages moved into gpp/codes there (older models call the diagnostics API of their time).
OLDEST = "cfdeb36"


def baseline_builder(revision: str, into: Path) -> ModuleType:
    """gpp.model.build of `revision`, as the module `gpp_model_baseline.build` (its imports of
    gpp.model.* rewritten to the copy; everything else is this tree's)."""
    return modules_at(revision, python_files_at(revision, "gpp/model"), into, BASELINE_PACKAGE)["build"]


def timed(fn: Callable[[], object]) -> float:
    """The CPU time of `fn` on its thread: on a busy machine, the time the thread waited for a
    core is not counted."""
    gc.collect()

    def run() -> float:
        t0 = time.thread_time()
        fn()
        return time.thread_time() - t0

    return with_deep_stack(run)


def compare(loaded: LoadResult, old_build: Callable[..., object]) -> bool:
    old_model, old_diagnostics = old_build(loaded.files)  # type: ignore[misc]
    new_model, new_diagnostics = build_model(loaded.files)
    return describe(old_model, old_diagnostics) == describe(new_model, new_diagnostics)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--baseline",
        default="HEAD",
        help=f"git revision to compare with (default: HEAD, i.e. what the uncommitted change does; {OLDEST} or later)",
    )
    parser.add_argument("--lines", type=int, nargs="+", default=[1000, 10000])
    parser.add_argument("--runs", type=int, default=15)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        try:
            old = baseline_builder(args.baseline, Path(tmp))
        except (OSError, subprocess.CalledProcessError) as e:
            print(f"model_speed: cannot read gpp/model of revision {args.baseline} with git: {e}", file=sys.stderr)
            return 2
        except Exception as e:  # an older model imports modules or names this tree no longer has
            print(
                f"model_speed: gpp/model of revision {args.baseline} does not load beside this tree "
                f"({type(e).__name__}: {e}); compare with {OLDEST} or a later revision",
                file=sys.stderr,
            )
            return 2
        print(f"load average: {os.getloadavg()[0]:.2f}; best / median of {args.runs} runs, interleaved")
        print(f"{'lines':>7} {'baseline ms':>16} {'this tree ms':>16} {'speed-up':>9} {'per pair':>9}  same model")
        for lines in args.lines:
            path = ROOT / "bench" / f"model-speed-{lines}.gpp"
            loaded = load([path], {path.resolve(): generate_program(lines)})
            same = with_deep_stack(partial(compare, loaded, old.build_model))
            before: list[float] = []
            after: list[float] = []
            for _ in range(args.runs):
                before.append(timed(partial(old.build_model, loaded.files)))
                after.append(timed(partial(build_model, loaded.files)))
            b, a = min(before), min(after)
            per_pair = statistics.median(x / y for x, y in zip(before, after, strict=True))
            shown_b = f"{b * 1000:.1f} / {statistics.median(before) * 1000:.1f}"
            shown_a = f"{a * 1000:.1f} / {statistics.median(after) * 1000:.1f}"
            print(f"{lines:>7} {shown_b:>16} {shown_a:>16} {b / a:>8.2f}x {per_pair:>8.2f}x  {'yes' if same else 'NO'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
