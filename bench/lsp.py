"""Language server latency: a real `gpp lsp` over stdio, driven like an editor.

Run: .venv/bin/python bench/lsp.py [--quick] [--lines 1000] [--against OTHER_CHECKOUT] [--timeline FILE]

For generated programs of 1,000 and 10,000 lines it measures, as the client sees it:
* edit -> diagnostics: the time from sending a `didChange` (one character typed) to receiving
  the `publishDiagnostics` for that version, for a space typed at the start of the last line
  and of the middle one (between declarations: no token changes), and for a letter typed into
  a name in a procedure's body in the middle (an unknown name while it is there);
* completion and hover round trips on the analysed document (no edit pending), and completion
  as an editor asks for it, at once after typing a letter (the check of that version running);
and, in-process, where an edit's analysis spends its time (the parse of the changed file, the
code model and type check, the lints). Times are medians (and 90th percentiles) over repeated
runs (60 edits of each kind and 60 completions after a key on 1,000 lines; 20 with --quick);
the targets of the language server (issue 10) are printed beside them. A publishDiagnostics
counts from the arrival of its bytes: the bench's own decoding of it (pygls' client, cattrs)
is left out and printed apart. Requests count until their answer is decoded.

`--timeline FILE` has this checkout's server append to FILE where each round's time went,
from the edit received to the diagnostics written (GPP_LSP_TIMING, see README).

`--against DIR` also runs the server of another checkout of gpp (say, `git worktree add
/tmp/gpp-main main`), program by program in turn with this one, and prints both medians and
their ratio: a comparison on a loaded machine that both sides see alike.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Awaitable, Callable
from functools import partial
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from genprog import generate_program
from lsprotocol import types
from pygls.lsp.client import LanguageClient

from gpp.base.perf import with_deep_stack
from gpp.base.source import Source
from gpp.check import check_loaded
from gpp.check.lints import run_lints
from gpp.model.build import build_model
from gpp.syntax.loader import load
from gpp.syntax.parser import parse

SERVER = [sys.executable, "-m", "gpp", "lsp"]
# What the language server should reach (issue 10), by (program, what).
TARGETS = {
    ("1,000 lines", "edit end -> diags"): 0.050,
    ("1,000 lines", "edit middle -> diags"): 0.050,
    ("1,000 lines", "edit in body -> diags"): 0.050,
    ("1,000 lines", "completion"): 0.010,
    ("1,000 lines", "completion after key"): 0.010,
}


class Client(LanguageClient):
    """A client that notes when each message's bytes arrived: a publishDiagnostics counts
    from then, not from when the client had decoded it (json, then lsprotocol's objects by
    cattrs: about a millisecond for the 60 diagnostics of the 1,000-line program, more than
    an editor's decoding; `decoding` keeps what it cost)."""

    def __init__(self) -> None:
        super().__init__("gpp-bench", "1")
        self.published: dict[tuple[str, int | None], float] = {}
        self.counts: dict[tuple[str, int | None], int] = {}  # how many diagnostics
        self.waiters: dict[tuple[str, int | None], asyncio.Future[float]] = {}
        self.arrived = 0.0  # when the bytes of the message being handled arrived
        self.decoding: list[float] = []

        @self.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def publish(params: types.PublishDiagnosticsParams) -> None:
            now = self.arrived
            self.decoding.append(time.perf_counter() - now)
            key = (params.uri, params.version)
            self.published[key] = now
            self.counts[key] = len(params.diagnostics)
            waiter = self.waiters.pop(key, None)
            if waiter is not None and not waiter.done():
                waiter.set_result(now)

        @self.feature(types.WINDOW_LOG_MESSAGE)
        def log(params: types.LogMessageParams) -> None:
            if params.type == types.MessageType.Error:
                print(params.message, file=sys.stderr)

    async def start_io(self, cmd: str, *args: str, **kwargs: Any) -> None:
        await super().start_io(cmd, *args, **kwargs)
        stdout = self._server.stdout  # (the message loop reads bodies with its readexactly)
        read = stdout.readexactly

        async def stamped(n: int) -> bytes:
            body = await read(n)
            self.arrived = time.perf_counter()
            return body

        stdout.readexactly = stamped  # type: ignore[method-assign]

    def published_at(self, uri: str, version: int) -> Awaitable[float]:
        key = (uri, version)
        fut: asyncio.Future[float] = asyncio.get_running_loop().create_future()
        if key in self.published:
            fut.set_result(self.published[key])
        else:
            self.waiters[key] = fut
        return fut


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


async def timed(n: int, fn: Callable[[], Awaitable[object]]) -> list[float]:
    out = []
    for _ in range(n):
        t0 = time.perf_counter()
        await fn()
        out.append(time.perf_counter() - t0)
    return out


async def measure(client: Client, folder: Path, lines: int, edits: int, requests: int) -> dict[str, list[float]]:
    text = generate_program(lines)
    path = folder / f"prog{lines}.gpp"
    uri = path.as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(types.TextDocumentItem(uri=uri, language_id="golog", version=1, text=text))
    )
    t0 = time.perf_counter()
    first = await client.published_at(uri, 1)
    results: dict[str, list[float]] = {"open": [first - t0]}
    # Type a space at the start of a line and delete it again, one version each: on the last
    # line (the easiest case for incremental work), then on the middle one (both between two
    # declarations: no token changes). Then a letter typed into a name in the body of a
    # procedure in the middle, and deleted again: `mo|ve9(` -> `mox|ve9(`, an unknown name (an
    # error more) while it is there.
    source = Source(text)
    version = 1
    middle = source.line_count() // 2
    body = text.index("\n", text.index("\nprocedure ", source.lsp_offset(middle, 0)) + 1) + 1
    body_line, body_char = source.lsp_position(text.index("move", body) + 2)
    places = [
        ("end", source.line_count() - 2, 0, " "),
        ("middle", middle, 0, " "),
        ("in body", body_line, body_char, "x"),
    ]
    for where, line, char, letter in places:
        changes: list[float] = []
        for k in range(edits):
            version += 1
            rng = types.Range(types.Position(line, char), types.Position(line, char if k % 2 == 0 else char + 1))
            change = types.TextDocumentContentChangePartial(range=rng, text=letter if k % 2 == 0 else "")
            identifier = types.VersionedTextDocumentIdentifier(uri=uri, version=version)
            t0 = time.perf_counter()
            client.text_document_did_change(types.DidChangeTextDocumentParams(identifier, [change]))
            changes.append(await client.published_at(uri, version) - t0)
        results[f"edit {where} -> diags"] = changes
        counts = sorted({client.counts[(uri, v)] for v in range(version - edits + 1, version + 1)})
        print(f"{lines:,} lines, edit {where}: {' or '.join(map(str, counts))} diagnostics")
    # A position inside the body of a procedure, on a name.
    offset = text.rindex("count0(") + 2
    line, char = source.lsp_position(offset)
    pos = types.Position(line, char)
    doc = types.TextDocumentIdentifier(uri)
    results["completion"] = await timed(
        requests, lambda: client.text_document_completion_async(types.CompletionParams(doc, pos))
    )
    results["hover"] = await timed(requests, lambda: client.text_document_hover_async(types.HoverParams(doc, pos)))
    # Completion as an editor asks for it: a letter typed (`co|unt0` -> `cou|unt0`), and at
    # once the request, while that version's check runs. (Then the letter goes again; each
    # round starts with the analysis idle.)
    after: list[float] = []
    typed = types.Position(line, char + 1)
    for _ in range(edits):
        for k in range(2):
            version += 1
            identifier = types.VersionedTextDocumentIdentifier(uri=uri, version=version)
            rng = types.Range(pos, pos if k == 0 else typed)
            change = types.TextDocumentContentChangePartial(range=rng, text="u" if k == 0 else "")
            t0 = time.perf_counter()
            client.text_document_did_change(types.DidChangeTextDocumentParams(identifier, [change]))
            if k == 0:
                await client.text_document_completion_async(types.CompletionParams(doc, typed))
                after.append(time.perf_counter() - t0)
            await client.published_at(uri, version)
    results["completion after key"] = after
    return results


