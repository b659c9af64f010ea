"""Several agents on one page (`gpp console`): agents that join with `--console-join`, an agent
named with `--agent`, one read from its live records topic on ROS 2, the hub's page in a real
browser with a panel per agent, each steered from its panel."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from gpp.runtime.events import OperatorEvent, decode
from tests.console.programs import endless_program, hidden_program
from tests.support.cli import run as gpp
from tests.support.console import ROOT, WAIT, ConsoleRun
from tests.traceview.test_traceview_browser import WAIT as BROWSER_WAIT
from tests.traceview.test_traceview_browser import browser, expect

if TYPE_CHECKING:
    from playwright.sync_api import Browser

__all__ = ["browser"]  # the fixture, shared with the trace viewer's tests

pytestmark = pytest.mark.slow


class HubRun(ConsoleRun):
    """`gpp console 127.0.0.1:0 ARGS...` in its own process."""

    def __init__(self, *args: str) -> None:  # the same reading of its address, another command
        env = {**os.environ, "PYTHONPATH": str(ROOT)}
        pipe = subprocess.PIPE
        command = [sys.executable, "-m", "gpp", "console", "127.0.0.1:0", *args]
        self.process = subprocess.Popen(
            command, cwd=ROOT, env=env, stdin=subprocess.DEVNULL, stdout=pipe, stderr=pipe, text=True
        )
        self._follow()


@pytest.fixture
def hub() -> Iterator[HubRun]:
    running = HubRun()
    yield running
    running.close()


def operator_records(trace: Path) -> list[OperatorEvent]:
    records = [decode(line) for line in trace.read_text(encoding="utf-8").splitlines()]
    return [r for r in records if isinstance(r, OperatorEvent)]


def test_two_agents_on_one_page_each_started_from_its_panel(browser: Browser, hub: HubRun, tmp_path: Path) -> None:
    program, name = hidden_program(tmp_path)
    traces = [tmp_path / "one.jsonl", tmp_path / "two.jsonl"]
    agents = []
    for trace in traces:
        # One after the other: the second starts once the first has joined.
        agents.append(ConsoleRun(program, "--console-wait", "--console-join", hub.url, "--trace", str(trace)))
    try:
        page = browser.new_page(viewport={"width": 1280, "height": 1000})
        page.set_default_timeout(BROWSER_WAIT)
        page.goto(hub.url)
        expect(page.locator("#count")).to_have_text("2 agents")
        panels = [page.frame_locator(f'iframe[data-agent="{n}"]') for n in range(2)]
        for panel in panels:
            expect(panel.locator("#status")).to_have_text("waiting for Start")
            expect(panel.locator(f'tr[data-fluent="{name}(kitchen)"] td.value')).to_have_text("waiting")
        for n, panel in enumerate(panels):
            panel.locator("#start").click()
            expect(panel.locator("#waiting")).to_contain_text("pinged() > 2")
            form = panel.locator('#exog-forms form[data-action="ping"]')
            form.locator('input[name="n"]').fill(str(5 + n))
            form.locator("button").click()
            expect(panel.locator("#status")).to_have_text("finished")
            expect(panel.locator('tr[data-fluent="pinged()"] td.value')).to_have_text(str(5 + n))
        for agent in agents:
            assert agent.finish()[0] == 0
        page.close()
    finally:
        for agent in agents:
            agent.close()
    for trace in traces:
        # Who asked: the browser, through the hub (both on loopback here).
        assert [(r.command, r.client) for r in operator_records(trace)] == [
            ("start", "127.0.0.1 via 127.0.0.1"),
            ("exog", "127.0.0.1 via 127.0.0.1"),
        ]


def test_an_agent_named_on_the_command_line(tmp_path: Path) -> None:
    agent = ConsoleRun(endless_program(tmp_path), "--console-wait", "--console-token", "robot-1")
    hub = HubRun("--agent", agent.url, "--token", "hub")
    try:
        assert hub.url.endswith("?token=hub")
        assert hub.request("agents/0/state")[0] == 401  # the hub's token, not the agent's
        view = hub.state_when(
            lambda v: v.get("status") == "waiting for Start", "the agent", path="agents/0/state?token=hub"
        )
        assert view["fluents"][0] == {"name": "rounds()", "value": "0", "changed": None}
        # Handed on with the agent's token; refused without the hub's.
        assert hub.request("agents/0/control", {"command": "stop"})[0] == 401
        assert hub.request("agents/0/control", {"command": "stop"}, {"X-Gpp-Token": "hub"}) == (200, {"ok": True})
        assert agent.finish()[0] == 130
    finally:
        agent.close()
        hub.close()


def test_joining_needs_a_console_and_a_hub_that_answers(tmp_path: Path) -> None:
    program = str(endless_program(tmp_path))
    result = gpp("run", program, "--console-join", "http://127.0.0.1:1/")
    assert result.returncode == 2
    assert "error: --console-join shows the run's console on another page: it needs --console" in result.stderr
    result = gpp("run", program, "--console", "127.0.0.1:0", "--console-join", "http://127.0.0.1:1/")
    assert result.returncode == 2
    assert "error: --console-join: cannot reach the console at http://127.0.0.1:1/" in result.stderr


def test_an_agent_on_ros2_read_from_its_live_records_topic(tmp_path: Path) -> None:
    """The agent's node publishes its records (gpp.platform.ros2.live, as a run on ros2 does);
    the hub's panel for it, fed from the topic, shows the run's fluents and its end. One
    process, one context, discovery off: nothing leaves the process."""
    pytest.importorskip("rclpy")
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "OFF"
    os.environ.setdefault("ROS_LOG_DIR", tempfile.mkdtemp(prefix="gpp-ros-log-"))
    import rclpy
    from rclpy.context import Context
    from rclpy.signals import SignalHandlerOptions

    from gpp.console.access import Access, Address
    from gpp.console.hub import Hub, Ros2Feed
    from gpp.platform.ros2.bridge import Bridge
    from gpp.platform.ros2.live import LiveTopics
    from gpp.run.runner import RunOptions, run_program

    context = Context()
    rclpy.init(
        context=context, args=["--ros-args", "--log-level", "error"], signal_handler_options=SignalHandlerOptions.NO
    )
    agent = Bridge(context=context, node_name="gpp_agent", namespace="/robot1")
    console = Bridge(context=context, node_name="gpp_console")
    hub = Hub(Access(Address("127.0.0.1", 0), None))
    hub.start()
    try:
        live = LiveTopics()
        live.attach(agent)
        # The hub listens before the run starts, as an operator's console does.
        hub.add(Ros2Feed("/robot1/gpp_agent", console))
        program = ROOT / "tests/programs/exog_events.gpp"
        outcome = run_program(program, RunOptions(), [live])
        assert outcome.ok
        live.flush()
        deadline = time.monotonic() + WAIT
        view: dict[str, Any] = {}
        while view.get("status") != "finished":
            assert time.monotonic() < deadline, f"the panel never showed the run's end: {view}"
            feed = hub.feeds[0]
            view = json.loads(feed.channel.latest)
            time.sleep(0.05)
        fluents = {f["name"]: f["value"] for f in view["fluents"]}
        assert fluents["open(front)"] == "true"
        assert view["agent"]["program"] == str(program)
        assert view["can"] == dict.fromkeys(("start", "pause", "resume", "stop", "exog", "act"), False)
    finally:
        hub.close()
        console.close()
        agent.close()
        context.try_shutdown()
