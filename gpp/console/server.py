"""The console's web server: Starlette on uvicorn, in a thread of its own (imported only when
`gpp run --console` is given).

* `GET /` the page (gpp/console/page.*), `GET /state` the view as JSON;
* `GET /events` the live stream (server-sent events): the whole view at once, then again
  whenever the run changed it (at most `PUSHES_PER_SECOND` times a second; the clock at
  least every `HEARTBEAT` seconds). A slow browser gets fewer views, never a queue of them: the
  stream always sends the newest. A browser that goes away ends its stream, nothing else;
* `POST /control` an operator's request (JSON: `command`, and `action` with `args` for `exog`
  and `act`), recorded for the executor's thread (gpp.console.control).

Every request passes gpp.console.access first.
"""

from __future__ import annotations

import asyncio
import contextlib
import importlib.resources
import json
import socket
import threading
from collections.abc import AsyncIterator, Callable
from typing import Any

import uvicorn
from starlette.applications import Starlette
from starlette.requests import Request as HttpRequest
from starlette.responses import HTMLResponse, JSONResponse, Response, StreamingResponse
from starlette.routing import Route

from gpp.console.access import FOR_HEADER, Access, AccessError
from gpp.console.control import ConsoleControl, Request, ground
from gpp.console.state import ConsoleState
from gpp.model.symbols import SymbolKind
from gpp.runtime.events import OPERATOR_COMMANDS

PUSHES_PER_SECOND = 5
HEARTBEAT = 1.0
# Seconds the server gives the open streams to send the last view when it closes.
CLOSE_GRACE = 2


def page_html(name: str = "page") -> str:
    """A page of the console: gpp/console/NAME.html with the CSS and its JS put in."""
    files = importlib.resources.files("gpp.console")
    html = files.joinpath(f"{name}.html").read_text("utf-8")
    css = files.joinpath("page.css").read_text("utf-8")
    js = files.joinpath(f"{name}.js").read_text("utf-8")
    return html.replace("/*CSS*/", css).replace("/*JS*/", js)


PAGE = page_html()


class Channel:
    """The newest view of one run (JSON text) for its live streams, on the server's event loop.
    A stream sends each view it has not sent (by number), the newest only: a slow reader skips
    views, never queues them."""

    def __init__(self) -> None:
        self.latest = "{}"
        self.sequence = 0
        self.closing = False
        self.streams = 0  # open live streams (the tests and the bench look)
        # Streams waiting for a new view (the others are still sending one: a slow browser's).
        self.ready = 0
        self._tick: asyncio.Event | None = None

    def publish(self, view: str) -> None:
        """A view for the streams (nothing when it is the one they have)."""
        if view == self.latest:
            return
        self.latest = view
        self.sequence += 1
        tick, self._tick = self._tick, asyncio.Event()
        if tick is not None:
            tick.set()

    def close(self, view: str) -> None:
        """The last view: the streams send it and end."""
        self.closing = True
        self.publish(view)
        if self._tick is not None:
            self._tick.set()

    def stream(self) -> AsyncIterator[str]:
        """A live stream of the views (counted from now on: the run's changes are pushed while
        one is open)."""
        self.streams += 1
        return self._stream()

    async def _stream(self) -> AsyncIterator[str]:
        try:
            seen = self.sequence
            yield f"data: {self.latest}\n\n"
            while True:
                if seen == self.sequence:
                    if self.closing:
                        return
                    if self._tick is None:
                        self._tick = asyncio.Event()
                    self.ready += 1
                    try:
                        with contextlib.suppress(TimeoutError):
                            await asyncio.wait_for(self._tick.wait(), HEARTBEAT * 5)
                    finally:
                        self.ready -= 1
                    if seen == self.sequence:
                        yield ": still here\n\n"  # a comment: a vanished browser is noticed
                        continue
                seen = self.sequence
                yield f"data: {self.latest}\n\n"
        finally:
            self.streams -= 1


def event_stream(channel: Channel) -> StreamingResponse:
    return StreamingResponse(channel.stream(), media_type="text/event-stream", headers={"Cache-Control": "no-store"})


def client_of(request: HttpRequest) -> str | None:
    """Who asked, for the `operator` record: the peer's address; for a request a `gpp console`
    hub passed on, the browser it names and then the hub (`10.0.0.7 via 127.0.0.1`: the name
    comes from the hub and is not checked, the peer's address is)."""
    peer = request.client.host if request.client else None
    named = request.headers.get(FOR_HEADER, "")
    if named and len(named) <= 100 and named.isprintable():
        return f"{named} via {peer}" if peer else named
    return peer


