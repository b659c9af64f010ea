"""The sim platform: a pymunk world on virtual time.

The executor calls `wait()` whenever the program is blocked; only then does the sim step its
physics, one fixed step (`world.dt`, 1/60 s by default) at a time, advancing every running
action (a task, see workbench.py and navigation.py) after each step, until an activity ends
or an exogenous event happens. The clock is sim time: runs go as fast as the CPU allows, or,
with `realtime`, paced to wall time. A scene whose bodies are at rest and that no action
uses is not stepped at all.

Randomness (grasp slips) comes from one seeded generator, so a run is reproducible per world
and seed.

What the world does not model is served by a scenario, in the dummy platform's format and with
its rules, on the sim's clock: the actions that are not mapped to a service of the sim (a
robot's `greet`, `ask_destination`), exogenous events at given times and the answers of
exogenous functions. A scenario rule for an action the sim serves can only inject a fault (it
fails or cancels the activity after its duration, unless the physics ends it first).
"""

from __future__ import annotations

import itertools
import random
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from gpp.base.paths import output_problem
from gpp.model.types import STRING, DomainType, Sym, Type
from gpp.platform.base import (
    ActionBinding,
    Activity,
    ActivityUpdate,
    ExogActionBinding,
    ExogOccurrence,
    Platform,
    PlatformConfig,
    PlatformError,
    Problem,
    ProgramInterface,
    RunFacts,
    parse_options,
)
from gpp.platform.dummy import DummyPlatform, Scenario, ScenarioError
from gpp.platform.options import BUILTIN, SimOptions
from gpp.platform.sim.navigation import Happening, MapScene
from gpp.platform.sim.services import SERVICES, check_interface, event_args
from gpp.platform.sim.task import Outcome, Task, fail
from gpp.platform.sim.workbench import Workbench
from gpp.platform.sim.world import World, WorldError
from gpp.runtime.state import ActivityStatus, GroundAction
from gpp.runtime.values import Value

if TYPE_CHECKING:
    from gpp.platform.sim.render import Recorder

FRAME_INTERVAL = 0.25  # s of sim time between two recorded frames


@dataclass
class Running:
    activity: Activity
    task: Task
    scene: Workbench | MapScene


@dataclass(frozen=True)
class SimStats:
    world: str
    steps: int
    sim_time: float
    wall_time: float  # from attach to close
    physics_time: float  # wall time spent stepping (inside wait)

    @property
    def steps_per_second(self) -> float:
        return self.steps / self.physics_time if self.physics_time > 0 else 0.0

    @property
    def speedup(self) -> float:
        """Sim time per wall time over the whole run (planning and the executor included)."""
        return self.sim_time / self.wall_time if self.wall_time > 0 else 0.0


