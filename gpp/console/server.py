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
from collections.abc import AsyncIterator
from typing import Any

import uvicorn
from starlette.applications import Starlette
from starlette.requests import Request as HttpRequest
from starlette.responses import HTMLResponse, JSONResponse, Response, StreamingResponse
from starlette.routing import Route

from gpp.console.access import Access, AccessError
from gpp.console.control import ConsoleControl, Request, ground
from gpp.console.state import ConsoleState
from gpp.model.symbols import SymbolKind
from gpp.runtime.events import OPERATOR_COMMANDS

PUSHES_PER_SECOND = 10
HEARTBEAT = 1.0
# Seconds the server gives the open streams to send the last view when it closes.
CLOSE_GRACE = 2


def page_html() -> str:
    """The page: gpp/console/page.html with its CSS and JS put in."""
    files = importlib.resources.files("gpp.console")
    html = files.joinpath("page.html").read_text("utf-8")
    css = files.joinpath("page.css").read_text("utf-8")
    js = files.joinpath("page.js").read_text("utf-8")
    return html.replace("/*CSS*/", css).replace("/*JS*/", js)


class ConsoleServer:
    """Serves one run's console at `access.address` until `close`."""

    def __init__(self, state: ConsoleState, control: ConsoleControl, access: Access) -> None:
        self.state = state
        self.control = control
        self.access = access
        self._page = page_html()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._tick: asyncio.Event | None = None
        self._woken: asyncio.Event | None = None
        # The newest view (JSON) and how many there were: a stream sends each it has not sent.
        self._latest = "{}"
        self._sequence = 0
        self._closing = False
        self._server: uvicorn.Server | None = None
        self._thread: threading.Thread | None = None
        self._socket: socket.socket | None = None
        self.port = access.address.port
        self.streams = 0  # open live streams (tests and the bench look)

    # ------------------------------------------------------------ life cycle

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
            raise AccessError(f"--console: cannot listen on {address.host}:{address.port}: {reason}") from None
        sock.listen(64)
        self._socket = sock
        self.port = sock.getsockname()[1]
        app = Starlette(
            routes=[
                Route("/", self._index),
                Route("/state", self._state),
                Route("/events", self._events),
                Route("/control", self._control, methods=["POST"]),
            ]
        )
        config = uvicorn.Config(
            app, log_level="error", lifespan="off", timeout_graceful_shutdown=CLOSE_GRACE, access_log=False
        )
        self._server = uvicorn.Server(config)
        started = threading.Event()
        self._thread = threading.Thread(target=self._serve, args=(started,), name="gpp-console", daemon=True)
        self._thread.start()
        started.wait(10.0)

    @property
    def url(self) -> str:
        base = self.access.address.url(self.port)
        return base + (f"?token={self.access.token}" if self.access.token else "")

    def _serve(self, started: threading.Event) -> None:
        assert self._server is not None and self._socket is not None

        async def serve() -> None:
            self._loop = asyncio.get_running_loop()
            self._tick = asyncio.Event()
            self.state.on_change(self._changed)
            pusher = asyncio.create_task(self._push())
            started.set()
            assert self._server is not None and self._socket is not None
            try:
                await self._server.serve(sockets=[self._socket])
            finally:
                pusher.cancel()

        try:
            asyncio.run(serve())
        finally:
            started.set()

    def close(self) -> None:
        """Send the last view to the open streams, end them, stop serving."""
        self.state.on_change(None)
        loop = self._loop
        if loop is not None and not loop.is_closed():
            with contextlib.suppress(RuntimeError):
                loop.call_soon_threadsafe(self._finish)
        if self._thread is not None:
            self._thread.join(CLOSE_GRACE + 3.0)
        if self._socket is not None:
            self._socket.close()

    def _finish(self) -> None:
        self._closing = True
        self._publish(self._view(closed=True))
        if self._server is not None:
            self._server.should_exit = True

    # ------------------------------------------------------------ pushing

    def _changed(self) -> None:
        """From the executor's thread: the run changed the view."""
        loop = self._loop
        if loop is not None:
            with contextlib.suppress(RuntimeError):  # the loop closed meanwhile
                loop.call_soon_threadsafe(self._wake)

    def _wake(self) -> None:
        if self._woken is not None:
            self._woken.set()

    async def _push(self) -> None:
        """Fold the run's records into a new view when they come (or the clock moved), and
        tell the streams."""
        woken = self._woken = asyncio.Event()
        while not self._closing:
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(woken.wait(), HEARTBEAT)
            woken.clear()
            view = self._view()
            if view != self._latest:
                self._publish(view)
            await asyncio.sleep(1.0 / PUSHES_PER_SECOND)

    def _publish(self, view: str) -> None:
        """A new view for the streams."""
        self._latest = view
        self._sequence += 1
        self._pulse()

    def _pulse(self) -> None:
        tick = self._tick
        self._tick = asyncio.Event()
        if tick is not None:
            tick.set()

    def _view(self, closed: bool = False) -> str:
        data = self.state.view(self.control.clock())
        data["closed"] = closed
        data["can"] = self.control.can()
        return json.dumps(data, ensure_ascii=False, default=str)

    # ------------------------------------------------------------ routes

    def _refused(self, request: HttpRequest, control: bool) -> Response | None:
        why = self.access.refusal(request.headers, request.query_params, control=control)
        if why is None:
            return None
        status = 401 if "token" in why else 403
        return JSONResponse({"error": f"refused: {why}"}, status_code=status)

    async def _index(self, request: HttpRequest) -> Response:
        refused = self._refused(request, control=False)
        if refused is not None:
            return refused
        return HTMLResponse(self._page, headers={"Cache-Control": "no-store", "Referrer-Policy": "no-referrer"})

    async def _state(self, request: HttpRequest) -> Response:
        refused = self._refused(request, control=False)
        if refused is not None:
            return refused
        if not self._closing:
            view = self._view()
            if view != self._latest:
                self._publish(view)
        return Response(self._latest, media_type="application/json")

    async def _events(self, request: HttpRequest) -> Response:
        refused = self._refused(request, control=False)
        if refused is not None:
            return refused
        return StreamingResponse(self._stream(), media_type="text/event-stream", headers={"Cache-Control": "no-store"})

    async def _stream(self) -> AsyncIterator[str]:
        self.streams += 1
        try:
            if self._sequence == 0:
                self._publish(self._view())
            seen = self._sequence
            yield f"data: {self._latest}\n\n"
            while True:
                if seen == self._sequence:
                    if self._closing:
                        return
                    tick = self._tick
                    if tick is not None:
                        with contextlib.suppress(TimeoutError):
                            await asyncio.wait_for(tick.wait(), HEARTBEAT * 5)
                    if seen == self._sequence:
                        yield ": still here\n\n"  # a comment: a vanished browser is noticed
                        continue
                seen = self._sequence
                yield f"data: {self._latest}\n\n"
        finally:
            self.streams -= 1

    async def _control(self, request: HttpRequest) -> Response:
        refused = self._refused(request, control=True)
        if refused is not None:
            return refused
        try:
            body: Any = await request.json()
        except ValueError:
            return JSONResponse({"error": "the request is not JSON"}, status_code=400)
        problem = self._read(body, request.client.host if request.client else None)
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


__all__ = ["ConsoleServer", "serve"]
