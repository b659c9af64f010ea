"""The DAP server: the protocol loop (the main thread of `gpp dap`), one handler per request,
the breakpoint table, and the backend (gpp.dap.backend) it asks for everything it shows.

Every request is answered: a request that cannot be done (bad arguments, a program that does
not check, a question while the run is running) is an error response with one clear line, and
a fault in gpp itself is an error response too (the adapter never crashes on a request)."""

from __future__ import annotations

import json
import os
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from gpp.base.source import Span
from gpp.dap.backend import THREAD_ID, SessionBackend, Stop
from gpp.dap.breakpoints import EXCEPTION_FILTERS, Breakpoints
from gpp.dap.protocol import Connection, DapError, Message, ProtocolError

Handler = Callable[[Message], "Message | None"]


def _source(span: Span) -> Message:
    path = span.source.path
    return {"name": Path(path).name, "path": str(Path(path).resolve()) if not path.startswith("<") else path}


class DebugServer:
    """One debugging session over one connection."""

    def __init__(self, connection: Connection) -> None:
        self.connection = connection
        self.backend: SessionBackend | None = None
        self.breakpoints = Breakpoints()
        self.configured = False
        self.stop_on_entry = False
        self.started = False
        self._ended = threading.Event()
        # The client's conventions (initialize's arguments): lines and columns from 1 or from 0.
        self.lines_start_at1 = True
        self.columns_start_at1 = True
        self.handlers: dict[str, Handler] = {
            "initialize": self.initialize,
            "launch": self.launch,
            "attach": self.attach,
            "setBreakpoints": self.set_breakpoints,
            "setFunctionBreakpoints": self.set_function_breakpoints,
            "setExceptionBreakpoints": self.set_exception_breakpoints,
            "configurationDone": self.configuration_done,
            "threads": self.threads,
            "stackTrace": self.stack_trace,
            "scopes": self.scopes,
            "variables": self.variables,
            "evaluate": self.evaluate,
            "continue": self.resume_with("continue"),
            "next": self.resume_with("next"),
            "stepIn": self.resume_with("stepIn"),
            "stepOut": self.resume_with("stepOut"),
            "stepBack": self.resume_with("stepBack"),
            "reverseContinue": self.resume_with("reverseContinue"),
            "pause": self.pause,
            "disconnect": self.disconnect,
            "terminate": self.terminate,
            "source": self.source,
        }
        self.finished = False
        # A stop to tell once the current request is answered.
        self.after_response: Stop | None = None

    # ---------------------------------------------------------------- the loop

    def serve(self) -> None:
        """Answer requests until the client disconnects or the stream ends."""
        try:
            while not self.finished:
                try:
                    message = self.connection.read()
                except ProtocolError as e:
                    self.output(f"gpp dap: {e}\n", "stderr")
                    continue
                if message is None:
                    break
                self.handle(message)
        finally:
            self.end_backend()

    def handle(self, message: Message) -> None:
        if message.get("type") != "request":
            return
        command = str(message.get("command", ""))
        handler = self.handlers.get(command)
        if handler is None:
            self.connection.fail(message, f"`{command}` is not a request gpp dap answers", show_user=False)
            return
        arguments = message.get("arguments")
        if arguments is not None and not isinstance(arguments, dict):
            self.connection.fail(message, f"the arguments of `{command}` are not an object")
            return
        try:
            body = handler(arguments or {})
        except DapError as e:
            self.connection.fail(message, str(e))
            return
        except Exception as e:  # a fault in gpp: an error response, never a crash
            if os.environ.get("GPP_DEBUG") == "1":
                raise
            self.connection.fail(message, f"internal error in gpp dap ({type(e).__name__}: {e}); please report it")
            return
        self.connection.respond(message, body)
        if self.after_response is not None:
            stop, self.after_response = self.after_response, None
            self.stopped(stop)
        if command == "launch":
            if self.backend is not None and self.backend.capabilities.step_back:
                more = {"supportsStepBack": True, **self.backend.capabilities.extra}
                self.connection.event("capabilities", {"capabilities": more})
            self.connection.event("initialized")
            self.maybe_start()
        elif command == "configurationDone":
            self.maybe_start()

    # ---------------------------------------------------------------- the client of the backend

    def stopped(self, stop: Stop) -> None:
        body: Message = {"reason": stop.reason, "threadId": THREAD_ID, "allThreadsStopped": True}
        if stop.description:
            body["description"] = stop.description
        if stop.text is not None:
            body["text"] = stop.text
        if stop.breakpoint_ids:
            body["hitBreakpointIds"] = list(stop.breakpoint_ids)
        self.connection.event("stopped", body)

    def output(self, text: str, category: str = "console", span: Span | None = None) -> None:
        body: Message = {"category": category, "output": text}
        if span is not None:
            body["source"] = _source(span)
            body["line"] = self.line_out(span.line)
            body["column"] = self.column_out(span.col)
        self.connection.event("output", body)

    def ended(self, exit_code: int) -> None:
        if self._ended.is_set():
            return
        self._ended.set()
        self.connection.event("exited", {"exitCode": exit_code})
        self.connection.event("terminated")

    # ---------------------------------------------------------------- requests

    def initialize(self, args: Message) -> Message:
        self.lines_start_at1 = args.get("linesStartAt1", True) is not False
        self.columns_start_at1 = args.get("columnsStartAt1", True) is not False
        return {
            "supportsConfigurationDoneRequest": True,
            "supportsFunctionBreakpoints": True,
            "supportsConditionalBreakpoints": True,
            "supportsHitConditionalBreakpoints": True,
            "supportsLogPoints": True,
            "supportsEvaluateForHovers": True,
            "supportsTerminateRequest": True,
            # Per backend: a recorded run's says so after its launch (a `capabilities` event).
            "supportsStepBack": False,
            "supportSuspendDebuggee": False,
            "supportTerminateDebuggee": True,
            "exceptionBreakpointFilters": [
                {"filter": name, "label": label, "description": description, "default": default}
                for name, (label, description, default) in EXCEPTION_FILTERS.items()
            ],
        }

    def launch(self, args: Message) -> Message | None:
        if self.backend is not None:
            raise DapError("this session has launched already: start a new session for another run")
        from gpp.dap.launch import make_backend

        self.stop_on_entry = _flag(args, "stopOnEntry")
        self.backend = make_backend(args, self)
        self.breakpoints.program = self.backend.program
        return None

    def attach(self, args: Message) -> Message | None:
        raise DapError("gpp dap launches runs (`launch` with a program or a trace); it cannot attach to one")

    def maybe_start(self) -> None:
        """Start the run once it is launched and configured (the client sends its breakpoints
        between the two). A client that sends no `configurationDone` gets none of that: the
        run starts at launch then."""
        if self.started or self.backend is None or not self.configured:
            return
        self.started = True
        self.backend.start(self.stop_on_entry)

    def configuration_done(self, args: Message) -> Message | None:
        self.configured = True
        return None

    def set_breakpoints(self, args: Message) -> Message:
        source = args.get("source")
        if not isinstance(source, dict) or not isinstance(source.get("path"), str):
            raise DapError("setBreakpoints needs `source.path`")
        wanted = args.get("breakpoints")
        if wanted is None:
            wanted = [{"line": line} for line in args.get("lines", [])]
        if not self.lines_start_at1 and isinstance(wanted, list):
            wanted = [{**b, "line": b["line"] + 1} if isinstance(b.get("line"), int) else b for b in wanted]
        if not isinstance(wanted, list) or not all(isinstance(b, dict) for b in wanted):
            raise DapError("setBreakpoints' `breakpoints` is a list of objects")
        placed = self.breakpoints.set_lines(source["path"], wanted)
        return {"breakpoints": [self.placed(b.reported()) for b in placed]}

    def placed(self, reported: Message) -> Message:
        """A breakpoint as the client counts lines and columns."""
        for key in ("line", "endLine"):
            if key in reported:
                reported[key] = self.line_out(reported[key])
        if "column" in reported:
            reported["column"] = self.column_out(reported["column"])
        return reported

    def line_out(self, line: int) -> int:
        return line if self.lines_start_at1 else line - 1

    def column_out(self, column: int) -> int:
        return column if self.columns_start_at1 else column - 1

    def set_function_breakpoints(self, args: Message) -> Message:
        wanted = args.get("breakpoints", [])
        if not isinstance(wanted, list) or not all(isinstance(b, dict) for b in wanted):
            raise DapError("setFunctionBreakpoints' `breakpoints` is a list of objects")
        placed = self.breakpoints.set_functions(wanted)
        return {"breakpoints": [b.reported() for b in placed]}

    def set_exception_breakpoints(self, args: Message) -> Message:
        filters = args.get("filters", [])
        if not isinstance(filters, list) or not all(isinstance(f, str) for f in filters):
            raise DapError("setExceptionBreakpoints' `filters` is a list of filter names")
        unknown = [f for f in filters if f not in EXCEPTION_FILTERS]
        if unknown:
            raise DapError(f"unknown exception filter `{unknown[0]}` (gpp dap has {', '.join(EXCEPTION_FILTERS)})")
        self.breakpoints.exceptions = frozenset(filters)
        return {"breakpoints": [{"verified": True} for _ in filters]}

    def threads(self, args: Message) -> Message:
        return {"threads": [{"id": THREAD_ID, "name": "main"}]}

    def stopped_backend(self) -> SessionBackend:
        backend = self.launched()
        if not backend.stopped():
            raise DapError("the run is running: pause it first")
        return backend

    def launched(self) -> SessionBackend:
        if self.backend is None:
            raise DapError("nothing is launched yet")
        return self.backend

    def stack_trace(self, args: Message) -> Message:
        frames = self.stopped_backend().stack()
        start = _int(args, "startFrame", 0)
        levels = _int(args, "levels", 0)
        shown = frames[start : start + levels] if levels > 0 else frames[start:]
        out: list[Message] = []
        for f in shown:
            frame: Message = {"id": f.id, "name": f.name, "line": 0, "column": 0}
            if f.span is not None:
                frame |= {
                    "source": _source(f.span),
                    "line": self.line_out(f.span.line),
                    "column": self.column_out(f.span.col),
                    "endLine": self.line_out(f.span.end_line),
                    "endColumn": self.column_out(f.span.end_col),
                }
            out.append(frame)
        return {"stackFrames": out, "totalFrames": len(frames)}

    def scopes(self, args: Message) -> Message:
        scopes = self.stopped_backend().scopes(_int(args, "frameId", 0))
        out: list[Message] = []
        for s in scopes:
            scope: Message = {"name": s.name, "variablesReference": s.reference, "expensive": s.expensive}
            if s.hint is not None:
                scope["presentationHint"] = s.hint
            if s.count is not None:
                scope["namedVariables"] = s.count
            out.append(scope)
        return {"scopes": out}

    def variables(self, args: Message) -> Message:
        found = self.stopped_backend().variables(_int(args, "variablesReference", 0))
        start, count = _int(args, "start", 0), _int(args, "count", 0)
        if count > 0:
            found = found[start : start + count]
        out: list[Message] = []
        for v in found:
            variable: Message = {"name": v.name, "value": v.value, "variablesReference": v.reference}
            if v.type:
                variable["type"] = v.type
            if v.evaluate_name is not None:
                variable["evaluateName"] = v.evaluate_name
            out.append(variable)
        return {"variables": out}

    def evaluate(self, args: Message) -> Message:
        expression = args.get("expression")
        if not isinstance(expression, str):
            raise DapError("evaluate needs an `expression`")
        frame_id = args.get("frameId")
        if frame_id is not None and not isinstance(frame_id, int):
            raise DapError("evaluate's `frameId` is a number")
        context = str(args.get("context", "repl"))
        found = self.stopped_backend().evaluate(expression, frame_id, context)
        body: Message = {"result": found.result, "variablesReference": found.reference}
        if found.type:
            body["type"] = found.type
        return body

    def resume_with(self, how: Any) -> Handler:
        def resume(args: Message) -> Message | None:
            backend = self.stopped_backend()
            if how in ("stepBack", "reverseContinue") and not backend.capabilities.step_back:
                raise DapError('stepping back needs a recorded run: launch a trace file (`"trace": "run.jsonl"`)')
            self.after_response = backend.resume(how)
            return {"allThreadsContinued": True} if how == "continue" else None

        return resume

    def pause(self, args: Message) -> Message | None:
        self.launched().pause()
        return None

    def terminate(self, args: Message) -> Message | None:
        self.end_backend()
        return None

    def disconnect(self, args: Message) -> Message | None:
        self.end_backend()
        self.finished = True
        return None

    def source(self, args: Message) -> Message:
        source = args.get("source")
        path = source.get("path") if isinstance(source, dict) else None
        if not isinstance(path, str):
            raise DapError("source needs `source.path`")
        try:
            return {"content": Path(path).read_text(encoding="utf-8"), "mimeType": "text/x-golog"}
        except (OSError, UnicodeDecodeError) as e:
            raise DapError(f"cannot read {path}: {e.strerror if isinstance(e, OSError) else e}") from None

    def end_backend(self) -> None:
        """End the run (if any) and wait for its trace to be finished (the backend then tells
        the end, `ended`)."""
        if self.backend is not None:
            self.backend.terminate()


def _flag(args: Message, name: str) -> bool:
    value = args.get(name, False)
    if not isinstance(value, bool):
        raise DapError(f"launch's `{name}` is true or false, not {json.dumps(value)}")
    return value


def _int(args: Message, name: str, default: int) -> int:
    value = args.get(name, default)
    if not isinstance(value, int) or isinstance(value, bool):
        raise DapError(f"`{name}` is a number")
    return value
