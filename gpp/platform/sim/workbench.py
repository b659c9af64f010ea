"""The workbench scene: a side view with gravity, a table with named slots, dynamic blocks and
a kinematic gripper that grasps with constraints (TOOLING.md §3.3).

Units are centimetres and seconds; y points up. The gripper is a sensor that collides with
nothing: a grasp is a PivotJoint (the block's top centre to the gripper's tip) plus a
GearJoint (no swinging), both with a `max_force` so that a collision cannot explode. What a
block rests on is read from the physics (its contact arbiters), never from bookkeeping.

The actions are tasks: generators that command the gripper for the next physics step and
yield once per step, returning an Outcome when they are done. The platform steps the space
and advances every running task after each step.
"""

from __future__ import annotations

import math
import random
from collections.abc import Generator
from dataclasses import dataclass

import pymunk

from gpp.platform.sim.task import Task, fail, final, unknown
from gpp.platform.sim.world import BlockSpec, WorkbenchSpec, placement_order

# Collision categories: blocks and fixtures collide; the gripper collides with nothing.
_SOLID = 0b01
_GRIPPER = 0b10
GRIP_OFFSET = 5.0  # the gripper's tip is this far below its centre: grasp point = block top
RESTING_SPEED = 0.5  # cm/s
RESTING_SPIN = 0.01  # rad/s
SETTLE_TIMEOUT = 5.0  # s
PLACING = 8.0  # cm above its place, a carried block slows down ...
PLACING_SPEED = 40.0  # cm/s ... to this speed


@dataclass
class Block:
    spec: BlockSpec
    body: pymunk.Body
    shape: pymunk.Poly

    @property
    def name(self) -> str:
        return self.spec.name

    def upright(self) -> int:
        """The quarter turn the block lies closest to (0: as built, 1: on its left side, ...)."""
        return round(self.body.angle / (math.pi / 2))

    def half_height(self) -> float:
        """Half the block's vertical extent when straightened to its nearest quarter turn."""
        return (self.spec.width if self.upright() % 2 else self.spec.height) / 2

    def top(self) -> float:
        return float(self.body.position.y) + self.half_height()


@dataclass
class Grasp:
    block: Block
    joints: tuple[pymunk.Constraint, ...]


