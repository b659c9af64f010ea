"""A small Debug Adapter Protocol client for the tests: a real `gpp dap` subprocess over stdio,
Content-Length framing, requests answered in order, events kept until asked for."""

from __future__ import annotations

import json
import os
import queue
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Any

from gpp.dap.protocol import encode_message, read_message

Message = dict[str, Any]

# Seconds a test waits for an answer or an event before it fails (never a measurement).
WAIT = 60.0

ROOT = Path(__file__).resolve().parents[2]


class DapFailure(AssertionError):
    """An answer or event did not come, or came other than expected."""


class DapClient:
    def __init__(self, process: subprocess.Popen[bytes]) -> None:
        self.process = process
        self.seq = 0
        self.responses: dict[int, queue.Queue[Message]] = {}
        self.events: queue.Queue[Message] = queue.Queue()
        self.seen: list[Message] = []
        self.disconnected = False
        self.lock = threading.Lock()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        while True:
            try:
                message = read_message(self.process.stdout)
            except Exception:
                message = {"type": "event", "event": "<bad frame>"}
            if message is None:
                self.events.put({"type": "event", "event": "<end of stream>"})
                return
            if message.get("type") == "response":
                with self.lock:
                    box = self.responses.setdefault(int(message["request_seq"]), queue.Queue())
                box.put(message)
            else:
                self.events.put(message)

    # ---------------------------------------------------------------- requests

    def send(self, command: str, arguments: Message | None = None) -> int:
        if command == "disconnect":
            self.disconnected = True
        self.seq += 1
        message: Message = {"seq": self.seq, "type": "request", "command": command}
        if arguments is not None:
            message["arguments"] = arguments
        assert self.process.stdin is not None
        self.process.stdin.write(encode_message(message))
        self.process.stdin.flush()
        return self.seq

    def response(self, seq: int) -> Message:
        with self.lock:
            box = self.responses.setdefault(seq, queue.Queue())
        try:
            return box.get(timeout=WAIT)
        except queue.Empty:
            raise DapFailure(f"no response to request {seq}") from None

    def request(self, command: str, arguments: Message | None = None) -> Message:
        """Send a request and return the whole response (success or not)."""
        return self.response(self.send(command, arguments))

    def ok(self, command: str, arguments: Message | None = None) -> Message:
        """A request that must succeed: its body."""
        found = self.request(command, arguments)
        if not found["success"]:
            raise DapFailure(f"{command} failed: {found.get('message')}")
        body: Message = found.get("body") or {}
        return body

    def error(self, command: str, arguments: Message | None = None) -> str:
        """A request that must fail: its message."""
        found = self.request(command, arguments)
        if found["success"]:
            raise DapFailure(f"{command} succeeded: {found.get('body')}")
        return str(found["message"])

    # ---------------------------------------------------------------- events

    def event(self, name: str) -> Message:
        """The next event called `name` (earlier ones of other names are kept in `seen`)."""
        while True:
            try:
                found = self.events.get(timeout=WAIT)
            except queue.Empty:
                raise DapFailure(f"no `{name}` event; seen {[e.get('event') for e in self.seen]}") from None
            self.seen.append(found)
            if found.get("event") == name:
                return found
            if found.get("event") in ("<end of stream>", "<bad frame>") or (
                found.get("event") == "terminated" and name not in ("exited", "output")
            ):
                raise DapFailure(f"`{found['event']}` while waiting for `{name}`; seen {self.outputs()}")

    def stopped(self) -> Message:
        body: Message = self.event("stopped")["body"]
        return body

    def outputs(self) -> list[str]:
        return [e["body"]["output"] for e in self.seen if e.get("event") == "output"]

    # ---------------------------------------------------------------- sessions

    def start(self, launch: Message, breakpoints: dict[str, list[Message]] | None = None, **more: Any) -> None:
        """initialize, launch, the breakpoints, configurationDone."""
        self.ok("initialize", {"adapterID": "gpp", "linesStartAt1": True, "columnsStartAt1": True})
        self.ok("launch", launch)
        self.event("initialized")
        for path, wanted in (breakpoints or {}).items():
            self.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": wanted})
        if "functions" in more:
            self.ok("setFunctionBreakpoints", {"breakpoints": [{"name": n} for n in more["functions"]]})
        if "exceptions" in more:
            self.ok("setExceptionBreakpoints", {"filters": more["exceptions"]})
        self.ok("configurationDone")

    def top(self) -> Message:
        frames: list[Message] = self.ok("stackTrace", {"threadId": 1})["stackFrames"]
        return frames[0]

    def scope(self, name: str, frame: int = 0) -> list[Message]:
        scopes = self.ok("scopes", {"frameId": frame})["scopes"]
        found = next(s for s in scopes if s["name"] == name)
        variables: list[Message] = self.ok("variables", {"variablesReference": found["variablesReference"]})[
            "variables"
        ]
        return variables

    def evaluate(self, expression: str, context: str = "repl", frame: int | None = 0) -> Message:
        args: Message = {"expression": expression, "context": context}
        if frame is not None:
            args["frameId"] = frame
        return self.ok("evaluate", args)

    def close(self) -> int:
        if self.process.poll() is None and not self.disconnected:
            with suppress(DapFailure, OSError):
                self.request("disconnect", {"terminateDebuggee": True})
        try:
            return self.process.wait(timeout=WAIT)
        except subprocess.TimeoutExpired:
            self.process.kill()
            return self.process.wait()


@contextmanager
def dap_session(cwd: Path | None = None) -> Iterator[DapClient]:
    """A `gpp dap` subprocess (this checkout's gpp) and a client talking to it."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    process = subprocess.Popen(
        [sys.executable, "-m", "gpp", "dap"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=cwd,
        env=env,
    )
    client = DapClient(process)
    try:
        yield client
    finally:
        client.close()
        for stream in (process.stdin, process.stdout, process.stderr):
            if stream is not None:
                stream.close()


def dumps(message: Message) -> str:
    return json.dumps(message, indent=1)


def line_of(path: Path, text: str, occurrence: int = 1) -> int:
    """The line (from 1) of the `occurrence`-th line of `path` that holds `text`."""
    found = [i for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1) if text in line]
    if len(found) < occurrence:
        raise DapFailure(f"`{text}` is not in {path} {occurrence} times")
    return found[occurrence - 1]
