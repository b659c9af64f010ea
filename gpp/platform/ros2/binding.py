"""The binding file of the ros2 platform: what a mapping cannot say (a mapped name's interface
type, timeouts, stamped fields, the sensing result field, QoS, the topics or services that
answer exogenous functions).

A TOML file beside the agent (`agent.ros2.toml` for `agent.gpp`), or the file named by a
`// ros2: FILE` line of the program, or by `-o binding=FILE`; its tables: docs/platforms.md.
Everything is checked when the file is read (unknown keys with a did-you-mean, value types);
whether its names fit the program is checked when the program attaches.
"""

from __future__ import annotations

import dataclasses
import math
import re
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gpp.base.source import Source, Span
from gpp.base.suggest import did_you_mean
from gpp.platform.ros2.names import MappedName, NameError_, is_name, normalize, parse_mapped
from gpp.platform.values import show_plain


class BindingError(Exception):
    """A binding file that cannot be used; the message says where (file:line) and why."""


_TIMEOUTS = ("server_timeout", "ack_timeout", "result_timeout", "feedback_timeout")
# Timeouts that may be 0 (no limit).
_MAY_BE_ZERO = ("result_timeout", "feedback_timeout")
# The tables of a binding file that are not ROS names.
_TABLES = ("defaults", "exog_function")
_DEFAULT_KEYS = frozenset({*_TIMEOUTS, "timeout", "resend", "discovery_timeout"})
_NAME_KEYS = frozenset({"type", *_TIMEOUTS, "resend", "stamp", "result", "qos"})
_FUNCTION_KEYS = frozenset(
    {"topic", "service", "feedback", "field", "request", "timeout", "qos", "server_timeout"}
    | {"max_age", "poll", "max_rate"}
)
# The keys that apply to one kind of source only.
_FUNCTION_KEY_KINDS = {
    "request": ("service",),
    "timeout": ("service",),
    "server_timeout": ("service",),
    "poll": ("service",),
    "qos": ("topic",),
    "max_age": ("topic", "feedback"),
    "max_rate": ("topic", "feedback"),
}
_QOS_KEYS = frozenset({"reliability", "durability", "depth", "history"})
_QOS_WORDS = {
    "reliability": ("reliable", "best_effort"),
    "durability": ("volatile", "transient_local"),
    "history": ("keep_last", "keep_all"),
}

DEFAULT_SERVER_TIMEOUT = 5.0
DEFAULT_ACK_TIMEOUT = 5.0
DEFAULT_SERVICE_TIMEOUT = 10.0
DEFAULT_FUNCTION_TIMEOUT = 2.0
# Discovery across processes on one machine (bench/ros2.py: 140 runs, both directions, idle
# and with both cores busy) takes about 0.1 s, but in about one run of six it misses its first
# exchange and waits for Fast DDS's next announcement, 3 s later: up to 3.29 s measured. 5 s
# leaves a margin.
DEFAULT_DISCOVERY_TIMEOUT = 5.0


@dataclass(frozen=True)
class Qos:
    reliability: str | None = None  # None: chosen from the publishers
    durability: str | None = None
    depth: int | None = None
    history: str | None = None


@dataclass
class NameEntry:
    """Settings for one mapped ROS name."""

    name: str
    type: str | None = None
    # The name as the binding file writes it (resolved again under the node's namespace).
    written: str = ""
    server_timeout: float | None = None
    ack_timeout: float | None = None
    result_timeout: float | None = None
    feedback_timeout: float | None = None
    resend: bool | None = None
    stamp: tuple[str, ...] = ()
    result: str | None = None
    qos: Qos | None = None
    span: Span | None = None


@dataclass
class FunctionEntry:
    """Where an exogenous function's answers come from."""

    function: str
    source: MappedName
    kind: str  # "topic", "service" or "feedback" (of the goals sent to an action)
    field: str | None = None
    request: dict[str, str] = dataclasses.field(default_factory=dict)
    timeout: float | None = None
    server_timeout: float | None = None
    qos: Qos | None = None
    span: Span | None = None
    # Topic and feedback: the latest value is no answer once it is older than this (s).
    max_age: float | None = None
    # Topic and feedback: a waiting program is woken at most this many times a second.
    max_rate: float | None = None
    # Service: a waiting program asks again every `poll` seconds.
    poll: float | None = None


