"""Serving one debugging session over stdio or a loopback TCP connection."""

from __future__ import annotations

import socket
import sys

from gpp.dap.protocol import Connection
from gpp.dap.server import DebugServer


def serve_stdio() -> None:
    """One session on stdin/stdout (nothing else may write to stdout: it is the protocol's)."""
    stdout = sys.stdout.buffer
    # Whatever else prints goes to stderr, where the editor shows it as the adapter's log.
    sys.stdout = sys.stderr
    DebugServer(Connection(sys.stdin.buffer, stdout)).serve()


def serve_tcp(host: str, port: int) -> None:
    """Wait for one client on HOST:PORT and serve its session."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as listener:
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        listener.bind((host, port))
        listener.listen(1)
        print(f"gpp dap: listening on {host}:{port}", file=sys.stderr, flush=True)
        connection, _ = listener.accept()
        with connection, connection.makefile("rb") as reader, connection.makefile("wb") as writer:
            DebugServer(Connection(reader, writer)).serve()
