"""What the built-in platforms declare without being imported (the sim needs pymunk, ros2
needs rclpy): where each one's class is, the directive that selects it, and its options.

Options are a frozen dataclass per platform; each field has a default and a `help`, and an
option that also has a command-line flag of its own (`--world W` for `-o world=W`) says so
with a `Flag`. The registry (gpp.platform) reads this module to choose a platform, and the CLI
builds the flags of `gpp run` and `gpp test` from it; each platform validates its options
with gpp.platform.base.parse_options. A platform from the `gpp.platforms` entry-point group
declares the same things on its class (`Options`, `selected_by`) and has no flags.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class Flag:
    """An option with a command-line flag of its own. `single_run`: only `gpp run` offers it
    (an output of one run, or pacing), `gpp test` does not."""

    single_run: bool = False


def about(help: str, flag: Flag | None = None, *, output: bool = False) -> dict[str, Any]:
    """The metadata of an option: its help, its flag if it has one, and whether it names a file
    the platform writes (`output`; any other option naming a file is something it reads)."""
    return {"help": help, "flag": flag, "output": output}


def is_output(f: dataclasses.Field[Any]) -> bool:
    return bool(f.metadata.get("output"))


def flag_of(f: dataclasses.Field[Any]) -> Flag | None:
    found = f.metadata.get("flag")
    return found if isinstance(found, Flag) else None


@dataclass(frozen=True)
class DummyOptions:
    scenario: Path | None = field(
        default=None,
        metadata=about("a TOML file scripting outcomes and events (default: the `// scenario:` line)", Flag()),
    )
    seed: int | None = field(default=None, metadata=about("seed for --random (default: 1)", Flag()))
    random: bool = field(default=False, metadata=about("random durations, exogenous events and answers", Flag()))


@dataclass(frozen=True)
class SimOptions:
    world: str | None = field(
        default=None,
        metadata=about("a world name from stdlib/worlds or a TOML file (default: the `// world:` line)", Flag()),
    )
    seed: int | None = field(default=None, metadata=about("seed for simulated faults (default: the world's)", Flag()))
    scenario: Path | None = field(
        default=None,
        metadata=about(
            "a TOML file scripting what the world does not model: the actions without a mapping the sim serves, "
            "exogenous events, answers (default: the `// scenario:` line)",
            Flag(),
        ),
    )
    record: Path | None = field(
        default=None, metadata=about("write an animated GIF of the run here", Flag(single_run=True), output=True)
    )
    snapshot: Path | None = field(
        default=None, metadata=about("write the last frame (PNG) here", Flag(single_run=True), output=True)
    )
    realtime: bool = field(default=False, metadata=about("pace sim time to wall time", Flag(single_run=True)))


@dataclass(frozen=True)
class Ros2Options:
    binding: Path | None = field(
        default=None,
        metadata=about("the binding file (default: the `// ros2:` line, else NAME.ros2.toml beside NAME.gpp)"),
    )
    domain_id: int | None = field(default=None, metadata=about("ROS domain id (default: $ROS_DOMAIN_ID, else 0)"))
    server_timeout: float | None = field(
        default=None, metadata=about("s to wait for a server to appear (default: the binding file's, else 5)")
    )
    node_name: str | None = field(
        default=None, metadata=about("the name of the agent's ROS node (default: gpp_agent; or `-r __node:=NAME`)")
    )
    namespace: str | None = field(
        default=None,
        metadata=about("the namespace of the agent's ROS node (default: $ROS_NAMESPACE, else /; or `-r __ns:=NS`)"),
    )
    discovery_timeout: float | None = field(
        default=None,
        metadata=about(
            "s the attach waits at most for discovery: for the names mapped without a type (their mappings are "
            "checked first) and the subscribers of the topics the program publishes on (default: the binding "
            "file's, else 5)"
        ),
    )
    log_level: str | None = field(
        default=None, metadata=about("rclpy's log level (debug, info, warn, error; default: warn; or `--log-level`)")
    )
    use_sim_time: bool = field(
        default=False,
        metadata=about(
            "follow the simulator's clock on /clock (as the ROS parameter use_sim_time does): context_time(), the "
            "trace's times, time stamps and time-based waits"
        ),
    )
    publish_trace: bool = field(
        default=True,
        metadata=about("publish the run's records on ~/events and its state on ~/state (latched), as JSON"),
    )


@dataclass(frozen=True)
class Declaration:
    """A built-in platform: its class as `module:Class`, the `// key:` directive that selects
    it, its options, and its check of a program without running it."""

    target: str
    options: type[Any]
    selected_by: str | None = None
    # Its check of a program without running it, as `module:function` (gpp.platform.static).
    static_check: str | None = None


BUILTIN: dict[str, Declaration] = {
    "dummy": Declaration("gpp.platform.dummy:DummyPlatform", DummyOptions),
    "sim": Declaration("gpp.platform.sim:SimPlatform", SimOptions, selected_by="world"),
    "ros2": Declaration(
        "gpp.platform.ros2:Ros2Platform",
        Ros2Options,
        selected_by="ros2",
        static_check="gpp.platform.ros2.static:check",
    ),
}
