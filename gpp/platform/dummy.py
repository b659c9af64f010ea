"""The dummy platform: virtual time, scripted or seeded-random outcomes.

Activities succeed after a duration (the action's `duration:` minimum, else 1 s) unless a
scenario says otherwise. A scenario (TOML) scripts, per action pattern, the outcome (final,
fail, cancel), the duration and the sensing result; exogenous events at given times; and the
answers of exogenous functions. With `random=True` and a seed it generates them instead, as
the original golog++ dummy backend did: durations of 0.01-0.5 s (or within `duration:`), an
exogenous event every 0-2 s, random exogenous function answers; reproducible per seed.

Time is virtual: when the program waits, the clock jumps to the next scheduled happening, so
runs take as long as the CPU needs, not as long as the robot would.
"""

from __future__ import annotations

import copy
import heapq
import random
import re
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gpp.base.numbers import MAX_SECONDS, bound_text, describe
from gpp.base.source import Source, Span
from gpp.base.suggest import did_you_mean
from gpp.model.types import BOOL, NUMBER, STRING, SYMBOL, CompoundType, DomainType, ListType, Sym, Type
from gpp.platform.base import (
    Activity,
    ActivityUpdate,
    Event,
    ExogOccurrence,
    Platform,
    PlatformConfig,
    PlatformError,
    Problem,
    ProgramInterface,
    RunFacts,
    parse_options,
)
from gpp.platform.options import BUILTIN, DummyOptions
from gpp.platform.values import ConversionError, show_plain, to_value
from gpp.runtime.state import ActivityStatus, GroundAction
from gpp.runtime.values import CompoundValue, Value, show


class ScenarioError(Exception):
    """A scenario file that cannot be used; the message says where and why."""


_OUTCOMES = {"final": ActivityStatus.FINAL, "fail": ActivityStatus.FAILED, "cancel": ActivityStatus.CANCELLED}

# The keys each kind of scenario entry may have.
_KEYS: dict[str, frozenset[str]] = {
    "defaults": frozenset({"duration"}),
    "action": frozenset({"match", "outcome", "duration", "result", "times"}),
    "exog": frozenset({"at", "action", "args"}),
    "exog_function": frozenset({"name", "args", "value", "values"}),
}


@dataclass
class ActionRule:
    pattern: str
    name: str
    args: tuple[str, ...] | None  # None: any arguments; "*" matches any one argument
    outcome: ActivityStatus = ActivityStatus.FINAL
    duration: float | None = None
    result: Any = None
    has_result: bool = False
    times: int | None = None  # applies to the first `times` matching activities
    used: int = 0
    span: Span | None = None  # the entry in the scenario file

    def matches(self, g: GroundAction) -> bool:
        if g.name != self.name or (self.times is not None and self.used >= self.times):
            return False
        if self.args is None:
            return True
        if len(self.args) != len(g.args):
            return False
        return all(_arg_matches(p, a) for p, a in zip(self.args, g.args, strict=True))


@dataclass
class ExogRule:
    at: float
    action: str
    args: list[Any]
    span: Span | None = None


@dataclass
class FunctionRule:
    name: str
    args: dict[str, Any] | None
    values: list[Any]
    used: int = 0
    span: Span | None = None

    def matches(self, name: str, args: Mapping[str, Value]) -> bool:
        if name != self.name:
            return False
        return self.args is None or all(k in args and _value_matches(v, args[k]) for k, v in self.args.items())