@dataclass
class Binding:
    path: Path | None = None
    server_timeout: float = DEFAULT_SERVER_TIMEOUT
    ack_timeout: float = DEFAULT_ACK_TIMEOUT
    result_timeout: float | None = None  # actions; services default to DEFAULT_SERVICE_TIMEOUT
    feedback_timeout: float | None = None  # actions: none by default
    resend: bool = False  # a goal request not answered within ack_timeout is sent once more
    timeout: float = DEFAULT_FUNCTION_TIMEOUT  # exogenous function calls
    # s to wait at attach for the names mapped without a type to show up in the ROS graph
    discovery_timeout: float = DEFAULT_DISCOVERY_TIMEOUT
    names: dict[str, NameEntry] = field(default_factory=dict)
    functions: dict[str, FunctionEntry] = field(default_factory=dict)

    def resolved(self, resolve: Callable[[str], str]) -> Binding:
        """The binding with its ROS names resolved by `resolve` (under the agent node's
        namespace, with its remapping rules), as the program's mapped names are."""
        names = {}
        for entry in self.names.values():
            name = resolve(entry.written or entry.name)
            names[name] = dataclasses.replace(entry, name=name)
        # A source with placeholders is resolved per name it stands for, once they are filled.
        functions = {
            fname: f
            if "{" in (f.source.written or f.source.name)
            else dataclasses.replace(
                f, source=dataclasses.replace(f.source, name=resolve(f.source.written or f.source.name))
            )
            for fname, f in self.functions.items()
        }
        return dataclasses.replace(self, names=names, functions=functions)

    def entry(self, name: str) -> NameEntry:
        return self.names.get(name) or NameEntry(name)

    def server_timeout_for(self, name: str) -> float:
        e = self.names.get(name)
        return e.server_timeout if e is not None and e.server_timeout is not None else self.server_timeout

    def ack_timeout_for(self, name: str) -> float:
        e = self.names.get(name)
        return e.ack_timeout if e is not None and e.ack_timeout is not None else self.ack_timeout

    def result_timeout_for(self, name: str, service: bool) -> float | None:
        e = self.names.get(name)
        if e is not None and e.result_timeout is not None:
            return e.result_timeout or None
        if self.result_timeout is not None:
            return self.result_timeout or None
        return DEFAULT_SERVICE_TIMEOUT if service else None

    def feedback_timeout_for(self, name: str) -> float | None:
        e = self.names.get(name)
        if e is not None and e.feedback_timeout is not None:
            return e.feedback_timeout or None
        return self.feedback_timeout or None

    def resend_for(self, name: str) -> bool:
        e = self.names.get(name)
        return e.resend if e is not None and e.resend is not None else self.resend

    @classmethod
    def load(cls, path: Path) -> Binding:
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as e:
            raise BindingError(f"cannot read binding file '{path}': {e.strerror}") from None
        except UnicodeDecodeError:
            raise BindingError(f"binding file '{path}' is not UTF-8 text") from None
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise BindingError(f"binding file '{path}' is not valid TOML: {e}") from None
        return cls.from_data(data, Source(text, str(path)), path)

    @classmethod
    def from_data(cls, data: Mapping[str, Any], source: Source | None = None, path: Path | None = None) -> Binding:
        where = str(path) if path is not None else "binding"
        spans = _header_spans(source) if source is not None else {}
        binding = cls(path)

        def at(key: str) -> str:
            span = spans.get(key)
            return f"{where}:{span.line}: [{_header(key)}]" if span is not None else f"{where}: [{_header(key)}]"

        for key, value in data.items():
            if key == "defaults":
                table = _table(value, at(key))
                _check_keys(table, _DEFAULT_KEYS, at(key))
                for t in _TIMEOUTS:
                    if t in table:
                        setattr(binding, t, _seconds(table[t], f"{at(key)} {t}", allow_zero=t in _MAY_BE_ZERO))
                if "resend" in table:
                    binding.resend = _flag(table["resend"], f"{at(key)} resend")
                if "timeout" in table:
                    binding.timeout = _seconds(table["timeout"], f"{at(key)} timeout")
                if "discovery_timeout" in table:
                    binding.discovery_timeout = _seconds(table["discovery_timeout"], f"{at(key)} discovery_timeout")
            elif key == "exog_function":
                functions = _table(value, f"{where}: [exog_function]")
                for fname, entry in functions.items():
                    fkey = f"exog_function.{fname}"
                    binding.functions[fname] = _function(fname, _table(entry, at(fkey)), at(fkey), spans.get(fkey))
            elif key.strip().startswith(("/", "~")) or (is_name(key.strip()) and not did_you_mean(key, _TABLES)):
                if "{" in key or "}" in key:
                    raise BindingError(
                        f"{at(key)}: a table of the binding file is for one ROS name and cannot have a placeholder: "
                        'write a table for each name the mapping stands for, such as ["/robot1/navigate"]'
                    )
                try:
                    parse_mapped(key)
                except NameError_ as e:
                    raise BindingError(f"{at(key)}: {e}") from None
                name = normalize(key)
                binding.names[name] = _name_entry(name, _table(value, at(key)), at(key), spans.get(key))
                binding.names[name].written = key.strip()
            else:
                hint = did_you_mean(key, _TABLES)
                raise BindingError(
                    f"{at(key)}: unknown table `{key}`: tables are `[defaults]`, `[exog_function.NAME]` and "
                    'ROS names, such as `["/stack"]` or `["navigate"]`' + (f"; {hint}" if hint else "")
                )
        return binding


