"""The trace viewer's page in a real browser: Debian's chromium (`make browser` installs it),
driven by Playwright (the `dev` extra; never `playwright install`, which would download a
browser of its own). The page of the blocksworld run on the sim loads without console errors
or network requests, draws one bar per activity, shows the source line on hover, zooms and
pans. Each step waits for the state it asserts (playwright's `expect`, or the chart's
`data-view` for the time window drawn) with a timeout long enough for a loaded machine, never
for a fixed time or for "some change". `GPP_UPDATE_SCREENSHOT=1` also writes its screenshot to
docs/trace_viewer.png (the tutorial's picture; its own variable, since the planning time shown in
it varies run to run)."""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import ExogEvent, StartEvent
from gpp.traceview.html import html_page
from gpp.traceview.model import build_run_model, load_trace

if TYPE_CHECKING:
    from playwright.sync_api import Browser, ConsoleMessage, Locator, LocatorAssertions, Page

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
SCREENSHOT = ROOT / "docs" / "trace_viewer.png"
UPDATE_SCREENSHOT = os.environ.get("GPP_UPDATE_SCREENSHOT") == "1"
CHROMIUM = "/usr/bin/chromium" if Path("/usr/bin/chromium").exists() else shutil.which("chromium")
# How long a step may take to show its state (ms): long, since a wait that holds ends at once.
WAIT = 30_000
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    if CHROMIUM is None:
        pytest.skip(
            "chromium is not installed, so the trace viewer's page cannot be tested in a browser: "
            "`make browser` installs Debian's chromium (as root), or `apt-get install chromium`"
        )
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.skip("the Python package playwright is not installed: pip install -e '.[dev]'")
    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, timeout=WAIT)
        yield launched
        launched.close()


