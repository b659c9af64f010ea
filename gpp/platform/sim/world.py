"""Worlds as data: the TOML files that describe what the sim platform simulates.

A world has up to two scenes and a fault section:

* `[workbench]` (side view, gravity, centimetres): a table with named slots, dynamic blocks
  with a size, mass, friction and an initial support (`on = "t1"` or `on = "b"`), and a
  kinematic gripper. Optionally `frame = "table"`: the map frame where the robot must stand
  to use the gripper.
* `[map]` (top view, no gravity, metres): walls, named frames, a round robot, a battery and
  regions that emit exogenous events when the robot enters them.
* `[faults]`: a seed, the probability that a grasp slips, obstacles that appear at given
  times on the map.

`World.load(name_or_path)` finds a world by file path, else by name in `stdlib/worlds/`
(an unknown name is an error that lists the available worlds with a did-you-mean). Every
problem in a world file is a WorldError with the file and the entry that is wrong.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gpp.base.numbers import MAX_SECONDS, bound_text, describe
from gpp.base.resources import stdlib_dir
from gpp.base.suggest import closest

DEFAULT_WORLD = "blocksworld"

# The ranges of a world's numbers (docs/semantics.md, "Numbers"): coordinates and lengths of the
# workbench (cm) and of the map's frames, regions and obstacles are within ±LIMIT; a map is at
# most MAX_MAP_SIZE metres a side and MAX_MAP_CELLS grid cells.
LIMIT = 10_000.0
MAX_MAP_SIZE = 10_000.0
MAX_MAP_CELLS = 4_000_000


class WorldError(ValueError):
    """A world that cannot be loaded or used; the message says where and why."""


@dataclass(frozen=True)
class SlotSpec:
    name: str
    x: float
    width: float


@dataclass(frozen=True)
class BlockSpec:
    name: str
    width: float
    height: float
    mass: float
    friction: float
    on: str
    color: str


@dataclass(frozen=True)
class WorkbenchSpec:
    width: float
    table_left: float
    table_right: float
    table_top: float
    slots: tuple[SlotSpec, ...]
    blocks: tuple[BlockSpec, ...]
    gripper_speed: float = 200.0
    gripper_home: tuple[float, float] | None = None
    frame: str | None = None
    iterations: int = 30
    gravity: float = 981.0

    def slot(self, name: str) -> SlotSpec | None:
        return next((s for s in self.slots if s.name == name), None)

    def block(self, name: str) -> BlockSpec | None:
        return next((b for b in self.blocks if b.name == name), None)

    @property
    def travel_height(self) -> float:
        """Above the tallest tower the blocks can make, with room for a carried block."""
        stacked = sum(max(b.width, b.height) for b in self.blocks)
        tallest = max((max(b.width, b.height) for b in self.blocks), default=0.0)
        return self.table_top + stacked + tallest + 30.0

    @property
    def home(self) -> tuple[float, float]:
        if self.gripper_home is not None:
            return self.gripper_home
        return ((self.table_left + self.table_right) / 2, self.travel_height)


@dataclass(frozen=True)
class FrameSpec:
    name: str
    x: float
    y: float


@dataclass(frozen=True)
class RegionSpec:
    """An area of the map; entering it emits `event` with `fields` (once, if `once`)."""

    name: str
    event: str
    fields: Mapping[str, Any]
    rect: tuple[float, float, float, float] | None = None
    circle: tuple[float, float, float] | None = None
    once: bool = True
    kind: str = "region"

    def contains(self, x: float, y: float) -> bool:
        if self.rect is not None:
            x0, y0, x1, y1 = self.rect
            return x0 <= x <= x1 and y0 <= y <= y1
        assert self.circle is not None
        cx, cy, r = self.circle
        return (x - cx) ** 2 + (y - cy) ** 2 <= r * r


@dataclass(frozen=True)
class ObstacleSpec:
    name: str
    at: float
    rect: tuple[float, float, float, float]


@dataclass(frozen=True)
class MapSpec:
    width: float
    height: float
    walls: tuple[tuple[float, float, float, float], ...]
    frames: tuple[FrameSpec, ...]
    regions: tuple[RegionSpec, ...] = ()
    resolution: float = 0.1
    robot_radius: float = 0.25
    robot_speed: float = 0.8
    robot_start: str | None = None
    battery: float | None = None  # initial level in percent; None: no battery
    drain_per_meter: float = 1.0
    report_every: float = 5.0
    wall_thickness: float = 0.1

    def frame(self, name: str) -> FrameSpec | None:
        return next((f for f in self.frames if f.name == name), None)


@dataclass(frozen=True)
class FaultSpec:
    seed: int | None = None
    grasp_slip: float = 0.0
    obstacles: tuple[ObstacleSpec, ...] = ()


@dataclass(frozen=True)
class World:
    name: str
    description: str = ""
    workbench: WorkbenchSpec | None = None
    map: MapSpec | None = None
    faults: FaultSpec = field(default_factory=FaultSpec)
    dt: float = 1 / 60
    path: Path | None = None

    # ---------------------------------------------------------------- loading

    @staticmethod
    def directory() -> Path:
        return stdlib_dir() / "worlds"

    @classmethod
    def available(cls) -> list[str]:
        return sorted(p.stem for p in cls.directory().glob("*.toml"))

    @classmethod
    def find(cls, name: str, base: Path | None = None) -> Path:
        """The file of world `name`: a path (absolute, or relative to `base` and then to the
        working directory), else `stdlib/worlds/NAME.toml`."""
        candidates: list[Path] = []
        for stem in (name, name + ".toml") if not name.endswith(".toml") else (name,):
            p = Path(stem)
            if p.is_absolute():
                candidates.append(p)
            else:
                if base is not None:
                    candidates.append(base / p)
                candidates.append(p)
        if "/" not in name and "\\" not in name:
            candidates.append(cls.directory() / (name if name.endswith(".toml") else name + ".toml"))
        for c in candidates:
            if c.is_file():
                return c
        known = cls.available()
        hint = closest(name.removesuffix(".toml"), known)
        message = f"no world `{name}` (available: {', '.join(known)}; or give the path of a .toml file)"
        if hint:
            message += f"; did you mean `{hint}`?"
        raise WorldError(message)

    @classmethod
    def load(cls, name: str | None = None, base: Path | None = None) -> World:
        path = cls.find(name or DEFAULT_WORLD, base)
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except OSError as e:
            raise WorldError(f"cannot read world '{path}': {e.strerror}") from None
        except tomllib.TOMLDecodeError as e:
            raise WorldError(f"world '{path}' is not valid TOML: {e}") from None
        except UnicodeDecodeError:
            raise WorldError(f"world '{path}' is not UTF-8 text") from None
        except ValueError:  # tomllib refuses a whole number of thousands of digits
            raise WorldError(f"world '{path}' has a whole number beyond the range of numbers") from None
        return cls.from_data(data, path)

    @classmethod
    def from_data(cls, data: Mapping[str, Any], path: Path | None = None) -> World:
        where = str(path) if path is not None else "world"
        r = _Reader(data, where)
        r.only({"name", "description", "dt", "workbench", "map", "faults"})
        name = r.text("name", path.stem if path is not None else "world")
        world = cls(
            name=name,
            description=r.text("description", ""),
            workbench=_workbench(r.table("workbench"), where) if "workbench" in data else None,
            map=_map(r.table("map"), where) if "map" in data else None,
            faults=_faults(r.table("faults"), where) if "faults" in data else FaultSpec(),
            dt=r.number("dt", 1 / 60, low=1e-4, high=0.1),
            path=path,
        )
        world.validate()
        return world

    def validate(self) -> None:
        where = str(self.path) if self.path is not None else "world"
        if self.workbench is None and self.map is None:
            raise WorldError(f"{where}: a world needs a [workbench] or a [map] (or both)")
        wb = self.workbench
        if wb is not None:
            names = [s.name for s in wb.slots] + [b.name for b in wb.blocks]
            dup = sorted({n for n in names if names.count(n) > 1})
            if dup:
                raise WorldError(f"{where}: [workbench] names used twice: {', '.join(dup)}")
            reserved = {"table", "floor"} & set(names)
            if reserved:
                raise WorldError(f"{where}: `table` and `floor` are reserved location names, not slots or blocks")
            for s in wb.slots:
                if not wb.table_left + s.width / 2 <= s.x <= wb.table_right - s.width / 2:
                    raise WorldError(f"{where}: slot `{s.name}` at x = {s.x:g} is not on the table")
            _placement_order(wb, where)  # every block rests on something, no cycles
            if wb.frame is not None and (self.map is None or self.map.frame(wb.frame) is None):
                raise WorldError(f"{where}: [workbench] frame `{wb.frame}` is not a frame of the [map]")
        m = self.map
        if m is not None:
            frames = [f.name for f in m.frames]
            dup = sorted({n for n in frames if frames.count(n) > 1})
            if dup:
                raise WorldError(f"{where}: [map] frames defined twice: {', '.join(dup)}")
            if m.robot_start is not None and m.frame(m.robot_start) is None:
                hint = _did_you_mean(m.robot_start, frames)
                raise WorldError(f"{where}: [map.robot] start `{m.robot_start}` is not a frame{hint}")
            for f in m.frames:
                if not (0 <= f.x <= m.width and 0 <= f.y <= m.height):
                    raise WorldError(f"{where}: frame `{f.name}` lies outside the map")
        if self.faults.obstacles and m is None:
            raise WorldError(f"{where}: [[faults.obstacle]] needs a [map]")
        if self.faults.grasp_slip and wb is None:
            raise WorldError(f"{where}: [faults] grasp_slip needs a [workbench]")

    # ---------------------------------------------------------------- what it serves

    def region_events(self) -> dict[str, tuple[str, ...]]:
        """Exogenous event names the world's regions emit -> their field names."""
        events: dict[str, tuple[str, ...]] = {}
        if self.map is not None:
            for region in self.map.regions:
                events.setdefault(region.event, tuple(sorted(region.fields)))
        return events


