"""Language server latency: a real `gpp lsp` over stdio, driven like an editor.

Run: .venv/bin/python bench/lsp.py [--quick]

For generated programs of 1,000 and 10,000 lines it measures, as the client sees it:
* edit -> diagnostics: the time from sending a `didChange` (one character typed) to receiving
  the `publishDiagnostics` for that version;
* completion and hover round trips on the analysed document (no edit pending);
and, in-process, where an edit's analysis spends its time (the parse of the changed file, the
code model and type check, the lints). Times are medians (and 90th percentiles) over repeated runs.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import tempfile
import time
from collections.abc import Awaitable, Callable
from functools import partial
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from genprog import generate_program
from lsprotocol import types
from pygls.lsp.client import LanguageClient

from gpp.check import check_loaded
from gpp.check.lints import run_lints
from gpp.model.build import build_model
from gpp.perf import with_deep_stack
from gpp.source import Source
from gpp.syntax.loader import load
from gpp.syntax.parser import parse

SERVER = [sys.executable, "-m", "gpp", "lsp"]


class Client(LanguageClient):
    def __init__(self) -> None:
        super().__init__("gpp-bench", "1")
        self.published: dict[tuple[str, int | None], float] = {}
        self.waiters: dict[tuple[str, int | None], asyncio.Future[float]] = {}

        @self.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def publish(params: types.PublishDiagnosticsParams) -> None:
            now = time.perf_counter()
            key = (params.uri, params.version)
            self.published[key] = now
            waiter = self.waiters.pop(key, None)
            if waiter is not None and not waiter.done():
                waiter.set_result(now)

        @self.feature(types.WINDOW_LOG_MESSAGE)
        def log(params: types.LogMessageParams) -> None:
            if params.type == types.MessageType.Error:
                print(params.message, file=sys.stderr)

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
    # Type a space at the start of the last line and delete it again, one version each.
    source = Source(text)
    last_line = source.line_count() - 2
    version = 1
    changes: list[float] = []
    for k in range(edits):
        version += 1
        rng = types.Range(types.Position(last_line, 0), types.Position(last_line, 0 if k % 2 == 0 else 1))
        change = types.TextDocumentContentChangePartial(range=rng, text=" " if k % 2 == 0 else "")
        t0 = time.perf_counter()
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(types.VersionedTextDocumentIdentifier(uri=uri, version=version), [change])
        )
        changes.append(await client.published_at(uri, version) - t0)
    results["edit -> diagnostics"] = changes
    # A position inside the body of a procedure, on a name.
    offset = text.rindex("count0(") + 2
    line, char = source.lsp_position(offset)
    pos = types.Position(line, char)
    doc = types.TextDocumentIdentifier(uri)
    results["completion"] = await timed(
        requests, lambda: client.text_document_completion_async(types.CompletionParams(doc, pos))
    )
    results["hover"] = await timed(requests, lambda: client.text_document_hover_async(types.HoverParams(doc, pos)))
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


async def main_async(quick: bool) -> None:
    sizes = [(1000, 10 if quick else 30, 50 if quick else 200), (10000, 3 if quick else 8, 20 if quick else 50)]
    client = Client()
    t0 = time.perf_counter()
    await client.start_io(*SERVER)
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    print(f"server start + initialize: {time.perf_counter() - t0:.2f} s")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for lines, edits, requests in sizes:
            found = await measure(client, Path(tmp), lines, edits, requests)
            for what, values in found.items():
                rows.append((f"{lines:,} lines", what, len(values), statistics.median(values), percentile(values, 0.9)))
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    print()
    print(f"| {'program':<13} | {'what':<20} | {'runs':>4} | {'median':>9} | {'p90':>9} |")
    print(f"|{'-' * 15}|{'-' * 22}|{'-' * 6}|{'-' * 11}|{'-' * 11}|")
    for program, what, n, med, p90 in rows:
        print(f"| {program:<13} | {what:<20} | {n:>4} | {med * 1000:>6.1f} ms | {p90 * 1000:>6.1f} ms |")
    print()
    print("where an edit's analysis goes (in-process, best of runs):")
    print()
    print(f"| {'program':<13} | {'phase':<36} | {'time':>9} |")
    print(f"|{'-' * 15}|{'-' * 38}|{'-' * 11}|")
    for lines in (1000, 10000):
        for name, seconds in phases(lines, 2 if quick else 5).items():
            print(f"| {f'{lines:,} lines':<13} | {name:<36} | {seconds * 1000:>6.1f} ms |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer runs")
    args = parser.parse_args()
    asyncio.run(main_async(args.quick))


if __name__ == "__main__":
    main()
