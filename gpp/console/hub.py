"""One console for several agents (`gpp console`): one page with a panel per run, so one
operator with one tablet watches and steers several robots.

An agent joins in one of three ways:

* `gpp run --console ... --console-join HUB_URL` registers its own console with the hub
  (`POST /register`, the hub's token in the header);
* `gpp console --agent URL` names an agent's console (its address with its token);
* `gpp console --ros2-agent NODE` reads an agent's live records from ROS (its `NODE/events`
  topic, gpp.platform.ros2.live) instead of a direct connection: its panel shows the run
  (fluents as they are set) and has no controls (the topic only tells).

The browser talks to the hub only (one address, one token); the hub reads each agent's live
stream and hands a control request on to the agent with the agent's token. Each agent's panel
is the one-agent page itself, served by the hub at `/agents/N/`, so the page code is one.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import threading
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Callable
from typing import Any

from starlette.requests import Request as HttpRequest
from starlette.responses import HTMLResponse, JSONResponse, Response
from starlette.routing import Route

from gpp.console.access import FOR_HEADER, TOKEN_HEADER, Access
from gpp.console.server import Channel, WebServer, event_stream, page_html, page_response, refused
from gpp.console.state import RecordFold
from gpp.runtime.events import decode

# Seconds to wait for an agent's console to answer a request the hub hands on.
AGENT_TIMEOUT = 10.0
HUB_PAGE = page_html("hub")


class Feed:
    """One agent as the hub sees it: its newest view (in `channel`), and how to ask it."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.channel = Channel()
        self.publish: Callable[[str], None] = lambda view: None  # set by the hub

    def control(self, body: bytes, client: str | None = None) -> tuple[int, Any]:
        """Pass an operator's request on to the agent (`client`: the browser that asked)."""
        return 405, {"error": "this agent's panel only shows its run"}

    def close(self) -> None:
        pass


