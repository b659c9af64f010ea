"""The platform base class: a plugin that the runner creates from a configuration, attaches to
a program, runs the program on, and closes.

A platform is one self-contained module: it declares its options as a dataclass (`Options`),
the `// key:` directive that makes `gpp test` choose it (`selected_by`), and builds itself in
`create(config)`. Neither the runner nor the CLI knows any platform's options: the CLI passes
`--platform-opt key=value` pairs (and its shorthand flags such as `--world`) through, and
`parse_options` validates them against the platform's `Options`, with a did-you-mean.

What the executor asks of a platform while the program runs (start, preempt, exogenous
functions, the clock, the event queue) is the contract in gpp.runtime.contract; it is
re-exported here for platform authors.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, TypeVar, Union

from gpp.base.suggest import did_you_mean
from gpp.model.types import Type
from gpp.runtime.contract import (
    ActionBinding,
    Activity,
    ActivityUpdate,
    Event,
    EventQueue,
    ExogActionBinding,
    ExogFunctionChanged,
    ExogFunctionSignature,
    ExogOccurrence,
    MappedArgument,
    MessageDropped,
    NoAnswer,
    Parameter,
    PlatformError,
    PlatformFault,
    PlatformNotice,
    PlatformWarning,
    Problem,
    ProgramInterface,
)
from gpp.runtime.events import TraceEvent
from gpp.runtime.values import Value

__all__ = [
    "ActionBinding",
    "Activity",
    "ActivityUpdate",
    "Event",
    "EventQueue",
    "ExogActionBinding",
    "ExogFunctionChanged",
    "ExogFunctionSignature",
    "ExogOccurrence",
    "MappedArgument",
    "MessageDropped",
    "NoAnswer",
    "NoOptions",
    "OptionValue",
    "Parameter",
    "Platform",
    "PlatformConfig",
    "PlatformError",
    "PlatformFault",
    "PlatformNotice",
    "PlatformWarning",
    "Problem",
    "ProgramInterface",
    "RunFacts",
    "parse_options",
]

# A platform option as given: text from the command line, or a value from code.
OptionValue = str | int | float | bool | Path


@dataclass(frozen=True)
class PlatformConfig:
    """Everything a platform is created from."""

    # The program to run (relative paths in its directives are relative to its folder).
    program: Path
    # The program's `// key: value` directives (from the comment lines at its top).
    directives: Mapping[str, str] = field(default_factory=dict)
    # Platform options: `--platform-opt key=value` and the CLI's shorthand flags.
    options: Mapping[str, OptionValue] = field(default_factory=dict)
    # The platform's own command-line arguments (for ros2: those after `--ros-args`).
    arguments: tuple[str, ...] = ()

    def directive_path(self, key: str) -> Path | None:
        """A directive naming a file, resolved against the program's folder."""
        value = self.directives.get(key)
        return self.program.parent / value if value is not None else None


@dataclass(frozen=True)
class RunFacts:
    """What a platform tells the trace's header about a run (what it needs to be repeated)."""

    world: str | None = None
    scenario: str | None = None
    seed: int | None = None
    node: str | None = None  # a ROS node's fully qualified name


@dataclass(frozen=True)
class NoOptions:
    """The options of a platform that takes none."""