class Workbench:
    def __init__(self, spec: WorkbenchSpec) -> None:
        self.spec = spec
        space = pymunk.Space()
        space.gravity = (0.0, -spec.gravity)
        space.iterations = spec.iterations
        self.space = space
        self.names: dict[pymunk.Shape, str] = {}
        static = space.static_body
        solid = pymunk.ShapeFilter(categories=_SOLID, mask=_SOLID)
        fixtures: list[tuple[pymunk.Shape, str]] = [
            (pymunk.Segment(static, (-50.0, -2.0), (spec.width + 50.0, -2.0), 2.0), "floor"),
            (pymunk.Segment(static, (-2.0, 0.0), (-2.0, 2000.0), 2.0), "wall"),
            (pymunk.Segment(static, (spec.width + 2.0, 0.0), (spec.width + 2.0, 2000.0), 2.0), "wall"),
            (
                pymunk.Poly(
                    static,
                    [
                        (spec.table_left, spec.table_top - 6.0),
                        (spec.table_right, spec.table_top - 6.0),
                        (spec.table_right, spec.table_top),
                        (spec.table_left, spec.table_top),
                    ],
                ),
                "table",
            ),
        ]
        for leg_x in (spec.table_left + 12.0, spec.table_right - 12.0):
            leg = pymunk.Poly(
                static,
                [(leg_x - 4, 0.0), (leg_x + 4, 0.0), (leg_x + 4, spec.table_top - 6), (leg_x - 4, spec.table_top - 6)],
            )
            fixtures.append((leg, "floor"))
        for shape, name in fixtures:
            shape.friction = 0.8
            shape.filter = solid
            self.names[shape] = name
            space.add(shape)

        self.blocks: dict[str, Block] = {}
        tops: dict[str, tuple[float, float]] = {s.name: (s.x, spec.table_top) for s in spec.slots}
        for b in placement_order(spec):
            x, below = tops[b.on]
            body = pymunk.Body(b.mass, pymunk.moment_for_box(b.mass, (b.width, b.height)))
            body.position = (x, below + b.height / 2)
            shape = pymunk.Poly.create_box(body, (b.width, b.height), radius=0.0)
            shape.mass = b.mass
            shape.friction = b.friction
            shape.elasticity = 0.0
            shape.filter = solid
            space.add(body, shape)
            self.names[shape] = b.name
            self.blocks[b.name] = Block(b, body, shape)
            tops[b.name] = (x, below + b.height)

        self.gripper = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.gripper.position = spec.home
        grip_shape = pymunk.Poly.create_box(self.gripper, (50.0, 10.0))
        grip_shape.sensor = True
        grip_shape.filter = pymunk.ShapeFilter(categories=_GRIPPER, mask=0)
        space.add(self.gripper, grip_shape)
        self.grasp: Grasp | None = None
        self.busy: str | None = None  # the activity that uses the gripper
        self.phase = ""
        # Physics only runs while something can move: a task runs or blocks are not at rest.
        self.awake = True

    # ---------------------------------------------------------------- physics

    def step(self, dt: float) -> None:
        self.space.step(dt)

    def resting(self, ignore_held: bool = False) -> bool:
        held = self.grasp.block if ignore_held and self.grasp is not None else None
        for block in self.blocks.values():
            if block is held:
                continue
            body = block.body
            v = body.velocity
            if v.x * v.x + v.y * v.y > RESTING_SPEED * RESTING_SPEED or abs(body.angular_velocity) > RESTING_SPIN:
                return False
        return True

    # ---------------------------------------------------------------- sensing from contacts

    def supports(self, name: str) -> list[tuple[str, float]]:
        """What block `name` rests on: (name, vertical impulse) of every contact below it,
        strongest first. Table contacts are named by slot (`t1`), else `table`."""
        block = self.blocks[name]
        found: dict[str, float] = {}

        def visit(arbiter: pymunk.Arbiter) -> None:
            mine, other = arbiter.shapes
            if mine.body is not block.body:
                mine, other = other, mine
                normal = -arbiter.contact_point_set.normal
            else:
                normal = arbiter.contact_point_set.normal
            # The normal points from this block to the other shape: downwards for a support.
            if normal.y > -0.7 or other.sensor:
                return
            label = self.names.get(other, "?")
            if label == "table":
                label = self.slot_at(float(block.body.position.x)) or "table"
            elif label == "wall":
                return
            found[label] = found.get(label, 0.0) + abs(float(arbiter.total_impulse.y)) + 1e-9

        block.body.each_arbiter(visit)
        return sorted(found.items(), key=lambda item: -item[1])

    def support(self, name: str) -> str | None:
        """The one thing block `name` rests on (its strongest support), or None."""
        found = self.supports(name)
        return found[0][0] if found else None

    def on(self, x: str, y: str) -> bool:
        return self.support(x) == y

    def slot_at(self, x: float) -> str | None:
        for slot in self.spec.slots:
            if abs(x - slot.x) <= slot.width / 2:
                return slot.name
        return None

    def above(self, name: str) -> list[str]:
        """Blocks that rest (at least partly) on block `name`."""
        return sorted(other for other in self.blocks if other != name and name in dict(self.supports(other)))

    def occupant(self, slot: str) -> str | None:
        """A block that stands in (or overlaps) slot `slot` on the table."""
        spec = self.spec.slot(slot)
        assert spec is not None
        top = self.spec.table_top
        box = pymunk.BB(spec.x - spec.width / 2 + 1, top + 1, spec.x + spec.width / 2 - 1, top + 6)
        for shape in self.space.bb_query(box, pymunk.ShapeFilter(mask=_SOLID)):
            name = self.names.get(shape)
            if name in self.blocks:
                return name
        return None

    def locations(self) -> dict[str, str | None]:
        return {name: self.support(name) for name in self.blocks}

    # ---------------------------------------------------------------- the gripper

    def command(self, target: tuple[float, float], dt: float, speed: float | None = None) -> bool:
        """Set the gripper's velocity towards `target` for the next step; True once there."""
        pos = self.gripper.position
        dx, dy = target[0] - pos.x, target[1] - pos.y
        dist = math.hypot(dx, dy)
        if dist < 1e-6:
            self.gripper.velocity = (0.0, 0.0)
            return True
        speed = min(speed or self.spec.gripper_speed, dist / dt)
        self.gripper.velocity = (dx / dist * speed, dy / dist * speed)
        return False

    def take(self, block: Block) -> None:
        """Grasp `block`: its top centre (straightened to the nearest quarter turn) is pinned
        to the gripper's tip, its rotation locked upright."""
        k = block.upright()
        turn = k * math.pi / 2
        up_local = pymunk.Vec2d(0.0, 1.0).rotated(-turn)
        anchor = up_local * block.half_height()
        pivot = pymunk.PivotJoint(self.gripper, block.body, (0.0, -GRIP_OFFSET), anchor)
        pivot.max_force = 5e5 * block.spec.mass
        gear = pymunk.GearJoint(self.gripper, block.body, turn, 1.0)
        gear.max_force = 5e7 * block.spec.mass
        self.space.add(pivot, gear)
        self.grasp = Grasp(block, (pivot, gear))

    def release(self) -> Block | None:
        if self.grasp is None:
            return None
        self.space.remove(*self.grasp.joints)
        block = self.grasp.block
        self.grasp = None
        return block

    def stop(self) -> None:
        self.gripper.velocity = (0.0, 0.0)

    # ---------------------------------------------------------------- tasks

    def move(
        self, target: tuple[float, float], dt: float, phase: str, speed: float | None = None
    ) -> Generator[None, None, None]:
        self.phase = phase
        while not self.command(target, dt, speed):
            yield
        self.stop()

    def settle(self, dt: float, minimum: float = 0.1, looking: bool = False) -> Generator[None, None, bool]:
        """Step until every block is at rest (after at least `minimum` s); False on timeout.
        `looking`: only a camera waits (the gripper's phase and its block are not concerned)."""
        if not looking:
            self.phase = "settle"
        elapsed = 0.0
        while True:
            yield
            elapsed += dt
            if elapsed >= minimum and self.resting(ignore_held=looking):
                return True
            if elapsed > SETTLE_TIMEOUT:
                return False

    def stack(self, x: str, y: str, dt: float, rng: random.Random, slip: float) -> Task:
        """Pick block `x`, put it on slot or block `y`, release, wait until the pile settles;
        final only if `x` then physically rests on `y`."""
        if x not in self.blocks:
            return fail(unknown(f"block `{x}` on the workbench", x, self.blocks))
        if y not in self.blocks and self.spec.slot(y) is None:
            return fail(unknown(f"slot or block `{y}` on the workbench", y, self.targets()))
        if x == y:
            return fail(f"cannot stack `{x}` on itself")
        if not self.resting() and not (yield from self.settle(dt)):
            return fail("the blocks do not come to rest")
        block = self.blocks[x]
        if self.on(x, y):
            return final(reason=f"`{x}` already rests on `{y}`")
        on_x = self.above(x)
        if on_x:
            return fail(f"`{x}` is not clear: {_and(on_x)} on it")
        if y in self.blocks:
            on_y = [b for b in self.above(y) if b != x]
            if on_y:
                return fail(f"`{y}` is not clear: {_and(on_y)} on it")
        else:
            occupant = self.occupant(y)
            if occupant is not None and occupant != x:
                return fail(f"slot `{y}` is taken by `{occupant}`")

        carried = block.spec.height if block.upright() % 2 == 0 else block.spec.width
        travel = self.clearance(carried, x)
        bx = float(block.body.position.x)
        gx = float(self.gripper.position.x)
        yield from self.move((gx, travel), dt, "up")
        yield from self.move((bx, travel), dt, f"over {x}")
        yield from self.move((float(block.body.position.x), block.top() + GRIP_OFFSET), dt, f"reach {x}")
        self.phase = "grasp"
        self.take(block)
        # A slip happens (with the world's probability) somewhere along the transport.
        slip_after = rng.uniform(0.15, 0.95) if slip > 0 and rng.random() < slip else None
        if y in self.blocks:
            tx = float(self.blocks[y].body.position.x)
            target_top = self.blocks[y].top()
        else:
            slot = self.spec.slot(y)
            assert slot is not None
            tx, target_top = slot.x, self.spec.table_top
        down = target_top + 1.0 + carried + GRIP_OFFSET
        path = [((bx, travel), "lift"), ((tx, travel), f"carry over {y}"), ((tx, down + PLACING), f"lower onto {y}")]
        total = _path_length((float(self.gripper.position.x), float(self.gripper.position.y)), [p for p, _ in path])
        travelled = 0.0
        for target, phase in path:
            self.phase = phase
            while True:
                before = self.gripper.position
                arrived = self.command(target, dt)
                if arrived:
                    break
                yield
                travelled += (self.gripper.position - before).length
                if slip_after is not None and travelled >= slip_after * total:
                    self.release()
                    self.stop()
                    self.phase = "slipped"
                    settled = yield from self.settle(dt, 0.3)
                    where = self.support(x)
                    landed = f"it came to rest on `{where}`" if where and settled else "it is still moving"
                    return fail(f"the grasp slipped: `{x}` dropped, {landed}")
        # Let the block hang still under the gripper, then lower it slowly onto its place.
        self.stop()
        self.phase = "steady"
        for _ in range(int(1.0 / dt)):
            v = block.body.velocity
            if abs(float(block.body.position.x) - tx) < 0.2 and v.x * v.x + v.y * v.y < 1.0:
                break
            yield
        yield from self.move((tx, down), dt, "place", PLACING_SPEED)
        self.phase = "release"
        self.release()
        top = float(self.gripper.position.y)
        yield from self.move((tx, top + 60.0), dt, "retreat")
        if not (yield from self.settle(dt)):
            return fail("the pile does not come to rest")
        where = self.support(x)
        if where != y:
            return fail(f"`{x}` came to rest on `{where}`, not on `{y}`")
        return final()

    def home(self, dt: float) -> Task:
        """Move the (empty) gripper up to travel height, then to its home position."""
        if self.grasp is not None:
            self.release()
        home = self.spec.home
        travel = max(self.clearance(0.0), float(self.gripper.position.y))
        yield from self.move((float(self.gripper.position.x), travel), dt, "up")
        yield from self.move((home[0], travel), dt, "over home")
        yield from self.move(home, dt, "home")
        return final()

    def sense(self, x: str, dt: float) -> Task:
        """Look at block `x` once the blocks are at rest: what does it rest on?"""
        if x not in self.blocks:
            return fail(unknown(f"block `{x}` on the workbench", x, self.blocks))
        if not (yield from self.settle(dt, 0.2, looking=True)):
            return fail("the blocks do not come to rest")
        if self.grasp is not None and self.grasp.block.name == x:
            return fail(f"`{x}` is in the gripper")
        where = self.support(x)
        if where is None:
            return fail(f"`{x}` rests on nothing")
        return final(where, True)

    def clearance(self, carried: float, moving: str | None = None) -> float:
        """A travel height for the gripper: a carried block of height `carried` clears every
        block that stands on the bench (the moving one excepted)."""
        tops = [b.top() for b in self.blocks.values() if b.name != moving]
        return max([self.spec.table_top, *tops]) + carried + GRIP_OFFSET + 20.0

    def settle_initial(self, dt: float) -> None:
        """Let the blocks find their contacts before time starts (not on the clock)."""
        for i in range(int(2.0 / dt)):
            self.space.step(dt)
            if i > 5 and self.resting():
                break

    def targets(self) -> list[str]:
        return [s.name for s in self.spec.slots] + sorted(self.blocks)


def _path_length(start: tuple[float, float], points: list[tuple[float, float]]) -> float:
    total, here = 0.0, start
    for p in points:
        total += math.dist(here, p)
        here = p
    return max(total, 1e-6)


def _and(names: list[str]) -> str:
    shown = [f"`{n}`" for n in names]
    text = shown[0] if len(shown) == 1 else ", ".join(shown[:-1]) + " and " + shown[-1]
    return text + (" is" if len(shown) == 1 else " are")