@dataclass
class Scenario:
    default_duration: float | None = None
    actions: list[ActionRule] = field(default_factory=list)
    exogs: list[ExogRule] = field(default_factory=list)
    functions: list[FunctionRule] = field(default_factory=list)

    @classmethod
    def load(cls, path: Path) -> Scenario:
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except OSError as e:
            raise ScenarioError(f"cannot read scenario '{path}': {e.strerror}") from None
        except UnicodeDecodeError:
            raise ScenarioError(f"scenario '{path}' is not UTF-8 text") from None
        except tomllib.TOMLDecodeError as e:
            raise ScenarioError(f"scenario '{path}' is not valid TOML: {e}") from None
        except ValueError:  # tomllib refuses a whole number of thousands of digits
            raise ScenarioError(f"scenario '{path}' has a whole number beyond the range of numbers") from None
        return cls.from_data(data, str(path), _entry_spans(Source.from_file(path)))

    @classmethod
    def from_data(
        cls, data: Mapping[str, Any], where: str = "scenario", spans: Mapping[tuple[str, int], Span] | None = None
    ) -> Scenario:
        """A scenario from TOML data; `spans` locates its `[[section]]` entries, by section name
        and index, in the file (for problems found when the program attaches)."""
        spans = spans or {}
        unknown = set(data) - set(_KEYS)
        if unknown:
            raise ScenarioError(
                f"{where}: unknown section(s) {', '.join(sorted(unknown))} (known: {', '.join(sorted(_KEYS))})"
            )
        scenario = cls()
        defaults = data.get("defaults", {})
        if not isinstance(defaults, dict):
            raise ScenarioError(f"{where}: [defaults] must be a table")
        _check_keys(defaults, "defaults", f"{where}: [defaults]")
        if "duration" in defaults:
            scenario.default_duration = _seconds(defaults["duration"], f"{where}: [defaults] duration")
        for i, entry in enumerate(_entries(data, "action", where)):
            at = f"{where}: [[action]] #{i + 1}"
            _check_keys(entry, "action", at)
            pattern = entry.get("match")
            if not isinstance(pattern, str):
                raise ScenarioError(f'{at}: `match = "name(args)"` is required')
            name, args = _parse_pattern(pattern, at)
            word = entry.get("outcome", "final")
            if not isinstance(word, str) or word not in _OUTCOMES:
                raise ScenarioError(f"{at}: outcome must be final, fail or cancel, not {show_plain(word)}")
            rule = ActionRule(pattern, name, args, _OUTCOMES[word], span=spans.get(("action", i)))
            if "duration" in entry:
                rule.duration = _seconds(entry["duration"], f"{at} duration")
            if "result" in entry:
                rule.result, rule.has_result = entry["result"], True
            if "times" in entry:
                times = entry["times"]
                if isinstance(times, bool) or not isinstance(times, int) or times < 1:
                    raise ScenarioError(f"{at}: times must be a whole number >= 1, not {show_plain(times)}")
                rule.times = times
            scenario.actions.append(rule)
        for i, entry in enumerate(_entries(data, "exog", where)):
            at = f"{where}: [[exog]] #{i + 1}"
            _check_keys(entry, "exog", at)
            if "action" not in entry or "at" not in entry:
                raise ScenarioError(f'{at}: `at = <seconds>` and `action = "name"` are required')
            if not isinstance(entry["action"], str) or not _is_name(entry["action"]):
                shown = show_plain(entry["action"])
                raise ScenarioError(f"{at}: action must be the name of an exogenous action, not {shown}")
            args = entry.get("args", [])
            if not isinstance(args, list):
                raise ScenarioError(f"{at}: args must be a list of values, not {show_plain(args)}")
            scenario.exogs.append(
                ExogRule(_seconds(entry["at"], f"{at} at"), entry["action"], list(args), spans.get(("exog", i)))
            )
        for i, entry in enumerate(_entries(data, "exog_function", where)):
            at = f"{where}: [[exog_function]] #{i + 1}"
            _check_keys(entry, "exog_function", at)
            if "name" not in entry or not ("value" in entry or "values" in entry):
                raise ScenarioError(f"{at}: `name` and `value` (or `values = [...]`) are required")
            if "value" in entry and "values" in entry:
                raise ScenarioError(f"{at}: give either `value` or `values`, not both")
            if "values" in entry and (not isinstance(entry["values"], list) or not entry["values"]):
                raise ScenarioError(f"{at}: values must be a non-empty list of answers")
            fargs = entry.get("args")
            if fargs is not None and not isinstance(fargs, dict):
                raise ScenarioError(f'{at}: args must be a table such as `{{ room = "kitchen" }}`')
            values = list(entry["values"]) if "values" in entry else [entry["value"]]
            scenario.functions.append(
                FunctionRule(str(entry["name"]), fargs, values, span=spans.get(("exog_function", i)))
            )
        return scenario


