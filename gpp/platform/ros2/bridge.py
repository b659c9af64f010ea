"""The agent's ROS 2 node and the one thread that spins it.

Every rclpy call runs on that thread: creating clients, publishers and subscriptions, sending
goals, cancelling them, calling services. Other threads (the interpreter) only hand it work
with `post` (thread-safe: rclpy's executor task queue) or `call` (the same, then a bounded
wait for the answer). This avoids the thread-safety hazards of rclpy 9 (entities created from
another thread while the executor spins, futures registered from two threads) and means the
interpreter never waits inside rclpy.

What runs on the spin thread never waits either: each goal or service call is a `Job`, a small
state machine driven by the callbacks of rclpy futures and by a 20 ms tick that watches its
deadlines (server appearing, goal acknowledged, server still alive, result in time). Whatever
happens, a job ends exactly once, through its `done` callback.
"""

from __future__ import annotations

import atexit
import concurrent.futures
import contextlib
import logging
import math
import re
import threading
import time
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import rclpy
from action_msgs.msg import GoalStatus
from action_msgs.srv import CancelGoal
from rclpy.action.client import ActionClient
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions

from gpp.platform.ros2.binding import Qos
from gpp.platform.ros2.interfaces import FieldError, Interface, InterfaceError, load_interface, make_message, to_plain
from gpp.platform.ros2.interfaces import fill_fields as _fill
from gpp.platform.ros2.names import DEFAULT_NODE_NAME, resolve
from gpp.platform.values import show_plain
from gpp.runtime.state import ActivityStatus

log = logging.getLogger("gpp.platform.ros2")

TICK = 0.02  # s between two checks of the jobs' deadlines
LIVENESS = 0.25  # s between two checks that the server of a running goal is still there

_STATUS = {
    GoalStatus.STATUS_UNKNOWN: "unknown",
    GoalStatus.STATUS_ACCEPTED: "accepted",
    GoalStatus.STATUS_EXECUTING: "executing",
    GoalStatus.STATUS_CANCELING: "canceling",
    GoalStatus.STATUS_SUCCEEDED: "succeeded",
    GoalStatus.STATUS_CANCELED: "canceled",
    GoalStatus.STATUS_ABORTED: "aborted",
}


@dataclass(frozen=True)
class Outcome:
    status: ActivityStatus
    result: Any = None  # plain data (the result or response), when there is one
    has_result: bool = False
    reason: str = ""


@dataclass(eq=False)
class Job:
    """One goal, service call or published message, from start to its one outcome."""

    name: str
    interface: Interface | None  # None: looked up in the graph first
    entries: Sequence[tuple[str, Any]]  # field path -> value
    done: Callable[[Outcome], None]
    stamps: tuple[str, ...] = ()
    server_timeout: float = 5.0
    ack_timeout: float = 5.0
    result_timeout: float | None = None
    # s a running goal may go without a feedback message (None: no limit)
    feedback_timeout: float | None = None
    # send the goal request once more when it is not answered within ack_timeout
    resend: bool = False
    qos: Qos | None = None
    # The interface came from the graph: when no server of it answers, the graph is looked at
    # again (its type may have changed).
    from_graph: bool = False
    # Called with a type the graph shows for the name: why the mapping does not fit it (then
    # nothing is sent and the job fails), or None.
    fits: Callable[[Interface], str | None] | None = None
    # what the program is told about the job while it goes on (a message that reached nobody;
    # with True: its server refused to cancel it); None: nobody listens
    notice: Callable[[str, bool], None] | None = None
    # Called (on the spin thread) with each feedback message of the goal, as plain data.
    feedback: Callable[[Any], None] | None = None
    # state, touched only on the spin thread
    phase: str = "new"  # new, resolving, waiting (for the server), matching (subscribers), sent, running, ended
    deadline: float = math.inf
    result_deadline: float = math.inf
    feedback_deadline: float = math.inf
    next_check: float = 0.0
    attempts: int = 0
    cancel_requested: bool = False
    message: Any = None
    client: Any = None
    pending: Any = None  # the future of the goal request or the service call
    goal: Any = None  # the accepted goal handle


