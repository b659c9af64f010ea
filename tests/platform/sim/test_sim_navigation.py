"""The sim's map with real physics: paths, cancelling, regions, the battery, obstacles."""

from __future__ import annotations

import math
import tomllib

import pymunk

from gpp.check import check_text
from gpp.model.types import Sym
from gpp.platform.base import ActivityUpdate, ExogOccurrence
from gpp.platform.sim import SimPlatform, World
from gpp.platform.sim.platform import make_activity, run_action
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.contract import program_interface
from gpp.runtime.state import ActivityStatus

CORRIDOR = """
name = "corridor"
[map]
size = [10.0, 3.0]
walls = [[0, 0, 10, 0], [10, 0, 10, 3], [10, 3, 0, 3], [0, 3, 0, 0]]
[map.robot]
start = "west"
[map.battery]
level = 100
drain_per_meter = 3.0
report_every = 5
[[map.frame]]
name = "west"
at = [1.0, 1.5]
[[map.frame]]
name = "east"
at = [9.0, 1.5]
[[map.region]]
name = "middle"
rect = [4.5, 0, 5.5, 3]
event = "/checkpoint"
fields = { id = "m" }
"""


def corridor(extra: str = "", battery: int = 100) -> SimPlatform:
    text = CORRIDOR.replace("level = 100", f"level = {battery}")
    return SimPlatform(World.from_data(tomllib.loads(text + extra)))


LISTENER = """
exog_action battery_report(number level) { mapping: "/battery" { level = level } }
exog_action victim_detected(symbol id) { mapping: "/victim_detected" { id = id } }
procedure main() { }
"""


def listen(sim: SimPlatform) -> None:
    """Attach a program that maps the world's events (as the stdlib does)."""
    check = check_text(LISTENER, lint=False)
    assert not check.errors, [d.message for d in check.diagnostics]
    sim.attach(program_interface(CompiledProgram(check.model)))  # some test worlds lack an event: fine here
    sim.queue.drain()  # the battery report at the start


def test_navigation_reaches_frames() -> None:
    sim = SimPlatform(World.load("blocksworld"))
    assert sim.map is not None
    update, _ = run_action(sim, "/navigate_to_frame", frame="table")
    assert update.status is ActivityStatus.FINAL
    assert sim.map.at_frame("table", tolerance=0.06)
    # Around the half wall, so longer than the straight line (5.4 m at 0.8 m/s).
    assert 5.4 / 0.8 < sim.now() < 15
    update, _ = run_action(sim, "/navigate_to_frame", frame="home")
    assert update.status is ActivityStatus.FINAL
    assert sim.map.at_frame("home", tolerance=0.06)


def test_a_cancel_stops_the_robot_mid_way() -> None:
    sim = corridor()
    m = sim.map
    assert m is not None
    drive = make_activity("/navigate_to_frame", frame="east")
    sim.start(drive)
    assert sim.wait(3.0) is False  # nothing ended by t = 3 s
    sim.preempt(drive)
    (_, update), *_ = sim.queue.drain()
    assert isinstance(update, ActivityUpdate) and update.status is ActivityStatus.CANCELLED
    x, y = m.position
    assert 2.5 < x < 5.0 and abs(y - 1.5) < 0.05
    assert not sim.live()
    for _ in range(120):  # physics goes on: the robot stays where it stopped
        m.step(sim.dt)
    assert math.dist(m.position, (x, y)) < 1e-6