class Platform:
    """Base class of platforms. Subclasses override what they serve (see the module docstring and
    gpp.runtime.contract.PlatformPort for what each method must do)."""

    name: ClassVar[str] = "platform"
    # True when time is simulated (the run goes as fast as the CPU allows).
    virtual_time: ClassVar[bool] = True
    # The `// key:` directive that makes `gpp test` run a program on this platform.
    selected_by: ClassVar[str | None] = None
    # The options `create` accepts: a frozen dataclass whose fields have defaults and a
    # `metadata={"help": ...}`.
    Options: ClassVar[type[Any]] = NoOptions

    def __init__(self) -> None:
        self.queue = EventQueue()

    @classmethod
    def create(cls, config: PlatformConfig) -> Platform:
        """The platform for a run (`gpp run --platform NAME`). Raises PlatformError for options
        it does not take, and for files it cannot use."""
        parse_options(cls.Options, config.options, cls.name)
        return cls()

    def attach(self, interface: ProgramInterface) -> list[Problem]:
        """Called once before the run. Returns every problem with the program's mappings (unknown
        mapped names, arguments, fields, values that cannot be served); empty when it fits."""
        return []

    def start(self, activity: Activity) -> None:
        raise NotImplementedError

    def preempt(self, activity: Activity) -> None:
        raise NotImplementedError

    def exog_function(
        self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
    ) -> Value:
        """Evaluate an exogenous function; `activity` is set while a `senses:` section of that
        activity is evaluated. (When the activity's update carried a result, the executor
        answers with it and does not ask the platform.)"""
        raise PlatformError(f"platform `{self.name}` does not provide exogenous function `{name}`")

    def now(self) -> float:
        raise NotImplementedError

    def wait(self, deadline: float | None, wall_deadline: float | None = None) -> bool:
        """The program is blocked: make time pass until something is queued or `deadline`
        (platform time) is reached. Returns False when nothing can ever arrive, or when the
        wall clock reaches `wall_deadline` (a `time.monotonic()` moment: the run's
        `--timeout`) first: a platform whose waiting takes wall-clock time returns by then."""
        raise NotImplementedError

    def live(self) -> bool:
        """Can an event still arrive (running activities, scheduled or live exogenous sources)?"""
        return True

    def close(self) -> None:
        """Stop threads and release resources. Called once, also after errors."""

    def trace_listener(self) -> Callable[[TraceEvent], None] | None:
        """A listener the run adds to its trace, told every record as it is written (a platform
        that shows the run to its own tools), or None."""
        return None

    def facts(self) -> RunFacts:
        """The world, scenario and seed of this run, where the platform has them."""
        return RunFacts()

    def entry_arguments(self) -> Mapping[str, tuple[object, str]]:
        """Values the platform was given for the entry procedure's parameters, by name, each
        with how it was given (for messages): the ros2 platform's ROS parameters (`-p n:=3`).
        Read once, after `create` and before `attach`."""
        return {}


# ---------------------------------------------------------------- options

OptionsT = TypeVar("OptionsT")


def parse_options(options_type: type[OptionsT], given: Mapping[str, OptionValue], platform: str) -> OptionsT:
    """A platform's options (a dataclass) from the given pairs: text is converted to the field's
    type, values from code are checked against it. Raises PlatformError for an unknown option
    (with a did-you-mean and the list of options) or a value that does not fit."""
    hints = typing.get_type_hints(options_type)
    known = {f.name: f for f in dataclasses.fields(options_type)}  # type: ignore[arg-type]
    values: dict[str, object] = {}
    for key, raw in given.items():
        if key not in known:
            hint = did_you_mean(key, known)
            listing = f"its options: {', '.join(sorted(known))}" if known else f"platform `{platform}` takes no options"
            raise PlatformError(
                f"platform `{platform}` has no option `{key}`" + (f"; {hint}" if hint else "") + f" ({listing})"
            )
        values[key] = _convert(raw, hints[key], f"option `{key}` of platform `{platform}`")
    return options_type(**values)


_TRUE = {"true", "yes", "on", "1"}
_FALSE = {"false", "no", "off", "0"}


def _convert(raw: OptionValue, target: object, what: str) -> object:
    """`raw` as a value of `target` (str, int, float, bool, Path, or one of those | None)."""
    kinds: tuple[object, ...] = (target,)
    if typing.get_origin(target) in (Union, types.UnionType):
        kinds = tuple(a for a in typing.get_args(target) if a is not type(None))
    kind = kinds[0]
    if kind is bool:
        if isinstance(raw, bool):
            return raw
        if isinstance(raw, str) and raw.lower() in _TRUE | _FALSE:
            return raw.lower() in _TRUE
        raise PlatformError(f"{what} must be true or false, not {raw!r}")
    if kind is int:
        if isinstance(raw, int) and not isinstance(raw, bool):
            return raw
        if isinstance(raw, str):
            try:
                return int(raw)
            except ValueError:
                pass
        raise PlatformError(f"{what} must be a whole number, not {raw!r}")
    if kind is float:
        if isinstance(raw, int | float) and not isinstance(raw, bool):
            return float(raw)
        if isinstance(raw, str):
            try:
                return float(raw)
            except ValueError:
                pass
        raise PlatformError(f"{what} must be a number, not {raw!r}")
    if kind is Path:
        if isinstance(raw, Path):
            return raw
        if isinstance(raw, str) and raw:
            return Path(raw)
        raise PlatformError(f"{what} must be a file path, not {raw!r}")
    if kind is str:
        if isinstance(raw, str):
            return raw
        if isinstance(raw, Path):
            return str(raw)
        raise PlatformError(f"{what} must be text, not {raw!r}")
    raise TypeError(f"{what}: options of type {kind!r} are not supported")