class Bridge:
    """A node (`gpp_agent`) on its own or a given context, spun by one daemon thread."""

    def __init__(
        self,
        context: Context | None = None,
        domain_id: int | None = None,
        node_name: str = DEFAULT_NODE_NAME,
        log_level: str = "warn",
        namespace: str | None = None,
        arguments: Sequence[str] = (),
        use_sim_time: bool = False,
    ) -> None:
        """`arguments`: the ROS arguments (those after `--ros-args`: remapping rules,
        parameters, parameter files, log levels), parsed by rcl; on a context of its own they
        are the context's (global) arguments, on a given one the node's. ArgumentError when
        rcl refuses them."""
        self.own_context = context is None
        if context is None:
            context = Context()
            _init(context, ["--ros-args", "--log-level", log_level, *arguments], domain_id)
        self.context = context
        overrides = [Parameter("use_sim_time", Parameter.Type.BOOL, True)] if use_sim_time else []
        try:
            self.node = rclpy.create_node(
                node_name,
                namespace=namespace,
                context=context,
                cli_args=["--ros-args", *arguments] if arguments and not self.own_context else None,
                start_parameter_services=False,
                parameter_overrides=overrides,
                automatically_declare_parameters_from_overrides=True,
            )
        except Exception as e:
            if self.own_context:
                context.try_shutdown()
            raise ArgumentError(_rcl_message(e)) from None
        # Read before the node spins (rclpy is then touched only on the spin thread).
        self.fully_qualified_name = self.node.get_fully_qualified_name()
        # The option or the ROS parameter (`--ros-args -p use_sim_time:=true`): rclpy's clock
        # of the node follows /clock (the stamps it fills in); the platform's clock does too.
        self.sim_time = bool(self.node.get_parameter("use_sim_time").value)
        # The names the node resolved (with its remapping rules) -> as they were expanded
        # before: an entity is made with the expanded name, so that rcl remaps it once.
        self._expanded: dict[str, str] = {}
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.jobs: list[Job] = []
        self.watchers: list[Callable[[float], None]] = []
        self._action_clients: dict[tuple[str, str], Any] = {}
        self._service_clients: dict[tuple[str, str], Any] = {}
        self._publishers: dict[tuple[str, str], Any] = {}
        self._stopping = False
        self._closed = False
        self.t0 = time.monotonic()
        # Created before the thread spins: the only entity not made on the spin thread.
        self._timer = self.node.create_timer(TICK, self._guarded(self._tick))
        self.thread = threading.Thread(target=self._spin, name="gpp-ros2-spin", daemon=True)
        _live.add(self)
        self.thread.start()

    # ---------------------------------------------------------------- the thread

    def _spin(self) -> None:
        while not self._stopping:
            try:
                self.executor.spin_once(timeout_sec=0.1)
            except Exception as e:  # a callback's exception surfaces here: log it, keep spinning
                if self._stopping or not self.context.ok():
                    break
                log.error("ros2: %s: %s", type(e).__name__, e)

    def post(self, fn: Callable[..., None], *args: Any) -> None:
        """Run `fn(*args)` on the spin thread, soon; its exceptions are logged."""
        if self._closed:
            return
        self.executor.create_task(self._guarded(fn), *args)

    def call(self, fn: Callable[..., Any], *args: Any, timeout: float = 5.0) -> Any:
        """Run `fn(*args)` on the spin thread and return its value (or raise its exception);
        TimeoutError when it has not run within `timeout` seconds."""
        if threading.current_thread() is self.thread:
            return fn(*args)
        answer: concurrent.futures.Future[Any] = concurrent.futures.Future()

        def run() -> None:
            try:
                answer.set_result(fn(*args))
            except BaseException as e:
                answer.set_exception(e)

        self.executor.create_task(run)
        return answer.result(timeout)

    def _guarded(self, fn: Callable[..., None]) -> Callable[..., None]:
        def run(*args: Any) -> None:
            try:
                fn(*args)
            except Exception as e:
                log.error("ros2: internal error in %s: %s: %s", getattr(fn, "__name__", fn), type(e).__name__, e)

        return run

    def now(self) -> float:
        return time.monotonic() - self.t0

    def close(self, grace: float = 1.0) -> None:
        """Cancel what still runs and let the subscribers acknowledge what was published
        (waiting at most `grace` s in all for the servers and subscribers), stop and join the
        spin thread, destroy the node, shut the context down (if it is ours). A message
        published just before the end is still on its way: destroying its publisher at once
        would lose it."""
        if self._closed:
            return
        if self.thread.is_alive():
            with contextlib.suppress(Exception):
                self.call(self._cancel_all, timeout=grace)
            deadline = time.monotonic() + grace
            while time.monotonic() < deadline and any(j.phase == "running" for j in list(self.jobs)):
                time.sleep(0.01)
            for publisher in list(self._publishers.values()):
                left = deadline - time.monotonic()
                if left <= 0:
                    break
                with contextlib.suppress(Exception):  # best effort publishers are acknowledged at once
                    publisher.wait_for_all_acked(Duration(nanoseconds=int(left * 1e9)))
        self._closed = True
        self._stopping = True
        self.executor.wake()
        self.thread.join(5.0)
        for job in list(self.jobs):
            self._end(job, Outcome(ActivityStatus.CANCELLED, reason="the ros2 platform closed"))
        try:
            self.executor.shutdown(timeout_sec=0)
            self.node.destroy_node()
        except Exception as e:
            log.debug("ros2: closing the node: %s", e)
        if self.own_context:
            self.context.try_shutdown()
        _live.discard(self)

    def _cancel_all(self) -> None:
        for job in list(self.jobs):
            self.cancel(job)

    # ---------------------------------------------------------------- names

    @property
    def namespace(self) -> str:
        return str(self.node.get_namespace())

    @property
    def node_name(self) -> str:
        return str(self.node.get_name())

    def resolve(self, name: str) -> str:
        """The absolute name `name` (as mapped: absolute, relative or `~`) stands for on the
        agent's node: expanded with its namespace and name, then remapped by its rules
        (gpp.platform.ros2.names.resolve; NameError_ when it is not a ROS name). From any
        thread: the remapping runs on the spin thread."""
        return resolve(name, self.namespace, self.node_name, self._remap)

    def _remap(self, expanded: str) -> str:
        if threading.current_thread() is not self.thread and self.thread.is_alive():
            return str(self.call(self._remap, expanded))
        remapped = str(self.node.resolve_topic_name(expanded))
        self._expanded.setdefault(remapped, expanded)
        return remapped

    def unremapped(self, name: str) -> str:
        """The name to make an entity of resolved name `name` with: rcl applies the remapping
        rules to it again, so an entity is made with the name before them (a rule `a:=b` and a
        rule `b:=c` take `a` to `b`, as ROS does, not on to `c`)."""
        return self._expanded.get(name, name)

    def same_name_nodes(self) -> int:
        """How many other nodes in the graph (on this domain) have the agent node's name and
        namespace (on the spin thread)."""
        me = (self.node_name, self.namespace)
        return sum(1 for found in self.node.get_node_names_and_namespaces() if tuple(found) == me) - 1

    def parameters(self) -> dict[str, Any]:
        """The node's ROS parameters given to it (`-p`, `--params-file`) by name, as plain
        values (lists for arrays)."""
        found: dict[str, Any] = {}
        for name, parameter in self.node.get_parameters_by_prefix("").items():
            value = parameter.value
            found[name] = value if isinstance(value, str | bool | int | float) or value is None else list(value)
        return found

    # ---------------------------------------------------------------- the graph

    def graph_type(self, name: str) -> tuple[str, str] | None:
        """(kind, type name) of `name` in the ROS graph now: an action server, a service server
        or a topic (with a publisher or a subscriber: an action that publishes on it finds its
        type from the subscribers waiting for its messages); None when it is not there (yet).
        Clients do not count: the agent's own client of a type no server has any more would
        hide the type a new server has."""
        found = self.served_type(name)
        if found is not None:
            return found
        for n, types in self.node.get_topic_names_and_types():
            if n == name and types and self.node.count_publishers(name) + self.node.count_subscribers(name) > 0:
                return "msg", types[0]
        return None

    def served_type(self, name: str) -> tuple[str, str] | None:
        """("action" or "srv", type name) of a server of `name` in the graph now, if one is."""
        goal = f"{name}/_action/send_goal"
        service = None
        for node, namespace in self.node.get_node_names_and_namespaces():
            try:
                served = self.node.get_service_names_and_types_by_node(node, namespace)
            except Exception:  # the node left meanwhile
                continue
            for n, types in served:
                if n == goal and types and types[0].endswith("_SendGoal"):
                    return "action", types[0].removesuffix("_SendGoal")
                if n == name and types and service is None:
                    service = types[0]
        return ("srv", service) if service is not None else None

    # ---------------------------------------------------------------- jobs

    def submit(self, job: Job) -> None:
        """Start a job (from any thread)."""
        self.post(self._begin, job)

    def cancel(self, job: Job) -> None:
        """Ask a job to stop (on the spin thread): a running goal is cancelled on its server;
        anything not on a server yet, and service calls (which cannot be cancelled), end
        cancelled here and a late answer is dropped."""
        if job.phase == "ended":
            return
        job.cancel_requested = True
        if job.phase == "sent" and job.interface is not None and job.interface.kind == "action":
            return  # cancelled as soon as it is accepted
        if job.phase == "running" and job.goal is not None:
            future = job.goal.cancel_goal_async()
            future.add_done_callback(self._guarded(lambda f: self._cancel_answered(job, f)))
            return
        self._end(job, Outcome(ActivityStatus.CANCELLED, reason="preempted"))

    def _cancel_answered(self, job: Job, future: Any) -> None:
        """A refused cancel leaves the goal running on its server: the job goes on tracking it
        (its end is reported as it comes), and the program is told."""
        response = future.result()
        if job.phase == "ended" or response is None or not _refused(response, job.goal):
            return  # cancelling, or the goal had ended already (its result tells how)
        message = f'the action server "{job.name}" refused to cancel the goal: it still runs'
        log.warning("ros2: %s", message)
        if job.notice is not None:
            job.notice(message, True)

    def _begin(self, job: Job) -> None:
        self.jobs.append(job)
        if job.cancel_requested:
            self._end(job, Outcome(ActivityStatus.CANCELLED, reason="preempted"))
            return
        if job.interface is None:
            job.phase = "resolving"
            job.deadline = self.now() + job.server_timeout
            self._resolve(job)
        else:
            self._prepare(job)

    def _resolve(self, job: Job) -> None:
        found = self.graph_type(job.name)
        if found is None:
            if self.now() >= job.deadline:
                self._fail(
                    job,
                    f'"{job.name}" is not available: no action server, service or topic of that name '
                    f"appeared within {job.server_timeout:g} s",
                )
            return
        try:
            interface = load_interface(found[1])
        except InterfaceError as e:
            self._fail(job, str(e))
            return
        unfit = job.fits(interface) if job.fits is not None else None
        if unfit is not None:
            self._fail(job, f'"{job.name}" ({interface.name}): {unfit}')
            return
        job.interface = interface
        job.from_graph = True
        self._prepare(job)

    def _prepare(self, job: Job) -> None:
        assert job.interface is not None
        try:
            job.message = make_message(job.interface.request, job.entries)
            if job.stamps:
                stamp = self.node.get_clock().now().to_msg()
                _fill(job.message, [(path, {"sec": stamp.sec, "nanosec": stamp.nanosec}) for path in job.stamps])
        except FieldError as e:
            self._fail(job, str(e))
            return
        kind = job.interface.kind
        key = (job.name, job.interface.name)
        if kind == "msg":
            job.client = self.publisher(job.name, job.interface, job.qos)
            job.phase = "matching"
            job.deadline = self.now() + job.server_timeout
            self._publish_when_matched(job)
            return
        clients = self._action_clients if kind == "action" else self._service_clients
        client = clients.get(key)
        if client is None:
            # A participant has one type per name: a client of the type the name had before
            # (its server went, one of another type came) goes first.
            if not self._drop_clients(job.name):
                self._fail(job, f'"{job.name}" is now {job.interface.name}, and a goal of its old type still runs')
                return
            try:
                if kind == "action":
                    client = ActionClient(self.node, job.interface.cls, self.unremapped(job.name))
                else:
                    client = self.node.create_client(job.interface.cls, self.unremapped(job.name))
            except Exception as e:
                self._fail(job, f'cannot make a client of "{job.name}" ({job.interface.name}): {e}')
                return
            clients[key] = client
        job.client = client
        job.phase = "waiting"
        job.deadline = self.now() + job.server_timeout
        self._wait_for_server(job)

    def _drop_clients(self, name: str) -> bool:
        """Destroy the clients of `name` (of another type than a job about to be prepared needs);
        False when one of them is still used by a job."""
        for clients in (self._action_clients, self._service_clients):
            for key, client in list(clients.items()):
                if key[0] != name:
                    continue
                if any(j.client is client for j in self.jobs if j.phase != "ended"):
                    return False
                del clients[key]
                if clients is self._action_clients:
                    client.destroy()
                else:
                    self.node.destroy_client(client)
        return True

    def publisher(self, name: str, interface: Interface, qos: Qos | None) -> Any:
        """The agent's publisher of `name` (made once, on the spin thread)."""
        key = (name, interface.name)
        publisher = self._publishers.get(key)
        if publisher is None:
            publisher = self.node.create_publisher(interface.cls, self.unremapped(name), qos_profile(qos, 10))
            self._publishers[key] = publisher
        return publisher

    def unmatched(self, publisher: Any) -> bool:
        """Does the graph show a subscriber of the publisher's topic that it has not matched yet
        (a message published now would not reach it)?"""
        return bool(publisher.get_subscription_count() < self.node.count_subscribers(publisher.topic_name))

    def _publish_when_matched(self, job: Job) -> None:
        """Publish once every subscriber the graph shows is matched (or server_timeout passed);
        a message that reaches no subscriber is said (kept for a late joiner when the
        publisher is transient local)."""
        if self.unmatched(job.client) and self.now() < job.deadline:
            return
        matched = job.client.get_subscription_count()
        job.client.publish(job.message)
        if matched == 0 and job.notice is not None:
            kept = job.qos is not None and job.qos.durability == "transient_local"
            fate = "it is kept for a subscriber that joins later" if kept else "nobody received it"
            job.notice(f'published on "{job.name}" with no subscriber matched: {fate}', False)
        self._end(job, Outcome(ActivityStatus.FINAL))

    def _server_ready(self, job: Job) -> bool:
        assert job.interface is not None
        if job.interface.kind == "action":
            return bool(job.client.server_is_ready())
        return bool(job.client.service_is_ready())

    def _wait_for_server(self, job: Job) -> None:
        if self._server_ready(job):
            self._send(job)
        elif job.from_graph and self._type_changed(job):
            job.interface = None
            job.client = None
            job.phase = "resolving"
            self._resolve(job)
        elif self.now() >= job.deadline:
            what = "action server" if job.interface is not None and job.interface.kind == "action" else "service"
            self._fail(job, f'no {what} "{job.name}" became available within {job.server_timeout:g} s')

    def _type_changed(self, job: Job) -> bool:
        """Does the graph show another type for a job's name than the one it was resolved to
        (no server of that type answers)?"""
        assert job.interface is not None
        found = self.graph_type(job.name)
        return found is not None and found[1] != job.interface.name

    def _send(self, job: Job) -> None:
        assert job.interface is not None
        job.attempts += 1
        now = self.now()
        if job.interface.kind == "action":
            job.phase = "sent"
            job.deadline = now + job.ack_timeout
            on_feedback = job.feedback

            def feedback(message: Any) -> None:
                self._feedback(job)
                if on_feedback is not None:
                    on_feedback(_plain_or_error(message.feedback))

            future = job.client.send_goal_async(job.message, feedback_callback=self._guarded(feedback))
            job.pending = future
            future.add_done_callback(self._guarded(lambda f: self._goal_answered(job, f)))
        else:
            job.phase = "running"
            job.result_deadline = now + job.result_timeout if job.result_timeout else math.inf
            job.next_check = now + LIVENESS
            future = job.client.call_async(job.message)
            job.pending = future
            future.add_done_callback(self._guarded(lambda f: self._response(job, f)))

    def _goal_answered(self, job: Job, future: Any) -> None:
        handle = future.result()
        if future is not job.pending or job.phase == "ended":
            # An answer to a request given up on (or to a job already ended): nobody waits for
            # this goal, so it must not run.
            if handle is not None and handle.accepted:
                handle.cancel_goal_async()
            return
        if handle is None or not handle.accepted:
            self._fail(job, f'the action server "{job.name}" rejected the goal')
            return
        job.goal = handle
        job.phase = "running"
        now = self.now()
        job.result_deadline = now + job.result_timeout if job.result_timeout else math.inf
        job.next_check = now + LIVENESS
        job.feedback_deadline = now + job.feedback_timeout if job.feedback_timeout else math.inf
        result = handle.get_result_async()
        result.add_done_callback(self._guarded(lambda f: self._result(job, f)))
        if job.cancel_requested:
            self.cancel(job)

    def _feedback(self, job: Job) -> None:
        if job.phase == "running" and job.feedback_timeout:
            job.feedback_deadline = self.now() + job.feedback_timeout

    def _result(self, job: Job, future: Any) -> None:
        if job.phase == "ended":
            return
        response = future.result()
        if response is None:
            self._fail(job, f'"{job.name}": the goal ended without a result')
            return
        status = response.status
        plain = _plain_or_error(response.result)
        if status == GoalStatus.STATUS_SUCCEEDED:
            if isinstance(plain, _Malformed):
                self._fail(job, f'"{job.name}": bad result: {plain.reason}')
            else:
                self._end(job, Outcome(ActivityStatus.FINAL, plain, True))
        elif status == GoalStatus.STATUS_CANCELED:
            if job.cancel_requested:
                self._end(job, Outcome(ActivityStatus.CANCELLED, reason="preempted"))
            else:
                self._fail(job, f'the action server "{job.name}" cancelled the goal')
        elif status == GoalStatus.STATUS_ABORTED:
            # The result of an aborted goal (Nav2's error_code and error_msg) goes with the
            # failure: the program reads it as the name's last result.
            reason = f'the action server "{job.name}" aborted the goal'
            if isinstance(plain, _Malformed):
                self._fail(job, reason)
            else:
                reason += f" (its result: {show_plain(plain)})"
                self._end(job, Outcome(ActivityStatus.FAILED, plain, True, reason))
        else:
            self._fail(job, f'"{job.name}": the goal ended with unexpected status {_STATUS.get(status, status)}')

    def _response(self, job: Job, future: Any) -> None:
        if future is not job.pending or job.phase == "ended":
            return  # a late answer to a call that was cancelled or timed out
        try:
            response = future.result()
        except Exception as e:
            self._fail(job, f'the call of "{job.name}" failed: {e}')
            return
        plain = _plain_or_error(response)
        if isinstance(plain, _Malformed):
            self._fail(job, f'"{job.name}": bad response: {plain.reason}')
        else:
            self._end(job, Outcome(ActivityStatus.FINAL, plain, True))

    def _tick(self) -> None:
        now = self.now()
        for job in list(self.jobs):
            if job.phase == "resolving":
                self._resolve(job)
            elif job.phase == "waiting":
                self._wait_for_server(job)
            elif job.phase == "matching":
                self._publish_when_matched(job)
            elif job.phase == "sent" and now >= job.deadline:
                if job.resend and job.attempts < 2:
                    log.warning(
                        "ros2: no answer to the goal for %s within %g s: sending it again", job.name, job.ack_timeout
                    )
                    self._send(job)
                else:
                    # A late acceptance of the request is cancelled (_goal_answered).
                    self._fail(
                        job,
                        f'the action server "{job.name}" did not answer the goal request within '
                        f"{job.ack_timeout:g} s" + (" (sent twice)" if job.attempts > 1 else ""),
                    )
            elif job.phase == "running":
                if now >= job.result_deadline:
                    if job.goal is not None:
                        job.goal.cancel_goal_async()
                    self._fail(job, f'"{job.name}" gave no result within {job.result_timeout:g} s')
                elif now >= job.feedback_deadline:
                    job.goal.cancel_goal_async()
                    self._fail(
                        job,
                        f'the action server "{job.name}" sent no feedback for {job.feedback_timeout:g} s '
                        "(feedback_timeout): it is taken for dead or stuck, and the goal was cancelled",
                    )
                elif now >= job.next_check:
                    job.next_check = now + LIVENESS
                    if not self._server_ready(job):
                        what = "action server" if job.goal is not None else "service"
                        self._fail(job, f'the {what} "{job.name}" went away before it answered')
        for watch in list(self.watchers):
            watch(now)

    def _fail(self, job: Job, reason: str) -> None:
        self._end(job, Outcome(ActivityStatus.FAILED, reason=reason))

    def _end(self, job: Job, outcome: Outcome) -> None:
        if job.phase == "ended":
            return
        job.phase = "ended"
        job.pending = None
        if job in self.jobs:
            self.jobs.remove(job)
        try:
            job.done(outcome)
        except Exception as e:
            log.error("ros2: reporting the end of %s: %s: %s", job.name, type(e).__name__, e)

    # ---------------------------------------------------------------- topics

    def topic_type(self, name: str) -> str | None:
        """The type of topic `name` when a publisher of it is in the graph now (a cheap look-up,
        made every tick for a topic whose type is not known yet)."""
        if self.node.count_publishers(name) == 0:
            return None
        for n, types in self.node.get_topic_names_and_types():
            if n == name and types:
                return str(types[0])
        return None

    def subscribe(
        self,
        name: str,
        cls: Any,
        callback: Callable[[Any], None],
        qos: Qos | None,
        depth: int,
        keep_all: bool = False,
        lost: Callable[[int], None] | None = None,
    ) -> Any:
        """A subscription (call on the spin thread), with reliability and durability chosen from
        the publishers already there unless `qos` says them; `lost(n)` is called when the
        middleware reports that n messages of a publisher never arrived."""
        from rclpy.event_handler import SubscriptionEventCallbacks

        profile = qos_profile(qos, depth, self.node.get_publishers_info_by_topic(name), keep_all)
        events = None
        if lost is not None:
            report = lost
            events = SubscriptionEventCallbacks(
                message_lost=self._guarded(lambda info: report(int(info.total_count_change)))
            )
        return self.node.create_subscription(
            cls, self.unremapped(name), self._guarded(callback), profile, event_callbacks=events
        )

    def best_effort_publishers(self, name: str) -> int:
        """How many publishers of topic `name` are best effort (they can lose messages)."""
        publishers = self.node.get_publishers_info_by_topic(name)
        return sum(p.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT for p in publishers)


