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

import contextlib
import dataclasses
import logging
import os
import re
import threading
import time
from collections.abc import Callable, Mapping, Sequence
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
    RunFacts,
    parse_options,
)
from gpp.platform.options import BUILTIN, Ros2Options
from gpp.platform.ros2 import placeholders
from gpp.platform.ros2.binding import (
    Binding,
    BindingError,
    FunctionEntry,
    NameEntry,
    find_binding,
)
from gpp.platform.ros2.live import LiveTopics
from gpp.platform.ros2.names import DEFAULT_NODE_NAME, NameError_, is_namespace, normalize, parse_mapped
from gpp.platform.values import ConversionError, to_value
from gpp.runtime.events import TraceEvent
from gpp.runtime.state import ActivityStatus
from gpp.runtime.values import Value

if TYPE_CHECKING:
    from gpp.platform.ros2 import checks
    from gpp.platform.ros2.bridge import Bridge, Job, Outcome
    from gpp.platform.ros2.checks import Target
    from gpp.platform.ros2.interfaces import Interface

log = logging.getLogger("gpp.platform.ros2")

# s between two looks at the graph for the types of names mapped without one, not yet seen
TARGET_LOOK = 0.1
# s between two looks at the graph for another node with the agent node's name
NODE_NAME_LOOK = 1.0
# The parameters every node has (rclpy declares them): not the entry procedure's.
NODE_PARAMETERS = frozenset({"use_sim_time", "start_type_description_service"})
CLOCK_TOPIC = "/clock"
# s (wall clock) at most between two looks at the simulator's clock while a program waits for
# a time: the clock's callback wakes the wait, this only bounds a wake-up that came just before.
SIM_SLICE = 0.02
_UNFIT = "the mapping does not fit the type the ROS graph shows (see the error); nothing was sent"

INSTALL_HINT = "platform `ros2` needs the ROS 2 Python packages, which are not installed: pip install 'gpp[ros]'"


