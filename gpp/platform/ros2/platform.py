"""The ros2 platform: a golog++ agent on ROS 2 action servers, services and topics, with no
glue code. The program's `mapping:` sections are the binding (see the README, "Running on a
robot"):

* an action mapped to `"/name"` or `"/name : pkg/action/Type"` sends a goal to that action
  server (`pkg/srv/Type`: calls the service; `pkg/msg/Type`: publishes one message); the
  mapping's keys are goal (request, message) fields, `a__b__c` reaches nested fields, a
  compound value fills a nested message, a list fills an array;
* the result (response) is the sensing value: a one-field result is unwrapped, a larger one
  fills a compound type with the same field names (or the binding file picks a field);
* an exogenous action mapped to `"/topic : pkg/msg/Type" { field = param }` happens for each
  message on the topic;
* exogenous functions are answered from the latest message on a topic, the latest feedback of
  a goal or by a service call, as the binding file declares; a new message (feedback) wakes a
  waiting program, and a value older than its `max_age` is no answer (the program waits).

What the mapping cannot say (timeouts, QoS, time stamps, result fields, the sources of
exogenous functions) is in the binding file (gpp.platform.ros2.binding). Every mapping whose
type is known is checked when the program attaches, before anything is sent.

rclpy is imported only when the platform is created, so that gpp works (and says how to
install the ROS packages) where they are missing.
"""

from __future__ import annotations

import logging
import re
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

from gpp.base.source import Span
from gpp.base.suggest import did_you_mean
from gpp.model.types import CompoundType, Type, base
from gpp.platform.base import (
    Activity,
    ActivityUpdate,
    ExogActionBinding,
    ExogFunctionChanged,
    ExogOccurrence,
    MessageDropped,
    NoAnswer,
    Platform,
    PlatformConfig,
    PlatformError,
    PlatformFault,
    PlatformNotice,
    PlatformWarning,
    Problem,
    ProgramInterface,
    parse_options,
)
from gpp.platform.options import BUILTIN, Ros2Options
from gpp.platform.ros2.binding import (
    Binding,
    BindingError,
    FunctionEntry,
    NameEntry,
    find_binding,
)
from gpp.platform.ros2.names import NameError_, parse_mapped
from gpp.platform.values import ConversionError, to_value
from gpp.runtime.state import ActivityStatus
from gpp.runtime.values import Value

if TYPE_CHECKING:
    from gpp.platform.ros2.bridge import Bridge, Job, Outcome
    from gpp.platform.ros2.checks import Target
    from gpp.platform.ros2.interfaces import Interface

log = logging.getLogger("gpp.platform.ros2")

# s between two looks at the graph for the types of names mapped without one, not yet seen
TARGET_LOOK = 0.1
_UNFIT = "the mapping does not fit the type the ROS graph shows (see the error); nothing was sent"

INSTALL_HINT = "platform `ros2` needs the ROS 2 Python packages, which are not installed: pip install 'gpp[ros]'"


@dataclass
class Topic:
    """One subscribed topic and the exogenous actions its messages become."""

    name: str
    interface: Interface | None
    routes: list[tuple[ExogActionBinding, list[tuple[str, str, Type]]]] = field(default_factory=list)
    qos_entry: NameEntry | None = None
    subscription: Any = None
    warned: bool = False
    unusable: bool = False  # its type, found in the graph, cannot be imported


@dataclass
class Source:
    """Where an exogenous function's answers come from, and (topic, feedback) its latest value.
    The value fields are written on the spin thread and read by the interpreter under `lock`."""

    entry: FunctionEntry
    signature_type: Type
    params: tuple[str, ...]
    interface: Interface | None = None
    span: Span | None = None  # the function's declaration
    latest: Any = None
    has_latest: bool = False
    received: float = 0.0  # platform time of the latest value
    subscription: Any = None
    lock: threading.Lock = field(default_factory=threading.Lock)
    # Wake-ups of a waiting program (spin thread only): the next allowed one, one held back,
    # a stale value already reported, the next poll of a service.
    next_wake: float = 0.0
    wake_held: bool = False
    stale_reported: bool = False
    next_poll: float = 0.0

    @property
    def name(self) -> str:
        return self.entry.function

    @property
    def watched(self) -> bool:
        """Can its answer change without being asked (a message, feedback, a poll)?"""
        return self.entry.kind != "service" or self.entry.poll is not None