class SimPlatform(Platform):
    """A world of pymunk scenes on virtual time; see the module docstring."""

    name = "sim"
    virtual_time = True
    selected_by = BUILTIN["sim"].selected_by
    Options = SimOptions
    # The statistics of the last closed run (for bench/sim.py).
    last_run: ClassVar[SimStats | None] = None

    def __init__(
        self,
        world: World | None = None,
        seed: int | None = None,
        record: Path | None = None,
        snapshot: Path | None = None,
        realtime: bool = False,
        frame_interval: float = FRAME_INTERVAL,
        scenario: Scenario | None = None,
        scenario_path: Path | None = None,
    ) -> None:
        super().__init__()
        self.world = world if world is not None else World.load()
        self.dt = self.world.dt
        self.seed = seed if seed is not None else (self.world.faults.seed if self.world.faults.seed is not None else 1)
        self.rng = random.Random(self.seed)
        self.workbench = Workbench(self.world.workbench) if self.world.workbench is not None else None
        if self.workbench is not None:
            self.workbench.settle_initial(self.dt)
        self.map = MapScene(self.world.map) if self.world.map is not None else None
        self.clock = 0.0
        self.steps = 0
        self.tasks: dict[int, Running] = {}
        self.results: dict[int, Value] = {}
        self.obstacles = sorted(self.world.faults.obstacles, key=lambda o: o.at)
        self.interface: ProgramInterface | None = None
        self.routes: dict[str, list[ExogActionBinding]] = {}
        self.realtime = realtime
        # What the world does not model, served as the dummy platform serves it, on this clock.
        self.script = DummyPlatform(scenario, scenario_path=scenario_path)
        self.scenario_path = scenario_path
        self.has_scenario = scenario is not None
        self.last_outcome = ""
        self._wall_start = time.perf_counter()
        self._physics = 0.0
        self.recorder: Recorder | None = None
        if record is not None or snapshot is not None:
            from gpp.platform.sim.render import Recorder

            self.recorder = Recorder(self.world, record, snapshot, frame_interval)

    @classmethod
    def create(cls, config: PlatformConfig) -> SimPlatform:
        """The platform for `gpp run --platform sim`: the world from the `world` option, else
        from a `// world: NAME` line at the top of the program, else the blocksworld. The world's
        `[faults] seed` is used unless the `seed` option is given."""
        options = parse_options(SimOptions, config.options, cls.name)
        for what, path in (("record", options.record), ("snapshot", options.snapshot)):
            problem = output_problem(path) if path is not None else None
            if problem is not None:
                raise PlatformError(f"option `{what}` of platform `sim`: {problem}")
        try:
            if options.world is not None:
                world = World.load(options.world)  # a name, or a path from the working directory
            else:
                world = World.load(config.directives.get("world"), config.program.parent)
        except WorldError as e:
            raise PlatformError(str(e)) from None
        seed = options.seed if options.seed is not None else world.faults.seed
        path = options.scenario if options.scenario is not None else config.directive_path("scenario")
        try:
            scenario = Scenario.load(path) if path is not None else None
        except ScenarioError as e:
            raise PlatformError(str(e)) from None
        return cls(
            world, seed, options.record, options.snapshot, options.realtime, scenario=scenario, scenario_path=path
        )

    # ---------------------------------------------------------------- contract

    def attach(self, interface: ProgramInterface) -> list[Problem]:
        self.interface = interface
        scripted = self.script.scenario
        problems = check_interface(
            interface,
            self.world,
            scripted_actions={r.name for r in scripted.actions},
            scripted_exogs={e.action for e in scripted.exogs},
        )
        problems += self.script.attach(interface)
        problems += self._injected_faults(interface)
        self.routes = {}
        for signature in interface.exog_actions.values():
            self.routes.setdefault(signature.mapped_name, []).append(signature)
        if self.map is not None:
            report = self.map.battery_report()
            if report is not None:
                self._report(report)
        self._wall_start = time.perf_counter()
        if self.recorder is not None:
            self.recorder.capture(self, force=True)
        return problems

    def start(self, activity: Activity) -> None:
        service = SERVICES.get(activity.mapped_name)
        if service is None:
            self.script.catch_up(self.clock)  # not modelled: the scenario serves it
            self.script.start(activity)
            return
        if self.script.rule_for(activity.action) is not None:
            self.script.catch_up(self.clock)  # a fault the scenario injects, unless the physics ends it first
            self.script.start(activity)
        args = {k: _name(v) for k, v in activity.args.items()}
        text = activity.action.text
        if service.scene == "workbench":
            if self.workbench is None:
                self._finish(activity, fail(f"world `{self.world.name}` has no workbench"))
                return
            scene: Workbench | MapScene = self.workbench
            problem = self._gripper_problem(activity)
            if problem is not None:
                self._finish(activity, fail(problem))
                return
            wb = self.workbench
            if activity.mapped_name == "/stack":
                wb.busy = text
                task = wb.stack(args["block"], args["location"], self.dt, self.rng, self.world.faults.grasp_slip)
            elif activity.mapped_name == "/gripper_home":
                wb.busy = text
                task = wb.home(self.dt)
            else:
                task = wb.sense(args["block"], self.dt)
        else:
            if self.map is None:
                self._finish(activity, fail(f"world `{self.world.name}` has no map"))
                return
            scene = self.map
            if self.map.busy is not None:
                self._finish(activity, fail(f"the robot is busy with `{self.map.busy}`"))
                return
            self.map.busy = text
            task = self.map.navigate(args["frame"], self.dt)
        scene.awake = True
        running = Running(activity, task, scene)
        self.tasks[activity.id] = running
        self._advance(running)

    def preempt(self, activity: Activity) -> None:
        running = self.tasks.get(activity.id)
        if running is None:
            self.script.preempt(activity)  # a scripted one (or one already ended)
            self._take_scripted()
            return
        self._stop(running)
        self._finish(activity, Outcome(ActivityStatus.CANCELLED, reason="preempted"))

    def _stop(self, running: Running) -> None:
        running.task.close()
        scene = running.scene
        if isinstance(scene, Workbench) and scene.busy == running.activity.action.text:
            scene.release()
            scene.stop()

    def exog_function(
        self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
    ) -> Value:
        if activity is not None and activity.id in self.results:
            return self.results[activity.id]
        if self.has_scenario:
            return self.script.exog_function(name, args, return_type, activity)
        raise PlatformError(
            f"the sim has no exogenous function `{name}`: its sensing results come with the actions that sense "
            '(use it in the `senses:` section of an action mapped to "/get_block_pose"), and a scenario '
            "(`--scenario`) answers the others"
        )

    def now(self) -> float:
        return self.clock

    def wait(self, deadline: float | None, wall_deadline: float | None = None) -> bool:
        wall0 = time.perf_counter()
        sim0 = self.clock
        try:
            while True:
                self._take_scripted()
                if len(self.queue):
                    return True
                if deadline is not None and self.clock >= deadline:
                    return False
                if wall_deadline is not None and time.monotonic() >= wall_deadline:
                    return False  # the run's wall-clock bound: the physics took that long
                if not self.tasks:
                    # Nothing moves: time jumps to what the scenario does next, or to the deadline.
                    due = self.script.next_time()
                    if due is None or (deadline is not None and due > deadline):
                        if deadline is not None and deadline > self.clock:
                            self.clock = deadline
                        return False
                    if self.realtime and due > self.clock:
                        pause = due - self.clock  # a scripted greeting takes its time too
                        if wall_deadline is not None and time.monotonic() + pause > wall_deadline:
                            pause = max(0.0, wall_deadline - time.monotonic())
                            time.sleep(pause)
                            self.clock += pause
                            return False  # the run's wall-clock bound comes first
                        time.sleep(pause)
                    self.clock = max(self.clock, due)
                    continue
                self._step()
                if self.realtime:
                    ahead = (self.clock - sim0) - (time.perf_counter() - wall0)
                    if ahead > 0.005:
                        time.sleep(ahead)
        finally:
            self._physics += time.perf_counter() - wall0

    def live(self) -> bool:
        return bool(self.tasks) or self.script.live()

    def close(self) -> None:
        for running in list(self.tasks.values()):
            running.task.close()
        self.tasks.clear()
        if self.recorder is not None:
            self.recorder.capture(self, force=True)
            self.recorder.save()
        SimPlatform.last_run = self.stats()

    def facts(self) -> RunFacts:
        scenario = str(self.scenario_path) if self.scenario_path is not None else None
        return RunFacts(world=self.world.name, scenario=scenario, seed=self.seed)

    # ---------------------------------------------------------------- reading the world

    def stats(self) -> SimStats:
        return SimStats(self.world.name, self.steps, self.clock, time.perf_counter() - self._wall_start, self._physics)

    def caption(self) -> str:
        running = [
            f"{r.activity.action.text}: {r.scene.phase}" if r.scene.phase else r.activity.action.text
            for r in self.tasks.values()
        ]
        return "   ".join(running) if running else self.last_outcome

    # ---------------------------------------------------------------- stepping

    def _step(self) -> None:
        dt = self.dt
        self.steps += 1
        self.clock += dt
        while self.obstacles and self.obstacles[0].at <= self.clock:
            assert self.map is not None
            self.map.add_obstacle(self.obstacles.pop(0))
        wb, m = self.workbench, self.map
        if wb is not None and wb.awake:
            wb.step(dt)
        if m is not None and m.awake:
            for happening in m.step(dt):
                self._report(happening)
        for running in list(self.tasks.values()):
            self._advance(running)
        if wb is not None and wb.awake and wb.busy is None and not self._uses(wb) and wb.resting():
            wb.awake = False
        if m is not None and m.awake and not self._uses(m):
            m.awake = False
        if self.recorder is not None:
            self.recorder.capture(self)

    def _uses(self, scene: Workbench | MapScene) -> bool:
        return any(r.scene is scene for r in self.tasks.values())

    def _advance(self, running: Running) -> None:
        try:
            next(running.task)
        except StopIteration as stop:
            outcome = stop.value
            assert isinstance(outcome, Outcome)
            self._finish(running.activity, outcome)

    def _take_scripted(self) -> None:
        """What the scenario has made happen by now, into the queue; an injected fault stops
        the physical task it ends."""
        while (due := self.script.next_time()) is not None and due <= self.clock:
            self.script.wait(self.clock)
        for _, event in self.script.queue.drain():
            if isinstance(event, ActivityUpdate) and (running := self.tasks.get(event.activity_id)) is not None:
                self._stop(running)
                self.tasks.pop(event.activity_id)
                self._release(running)
                self.last_outcome = f"{running.activity.action.text}: {event.status.value} (scenario)"
            self.queue.put(event, self.clock)

    def _release(self, running: Running) -> None:
        if running.scene.busy == running.activity.action.text:
            running.scene.busy = None
            running.scene.phase = ""

    def _injected_faults(self, interface: ProgramInterface) -> list[Problem]:
        """A scenario rule for an action the sim serves physically can only make it fail or be
        cancelled: the physics decides where it ends and what it senses."""
        problems: list[Problem] = []
        for rule in self.script.scenario.actions:
            binding: ActionBinding | None = interface.actions.get(rule.name)
            if binding is None or binding.mapped_name not in SERVICES:
                continue
            if rule.outcome is ActivityStatus.FINAL or rule.has_result:
                problems.append(
                    Problem(
                        f'scenario: `{rule.name}` is served by the sim\'s physics ("{binding.mapped_name}"): a rule '
                        'for it can only inject a fault (`outcome = "fail"` or `"cancel"`, no `result`)',
                        rule.span,
                    )
                )
        return problems

    def _finish(self, activity: Activity, outcome: Outcome) -> None:
        self.script.forget(activity.id)
        running = self.tasks.pop(activity.id, None)
        if running is not None:
            self._release(running)
        result: Value = None
        if outcome.has_result:
            result = self._sensed(activity, outcome.result)
            self.results[activity.id] = result
        self.last_outcome = f"{activity.action.text}: {outcome.status.value}" + (
            f" ({outcome.reason})" if outcome.reason else ""
        )
        self.queue.put(
            ActivityUpdate(activity.id, outcome.status, result, outcome.has_result, outcome.reason), self.clock
        )

    def _sensed(self, activity: Activity, value: object) -> Value:
        t = self.interface.sensing(activity.action.name) if self.interface is not None else None
        element = t.element if isinstance(t, DomainType) else t
        if isinstance(value, str):
            return value if element is STRING else Sym(value)
        assert value is None or isinstance(value, bool | int | float)
        return value

    def _report(self, happening: Happening) -> None:
        for signature in self.routes.get(happening.event, []):
            args = event_args(signature, happening.fields)
            if args is not None:
                self.queue.put(ExogOccurrence(signature.name, args), self.clock)

    def _gripper_problem(self, activity: Activity) -> str | None:
        wb = self.workbench
        assert wb is not None
        if activity.mapped_name == "/get_block_pose":
            return None  # a camera over the table: no gripper, no robot needed
        if wb.busy is not None:
            return f"the gripper is busy with `{wb.busy}`"
        frame = wb.spec.frame
        if frame is not None and self.map is not None and not self.map.at_frame(frame):
            nearest = self.map.nearest_frame()
            where = f" (it is at `{nearest[0]}`)" if nearest is not None and nearest[1] < 0.3 else ""
            return f"the robot is not at the workbench: navigate to frame `{frame}` first{where}"
        return None