@dataclass
class Topic:
    """One subscribed topic and the exogenous actions its messages become."""

    name: str
    interface: Interface | None
    # Each exogenous action its messages become: the message field that fills each parameter
    # (path, parameter, type), and the parameters filled from the topic's name (placeholders).
    routes: list[tuple[ExogActionBinding, list[tuple[str, str, Type]], Mapping[str, Value]]] = field(
        default_factory=list
    )
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
    params: tuple[str, ...]  # those a service request is asked with (not the name's placeholders)
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
        node_name: str = DEFAULT_NODE_NAME,
        log_level: str = "warn",
        namespace: str | None = None,
        arguments: Sequence[str] = (),
        use_sim_time: bool = False,
        publish_trace: bool = True,
    ) -> None:
        super().__init__()
        self.binding = binding or Binding()
        self.context = context if context is not None else Ros2Platform.shared_context
        self.domain_id = domain_id
        self.node_name = node_name
        self.log_level = log_level
        self.namespace = namespace
        # The ROS arguments (after `--ros-args`), parsed by rcl when the node starts.
        self.arguments = tuple(arguments)
        self.duplicate_warned = False
        self._resolved: dict[str, str] = {}  # a name as written -> as the node resolves it
        self.t0 = time.monotonic()
        self.bridge: Bridge | None = None
        self.interface: ProgramInterface | None = None
        # (action, the values of its mapped name's placeholders: () without) -> how it is served
        self.targets: dict[tuple[str, tuple[str | None, ...]], Target] = {}
        self.topics: dict[str, Topic] = {}
        # exogenous function (with its placeholders' values: `battery(robot1)`) -> its source
        self.sources: dict[str, Source] = {}
        # exogenous function whose source has placeholders -> their parameters
        self._source_params: dict[str, tuple[str, ...]] = {}
        self._jobs: dict[int, Job] = {}
        self._lock = threading.Lock()
        self._results: dict[int, Value] = {}
        self._last: dict[str, Any] = {}  # mapped ROS name -> its last result (plain)
        self.exog_received = 0
        self._next_target_look = 0.0
        self.use_sim_time = use_sim_time
        self.live_topics = LiveTopics() if publish_trace else None
        # Sim time (the option or the node's use_sim_time parameter): the platform's clock goes
        # on from the last time it told before (`_sim_base`: the header's) by the /clock time
        # since its first message, never going back; `_deadline` is what a waiting program
        # waits for (the clock's callback wakes it).
        self.sim_time = False
        self._told = 0.0
        self._clock_lock = threading.Lock()
        self._sim_origin: float | None = None
        self._sim_base = 0.0
        self._sim_now = 0.0
        self._deadline: float | None = None

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
        platform = cls(
            binding,
            None,
            options.domain_id,
            options.node_name or DEFAULT_NODE_NAME,
            options.log_level or "warn",
            namespace_of(options),
            check_arguments(options, config.arguments),
            options.use_sim_time,
            options.publish_trace,
        )
        platform.start_node()
        return platform

    def start_node(self) -> None:
        """Start the agent's node (and its spin thread), unless it runs: rcl parses the ROS
        arguments then. PlatformError, one line, for arguments rcl refuses."""
        from gpp.platform.ros2.bridge import ArgumentError, Bridge

        if self.bridge is not None:
            return
        try:
            self.bridge = Bridge(
                self.context,
                self.domain_id,
                self.node_name,
                self.log_level,
                self.namespace,
                self.arguments,
                self.use_sim_time,
            )
        except ArgumentError as e:
            raise PlatformError(
                f"--ros-args: {e}" if self.arguments else f"cannot start the agent's node: {e}"
            ) from None
        if not self.bridge.sim_time:
            self.t0 = self.bridge.t0

    def facts(self) -> RunFacts:
        """The agent's node, fully qualified (`/robot1/courier`), for the trace's header."""
        return RunFacts(node=self.bridge.fully_qualified_name if self.bridge is not None else None)

    def entry_arguments(self) -> Mapping[str, tuple[object, str]]:
        """The node's ROS parameters (`-p n:=3`, `--params-file`) but those every node has:
        the values of the entry procedure's parameters."""
        if self.bridge is None:
            return {}
        return {
            name: (value, f"the ROS parameter `{name}`")
            for name, value in self.bridge.parameters().items()
            if name not in NODE_PARAMETERS
        }

    # ---------------------------------------------------------------- attach

    def attach(self, interface: ProgramInterface) -> list[Problem]:
        from gpp.platform.ros2 import checks

        problems: list[Problem] = []
        try:
            self.start_node()
        except PlatformError as e:
            return [Problem(str(e))]
        assert self.bridge is not None
        bridge = self.bridge
        # The names as the node resolves them: under its namespace, with its remapping rules.
        interface = resolved_interface(interface, bridge.resolve)
        try:
            self.binding = self.binding.resolved(bridge.resolve)
        except NameError_ as e:
            return [Problem(f"binding file: {e}")]
        self.interface = interface
        self._check_node_name()
        if self.live_topics is not None:
            try:
                self.live_topics.attach(bridge)
            except Exception as e:
                return [Problem(f"cannot publish the run's records: {type(e).__name__}: {e}")]
        # One wait for discovery, at most discovery_timeout in all: first for the names mapped
        # without a type (their mappings are checked against the types the graph shows), then
        # for the subscribers of the topics the program publishes on (_wait_for_subscribers).
        # With sim time, the first /clock message comes first.
        deadline = time.monotonic() + self.binding.discovery_timeout
        if bridge.sim_time:
            problem = self._follow_clock(deadline)
            if problem is not None:
                return [problem]
        resolve = self._resolve_mapped
        graph = checks.Graph(bridge, checks.untyped_names(interface, self.binding, resolve), deadline)
        # A mapped name with placeholders is served as one mapping per name it stands for.
        unserved = placeholders.mapping_problems(interface)
        problems.extend(p for name in sorted(unserved) for p in unserved[name])
        for name, action in sorted(interface.actions.items()):
            if name in unserved:
                continue
            for instance, binding in placeholders.bound_instances(action, resolve):
                target, found = checks.action_target(binding, self.binding, graph)
                problems.extend(p for p in found if p not in problems)
                if target is not None:
                    self.targets[name, instance.key] = target
        for name, exog_action in sorted(interface.exog_actions.items()):
            if name in unserved:
                continue
            for instance, exog in placeholders.bound_instances(exog_action, resolve):
                problems.extend(self._route(exog, instance.values, graph))
        self._sources(interface, graph, problems)
        problems.extend(checks.unused_entries(self.binding, interface, resolve))
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

    def _route(self, exog: ExogActionBinding, from_name: Mapping[str, Value], graph: checks.Graph) -> list[Problem]:
        """Route the messages of an exogenous action's topic to it (`from_name`: the values of
        the parameters its topic's name fills); the problems found."""
        from gpp.platform.ros2 import checks

        name = exog.name
        problems: list[Problem] = []
        found_topic, found = checks.exog_route(exog, self.binding, graph, from_name)
        problems.extend(found)
        if found_topic is not None:
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
                return problems
            topic.interface = topic.interface or iface
            topic.routes.append((exog, routes, from_name))
        return problems

    def _sources(self, interface: ProgramInterface, graph: checks.Graph, problems: list[Problem]) -> None:
        """The sources of the exogenous functions the binding file declares, one per name a
        source with placeholders stands for; the problems found go to `problems`."""
        from gpp.platform.ros2 import checks

        for fname, template in sorted(self.binding.functions.items()):
            signature = interface.exog_functions.get(fname)
            if signature is None:
                problems.append(
                    Problem(
                        f"binding file: [exog_function.{fname}]: the program declares no exogenous function `{fname}`",
                        template.span,
                        "not in the program",
                        help=did_you_mean(fname, interface.exog_functions),
                    )
                )
                continue
            what = f"binding file: [exog_function.{fname}] {template.kind}"
            written = template.source.written or template.source.name
            unserved = placeholders.problems(what, written, signature.params, template.span)
            if unserved:
                problems.extend(unserved)
                continue
            in_name = placeholders.placeholders(written)
            if in_name:
                self._source_params[fname] = in_name
            for instance in placeholders.instances(written, signature.params):
                source_name = template.source
                if in_name:  # resolved once its placeholders are filled
                    source_name = parse_mapped(self._resolve_mapped(instance.text))
                entry = dataclasses.replace(template, source=source_name)
                known = None
                if entry.kind == "feedback":
                    known, found = self._feedback_type(entry)
                    problems.extend(found)
                    if found:
                        continue
                source, found = checks.function_source(entry, signature, graph, known, frozenset(in_name))
                problems.extend(p for p in found if p not in problems)
                if source is not None:
                    asked = tuple(p for p in signature.param_names if p not in in_name or p in entry.request.values())
                    key = _source_key(fname, in_name, instance.values)
                    self.sources[key] = Source(entry, signature.return_type, asked, source, signature.span)

    def _check_node_name(self) -> None:
        """Warn (once) when another node on the domain has the agent's name and namespace: ROS
        tools cannot tell them apart, and their parameters and logs mix. Looked at when the
        program attaches and then every second, for an agent or node that comes later."""
        assert self.bridge is not None
        bridge = self.bridge
        next_look = [0.0]

        def look(now: float) -> None:
            if self.duplicate_warned or now < next_look[0]:
                return
            next_look[0] = now + NODE_NAME_LOOK
            if bridge.same_name_nodes() > 0:
                self.duplicate_warned = True
                name = bridge.node.get_fully_qualified_name()
                self._warn(
                    f'another node on this ROS domain is called "{name}", as the agent\'s node is: '
                    "ROS tools cannot tell the two apart",
                    None,
                    help="give each agent a name of its own: `-r __node:=NAME` or `-r __ns:=/NAMESPACE` after "
                    "--ros-args, or -o node_name=NAME",
                )

        with contextlib.suppress(Exception):
            bridge.call(look, 0.0, timeout=5.0)
        bridge.watchers.append(look)

    def _follow_clock(self, deadline: float) -> Problem | None:
        """Subscribe to /clock and wait (until `deadline`) for its first message: from then on
        the platform's clock is the simulator's."""
        from rosgraph_msgs.msg import Clock

        from gpp.platform.ros2.binding import Qos

        assert self.bridge is not None
        bridge = self.bridge
        with self._clock_lock:
            self._sim_base = self._sim_now = self._told
        self.sim_time = True
        qos = Qos(reliability="best_effort", durability="volatile")
        bridge.call(bridge.subscribe, CLOCK_TOPIC, Clock, self._clock, qos, 1, timeout=5.0)
        while time.monotonic() < deadline:
            with self._clock_lock:
                if self._sim_origin is not None:
                    return None
            time.sleep(0.01)
        return Problem(
            f"use_sim_time is set, but no message on {CLOCK_TOPIC} arrived within "
            f"{self.binding.discovery_timeout:g} s (discovery_timeout): start the simulator (what publishes "
            f"{CLOCK_TOPIC}) first"
        )

    def _clock(self, msg: Any) -> None:
        """On the spin thread: the simulator's clock moved; a program waiting for a time it has
        reached is woken."""
        seconds = msg.clock.sec + msg.clock.nanosec * 1e-9
        with self._clock_lock:
            if self._sim_origin is None:
                self._sim_origin = seconds
            self._sim_now = max(self._sim_now, self._sim_base + seconds - self._sim_origin)
            due = self._deadline is not None and self._sim_now >= self._deadline
        if due:
            self.queue.wake()

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
            for exog, *_ in topic.routes:
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

    def _watch_sources(self, tick: float) -> None:
        """On the spin thread, every tick: held-back wake-ups, values that just became too old,
        and polled services wake a waiting program. In the platform's time, as the values'
        arrival (the simulator's with sim time; the bridge's `tick` is wall-clock time)."""
        now = self.now()
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
                for exog, *_ in topic.routes:
                    self.queue.put(MessageDropped(topic.name, exog.name, str(e), exog.span), self.now())
                continue
            problems = [
                p for exog, routes, _ in topic.routes for p in route_problems(exog, topic.name, interface, routes)
            ]
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
        for exog, routes, from_name in topic.routes:
            values = dict(from_name)
            for path, param, t in routes:
                try:
                    values[param] = to_value(pick(plain, path), t)
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
                self.queue.put(ExogOccurrence(exog.name, tuple(values[p] for p in exog.param_names)), now)

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
        for exog, *_ in topic.routes:
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
        action = self.interface.actions.get(activity.action.name) if self.interface is not None else None
        key = placeholders.instance_key(action.mapped_name, action.params, activity.action.args) if action else ()
        target = self.targets.get((activity.action.name, key))
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
        in_name = self._source_params.get(name)
        source = self.sources.get(name if in_name is None else _source_key(name, in_name, args))
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
                    mapped = self._resolve(parse_mapped(value).written)
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

    def _resolve_mapped(self, text: str) -> str:
        """A mapped name (with its type) whose placeholders were filled, as the node resolves it."""
        return resolved_mapped(text, self._resolve)

    def _resolve(self, name: str) -> str:
        """`name` as the agent's node resolves it (gpp.platform.ros2.names.resolve), once."""
        found = self._resolved.get(name)
        if found is None:
            found = self.bridge.resolve(name) if self.bridge is not None else normalize(name)
            self._resolved[name] = found
        return found

    def now(self) -> float:
        if self.sim_time:
            with self._clock_lock:
                return self._sim_now
        now = time.monotonic() - self.t0
        self._told = max(self._told, now)
        return now

    def wait(self, deadline: float | None, wall_deadline: float | None = None) -> bool:
        with self._clock_lock:
            self._deadline = deadline
        try:
            while True:
                if len(self.queue):
                    return True
                if deadline is None and not self.live():
                    return False  # nothing can arrive, and the program waits for no moment
                slice_ = 0.1
                if deadline is not None:
                    left = deadline - self.now()
                    if left <= 0:
                        return False
                    # In sim time the clock's callback wakes the wait; left is simulated time.
                    slice_ = SIM_SLICE if self.sim_time else min(slice_, left)
                if wall_deadline is not None:
                    # The run's wall-clock bound (`--timeout`), in wall-clock time also in sim time.
                    slice_ = min(slice_, wall_deadline - time.monotonic())
                    if slice_ <= 0:
                        return False
                if self.queue.wait(slice_):
                    return True
        finally:
            with self._clock_lock:
                self._deadline = None

    def live(self) -> bool:
        with self._lock:
            running = bool(self._jobs)
        return running or bool(self.topics) or any(s.watched for s in self.sources.values())

    def trace_listener(self) -> Callable[[TraceEvent], None] | None:
        return self.live_topics

    def close(self) -> None:
        if self.bridge is not None:
            if self.live_topics is not None:
                try:
                    self.live_topics.flush()
                except Exception as e:
                    log.warning("ros2: the last records were not published: %s: %s", type(e).__name__, e)
            self.bridge.close()