def test_victim_events_arrive_when_the_robot_enters_a_region() -> None:
    sim = SimPlatform(World.load("rescue"))
    m = sim.map
    assert m is not None
    listen(sim)
    drive = make_activity("/navigate_to_frame", frame="room2")
    sim.start(drive)
    seen: list[tuple[float, tuple[float, float]]] = []
    done = False
    while not done:
        assert sim.wait(None) or len(sim.queue)
        for t, event in sim.queue.drain():
            if isinstance(event, ExogOccurrence) and event.action == "victim_detected":
                assert event.args == (Sym("v1"),)
                seen.append((t, m.position))
            elif isinstance(event, ActivityUpdate):
                assert event.status is ActivityStatus.FINAL
                done = True
    assert len(seen) == 1
    t, (x, y) = seen[0]
    region = next(r for r in m.spec.regions if r.name == "v1")
    assert region.circle is not None
    cx, cy, radius = region.circle
    # Reported in the step the robot crossed into the circle.
    assert radius - 0.05 < math.dist((x, y), (cx, cy)) <= radius
    assert 0 < t < sim.now()
    # A victim is reported once, even when the robot comes back.
    run_action(sim, "/navigate_to_frame", frame="home")
    _, events = run_action(sim, "/navigate_to_frame", frame="room2")
    assert not [e for e in events if e.action == "victim_detected"]


def test_the_battery_drains_with_distance_and_reports_every_step() -> None:
    sim = corridor()
    m = sim.map
    assert m is not None
    listen(sim)
    update, events = run_action(sim, "/navigate_to_frame", frame="east")
    assert update.status is ActivityStatus.FINAL
    levels = [e.args[0] for e in events if e.action == "battery_report"]
    assert m.battery is not None
    assert math.isclose(m.battery, 100 - 3.0 * m.distance, abs_tol=1e-6)
    assert 7.9 < m.distance < 8.1
    assert levels == [95, 90, 85, 80]  # 76 % left: reported when a multiple of 5 is reached


def test_an_empty_battery_stops_the_robot() -> None:
    sim = corridor(battery=9)
    update, _ = run_action(sim, "/navigate_to_frame", frame="east")
    assert update.status is ActivityStatus.FAILED
    assert "the battery is empty" in update.reason
    assert sim.map is not None and 3.9 < sim.map.position[0] < 4.2  # 9 % at 3 %/m: 3 m
    again, _ = run_action(sim, "/navigate_to_frame", frame="west")
    assert again.status is ActivityStatus.FAILED


def test_an_obstacle_that_blocks_the_way_fails_the_drive() -> None:
    sim = corridor('[[faults.obstacle]]\nname = "door"\nat = 1.0\nrect = [6.0, 0, 6.3, 3]\n')
    update, _ = run_action(sim, "/navigate_to_frame", frame="east")
    assert update.status is ActivityStatus.FAILED
    assert "no path to frame `east`: `door` blocks the way" in update.reason
    assert sim.map is not None and sim.map.position[0] < 6.0


def test_an_obstacle_that_leaves_room_makes_the_robot_replan() -> None:
    sim = corridor('[[faults.obstacle]]\nname = "box"\nat = 1.0\nrect = [6.0, 0.5, 6.6, 2.2]\n')
    m = sim.map
    assert m is not None
    update, _ = run_action(sim, "/navigate_to_frame", frame="east")
    assert update.status is ActivityStatus.FINAL
    assert m.obstacles[0].known
    assert any(p[1] > 2.2 for p in m.trail if 6.0 <= p[0] <= 6.6)  # went around, north of it


def test_an_unmapped_obstacle_gets_the_robot_stuck() -> None:
    sim = corridor()
    m = sim.map
    assert m is not None
    # A glass wall the map does not know: only physics has it.
    glass = pymunk.Segment(m.space.static_body, (5.0, 0.0), (5.0, 3.0), 0.05)
    m.space.add(glass)
    update, _ = run_action(sim, "/navigate_to_frame", frame="east")
    assert update.status is ActivityStatus.FAILED
    assert "stuck at" in update.reason
    assert 4.6 < m.position[0] < 4.75


def test_unknown_frames_and_a_busy_robot_fail() -> None:
    sim = corridor()
    update, _ = run_action(sim, "/navigate_to_frame", frame="eats")
    assert update.status is ActivityStatus.FAILED
    assert "no frame `eats` on the map; did you mean `east`?" in update.reason
    sim.start(make_activity("/navigate_to_frame", frame="east"))
    busy, _ = run_action(sim, "/navigate_to_frame", frame="west")
    assert busy.status is ActivityStatus.FAILED and "the robot is busy" in busy.reason