class HttpFeed(Feed):
    """An agent's own console (`gpp run --console`), read over HTTP by a thread of its own."""

    def __init__(self, url: str) -> None:
        parts = urllib.parse.urlsplit(url)
        if parts.scheme != "http" or not parts.netloc:
            raise ValueError(f"an agent's console is an http:// address, not {url!r}")
        token = urllib.parse.parse_qs(parts.query).get("token", [None])[0]
        super().__init__(parts.netloc)
        self.base = f"http://{parts.netloc}/"
        self.token = token
        self._stop = threading.Event()
        self._answer: Any = None
        self._thread = threading.Thread(target=self._read, name=f"gpp-console-feed-{self.name}", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _headers(self) -> dict[str, str]:
        return {TOKEN_HEADER: self.token} if self.token else {}

    def _read(self) -> None:
        """Follow the agent's live stream: each view it sends becomes this feed's."""
        request = urllib.request.Request(self.base + "events", headers=self._headers())
        try:
            with urllib.request.urlopen(request, timeout=None) as answer:
                self._answer = answer
                for line in answer:
                    if self._stop.is_set():
                        return
                    if line.startswith(b"data: "):
                        self.publish(line[6:].decode("utf-8").strip())
        except (OSError, ValueError) as e:
            if not self._stop.is_set():
                self.publish(json.dumps({"agent": {"program": self.name}, "status": "disconnected", "problem": str(e)}))

    def control(self, body: bytes, client: str | None = None) -> tuple[int, Any]:
        headers = {"Content-Type": "application/json", **self._headers(), **({FOR_HEADER: client} if client else {})}
        request = urllib.request.Request(self.base + "control", data=body, headers=headers)
        try:
            with urllib.request.urlopen(request, timeout=AGENT_TIMEOUT) as answer:
                return answer.status, json.loads(answer.read())
        except urllib.error.HTTPError as e:
            return e.code, json.loads(e.read() or b"{}")
        except OSError as e:
            return 502, {"error": f"the agent's console does not answer: {e}"}

    def close(self) -> None:
        self._stop.set()
        with contextlib.suppress(Exception):
            if self._answer is not None:
                self._answer.close()


class Ros2Feed(Feed):
    """An agent on ROS, read from its live records topic (`NODE/events`, gpp.platform.ros2.live)."""

    def __init__(self, node: str, bridge: Any) -> None:
        super().__init__(node)
        from gpp.platform.ros2.binding import Qos
        from gpp.platform.ros2.bridge import qos_profile
        from gpp.platform.ros2.interfaces import load_interface
        from gpp.platform.ros2.live import EVENTS_KEPT

        self.state = RecordFold()
        string = load_interface("std_msgs/msg/String")
        qos = Qos(reliability="reliable", durability="transient_local", history="keep_last", depth=EVENTS_KEPT)
        topic = node.rstrip("/") + "/events"
        self._subscription = bridge.call(
            lambda: bridge.node.create_subscription(string.cls, topic, self._record, qos_profile(qos, EVENTS_KEPT))
        )

    def _record(self, message: Any) -> None:
        """On the ROS spin thread: one trace record of the agent."""
        try:
            self.state(decode(message.data))
        except (ValueError, TypeError):
            return  # not a record of a run
        view = self.state.view()
        view.update(closed=False, can=dict.fromkeys(("start", "pause", "resume", "stop", "exog", "act"), False))
        self.publish(json.dumps(view, ensure_ascii=False, default=str))


class Hub(WebServer):
    """Serves the page of several agents at `access.address` until `close`."""

    def __init__(self, access: Access) -> None:
        super().__init__(access)
        self.feeds: list[Feed] = []
        self.roster = Channel()
        self._lock = threading.Lock()

    def routes(self) -> list[Route]:
        return [
            Route("/", self._index),
            Route("/agents", self._agents),
            Route("/register", self._register, methods=["POST"]),
            Route("/agents/{n:int}/", self._agent_page),
            Route("/agents/{n:int}/events", self._agent_events),
            Route("/agents/{n:int}/state", self._agent_state),
            Route("/agents/{n:int}/control", self._agent_control, methods=["POST"]),
        ]

    def add(self, feed: Feed) -> None:
        """Show one more agent (from any thread)."""

        def publish(view: str) -> None:
            self.call_soon(feed.channel.publish, view)

        feed.publish = publish
        with self._lock:
            self.feeds.append(feed)
            names = json.dumps([f.name for f in self.feeds])
        self.call_soon(self.roster.publish, names)
        if isinstance(feed, HttpFeed):
            feed.start()

    def closing(self) -> None:
        for feed in self.feeds:
            feed.close()
            feed.channel.close(feed.channel.latest)
        self.roster.close(self.roster.latest)

    def _feed(self, n: int) -> Feed | None:
        with self._lock:
            return self.feeds[n] if 0 <= n < len(self.feeds) else None

    async def _index(self, request: HttpRequest) -> Response:
        return refused(self.access, request, control=False) or HTMLResponse(
            HUB_PAGE, headers={"Cache-Control": "no-store", "Referrer-Policy": "no-referrer"}
        )

    async def _agents(self, request: HttpRequest) -> Response:
        return refused(self.access, request, control=False) or event_stream(self.roster)

    async def _register(self, request: HttpRequest) -> Response:
        answer = refused(self.access, request, control=True)
        if answer is not None:
            return answer
        try:
            body = await request.json()
            feed = HttpFeed(str(body["url"]))
        except (ValueError, KeyError, TypeError) as e:
            return JSONResponse({"error": f"`url` is the agent console's address: {e}"}, status_code=400)
        self.add(feed)
        return JSONResponse({"ok": True, "agent": len(self.feeds) - 1})

    async def _agent_page(self, request: HttpRequest) -> Response:
        answer = refused(self.access, request, control=False)
        if answer is not None:
            return answer
        return page_response() if self._feed(request.path_params["n"]) else JSONResponse({}, status_code=404)

    async def _agent_events(self, request: HttpRequest) -> Response:
        feed = self._feed(request.path_params["n"])
        answer = refused(self.access, request, control=False)
        if answer is not None or feed is None:
            return answer or JSONResponse({}, status_code=404)
        return event_stream(feed.channel)

    async def _agent_state(self, request: HttpRequest) -> Response:
        feed = self._feed(request.path_params["n"])
        answer = refused(self.access, request, control=False)
        if answer is not None or feed is None:
            return answer or JSONResponse({}, status_code=404)
        return Response(feed.channel.latest, media_type="application/json")

    async def _agent_control(self, request: HttpRequest) -> Response:
        feed = self._feed(request.path_params["n"])
        answer = refused(self.access, request, control=True)
        if answer is not None or feed is None:
            return answer or JSONResponse({}, status_code=404)
        client = request.client.host if request.client else None
        status, body = await asyncio.to_thread(feed.control, await request.body(), client)
        return JSONResponse(body, status_code=status)


def join(hub_url: str, agent_url: str) -> str | None:
    """Register an agent's console with a hub (`--console-join`); why it failed, or None."""
    parts = urllib.parse.urlsplit(hub_url)
    token = urllib.parse.parse_qs(parts.query).get("token", [None])[0]
    headers = {"Content-Type": "application/json", **({TOKEN_HEADER: token} if token else {})}
    request = urllib.request.Request(
        f"{parts.scheme}://{parts.netloc}/register", data=json.dumps({"url": agent_url}).encode(), headers=headers
    )
    try:
        with urllib.request.urlopen(request, timeout=AGENT_TIMEOUT):
            return None
    except urllib.error.HTTPError as e:
        return f"the console at {hub_url} refused: {json.loads(e.read() or b'{}').get('error', e.reason)}"
    except (OSError, ValueError) as e:
        return f"cannot reach the console at {hub_url}: {e}"