def refused(access: Access, request: HttpRequest, control: bool) -> Response | None:
    """The answer to a request `access` refuses (None: it is allowed)."""
    why = access.refusal(request.headers, request.query_params, control=control)
    if why is None:
        return None
    return JSONResponse({"error": f"refused: {why}"}, status_code=401 if "token" in why else 403)


def page_response() -> HTMLResponse:
    return HTMLResponse(PAGE, headers={"Cache-Control": "no-store", "Referrer-Policy": "no-referrer"})


class _QuietServer(uvicorn.Server):
    """uvicorn's server without the ten wakes a second of its main loop (each would cost the
    run a hand-over of the interpreter's lock): it serves until `leave` is called, on its loop."""

    _left: asyncio.Event | None = None

    async def main_loop(self) -> None:
        self._left = asyncio.Event()
        await self.on_tick(0)  # the default headers, once
        if not self.should_exit:
            await self._left.wait()

    def leave(self) -> None:
        self.should_exit = True
        if self._left is not None:
            self._left.set()


class WebServer:
    """A web server in a thread of its own (uvicorn), its routes those of the subclass, at
    `access.address` until `close`."""

    def __init__(self, access: Access) -> None:
        self.access = access
        self.port = access.address.port
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: _QuietServer | None = None
        self._thread: threading.Thread | None = None
        self._socket: socket.socket | None = None

    def routes(self) -> list[Route]:
        raise NotImplementedError

    async def begin(self) -> None:
        """On the server's loop, before it serves."""

    def closing(self) -> None:
        """On the server's loop, when it closes: end the streams (with their last view)."""

    def start(self) -> None:
        """Listen (AccessError when the address cannot be used) and serve in a thread."""
        address = self.access.address
        family = socket.AF_INET6 if ":" in address.host else socket.AF_INET
        sock = socket.socket(family, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            sock.bind((address.host, address.port))
        except (OSError, OverflowError) as e:
            sock.close()
            reason = e.strerror if isinstance(e, OSError) and e.strerror else str(e)
            raise AccessError(f"cannot listen on {address.host}:{address.port}: {reason}") from None
        sock.listen(64)
        self._socket = sock
        self.port = sock.getsockname()[1]
        config = uvicorn.Config(
            Starlette(routes=self.routes()),
            log_level="error",
            lifespan="off",
            timeout_graceful_shutdown=CLOSE_GRACE,
            access_log=False,
            date_header=False,
        )
        self._server = _QuietServer(config)
        started = threading.Event()
        self._thread = threading.Thread(target=self._serve, args=(started,), name="gpp-console", daemon=True)
        self._thread.start()
        started.wait(10.0)

    @property
    def thread_id(self) -> int | None:
        """The server thread's id in the system (the bench reads its CPU time)."""
        return self._thread.native_id if self._thread is not None else None

    @property
    def url(self) -> str:
        base = self.access.address.url(self.port)
        return base + (f"?token={self.access.token}" if self.access.token else "")

    def _serve(self, started: threading.Event) -> None:
        async def serve() -> None:
            self._loop = asyncio.get_running_loop()
            await self.begin()
            assert self._server is not None and self._socket is not None
            serving = asyncio.create_task(self._server.serve(sockets=[self._socket]))
            # Ready once uvicorn has set itself up: that work is not the run's.
            while not self._server.started and not serving.done():
                await asyncio.sleep(0.005)
            started.set()
            await serving

        try:
            asyncio.run(serve())
        finally:
            started.set()

    def call_soon(self, fn: Callable[..., None], *args: object) -> None:
        """Have the server's loop call `fn(*args)` (from any thread)."""
        loop = self._loop
        if loop is not None:
            with contextlib.suppress(RuntimeError):  # the loop closed meanwhile
                loop.call_soon_threadsafe(fn, *args)

    def close(self) -> None:
        """Send the last views to the open streams, end them, stop serving."""
        self.call_soon(self._finish)
        if self._thread is not None:
            self._thread.join(CLOSE_GRACE + 3.0)
        if self._socket is not None:
            self._socket.close()

    def _finish(self) -> None:
        self.closing()
        if self._server is not None:
            self._server.leave()


class ConsoleServer(WebServer):
    """Serves one run's console at `access.address` until `close`."""

    def __init__(self, state: ConsoleState, control: ConsoleControl, access: Access) -> None:
        super().__init__(access)
        self.state = state
        self.control = control
        self.channel = Channel()
        self._woken: asyncio.Event | None = None
        self._pusher: asyncio.Task[None] | None = None

    def routes(self) -> list[Route]:
        return [
            Route("/", self._index),
            Route("/state", self._state),
            Route("/events", self._events),
            Route("/control", self._control, methods=["POST"]),
        ]

    async def begin(self) -> None:
        self._pusher = asyncio.create_task(self._push())

    def close(self) -> None:
        self.state.on_change(None)
        super().close()

    def closing(self) -> None:
        self.channel.close(self._view(closed=True))

    # ------------------------------------------------------------ pushing

    def _changed(self) -> None:
        """From the executor's thread: the run changed the view."""
        self.call_soon(self._wake)

    def _wake(self) -> None:
        if self._woken is not None:
            self._woken.set()

    async def _push(self) -> None:
        """While a browser looks, make a new view when the run changed it (told at once of the
        few records the page must show soon: a plan, a failure, the end; the others are counted,
        the count looked at `PUSHES_PER_SECOND` times a second), or the clock moved (every
        `HEARTBEAT`), and tell the streams; but only when a stream waits for one (a slow
        browser still sending the last one gets no new view made for it). While none looks,
        nothing: each wake of this thread costs the run a hand-over of the interpreter's lock."""
        woken = self._woken = asyncio.Event()
        loop = asyncio.get_running_loop()
        seen, published = -1, 0.0
        while not self.channel.closing:
            watched = self.channel.streams > 0
            self.state.on_change(self._changed if watched else None)
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(woken.wait(), 1.0 / PUSHES_PER_SECOND if watched else None)
            told = woken.is_set()
            woken.clear()
            if not self.channel.streams:
                continue
            if not self.channel.ready:
                continue  # every stream still sends a view (slow browsers): none would take a new one
            records = self.state.records
            if told or records != seen or loop.time() - published >= HEARTBEAT:
                seen, published = records, loop.time()
                self.channel.publish(self._view())
                await asyncio.sleep(1.0 / PUSHES_PER_SECOND)

    def _view(self, closed: bool = False) -> str:
        data = self.state.view(self.control.clock())
        data["closed"] = closed
        data["can"] = self.control.can()
        return json.dumps(data, ensure_ascii=False, default=str)

    # ------------------------------------------------------------ routes

    async def _index(self, request: HttpRequest) -> Response:
        return refused(self.access, request, control=False) or page_response()

    async def _state(self, request: HttpRequest) -> Response:
        answer = refused(self.access, request, control=False)
        if answer is not None:
            return answer
        if not self.channel.closing:
            self.channel.publish(self._view())
        return Response(self.channel.latest, media_type="application/json")

    async def _events(self, request: HttpRequest) -> Response:
        answer = refused(self.access, request, control=False)
        if answer is not None:
            return answer
        if not self.channel.closing:
            self.channel.publish(self._view())  # the stream starts with the world as it is now
        self._wake()  # the pusher is told of changes from now on
        return event_stream(self.channel)

    async def _control(self, request: HttpRequest) -> Response:
        answer = refused(self.access, request, control=True)
        if answer is not None:
            return answer
        try:
            body: Any = await request.json()
        except ValueError:
            return JSONResponse({"error": "the request is not JSON"}, status_code=400)
        problem = self._read(body, client_of(request))
        if isinstance(problem, str):
            return JSONResponse({"error": problem}, status_code=400)
        self.control.request(problem)
        return JSONResponse({"ok": True})

    def _read(self, body: Any, client: str | None) -> Request | str:
        """The request a control body asks for, or why it is not one."""
        if not isinstance(body, dict) or body.get("command") not in OPERATOR_COMMANDS:
            return f"`command` is one of {', '.join(OPERATOR_COMMANDS)}"
        command = str(body["command"])
        refusal = self.control.refusal(command)
        if refusal is not None:
            return refusal
        if command not in ("exog", "act"):
            return Request(command, client=client)
        name, args = body.get("action"), body.get("args", {})
        if not isinstance(name, str) or not isinstance(args, dict):
            return "`action` names the action and `args` gives its arguments by name, as text"
        kind = SymbolKind.EXOG_ACTION if command == "exog" else SymbolKind.ACTION
        try:
            action = ground(self.control.model, name, {str(k): str(v) for k, v in args.items()}, kind)
        except ValueError as e:
            return str(e)
        return Request(command, action, client)


def serve(state: ConsoleState, control: ConsoleControl, access: Access) -> ConsoleServer:
    """Start a console server (AccessError when it cannot listen)."""
    server = ConsoleServer(state, control, access)
    server.start()
    return server


__all__ = ["Channel", "ConsoleServer", "WebServer", "serve"]
