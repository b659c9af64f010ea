"""The golog++ language server's core (`gpp lsp`, composed in lsp.main): `GppServer`, pygls 2
on stdio (or TCP for debugging), with the documents kept in a gpp.check.session.Session, the
programs checked in rounds on the analysis thread (only the results for a document's current
version are published), the features answered on a request thread, the garbage collector
governed by lsp.gc_policy.GcPolicy, and the document synchronisation handlers
(`document_server`). Why the threads and what keeps a round short: docs/design.md, "Analysis
session and language server".

GPP_LSP_TIMING=FILE appends to FILE where each round's time goes (`Timeline`) and how long
each completion took inside the server. Every handler catches what goes wrong, logs it to the
client (window/logMessage) and answers with an empty result (`guarded`).
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import inspect
import itertools
import json
import os
import stat
import sys
import threading
import time
import traceback
from collections.abc import Awaitable, Callable, Sequence
from concurrent.futures import Future
from pathlib import Path
from typing import Any, BinaryIO, ParamSpec, TypeVar, cast
from urllib.parse import quote, unquote, urlparse

from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pygls.io_ import StdoutWriter, run_async
from pygls.lsp.server import LanguageServer
from pygls.protocol import LanguageServerProtocol, lsp_method

from gpp import __version__
from gpp.base import diagnostics as diag
from gpp.check import CheckResult
from gpp.check.session import AnalysisThread, Document, LspEdit, Session, diagnostics_in
from gpp.codes import W0101, W0102
from gpp.platform.static import static_diagnostics
from lsp.codes_doc import code_url
from lsp.gc_policy import GcPolicy
from lsp.ranges import lsp_range

P = ParamSpec("P")
R = TypeVar("R")

# Lints about declarations nobody uses: editors grey them out.
_UNNECESSARY = frozenset({W0101.code, W0102.code})
_SEVERITY = {
    diag.Severity.ERROR: types.DiagnosticSeverity.Error,
    diag.Severity.WARNING: types.DiagnosticSeverity.Warning,
    diag.Severity.NOTE: types.DiagnosticSeverity.Information,
}
# How long after a round of checks, if no edit came since, the garbage collector catches up.
SETTLE_AFTER_SECONDS = 1.0
# How long after a round of checks, if no edit came since, the checks it replaced are freed.
FREE_AFTER_SECONDS = 0.02
# How many times the event loop goes round before a round of checks starts: a request an
# editor sends with the edit (completion after a keystroke) is read, answered and written in
# those turns, before the check competes with it for the interpreter lock. (Microseconds.)
START_AFTER_TURNS = 3
# How long a request waits for the analysis of the document's current version.
_WAIT_SECONDS = 30.0


# ---------------------------------------------------------------- the timeline


class Timeline:
    """With GPP_LSP_TIMING=FILE in the environment: one line appended to FILE per round of
    checks, where the time from the first edit the round answers to the diagnostics written
    on stdout went (in milliseconds):

    `edit` the first change not yet checked arrived (the handler ran) -> `queue` the round was
    submitted -> `wait` the analysis thread began it -> `pause` the collector paused -> `check`
    the programs checked -> `free` the checks replaced by the last round freed (unless a pause
    after it freed them) -> `back` the event loop took the results -> `convert` the diagnostics
    converted -> `publish` written and flushed."""

    def __init__(self, file: str | None) -> None:
        self.file = file
        self.enabled = bool(file)
        self._first_edit: float | None = None
        self._marks: list[tuple[str, float]] = []

    def edit(self) -> None:
        if self.enabled and self._first_edit is None:
            self._first_edit = time.perf_counter()

    def start(self) -> None:
        """A round is submitted: it answers the edits since the last one."""
        if self.enabled:
            now = time.perf_counter()
            self._marks = [("edit", self._first_edit or now), ("queue", now)]
            self._first_edit = None

    def mark(self, name: str) -> None:
        if self.enabled:
            self._marks.append((name, time.perf_counter()))

    def report(self, what: str) -> None:
        if not self.enabled or not self._marks:
            return
        marks, self._marks = self._marks, []
        self.write(what, marks)

    def write(self, what: str, marks: Sequence[tuple[str, float]]) -> None:
        """A line of its own: `what`, and the time from each mark to the next."""
        if not self.file:
            return
        steps = " ".join(f"{name} {(t - prev) * 1000:.1f}" for (_, prev), (name, t) in itertools.pairwise(marks))
        total = (marks[-1][1] - marks[0][1]) * 1000
        with contextlib.suppress(OSError), open(self.file, "a", encoding="utf-8") as out:
            out.write(f"{what}: {steps} = {total:.1f} ms\n")


# ---------------------------------------------------------------- URIs and paths


def uri_to_path(uri: str) -> Path:
    """The file a document URI names. A URI of another scheme (an editor's unsaved `untitled:`
    buffer) becomes a path under a folder that does not exist, named after the scheme."""
    parsed = urlparse(uri)
    if parsed.scheme in ("file", ""):
        return Path(unquote(parsed.path)).resolve()
    return Path("/", f"<{parsed.scheme}>", quote(unquote(parsed.path or parsed.netloc), safe="")).resolve()


# ---------------------------------------------------------------- the protocol


class RequestFailed(JsonRpcException):
    """LSP's RequestFailed: the request was valid but cannot be done (a refused rename). The
    client gets the reason as the error's message; the server's log gets one line."""

    CODE = -32803


class _Protocol(LanguageServerProtocol):
    """pygls' protocol, but the documents are gpp's (gpp.check.session): pygls' own copies would
    cost a second application of every edit, and it counts line breaks its own way (Python's
    `splitlines`, which also breaks at form feeds and U+2028)."""

    @lsp_method(types.INITIALIZE)
    def lsp_initialize(self, params: types.InitializeParams) -> Any:
        # gpp counts positions in UTF-16 units, the protocol's default: a client that offers
        # other encodings too (Neovim offers UTF-8 first) gets UTF-16 announced.
        general = params.capabilities.general
        if general is not None:
            general.position_encodings = None
        return (yield from super().lsp_initialize(params))

    def _send_handler_result(self, future: Future[Any], *, msg_id: Any) -> None:
        """pygls' answer to a request, but a refusal (RequestFailed) is answered without
        pygls' report of an exception (a traceback on stderr): it is no error of the server,
        and its reason is logged to the client in one line."""
        refusal = None if future.cancelled() else future.exception()
        if not isinstance(refusal, RequestFailed):
            super()._send_handler_result(future, msg_id=msg_id)
            return
        self._request_futures.pop(msg_id, None)
        self._send_response(msg_id, error=refusal.to_response_error())
        server = self._server
        if isinstance(server, GppServer):
            server.log(f"gpp: request {msg_id} refused: {refusal.message}", types.MessageType.Info)

    @lsp_method(types.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params: types.DidOpenTextDocumentParams) -> Any:
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_OPEN)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: types.DidChangeTextDocumentParams) -> Any:
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params: types.DidCloseTextDocumentParams) -> Any:
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CLOSE)) is not None:
            yield handler, (params,), None


# ---------------------------------------------------------------- reading stdin


class _PipeReader:
    """stdin read by the event loop itself (asyncio's pipe transport). pygls reads it on a
    thread pool instead, two lines and a body per message, each handed back to the event loop:
    six hand-overs of the interpreter lock per message, each waiting for a running check to
    let go of it (up to the switch interval)."""

    def __init__(self, reader: asyncio.StreamReader) -> None:
        self._reader = reader

    async def readline(self) -> bytes:
        return await self._reader.readline()

    async def readexactly(self, n: int) -> bytes:
        try:
            return await self._reader.readexactly(n)
        except asyncio.IncompleteReadError:
            return b""  # the client is gone


def _is_pipe(stream: BinaryIO) -> bool:
    """Whether asyncio can read `stream` with a pipe transport (a pipe, socket or terminal,
    not a regular file)."""
    try:
        mode = os.fstat(stream.fileno()).st_mode
    except (OSError, ValueError):
        return False
    return stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode) or stat.S_ISCHR(mode)


# ---------------------------------------------------------------- the server


class GppServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("gpp", __version__, protocol_cls=_Protocol)
        self.session = Session(extra_checks=static_diagnostics)
        self.analysis = AnalysisThread("gpp-analysis")
        self.requests = AnalysisThread("gpp-requests")
        # The garbage collector waits while a round of checks runs (lsp.gc_policy.GcPolicy).
        self.collector = GcPolicy()
        self.uris: dict[Path, str] = {}
        # The latest checks of each open document: (version, the programs' results).
        self.results: dict[Path, tuple[int, list[CheckResult]]] = {}
        # What was published last for each document: (version, diagnostics as JSON texts).
        self._published: dict[Path, tuple[int, list[str]]] = {}
        # The JSON texts of the diagnostics published last for each document (diagnostics_json).
        self._converted: dict[Path, dict[tuple[object, ...], str]] = {}
        self._writes: set[asyncio.Future[Any]] = set()  # (send_json's, until done)
        self._running = False
        self._again = False
        self._round_done: asyncio.Event | None = None
        self._settle: asyncio.TimerHandle | None = None
        # The checks replaced by the last rounds, not freed yet (_free_now, or the next round).
        self._garbage: list[object] = []
        self._free: asyncio.TimerHandle | None = None
        self.timeline = Timeline(os.environ.get("GPP_LSP_TIMING"))

    def start_io(self, stdin: BinaryIO | None = None, stdout: BinaryIO | None = None) -> None:
        """pygls' stdio server, with stdin read on the event loop when it is a pipe
        (`_PipeReader`); pygls' own reader otherwise."""
        source = stdin or sys.stdin.buffer
        if not _is_pipe(source):
            super().start_io(stdin, stdout)
            return
        self._stop_event = stop_event = threading.Event()
        self.protocol.set_writer(StdoutWriter(stdout or sys.stdout.buffer))

        async def serve() -> None:
            reader = asyncio.StreamReader()
            loop = asyncio.get_running_loop()
            await loop.connect_read_pipe(lambda: asyncio.StreamReaderProtocol(reader), source)
            await run_async(stop_event, _PipeReader(reader), self.protocol, error_handler=self.report_server_error)

        try:
            asyncio.run(serve())
        except BrokenPipeError:
            pass  # the client is gone
        except (KeyboardInterrupt, SystemExit):
            pass
        finally:
            self.shutdown()  # type: ignore[no-untyped-call]  # (pygls leaves it untyped)

    # ------------------------------------------------------------ logging

    def log(self, message: str, kind: types.MessageType = types.MessageType.Log) -> None:
        with contextlib.suppress(Exception):  # the client is gone: nothing to tell
            self.window_log_message(types.LogMessageParams(type=kind, message=message))

    def log_exception(self, what: str, e: BaseException) -> None:
        detail = "".join(traceback.format_exception(e))
        message = f"gpp: internal error in {what} (this is a bug in gpp {__version__}):\n{detail}"
        self.log(message, types.MessageType.Error)

    def uri_of(self, path_or_identity: Path | str) -> str:
        path = Path(path_or_identity)
        known = self.uris.get(path)
        if known is not None:
            return known
        return path.as_uri() if path.is_absolute() else str(path)

    # ------------------------------------------------------------ analysis

    def schedule(self) -> None:
        """Check the open documents again, soon: now if the analysis thread is idle, else once
        its current round is over (edits in between are coalesced into that one round)."""
        if self._running:
            self._again = True
            return
        self._running = True
        for timer in (self._settle, self._free):
            if timer is not None:
                timer.cancel()  # typing goes on: collect later, free in the round
        self._settle = self._free = None
        self.timeline.start()
        self._start_round(START_AFTER_TURNS)

    def _start_round(self, turns: int) -> None:
        """Submit the round once the event loop has gone round `turns` more times."""
        loop = asyncio.get_running_loop()
        if turns > 0:
            loop.call_soon(self._start_round, turns - 1)
            return
        garbage, self._garbage = self._garbage, []
        future = self.analysis.submit(functools.partial(self._analyze, garbage))
        future.add_done_callback(lambda f: loop.call_soon_threadsafe(self._analyzed, f))

    def _analyze(
        self, garbage: list[object]
    ) -> dict[Path, tuple[int, list[CheckResult], list[diag.Diagnostic]] | BaseException]:
        """On the analysis thread: check every open document's programs, then free `garbage`
        (the checks the last rounds replaced). Not before: freeing a tree is one stretch of the
        interpreter's own code that does not let go of the interpreter lock (5 to 15 ms for
        1,000 lines), and a request sent with the keystroke (completion) may still come in
        the round's first milliseconds."""
        self.timeline.mark("wait")
        self.collector.pause()
        self.timeline.mark("pause")
        snapshot = self.session.snapshot()
        texts = {p: d.text for p, d in snapshot.items()}
        out: dict[Path, tuple[int, list[CheckResult], list[diag.Diagnostic]] | BaseException] = {}
        for path, doc in snapshot.items():
            current = self.session.document(path)
            if current is None or current.version != doc.version:
                continue  # changed (or closed) since the round began: its result would be dropped
            try:
                results = self.session.results_for(path, texts)
                out[path] = (doc.version, results, diagnostics_in(results, path))
            except Exception as e:
                out[path] = e
        self.timeline.mark("check")
        garbage.clear()
        self.collector.settle()
        self.timeline.mark("free")
        return out

    def _analyzed(
        self, future: Future[dict[Path, tuple[int, list[CheckResult], list[diag.Diagnostic]] | BaseException]]
    ) -> None:
        """On the event loop: publish what is still current, drop what is stale."""
        self.timeline.mark("back")
        self._running = False
        published: list[str] = []
        try:
            found = future.result()
        except Exception as e:
            self.log_exception("the analysis", e)
            found = {}
        for path, outcome in found.items():
            doc = self.session.document(path)
            if doc is None:
                continue
            if isinstance(outcome, BaseException):
                self.log_exception(f"checking {path}", outcome)
                if doc.version >= self.results.get(path, (-1, []))[0]:
                    self.results[path] = (doc.version, [])
                continue
            version, results, problems = outcome
            if version != doc.version:
                continue  # stale: the document changed meanwhile, the next round publishes
            # The check this replaces: freed (by reference counting, a whole tree and model:
            # 5 to 15 ms for 1,000 lines) once the diagnostics are out, not before (_free_now,
            # or at the end of the next round).
            self._garbage.append(self.results.get(path))
            self.results[path] = (version, results)
            try:
                lsp_diags = self.diagnostics_json(path, problems)
            except Exception as e:
                self.log_exception(f"converting the diagnostics of {path}", e)
                lsp_diags = []
            if self._published.get(path) != (version, lsp_diags):
                self.timeline.mark("convert")  # (with those of documents not published again)
                self._published[path] = (version, lsp_diags)
                # (Sent as JSON text, the diagnostics' texts kept from the last time: pygls
                # would convert lsprotocol's objects again, and encode them all again.)
                self.send_json(
                    f'{{"jsonrpc": "2.0", "method": "{types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS}", "params": '
                    f'{{"uri": {json.dumps(self.uri_of(path))}, "diagnostics": [{", ".join(lsp_diags)}], '
                    f'"version": {version}}}}}'
                )
                self.timeline.mark("publish")
                published.append(f"{path.name} v{version} ({len(lsp_diags)} diagnostics)")
        self.timeline.report(", ".join(published) or "nothing published")
        if self._round_done is not None:
            self._round_done.set()
            self._round_done = None
        if self.collector.due:
            # A long burst without a pause: collect now that its diagnostics are out, not at
            # the start of the next round.
            self.analysis.submit(functools.partial(self._collect, f"after {self.collector.rounds} rounds"))
        if self._again:
            self._again = False
            self.schedule()
            return
        loop = asyncio.get_running_loop()
        if self._garbage:
            self._free = loop.call_later(FREE_AFTER_SECONDS, self._free_now)
        if self.collector.pending:
            # Collect the garbage of the rounds once the typing pauses.
            self._settle = loop.call_later(SETTLE_AFTER_SECONDS, self._settle_now)

    def _free_now(self) -> None:
        """On the event loop, no round running: free the checks the last rounds replaced. (A
        request that comes meanwhile waits for it, but does not share the interpreter lock
        with it, handing it over again and again.)"""
        self._free = None
        self._garbage.clear()

    def _settle_now(self) -> None:
        self._settle = None
        if not self._running and self.collector.pending:
            self.analysis.submit(functools.partial(self._collect, "the typing paused"))

    def _collect(self, why: str) -> None:
        """On the analysis thread: a full collection (a line in the timeline)."""
        t0 = time.perf_counter()
        self.collector.collect()
        done = time.perf_counter()
        self.timeline.write(
            f"garbage collected, {why} ({self.collector.freed} objects freed)", [("start", t0), ("collect", done)]
        )

    async def result_for(self, uri: str) -> tuple[CheckResult, Path] | None:
        """The check of the program (the first one) a document belongs to, for its current
        version; waits for the analysis when the document changed since the last one."""
        path = uri_to_path(uri)
        loop = asyncio.get_running_loop()
        deadline = loop.time() + _WAIT_SECONDS
        while True:
            doc = self.session.document(path)
            if doc is None:
                return None
            known = self.results.get(path)
            if known is not None and known[0] == doc.version:
                return (known[1][0], path) if known[1] else None
            if self._round_done is None:
                self._round_done = asyncio.Event()
            if not self._running:
                self.schedule()
            try:
                await asyncio.wait_for(self._round_done.wait(), max(0.0, deadline - loop.time()))
            except TimeoutError:
                return None

    def earlier_check(self, path: Path) -> tuple[CheckResult, Document] | None:
        """When a document changed since its last check: that check (of the program it
        belongs to first) and the document now; else None."""
        doc = self.session.document(path)
        known = self.results.get(path)
        if doc is None or known is None or known[0] == doc.version or not known[1]:
            return None
        return known[1][0], doc

    async def on_request_thread(self, fn: Callable[[], R]) -> R:
        return await asyncio.wrap_future(self.requests.submit(fn))

    async def on_analysis_thread(self, fn: Callable[[], R]) -> R:
        return await asyncio.wrap_future(self.analysis.submit(fn))

    # ------------------------------------------------------------ conversions

    def send_json(self, body: str) -> None:
        """Write one message, given as JSON text, as pygls' `_send_data` writes the ones it
        encodes."""
        protocol = self.protocol
        if protocol.writer is None:
            return
        data = body.encode(protocol.CHARSET)
        if protocol._include_headers:
            header = f"Content-Length: {len(data)}\r\nContent-Type: {protocol.CONTENT_TYPE}; charset={protocol.CHARSET}"
            data = f"{header}\r\n\r\n".encode(protocol.CHARSET) + data
        written = protocol.writer.write(data)
        if inspect.isawaitable(written):  # (a writer of pygls' other transports)
            task = asyncio.ensure_future(written)
            self._writes.add(task)
            task.add_done_callback(self._writes.discard)

    def diagnostics_json(self, path: Path, problems: Sequence[diag.Diagnostic]) -> list[str]:
        """The diagnostics of a document as the JSON texts of the protocol's objects. A
        diagnostic that was published for the document last time too (same code, message,
        place, ...) is not converted again: an edit changes a few of them, and converting one
        costs tens of microseconds (lsprotocol's objects, then cattrs, then json)."""
        before = self._converted.get(path, {})
        now: dict[tuple[object, ...], str] = {}
        out: list[str] = []
        for d in problems:
            key = self._lsp_key(d)
            found = now.get(key) or before.get(key)
            if found is None:
                found = json.dumps(self.protocol._converter.unstructure(self.to_lsp(d)))
            now[key] = found
            out.append(found)
        self._converted[path] = now
        return out

    def _lsp_key(self, d: diag.Diagnostic) -> tuple[object, ...]:
        """What `to_lsp` makes of `d` depends on, and nothing else."""
        secondary = tuple(
            (self.uri_of(label.span.source.identity), label.span.lsp_range(), label.message) for label in d.secondary
        )
        return (d.code, d.severity, d.message, d.notes, d.help, d.span.lsp_range(), secondary)

    def to_lsp(self, d: diag.Diagnostic) -> types.Diagnostic:
        lines = [d.message, *(f"note: {n}" for n in d.notes)]
        if d.help:
            lines.append(f"help: {d.help}")
        url = code_url(d.code)
        return types.Diagnostic(
            range=lsp_range(d.span),
            message="\n".join(lines),
            severity=_SEVERITY[d.severity],
            code=d.code,
            code_description=types.CodeDescription(href=url) if url else None,
            source="gpp",
            tags=[types.DiagnosticTag.Unnecessary] if d.code in _UNNECESSARY else None,
            related_information=[
                types.DiagnosticRelatedInformation(
                    location=types.Location(self.uri_of(label.span.source.identity), lsp_range(label.span)),
                    message=label.message or "related",
                )
                for label in d.secondary
            ]
            or None,
        )

    def quick_fixes(self, result: CheckResult, path: Path, start: int, end: int) -> list[types.CodeAction]:
        """A quick fix for every diagnostic with a fix whose span touches [start, end]."""
        identity = str(path)
        actions: list[types.CodeAction] = []
        for found in result.diagnostics:
            span = found.span
            if found.fix is None or span.source.identity != identity or span.end < start or end < span.start:
                continue
            changes: dict[str, list[types.TextEdit]] = {}
            for edit in found.fix.edits:
                changes.setdefault(self.uri_of(edit.span.source.identity), []).append(
                    types.TextEdit(range=lsp_range(edit.span), new_text=edit.text)
                )
            actions.append(
                types.CodeAction(
                    title=found.fix.message,
                    kind=types.CodeActionKind.QuickFix,
                    diagnostics=[self.to_lsp(found)],
                    is_preferred=True,
                    edit=types.WorkspaceEdit(changes=changes),
                )
            )
        return actions


def guarded(default: Callable[[], object]) -> Callable[[Callable[P, Awaitable[R]]], Callable[P, Awaitable[R]]]:
    """Catch and log whatever a handler raises, and answer with `default()` instead (an error
    meant for the client, a JsonRpcException, is answered as such)."""

    def wrap(handler: Callable[P, Awaitable[R]]) -> Callable[P, Awaitable[R]]:
        @functools.wraps(handler)
        async def guarded(*args: P.args, **kwargs: P.kwargs) -> R:
            try:
                return await handler(*args, **kwargs)
            except JsonRpcException:
                raise
            except Exception as e:
                server = args[0]
                if isinstance(server, GppServer):
                    server.log_exception(handler.__name__, e)
                return cast(R, default())

        return guarded

    return wrap


def _none() -> None:
    return None


def _edits(changes: Sequence[types.TextDocumentContentChangeEvent]) -> list[LspEdit]:
    out: list[LspEdit] = []
    for change in changes:
        if isinstance(change, types.TextDocumentContentChangePartial):
            r = change.range
            out.append((((r.start.line, r.start.character), (r.end.line, r.end.character)), change.text))
        else:
            out.append((None, change.text))
    return out


def document_server() -> GppServer:
    """A server that keeps the documents: initialization, document synchronisation, workspace
    folders, shutdown (lsp.main adds the requests of lsp.handlers)."""
    server = GppServer()

    @server.feature(types.INITIALIZE)
    def initialize(ls: GppServer, params: types.InitializeParams) -> None:
        folders = [uri_to_path(f.uri) for f in params.workspace_folders or ()]
        if not folders and params.root_uri:
            folders = [uri_to_path(params.root_uri)]
        ls.session.set_folders([f for f in folders if f.is_dir()])

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    @guarded(_none)
    async def did_open(ls: GppServer, params: types.DidOpenTextDocumentParams) -> None:
        doc = params.text_document
        path = uri_to_path(doc.uri)
        ls.uris[path] = doc.uri
        ls.session.open(path, doc.text, doc.version)
        ls.schedule()

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    @guarded(_none)
    async def did_change(ls: GppServer, params: types.DidChangeTextDocumentParams) -> None:
        doc = params.text_document
        ls.timeline.edit()
        ls.session.edit(uri_to_path(doc.uri), _edits(params.content_changes), doc.version)
        ls.schedule()

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    @guarded(_none)
    async def did_close(ls: GppServer, params: types.DidCloseTextDocumentParams) -> None:
        path = uri_to_path(params.text_document.uri)
        ls.session.close(path)
        ls.results.pop(path, None)
        ls._converted.pop(path, None)
        if ls._published.pop(path, None):
            ls.text_document_publish_diagnostics(
                types.PublishDiagnosticsParams(uri=params.text_document.uri, diagnostics=[])
            )
        ls.uris.pop(path, None)
        ls.schedule()  # the programs that include it now read it from disk

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    @guarded(_none)
    async def did_save(ls: GppServer, params: types.DidSaveTextDocumentParams) -> None:
        ls.session.rescan()
        ls.schedule()

    @server.feature(types.WORKSPACE_DID_CHANGE_WATCHED_FILES)
    @guarded(_none)
    async def did_change_watched_files(ls: GppServer, params: types.DidChangeWatchedFilesParams) -> None:
        ls.session.rescan()
        ls.schedule()

    @server.feature(types.WORKSPACE_DID_CHANGE_WORKSPACE_FOLDERS)
    @guarded(_none)
    async def did_change_folders(ls: GppServer, params: types.DidChangeWorkspaceFoldersParams) -> None:
        folders = [f for f in ls.session.folders if f not in {uri_to_path(r.uri) for r in params.event.removed}]
        folders += [uri_to_path(a.uri) for a in params.event.added]
        ls.session.set_folders([f for f in folders if f.is_dir()])
        ls.schedule()

    @server.feature(types.SHUTDOWN)
    async def shutdown(ls: GppServer, params: None) -> None:
        ls.analysis.close(1.0)
        ls.requests.close(1.0)

    return server
