"""Frames of the sim rendered with Pillow: the map (top view: walls, frames, regions, the robot,
its planned path and trail, obstacles, the battery) beside the workbench (side view: table,
slots, labelled blocks, the gripper), with the time and the running actions as a caption.

`Recorder` samples frames at a fixed sim-time interval for `--record run.gif` (an animated
GIF played a few times faster than sim time, on one shared palette to stay small) and keeps
the last frame for `--snapshot end.png`.
"""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

from PIL import Image, ImageDraw, ImageFont

from gpp.platform.sim.world import World

if TYPE_CHECKING:
    from gpp.platform.sim.navigation import MapScene
    from gpp.platform.sim.workbench import Workbench


class Scene(Protocol):
    """What a frame shows of the sim (gpp.platform.sim.platform.SimPlatform is one)."""

    world: World
    map: MapScene | None
    workbench: Workbench | None
    clock: float

    def caption(self) -> str:
        """The running actions, as the frame's caption."""
        ...


Color = tuple[int, int, int]

BACKGROUND: Color = (250, 249, 246)
PANEL: Color = (255, 255, 255)
INK: Color = (33, 37, 41)
MUTED: Color = (134, 142, 150)
LIGHT: Color = (222, 226, 230)
WALL: Color = (52, 58, 64)
WOOD: Color = (166, 124, 82)
WOOD_DARK: Color = (120, 88, 58)
ROBOT: Color = (25, 113, 194)
PATH: Color = (77, 171, 247)
TRAIL: Color = (190, 200, 210)
FRAME: Color = (112, 72, 232)
REGION: Color = (253, 126, 20)
FOUND: Color = (47, 158, 68)
OBSTACLE: Color = (201, 42, 42)
CAPTION: Color = (241, 243, 245)
GRIPPER: Color = (73, 80, 87)

PLAYBACK_SPEEDUP = 4.0  # the GIF plays this many times faster than sim time
CAPTION_HEIGHT = 40
PAD = 10


@cache
def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    return ImageFont.load_default(size=size)


def _rgb(text: str) -> Color:
    text = text.lstrip("#")
    if len(text) == 3:
        text = "".join(c * 2 for c in text)
    return (int(text[0:2], 16), int(text[2:4], 16), int(text[4:6], 16))


def _mix(a: Color, b: Color, t: float) -> Color:
    return (round(a[0] + (b[0] - a[0]) * t), round(a[1] + (b[1] - a[1]) * t), round(a[2] + (b[2] - a[2]) * t))


