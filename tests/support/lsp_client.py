"""A pytest-lsp client for gpp's language server tests: the real server (`python -m gpp lsp`)
over stdio, a client that records every publishDiagnostics with its version, and helpers."""

from __future__ import annotations

import asyncio
import sys
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient
from pygls.protocol import default_converter
from pytest_lsp import ClientServerConfig
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features
from pytest_lsp.client import LanguageClient as TestClient

from gpp.base.diagnostics import Diagnostic
from gpp.check import check_program

SERVER = [sys.executable, "-m", "gpp", "lsp"]


class Published:
    """Every publishDiagnostics a client received, in order."""

    def __init__(self) -> None:
        self.items: list[types.PublishDiagnosticsParams] = []

    def of(self, uri: str) -> list[types.PublishDiagnosticsParams]:
        return [p for p in self.items if p.uri == uri]


PUBLISHED: dict[int, Published] = {}


def make_client() -> LanguageClient:
    client = TestClient(converter_factory=default_converter)
    published = PUBLISHED.setdefault(id(client), Published())

    def record(client: LanguageClient, params: types.PublishDiagnosticsParams) -> None:
        published.items.append(params)
        client.diagnostics[params.uri] = params.diagnostics  # type: ignore[attr-defined]

    features = dict(DEFAULT_CLIENT_FEATURES)
    features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = record
    register_lsp_features(client, features)  # type: ignore[arg-type]
    return client


CONFIG = ClientServerConfig(server_command=SERVER, client_factory=make_client)


def published(client: LanguageClient) -> Published:
    return PUBLISHED[id(client)]


async def diagnostics(client: LanguageClient, uri: str, version: int, timeout: float = 20.0) -> list[types.Diagnostic]:
    """The diagnostics published for `uri` at `version` (waits for them)."""
    record = published(client)
    loop = asyncio.get_running_loop()
    deadline = loop.time() + timeout
    while True:
        for p in reversed(record.of(uri)):
            if p.version == version:
                return list(p.diagnostics)
        if loop.time() > deadline:
            seen = [p.version for p in record.of(uri)]
            raise AssertionError(f"no diagnostics for {uri} version {version} (got versions {seen})")
        await asyncio.sleep(0.005)


def open_doc(client: LanguageClient, path: Path, text: str, version: int = 1) -> str:
    uri = path.as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            types.TextDocumentItem(uri=uri, language_id="golog", version=version, text=text)
        )
    )
    return uri


def change(
    client: LanguageClient, uri: str, version: int, edits: list[tuple[tuple[int, int, int, int] | None, str]]
) -> None:
    """Send a didChange: each edit is ((line, char, end_line, end_char) or None for all, text)."""
    changes: list[types.TextDocumentContentChangeEvent] = []
    for where, text in edits:
        if where is None:
            changes.append(types.TextDocumentContentChangeWholeDocument(text=text))
        else:
            l1, c1, l2, c2 = where
            rng = types.Range(types.Position(l1, c1), types.Position(l2, c2))
            changes.append(types.TextDocumentContentChangePartial(range=rng, text=text))
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(types.VersionedTextDocumentIdentifier(uri=uri, version=version), changes)
    )


def expected(path: Path, text: str | None = None) -> list[tuple[str, tuple[int, int, int, int], str]]:
    """(code, (line, char, end line, end char), first line of the message) of what `gpp check`
    finds in the file `path` (with `text` instead of its content on disk), in LSP positions."""
    result = check_program(path, overrides={path: text} if text is not None else None)
    ident = str(path.resolve())
    return [_key(d) for d in result.diagnostics if d.span.source.identity == ident]


def _key(d: Diagnostic) -> tuple[str, tuple[int, int, int, int], str]:
    (l1, c1), (l2, c2) = d.span.lsp_range()
    return d.code, (l1, c1, l2, c2), d.message.split("\n")[0]


def keys(diags: list[types.Diagnostic]) -> list[tuple[str, tuple[int, int, int, int], str]]:
    return [
        (
            str(d.code),
            (d.range.start.line, d.range.start.character, d.range.end.line, d.range.end.character),
            d.message.split("\n")[0],
        )
        for d in diags
    ]