class Ros2Platform(Platform):
    name = "ros2"
    virtual_time = False
    selected_by = BUILTIN["ros2"].selected_by
    Options = Ros2Options
    # For tests: the rclpy Context that a new platform joins (None: its own).
    shared_context: ClassVar[Any] = None

    def __init__(
        self,
        binding: Binding | None = None,
        context: Any = None,
        domain_id: int | None = None,
        node_name: str = "gpp_agent",
        log_level: str = "warn",
    ) -> None:
        super().__init__()
        self.binding = binding or Binding()
        self.context = context if context is not None else Ros2Platform.shared_context
        self.domain_id = domain_id
        self.node_name = node_name
        self.log_level = log_level
        self.t0 = time.monotonic()
        self.bridge: Bridge | None = None
        self.interface: ProgramInterface | None = None
        self.targets: dict[str, Target] = {}
        self.topics: dict[str, Topic] = {}
        self.sources: dict[str, Source] = {}
        self._jobs: dict[int, Job] = {}
        self._lock = threading.Lock()
        self._results: dict[int, Value] = {}
        self._last: dict[str, Any] = {}  # mapped ROS name -> its last result (plain)
        self.exog_received = 0
        self._next_target_look = 0.0

    @classmethod
    def create(cls, config: PlatformConfig) -> Ros2Platform:
        options = parse_options(Ros2Options, config.options, cls.name)
        check_options(options)
        try:
            import rclpy  # noqa: F401
        except ImportError:
            raise PlatformError(INSTALL_HINT) from None
        path = find_binding(config.program, options.binding, config.directive_path("ros2"))
        try:
            binding = Binding.load(path) if path is not None else Binding()
        except BindingError as e:
            raise PlatformError(str(e)) from None
        if options.server_timeout is not None:
            binding.server_timeout = options.server_timeout
        if options.discovery_timeout is not None:
            if options.discovery_timeout <= 0:
                raise PlatformError(
                    f"option `discovery_timeout` of platform `ros2` must be a number of seconds > 0, "
                    f"not {options.discovery_timeout:g}"
                )
            binding.discovery_timeout = options.discovery_timeout
        return cls(binding, None, options.domain_id, options.node_name, options.log_level)

    # ---------------------------------------------------------------- attach

    def attach(self, interface: ProgramInterface) -> list[Problem]:
        from gpp.platform.ros2 import checks
        from gpp.platform.ros2.bridge import Bridge

        self.interface = interface
        problems: list[Problem] = []
        try:
            self.bridge = Bridge(self.context, self.domain_id, self.node_name, self.log_level)
        except Exception as e:
            return [Problem(f"cannot start the agent's ROS 2 node: {type(e).__name__}: {e}")]
        bridge = self.bridge
        self.t0 = bridge.t0
        # One wait for discovery, at most discovery_timeout in all: first for the names mapped
        # without a type (their mappings are checked against the types the graph shows), then
        # for the subscribers of the topics the program publishes on (_wait_for_subscribers).
        deadline = time.monotonic() + self.binding.discovery_timeout
        graph = checks.Graph(bridge, checks.untyped_names(interface, self.binding), deadline)
        for name, binding in sorted(interface.actions.items()):
            target, found = checks.action_target(binding, self.binding, graph)
            problems.extend(found)
            if target is not None:
                self.targets[name] = target
        for name, exog in sorted(interface.exog_actions.items()):
            found_topic, found = checks.exog_route(exog, self.binding, graph)
            problems.extend(found)
            if found_topic is None:
                continue
            topic_name, iface, routes = found_topic
            topic = self.topics.get(topic_name)
            if topic is None:
                topic = Topic(topic_name, iface, qos_entry=self.binding.names.get(topic_name))
                self.topics[topic_name] = topic
            elif iface is not None and topic.interface is not None and iface.name != topic.interface.name:
                problems.append(
                    Problem(
                        f'exogenous action `{name}`: topic "{topic_name}" is mapped with type `{iface.name}` here '
                        f"and `{topic.interface.name}` elsewhere",
                        exog.span,
                    )
                )
                continue
            topic.interface = topic.interface or iface
            topic.routes.append((exog, routes))
        for fname, entry in sorted(self.binding.functions.items()):
            signature = interface.exog_functions.get(fname)
            if signature is None:
                problems.append(
                    Problem(
                        f"binding file: [exog_function.{fname}]: the program declares no exogenous function `{fname}`",
                        entry.span,
                        "not in the program",
                        help=did_you_mean(fname, interface.exog_functions),
                    )
                )
                continue
            known = None
            if entry.kind == "feedback":
                known, found = self._feedback_type(entry)
                problems.extend(found)
                if found:
                    continue
            source, found = checks.function_source(entry, signature, graph, known)
            problems.extend(found)
            if source is not None:
                self.sources[fname] = Source(
                    entry, signature.return_type, signature.param_names, source, signature.span
                )
        problems.extend(checks.unused_entries(self.binding, interface))
        if problems:
            return problems
        try:
            bridge.call(self._subscribe_all, timeout=5.0)
        except Exception as e:
            return [Problem(f"cannot subscribe to the program's topics: {type(e).__name__}: {e}")]
        bridge.watchers.append(self._watch_topics)
        bridge.watchers.append(self._watch_targets)
        bridge.watchers.append(self._watch_sources)
        self._wait_for_subscribers(deadline)
        return []

    def _wait_for_subscribers(self, deadline: float) -> None:
        """Make the publishers of the actions that publish now, and wait (until `deadline`, the
        end of the attach's one wait for discovery) until each has a subscriber and has matched
        all those the graph shows: a subscriber that is up before the run gets the first
        message."""
        assert self.bridge is not None
        bridge = self.bridge
        publishers = [
            bridge.call(bridge.publisher, t.name.name, t.interface, t.entry.qos, timeout=5.0)
            for t in self.targets.values()
            if t.interface is not None and t.interface.kind == "msg"
        ]
        while publishers and time.monotonic() < deadline:
            try:
                publishers = [p for p in publishers if bridge.call(_waiting_for_subscriber, bridge, p, timeout=1.0)]
            except TimeoutError:
                break
            time.sleep(0.02)

    def _feedback_type(self, entry: FunctionEntry) -> tuple[str | None, list[Problem]]:
        """The action type whose feedback answers `entry`: that of the program's mapping to
        its action name (an error when no action is mapped to it)."""
        name = entry.source.name
        targets = [t for t in self.targets.values() if t.name.name == name]
        if not targets:
            mapped = sorted({t.name.name for t in self.targets.values()})
            return None, [
                Problem(
                    f"binding file: [exog_function.{entry.function}] feedback: "
                    f'no action of the program is mapped to "{name}"',
                    entry.span,
                    help=did_you_mean(name, mapped),
                )
            ]
        for target in targets:
            if target.interface is not None:
                return target.interface.name, []
        return entry.source.type, []

    def _subscribe_all(self) -> None:
        for topic in self.topics.values():
            if topic.interface is not None:
                self._subscribe(topic)
        for source in self.sources.values():
            if source.entry.kind == "topic" and source.interface is not None:
                self._subscribe_source(source)

    def _subscribe(self, topic: Topic) -> None:
        assert self.bridge is not None and topic.interface is not None
        qos = topic.qos_entry.qos if topic.qos_entry is not None else None
        topic.subscription = self.bridge.subscribe(
            topic.name,
            topic.interface.cls,
            lambda msg: self._message(topic, msg),
            qos,
            1000,
            keep_all=True,
            lost=lambda n: self._lost(topic, n),
        )
        if (qos is None or qos.reliability is None) and self.bridge.best_effort_publishers(topic.name):
            for exog, _ in topic.routes:
                self._warn(
                    f'topic "{topic.name}" has a best-effort publisher: a message it sends can be lost on the way '
                    f"(each loss the middleware notices is a `dropped` record for `{exog.name}`)",
                    exog.span,
                    "its messages can be lost",
                )

    def _subscribe_source(self, source: Source) -> None:
        assert self.bridge is not None and source.interface is not None

        def latest(msg: Any) -> None:
            from gpp.platform.ros2.interfaces import to_plain

            self._arrived(source, to_plain(msg))

        source.subscription = self.bridge.subscribe(
            source.entry.source.name, source.interface.cls, latest, source.entry.qos, 1
        )

    def _arrived(self, source: Source, plain: Any) -> None:
        """On the spin thread: a new value (message, feedback) of a source; a waiting program
        is woken (at most `max_rate` times a second)."""
        now = self.now()
        with source.lock:
            source.latest = plain
            source.has_latest = True
            source.received = now
        source.stale_reported = False
        self._wake(source, now)

    def _wake(self, source: Source, now: float) -> None:
        rate = source.entry.max_rate
        if rate is not None and now < source.next_wake:
            source.wake_held = True  # the tick at `next_wake` wakes it, with the value then
            return
        source.wake_held = False
        source.next_wake = now + 1.0 / rate if rate is not None else 0.0
        self.queue.put(ExogFunctionChanged(source.name), now)

    def _watch_sources(self, now: float) -> None:
        """On the spin thread, every tick: held-back wake-ups, values that just became too old,
        and polled services wake a waiting program."""
        for source in self.sources.values():
            entry = source.entry
            if source.wake_held and now >= source.next_wake:
                self._wake(source, now)
            if entry.max_age is not None and not source.stale_reported:
                with source.lock:
                    stale = source.has_latest and now - source.received > entry.max_age
                if stale:
                    source.stale_reported = True
                    self.queue.put(ExogFunctionChanged(source.name), now)
            if entry.poll is not None and now >= source.next_poll:
                source.next_poll = now + entry.poll
                self.queue.put(ExogFunctionChanged(source.name), now)

    def _watch_topics(self, now: float) -> None:
        """On the spin thread, every tick: subscribe to a topic whose type was not known at
        attach as soon as a publisher of it is in the graph. (rclpy 9 gives no graph event
        to wait on; this look-up costs a few microseconds.)"""
        from gpp.platform.ros2.checks import route_problems
        from gpp.platform.ros2.interfaces import InterfaceError, load_interface

        assert self.bridge is not None
        for topic in self.topics.values():
            if topic.subscription is not None or topic.unusable:
                continue
            found = self.bridge.topic_type(topic.name)
            if found is None:
                if not topic.warned:
                    topic.warned = True
                    log.warning(
                        'ros2: topic "%s" has no publisher yet and its type is not in the mapping; '
                        "it is subscribed when a publisher appears",
                        topic.name,
                    )
                continue
            try:
                interface = load_interface(found)
            except InterfaceError as e:
                topic.unusable = True  # never subscribed: each exogenous action says why
                for exog, _ in topic.routes:
                    self.queue.put(MessageDropped(topic.name, exog.name, str(e), exog.span), self.now())
                continue
            problems = [p for exog, routes in topic.routes for p in route_problems(exog, topic.name, interface, routes)]
            if problems:
                topic.unusable = True  # never subscribed: the run stops
                self.queue.put(PlatformFault(tuple(problems)), self.now())
                continue
            topic.interface = interface
            self._subscribe(topic)

    def _watch_targets(self, now: float) -> None:
        """On the spin thread: check the mappings of the names whose type the graph did not show
        at attach as soon as it does, whether a goal waits for them or not."""
        if now < self._next_target_look:
            return
        self._next_target_look = now + TARGET_LOOK
        waiting = [t for t in self.targets.values() if t.interface is None and not t.unfit]
        if not waiting:
            return
        assert self.bridge is not None
        for target in waiting:
            found = self.bridge.graph_type(target.name.name)
            if found is not None:
                from gpp.platform.ros2.interfaces import InterfaceError, load_interface

                try:
                    interface = load_interface(found[1])
                except InterfaceError:
                    continue  # the goal that needs it fails with the reason
                self._fits(target, interface)

    def _fits(self, target: Target, interface: Interface) -> str | None:
        """On the spin thread: why the mapping of `target` does not fit `interface`, a type the
        graph showed after attach (None: it fits). Checked once per type: a fit is kept for the
        next goals; problems stop the run (PlatformFault), and nothing is ever sent for that
        mapping."""
        from gpp.platform.ros2.checks import action_problems

        if target.unfit:
            return _UNFIT
        if target.interface is not None and target.interface.name == interface.name:
            return None
        problems = action_problems(target.binding, target.name, target.entry, interface)
        if problems:
            target.unfit = tuple(problems)
            self.queue.put(PlatformFault(target.unfit), self.now())
            return _UNFIT
        target.interface = interface
        target.from_graph = True
        return None

    def _message(self, topic: Topic, msg: Any) -> None:
        """On the spin thread: a message on a subscribed topic becomes the exogenous events
        mapped to it, queued in arrival order; one that does not fit an exogenous action is
        dropped for it, with the reason."""
        from gpp.platform.ros2.interfaces import pick, to_plain

        plain = to_plain(msg)
        now = self.now()
        for exog, routes in topic.routes:
            args: list[Value] = []
            for path, param, t in routes:
                try:
                    args.append(to_value(pick(plain, path), t))
                except KeyError:
                    reason, help_ = self._no_field(topic, path)
                    self.queue.put(
                        MessageDropped(topic.name, exog.name, reason, exog.field_spans.get(path, exog.span), help_),
                        now,
                    )
                    break
                except ConversionError as e:
                    self.queue.put(
                        MessageDropped(
                            topic.name,
                            exog.name,
                            f"field `{path}` for parameter `{param}`: {e}",
                            exog.field_spans.get(path, exog.span),
                        ),
                        now,
                    )
                    break
            else:
                self.exog_received += 1
                self.queue.put(ExogOccurrence(exog.name, tuple(args)), now)

    @staticmethod
    def _no_field(topic: Topic, path: str) -> tuple[str, str | None]:
        """Why field `path` is not in the messages of `topic`, with a did-you-mean."""
        from gpp.platform.ros2.interfaces import FieldError, field_at

        if topic.interface is not None:
            try:
                field_at(topic.interface.cls, path)
            except FieldError as e:
                return f"{topic.interface.name}: {e}", e.hint
        return f"the message has no field `{path}`", None

    def _lost(self, topic: Topic, count: int) -> None:
        """On the spin thread: the middleware reports `count` messages of the topic lost."""
        if count <= 0:
            return
        now = self.now()
        for exog, _ in topic.routes:
            self.queue.put(
                MessageDropped(
                    topic.name,
                    exog.name,
                    f"{count} message(s) lost on the way (sent faster than the agent took them from a publisher "
                    "keeping fewer, or by a best-effort publisher)",
                    exog.span,
                    'give the publisher a deeper history or `history = "keep_all"`, or make it reliable',
                    count,
                ),
                now,
            )

    def _warn(self, message: str, span: Span | None, label: str = "", help: str | None = None) -> None:
        self.queue.put(PlatformWarning(message, span, label, help), self.now())

    # ---------------------------------------------------------------- the contract

    def start(self, activity: Activity) -> None:
        from gpp.platform.ros2.bridge import Job
        from gpp.platform.ros2.interfaces import FieldError, make_message

        if self.bridge is None:
            raise PlatformError("the ros2 platform is not attached to a program")
        target = self.targets.get(activity.action.name)
        if target is None:
            raise PlatformError(f'no ROS 2 mapping for `{activity.action.name}` ("{activity.mapped_name}")')
        entries = list(activity.args.items())
        name = target.name.name
        b = self.binding
        if target.unfit:
            self._update(activity, ActivityStatus.FAILED, reason=f'"{name}": {_UNFIT}')
            return
        interface = target.interface  # None: resolved from the graph, and checked, first
        service = interface is not None and interface.kind == "srv"
        job = Job(
            name,
            interface,
            entries,
            lambda outcome: self._ended(activity, target, outcome),
            stamps=target.entry.stamp,
            server_timeout=b.server_timeout_for(name),
            ack_timeout=b.ack_timeout_for(name),
            result_timeout=b.result_timeout_for(name, service),
            feedback_timeout=b.feedback_timeout_for(name),
            resend=b.resend_for(name),
            qos=target.entry.qos,
            from_graph=target.from_graph,
            fits=lambda found: self._fits(target, found),
            notice=lambda message, cancel_refused: self._notice(activity, message, cancel_refused),
            feedback=self._feedback_to(name),
        )
        if interface is not None:
            # Checked here, before anything is sent: an argument that does not fit ends the
            # activity failed at once.
            try:
                make_message(interface.request, entries)
            except FieldError as e:
                self._update(activity, ActivityStatus.FAILED, reason=f'"{name}": {e}')
                return
        with self._lock:
            self._jobs[activity.id] = job
        self.bridge.submit(job)

    def _feedback_to(self, name: str) -> Callable[[Any], None] | None:
        """For a goal about to be sent to action `name`: what to do with its feedback, when an
        exogenous function answers with it. Its value is cleared now: the feedback of an
        earlier goal is no answer about this one."""
        sources = [s for s in self.sources.values() if s.entry.kind == "feedback" and s.entry.source.name == name]
        if not sources:
            return None
        for source in sources:
            with source.lock:
                source.has_latest = False
                source.latest = None

        def feedback(plain: Any) -> None:
            from gpp.platform.ros2.bridge import is_malformed

            if is_malformed(plain):
                return
            for source in sources:
                self._arrived(source, plain)

        return feedback

    def preempt(self, activity: Activity) -> None:
        with self._lock:
            job = self._jobs.get(activity.id)
        if job is None or self.bridge is None:
            return
        self.bridge.post(self.bridge.cancel, job)

    def _notice(self, activity: Activity, message: str, cancel_refused: bool) -> None:
        """On the spin thread: the program is told something about a running activity."""
        self.queue.put(PlatformNotice(message, activity.id, cancel_refused), self.now())

    def _ended(self, activity: Activity, target: Target, outcome: Outcome) -> None:
        """On the spin thread: a job ended; its activity's update is queued. Its result, if it
        has one (also a failed goal's: Nav2's error_code), is the name's last result."""
        with self._lock:
            self._jobs.pop(activity.id, None)
        status, reason = outcome.status, outcome.reason
        result: Value = None
        has_result = False
        if outcome.has_result:
            self._last[target.name.name] = outcome.result
            sensing = target.binding.sensing
            if sensing is not None and status is ActivityStatus.FINAL:
                try:
                    result = sensed_value(outcome.result, sensing, target.entry.result)
                    has_result = True
                    self._results[activity.id] = result
                except (KeyError, ConversionError) as e:
                    status, reason = ActivityStatus.FAILED, f'"{target.name.name}": bad result for the sensing: {e}'
        self._update(activity, status, result, has_result, reason)

    def _update(
        self,
        activity: Activity,
        status: ActivityStatus,
        result: Value = None,
        has_result: bool = False,
        reason: str = "",
    ) -> None:
        self.queue.put(ActivityUpdate(activity.id, status, result, has_result, reason), self.now())

    def exog_function(
        self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
    ) -> Value:
        source = self.sources.get(name)
        if source is not None:
            return self._ask(source, args, return_type)
        if activity is not None:
            if activity.id in self._results:
                return self._results[activity.id]
            raise PlatformError(
                f'`{name}`: "{activity.mapped_name}" gave no result to sense (the goal result or the response '
                "had no fields, or the action ended otherwise)"
            )
        # The golog++ ROS convention: a function given a mapped name answers with its last result.
        for value in args.values():
            if isinstance(value, str):
                try:
                    mapped = parse_mapped(value).name
                except NameError_:
                    continue
                if mapped in self._last:
                    try:
                        return to_value(_unwrap(self._last[mapped], return_type), return_type)
                    except ConversionError as e:
                        raise PlatformError(f'the last result of "{mapped}": {e}') from None
        raise PlatformError(
            f"the ros2 platform has no source for exogenous function `{name}`: declare one in the binding file "
            f'(`[exog_function.{name}]` with `topic = "/name : package/msg/Type"` or `service = "/name"`)'
        )

    def _ask(self, source: Source, args: Mapping[str, Value], return_type: Type) -> Value:
        from gpp.platform.ros2.bridge import Job

        entry = source.entry
        timeout = entry.timeout if entry.timeout is not None else self.binding.timeout
        what = f'`{entry.function}` ({entry.kind} "{entry.source.name}")'
        if entry.kind != "service":
            with source.lock:
                has, plain, received = source.has_latest, source.latest, source.received
            kind = "message" if entry.kind == "topic" else "feedback"
            where = f'"{entry.source.name}"'
            if not has:
                raise NoAnswer(
                    f"no {kind} on {where} yet"
                    if entry.kind == "topic"
                    else f"no feedback yet from the goal running on {where}"
                )
            age = self.now() - received
            if entry.max_age is not None and age > entry.max_age:
                raise NoAnswer(f"its last {kind} on {where} is {age:.1f} s old (max_age {entry.max_age:g} s)")
        else:
            assert self.bridge is not None
            by_param = {param: req for req, param in entry.request.items()}
            entries = [(by_param.get(p, p), args[p]) for p in source.params if p in args]
            answer: list[Outcome] = []
            done = threading.Event()

            def finished(outcome: Outcome) -> None:
                answer.append(outcome)
                done.set()

            server_timeout = entry.server_timeout if entry.server_timeout is not None else timeout
            job = Job(entry.source.name, source.interface, entries, finished, server_timeout=server_timeout)
            job.result_timeout = timeout
            self.bridge.submit(job)
            if not done.wait(timeout + server_timeout + 0.5):
                self.bridge.post(self.bridge.cancel, job)
                raise NoAnswer(f"{what}: no answer within {timeout:g} s")
            outcome = answer[0]
            if outcome.status is not ActivityStatus.FINAL:
                raise NoAnswer(f"{what}: {outcome.reason}")
            plain = outcome.result
        try:
            return sensed_value(plain, return_type, entry.field)
        except (KeyError, ConversionError) as e:
            raise PlatformError(f"{what}: {e}") from None

    def now(self) -> float:
        return time.monotonic() - self.t0

    def wait(self, deadline: float | None, wall_deadline: float | None = None) -> bool:
        while True:
            if len(self.queue):
                return True
            if deadline is None and not self.live():
                return False  # nothing can arrive, and the program waits for no moment
            slice_ = 0.1
            if deadline is not None:
                slice_ = min(slice_, deadline - self.now())
                if slice_ <= 0:
                    return False
            if wall_deadline is not None:
                slice_ = min(slice_, wall_deadline - time.monotonic())
                if slice_ <= 0:
                    return False
            if self.queue.wait(slice_):
                return True

    def live(self) -> bool:
        with self._lock:
            running = bool(self._jobs)
        return running or bool(self.topics) or any(s.watched for s in self.sources.values())

    def close(self) -> None:
        if self.bridge is not None:
            self.bridge.close()


