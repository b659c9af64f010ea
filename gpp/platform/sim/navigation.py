"""The map scene: a top view without gravity, walls, named frames and a round robot driven by
velocity commands along a path planned on an occupancy grid (A*, 8-connected).

Units are metres and seconds; y points up. The robot is a dynamic circle whose velocity is
set before every physics step, so walls and obstacles stop it for real. Obstacles that
appear (world faults) become known to the robot when it comes within sensor range; it then
plans again and gives up when no path is left. It also gives up when it stops making
progress (stuck) or its battery is empty.

After every step the scene reports happenings: the robot entered a region (an exogenous
event such as "/victim_detected" { id }) or its battery level crossed a reporting step
("/battery" { level }).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import pymunk

from gpp.platform.sim.task import Task, fail, final, unknown
from gpp.platform.sim.world import MapSpec, ObstacleSpec

SENSOR_RANGE = 1.5  # m: obstacles closer than this are seen
ARRIVED = 0.05  # m
STUCK_WINDOW = 2.0  # s without progress
STUCK_PROGRESS = 0.05  # m
MARGIN = 0.05  # m of clearance added to the robot's radius when planning

Point = tuple[float, float]


@dataclass(frozen=True)
class Happening:
    """Something the map reports: an event name (the backend name) and its fields."""

    event: str
    fields: Mapping[str, Any]


class Grid:
    """An occupancy grid inflated by the robot's radius (so the robot is a point on it)."""

    def __init__(self, width: float, height: float, resolution: float, inflate: float) -> None:
        self.res = resolution
        self.nx = max(1, math.ceil(width / resolution))
        self.ny = max(1, math.ceil(height / resolution))
        self.inflate = inflate
        self.blocked = bytearray(self.nx * self.ny)

    def cell(self, p: Point) -> tuple[int, int]:
        i = min(self.nx - 1, max(0, int(p[0] / self.res)))
        j = min(self.ny - 1, max(0, int(p[1] / self.res)))
        return i, j

    def center(self, i: int, j: int) -> Point:
        return ((i + 0.5) * self.res, (j + 0.5) * self.res)

    def free(self, i: int, j: int) -> bool:
        return 0 <= i < self.nx and 0 <= j < self.ny and not self.blocked[j * self.nx + i]

    def _mark(self, box: tuple[float, float, float, float], distance: Any, reach: float) -> None:
        x0, y0, x1, y1 = box
        i0, j0 = self.cell((x0 - reach, y0 - reach))
        i1, j1 = self.cell((x1 + reach, y1 + reach))
        for j in range(j0, j1 + 1):
            for i in range(i0, i1 + 1):
                if distance(self.center(i, j)) <= reach:
                    self.blocked[j * self.nx + i] = 1

    def add_segment(self, a: Point, b: Point, thickness: float) -> None:
        box = (min(a[0], b[0]), min(a[1], b[1]), max(a[0], b[0]), max(a[1], b[1]))
        self._mark(box, lambda p: _segment_distance(p, a, b), thickness / 2 + self.inflate)

    def add_rect(self, rect: tuple[float, float, float, float]) -> None:
        self._mark(rect, lambda p: _rect_distance(p, rect), self.inflate)

    def line_free(self, p: Point, q: Point) -> bool:
        n = max(1, int(math.dist(p, q) / (self.res / 2)))
        nx, ny, res, blocked = self.nx, self.ny, self.res, self.blocked
        dx, dy = (q[0] - p[0]) / n, (q[1] - p[1]) / n
        for k in range(n + 1):
            i = int((p[0] + dx * k) / res)
            j = int((p[1] + dy * k) / res)
            if not (0 <= i < nx and 0 <= j < ny) or blocked[j * nx + i]:
                return False
        return True

    def plan(self, start: Point, goal: Point) -> list[Point] | None:
        """A shortest 8-connected path from `start` to `goal`, shortcut to few waypoints;
        None when the goal cannot be reached."""
        s, g = self.cell(start), self.cell(goal)
        if not self.free(*g):
            return None
        escape: list[Point] = []
        if not self.free(*s):
            # The robot stands inside the inflated zone (it touches a wall): leave it by the
            # nearest free cell.
            near = self._nearest_free(s)
            if near is None:
                return None
            escape = [self.center(*near)]
            s = near
        nx, ny, blocked = self.nx, self.ny, self.blocked
        start_index, goal_index = s[1] * nx + s[0], g[1] * nx + g[0]
        gi, gj = g
        diagonal = math.sqrt(2)
        extra = diagonal - 1
        cost = [math.inf] * (nx * ny)
        came = [-1] * (nx * ny)
        cost[start_index] = 0.0
        frontier = [(0.0, 0.0, start_index)]
        found = False
        while frontier:
            _, c, here = heapq.heappop(frontier)
            if here == goal_index:
                found = True
                break
            if c > cost[here]:
                continue
            j, i = divmod(here, nx)
            candidates: list[tuple[int, int, float]] = []
            for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                ni, nj = i + di, j + dj
                if 0 <= ni < nx and 0 <= nj < ny and not blocked[nj * nx + ni]:
                    candidates.append((ni, nj, 1.0))
            for di, dj in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                ni, nj = i + di, j + dj
                if (
                    0 <= ni < nx
                    and 0 <= nj < ny
                    and not blocked[nj * nx + ni]
                    and not blocked[j * nx + ni]  # no corner cutting
                    and not blocked[nj * nx + i]
                ):
                    candidates.append((ni, nj, diagonal))
            for ni, nj, step in candidates:
                n = nj * nx + ni
                nc = c + step
                if nc < cost[n]:
                    cost[n] = nc
                    came[n] = here
                    hx, hy = abs(ni - gi), abs(nj - gj)
                    heapq.heappush(frontier, (nc + max(hx, hy) + extra * min(hx, hy), nc, n))
        if not found:
            return None
        cells = [goal_index]
        while cells[-1] != start_index:
            cells.append(came[cells[-1]])
        cells.reverse()
        points = [*escape, *(self.center(c % nx, c // nx) for c in cells[1:-1]), goal]
        return self._shortcut(start if not escape else escape[0], points)

    def _nearest_free(self, s: tuple[int, int]) -> tuple[int, int] | None:
        seen = {s}
        queue = [s]
        for here in queue:
            if self.free(*here):
                return here
            i, j = here
            for n in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
                if n not in seen and 0 <= n[0] < self.nx and 0 <= n[1] < self.ny:
                    seen.add(n)
                    queue.append(n)
            if len(queue) > 400:
                return None
        return None

    def _shortcut(self, start: Point, points: list[Point]) -> list[Point]:
        """Drop waypoints that a straight line can skip (string pulling)."""
        result: list[Point] = []
        anchor = start
        for k in range(len(points) - 1):
            if not self.line_free(anchor, points[k + 1]):
                result.append(points[k])
                anchor = points[k]
        result.append(points[-1])
        return result


@dataclass
class Obstacle:
    spec: ObstacleSpec
    shape: pymunk.Poly
    known: bool = False


class MapScene:
    def __init__(self, spec: MapSpec) -> None:
        self.spec = spec
        space = pymunk.Space()
        space.iterations = 10
        space.collision_slop = 0.002
        self.space = space
        for x1, y1, x2, y2 in spec.walls:
            wall = pymunk.Segment(space.static_body, (x1, y1), (x2, y2), spec.wall_thickness / 2)
            wall.friction = 0.0
            space.add(wall)
        self.robot = pymunk.Body(10.0, math.inf)
        start = spec.frame(spec.robot_start) if spec.robot_start else (spec.frames[0] if spec.frames else None)
        self.robot.position = (start.x, start.y) if start is not None else (spec.width / 2, spec.height / 2)
        body_shape = pymunk.Circle(self.robot, spec.robot_radius)
        body_shape.friction = 0.0
        body_shape.elasticity = 0.0
        space.add(self.robot, body_shape)
        # Velocity control as on a real base: a kinematic body moves at the commanded velocity
        # and drags the robot along through a joint of limited force (no position correction),
        # so contacts win: a wall stops the robot instead of letting it sink in.
        self.control = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.control.position = self.robot.position
        drive = pymunk.PivotJoint(self.control, self.robot, (0.0, 0.0), (0.0, 0.0))
        drive.max_bias = 0.0
        drive.max_force = 10.0 * 30.0  # mass * 30 m/s^2
        space.add(self.control, drive)
        self.grid = Grid(spec.width, spec.height, spec.resolution, spec.robot_radius + MARGIN)
        for x1, y1, x2, y2 in spec.walls:
            self.grid.add_segment((x1, y1), (x2, y2), spec.wall_thickness)
        self.heading = 0.0
        self.path: list[Point] = []
        self.trail: list[Point] = [self.position]
        self.obstacles: list[Obstacle] = []
        self.battery = spec.battery
        self._reported = self._bucket(spec.battery) if spec.battery is not None else 0
        self._last = self.position
        self._inside = {r.name for r in spec.regions if r.contains(*self.position)}
        self.fired: set[str] = set()
        self.busy: str | None = None
        self.phase = ""
        self.awake = False
        self.distance = 0.0

    @property
    def position(self) -> Point:
        p = self.robot.position
        return (float(p.x), float(p.y))

    def at_frame(self, name: str, tolerance: float = 0.3) -> bool:
        frame = self.spec.frame(name)
        return frame is not None and math.dist(self.position, (frame.x, frame.y)) <= tolerance

    def nearest_frame(self) -> tuple[str, float] | None:
        best = min(self.spec.frames, key=lambda f: math.dist(self.position, (f.x, f.y)), default=None)
        return (best.name, math.dist(self.position, (best.x, best.y))) if best is not None else None

    # ---------------------------------------------------------------- physics

    def add_obstacle(self, spec: ObstacleSpec) -> None:
        x0, y0, x1, y1 = spec.rect
        shape = pymunk.Poly(self.space.static_body, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
        shape.friction = 0.0
        self.space.add(shape)
        self.obstacles.append(Obstacle(spec, shape))

    def step(self, dt: float) -> list[Happening]:
        self.space.step(dt)
        here = self.position
        moved = math.dist(here, self._last)
        self._last = here
        happenings: list[Happening] = []
        if moved > 1e-9:
            self.distance += moved
            if len(self.trail) == 0 or math.dist(self.trail[-1], here) > 0.1:
                self.trail.append(here)
            if self.battery is not None and self.battery > 0:
                self.battery = max(0.0, self.battery - self.spec.drain_per_meter * moved)
                bucket = self._bucket(self.battery)
                if bucket < self._reported:
                    self._reported = bucket
                    level = bucket * self.spec.report_every if self.battery > 0 else 0.0
                    happenings.append(Happening("/battery", {"level": _tidy(level)}))
            for region in self.spec.regions:
                inside = region.contains(*here)
                if inside and region.name not in self._inside:
                    self._inside.add(region.name)
                    if not (region.once and region.name in self.fired):
                        self.fired.add(region.name)
                        happenings.append(Happening(region.event, dict(region.fields)))
                elif not inside:
                    self._inside.discard(region.name)
        return happenings

    def battery_report(self) -> Happening | None:
        if self.battery is None:
            return None
        return Happening("/battery", {"level": _tidy(self._reported * self.spec.report_every)})

    def _bucket(self, level: float) -> int:
        return math.ceil(level / self.spec.report_every - 1e-9)

    def stop(self) -> None:
        self.control.velocity = (0.0, 0.0)
        self.robot.velocity = (0.0, 0.0)

    def unknown_obstacles(self) -> bool:
        return any(not o.known for o in self.obstacles)

    def sees_new_obstacle(self) -> Obstacle | None:
        here = self.position
        for o in self.obstacles:
            if not o.known and _rect_distance(here, o.spec.rect) <= SENSOR_RANGE + self.spec.robot_radius:
                o.known = True
                self.grid.add_rect(o.spec.rect)
                return o
        return None

    # ---------------------------------------------------------------- the task

    def navigate(self, frame: str, dt: float) -> Task:
        """Drive to `frame` along a planned path; fails when no path exists, the robot makes no
        progress, or the battery is empty."""
        goal_frame = self.spec.frame(frame)
        if goal_frame is None:
            return fail(unknown(f"frame `{frame}` on the map", frame, (f.name for f in self.spec.frames)))
        goal = (goal_frame.x, goal_frame.y)
        if self.battery is not None and self.battery <= 0:
            return fail("the battery is empty")
        self.phase = "plan"
        while self.sees_new_obstacle() is not None:
            pass
        path = self.grid.plan(self.position, goal)
        if path is None:
            return fail(f"no path to frame `{frame}`")
        self.path = path
        suffix = _suffixes(path)
        index = 0
        speed = self.spec.robot_speed
        best = math.inf
        progress_t = elapsed = 0.0
        self.phase = "drive"
        try:
            while True:
                here = self.position
                if math.dist(here, goal) <= ARRIVED:
                    return final()
                if self.battery is not None and self.battery <= 0:
                    return fail(f"the battery is empty: the robot stopped at ({here[0]:.2f}, {here[1]:.2f})")
                seen = self.sees_new_obstacle() if self.unknown_obstacles() else None
                if seen is not None:
                    while self.sees_new_obstacle() is not None:
                        pass
                    replanned = self.grid.plan(here, goal)
                    if replanned is None:
                        self.path = []
                        return fail(f"no path to frame `{frame}`: `{seen.spec.name}` blocks the way")
                    self.path, suffix, index = replanned, _suffixes(replanned), 0
                    best, progress_t = math.inf, elapsed
                path = self.path
                while index < len(path) - 1 and math.dist(here, path[index]) < 0.15:
                    index += 1
                tx, ty = path[index]
                dx, dy = tx - here[0], ty - here[1]
                dist = math.hypot(dx, dy)
                left = dist + suffix[index]
                if left < best - STUCK_PROGRESS:
                    best, progress_t = left, elapsed
                elif elapsed - progress_t > STUCK_WINDOW:
                    return fail(f"stuck at ({here[0]:.2f}, {here[1]:.2f}) on the way to `{frame}`")
                v = min(speed, max(0.15, 2.0 * left), dist / dt)
                if dist > 1e-9:
                    self.control.velocity = (dx / dist * v, dy / dist * v)
                    self.heading = math.atan2(dy, dx)
                yield
                elapsed += dt
        finally:
            self.stop()


def _suffixes(path: list[Point]) -> list[float]:
    """suffix[i]: the length of the path from waypoint i to its end."""
    suffix = [0.0] * len(path)
    for i in range(len(path) - 2, -1, -1):
        suffix[i] = suffix[i + 1] + math.dist(path[i], path[i + 1])
    return suffix


def _segment_distance(p: Point, a: Point, b: Point) -> float:
    ax, ay = a
    bx, by = b
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / length2))
    return math.hypot(p[0] - (ax + t * dx), p[1] - (ay + t * dy))


def _rect_distance(p: Point, rect: tuple[float, float, float, float]) -> float:
    x0, y0, x1, y1 = rect
    dx = max(x0 - p[0], 0.0, p[0] - x1)
    dy = max(y0 - p[1], 0.0, p[1] - y1)
    return math.hypot(dx, dy)


def _tidy(level: float) -> int | float:
    return int(level) if float(level).is_integer() else round(level, 2)