class Renderer:
    """Draws one frame of a world; the static parts are drawn once and reused."""

    def __init__(self, world: World, width: int | None = None) -> None:
        self.world = world
        both = world.map is not None and world.workbench is not None
        self.map_box: tuple[int, int, int, int] | None = None
        self.bench_box: tuple[int, int, int, int] | None = None
        self.map_scale = self.bench_scale = 1.0
        x = PAD
        height = 0
        if world.map is not None:
            m = world.map
            limit_w = 300 if both else (width or 640)
            self.map_scale = min(limit_w / m.width, 380 / m.height)
            w, h = round(m.width * self.map_scale), round(m.height * self.map_scale)
            self.map_box = (x, PAD + 18, x + w, PAD + 18 + h)
            x += w + PAD
            height = max(height, h + 18)
        if world.workbench is not None:
            wb = world.workbench
            limit_w = 440 if both else (width or 560)
            self.bench_scale = limit_w / wb.width
            top = wb.travel_height + 40
            w, h = round(wb.width * self.bench_scale), round(top * self.bench_scale)
            self.bench_box = (x, PAD + 18, x + w, PAD + 18 + h)
            x += w + PAD
            height = max(height, h + 18)
        self.size = (max(x, 320), PAD + height + PAD + CAPTION_HEIGHT)
        self.palette = self._palette()
        self._static = self._draw_static()

    # ---------------------------------------------------------------- coordinates

    def map_point(self, x: float, y: float) -> tuple[float, float]:
        assert self.map_box is not None
        x0, _, _, y1 = self.map_box
        return (x0 + x * self.map_scale, y1 - y * self.map_scale)

    def bench_point(self, x: float, y: float) -> tuple[float, float]:
        assert self.bench_box is not None
        x0, _, _, y1 = self.bench_box
        return (x0 + x * self.bench_scale, y1 - y * self.bench_scale)

    # ---------------------------------------------------------------- static parts

    def _draw_static(self) -> Image.Image:
        image = Image.new("RGB", self.size, BACKGROUND)
        draw = ImageDraw.Draw(image)
        title = _font(12)
        if self.map_box is not None and self.world.map is not None:
            m = self.world.map
            draw.rectangle(self.map_box, fill=PANEL, outline=LIGHT)
            draw.text((self.map_box[0], PAD), "map (top view)", fill=MUTED, font=title)
            for region in m.regions:
                self._region(draw, region.rect, region.circle, _mix(REGION, PANEL, 0.85), None)
            width = max(2, round(m.wall_thickness * self.map_scale))
            for x1, y1, x2, y2 in m.walls:
                draw.line([self.map_point(x1, y1), self.map_point(x2, y2)], fill=WALL, width=width)
            for f in m.frames:
                px, py = self.map_point(f.x, f.y)
                draw.line([(px - 4, py - 4), (px + 4, py + 4)], fill=FRAME, width=2)
                draw.line([(px - 4, py + 4), (px + 4, py - 4)], fill=FRAME, width=2)
                draw.text(
                    (px, py + 7 + m.robot_radius * self.map_scale), f.name, fill=FRAME, font=_font(11), anchor="mt"
                )
        if self.bench_box is not None and self.world.workbench is not None:
            wb = self.world.workbench
            draw.rectangle(self.bench_box, fill=PANEL, outline=LIGHT)
            draw.text((self.bench_box[0], PAD), "workbench (side view)", fill=MUTED, font=title)
            draw.line([self.bench_point(0, 0), self.bench_point(wb.width, 0)], fill=WALL, width=2)
            for leg_x in (wb.table_left + 12, wb.table_right - 12):
                draw.rectangle(
                    [self.bench_point(leg_x - 4, wb.table_top - 6), self.bench_point(leg_x + 4, 0)], fill=WOOD_DARK
                )
            draw.rectangle(
                [self.bench_point(wb.table_left, wb.table_top), self.bench_point(wb.table_right, wb.table_top - 6)],
                fill=WOOD,
            )
            for slot in wb.slots:
                left = self.bench_point(slot.x - slot.width / 2, wb.table_top - 6)
                right = self.bench_point(slot.x + slot.width / 2, wb.table_top - 6)
                draw.line([(left[0], left[1] + 3), (right[0], right[1] + 3)], fill=FRAME, width=2)
                cx, cy = self.bench_point(slot.x, wb.table_top - 6)
                _centered(draw, (cx, cy + 12), slot.name, FRAME, _font(11))
        draw.rectangle([0, self.size[1] - CAPTION_HEIGHT, self.size[0], self.size[1]], fill=CAPTION)
        return image

    def _region(
        self,
        draw: ImageDraw.ImageDraw,
        rect: tuple[float, float, float, float] | None,
        circle: tuple[float, float, float] | None,
        fill: Color | None,
        outline: Color | None,
    ) -> None:
        if rect is not None:
            x0, y0, x1, y1 = rect
            a, b = self.map_point(x0, y1), self.map_point(x1, y0)
            draw.rectangle([a, b], fill=fill, outline=outline, width=2)
        elif circle is not None:
            cx, cy, r = circle
            px, py = self.map_point(cx, cy)
            rr = r * self.map_scale
            draw.ellipse([px - rr, py - rr, px + rr, py + rr], fill=fill, outline=outline, width=2)

    # ---------------------------------------------------------------- a frame

    def draw(self, sim: Scene) -> Image.Image:
        image = self._static.copy()
        draw = ImageDraw.Draw(image)
        if sim.map is not None and self.map_box is not None:
            self._draw_map(draw, sim.map)
        if sim.workbench is not None and self.bench_box is not None:
            away = False
            frame = sim.workbench.spec.frame
            if frame is not None and sim.map is not None:
                away = not sim.map.at_frame(frame)
            self._draw_bench(draw, sim.workbench, away)
        y = self.size[1] - CAPTION_HEIGHT
        draw.text((PAD, y + 6), f"t = {sim.clock:6.1f} s", fill=INK, font=_font(14))
        caption = sim.caption()
        font = _font(13)
        while caption and draw.textlength(caption, font=font) > self.size[0] - 110 - PAD:
            caption = caption[:-2] + "…"
        draw.text((110, y + 7), caption, fill=INK, font=font)
        world = f"world {sim.world.name}"
        draw.text((PAD, y + 24), world, fill=MUTED, font=_font(10))
        return image

    def _draw_map(self, draw: ImageDraw.ImageDraw, m: MapScene) -> None:
        for region in m.spec.regions:
            if region.kind == "victim" or region.name in m.fired:
                color = FOUND if region.name in m.fired else REGION
                self._region(draw, region.rect, region.circle, None, color)
                if region.circle is not None:
                    px, py = self.map_point(region.circle[0], region.circle[1])
                    draw.ellipse([px - 4, py - 4, px + 4, py + 4], fill=color)
                    _centered(draw, (px, py + 12), region.name, color, _font(11))
        for o in m.obstacles:
            x0, y0, x1, y1 = o.spec.rect
            draw.rectangle([self.map_point(x0, y1), self.map_point(x1, y0)], fill=OBSTACLE)
        if len(m.trail) > 1:
            draw.line([self.map_point(*p) for p in m.trail], fill=TRAIL, width=2)
        if m.busy is not None and m.path:
            draw.line([self.map_point(*m.position)] + [self.map_point(*p) for p in m.path], fill=PATH, width=2)
            gx, gy = self.map_point(*m.path[-1])
            draw.ellipse([gx - 3, gy - 3, gx + 3, gy + 3], outline=PATH, width=2)
        px, py = self.map_point(*m.position)
        r = m.spec.robot_radius * self.map_scale
        draw.ellipse([px - r, py - r, px + r, py + r], fill=ROBOT, outline=INK)
        draw.line([(px, py), (px + math.cos(m.heading) * r, py - math.sin(m.heading) * r)], fill=PANEL, width=2)
        if m.battery is not None:
            assert self.map_box is not None
            x1, y0 = self.map_box[2], PAD
            level = max(0.0, min(100.0, m.battery))
            color = FOUND if level > 30 else REGION if level > 15 else OBSTACLE
            draw.rectangle([x1 - 60, y0 + 1, x1 - 10, y0 + 11], outline=INK)
            draw.rectangle([x1 - 59, y0 + 2, x1 - 59 + round(48 * level / 100), y0 + 10], fill=color)
            draw.text((x1 - 100, y0), f"{level:3.0f}%", fill=INK, font=_font(11))

    def _draw_bench(self, draw: ImageDraw.ImageDraw, wb: Workbench, away: bool) -> None:
        font = _font(max(10, round(18 * self.bench_scale / 0.8 * 0.8)))
        for block in wb.blocks.values():
            body = block.body
            points = [self.bench_point(*body.local_to_world(v)) for v in block.shape.get_vertices()]
            color = _rgb(block.spec.color)
            draw.polygon(points, fill=color, outline=INK)
            cx, cy = self.bench_point(body.position.x, body.position.y)
            _centered(draw, (cx, cy), block.name, PANEL, font)
        g = wb.gripper.position
        color = _mix(GRIPPER, PANEL, 0.6) if away else GRIPPER
        left, top = self.bench_point(g.x - 25, g.y + 5)
        right, bottom = self.bench_point(g.x + 25, g.y - 5)
        draw.rectangle([left, top, right, bottom], fill=color)
        mast = self.bench_point(g.x, g.y + 5)
        draw.line([mast, (mast[0], self.bench_box[1] if self.bench_box else 0)], fill=color, width=3)
        finger = 5 * self.bench_scale * 2
        for side in (left, right):
            draw.line([(side, bottom), (side, bottom + finger)], fill=color, width=3)
        if wb.grasp is not None:
            tip = self.bench_point(g.x, g.y - 5)
            draw.ellipse([tip[0] - 3, tip[1] - 3, tip[0] + 3, tip[1] + 3], fill=OBSTACLE)
        if away:
            assert self.bench_box is not None
            draw.text((self.bench_box[2] - 150, PAD), "robot away from the table", fill=MUTED, font=_font(11))

    # ---------------------------------------------------------------- palette

    def _palette(self) -> Image.Image:
        colors: list[Color] = [
            BACKGROUND, PANEL, INK, MUTED, LIGHT, WALL, WOOD, WOOD_DARK, ROBOT, PATH, TRAIL, FRAME,
            REGION, FOUND, OBSTACLE, CAPTION, GRIPPER, _mix(REGION, PANEL, 0.85), _mix(GRIPPER, PANEL, 0.6),
        ]  # fmt: skip
        if self.world.workbench is not None:
            colors += [_rgb(b.color) for b in self.world.workbench.blocks]
        # Ramps for anti-aliased text and edges.
        for base in (INK, FRAME, REGION, FOUND, ROBOT, MUTED):
            for bg in (PANEL, CAPTION):
                colors += [_mix(base, bg, t / 6) for t in range(1, 6)]
        if self.world.workbench is not None:
            for b in self.world.workbench.blocks:
                colors += [_mix(PANEL, _rgb(b.color), t / 4) for t in range(1, 4)]
        unique = list(dict.fromkeys(colors))[:256]
        flat = [c for color in unique for c in color]
        flat += flat[:3] * (256 - len(unique))
        palette = Image.new("P", (1, 1))
        palette.putpalette(flat)
        return palette

    def indexed(self, image: Image.Image) -> Image.Image:
        return image.quantize(palette=self.palette, dither=Image.Dither.NONE)