def _placement_order(wb: WorkbenchSpec, where: str) -> list[BlockSpec]:
    """Blocks in an order where each block's support is placed before it."""
    placed: dict[str, BlockSpec] = {}
    order: list[BlockSpec] = []
    pending = list(wb.blocks)
    slots = {s.name for s in wb.slots}
    occupied: dict[str, str] = {}
    while pending:
        progress = False
        for b in list(pending):
            if b.on in slots or b.on in placed:
                if b.on in occupied:
                    raise WorldError(f"{where}: blocks `{occupied[b.on]}` and `{b.name}` are both on `{b.on}`")
                occupied[b.on] = b.name
                placed[b.name] = b
                order.append(b)
                pending.remove(b)
                progress = True
            elif b.on not in slots and wb.block(b.on) is None:
                hint = _did_you_mean(b.on, sorted(slots | {x.name for x in wb.blocks}))
                raise WorldError(f"{where}: block `{b.name}` is on `{b.on}`, which is no slot or block{hint}")
        if not progress:
            raise WorldError(f"{where}: blocks {', '.join(b.name for b in pending)} rest on each other in a cycle")
    return order


def placement_order(wb: WorkbenchSpec) -> list[BlockSpec]:
    return _placement_order(wb, "world")


def _did_you_mean(name: str, known: list[str]) -> str:
    hint = closest(name, known)
    return f" (did you mean `{hint}`?)" if hint else f" (known: {', '.join(known)})" if known else ""


