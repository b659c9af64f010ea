"""The platform life cycle: platforms create themselves from a typed configuration and validate
their own options; the registry chooses a platform from a program's directives; problems found
when a platform attaches are diagnostics at the mapping; a run ends by waiting, bounded, for the
platform to acknowledge the cancellation of what still runs."""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from gpp.check import check_text
from gpp.platform import choose_platform, platform_class
from gpp.platform.base import Activity, Platform, PlatformConfig, PlatformError, parse_options
from gpp.platform.dummy import DummyOptions, DummyPlatform
from gpp.platform.sim import SimPlatform
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.contract import program_interface
from gpp.runtime.executor import Executor, RunStatus
from gpp.runtime.trace import Recording, Trace
from gpp.syntax.directives import directives
from tests.support.cli import Result, run

ROOT = Path(__file__).resolve().parents[2]


# ---------------------------------------------------------------- options


@dataclass(frozen=True)
class ToyOptions:
    speed: float = field(default=1.0, metadata={"help": "how fast"})
    laps: int | None = None
    log: Path | None = None
    loud: bool = False
    name: str = "toy"


def test_options_from_text_are_converted_to_their_declared_types() -> None:
    given = {"speed": "2.5", "laps": "3", "log": "out.txt", "loud": "yes", "name": "x"}
    assert parse_options(ToyOptions, given, "toy") == ToyOptions(2.5, 3, Path("out.txt"), True, "x")
    assert parse_options(ToyOptions, {"speed": 2, "loud": False}, "toy") == ToyOptions(speed=2.0)
    assert parse_options(ToyOptions, {}, "toy") == ToyOptions()


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"sped": "2"}, "platform `toy` has no option `sped`; did you mean `speed`? (its options: laps, log, loud,"),
        ({"zzz": "red"}, "platform `toy` has no option `zzz` (its options: laps, log, loud, name, speed)"),
        ({"laps": "three"}, "option `laps` of platform `toy` must be a whole number, not 'three'"),
        ({"laps": 2.5}, "option `laps` of platform `toy` must be a whole number, not 2.5"),
        ({"speed": "fast"}, "option `speed` of platform `toy` must be a number, not 'fast'"),
        ({"loud": "maybe"}, "option `loud` of platform `toy` must be true or false, not 'maybe'"),
        ({"log": ""}, "option `log` of platform `toy` must be a file path, not ''"),
    ],
)
def test_a_bad_option_is_an_error_that_says_what_fits(given: Mapping[str, str], message: str) -> None:
    with pytest.raises(PlatformError) as caught:
        parse_options(ToyOptions, given, "toy")
    assert message in str(caught.value)


def test_a_platform_without_options_says_so() -> None:
    with pytest.raises(PlatformError, match=r"platform `platform` has no option `x` \(platform `platform` takes no"):
        Platform.create(PlatformConfig(Path("p.gpp"), options={"x": "1"}))


def test_each_platform_declares_its_own_options() -> None:
    program = ROOT / "examples" / "blocksworld.gpp"
    with pytest.raises(PlatformError, match="platform `dummy` has no option `world`"):
        DummyPlatform.create(PlatformConfig(program, {}, {"world": "rescue"}))
    with pytest.raises(PlatformError, match="platform `sim` has no option `random`"):
        SimPlatform.create(PlatformConfig(program, {}, {"random": "true"}))
    dummy = DummyPlatform.create(PlatformConfig(program, {}, {"random": "true", "seed": "7"}))
    assert dummy.random_mode and dummy.rng.random() == DummyPlatform(None, 7).rng.random()
    assert DummyPlatform.Options is DummyOptions


def test_the_dummy_reads_its_scenario_directive_relative_to_the_program(tmp_path: Path) -> None:
    (tmp_path / "s.toml").write_text('[[action]]\nmatch = "go"\noutcome = "fail"\n', encoding="utf-8")
    program = tmp_path / "p.gpp"
    dummy = DummyPlatform.create(PlatformConfig(program, {"scenario": "s.toml"}))
    assert [r.pattern for r in dummy.scenario.actions] == ["go"]
    with pytest.raises(PlatformError, match="cannot read scenario"):
        DummyPlatform.create(PlatformConfig(program, {"scenario": "missing.toml"}))


# ---------------------------------------------------------------- registry and directives


def test_directives_are_one_word_comments_at_the_top() -> None:
    text = "// world: rescue\n// A comment: with words\n//scenario:s.toml\n\nprocedure main() { }\n// late: no\n"
    assert directives(text) == {"world": "rescue", "scenario": "s.toml"}


def test_the_platform_is_chosen_by_asking_the_platforms() -> None:
    assert choose_platform({"world": "rescue"}) == "sim"  # SimPlatform.selected_by
    assert choose_platform({"scenario": "s.toml"}) == "dummy"
    assert choose_platform({}) == "dummy"
    assert platform_class("sim").selected_by == "world"