class ArgumentError(ValueError):
    """ROS arguments that rcl refuses (a remapping rule, a parameter, a file, a log level, a
    node name or namespace), in one line."""


def _init(context: Context, args: list[str], domain_id: int | None) -> None:
    """rclpy.init on `context` with `args`; ArgumentError with rcl's reason when it refuses
    them (rcl's own log line about it is kept quiet: the error says it)."""
    from rclpy.impl.logging_severity import LoggingSeverity
    from rclpy.logging import set_logger_level

    set_logger_level("rcl", LoggingSeverity.FATAL)
    try:
        rclpy.init(args=args, context=context, domain_id=domain_id, signal_handler_options=SignalHandlerOptions.NO)
    except Exception as e:
        raise ArgumentError(_rcl_message(e)) from None
    finally:
        set_logger_level("rcl", LoggingSeverity.UNSET)


def _rcl_message(e: Exception) -> str:
    """What rcl (or rclpy) says is wrong, without where in rcl's sources it noticed."""
    text = str(e)
    if type(e).__name__ == "UnknownROSArgsError":
        return "unknown ROS arguments: " + text.strip("[]").replace("'", "")
    text = text.removeprefix("failed to initialize rcl: ")
    text = re.split(r"\. Error: |, at /", text)[0]
    return text[:1].lower() + text[1:]


