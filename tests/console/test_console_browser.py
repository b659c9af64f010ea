"""The console's page in a real browser: Debian's chromium driven by Playwright, as the trace
viewer's tests do (tests/traceview/test_traceview_browser.py: its `browser` fixture and
`expect`). Every step waits for the state it asserts, never for a fixed time. At a desktop and
at a phone's viewport. `GPP_UPDATE_SCREENSHOT=1` also writes the pictures of docs/console.md.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from gpp.runtime.events import FinishEvent, OperatorEvent, decode
from tests.console.programs import endless_program, hidden_program
from tests.support.console import ROOT, ConsoleRun
from tests.traceview.test_traceview_browser import WAIT, browser, expect

if TYPE_CHECKING:
    from playwright.sync_api import Browser, ConsoleMessage, Page

__all__ = ["browser"]  # the fixture, shared with the trace viewer's tests

UPDATE_SCREENSHOT = os.environ.get("GPP_UPDATE_SCREENSHOT") == "1"
DESKTOP = {"width": 1280, "height": 900}
PHONE = {"width": 390, "height": 844}
VIEWPORTS = [pytest.param(DESKTOP, id="desktop"), pytest.param(PHONE, id="phone")]


class Console:
    """The console of a run opened in a page, with what the page said on its console."""

    def __init__(self, browser: Browser, run: ConsoleRun, viewport: dict[str, int]) -> None:
        self.run = run
        phone = viewport is PHONE
        self.context = browser.new_context(viewport=viewport, is_mobile=phone, has_touch=phone)  # type: ignore[arg-type]
        self.page: Page = self.context.new_page()
        self.page.set_default_timeout(WAIT)
        self.problems: list[str] = []
        self.page.on("console", self._console)
        self.page.on("pageerror", lambda e: self.problems.append(f"page error: {e}"))
        self.page.goto(run.url)

    def _console(self, message: ConsoleMessage) -> None:
        if message.type in ("error", "warning"):
            self.problems.append(f"{message.type}: {message.text}")

    def status(self, status: str) -> None:
        expect(self.page.locator("#status")).to_have_text(status)

    def fluent(self, name: str, value: str) -> None:
        expect(self.page.locator(f'tr[data-fluent="{name}"] td.value')).to_have_text(value)

    def close(self) -> None:
        self.context.close()
        self.run.close()


@pytest.fixture
def opened(browser: Browser) -> Iterator[list[Console]]:
    """The consoles a test opens (closed after it, their runs ended)."""
    consoles: list[Console] = []
    yield consoles
    for console in consoles:
        console.close()


def save_screenshot(page: Page, path: Path) -> None:
    """The page as a small PNG for the docs (64 colours are plenty for it)."""
    from PIL import Image

    page.screenshot(path=str(path))
    with Image.open(path) as shot:
        shot.quantize(64).save(path, optimize=True)


def operator_commands(trace: Path) -> list[tuple[str, str | None]]:
    records = [decode(line) for line in trace.read_text(encoding="utf-8").splitlines()]
    return [(r.command, r.action) for r in records if isinstance(r, OperatorEvent)]


def finish(trace: Path) -> FinishEvent:
    last = decode(trace.read_text(encoding="utf-8").splitlines()[-1])
    assert isinstance(last, FinishEvent)
    return last


@pytest.mark.parametrize("viewport", VIEWPORTS)
def test_a_hidden_programs_fluents_then_start_and_an_event_from_the_form(
    browser: Browser, opened: list[Console], tmp_path: Path, viewport: dict[str, int]
) -> None:
    program, name = hidden_program(tmp_path)
    trace = tmp_path / "run.jsonl"
    console = Console(browser, ConsoleRun(program, "--console-wait", "--trace", str(trace)), viewport)
    opened.append(console)
    page = console.page
    console.status("waiting for Start")
    console.fluent(f"{name}(kitchen)", "waiting")
    console.fluent(f"{name}(hall)", "waiting")
    console.fluent("pinged()", "0")
    expect(page.locator("#pause")).to_be_disabled()
    page.click("#start")
    # It waits for the event: the page says for what.
    expect(page.locator("#waiting")).to_contain_text("pinged() > 2")
    form = page.locator('#exog-forms form[data-action="ping"]')
    form.locator('input[name="n"]').fill("7")
    form.locator('select[name="r"]').select_option("hall")
    form.locator("button").click()
    console.status("finished")
    console.fluent(f"{name}(kitchen)", "done")
    console.fluent("pinged()", "7")
    expect(page.locator("#events")).to_contain_text("exog   ping(7,hall)")
    code, _ = console.run.finish()
    assert code == 0
    assert operator_commands(trace) == [("start", None), ("exog", "ping(7,hall)")]
    assert console.problems == []
    if viewport is PHONE:
        # Nothing wider than the phone: no sideways scrolling.
        wide = page.evaluate(
            "() => [...document.querySelectorAll('*')].filter(e => e.getBoundingClientRect().right > 390)"
            ".map(e => e.tagName + '#' + e.id + ' ' + e.className)"
        )
        assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"], wide


@pytest.mark.parametrize("viewport", VIEWPORTS)
def test_blocksworld_scanned_before_the_start_then_built_from_the_start_button(
    browser: Browser, opened: list[Console], tmp_path: Path, viewport: dict[str, int]
) -> None:
    trace = tmp_path / "run.jsonl"
    run = ConsoleRun(Path("examples/blocksworld.gpp"), "--platform", "sim", "--console-wait", "--trace", str(trace))
    console = Console(browser, run, viewport)
    opened.append(console)
    page = console.page
    console.status("waiting for Start")
    console.fluent("loc(a)", "null")
    # The paper's "Scan Blocks": look at each block from the page before the start.
    form = page.locator('#act-forms form[data-action="get_block_pose"]')
    for block, under in (("a", "b"), ("b", "t1"), ("c", "t2")):
        form.locator('select[name="x"]').select_option(block)
        form.locator("button").click()
        console.fluent(f"loc({block})", under)
    if UPDATE_SCREENSHOT:
        save_screenshot(page, ROOT / "docs" / ("console.png" if viewport is DESKTOP else "console_phone.png"))
    page.click("#start")
    expect(page.locator("#act-box")).to_be_hidden()
    console.status("finished")
    for block, under in (("a", "b"), ("b", "c"), ("c", "t3")):
        console.fluent(f"loc({block})", under)
    code, _ = run.finish()
    assert code == 0
    assert operator_commands(trace) == [
        ("act", "get_block_pose(a)"),
        ("act", "get_block_pose(b)"),
        ("act", "get_block_pose(c)"),
        ("start", None),
    ]
    assert console.problems == []


def test_pause_holds_the_clock_of_a_virtual_time_platform(
    browser: Browser, opened: list[Console], tmp_path: Path
) -> None:
    trace = tmp_path / "run.jsonl"
    console = Console(browser, ConsoleRun(endless_program(tmp_path), "--trace", str(trace)), DESKTOP)
    opened.append(console)
    page = console.page
    page.wait_for_function("Number(document.getElementById('clock').textContent) >= 3", timeout=WAIT)
    page.click("#pause")
    console.status("paused")
    held = page.inner_text("#clock")
    rounds = page.inner_text('tr[data-fluent="rounds()"] td.value')
    # An event sent while paused is taken in at once; the clock has not moved meanwhile.
    page.locator('#exog-forms form[data-action="halt"] button').click()
    console.fluent("halted()", "true")
    assert page.inner_text("#clock") == held
    assert page.inner_text('tr[data-fluent="rounds()"] td.value') == rounds
    page.click("#resume")
    console.status("finished")
    code, _ = console.run.finish()
    assert code == 0
    assert operator_commands(trace) == [("pause", None), ("exog", "halt()"), ("resume", None)]
    assert finish(trace).status == "finished"


@pytest.mark.parametrize("viewport", VIEWPORTS)
def test_stop_finishes_the_trace(
    browser: Browser, opened: list[Console], tmp_path: Path, viewport: dict[str, int]
) -> None:
    trace = tmp_path / "run.jsonl"
    console = Console(browser, ConsoleRun(endless_program(tmp_path), "--trace", str(trace)), viewport)
    opened.append(console)
    page = console.page
    console.status("running")
    page.click("#stop")
    console.status("interrupted")
    # The stop's reason first (a tick that ran may add what its cancellation did).
    expect(page.locator("#problem")).to_contain_text("stopped by the operator at the console")
    code, _ = console.run.finish()
    assert code == 130
    assert operator_commands(trace) == [("stop", None)]
    assert finish(trace).status == "interrupted"
    assert console.problems == []