def _centered(
    draw: ImageDraw.ImageDraw,
    at: tuple[float, float],
    text: str,
    fill: Color,
    font: ImageFont.FreeTypeFont | ImageFont.ImageFont,
) -> None:
    draw.text(at, text, fill=fill, font=font, anchor="mm")


class Recorder:
    """Frames for `--record` (GIF) and `--snapshot` (PNG of the last frame)."""

    def __init__(self, world: World, gif: Path | None, png: Path | None, interval: float) -> None:
        self.renderer = Renderer(world)
        self.gif = gif
        self.png = png
        self.interval = interval
        self.frames: list[Image.Image] = []
        self.next_time = 0.0
        self.last: Image.Image | None = None

    def capture(self, sim: Scene, force: bool = False) -> None:
        if not force and (self.gif is None or sim.clock + 1e-9 < self.next_time):
            return
        image = self.renderer.draw(sim)
        self.last = image
        if self.gif is not None:
            self.frames.append(self.renderer.indexed(image))
            while self.next_time <= sim.clock + 1e-9:
                self.next_time += self.interval

    def save(self) -> None:
        if self.gif is not None and self.frames:
            frame_ms = max(20, round(self.interval * 1000 / PLAYBACK_SPEEDUP / 10) * 10)
            durations = [frame_ms] * len(self.frames)
            durations[-1] = 2000
            self.gif.parent.mkdir(parents=True, exist_ok=True)
            self.frames[0].save(
                self.gif, save_all=True, append_images=self.frames[1:], duration=durations, loop=0, optimize=True
            )
        if self.png is not None and self.last is not None:
            self.png.parent.mkdir(parents=True, exist_ok=True)
            self.last.save(self.png)


def snapshot(sim: Scene) -> Image.Image:
    """The current frame of a running sim (for tests and tools)."""
    return Renderer(sim.world).draw(sim)