def qos_profile(qos: Qos | None, depth: int, publishers: Sequence[Any] = (), keep_all: bool = False) -> QoSProfile:
    """The QoS of a subscription or publisher: what the binding says; otherwise best effort
    when a publisher is best effort (a reliable subscription would receive nothing from it),
    transient local when every publisher is (to get the message it keeps), else reliable and
    volatile; `depth` messages are kept, or all until they are taken (`keep_all`: a reliable
    publisher then waits rather than a message being dropped)."""
    qos = qos or Qos()
    reliability = qos.reliability
    if reliability is None:
        best_effort = any(p.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT for p in publishers)
        reliability = "best_effort" if best_effort else "reliable"
    durability = qos.durability
    if durability is None:
        latched = bool(publishers) and all(
            p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in publishers
        )
        durability = "transient_local" if latched else "volatile"
    all_ = qos.history == "keep_all" or (qos.history is None and keep_all)
    history = HistoryPolicy.KEEP_ALL if all_ else HistoryPolicy.KEEP_LAST
    return QoSProfile(
        history=history,
        depth=qos.depth or depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if reliability == "best_effort" else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if durability == "transient_local" else DurabilityPolicy.VOLATILE,
    )


def _refused(response: Any, goal: Any) -> bool:
    """Did the server refuse to cancel `goal`? rclcpp says so with ERROR_REJECTED; rclpy answers
    ERROR_NONE and leaves the goal out of `goals_canceling`."""
    code = response.return_code
    if code == CancelGoal.Response.ERROR_REJECTED:
        return True
    ours = bytes(goal.goal_id.uuid)
    return bool(code == CancelGoal.Response.ERROR_NONE) and all(
        bytes(g.goal_id.uuid) != ours for g in response.goals_canceling
    )


@dataclass(frozen=True)
class _Malformed:
    reason: str


def _plain_or_error(msg: Any) -> Any:
    try:
        return to_plain(msg)
    except Exception as e:
        return _Malformed(f"it cannot be read ({e})")


def is_malformed(plain: Any) -> bool:
    """Is this what `_plain_or_error` gives for a message it could not convert?"""
    return isinstance(plain, _Malformed)


# Bridges still open when the interpreter exits are closed first: a thread still spinning at
# exit makes the process abort ("terminate called without an active exception").
_live: weakref.WeakSet[Bridge] = weakref.WeakSet()


@atexit.register
def _close_all() -> None:
    for bridge in list(_live):
        with contextlib.suppress(Exception):
            bridge.close(grace=0.5)
