"""Who may use the console (docs/console.md, "Security"): the address it listens on, the token,
and the checks every request passes. No web library is imported here.

* It listens on loopback unless told otherwise; any other address needs a token (given, or
  generated and printed as Jupyter does).
* With a token, every request needs it: the page and the live stream in the query (`?token=`)
  or the header, a control request in the `X-Gpp-Token` header only (never a cookie: another
  site's page cannot make the browser send a header, so it cannot drive the robot).
* A request that names another origin (`Origin`, `Sec-Fetch-Site`) is refused, and so is one
  for a host name that is not the console's own on loopback (DNS rebinding). No CORS headers
  are ever sent.
"""

from __future__ import annotations

import hmac
import ipaddress
import re
import secrets
from collections.abc import Mapping
from dataclasses import dataclass

DEFAULT_ADDRESS = "127.0.0.1:8765"
TOKEN_HEADER = "x-gpp-token"
# The header in which the `gpp console` hub says for whom it passes a control request on.
FOR_HEADER = "x-gpp-for"
LOOPBACK_NAMES = ("localhost", "127.0.0.1", "::1")


class AccessError(Exception):
    """A console address or token that cannot be used (a usage error)."""


@dataclass(frozen=True, slots=True)
class Address:
    host: str
    port: int

    @property
    def loopback(self) -> bool:
        return is_loopback(self.host)

    def url(self, port: int | None = None) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        if self.host in ("0.0.0.0", "::"):
            host = "127.0.0.1"  # what a browser on this machine opens; other machines use its address
        return f"http://{host}:{self.port if port is None else port}/"


def parse_address(text: str) -> Address:
    """`HOST:PORT`, `[IPv6]:PORT` or `PORT` (on 127.0.0.1)."""
    found = re.fullmatch(r"\s*(?:(\[[^\]]+\]|[^\s:\[\]]*):)?([0-9]{1,5})\s*", text)
    if found is None:
        raise AccessError(f"--console takes HOST:PORT (such as {DEFAULT_ADDRESS}), not {text!r}")
    host = (found.group(1) or "127.0.0.1").strip("[]") or "127.0.0.1"
    port = int(found.group(2))
    if port > 65535:
        raise AccessError(f"--console: port {port} is not a port number (0 to 65535)")
    return Address(host, port)


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def new_token() -> str:
    return secrets.token_urlsafe(24)


@dataclass(frozen=True, slots=True)
class Access:
    """The rules for one console: where it listens, the token it needs (None: none)."""

    address: Address
    token: str | None

    def refusal(self, headers: Mapping[str, str], query: Mapping[str, str], *, control: bool) -> str | None:
        """Why a request is refused (None: it is allowed). `headers` with lower-case names;
        `control`: it changes the run (a header token only)."""
        host = headers.get("host", "")
        if self.address.loopback and _host_name(host) not in LOOPBACK_NAMES:
            return f"this console answers on loopback only, not for host {host!r}"
        origin = headers.get("origin")
        if origin is not None and origin != f"http://{host}":
            return "a request from another origin"
        if headers.get("sec-fetch-site", "same-origin") not in ("same-origin", "none"):
            return "a request from another site"
        if control and not headers.get("content-type", "").startswith("application/json"):
            return "a control request is JSON"
        if self.token is None:
            return None
        given = headers.get(TOKEN_HEADER)
        if given is None and not control:
            given = query.get("token")
        if given is None:
            return "no token" if not control else "no token in the X-Gpp-Token header"
        if not hmac.compare_digest(given.encode(), self.token.encode()):
            return "a wrong token"
        return None


def _host_name(host: str) -> str:
    """The name in a Host header, without its port."""
    if host.startswith("["):
        return host[1:].partition("]")[0]
    return host.rpartition(":")[0] if ":" in host else host