def find_binding(program: Path, explicit: Path | None, directive: Path | None) -> Path | None:
    """The binding file for a program: the option, else the `// ros2:` directive, else
    `NAME.ros2.toml` beside `NAME.gpp` when it exists."""
    if explicit is not None:
        return explicit
    if directive is not None:
        return directive
    beside = program.with_name(program.stem + ".ros2.toml")
    return beside if beside.is_file() else None


def _name_entry(name: str, table: Mapping[str, Any], at: str, span: Span | None) -> NameEntry:
    _check_keys(table, _NAME_KEYS, at)
    entry = NameEntry(name, span=span)
    if "type" in table:
        entry.type = _text(table["type"], f"{at} type")
    for t in _TIMEOUTS:
        if t in table:
            setattr(entry, t, _seconds(table[t], f"{at} {t}", allow_zero=t in _MAY_BE_ZERO))
    if "resend" in table:
        entry.resend = _flag(table["resend"], f"{at} resend")
    if "stamp" in table:
        stamps = table["stamp"]
        if isinstance(stamps, str):
            stamps = [stamps]
        if not isinstance(stamps, list) or not all(isinstance(s, str) and s for s in stamps):
            raise BindingError(f'{at} stamp: expected a list of field paths such as ["header.stamp"]')
        entry.stamp = tuple(stamps)
    if "result" in table:
        entry.result = _text(table["result"], f"{at} result")
    if "qos" in table:
        entry.qos = _qos(table["qos"], f"{at} qos")
    return entry


