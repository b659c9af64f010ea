"""Fuzzing the language server: random edits to open documents, and after each one the
diagnostics the server publishes for that version compared with what `gpp check` finds in the
same text.

Run: .venv/bin/python bench/lspfuzz.py [--edits N] [--seed K] [--out DIR]
(`make fuzz` runs 2,000 edits; the test suite runs a few.)

One real `gpp lsp` over stdio. A program of examples/ or tests/programs/ is opened in a
temporary folder and edited, one didChange at a time, each a random incremental change: a
token-level piece of the vocabulary of bench/fuzz.py inserted, a range deleted, a range replaced
(the ranges sent as the protocol counts: lines and UTF-16 units). After each change the client
waits for the diagnostics of that version and compares them, (code, range, first line of the
message) in order, with `gpp check`'s on the text the client holds; every 200 edits another
program is opened. A mismatch, a server that stops answering or exits, is a finding: the text
and the last edit are written to DIR (default fuzz-findings/). The report gives edits/s and the
findings. Exit code 1 when there was a finding, else 0.
"""

from __future__ import annotations

import argparse
import asyncio
import random
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # bench and tests.support, also when run as a script

from bench.fuzz import VOCABULARY, pieces  # noqa: E402
from gpp.base.source import Source  # noqa: E402
from tests.support.lsp_client import expected, keys  # noqa: E402

SERVER = [sys.executable, "-m", "gpp", "lsp"]
PROGRAMS = sorted(p for d in ("examples", "tests/programs") for p in (ROOT / d).glob("*.gpp"))
EDITS_PER_DOCUMENT = 200
WAIT = 60.0  # s for the diagnostics of one version (a check of a mutated example takes ms)


@dataclass
class Finding:
    what: str
    text: str
    edit: str


@dataclass
class Report:
    edits: int = 0
    seconds: float = 0.0
    diagnostics: int = 0  # how many published diagnostics were compared
    findings: list[Finding] = field(default_factory=list)


class Client(LanguageClient):
    """A client that keeps the latest diagnostics published for each (uri, version)."""

    def __init__(self) -> None:
        super().__init__("gpp-lspfuzz", "1")
        self.published: dict[tuple[str, int | None], list[types.Diagnostic]] = {}
        self.arrived = asyncio.Event()

        @self.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def publish(params: types.PublishDiagnosticsParams) -> None:
            self.published[(params.uri, params.version)] = list(params.diagnostics)
            self.arrived.set()

    async def diagnostics(self, uri: str, version: int) -> list[types.Diagnostic] | None:
        """The diagnostics of `uri` at `version`, or None when none came within WAIT s."""
        deadline = time.monotonic() + WAIT
        while (uri, version) not in self.published:
            self.arrived.clear()
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            try:
                await asyncio.wait_for(self.arrived.wait(), left)
            except TimeoutError:
                return None
        return self.published.pop((uri, version))


def random_edit(text: str, rnd: random.Random) -> tuple[int, int, str]:
    """(start, end, new text): an insertion, a deletion or a replacement, at token boundaries
    most of the time, anywhere the rest."""
    parts = pieces(text)
    bounds = [0]
    for part in parts:
        bounds.append(bounds[-1] + len(part))
    if rnd.random() < 0.8:
        i = rnd.randrange(len(bounds))
        start, end = bounds[i], bounds[min(len(bounds) - 1, i + rnd.randint(0, 3))]
    else:
        start = rnd.randint(0, len(text))
        end = min(len(text), start + rnd.randint(0, 12))
    op = rnd.random()
    if op < 0.35:
        return start, start, rnd.choice(VOCABULARY) + rnd.choice(("", " ", "\n"))
    if op < 0.65:
        return start, end, ""
    return start, end, rnd.choice(VOCABULARY)


async def fuzz(edits: int, seed: int) -> Report:
    rnd = random.Random(seed)
    report = Report()
    client = Client()
    await client.start_io(*SERVER, cwd=str(ROOT))
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    started = time.perf_counter()
    try:
        with tempfile.TemporaryDirectory() as folder:
            done = 0
            while done < edits:
                original = rnd.choice(PROGRAMS)
                path = Path(folder) / f"doc{done}.gpp"
                text = original.read_text(encoding="utf-8")
                path.write_text(text, encoding="utf-8")
                uri = path.as_uri()
                version = 1
                client.text_document_did_open(
                    types.DidOpenTextDocumentParams(
                        types.TextDocumentItem(uri=uri, language_id="golog", version=version, text=text)
                    )
                )
                for _ in range(min(EDITS_PER_DOCUMENT, edits - done)):
                    start, end, new = random_edit(text, rnd)
                    source = Source(text, str(path))
                    (l1, c1), (l2, c2) = source.lsp_position(start), source.lsp_position(end)
                    version += 1
                    change = types.TextDocumentContentChangePartial(
                        range=types.Range(types.Position(l1, c1), types.Position(l2, c2)), text=new
                    )
                    client.text_document_did_change(
                        types.DidChangeTextDocumentParams(
                            types.VersionedTextDocumentIdentifier(version=version, uri=uri), [change]
                        )
                    )
                    edit = f"{original.name}: replace [{start}, {end}) by {new!r} (version {version})"
                    text = text[:start] + new + text[end:]
                    done += 1
                    found = await client.diagnostics(uri, version)
                    if found is None:
                        report.findings.append(Finding(f"no diagnostics within {WAIT:.0f} s", text, edit))
                        return report
                    want = expected(path, text)
                    report.diagnostics += len(found)
                    if keys(found) != want:
                        report.findings.append(Finding(f"published {keys(found)}\ngpp check {want}", text, edit))
                client.text_document_did_close(types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(uri=uri)))
    finally:
        report.edits = done
        report.seconds = time.perf_counter() - started
        try:
            await asyncio.wait_for(client.shutdown_async(None), 10)
            client.exit(None)
        finally:
            await client.stop()
    return report


def write_findings(report: Report, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for i, f in enumerate(report.findings):
        (out / f"lsp-{i}.gpp").write_text(f.text, encoding="utf-8")
        (out / f"lsp-{i}.txt").write_text(f"{f.edit}\n{f.what}\n", encoding="utf-8")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--edits", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", type=Path, default=ROOT / "fuzz-findings")
    args = parser.parse_args()
    report = asyncio.run(fuzz(args.edits, args.seed))
    rate = report.edits / report.seconds if report.seconds else 0.0
    print(
        f"{report.edits} edits in {report.seconds:.1f} s ({rate:.0f} edits/s), {report.diagnostics} diagnostics "
        f"compared, {len(report.findings)} findings"
    )
    if report.findings:
        write_findings(report, args.out)
        for f in report.findings[:5]:
            print(f"  {f.edit}\n    {f.what}")
        print(f"reproducers in {args.out}")
    return 1 if report.findings else 0


if __name__ == "__main__":
    sys.exit(main())