_HEADER = re.compile(r"^[ \t]*\[\[[ \t]*([A-Za-z_]+)[ \t]*\]\]", re.MULTILINE)


def _entry_spans(source: Source) -> dict[tuple[str, int], Span]:
    """Where each `[[section]]` entry of a scenario file begins: its header line."""
    spans: dict[tuple[str, int], Span] = {}
    counts: dict[str, int] = {}
    for m in _HEADER.finditer(source.text):
        section = m.group(1)
        index = counts.get(section, 0)
        counts[section] = index + 1
        spans[(section, index)] = Span(source, m.start(0) + len(m.group(0)) - len(m.group(0).lstrip()), m.end(0))
    return spans


def _entries(data: Mapping[str, Any], section: str, where: str) -> list[dict[str, Any]]:
    entries = data.get(section, [])
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        raise ScenarioError(f"{where}: `{section}` must be an array of tables, written [[{section}]]")
    return entries


def _check_keys(entry: Mapping[str, Any], section: str, at: str) -> None:
    unknown = set(entry) - _KEYS[section]
    if unknown:
        known = ", ".join(sorted(_KEYS[section]))
        raise ScenarioError(f"{at}: unknown key(s) {', '.join(sorted(unknown))} (known: {known})")


class DummyPlatform(Platform):
    name = "dummy"
    virtual_time = True
    selected_by = BUILTIN["dummy"].selected_by
    Options = DummyOptions

    def __init__(
        self,
        scenario: Scenario | None = None,
        seed: int = 1,
        random_mode: bool = False,
        scenario_path: Path | None = None,
    ) -> None:
        super().__init__()
        self.seed = seed
        self.scenario_path = scenario_path
        # A copy: the rules count their uses, and a scenario may serve several runs.
        self.scenario = copy.deepcopy(scenario) if scenario is not None else Scenario()
        self.random_mode = random_mode
        self.rng = random.Random(seed)
        self.clock = 0.0
        self._agenda: list[tuple[float, int, Event]] = []
        self._seq = 0
        self._pending: dict[int, tuple[float, int]] = {}  # activity id -> scheduled (time, seq)
        self._cancelled: set[int] = set()
        self._results: dict[int, tuple[bool, Any]] = {}
        self.interface: ProgramInterface | None = None
        self._next_random_exog = 0.0

    @classmethod
    def create(cls, config: PlatformConfig) -> DummyPlatform:
        """The platform for `gpp run`: the scenario from the `scenario` option, else from a
        `// scenario: FILE` line at the top of the program (relative to it), else none."""
        options = parse_options(DummyOptions, config.options, cls.name)
        if options.seed is not None and not options.random:
            raise PlatformError(
                "option `seed` of platform `dummy` applies only with `random` (without it nothing is random)"
            )
        path = options.scenario if options.scenario is not None else config.directive_path("scenario")
        try:
            scenario = Scenario.load(path) if path is not None else None
        except ScenarioError as e:
            raise PlatformError(str(e)) from None
        return cls(scenario, options.seed if options.seed is not None else 1, options.random, path)

    def facts(self) -> RunFacts:
        scenario = str(self.scenario_path) if self.scenario_path is not None else None
        return RunFacts(scenario=scenario, seed=self.seed if self.random_mode else None)

    # ---------------------------------------------------------------- contract

    def attach(self, interface: ProgramInterface) -> list[Problem]:
        self.interface = interface
        problems: list[Problem] = []

        def problem(message: str, span: Span | None, known: Iterable[str] = (), name: str = "") -> None:
            hint = did_you_mean(name, known) if name else None
            problems.append(Problem("scenario: " + message, span, help=hint))

        for rule in self.scenario.actions:
            binding = interface.actions.get(rule.name)
            if binding is None:
                problem(
                    f"no action `{rule.name}` in the program (pattern `{rule.pattern}`)",
                    rule.span,
                    interface.actions,
                    rule.name,
                )
            elif rule.has_result:
                if binding.sensing is None:
                    problem(f"`{rule.pattern}` gives a result, but `{rule.name}` senses nothing", rule.span)
                    continue
                try:
                    to_value(rule.result, binding.sensing)
                except ConversionError as e:
                    problem(f"the result for `{rule.pattern}`: {e}", rule.span)
        for exog in self.scenario.exogs:
            signature = interface.exog_actions.get(exog.action)
            if signature is None:
                problem(
                    f"no exogenous action `{exog.action}` in the program",
                    exog.span,
                    interface.exog_actions,
                    exog.action,
                )
                continue
            if len(exog.args) != len(signature.params):
                n, given = len(signature.params), len(exog.args)
                problem(f"`{exog.action}` takes {n} argument(s), the scenario gives {given}", exog.span)
                continue
            try:
                args = tuple(to_value(a, t) for a, t in zip(exog.args, signature.param_types, strict=True))
            except ConversionError as e:
                problem(f"`{exog.action}` at {exog.at:g} s: {e}", exog.span)
                continue
            self._schedule(exog.at, ExogOccurrence(exog.action, args))
        for f in self.scenario.functions:
            function = interface.exog_functions.get(f.name)
            if function is None:
                problem(f"no exogenous function `{f.name}` in the program", f.span, interface.exog_functions, f.name)
                continue
            params = function.param_names
            for key in f.args or {}:
                if key not in params:
                    shown = ", ".join(params) if params else "none"
                    problem(f"`{f.name}` has no parameter `{key}` (parameters: {shown})", f.span, params, key)
            for value in f.values:
                try:
                    to_value(value, function.return_type)
                except ConversionError as e:
                    problem(f"an answer of `{f.name}`: {e}", f.span)
        if self.random_mode and interface.exog_actions:
            self._next_random_exog = self.rng.uniform(0.0, 2.0)
        return problems

    def start(self, activity: Activity) -> None:
        g = activity.action
        rule = next((r for r in self.scenario.actions if r.matches(g)), None)
        if rule is None:
            wrong = next((r for r in self.scenario.actions if r.name == g.name and r.args is not None), None)
            if wrong is not None and wrong.args is not None and len(wrong.args) != len(g.args):
                raise PlatformError(
                    f"scenario pattern `{wrong.pattern}` has {len(wrong.args)} argument(s), "
                    f"`{g.name}` takes {len(g.args)}"
                )
        if rule is not None:
            rule.used += 1
        duration = self._duration(activity, rule)
        outcome = rule.outcome if rule is not None else ActivityStatus.FINAL
        if rule is not None and rule.has_result:
            sensed = self.interface.sensing(g.name) if self.interface else None
            try:
                self._results[activity.id] = (True, to_value(rule.result, sensed))
            except ConversionError as e:
                raise PlatformError(f"scenario result for `{rule.pattern}`: {e}") from None
        update = ActivityUpdate(activity.id, outcome, reason="scenario" if rule else "")
        self._pending[activity.id] = self._schedule(self.clock + duration, update)

    def preempt(self, activity: Activity) -> None:
        if activity.id not in self._pending:
            return  # already ended
        del self._pending[activity.id]
        self._cancelled.add(activity.id)
        self.queue.put(ActivityUpdate(activity.id, ActivityStatus.CANCELLED, reason="preempted"), self.clock)

    def exog_function(
        self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
    ) -> Value:
        for rule in self.scenario.functions:
            if not rule.matches(name, args):
                continue
            value = rule.values[min(rule.used, len(rule.values) - 1)]
            rule.used += 1
            try:
                return to_value(value, return_type)
            except ConversionError as e:
                raise PlatformError(f"the scenario's answer for `{name}`: {e}") from None
        if self.random_mode:
            return random_value(self.rng, return_type)
        shown = ", ".join(f"{k}={show(v)}" for k, v in args.items())
        raise PlatformError(f"the scenario gives no answer for `{name}({shown})`")

    def now(self) -> float:
        return self.clock

    def wait(self, deadline: float | None, wall_deadline: float | None = None) -> bool:
        # Virtual time: waiting takes no wall-clock time, so `wall_deadline` cannot come first.
        self._schedule_random_exog()
        while self._agenda:
            t, seq, event = self._agenda[0]
            if deadline is not None and t > deadline:
                # Something will happen, but after the deadline: time runs up to it.
                self.clock = max(self.clock, float(deadline))
                return False
            heapq.heappop(self._agenda)
            if isinstance(event, ActivityUpdate):
                if event.activity_id in self._cancelled or self._pending.get(event.activity_id) != (t, seq):
                    continue  # preempted before it ended
                del self._pending[event.activity_id]
                has_result, result = self._results.pop(event.activity_id, (False, None))
                if has_result and event.status is ActivityStatus.FINAL:
                    event = ActivityUpdate(event.activity_id, event.status, result, True, event.reason)
            self.clock = max(self.clock, t)
            self.queue.put(event, self.clock)
            return True
        if deadline is not None and deadline > self.clock:
            self.clock = float(deadline)  # the program waits for the clock: time passes
        # Nothing else can happen.
        return False

    def live(self) -> bool:
        return bool(self._agenda) or (self.random_mode and bool(self.interface and self.interface.exog_actions))

    # ---------------------------------------------------------------- serving another platform

    def rule_for(self, action: GroundAction) -> ActionRule | None:
        """The `[[action]]` rule that the next activity of `action` would follow (not used up)."""
        return next((r for r in self.scenario.actions if r.matches(action)), None)

    def next_time(self) -> float | None:
        """When the next scheduled happening is due, None when nothing is (the endings of
        activities preempted meanwhile are dropped)."""
        while self._agenda:
            t, seq, event = self._agenda[0]
            if isinstance(event, ActivityUpdate) and self._pending.get(event.activity_id) != (t, seq):
                heapq.heappop(self._agenda)
                continue
            return t
        return None

    def catch_up(self, clock: float) -> None:
        """Another platform's clock, which serves this one's scenario, has reached `clock`: the
        activities started from now on end relative to it."""
        self.clock = max(self.clock, clock)

    def forget(self, activity_id: int) -> None:
        """The activity ended otherwise: what the scenario scheduled for it does not happen."""
        self._pending.pop(activity_id, None)
        self._results.pop(activity_id, None)

    # ---------------------------------------------------------------- helpers

    def _schedule(self, t: float, event: Event) -> tuple[float, int]:
        self._seq += 1
        heapq.heappush(self._agenda, (t, self._seq, event))
        return (t, self._seq)

    def _duration(self, activity: Activity, rule: ActionRule | None) -> float:
        if rule is not None and rule.duration is not None:
            return rule.duration
        low, high = activity.duration if activity.duration is not None else (None, None)
        if self.random_mode:
            if low is not None and high is not None:
                return self.rng.uniform(low, high)
            return self.rng.uniform(0.01, 0.5)
        if self.scenario.default_duration is not None:
            return self.scenario.default_duration
        return low if low is not None and low > 0 else 1.0

    def _schedule_random_exog(self) -> None:
        """Random mode: keep one random exogenous event scheduled ahead (every 0-2 s)."""
        if not self.random_mode or self.interface is None or not self.interface.exog_actions:
            return
        if any(isinstance(e, ExogOccurrence) for _, _, e in self._agenda):
            return
        signature = self.rng.choice(sorted(self.interface.exog_actions.values(), key=lambda s: s.name))
        args = tuple(random_value(self.rng, t) for t in signature.param_types)
        at = max(self._next_random_exog, self.clock)
        self._schedule(at, ExogOccurrence(signature.name, args))
        self._next_random_exog = at + self.rng.uniform(0.0, 2.0)


