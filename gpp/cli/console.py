"""`gpp console`: one page for several agents (gpp.console.hub). Registered on the app by
gpp.cli.app. The web libraries are imported only when the command runs."""

from __future__ import annotations

import sys
import time
from typing import Annotated

import typer

from gpp.cli.common import console_access, usage_error

DEFAULT_HUB = "127.0.0.1:8770"


def register(app: typer.Typer) -> None:
    app.command(name="console")(console)


def console(
    address: Annotated[
        str,
        typer.Argument(metavar="[HOST:PORT]", help=f"Where the page is served (default {DEFAULT_HUB})."),
    ] = DEFAULT_HUB,
    agent: Annotated[
        list[str] | None,
        typer.Option(
            "--agent",
            metavar="URL",
            help="An agent's console (`gpp run --console`), its address as it printed it, token included (repeatable).",
        ),
    ] = None,
    ros2_agent: Annotated[
        list[str] | None,
        typer.Option(
            "--ros2-agent",
            metavar="NODE",
            help="An agent on ROS 2, read from its live records topic NODE/events (repeatable; its panel "
            "only shows the run).",
        ),
    ] = None,
    token: Annotated[
        str | None,
        typer.Option(
            "--token", metavar="TOKEN", help="The token the page asks for (default: none on loopback, else a new one)."
        ),
    ] = None,
) -> None:
    """Serve one page for several agents: those named here, and every `gpp run --console
    --console-join URL` that joins. Runs until Ctrl-C."""
    from gpp.console.access import AccessError
    from gpp.console.hub import HttpFeed, Hub, Ros2Feed

    access = console_access(address, False, token)
    assert access is not None
    feeds: list[HttpFeed] = []
    for url in agent or []:
        try:
            feeds.append(HttpFeed(url))
        except ValueError as e:
            usage_error(f"--agent: {e}")
    hub = Hub(access)
    try:
        hub.start()
    except AccessError as e:
        usage_error(f"gpp console: {e}")
    bridge = None
    try:
        for feed in feeds:
            hub.add(feed)
        if ros2_agent:
            from gpp.platform.ros2.bridge import Bridge

            bridge = Bridge(node_name="gpp_console")
            for node in ros2_agent:
                hub.add(Ros2Feed(node, bridge))
        print(f"console: {hub.url}", file=sys.stderr, flush=True)
        if not access.address.loopback:
            print(
                f"warning: the console listens on {access.address.host}, beyond this machine, without TLS: its "
                "token and everything it shows cross the network in plain text",
                file=sys.stderr,
                flush=True,
            )
        while True:
            time.sleep(3600)
    finally:
        hub.close()
        if bridge is not None:
            bridge.close()