class _Reader:
    """Typed access to one TOML table, with messages that say which entry is wrong."""

    def __init__(self, data: Mapping[str, Any], where: str) -> None:
        if not isinstance(data, Mapping):
            raise WorldError(f"{where} must be a table")
        self.data = data
        self.where = where

    def only(self, known: set[str]) -> None:
        unknown = sorted(set(self.data) - known)
        if unknown:
            hints = [f"`{k}`" + _did_you_mean(k, sorted(known)) for k in unknown]
            raise WorldError(f"{self.where}: unknown key(s) {', '.join(hints)}")

    def table(self, key: str) -> _Reader:
        return _Reader(self.data.get(key, {}), f"{self.where} [{key}]")

    def tables(self, key: str) -> list[_Reader]:
        items = self.data.get(key, [])
        if not isinstance(items, list):
            raise WorldError(f"{self.where}: `{key}` must be an array of tables ([[...{key}]])")
        return [_Reader(item, f"{self.where} [[{key}]] #{i + 1}") for i, item in enumerate(items)]

    def text(self, key: str, default: str | None = None) -> str:
        v = self.data.get(key, default)
        if not isinstance(v, str):
            raise WorldError(f"{self.where}: `{key}` must be a string" + ("" if key in self.data else " (required)"))
        return v

    def optional_text(self, key: str) -> str | None:
        return self.text(key) if key in self.data else None

    def number(self, key: str, default: float | None = None, low: float = -LIMIT, high: float = LIMIT) -> float:
        """A number between `low` and `high` (never NaN or an infinity)."""
        v = self.data.get(key, default)
        if isinstance(v, bool) or not isinstance(v, int | float):
            raise WorldError(f"{self.where}: `{key}` must be a number" + ("" if key in self.data else " (required)"))
        if not low <= v <= high:  # also false for NaN
            raise WorldError(
                f"{self.where}: `{key}` must be between {bound_text(low)} and {bound_text(high)}, not {describe(v)}"
            )
        return float(v)

    def numbers(
        self,
        key: str,
        n: int,
        default: tuple[float, ...] | None = None,
        low: float = -LIMIT,
        high: float = LIMIT,
    ) -> tuple[float, ...]:
        """A list of `n` numbers, each between `low` and `high`."""
        v = self.data.get(key, default)
        if (
            not isinstance(v, list | tuple)
            or len(v) != n
            or any(isinstance(x, bool) or not isinstance(x, int | float) for x in v)
        ):
            raise WorldError(f"{self.where}: `{key}` must be a list of {n} numbers")
        for x in v:
            if not low <= x <= high:
                raise WorldError(
                    f"{self.where}: `{key}` must be a list of {n} numbers between {bound_text(low)} and "
                    f"{bound_text(high)}, not {describe(x)}"
                )
        return tuple(float(x) for x in v)

    def flag(self, key: str, default: bool) -> bool:
        v = self.data.get(key, default)
        if not isinstance(v, bool):
            raise WorldError(f"{self.where}: `{key}` must be true or false")
        return v


