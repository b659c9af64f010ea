"""The Debug Adapter Protocol's wire format: messages as JSON with a `Content-Length` header,
over a byte stream (stdio or a TCP connection), and the one writer several threads share."""

from __future__ import annotations

import json
import threading
from typing import Any, BinaryIO

Message = dict[str, Any]


class ProtocolError(Exception):
    """The peer sent something that is not a DAP message (bad header, bad JSON)."""


class DapError(Exception):
    """A request that cannot be done: the message is the error response's one line for the user."""


def read_message(stream: BinaryIO) -> Message | None:
    """The next message, or None at the end of the stream. ProtocolError for a bad frame (the
    stream is then read past it)."""
    length: int | None = None
    while True:
        line = stream.readline()
        if not line:
            return None
        text = line.decode("ascii", "replace").strip()
        if not text:
            if length is None:
                continue  # stray blank line between frames
            break
        name, _, value = text.partition(":")
        if name.strip().lower() == "content-length":
            if not value.strip().isdigit():
                raise ProtocolError(f"bad Content-Length header `{text}`")
            length = int(value.strip())
    body = stream.read(length)
    if len(body) < length:
        return None
    try:
        message = json.loads(body.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise ProtocolError(f"a message that is not JSON: {e}") from None
    if not isinstance(message, dict):
        raise ProtocolError("a message that is not a JSON object")
    return message


def encode_message(message: Message) -> bytes:
    body = json.dumps(message, separators=(",", ":"), ensure_ascii=False).encode("utf-8")
    return b"Content-Length: " + str(len(body)).encode("ascii") + b"\r\n\r\n" + body


class Connection:
    """One DAP peer: reads requests (the protocol loop's thread only) and writes responses and
    events (any thread: the run's thread sends `stopped`, `output`, `terminated`)."""

    def __init__(self, reader: BinaryIO, writer: BinaryIO) -> None:
        self.reader = reader
        self.writer = writer
        self._lock = threading.Lock()
        self._seq = 0
        self.closed = False

    def read(self) -> Message | None:
        return read_message(self.reader)

    def send(self, message: Message) -> None:
        with self._lock:
            if self.closed:
                return
            self._seq += 1
            message["seq"] = self._seq
            try:
                self.writer.write(encode_message(message))
                self.writer.flush()
            except (OSError, ValueError):
                self.closed = True  # the editor went away: nothing more to say

    def respond(self, request: Message, body: Message | None = None) -> None:
        self.send(
            {
                "type": "response",
                "request_seq": request.get("seq", 0),
                "success": True,
                "command": request.get("command", ""),
                "body": body or {},
            }
        )

    def fail(self, request: Message, message: str, show_user: bool = True) -> None:
        self.send(
            {
                "type": "response",
                "request_seq": request.get("seq", 0),
                "success": False,
                "command": request.get("command", ""),
                "message": message,
                "body": {"error": {"id": 1, "format": message, "showUser": show_user}},
            }
        )

    def event(self, name: str, body: Message | None = None) -> None:
        message: Message = {"type": "event", "event": name}
        if body is not None:
            message["body"] = body
        self.send(message)
