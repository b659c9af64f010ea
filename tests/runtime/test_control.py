"""The run-control hook (gpp.runtime.control): a control holds the run at checkpoints (the
virtual clock stands still), stops it as Ctrl-C does, is told of blocked runs and failures, and
brings events from its own thread through `request_attention`."""

from __future__ import annotations

import threading
import time
from pathlib import Path

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.contract import EventQueue, ExogOccurrence
from gpp.runtime.control import Happening, RunControl, RunStopped, request_attention
from gpp.runtime.events import ErrorEvent, ExogEvent, FinishEvent, UpdateEvent
from gpp.runtime.executor import Executor, RunStatus
from gpp.runtime.semantics import Prog, Step
from gpp.runtime.state import ActivityStatus

PROGRAM = """\
// scenario: world.toml
bool fluent arrived() { initially: () = false; }
number fluent trips() { initially: () = 0; }
exog_action arrives() { effect: arrived() = true; }
action drive() {
duration: [1, 100]
effect:
    trips() = trips() + 1;
}
procedure main() {
    drive();
    drive();
    test(arrived());
}
"""

SCENARIO = '[[action]]\nmatch = "drive()"\nduration = 5.0\n'


def run(tmp_path: Path, control: RunControl, scenario: str = SCENARIO) -> RunOutcome:
    path = tmp_path / "agent.gpp"
    path.write_text(PROGRAM)
    (tmp_path / "world.toml").write_text(scenario)
    outcome = run_program(path, RunOptions(record=True, control=control))
    assert outcome.result is not None, [d.message for d in outcome.diagnostics]
    return outcome


class Watcher(RunControl):
    """Records what it is told; brings `arrives` when asked to in `attend`."""

    def __init__(self, live: bool = False) -> None:
        self.started_at: float | None = None
        self.checkpoints: list[float] = []
        self.happenings: list[Happening] = []
        self.attended = 0
        self.ended = False
        self.is_live = live
        self.queue: EventQueue | None = None

    def started(self, executor: Executor, prog: Prog) -> None:
        self.started_at = executor.platform.now()
        self.queue = executor.platform.queue

    def checkpoint(self, executor: Executor, prog: Prog) -> None:
        self.checkpoints.append(executor.platform.now())

    def happened(self, executor: Executor, prog: Prog | None, happening: Happening) -> None:
        self.happenings.append(happening)

    def attend(self, executor: Executor) -> None:
        self.attended += 1
        executor.platform.queue.put(ExogOccurrence("arrives", ()), executor.platform.now())
        self.is_live = False

    def live(self) -> bool:
        return self.is_live

    def finished(self, executor: Executor) -> None:
        self.ended = True


def test_a_control_is_told_each_turn_and_of_a_blocked_run(tmp_path: Path) -> None:
    watcher = Watcher()
    outcome = run(tmp_path, watcher)
    assert outcome.result is not None and outcome.result.status is RunStatus.BLOCKED
    assert watcher.started_at == 0.0 and watcher.ended
    assert watcher.checkpoints[0] == 0.0 and watcher.checkpoints[-1] == 10.0
    assert watcher.checkpoints == sorted(watcher.checkpoints)
    [blocked] = watcher.happenings
    assert blocked.kind == "blocked" and "arrived()" in blocked.description
    assert blocked.span is not None and PROGRAM[blocked.span.start : blocked.span.end].startswith("test(arrived())")


def test_a_failed_action_is_a_happening(tmp_path: Path) -> None:
    watcher = Watcher()
    run(tmp_path, watcher, SCENARIO.replace("duration = 5.0", 'duration = 5.0\noutcome = "fail"'))
    assert watcher.happenings[0].kind == "failed"
    assert watcher.happenings[0].description.startswith("drive() failed")


def test_a_live_control_brings_an_event_from_its_own_thread(tmp_path: Path) -> None:
    watcher = Watcher(live=True)
    outcomes: list[RunOutcome] = []
    runner = threading.Thread(target=lambda: outcomes.append(run(tmp_path, watcher)))
    runner.start()
    # The program waits for `arrived()` (the control is live: it does not end as blocked).
    deadline = time.monotonic() + 30
    while not (watcher.checkpoints and watcher.checkpoints[-1] == 10.0) and time.monotonic() < deadline:
        time.sleep(0.01)
    assert runner.is_alive()
    # As the console's server thread would: only the queue is touched from here.
    assert watcher.queue is not None
    request_attention(watcher.queue, 10.0)
    runner.join(30)
    [outcome] = outcomes
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert watcher.attended == 1 and watcher.happenings == []
    assert outcome.recording is not None and [e.action for e in outcome.recording.of(ExogEvent)] == ["arrives()"]


