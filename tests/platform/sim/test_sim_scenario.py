"""The sim with a scenario, in one run: the world serves what it models physically (driving,
stacking, its events), the scenario the rest (actions without a mapping to the sim, timed
exogenous events, sensing answers, injected faults); one agent runs unchanged on the dummy
platform and on the sim. Also: a world without a battery serves sim/navigation.gpp."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import ExogEvent, HeaderEvent, SenseEvent, StartEvent, UpdateEvent
from gpp.runtime.executor import RunStatus
from tests.support.cli import run as gpp

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples"
RECEPTIONIST = EXAMPLES / "receptionist.gpp"
RECEPTION_WORLD = str(EXAMPLES / "receptionist_world.toml")

# A world with a map and no battery: `[map.battery]` is optional.
CORRIDOR = """\
name = "corridor"
[map]
size = [10.0, 3.0]
walls = [[0, 0, 10, 0], [10, 0, 10, 3], [10, 3, 0, 3], [0, 3, 0, 0]]
[map.robot]
start = "home"
[[map.frame]]
name = "home"
at = [1.0, 1.5]
[[map.frame]]
name = "desk"
at = [8.0, 1.5]
"""


def finished(outcome: RunOutcome) -> RunOutcome:
    shown = [f"{d.code} {d.message} {' '.join(d.notes)}" for d in outcome.diagnostics]
    assert outcome.result is not None, shown
    assert outcome.result.status is RunStatus.FINISHED, shown
    assert outcome.postcond is True, shown
    return outcome


def run(path: Path, platform: str, **options: str) -> RunOutcome:
    return run_program(path, RunOptions(record=True, platform=platform, platform_options=options))


def steps(
    outcome: RunOutcome,
) -> tuple[list[str], list[tuple[str, str, str | None]], list[str], list[tuple[str, object]]]:
    """What a run did: the activities started, how each ended, the events, what was sensed."""
    assert outcome.recording is not None
    records = outcome.recording
    return (
        [r.action for r in records.of(StartEvent)],
        [(r.action, r.status, r.reason) for r in records.of(UpdateEvent)],
        [r.action for r in records.of(ExogEvent)],
        [(r.fluent, r.value) for r in records.of(SenseEvent)],
    )


def test_the_receptionist_runs_unchanged_on_the_dummy_platform_and_on_the_sim() -> None:
    dummy = steps(finished(run(RECEPTIONIST, "dummy")))
    sim_outcome = finished(run(RECEPTIONIST, "sim", world=RECEPTION_WORLD))
    sim = steps(sim_outcome)
    # The same decisions on both: solve guides bob first (the shorter tour), the first drive
    # to room1 fails (the scenario injects it) and is retried.
    started = [
        "greet(alice)",
        "ask_destination(alice)",
        "greet(bob)",
        "ask_destination(bob)",
        "goto(room2)",
        "hand_over(bob)",
        "goto(room1)",
        "goto(room1)",
        "hand_over(alice)",
        "goto(lobby)",
    ]
    assert dummy[0] == sim[0] == started
    assert dummy[2] == sim[2] == ["visitor_arrives(alice)", "visitor_arrives(bob)"]
    assert (
        dummy[3] == sim[3] == [("destination(alice)", {"symbol": "room1"}), ("destination(bob)", {"symbol": "room2"})]
    )
    failed = [("goto(room1)", "failed", "scenario")]
    assert [u for u in dummy[1] if u[1] != "final"] == [u for u in sim[1] if u[1] != "final"] == failed
    # On the sim the robot drove: the drives took the time the physics took, not the dummy's.
    assert sim_outcome.recording is not None
    (header,) = sim_outcome.recording.of(HeaderEvent)
    assert header.world == "receptionist" and header.scenario is not None
    assert header.scenario.endswith("receptionist.toml")


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


AGENT = """\
// world: corridor.toml
// scenario: desk.toml
#include "sim/navigation.gpp"
symbol domain frame = {home, desk}
bool fluent greeted() { initially: () = false; }
number fluent parcels() { initially: () = 0; }
number fluent weight() { initially: () = null; }
number exog_function scale();
exog_action parcel_arrives() { effect: parcels() = parcels() + 1; }
action greet() { effect: greeted() = true; }
action weigh() { senses: weight() = scale(); }
procedure main() {
    greet();
    test(parcels() > 0);
    navigate_to_frame(desk);
    weigh();
}
bool function postcond() = greeted() & robot_at() == desk & weight() == 3
"""

DESK = """\
[[exog]]
at = 2.5
action = "parcel_arrives"