def test_an_unknown_platform_has_a_did_you_mean() -> None:
    with pytest.raises(
        PlatformError, match=r"unknown platform `simm`; did you mean `sim`\? \(available: dummy, ros2, sim"
    ):
        platform_class("simm")


# ---------------------------------------------------------------- the CLI


def gpp(*args: str, cwd: Path = ROOT) -> Result:
    return run(*args, cwd=cwd)


def test_run_honours_the_world_directive_without_platform() -> None:
    result = gpp("run", "-q", "examples/rescue.gpp")
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.startswith("examples/rescue.gpp on sim: finished")


def test_platform_opt_pairs_reach_the_platform() -> None:
    result = gpp("run", "-q", "examples/rescue.gpp", "-p", "sim", "-o", "world=rescue", "-o", "seed=2")
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--world", "rescue"], "--world is an option of platform sim, not of `dummy`"),
        (["-o", "wrold=rescue", "-p", "sim"], "platform `sim` has no option `wrold`; did you mean `world`?"),
        (["-o", "seed=abc"], "option `seed` of platform `dummy` must be a whole number, not 'abc'"),
        (["-o", "seed"], "--platform-opt takes KEY=VALUE, not 'seed'"),
        (["-o", "seed=1", "--seed", "2"], "platform option `seed` is given twice"),
        (["--seed", "2"], "option `seed` of platform `dummy` applies only with `random`"),
    ],
)
def test_options_that_do_not_apply_are_usage_errors(args: list[str], message: str) -> None:
    result = gpp("run", "-q", "examples/durative.gpp", *args)
    assert result.returncode == 2, result.stdout + result.stderr
    assert message in result.stderr
    assert "Traceback" not in result.stderr


def test_a_program_that_does_not_fit_is_reported_at_its_mapping(tmp_path: Path) -> None:
    program = tmp_path / "unfit.gpp"
    program.write_text(
        "// world: blocksworld\nsymbol domain block = {a}\n"
        'action put(block b) {\nmapping:\n    "/stak" { block = b }\n}\n'
        "procedure main() { put(a); }\n",
        encoding="utf-8",
    )
    result = gpp("run", "-q", str(program), cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    out = result.stdout + result.stderr
    assert 'error[R0007]: action `put` is mapped to "/stak", which the sim does not serve' in out
    assert "unfit.gpp:5:5" in out
    assert "did you mean `/stack`?" in out


# ---------------------------------------------------------------- closing


class Deaf(DummyPlatform):
    """A dummy that ignores preemption: it never acknowledges a cancellation."""

    def preempt(self, activity: Activity) -> None:
        pass


PROGRAM = """
action drive() { duration: [100, 100] }
number fluent n() { initially: () = 0; }
procedure main() { start(drive()); n() = 1; test(false); }
"""


def test_a_cancellation_that_is_never_acknowledged_is_recorded_after_a_bounded_wait() -> None:
    check = check_text(PROGRAM, lint=False)
    assert not check.errors, [d.message for d in check.diagnostics]
    program = CompiledProgram(check.model)
    platform = Deaf()
    trace = Recording()
    executor = Executor(program, platform, Trace(listeners=[trace]), time_limit=10)
    executor.cancel_grace = 0.2
    assert platform.attach(program_interface(program)) == []
    started = time.perf_counter()
    result = executor.run()
    assert time.perf_counter() - started < 5
    assert result.status is RunStatus.TIMEOUT
    events = [(r.EVENT, getattr(r, "message", "")) for r in trace.records]
    assert events[-3:] == [
        ("cancel", ""),
        ("error", "platform `dummy` did not acknowledge the cancellation of `drive()` within 0.2 s"),
        ("finish", ""),
    ]


class OldPort(DummyPlatform):
    """A platform plugin written before `wait` took the run's wall-clock bound."""

    def wait(self, deadline: float | None) -> bool:  # type: ignore[override]
        self.waited = getattr(self, "waited", 0) + 1
        return super().wait(deadline)


def test_a_platform_whose_wait_takes_no_wall_clock_bound_still_runs_under_a_timeout() -> None:
    check = check_text(PROGRAM, lint=False)
    program = CompiledProgram(check.model)
    platform = OldPort()
    trace = Recording()
    executor = Executor(program, platform, Trace(listeners=[trace]), timeout=30)
    assert platform.attach(program_interface(program)) == []
    result = executor.run()
    # The program waits for `drive()` through the plugin's own `wait` (no TypeError), then
    # nothing can make `test(false)` hold: the run stops blocked.
    assert platform.waited >= 1
    assert result.status is RunStatus.BLOCKED, [r.EVENT for r in trace.records]
