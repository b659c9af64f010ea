"""Runs a robot programmer can trust: bounded in time, stopped cleanly by SIGTERM, and no option
or output path silently ignored."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.support import disks
from tests.support.cli import Result, run

ROOT = Path(__file__).resolve().parents[2]
LOOP = "number fluent n() { initially: () = 0; }\nprocedure main() { while (true) n() = n() + 1; }\n"


def gpp(*args: str, cwd: Path = ROOT) -> Result:
    return run(*args, cwd=cwd)


@pytest.mark.parametrize("flag", ["--timeout", "--time-limit"])
@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf"])
@pytest.mark.parametrize("command", ["run", "test"])
def test_a_bound_must_be_positive(command: str, value: str, flag: str) -> None:
    result = gpp(command, "examples/durative.gpp", f"{flag}={value}")
    assert result.returncode == 2, result.stdout + result.stderr
    assert f"{flag} must be a number of seconds greater than 0" in result.stderr


# ---------------------------------------------------------------- the two bounds (SEMANTICS §4)

# A mission of 38 s of platform time, which the dummy platform runs in a moment.
MISSION = (
    "number fluent legs() { initially: () = 0; }\n"
    "action drive() { duration: [19, 19] effect: legs() = legs() + 1; }\n"
    "procedure main() { drive(); drive(); }\n"
    "bool function postcond() = legs() == 2\n"
)


def test_the_test_timeout_is_wall_clock_time_so_a_long_simulated_mission_passes(tmp_path: Path) -> None:
    (tmp_path / "gpp.toml").write_text('[test]\npaths = ["tests"]\ntimeout = 30\n', encoding="utf-8")
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "mission.gpp").write_text(MISSION, encoding="utf-8")
    result = gpp("test", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip().splitlines()[-1] == "1 passed, 0 failed"


def test_the_time_limit_bounds_platform_time_and_r0013_says_which_bound(tmp_path: Path) -> None:
    (tmp_path / "mission.gpp").write_text(MISSION, encoding="utf-8")
    result = gpp("run", "-q", "mission.gpp", "--time-limit", "30", "--timeout", "600", cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "error[R0013]: the run reached its time limit of 30 s of platform time (`--time-limit`)" in result.stdout
    (tmp_path / "gpp.toml").write_text("[test]\ntime_limit = 30\n", encoding="utf-8")
    tested = gpp("test", "mission.gpp", cwd=tmp_path)
    assert tested.returncode == 1, tested.stdout
    assert "time limit of 30 s of platform time" in tested.stdout


# Plans for far longer than any test waits: 7 values per step, 40 steps, every state new.
LONG_PLANNING = """
list[number] fluent picked() { initially: () = list[number] []; }
number function reward() = if (length(picked()) > 0) picked()[length(picked()) - 1] else 0
procedure main() {
    solve(40, reward()) while (true) pick (number v in {1, 2, 3, 4, 5, 6, 7}) push_back(picked(), v);
}
"""


def test_the_timeout_holds_while_the_planner_plans(tmp_path: Path) -> None:
    (tmp_path / "plans.gpp").write_text(LONG_PLANNING, encoding="utf-8")
    result = gpp("run", "-q", "plans.gpp", "--timeout", "1", cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "error[R0013]: the run reached its timeout of 1 s of wall-clock time (`--timeout`" in result.stdout
    assert "planning here" in result.stdout
    assert "plans.gpp on dummy: timeout" in result.stdout


# A drive of several seconds on the sim, paced to the wall clock.
LONG_DRIVE = """// world: rescue
#include "sim/rescue.gpp"
symbol domain room = {room1, room2, room3, room4}
symbol domain frame = room | {home}
symbol domain victim = {v1, v2}
procedure main() { navigate_to_frame(room4); }
"""


def test_the_timeout_holds_while_the_program_waits_on_a_realtime_platform(tmp_path: Path) -> None:
    (tmp_path / "drive.gpp").write_text(LONG_DRIVE, encoding="utf-8")
    result = gpp("run", "-q", "drive.gpp", "--realtime", "--timeout", "1", cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "error[R0013]: the run reached its timeout of 1 s of wall-clock time (`--timeout`" in result.stdout
    assert "waiting here" in result.stdout
    assert "it waits here: it waits for `navigate_to_frame(room4)` to end" in result.stdout
    assert "drive.gpp on sim: timeout" in result.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--trace", "missing/t.jsonl"], "--trace: the folder 'missing' does not exist"),
        (["--trace", "examples"], "--trace: 'examples' is a folder, not a file"),
        (["-p", "sim", "--record", "missing/run.gif"], "option `record` of platform `sim`: the folder 'missing'"),
        (["-p", "sim", "--snapshot", "examples"], "option `snapshot` of platform `sim`: 'examples' is a folder"),
    ],
)
def test_outputs_that_cannot_be_written_are_usage_errors_before_the_run(args: list[str], message: str) -> None:
    result = gpp("run", "-q", "examples/blocksworld.gpp", *args)
    assert result.returncode == 2, result.stdout + result.stderr
    assert message in result.stderr
    assert "finished" not in result.stdout  # nothing ran


def inputs_project(tmp_path: Path) -> dict[str, bytes]:
    """An agent with an include and a scenario (by its directive), and a world file: what a run
    reads, by name, with its bytes."""
    files = {
        "agent.gpp": b'// scenario: events.toml\n#include "lib.gpp"\nprocedure main() { go(); }\n',
        "lib.gpp": b"action go() { }\n",
        "events.toml": b"",
        "other.toml": b"",
        "sub/agent2.gpp": b"procedure main() { }\n",
    }
    for name, data in files.items():
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_bytes(data)
    return files


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--trace", "agent.gpp"], "--trace: 'agent.gpp' is the program; writing there would overwrite it"),
        (["--trace", "./sub/../agent.gpp"], "is the program; writing there would overwrite it"),
        (["--trace", "lib.gpp"], "--trace: 'lib.gpp' is a file the program includes"),
        (["--trace", "events.toml"], "--trace: 'events.toml' is the file of its `// scenario:` line"),
        (
            ["--scenario", "other.toml", "--trace", "other.toml"],
            "--trace: 'other.toml' is the file of option `scenario`",
        ),
        (["-p", "sim", "--record", "lib.gpp"], "option `record`: 'lib.gpp' is a file the program includes"),
    ],
)
def test_a_run_refuses_to_write_over_a_file_it_reads(tmp_path: Path, args: list[str], message: str) -> None:
    files = inputs_project(tmp_path)
    if "--scenario" in args:  # the scenario given as an option instead of the directive
        (tmp_path / "agent.gpp").write_bytes(files["agent.gpp"].split(b"\n", 1)[1])
        files["agent.gpp"] = (tmp_path / "agent.gpp").read_bytes()
    result = gpp("run", "-q", "agent.gpp", *args, cwd=tmp_path)
    assert result.returncode == 2, result.stdout + result.stderr
    assert message in result.stderr
    assert {name: (tmp_path / name).read_bytes() for name in files} == files  # nothing was written


def test_a_trace_may_replace_an_older_trace(tmp_path: Path) -> None:
    inputs_project(tmp_path)
    (tmp_path / "run.jsonl").write_text("old\n", encoding="utf-8")
    result = gpp("run", "-q", "agent.gpp", "--trace", "run.jsonl", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert (tmp_path / "run.jsonl").read_text(encoding="utf-8").startswith("{")


def test_a_trace_that_cannot_be_written_stops_the_run_with_one_line() -> None:
    result = gpp("run", "-q", "examples/durative.gpp", "--trace", "/dev/full")
    assert (result.returncode, result.stderr) == (
        1,
        "error: cannot write the trace '/dev/full': No space left on device\n",
    )


def test_a_disk_full_mid_run_stops_it_and_cancels_its_activities(tmp_path: Path) -> None:
    from gpp.run.runner import RunOptions, run_program
    from gpp.runtime.events import FinishEvent, TraceEvent, UpdateEvent
    from gpp.runtime.trace import TraceWriteError

    program = (
        "number fluent n() { initially: () = 0; }\n"
        "action long() { duration: [100, 100] }\n"
        "procedure main() { start(long()); while (n() < 100000) n() = n() + 1; end(long()); }\n"
    )
    seen: list[TraceEvent] = []
    with disks.full_disk(tmp_path / "disk", {"agent.gpp": program}, free=16 * 1024) as disk:
        with pytest.raises(TraceWriteError, match="No space left on device"):
            run_program(disk / "agent.gpp", RunOptions(platform="dummy", trace=disk / "run.jsonl"), [seen.append])
        written = (disk / "run.jsonl").read_text(encoding="utf-8").splitlines()
    assert len(written) > 10 and all(line.startswith("{") for line in written[:-1])  # up to where the disk was full
    [update] = [e for e in seen if isinstance(e, UpdateEvent)]
    assert (update.action, update.status) == ("long()", "cancelled")
    assert isinstance(seen[-1], FinishEvent) and seen[-1].status == "error"


@pytest.mark.slow
def test_gpp_test_bounds_an_endless_program(tmp_path: Path) -> None:
    (tmp_path / "loop.gpp").write_text(LOOP, encoding="utf-8")
    (tmp_path / "fine.gpp").write_text("procedure main() { }\n", encoding="utf-8")
    started = time.perf_counter()
    result = gpp("test", "--timeout", "1", str(tmp_path))
    assert time.perf_counter() - started < 60
    assert result.returncode == 1, result.stdout + result.stderr
    assert "1 passed, 1 failed" in result.stdout
    assert "timeout" in result.stdout


def realtime_blocksworld(trace: Path) -> subprocess.Popen[str]:
    """`gpp run examples/blocksworld.gpp --realtime` in a process of its own, tracing to `trace`."""
    return subprocess.Popen(
        [sys.executable, "-m", "gpp", "run", "-q", "examples/blocksworld.gpp", "--realtime", "--trace", str(trace)],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def wait_for_an_activity(process: subprocess.Popen[str], trace: Path) -> None:
    """Wait (60 s at most) until the run's trace shows an activity started on the platform."""
    deadline = time.monotonic() + 60
    while not (trace.exists() and '"event": "start"' in trace.read_text(encoding="utf-8")):
        assert process.poll() is None and time.monotonic() < deadline, "no activity started"
        time.sleep(0.05)