def _seconds(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value <= MAX_SECONDS:
        shown = describe(value) if isinstance(value, int | float) and not isinstance(value, bool) else show_plain(value)
        raise ScenarioError(f"{what} must be a number of seconds from 0 to {bound_text(MAX_SECONDS)}, not {shown}")
    return float(value)


_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def _is_name(text: str) -> bool:
    return _NAME.fullmatch(text) is not None


def _parse_pattern(pattern: str, where: str) -> tuple[str, tuple[str, ...] | None]:
    """`name` (any arguments) or `name(arg, ...)`: each argument is `*`, a number, `true`,
    `false`, `null`, a symbol name or a double-quoted string (spaces inside strings kept)."""
    bad = ScenarioError(
        f"{where}: pattern {pattern!r} must look like `name` or `name(arg, ...)` with arguments such as "
        '`*`, `kitchen`, `3`, `"text"`'
    )
    text = pattern.strip()
    if "(" not in text:
        if not _is_name(text):
            raise bad
        return text, None
    name, _, rest = text.partition("(")
    name = name.strip()
    if not _is_name(name) or not rest.rstrip().endswith(")"):
        raise bad
    inner = rest.rstrip()[:-1]
    args: list[str] = []
    current = ""
    quoted = escaped = False
    for ch in inner:
        if quoted:
            current += ch
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                quoted = False
        elif ch == '"':
            if current.strip():
                raise bad
            current = ch
            quoted = True
        elif ch == ",":
            args.append(current.strip())
            current = ""
        elif ch in "()":
            raise bad
        else:
            current += ch
    if quoted:
        raise bad
    if inner.strip() or args:
        args.append(current.strip())
    for a in args:
        if a.startswith('"') and (len(a) < 2 or not a.endswith('"')):
            raise bad
        if not a or (not a.startswith('"') and " " in a):
            raise bad
    return name, tuple(args)


def _arg_matches(pattern: str, value: Value) -> bool:
    """Does one pattern argument match an actual argument value?"""
    if pattern == "*":
        return True
    if pattern.startswith('"'):
        return isinstance(value, str) and pattern[1:-1].replace('\\"', '"').replace("\\\\", "\\") == value
    if value is None or isinstance(value, bool):
        return pattern == show(value)
    if isinstance(value, int | float):
        try:
            return float(pattern) == value
        except ValueError:
            return False
    return pattern == show(value)


def _value_matches(wanted: Any, value: Value) -> bool:
    """Does a TOML value (an `args` entry of an exog_function rule) equal a golog++ value?"""
    if isinstance(wanted, dict) and wanted.get("null") is True:
        return value is None
    if isinstance(wanted, bool) or isinstance(value, bool):
        return isinstance(wanted, bool) and isinstance(value, bool) and wanted == value
    if isinstance(wanted, int | float):
        return isinstance(value, int | float) and wanted == value
    if isinstance(wanted, str):
        return value == wanted if isinstance(value, str) else isinstance(value, Sym) and value.name == wanted
    if isinstance(wanted, list):
        return (
            isinstance(value, tuple)
            and len(value) == len(wanted)
            and all(_value_matches(w, v) for w, v in zip(wanted, value, strict=True))
        )
    if isinstance(wanted, dict) and isinstance(value, CompoundValue):
        names = {n for n, _ in value.fields}
        return set(wanted) <= names and all(_value_matches(w, value.get(k)) for k, w in wanted.items())
    return False


def random_value(rng: random.Random, t: Type) -> Value:
    """A random value of type `t`, like the original dummy backend's."""
    if isinstance(t, DomainType):
        return rng.choice(t.values) if t.values else None
    if t is BOOL:
        return rng.random() < 0.5
    if t is NUMBER:
        return rng.randint(-1000, 1000)
    if t is STRING:
        return "".join(rng.choice("abcdefghijklmnopqrstuvwxyz ") for _ in range(rng.randint(0, 16)))
    if t is SYMBOL:
        return Sym("s" + str(rng.randint(0, 99)))
    if isinstance(t, ListType):
        return tuple(random_value(rng, t.element) for _ in range(rng.randint(0, 4)))
    if isinstance(t, CompoundType):
        return CompoundValue(t.name, tuple((n, random_value(rng, ft)) for n, ft in t.fields.items()))
    return None