@pytest.fixture(scope="module")
def blocksworld(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """(trace, page) of examples/blocksworld.gpp run on the sim now, made from the repository's
    root as a user would (relative source locations, the program found for its source lines)."""
    out = tmp_path_factory.mktemp("blocksworld")
    cwd = Path.cwd()
    os.chdir(ROOT)
    try:
        trace = out / "run.jsonl"
        outcome = run_program(Path("examples/blocksworld.gpp"), RunOptions(platform="sim", trace=trace))
        assert outcome.ok
        page, sources = html_page(build_run_model(load_trace(trace).events), trace_name="run.jsonl", search=[ROOT])
        assert sources.missing == []
    finally:
        os.chdir(cwd)
    html = out / "run.html"
    html.write_text(page, encoding="utf-8")
    return trace, html


def expect(locator: Locator) -> LocatorAssertions:
    """Playwright's `expect`, its timeout set to WAIT (imported here, so that the module loads
    without playwright and the `browser` fixture says why it skips)."""
    from playwright.sync_api import expect as playwright_expect

    playwright_expect.set_options(timeout=WAIT)
    return playwright_expect(locator)


class Opened:
    """A page opened from a file, with what it said on the console and what it requested."""

    def __init__(self, browser: Browser, path: Path, width: int = 1280) -> None:
        self.url = path.resolve().as_uri()
        self.page: Page = browser.new_page(viewport={"width": width, "height": 800})
        self.page.set_default_timeout(WAIT)
        self.problems: list[str] = []
        self.requests: list[str] = []
        self.page.on("console", self._console)
        self.page.on("pageerror", lambda e: self.problems.append(f"page error: {e}"))
        self.page.on("requestfailed", lambda r: self.problems.append(f"request failed: {r.url}"))
        self.page.on("request", lambda r: self.requests.append(r.url))
        self.page.goto(self.url)
        self.page.wait_for_selector("body[data-ready=true]")

    def _console(self, message: ConsoleMessage) -> None:
        if message.type in ("error", "warning"):
            self.problems.append(f"{message.type}: {message.text}")

    def attr(self, selector: str, name: str) -> list[Any]:
        return list(self.page.eval_on_selector_all(selector, f"els => els.map(e => e.getAttribute('{name}'))"))

    def range_text(self) -> str:
        return self.page.inner_text("#range")

    def view(self) -> tuple[float, float]:
        """The time window (start, end) of the chart's last drawing: its `data-view`."""
        start, end = (self.page.get_attribute("#chart", "data-view") or "nan nan").split()
        return float(start), float(end)

    def plot(self) -> tuple[float, float]:
        """The plot area (left, width) in the chart's pixels: its `data-plot`."""
        left, width = (self.page.get_attribute("#chart", "data-plot") or "nan nan").split()
        return float(left), float(width)

    def wait_for_view(self, condition: str, what: str) -> tuple[float, float]:
        """Wait until the chart draws a window for which `condition` holds, a JavaScript
        expression over `start` and `end` (and `near(a, b, tolerance)`), and return that window.
        A view changes at once and is drawn at the next frame, so a test waits for the drawing."""
        from playwright.sync_api import TimeoutError as PlaywrightTimeout

        script = (
            "() => { const v = document.getElementById('chart').getAttribute('data-view');"
            " if (!v) return false; const [start, end] = v.split(' ').map(Number);"
            f" const near = (a, b, tolerance) => Math.abs(a - b) <= tolerance; return {condition}; }}"
        )
        try:
            self.page.wait_for_function(script, timeout=WAIT)
        except PlaywrightTimeout:
            pytest.fail(f"the chart did not show {what} within {WAIT // 1000} s: it shows {self.view()}")
        return self.view()


@pytest.fixture
def opened(browser: Browser, blocksworld: tuple[Path, Path]) -> Iterator[Opened]:
    opened = Opened(browser, blocksworld[1])
    yield opened
    opened.page.close()


def test_the_page_loads_cleanly_and_draws_every_activity(opened: Opened, blocksworld: tuple[Path, Path]) -> None:
    events = load_trace(blocksworld[0]).events
    starts = [e for e in events if isinstance(e, StartEvent)]
    assert opened.problems == []
    assert opened.requests == [opened.url]  # nothing but the page itself: no network, no other file
    assert opened.page.title() == "examples/blocksworld.gpp · gpp trace"
    # One bar per activity, with its action, id and lane (lane by lane).
    ids = [int(i) for i in opened.attr("g.activity", "data-id")]
    actions = opened.attr("g.activity", "data-action")
    assert sorted(zip(ids, actions, strict=True)) == [(s.id, s.action) for s in starts]
    lanes = {"get_block_pose", "navigate_to_frame", "stack", "gripper_home"}
    assert set(opened.attr("g.activity", "data-lane")) == lanes
    for bar in opened.page.locator("g.activity rect.bar").all():
        box = bar.bounding_box()
        assert box is not None and box["width"] >= 3 and box["height"] > 10
    # The widest bars carry their action as a label.
    labels = opened.page.locator("g.activity text.bar-label").all_text_contents()
    assert {"navigate_to_frame(table)", "navigate_to_frame(home)", "stack(c,t3)"} <= set(labels)
    exog = [e.action for e in events if isinstance(e, ExogEvent)]
    assert opened.attr("g.exog", "data-action") == exog
    assert opened.page.locator("g.plan").count() == 1
    assert opened.attr("g.series", "data-name") == ["battery()", "battery_report(·)"]
    assert opened.attr("g.series", "data-samples") == [str(len(exog))] * 2
    # The page around the chart.
    assert opened.page.inner_text("#status") == "FINISHED"
    assert "13 activities in 4 lanes" in opened.page.inner_text("#meta")
    legend = opened.page.inner_text("#legend")
    assert "final" in legend and "exogenous event" in legend and "plan" in legend
    assert opened.page.locator("#plans-table tbody tr").count() == 1
    assert opened.page.locator("#activities-table tbody tr").count() == 0  # filled when opened
    opened.page.click("#activities-card summary")
    # The table is filled by the `toggle` event, after the click returns: wait for its rows.
    expect(opened.page.locator("#activities-table tbody tr")).to_have_count(len(starts))
    assert opened.page.locator("text.axis-label").first.text_content() == "0 s"


def test_hover_shows_the_step_and_its_source_line(opened: Opened, blocksworld: tuple[Path, Path]) -> None:
    starts = [e for e in load_trace(blocksworld[0]).events if isinstance(e, StartEvent)]
    stack = next(s for s in starts if s.action == "stack(a,t2)")
    assert stack.at is not None
    file, line, _ = stack.at.rsplit(":", 2)
    source = (ROOT / file).read_text(encoding="utf-8").splitlines()[int(line) - 1].strip()
    tooltip = opened.page.locator("#tooltip")
    assert tooltip.is_hidden()
    # The tooltip follows pointer events, which the page may handle after the hover returns.
    opened.page.hover(f'g.activity[data-id="{stack.id}"] rect.bar')
    expect(tooltip).to_be_visible()
    for part in ("stack(a,t2)", stack.at, source):
        expect(tooltip).to_contain_text(part)
    assert opened.page.locator("#tooltip pre.src .hl").inner_text().strip().endswith(source)
    # Moving off the chart hides it; an exogenous event and the plan explain themselves too.
    opened.page.mouse.move(5, 5)
    expect(tooltip).to_be_hidden()
    opened.page.hover("g.exog >> nth=1")
    expect(tooltip).to_contain_text("battery_report(95)")
    opened.page.hover("g.plan")
    for part in ("value 96", "horizon", "stack(c,t3)"):
        expect(tooltip).to_contain_text(part)
    assert opened.problems == []


def test_zoom_and_pan(opened: Opened) -> None:
    page = opened.page
    whole = opened.range_text()
    assert whole.startswith("showing 0.0 s – 35.8 s")
    full = opened.view()
    left, width = opened.plot()
    exact = (full[1] - full[0]) * 1e-9  # rounding only
    # Zoom in twice: a quarter of the run (and its margins), around its middle. Each click
    # halves the view, and a frame may be drawn between the clicks: wait for the quarter.
    page.click("#zoom-in")
    page.click("#zoom-in")
    quarter, middle = (full[1] - full[0]) / 4, (full[0] + full[1]) / 2
    zoomed = opened.wait_for_view(
        f"near(end - start, {quarter!r}, {exact!r}) && near((start + end) / 2, {middle!r}, {exact!r})",
        "a quarter of the run around its middle",
    )
    zoomed_text = opened.range_text()
    start, end = float(zoomed_text.split()[1]), float(zoomed_text.split()[4])
    assert 8 < end - start < 10
    assert abs((start + end) / 2 - 35.8 / 2) < 0.5
    drawn = page.locator("g.activity").count()
    assert 0 < drawn < 13  # only what is on screen
    # Drag 300 pixels to the left to pan: the window moves as far later in time.
    box = page.locator("#chart").bounding_box()
    assert box is not None
    y = box["y"] + 60
    span = zoomed[1] - zoomed[0]
    pixel = span / width  # one pixel's time: pointer positions may be rounded to whole pixels
    page.mouse.move(box["x"] + 700, y)
    page.mouse.down()
    page.mouse.move(box["x"] + 400, y, steps=5)
    page.mouse.up()
    later = zoomed[0] + 300 * pixel
    panned = opened.wait_for_view(
        f"near(start, {later!r}, {pixel!r}) && near(end - start, {span!r}, {exact!r})",
        f"the zoomed window 300 pixels later (from {later:.3f} s)",
    )
    assert float(opened.range_text().split()[1]) > start
    # The wheel zooms in around the pointer: a narrower window, the same time under the pointer.
    px = 600
    at = (px - left) / width
    under = panned[0] + at * (panned[1] - panned[0])
    page.mouse.move(box["x"] + px, y)
    page.mouse.wheel(0, -400)
    opened.wait_for_view(
        f"end - start < {span * 0.9!r} && near(start + {at!r} * (end - start), {under!r}, {pixel!r})",
        f"a narrower window with {under:.3f} s still under the pointer",
    )
    # Double-click shows the whole run again.
    page.dblclick("#chart")
    opened.wait_for_view(f"near(start, {full[0]!r}, {exact!r}) && near(end, {full[1]!r}, {exact!r})", "the whole run")
    assert opened.range_text() == whole
    assert opened.problems == []


def test_a_run_that_stops_renders_its_waits_and_problems(browser: Browser, tmp_path: Path) -> None:
    from tests.support.traces import stopped_run

    page, _ = html_page(build_run_model(stopped_run()), trace_name="stopped.jsonl", search=[tmp_path])
    path = tmp_path / "stopped.html"
    path.write_text(page, encoding="utf-8")
    opened = Opened(browser, path, width=900)
    try:
        assert opened.problems == []
        assert sorted(opened.attr("g.activity", "data-status")) == ["failed", "final", "running"]
        assert opened.page.locator("g.wait-span").count() == 1
        assert opened.page.locator("g.problem").count() == 1
        opened.page.hover("g.problem")
        for part in ("R0002", "agent.gpp:14:9", "not embedded"):
            expect(opened.page.locator("#tooltip")).to_contain_text(part)
        assert opened.page.inner_text("#status") == "ERROR"
    finally:
        opened.page.close()


def test_what_operators_did_is_a_row_with_who_asked(browser: Browser, tmp_path: Path) -> None:
    from tests.support.traces import operator_trace

    model = build_run_model(load_trace(operator_trace(tmp_path)).events)
    page, _ = html_page(model, trace_name="operator.jsonl", search=[tmp_path])
    path = tmp_path / "operator.html"
    path.write_text(page, encoding="utf-8")
    opened = Opened(browser, path, width=900)
    try:
        assert opened.problems == []
        assert opened.attr("g.operator", "data-command") == ["exog", "start"]
        opened.page.hover("g.operator >> nth=1")  # both at 0 s: the later is drawn on top
        for part in ("operator at the console", "start", "127.0.0.1"):
            expect(opened.page.locator("#tooltip")).to_contain_text(part)
    finally:
        opened.page.close()


def test_quick_retries_simultaneous_events_close_changes_and_states(browser: Browser, tmp_path: Path) -> None:
    """tests/traceview/programs/retries.gpp: two visitors arrive at once, two assignments 1 s
    apart, a `goto(room1)` fails at once and is retried, and where the robot is changes."""
    trace = tmp_path / "retries.jsonl"
    assert run_program(HERE / "programs" / "retries.gpp", RunOptions(trace=trace)).ok
    page, _ = html_page(build_run_model(load_trace(trace).events), trace_name="retries.jsonl", search=[HERE])
    path = tmp_path / "retries.html"
    path.write_text(page, encoding="utf-8")
    opened = Opened(browser, path, width=1000)
    try:
        assert opened.problems == []
        # The two arrivals at one time: one mark, one label that names both.
        assert opened.attr("g.exog", "data-count") == ["2"]
        labels = opened.page.locator("text.mark-label").all_text_contents()
        assert "×2 (ann), (bob)" in labels
        opened.page.hover("g.exog")
        for part in ("arrive(ann)", "arrive(bob)"):
            expect(opened.page.locator("#tooltip")).to_contain_text(part)
        # Both assignments' labels whole, though 1 s apart.
        assert {"visitors_greeted_so_far() = 1", "visitors_greeted_so_far() = 2"} <= set(labels)
        # The failed attempt took no time: its bar is drawn over its retry's, at least 3 px wide.
        order = opened.attr("g.activity", "data-status")
        assert order.index("failed") > max(i for i, status in enumerate(order) if status == "final")
        box = opened.page.locator('g.activity[data-status="failed"] rect.bar').bounding_box()
        assert box is not None and box["width"] >= 3
        # Why it failed is on the page, not only in a tooltip.
        expect(opened.page.locator("#failures-card")).to_be_visible()
        row = opened.page.locator("#failures-table tbody tr")
        expect(row).to_have_count(1)
        for part in ("goto(room1)", "failed", "scenario", "retries.gpp:"):
            expect(row).to_contain_text(part)
        # Where the robot is: a band per value it held.
        assert opened.attr('g.state[data-fluent="robot_at()"]', "data-value") == ["room1", "room2", "lobby"]
        assert "room1" in opened.page.locator("text.state-label").all_text_contents()
    finally:
        opened.page.close()


def test_screenshot_of_the_blocksworld_run(opened: Opened, tmp_path: Path) -> None:
    """The README's picture: the whole page with the tooltip of a step. Written to
    docs/trace_viewer.png with GPP_UPDATE_SCREENSHOT=1."""
    opened.page.hover('g.activity[data-action="stack(a,t2)"] rect.bar')
    expect(opened.page.locator("#tooltip")).to_contain_text("stack(a,t2)")
    shot = tmp_path / "trace_viewer.png"
    opened.page.screenshot(path=str(shot), full_page=True)
    data = shot.read_bytes()
    assert data.startswith(b"\x89PNG") and len(data) > 20_000
    if UPDATE_SCREENSHOT:
        SCREENSHOT.write_bytes(data)
    assert SCREENSHOT.is_file(), "no docs/trace_viewer.png; make it with GPP_UPDATE_SCREENSHOT=1"