def phases(lines: int, runs: int) -> dict[str, float]:
    """In-process: what one edit's analysis costs, phase by phase (best of `runs`)."""
    text = generate_program(lines)
    path = Path(tempfile.gettempdir()) / f"gpp-bench-{lines}.gpp"
    best: dict[str, float] = {}

    def keep(name: str, seconds: float) -> None:
        best[name] = min(best.get(name, float("inf")), seconds)

    for _ in range(runs):
        t0 = time.perf_counter()
        parse(Source(text, str(path)))
        keep("parse (tokens + AST)", time.perf_counter() - t0)
        loaded = load([path], {path: text})
        t0 = time.perf_counter()
        model, _ = with_deep_stack(partial(build_model, loaded.files))
        keep("code model + type check", time.perf_counter() - t0)
        t0 = time.perf_counter()
        with_deep_stack(partial(run_lints, model, {path.resolve()}))
        keep("lints", time.perf_counter() - t0)
        t0 = time.perf_counter()
        check_loaded(load([path], {path: text}))
        keep("whole check (parse + model + lints)", time.perf_counter() - t0)
    return best


async def start(checkout: str | None, timeline: str | None = None) -> Client:
    """A server of this checkout of gpp, or of another. (`python -m gpp` imports gpp from the
    working directory first: the server runs in its checkout.)"""
    client = Client()
    folder = Path(checkout) if checkout is not None else Path(__file__).resolve().parent.parent
    env = {**os.environ, "PYTHONPATH": str(folder)}
    if timeline is not None:
        env["GPP_LSP_TIMING"] = str(Path(timeline).resolve())
    await client.start_io(*SERVER, env=env, cwd=str(folder))
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    return client