def resolved_mapped(text: str, resolve: Callable[[str], str]) -> str:
    """Mapped name `text` (`"name"` or `"name : pkg/kind/Type"`) with its name resolved by
    `resolve` (its type kept); one that is not a ROS name (or has placeholders, resolved per
    name it stands for) stays as it is."""
    try:
        mapped = parse_mapped(text)
        name = resolve(mapped.written)
    except NameError_:
        return text
    return f"{name} : {mapped.type}" if mapped.type is not None else name


def resolved_interface(interface: ProgramInterface, resolve: Callable[[str], str]) -> ProgramInterface:
    """The program's interface with each mapped name resolved by `resolve` (its type kept); a
    mapped name that is not a ROS name stays as it is (its mapping's check reports it)."""

    def resolved(text: str) -> str:
        return resolved_mapped(text, resolve)

    return dataclasses.replace(
        interface,
        actions={k: dataclasses.replace(a, mapped_name=resolved(a.mapped_name)) for k, a in interface.actions.items()},
        exog_actions={
            k: dataclasses.replace(e, mapped_name=resolved(e.mapped_name)) for k, e in interface.exog_actions.items()
        },
    )


def namespace_of(options: Ros2Options) -> str | None:
    """The agent node's namespace: the option's, else $ROS_NAMESPACE (made absolute), else
    None (the root, unless `-r __ns:=` says otherwise)."""
    if options.namespace is not None:
        return options.namespace
    found = os.environ.get("ROS_NAMESPACE", "").strip()
    if not found:
        return None
    namespace = found if found.startswith("/") else "/" + found
    if not is_namespace(namespace):
        raise PlatformError(
            f'$ROS_NAMESPACE must be a ROS namespace (such as "/robot1": letters, digits and `_` between `/`), '
            f'not "{found}"'
        )
    return namespace