class Holder(Watcher):
    """Holds the run at its second checkpoint until released, then stops it while an activity runs."""

    def __init__(self) -> None:
        super().__init__()
        self.holding = threading.Event()
        self.release = threading.Event()
        self.executor: Executor | None = None

    def checkpoint(self, executor: Executor, prog: Prog) -> None:
        super().checkpoint(executor, prog)
        self.executor = executor
        if len(self.checkpoints) == 2:
            self.holding.set()
            assert self.release.wait(30)
        elif self.release.is_set() and any(executor.acts.status(g) is ActivityStatus.RUNNING for g in executor.records):
            raise RunStopped("stopped by the operator")


def test_a_held_run_keeps_its_clock_and_a_stop_ends_it_as_ctrl_c_does(tmp_path: Path) -> None:
    holder = Holder()
    outcomes: list[RunOutcome] = []
    runner = threading.Thread(target=lambda: outcomes.append(run(tmp_path, holder)))
    runner.start()
    assert holder.holding.wait(30)
    assert holder.executor is not None
    held_at = holder.executor.platform.now()
    time.sleep(0.2)
    assert holder.executor.platform.now() == held_at  # virtual time stands still while held
    holder.release.set()
    runner.join(30)
    [outcome] = outcomes
    assert outcome.result is not None and outcome.result.status is RunStatus.INTERRUPTED
    assert outcome.recording is not None
    assert [e.message for e in outcome.recording.of(ErrorEvent)] == ["stopped by the operator"]
    *_, finish = outcome.recording
    assert isinstance(finish, FinishEvent) and finish.status == "interrupted"
    # The drive that was running when the stop came was cancelled.
    assert [(e.action, e.status) for e in outcome.recording.of(UpdateEvent)][-1] == ("drive()", "cancelled")


class Stepper(Watcher):
    """Records each transition it is told of, with the world as it is before the step."""

    def __init__(self) -> None:
        super().__init__()
        self.steps: list[tuple[str, str, int]] = []

    def stepping(self, executor: Executor, prog: Prog, step: Step, after: Prog) -> None:
        trips = executor.program.read(executor.state, "trips", ())
        assert isinstance(trips, int)
        self.steps.append((step.describe(), step.span.text.strip(), trips))


def test_a_control_is_told_each_transition_before_it_is_taken(tmp_path: Path) -> None:
    stepper = Stepper()
    outcome = run(tmp_path, stepper)
    assert outcome.result is not None
    # Each step with its statement, told before it is performed: the ends have not yet counted.
    assert stepper.steps == [
        ("start(drive())", "drive();", 0),
        ("end(drive())", "drive();", 0),
        ("start(drive())", "drive();", 1),
        ("end(drive())", "drive();", 1),
    ]
    assert len(stepper.steps) == outcome.result.steps


class StopOnAttention(Watcher):
    """Asks for attention while an activity runs, and stops the run when it gets it."""

    def checkpoint(self, executor: Executor, prog: Prog) -> None:
        super().checkpoint(executor, prog)
        if any(True for _ in executor.acts.running()) and not self.attended:
            self.attended = -1
            request_attention(executor.platform.queue, executor.platform.now())

    def attend(self, executor: Executor) -> None:
        raise RunStopped("stopped by the operator")


def test_a_stop_in_the_middle_of_the_queue_loses_no_activity_end(tmp_path: Path) -> None:
    # The attention is queued before the drive's end: the end is still taken in, so the run's
    # end does not wait for an acknowledgement that was already there.
    outcome = run(tmp_path, StopOnAttention())
    assert outcome.result is not None and outcome.result.status is RunStatus.INTERRUPTED
    assert outcome.recording is not None
    assert [e.message for e in outcome.recording.of(ErrorEvent)] == ["stopped by the operator"]
    assert [(e.action, e.status) for e in outcome.recording.of(UpdateEvent)] == [("drive()", "final")]