def _name(v: Value) -> str:
    if isinstance(v, Sym):
        return v.name
    return v if isinstance(v, str) else str(v)


_ids = itertools.count(100_000)


def make_activity(mapped: str, **args: str) -> Activity:
    """An activity for a mapped name with symbol arguments, as if a program had started it
    (for scripts and tests that drive the sim without a program)."""
    action = mapped.strip("/").replace("/", "_")
    values: dict[str, Value] = {k: Sym(v) for k, v in args.items()}
    return Activity(next(_ids), GroundAction(action, tuple(values.values())), mapped, values)


def run_action(
    sim: SimPlatform, mapped: str, timeout: float | None = None, **args: str
) -> tuple[ActivityUpdate, list[ExogOccurrence]]:
    """Start one activity (see make_activity) and step the sim until it ends; returns its
    update and the exogenous events that happened meanwhile."""
    activity = make_activity(mapped, **args)
    events: list[ExogOccurrence] = []
    sim.start(activity)
    deadline = sim.now() + timeout if timeout is not None else None
    while True:
        for _, event in sim.queue.drain():
            if isinstance(event, ExogOccurrence):
                events.append(event)
            elif isinstance(event, ActivityUpdate) and event.activity_id == activity.id:
                return event, events
        if not sim.wait(deadline) and len(sim.queue) == 0:
            raise TimeoutError(f'"{mapped}" did not end by t = {sim.now():.2f} s')