# What the ROS arguments set of the platform's options: a remapping rule's left side (or the
# flag) -> the option.
_SET_BY_ARGUMENTS = {"__node": "node_name", "__name": "node_name", "__ns": "namespace", "--log-level": "log_level"}


def check_arguments(options: Ros2Options, arguments: Sequence[str]) -> tuple[str, ...]:
    """The ROS arguments, refused (PlatformError) when they set what an option given with -o
    sets too (the node's name or namespace, the log level)."""
    for i, flag in enumerate(arguments):
        value = arguments[i + 1] if i + 1 < len(arguments) else ""
        if flag in ("-r", "--remap"):
            key = value.partition(":=")[0].rpartition(":")[2]
        elif flag == "--log-level":
            key = flag
        else:
            continue
        option = _SET_BY_ARGUMENTS.get(key)
        if option is not None and getattr(options, option) is not None:
            raise PlatformError(
                f"the {option.replace('_', ' ')} is given twice: by -o {option}={getattr(options, option)} "
                f"and by `{flag} {value}` after --ros-args"
            )
    return tuple(arguments)


def _source_key(function: str, in_name: tuple[str, ...], values: Mapping[str, Value]) -> str:
    """The key of an exogenous function's source: its name, with the values of the parameters
    its source's name has as placeholders (`battery(robot1)`)."""
    if not in_name:
        return function
    return f"{function}({','.join(str(placeholders.name_text(values.get(p))) for p in in_name)})"


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
    if options.namespace is not None and not is_namespace(options.namespace):
        raise PlatformError(
            f'option `namespace` of platform `ros2` must be an absolute ROS namespace (such as "/robot1": letters, '
            f'digits and `_` between `/`), not "{options.namespace}"'
        )
    if options.node_name is not None and not _NODE_NAME.match(options.node_name):
        raise PlatformError(
            f"option `node_name` of platform `ros2` must be a ROS node name (letters, digits and `_`, not starting "
            f'with a digit; no `/` or namespace), not "{options.node_name}"'
        )
    if options.log_level is not None and options.log_level.lower() not in LOG_LEVELS:
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
