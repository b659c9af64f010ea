"""Recording a run to replay (gpp.traceview.replay, `gpp dap` on a trace) with the live run's
state at each step, taken by a run control, to compare the replay with."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from gpp.run.runner import RunOptions, run_program
from gpp.runtime.control import Executor, RunControl
from gpp.runtime.semantics import Prog
from gpp.runtime.values import to_json
from gpp.traceview.replay import ReplayState

ROOT = Path(__file__).resolve().parents[2]
# An agent with procedure calls, a recursion, a pick's local, a loop and a `solve`.
REPLAY_AGENT = ROOT / "tests" / "traceview" / "programs" / "replay_agent.gpp"
BLOCKSWORLD = ROOT / "examples" / "blocksworld.gpp"


@dataclass
class LiveState:
    """What the live run's state was, as the trace writes values."""

    fluents: dict[str, object]  # every fluent instance the program knows, with its value
    initial: dict[str, object]  # their initial values
    activities: dict[int, tuple[str, str]]  # id -> (action, status)


@dataclass
class Watcher(RunControl):
    """Records the live state at each checkpoint, by the number of transitions taken so far:
    the last checkpoint before transition n+1 is the state a replay shows at position n."""

    states: dict[int, LiveState] = field(default_factory=dict)
    final: LiveState | None = None

    def checkpoint(self, executor: Executor, prog: Prog) -> None:
        self.states[executor.result.steps] = _live(executor)  # type: ignore[attr-defined]

    def finished(self, executor: Executor) -> None:
        self.final = _live(executor)


def _live(executor: Executor) -> LiveState:
    program, state = executor.program, executor.state
    texts = [program.instance_text(slot) for slot in range(len(program.instances))]
    records = executor.records  # type: ignore[attr-defined]
    return LiveState(
        {text: to_json(state.get(slot, program.initial)) for slot, text in enumerate(texts)},
        {text: to_json(program.initial(slot)) for slot, text in enumerate(texts)},
        {records[g].id: (g.text, status.value) for g, status in executor.acts.items()},
    )


def record(tmp_path: Path, program: Path, name: str, **options: object) -> tuple[Path, Watcher]:
    """Run `program` with a trace recorded with steps, watching the live state."""
    watcher = Watcher()
    trace = tmp_path / f"{name}.jsonl"
    run_options = RunOptions(trace=trace, trace_steps=True, control=watcher, **options)  # type: ignore[arg-type]
    outcome = run_program(program, run_options)
    assert outcome.result is not None and outcome.result.status.value == "finished", outcome.diagnostics
    return trace, watcher


def assert_same(replayed: ReplayState, live: LiveState, where: str) -> None:
    for text, value in replayed.fluents.items():
        assert live.fluents.get(text) == value, (where, text)
    for text, value in live.fluents.items():
        if text not in replayed.fluents:
            assert value == live.initial[text], (where, text, "changed in the run but not in the replay")
    assert {a.id: (a.action, a.status) for a in replayed.activities.values()} == live.activities, where