def _function(name: str, table: Mapping[str, Any], at: str, span: Span | None) -> FunctionEntry:
    _check_keys(table, _FUNCTION_KEYS, at)
    kinds = [k for k in ("topic", "service", "feedback") if k in table]
    if len(kinds) != 1:
        raise BindingError(
            f'{at}: give the source of `{name}`: `topic = "/name : package/msg/Type"` (its latest message), '
            '`service = "/name"` (a call each time) or `feedback = "/action"` (the latest feedback of the goal '
            "running on a mapped action)"
        )
    kind = kinds[0]
    for key, applies in _FUNCTION_KEY_KINDS.items():
        if key in table and kind not in applies:
            hint = "; a topic's value has a maximum age (`max_age`) instead" if key == "timeout" else ""
            raise BindingError(f"{at} {key}: only a {' or '.join(applies)} source takes `{key}`{hint}")
    try:
        source = parse_mapped(_text(table[kind], f"{at} {kind}"), placeholders=True)
    except NameError_ as e:
        raise BindingError(f"{at} {kind}: {e}") from None
    entry = FunctionEntry(name, source, kind, span=span)
    if "field" in table:
        entry.field = _text(table["field"], f"{at} field")
    if "request" in table:
        request = _table(table["request"], f"{at} request")
        for k, v in request.items():
            if not isinstance(v, str) or not v:
                raise BindingError(
                    f'{at} request: `{k}` must name a parameter of `{name}` (a string such as "x"), not {show_plain(v)}'
                )
            entry.request[k] = v
    if "timeout" in table:
        entry.timeout = _seconds(table["timeout"], f"{at} timeout")
    if "server_timeout" in table:
        entry.server_timeout = _seconds(table["server_timeout"], f"{at} server_timeout")
    if "qos" in table:
        entry.qos = _qos(table["qos"], f"{at} qos")
    if "max_age" in table:
        entry.max_age = _seconds(table["max_age"], f"{at} max_age")
    if "poll" in table:
        entry.poll = _seconds(table["poll"], f"{at} poll")
    if "max_rate" in table:
        entry.max_rate = _per_second(table["max_rate"], f"{at} max_rate")
    return entry


def _qos(value: Any, at: str) -> Qos:
    table = _table(value, at)
    _check_keys(table, _QOS_KEYS, at)
    words: dict[str, str] = {}
    for key, allowed in _QOS_WORDS.items():
        if key in table:
            v = table[key]
            if v not in allowed:
                hint = did_you_mean(str(v), allowed)
                raise BindingError(
                    f"{at}: {key} must be {' or '.join(show_plain(a) for a in allowed)}, not {show_plain(v)}"
                    + (f"; {hint}" if hint else "")
                )
            words[key] = v
    depth = table.get("depth")
    if depth is not None and (isinstance(depth, bool) or not isinstance(depth, int) or depth < 1):
        raise BindingError(f"{at}: depth must be a whole number >= 1, not {show_plain(depth)}")
    return Qos(words.get("reliability"), words.get("durability"), depth, words.get("history"))


def _table(value: Any, at: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise BindingError(f"{at}: expected a table, not {show_plain(value)}")
    return value


def _check_keys(table: Mapping[str, Any], known: frozenset[str], at: str) -> None:
    for key in table:
        if key not in known:
            hint = did_you_mean(key, known)
            raise BindingError(
                f"{at}: unknown key `{key}`" + (f"; {hint}" if hint else "") + f" (known: {', '.join(sorted(known))})"
            )


def _text(value: Any, at: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise BindingError(f"{at}: expected a non-empty string, not {show_plain(value)}")
    return value.strip()


def _flag(value: Any, at: str) -> bool:
    if not isinstance(value, bool):
        raise BindingError(f"{at}: expected true or false, not {show_plain(value)}")
    return value


def _seconds(value: Any, at: str, allow_zero: bool = False) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or value < 0 or (value == 0 and not allow_zero):
        bound = ">= 0 (0: no limit)" if allow_zero else "> 0"
        raise BindingError(f"{at}: expected a number of seconds {bound}, not {show_plain(value)}")
    return float(value)


def _per_second(value: Any, at: str) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or value <= 0:
        raise BindingError(f"{at}: expected a number of times a second > 0, not {show_plain(value)}")
    return float(value)


_HEADER_LINE = re.compile(r"^[ \t]*\[(?!\[)(.+?)\][ \t]*(#.*)?$", re.MULTILINE)


def _header(key: str) -> str:
    return f'"{key}"' if key.startswith(("/", "~")) else key


def _header_spans(source: Source) -> dict[str, Span]:
    """Where each `[table]` header of the file is, by its key (`/stack`, `defaults`,
    `exog_function.battery`)."""
    spans: dict[str, Span] = {}
    for m in _HEADER_LINE.finditer(source.text):
        parts = [p.strip().strip('"').strip("'") for p in re.split(r"\.(?=(?:[^\"]*\"[^\"]*\")*[^\"]*$)", m.group(1))]
        key = ".".join(parts)
        spans.setdefault(key, Span(source, m.start(1) - 1, m.end(1) + 1))
    return spans