@pytest.mark.slow
def test_sigterm_cancels_activities_finishes_the_trace_and_exits_143(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    process = realtime_blocksworld(trace)
    try:
        wait_for_an_activity(process, trace)
        time.sleep(0.3)
        process.send_signal(signal.SIGTERM)
        out, err = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 143, out + err
    records = [json.loads(line) for line in trace.read_text(encoding="utf-8").splitlines()]
    assert records[-1]["event"] == "finish" and records[-1]["status"] == "interrupted"
    errors = [r for r in records if r["event"] == "error"]
    assert errors[0]["message"] == "terminated (SIGTERM)"
    cancelled = [r["id"] for r in records if r["event"] == "cancel"]
    acknowledged = [r["id"] for r in records if r["event"] == "update" and r["status"] == "cancelled"]
    assert cancelled and acknowledged == cancelled
    assert "Traceback" not in err


@pytest.mark.slow
@pytest.mark.skipif(os.name != "posix", reason="signals")
def test_ctrl_c_still_exits_130(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    process = realtime_blocksworld(trace)
    try:
        # Ctrl-C while an activity runs (not a fixed delay: under load start-up takes longer).
        wait_for_an_activity(process, trace)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 130, out + err
    assert err.endswith("interrupted\n")


# ---------------------------------------------------------------- parameters of main

PARAMS = """symbol domain Room = {hall, kitchen}
number fluent x() { initially: () = 0; }
Room fluent at() { initially: () = hall; }
bool fluent flag() { initially: () = false; }
list[number] fluent l() { initially: () = list[number] []; }
procedure main(number n, Room r, bool b, list[number] xs) { x() = n; at() = r; flag() = b; l() = xs; }
bool function postcond() = x() == 3 & at() == kitchen & flag() & length(l()) == 2
"""


def test_main_takes_its_parameters_from_arg(tmp_path: Path) -> None:
    (tmp_path / "p.gpp").write_text(PARAMS, encoding="utf-8")
    args = ["--arg", "n=3", "--arg", "r=kitchen", "--arg", "b=true", "--arg", "xs=[1, 2]"]
    result = gpp("run", "-q", "p.gpp", *args, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "postcond()         holds" in result.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "`main(number n, Room r, bool b, list[number] xs)` needs a value for `n`: give it with --arg n=VALUE"),
        (["--arg", "xz=3"], "`main` has no parameter `xz`; did you mean `xs`? (it takes n, r, b, xs)"),
        (["--arg", "n=abc"], '--arg n: expected a number, got "abc"'),
        (
            ["--arg", "n=1", "--arg", "r=attic", "--arg", "b=true", "--arg", "xs=[]"],
            "--arg r: attic is not in domain `Room`",
        ),
        (["--arg", "n"], "--arg takes KEY=VALUE, not 'n'"),
    ],
)
def test_parameters_of_main_that_do_not_fit_are_usage_errors(tmp_path: Path, args: list[str], message: str) -> None:
    (tmp_path / "p.gpp").write_text(PARAMS, encoding="utf-8")
    result = gpp("run", "-q", "p.gpp", *args, cwd=tmp_path)
    assert result.returncode == 2, result.stdout + result.stderr
    assert message in result.stderr
    assert "internal error" not in result.stdout + result.stderr


# ---------------------------------------------------------------- the live panel's clock


@pytest.mark.slow  # seconds of a realtime drive
def test_the_live_panels_clock_ticks_between_events_on_a_realtime_platform(tmp_path: Path) -> None:
    import io
    import re

    from rich.console import Console

    from gpp.run.runner import RunOptions, run_program
    from gpp.run.view import LiveView

    program = tmp_path / "drive.gpp"
    program.write_text(LONG_DRIVE, encoding="utf-8")
    out = io.StringIO()
    view = LiveView(Console(file=out, width=120, force_terminal=True, color_system=None), "drive.gpp")
    options = RunOptions(platform_options={"realtime": True}, timeout=2.5, record=True, clock=view.watch_clock)
    with view:
        outcome = run_program(program, options, [view])
    assert outcome.recording is not None and outcome.result is not None
    event_times = {round(e.t, 2) for e in outcome.recording.records}
    shown = {float(t) for t in re.findall(r"t = ([0-9]+\.[0-9]+) s", out.getvalue())}
    # The panel was redrawn with the platform's clock between the events, not only at them.
    ticks = shown - event_times
    assert len(ticks) >= 3, (sorted(shown), sorted(event_times))
    assert max(shown) <= max(event_times)