async def stop(client: Client) -> None:
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()


Row = tuple[str, str, list[float]]


async def run_servers(
    quick: bool, against: str | None, sizes: list[int], timeline: str | None
) -> tuple[list[Row], list[Row]]:
    """The rows of this checkout's server and, with `against`, of the other's (each program
    measured by one server, then by the other)."""
    runs = {1000: (20 if quick else 60, 50 if quick else 200), 10000: (3 if quick else 8, 20 if quick else 50)}
    t0 = time.perf_counter()
    client = await start(None, timeline)
    print(f"server start + initialize: {time.perf_counter() - t0:.2f} s")
    other = await start(against) if against is not None else None
    rows: list[Row] = []
    other_rows: list[Row] = []
    with tempfile.TemporaryDirectory() as tmp:
        for lines in sizes:
            edits, requests = runs[lines]
            for server, out, folder in ((client, rows, "this"), (other, other_rows, "other")):
                if server is None:
                    continue
                (Path(tmp) / folder).mkdir(exist_ok=True)
                found = await measure(server, Path(tmp) / folder, lines, edits, requests)
                out.extend((f"{lines:,} lines", what, values) for what, values in found.items())
    await stop(client)
    if other is not None:
        await stop(other)
    decoding = statistics.median(client.decoding)
    print(f"the client's decoding of a publishDiagnostics (not counted above): median {ms(decoding)}")
    return rows, other_rows


def ms(seconds: float | None) -> str:
    return "" if seconds is None else f"{seconds * 1000:.1f} ms"


def table_row(cells: list[tuple[str, int]]) -> str:
    """A Markdown table row: (text, width) cells, numbers right-aligned (width < 0: left)."""
    return "| " + " | ".join(f"{text:<{-w}}" if w < 0 else f"{text:>{w}}" for text, w in cells) + " |"


async def main_async(quick: bool, against: str | None, sizes: list[int], timeline: str | None) -> None:
    rows, other_rows = await run_servers(quick, against, sizes, timeline)
    widths = [-13, -21, 4, 9, 9, 7] + ([9, 10] if against is not None else [])
    names = ["program", "what", "runs", "median", "p90", "target", "other", "other/this"]
    print()
    print(table_row(list(zip(names, widths, strict=False))))
    print("|" + "|".join("-" * (abs(w) + 2) for w in widths) + "|")
    for k, (program, what, values) in enumerate(rows):
        med = statistics.median(values)
        target = TARGETS.get((program, what))
        cells = [program, what, str(len(values)), ms(med), ms(percentile(values, 0.9))]
        cells.append("" if target is None else f"{target * 1000:.0f} ms")
        if against is not None:
            other_med = statistics.median(other_rows[k][2])
            cells += [ms(other_med), f"{other_med / med:.2f}x"]
        print(table_row(list(zip(cells, widths, strict=True))))
    print()
    print("where an edit's analysis goes (in-process, best of runs):")
    print()
    print(f"| {'program':<13} | {'phase':<36} | {'time':>9} |")
    print(f"|{'-' * 15}|{'-' * 38}|{'-' * 11}|")
    for lines in sizes:
        for name, seconds in phases(lines, 2 if quick else 5).items():
            print(f"| {f'{lines:,} lines':<13} | {name:<36} | {seconds * 1000:>6.1f} ms |")
    print(f"\nload average: {' '.join(Path('/proc/loadavg').read_text().split()[:3])}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer runs")
    parser.add_argument("--against", metavar="DIR", help="also run the server of this other checkout of gpp")
    parser.add_argument(
        "--lines", type=int, choices=[1000, 10000], action="append", help="only this program size (repeatable)"
    )
    parser.add_argument(
        "--timeline", metavar="FILE", help="this checkout's server appends where each round's time went to FILE"
    )
    args = parser.parse_args()
    if args.against is not None and not (Path(args.against) / "gpp" / "__init__.py").is_file():
        parser.error(f"--against: {args.against} is no checkout of gpp (no gpp/__init__.py in it)")
    asyncio.run(main_async(args.quick, args.against, args.lines or [1000, 10000], args.timeline))


if __name__ == "__main__":
    main()