def _workbench(r: _Reader, where: str) -> WorkbenchSpec:
    r.only({"frame", "width", "table", "gripper", "slot", "block", "iterations", "gravity"})
    table = r.table("table")
    table.only({"left", "right", "top"})
    gripper = r.table("gripper")
    gripper.only({"speed", "home"})
    slots: list[SlotSpec] = []
    for s in r.tables("slot"):
        s.only({"name", "x", "width"})
        slots.append(SlotSpec(s.text("name"), s.number("x"), s.number("width", 60.0, low=1.0, high=LIMIT)))
    blocks: list[BlockSpec] = []
    palette = ["#d1495b", "#2e86ab", "#edae49", "#66a182", "#8d6a9f", "#e07a5f", "#3d405b", "#81b29a"]
    for i, b in enumerate(r.tables("block")):
        b.only({"name", "size", "mass", "friction", "on", "color"})
        w, h = b.numbers("size", 2, (40.0, 40.0), low=1.0, high=1000.0)
        blocks.append(
            BlockSpec(
                b.text("name"),
                w,
                h,
                b.number("mass", 1.0, low=0.01, high=1000.0),
                b.number("friction", 0.7, low=0.0, high=10.0),
                b.text("on"),
                b.text("color", palette[i % len(palette)]),
            )
        )
    home = gripper.numbers("home", 2) if "home" in gripper.data else None
    return WorkbenchSpec(
        width=r.number("width", 600.0, low=100.0, high=LIMIT),
        table_left=table.number("left", 60.0, low=0.0, high=LIMIT),
        table_right=table.number("right", 540.0, low=0.0, high=LIMIT),
        table_top=table.number("top", 75.0, low=0.0, high=LIMIT),
        slots=tuple(slots),
        blocks=tuple(blocks),
        gripper_speed=gripper.number("speed", 200.0, low=1.0, high=LIMIT),
        gripper_home=(home[0], home[1]) if home is not None else None,
        frame=r.optional_text("frame"),
        iterations=int(r.number("iterations", 30, low=1, high=200)),
        gravity=r.number("gravity", 981.0, low=0.0, high=LIMIT),
    )