[[exog_function]]
name = "scale"
value = 3
"""


def test_the_sim_serves_the_world_and_the_scenario_the_rest(tmp_path: Path) -> None:
    write(tmp_path, "corridor.toml", CORRIDOR)
    write(tmp_path, "desk.toml", DESK)
    outcome = finished(run(write(tmp_path, "agent.gpp", AGENT), "sim"))
    started, _, exogs, sensed = steps(outcome)
    assert started == ["greet()", "navigate_to_frame(desk)", "weigh()"]
    assert exogs == ["parcel_arrives()"]
    assert sensed == [("weight()", 3)]
    assert outcome.recording is not None
    # The event came at its time (the robot was idle: no physics step in between), and
    # the drive of 7 m took what the physics took.
    (event,) = outcome.recording.of(ExogEvent)
    assert event.t == 2.5
    drive = next(r for r in outcome.recording.of(UpdateEvent) if r.action == "navigate_to_frame(desk)")
    assert drive.t > 2.5 + 7 / 0.8


def test_without_a_scenario_the_actions_the_world_does_not_model_take_their_duration(tmp_path: Path) -> None:
    write(tmp_path, "corridor.toml", CORRIDOR)
    program = AGENT.replace("// scenario: desk.toml\n", "").replace("test(parcels() > 0);", "").replace("weigh();", "")
    program = program.replace("& weight() == 3", "")
    outcome = finished(run(write(tmp_path, "agent.gpp", program), "sim"))
    assert steps(outcome)[0] == ["greet()", "navigate_to_frame(desk)"]


def test_a_scenario_cannot_script_what_the_physics_decides(tmp_path: Path) -> None:
    write(tmp_path, "corridor.toml", CORRIDOR)
    write(tmp_path, "desk.toml", DESK + '\n[[action]]\nmatch = "navigate_to_frame(desk)"\nduration = 1\n')
    outcome = run(write(tmp_path, "agent.gpp", AGENT), "sim")
    assert outcome.result is None  # nothing ran
    (error,) = [d for d in outcome.diagnostics if d.code == "R0007"]
    assert "`navigate_to_frame` is served by the sim's physics" in error.message
    assert error.span.text == "[[action]]" and error.span.line == 9


def test_an_explicit_mapping_the_sim_does_not_serve_is_the_scenarios_when_it_names_it(tmp_path: Path) -> None:
    write(tmp_path, "corridor.toml", CORRIDOR)
    mapped = AGENT.replace("action greet() {", 'action greet() {\nmapping:\n    "/speech/say" { }\n')
    write(tmp_path, "desk.toml", DESK)
    outcome = run(write(tmp_path, "agent.gpp", mapped), "sim")
    (error,) = [d for d in outcome.diagnostics if d.code == "R0007"]
    assert error.message == 'action `greet` is mapped to "/speech/say", which the sim does not serve'
    assert 'an `[[action]]` rule `match = "greet"`' in error.notes[1]
    write(tmp_path, "desk.toml", DESK + '\n[[action]]\nmatch = "greet"\nduration = 0.5\n')
    finished(run(tmp_path / "agent.gpp", "sim"))


def test_the_scenario_flag_applies_to_the_sim(tmp_path: Path) -> None:
    write(tmp_path, "corridor.toml", CORRIDOR)
    write(tmp_path, "other.toml", DESK.replace("value = 3", "value = 4"))
    program = write(tmp_path, "agent.gpp", AGENT.replace("// scenario: desk.toml\n", "").replace("== 3", "== 4"))
    result = gpp("run", "-q", str(program), "--scenario", "other.toml", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "on sim: finished" in result.stdout


@pytest.mark.parametrize("platform", ["dummy", "sim"])
def test_navigation_needs_no_battery(tmp_path: Path, platform: str) -> None:
    write(tmp_path, "corridor.toml", CORRIDOR)
    program = write(
        tmp_path,
        "drive.gpp",
        '// world: corridor.toml\n#include "sim/navigation.gpp"\nsymbol domain frame = {home, desk}\n'
        "procedure main() { navigate_to_frame(desk); }\n"
        "bool function postcond() = robot_at() == desk & battery() == 100\n",
    )
    outcome = finished(run(program, platform))
    assert steps(outcome)[2] == []  # no battery, no reports


def test_a_scripted_activity_can_be_cancelled_on_the_sim(tmp_path: Path) -> None:
    write(tmp_path, "corridor.toml", CORRIDOR)
    write(tmp_path, "slow.toml", '[[action]]\nmatch = "greet"\nduration = 30\n')
    program = write(
        tmp_path,
        "agent.gpp",
        "// world: corridor.toml\n// scenario: slow.toml\n"
        "action greet() { }\n"
        "procedure main() { start(greet()); test(context_time() >= 2); cancel(greet()); end(greet()); }\n"
        "bool function postcond() = context_time() == 2\n",
    )
    outcome = finished(run(program, "sim"))
    assert steps(outcome)[1] == [("greet()", "cancelled", "preempted")]


def test_frames_the_world_lacks_are_reported_before_the_run() -> None:
    # The receptionist in the default world (the blocksworld), whose map has other frames.
    outcome = run(RECEPTIONIST, "sim")
    assert outcome.result is None
    (error,) = [d for d in outcome.diagnostics if d.code == "R0007"]
    assert error.message == (
        "action `goto`: world `blocksworld` has no frame `lobby`, `room1`, `room2` (its frames: `home`, `table`)"
    )
    assert error.span.text == "frame = p"
    assert error.help is not None and "--world" in error.help