def _waiting_for_subscriber(bridge: Bridge, publisher: Any) -> bool:
    """On the spin thread: has the publisher no subscriber, or one the graph shows unmatched?"""
    return bool(publisher.get_subscription_count() == 0 or bridge.unmatched(publisher))


# Fast DDS derives its ports from the domain id: above 232 they leave the port range.
MAX_DOMAIN_ID = 232
_NODE_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
LOG_LEVELS = ("debug", "info", "warn", "error", "fatal")


def check_options(options: Ros2Options) -> None:
    """Options rclpy or Fast DDS would refuse with an error of their own (or a traceback) are
    refused here, each with one line (a usage error)."""
    if options.domain_id is not None and not 0 <= options.domain_id <= MAX_DOMAIN_ID:
        raise PlatformError(
            f"option `domain_id` of platform `ros2` must be a whole number from 0 to {MAX_DOMAIN_ID}, "
            f"not {options.domain_id}"
        )
    if not _NODE_NAME.match(options.node_name):
        raise PlatformError(
            f"option `node_name` of platform `ros2` must be a ROS node name (letters, digits and `_`, not starting "
            f'with a digit; no `/` or namespace), not "{options.node_name}"'
        )
    if options.log_level.lower() not in LOG_LEVELS:
        hint = did_you_mean(options.log_level, LOG_LEVELS)
        raise PlatformError(
            f"option `log_level` of platform `ros2` must be one of {', '.join(LOG_LEVELS)}, "
            f'not "{options.log_level}"' + (f"; {hint}" if hint else "")
        )


def sensed_value(plain: Any, t: Type, path: str | None) -> Value:
    """The golog++ value of type `t` that a result (plain data) gives: the field at `path`
    when given; else a one-field result unwrapped (unless `t` is a compound type); else the
    whole result as a compound with the same field names."""
    from gpp.platform.ros2.interfaces import pick

    value = pick(plain, path) if path else _unwrap(plain, t)
    return to_value(value, t)


def _unwrap(plain: Any, t: Type) -> Any:
    """A one-field result as that field's value, unless it is the compound `t` itself: `t` is
    not a compound type, or the field is a message and not a field of `t` (a result `{pose:
    {x, y}}` fills a compound `{x, y}`)."""
    if not isinstance(plain, dict) or len(plain) != 1:
        return plain
    ((name, value),) = plain.items()
    compound = base(t)
    if not isinstance(compound, CompoundType) or (isinstance(value, dict) and name not in compound.fields):
        return value
    return plain