def _map(r: _Reader, where: str) -> MapSpec:
    r.only({"size", "resolution", "walls", "robot", "battery", "frame", "region", "wall_thickness"})
    width, height = r.numbers("size", 2, low=0.1, high=MAX_MAP_SIZE)
    resolution = r.number("resolution", 0.1, low=0.01, high=1.0)
    cells = math.ceil(width / resolution) * math.ceil(height / resolution)
    if cells > MAX_MAP_CELLS:
        raise WorldError(
            f"{r.where}: a map of {width:g} x {height:g} m at a `resolution` of {resolution:g} m has {cells} grid "
            f"cells, at most {MAX_MAP_CELLS} are allowed (make the map smaller or the resolution coarser)"
        )
    walls = r.data.get("walls", [])
    if not isinstance(walls, list) or any(
        not isinstance(w, list) or len(w) != 4 or any(isinstance(x, bool) or not isinstance(x, int | float) for x in w)
        for w in walls
    ):
        raise WorldError(f"{r.where}: `walls` must be a list of [x1, y1, x2, y2] segments")
    for w in walls:
        for x in w:
            if not -MAX_MAP_SIZE <= x <= MAX_MAP_SIZE:
                raise WorldError(
                    f"{r.where}: `walls` must hold coordinates between {bound_text(-MAX_MAP_SIZE)} and "
                    f"{bound_text(MAX_MAP_SIZE)}, not {describe(x)}"
                )
    robot = r.table("robot")
    robot.only({"radius", "speed", "start"})
    battery = r.table("battery")
    battery.only({"level", "drain_per_meter", "report_every"})
    frames: list[FrameSpec] = []
    for f in r.tables("frame"):
        f.only({"name", "at"})
        x, y = f.numbers("at", 2)
        frames.append(FrameSpec(f.text("name"), x, y))
    regions: list[RegionSpec] = []
    for g in r.tables("region"):
        g.only({"name", "rect", "circle", "event", "fields", "once", "kind"})
        rect = g.numbers("rect", 4) if "rect" in g.data else None
        circle = g.numbers("circle", 3) if "circle" in g.data else None
        if (rect is None) == (circle is None):
            raise WorldError(f"{g.where}: give either `rect = [x0, y0, x1, y1]` or `circle = [x, y, r]`")
        fields = g.data.get("fields", {})
        if not isinstance(fields, dict):
            raise WorldError(f'{g.where}: `fields` must be a table like {{ id = "v1" }}')
        regions.append(
            RegionSpec(
                g.text("name"),
                g.text("event"),
                dict(fields),
                (rect[0], rect[1], rect[2], rect[3]) if rect else None,
                (circle[0], circle[1], circle[2]) if circle else None,
                g.flag("once", True),
                g.text("kind", "region"),
            )
        )
    return MapSpec(
        width=width,
        height=height,
        walls=tuple((float(a), float(b), float(c), float(d)) for a, b, c, d in walls),
        frames=tuple(frames),
        regions=tuple(regions),
        resolution=resolution,
        robot_radius=robot.number("radius", 0.25, low=0.01, high=100.0),
        robot_speed=robot.number("speed", 0.8, low=0.01, high=100.0),
        robot_start=robot.optional_text("start"),
        battery=battery.number("level", 100.0, low=0.0, high=100.0) if "battery" in r.data else None,
        drain_per_meter=battery.number("drain_per_meter", 1.0, low=0.0, high=100.0),
        report_every=battery.number("report_every", 5.0, low=0.1, high=MAX_SECONDS),
        wall_thickness=r.number("wall_thickness", 0.1, low=0.01, high=10.0),
    )


def _faults(r: _Reader, where: str) -> FaultSpec:
    r.only({"seed", "grasp_slip", "obstacle"})
    obstacles: list[ObstacleSpec] = []
    for o in r.tables("obstacle"):
        o.only({"name", "at", "rect"})
        x0, y0, x1, y1 = o.numbers("rect", 4)
        obstacles.append(
            ObstacleSpec(
                o.text("name", f"obstacle{len(obstacles) + 1}"),
                o.number("at", low=0.0, high=MAX_SECONDS),
                (x0, y0, x1, y1),
            )
        )
    seed = r.data.get("seed")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int)):
        raise WorldError(f"{r.where}: `seed` must be a whole number")
    return FaultSpec(seed, r.number("grasp_slip", 0.0, low=0.0, high=1.0), tuple(obstacles))
