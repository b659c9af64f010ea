"""The language server as `gpp lsp` runs it: the document server of lsp.server with the
requests of lsp.handlers, on stdio or on a TCP port."""

from __future__ import annotations

import sys

from lsp.handlers import register_features
from lsp.server import GppServer, document_server

# How often a thread that holds the interpreter lock lets a waiting one run (Python's default
# is every 5 ms): a request answered while a check runs needs the lock a dozen times, on the
# event loop and on the request thread, and waited 5 ms each time.
SWITCH_INTERVAL_SECONDS = 0.001


def make_server() -> GppServer:
    """The server with every handler registered."""
    server = document_server()
    register_features(server)
    return server


def serve_stdio() -> None:
    sys.setswitchinterval(SWITCH_INTERVAL_SECONDS)
    make_server().start_io()


def serve_tcp(host: str, port: int) -> None:
    sys.setswitchinterval(SWITCH_INTERVAL_SECONDS)
    make_server().start_tcp(host, port)
