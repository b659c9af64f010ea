"""The language server end to end: `python -m gpp lsp` over stdio, driven by pytest-lsp.

One server serves the whole module (its workspace folder is a temporary folder); each test
opens documents of its own. The client profiles of real editors get a server each.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import signal
import socket
import subprocess
import sys
from collections.abc import AsyncIterator, Coroutine
from pathlib import Path

import pytest
import pytest_lsp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lsprotocol import converters, types
from pygls.exceptions import JsonRpcException
from pygls.lsp.client import LanguageClient

import gpp
from bench.genprog import callers_of_a_renamed_action
from gpp.base.source import Source
from gpp.check import CheckResult, check_program
from gpp.syntax.format import format_text
from lsp import features
from tests.support.budget import examples
from tests.support.lsp_client import (
    CONFIG,
    SERVER,
    change,
    diagnostics,
    expected,
    keys,
    make_client,
    open_doc,
    published,
)

ROOT = Path(__file__).resolve().parents[2]

# The async tests share the module's server, so they run in the module's event loop (and in
# order, in one test worker: some use documents earlier ones opened; see --dist in pyproject.toml).
in_module_loop = pytest.mark.asyncio(loop_scope="module")

INIT: dict[str, types.InitializeResult] = {}


@pytest_lsp.fixture(scope="module", config=CONFIG)
@in_module_loop
async def client(lsp_client: LanguageClient, request: pytest.FixtureRequest) -> AsyncIterator[None]:
    folder: Path = request.getfixturevalue("workspace")
    INIT["result"] = await lsp_client.initialize_session(
        types.InitializeParams(
            capabilities=types.ClientCapabilities(),
            workspace_folders=[types.WorkspaceFolder(uri=folder.as_uri(), name="ws")],
        )
    )
    yield
    await lsp_client.shutdown_session()


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("ws")
    (folder / "lib.gpp").write_text("action a() { }\nbool fluent f() { initially: () = true; }\n", encoding="utf-8")
    (folder / "main.gpp").write_text('#include "lib.gpp"\nprocedure main() { a(); f() = false; }\n', encoding="utf-8")
    return folder


AGENT = """\
// a comment with ünïcödé 😀
symbol domain Loc = {kitchen, hall}
Loc fluent at() { initially: () = kitchen; }
string fluent msg() { initially: () = "😀 é"; }
action go(Loc to) { effect: at() = to; }
action unused_act() { }
procedure main() {
    msg() = "😀"; go(kitchn);
    go(hall);
}
procedure main() { }
"""


def codes_page() -> str:
    return (ROOT / "docs" / "codes.md").as_uri()


# ---------------------------------------------------------------- start-up


def test_importing_the_cli_does_not_import_the_language_server() -> None:
    code = "import sys, gpp.cli; print(sorted(m for m in ('pygls', 'lsprotocol', 'lsp') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60)
    assert out.stdout.strip() == "[]"


@in_module_loop
async def test_the_server_announces_utf16_and_incremental_sync(client: LanguageClient) -> None:
    caps = INIT["result"].capabilities
    assert caps.position_encoding == types.PositionEncodingKind.Utf16
    assert isinstance(caps.text_document_sync, types.TextDocumentSyncOptions)
    assert caps.text_document_sync.change == types.TextDocumentSyncKind.Incremental
    assert isinstance(caps.code_action_provider, types.CodeActionOptions)
    assert list(caps.code_action_provider.code_action_kinds or ()) == [types.CodeActionKind.QuickFix]
    assert INIT["result"].server_info is not None and INIT["result"].server_info.name == "gpp"


# ---------------------------------------------------------------- diagnostics


@in_module_loop
async def test_diagnostics_have_exact_ranges_codes_links_and_related_places(
    client: LanguageClient, workspace: Path
) -> None:
    path = workspace / "agent.gpp"
    uri = open_doc(client, path, AGENT)
    found = await diagnostics(client, uri, 1)
    # `kitchn` comes after `"😀"` on its line: 21 UTF-16 units in (20 characters).
    assert found == [
        types.Diagnostic(
            range=types.Range(types.Position(5, 7), types.Position(5, 17)),
            message="action `unused_act` is never used",
            severity=types.DiagnosticSeverity.Warning,
            code="W0101",
            code_description=types.CodeDescription(href=codes_page() + "#w0101"),
            source="gpp",
            tags=(types.DiagnosticTag.Unnecessary,),
        ),
        types.Diagnostic(
            range=types.Range(types.Position(7, 21), types.Position(7, 27)),
            message="unknown name `kitchn`\nhelp: did you mean `kitchen`?",
            severity=types.DiagnosticSeverity.Error,
            code="E0101",
            code_description=types.CodeDescription(href=codes_page() + "#e0101"),
            source="gpp",
        ),
        types.Diagnostic(
            range=types.Range(types.Position(10, 10), types.Position(10, 14)),
            message="`main` is defined twice\nhelp: remove one of the definitions, or rename one of them",
            severity=types.DiagnosticSeverity.Error,
            code="E0301",
            code_description=types.CodeDescription(href=codes_page() + "#e0301"),
            source="gpp",
            related_information=(
                types.DiagnosticRelatedInformation(
                    location=types.Location(uri, types.Range(types.Position(6, 10), types.Position(6, 14))),
                    message="first defined here",
                ),
            ),
        ),
    ]
    assert keys(found) == expected(path, AGENT)
    assert "## W0101" in (ROOT / "docs" / "codes.md").read_text(encoding="utf-8")


@in_module_loop
async def test_incremental_edits_with_crlf_lone_cr_and_astral_characters(
    client: LanguageClient, workspace: Path
) -> None:
    text = (
        "number fluent n() { initially: () = 0; }\r\n"
        'string fluent s() { initially: () = "😀"; }\r'
        'procedure main() { n() = 1; s() = "a";\n'
        "}\n"
    )
    uri = open_doc(client, workspace / "edits.gpp", text)
    assert await diagnostics(client, uri, 1) == []
    # Line 1 ends with a lone `\r`; its `😀` takes UTF-16 units 37 and 38: replace the `"` after
    # it (39..40) with `x"`, and call an unknown `q()` at the start of main (line 2, after `{`);
    # then write `1` over the `0` of line 0 (which ends with `\r\n`).
    change(client, uri, 2, [((1, 39, 1, 40), 'x"'), ((2, 18, 2, 18), " q();")])
    change(client, uri, 3, [((0, 36, 0, 37), "1")])
    final = (
        "number fluent n() { initially: () = 1; }\r\n"
        'string fluent s() { initially: () = "😀x"; }\r'
        'procedure main() { q(); n() = 1; s() = "a";\n'
        "}\n"
    )
    found = await diagnostics(client, uri, 3)
    assert keys(found) == [("E0103", (2, 19, 2, 20), "unknown action or procedure `q`")]
    assert keys(found) == expected(workspace / "edits.gpp", final)


@in_module_loop
async def test_diagnostics_move_and_change_with_the_edits_that_keep_others_as_they_were(
    client: LanguageClient, workspace: Path
) -> None:
    """The server converts a diagnostic it published last time only once: what an edit
    moves, changes or adds is published anew, the rest exactly as before."""
    path = workspace / "kept.gpp"
    text = "procedure main() {\n    p();\n    q();\n}\n"
    uri = open_doc(client, path, text)
    first = await diagnostics(client, uri, 1)
    assert [k[:2] for k in keys(first)] == [("E0103", (1, 4, 1, 5)), ("E0103", (2, 4, 2, 5))]
    change(client, uri, 2, [((2, 0, 2, 0), "\n")])  # q() one line down
    change(client, uri, 3, [((1, 4, 1, 5), "r")])  # p() renamed r()
    third = await diagnostics(client, uri, 3)
    text = "procedure main() {\n    r();\n\n    q();\n}\n"
    assert keys(third) == expected(path, text)
    assert [k[:2] for k in keys(third)] == [("E0103", (1, 4, 1, 5)), ("E0103", (3, 4, 3, 5))]
    assert "`r`" in third[0].message and "`q`" in third[1].message
    change(client, uri, 4, [((4, 1, 4, 1), " ")])  # after the body: nothing moves
    assert await diagnostics(client, uri, 4) == third


@in_module_loop
async def test_a_quick_fix_for_each_diagnostic_with_a_fix(client: LanguageClient, workspace: Path) -> None:
    uri = open_doc(client, workspace / "fix.gpp", "action a() { }\nprocedure main() {\n    a()\n}\n")
    [missing] = await diagnostics(client, uri, 1)
    assert (missing.code, missing.range) == ("E0011", types.Range(types.Position(2, 7), types.Position(2, 7)))
    actions = await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=types.TextDocumentIdentifier(uri),
            range=types.Range(types.Position(2, 0), types.Position(2, 7)),
            context=types.CodeActionContext(diagnostics=[missing]),
        )
    )
    assert actions == (
        types.CodeAction(
            title="insert `;`",
            kind=types.CodeActionKind.QuickFix,
            diagnostics=(missing,),
            is_preferred=True,
            edit=types.WorkspaceEdit(
                changes={uri: (types.TextEdit(types.Range(types.Position(2, 7), types.Position(2, 7)), ";"),)}
            ),
        ),
    )
    # Away from the problem: no fix offered.
    elsewhere = await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=types.TextDocumentIdentifier(uri),
            range=types.Range(types.Position(0, 0), types.Position(0, 3)),
            context=types.CodeActionContext(diagnostics=[]),
        )
    )
    assert elsewhere == ()


@in_module_loop
async def test_an_included_file_is_checked_under_its_program_and_its_buffer_wins(
    client: LanguageClient, workspace: Path
) -> None:
    lib_uri = open_doc(client, workspace / "lib.gpp", (workspace / "lib.gpp").read_text(encoding="utf-8"))
    # Alone, `a` and `f` would be unused (W0101); under main.gpp they are used.
    assert await diagnostics(client, lib_uri, 1) == []
    main_uri = open_doc(client, workspace / "main.gpp", (workspace / "main.gpp").read_text(encoding="utf-8"))
    assert await diagnostics(client, main_uri, 1) == []
    # The unsaved buffer of lib.gpp loses `f`: main.gpp, which includes it, now misses it.
    change(client, lib_uri, 2, [((1, 0, 2, 0), "")])
    await diagnostics(client, lib_uri, 2)
    await _until(lambda: keys(list(client.diagnostics[main_uri])))  # type: ignore[attr-defined]
    assert keys(list(client.diagnostics[main_uri])) == [  # type: ignore[attr-defined]
        ("E0103", (1, 24, 1, 25), "unknown fluent or function `f`")
    ]
    client.text_document_did_close(types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(lib_uri)))
    # Closed: main.gpp reads lib.gpp from the disk again.
    await _until(lambda: not keys(list(client.diagnostics[main_uri])))  # type: ignore[attr-defined]


@in_module_loop
async def test_an_unsaved_untitled_buffer_is_checked(client: LanguageClient) -> None:
    uri = "untitled:Untitled-1"
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            types.TextDocumentItem(uri=uri, language_id="golog", version=1, text="procedure main() { nope(); }\n")
        )
    )
    found = await diagnostics(client, uri, 1)
    assert keys(found) == [("E0103", (0, 19, 0, 23), "unknown action or procedure `nope`")]
    on_main = types.HoverParams(types.TextDocumentIdentifier(uri), types.Position(0, 12))
    hover = await client.text_document_hover_async(on_main)
    assert hover is not None and isinstance(hover.contents, types.MarkupContent)
    assert "procedure main()" in hover.contents.value


async def _until(condition: object, timeout: float = 20.0) -> None:
    assert callable(condition)
    loop = asyncio.get_running_loop()
    deadline = loop.time() + timeout
    while not condition():
        assert loop.time() < deadline, "timed out"
        await asyncio.sleep(0.01)


def fluents(count: int) -> str:
    """`count` lines, one fluent each: a program whose check takes a while."""
    return "".join(f"number fluent v{i}() {{ initially: () = {i}; }}\n" for i in range(count))


async def open_checked(client: LanguageClient, path: Path, text: str) -> str:
    """Open a document and wait for the diagnostics of its first version."""
    uri = open_doc(client, path, text)
    await diagnostics(client, uri, 1)
    return uri


@in_module_loop
async def test_quick_edits_are_coalesced_and_a_stale_analysis_is_never_published(
    client: LanguageClient, workspace: Path
) -> None:
    body = fluents(400)
    uri = await open_checked(client, workspace / "typing.gpp", body + "procedure main() {\n}\n")
    typed = "v1() = v2() + w;"
    for k, ch in enumerate(typed):  # one keystroke each, at the start of the line of `}`
        change(client, uri, k + 2, [((401, k, 401, k), ch)])
    last = len(typed) + 1
    found = await diagnostics(client, uri, last)
    final = body + "procedure main() {\n" + typed + "}\n"
    assert keys(found) == expected(workspace / "typing.gpp", final)
    assert ("E0101", (401, 14, 401, 15), "unknown name `w`") in keys(found)
    versions = [p.version for p in published(client).of(uri)]
    assert versions == sorted(versions) and len(set(versions)) == len(versions)
    assert versions[-1] == last
    assert len(versions) < len(typed)  # coalesced: not one analysis per keystroke


@in_module_loop
async def test_completion_right_after_a_keystroke_does_not_wait_for_the_check(
    client: LanguageClient, workspace: Path
) -> None:
    # 5,000 fluents: the check of the new version takes many times what answering a completion
    # does, so that the answer comes first on a loaded machine too.
    text = fluents(5000) + "procedure main() {\n    x\n}\n"
    path = workspace / "keystroke.gpp"
    uri = await open_checked(client, path, text)
    change(client, uri, 2, [((5001, 4, 5001, 5), "v99")])  # `x` becomes `v99`, as typed
    got = await client.text_document_completion_async(
        types.CompletionParams(types.TextDocumentIdentifier(uri), types.Position(5001, 7))
    )
    # Answered from the check of version 1 while version 2's runs: its diagnostics are not out.
    assert 2 not in [p.version for p in published(client).of(uri)]
    assert isinstance(got, types.CompletionList) and got.is_incomplete
    # The names holding `v`, `9`, `9` in order, as a check of the new text has them.
    now = text.replace("    x\n", "    v99\n")
    resolved = path.resolve()
    want = features.completion_list(
        check_program(resolved, overrides={resolved: now}), resolved, now.index("v99\n") + 3
    )
    assert [i.label for i in got.items] == [i.label for i in want.items]
    assert {"v99", "v199", "v989", "v909"} <= {i.label for i in got.items} and "v98" not in {i.label for i in got.items}
    await diagnostics(client, uri, 2)


@in_module_loop
async def test_hover_and_definition_right_after_an_edit_answer_from_the_last_check(
    client: LanguageClient, workspace: Path
) -> None:
    # 8,000 errors with a did-you-mean: a check that takes a while.
    head = "symbol domain Place = {kitchen, hall}\naction drive(Place to) { }\n"
    text = head + callers_of_a_renamed_action(8_000) + "procedure main() {\n    drive(hall);\n}\n"
    line = text.count("\n") - 2  # of `drive(hall);`

    def span(line: int, start: int, end: int) -> dict[str, dict[str, int]]:
        return {"start": {"line": line, "character": start}, "end": {"line": line, "character": end}}

    uri = await open_checked(client, workspace / "long_check.gpp", text)
    document = types.TextDocumentIdentifier(uri)

    async def hover_and_definition(at: types.Position) -> tuple[object, object, list[int]]:
        hover = client.text_document_hover_async(types.HoverParams(document, at))
        definition = client.text_document_definition_async(types.DefinitionParams(document, at))
        found = await asyncio.gather(hover, definition)
        return plain(found[0]), plain(found[1]), [p.version for p in published(client).of(uri)]

    # A line inserted at the top: everything below it moved down by one.
    change(client, uri, 2, [((0, 0, 0, 0), "// moved\n")])
    hover, definition, versions = await hover_and_definition(types.Position(line + 1, 5))
    assert 2 not in versions  # answered while version 2 was being checked
    assert hover == {
        "contents": {"kind": "markdown", "value": "```gpp\naction drive(Place to)\n```"},
        "range": span(line + 1, 4, 9),
    }
    assert definition == [{"uri": uri, "range": span(2, 7, 12)}]
    await diagnostics(client, uri, 2)
    # The check of version 2 answers the same.
    assert (await hover_and_definition(types.Position(line + 1, 5)))[:2] == (hover, definition)

    # Where the text changed since the last check, it cannot answer: the new check does.
    change(client, uri, 3, [((line + 1, 10, line + 1, 14), "kitchen")])
    hover, definition, versions = await hover_and_definition(types.Position(line + 1, 12))
    assert 3 in versions
    assert definition == [{"uri": uri, "range": span(1, 23, 30)}]  # `kitchen` in `Place`
    client.text_document_did_close(types.DidCloseTextDocumentParams(document))


# ---------------------------------------------------------------- other ways to start it


async def _profile_session(client: LanguageClient, profile: str, folder: Path) -> None:
    """Initialize as the editor `profile` does, and see a diagnostic at a UTF-16 position."""
    result = await client.initialize_session(  # type: ignore[attr-defined]
        types.InitializeParams(capabilities=pytest_lsp.client_capabilities(profile))
    )
    # Neovim offers UTF-8 first; gpp answers in UTF-16, which every client supports.
    assert result.capabilities.position_encoding == types.PositionEncodingKind.Utf16
    text = 'string fluent s() { initially: () = ""; }\nprocedure main() {\n    s() = "é😀"\n}\n'
    uri = open_doc(client, folder / f"{profile}.gpp", text)
    found = await diagnostics(client, uri, 1)
    # After `"é😀"`: 15 UTF-16 units (13 characters, 17 UTF-8 bytes).
    assert keys(found) == [("E0011", (2, 15, 2, 15), "expected `;` after this statement")]
    await client.shutdown_session()  # type: ignore[attr-defined]


@pytest.mark.slow
@in_module_loop
async def test_neovim_over_stdio(tmp_path: Path) -> None:
    c = make_client()
    await c.start_io(*SERVER)  # type: ignore[attr-defined]
    await _profile_session(c, "neovim", tmp_path)


@pytest.mark.slow
@in_module_loop
async def test_the_timeline_names_each_round_and_its_steps(tmp_path: Path) -> None:
    timeline = tmp_path / "timeline.txt"
    c = make_client()
    await c.start_io(*SERVER, env={**os.environ, "GPP_LSP_TIMING": str(timeline)})  # type: ignore[attr-defined]
    try:
        await c.initialize_session(types.InitializeParams(capabilities=types.ClientCapabilities()))  # type: ignore[attr-defined]
        path = tmp_path / "t.gpp"
        uri = open_doc(c, path, "procedure main() { nothing(); }\n")
        found = [await diagnostics(c, uri, 1)]
        for version in range(2, 35):  # a burst: each edit as soon as the last one's diagnostics came
            change(
                c,
                uri,
                version,
                [((0, 19, 0, 26 if version % 2 == 0 else 25), "nothin" if version % 2 == 0 else "nothing")],
            )
            found.append(await diagnostics(c, uri, version))
        for _ in range(200):  # the typing pauses after 34 rounds: their garbage is collected a second later
            if "garbage collected" in timeline.read_text(encoding="utf-8"):
                break
            await asyncio.sleep(0.05)
    finally:
        await c.shutdown_session()  # type: ignore[attr-defined]
    assert [len(f) for f in found] == [1] * 34
    lines = timeline.read_text(encoding="utf-8").splitlines()
    names = ["queue", "wait", "pause", "check", "free", "back", "convert", "publish"]
    steps = " ".join(rf"{name} \d+\.\d" for name in names)
    rounds = [line for line in lines if not line.startswith("garbage collected, ")]
    assert len(rounds) == 34, lines
    for version, line in enumerate(rounds, 1):
        assert re.fullmatch(rf"t\.gpp v{version} \(1 diagnostics\): {steps} = \d+\.\d ms", line), line
    # Nothing collected during the burst (what each round made is frozen out of the collector's
    # way instead), once when the typing paused.
    assert lines[:-1] == rounds, lines
    assert re.fullmatch(
        r"garbage collected, the typing paused \(\d+ objects freed\): collect \d+\.\d = \d+\.\d ms", lines[-1]
    ), lines


@pytest.mark.slow
def test_the_server_reads_stdin_from_a_file_too(tmp_path: Path) -> None:
    """stdin from a regular file (no pipe for the event loop to watch): pygls' own reader."""

    def message(payload: dict[str, object]) -> bytes:
        body = json.dumps({"jsonrpc": "2.0", **payload}).encode()
        return b"Content-Length: %d\r\n\r\n%s" % (len(body), body)

    requests = tmp_path / "requests"
    requests.write_bytes(
        message({"id": 1, "method": "initialize", "params": {"capabilities": {}}})
        + message({"id": 2, "method": "shutdown"})
        + message({"method": "exit"})
    )
    with requests.open("rb") as stdin:
        out = subprocess.run(SERVER, stdin=stdin, capture_output=True, timeout=60)
    assert out.returncode == 0, out.stderr
    answers = [json.loads(part.split(b"\r\n\r\n", 1)[1]) for part in out.stdout.split(b"Content-Length")[1:]]
    assert [(a["id"], sorted(a)) for a in answers] == [(k, ["id", "jsonrpc", "result"]) for k in (1, 2)]
    assert answers[0]["result"]["serverInfo"] == {"name": "gpp", "version": gpp.__version__}


@pytest.mark.slow
@in_module_loop
async def test_visual_studio_code_over_tcp_on_loopback(tmp_path: Path) -> None:
    bad = subprocess.run([*SERVER, "--tcp", "0.0.0.0:2087"], capture_output=True, text=True, timeout=60)
    assert (bad.returncode, bad.stderr) == (
        2,
        "error: --tcp listens on loopback addresses only (127.0.0.1, ::1, localhost), not `0.0.0.0`\n",
    )
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = subprocess.Popen([*SERVER, "--tcp", f"127.0.0.1:{port}"], stderr=subprocess.DEVNULL)
    try:
        c = make_client()
        loop = asyncio.get_running_loop()
        deadline = loop.time() + 30
        while True:  # until the server listens (a probe connection would be its one client)
            try:
                await c.start_tcp("127.0.0.1", port)  # type: ignore[attr-defined]
                break
            except OSError:
                assert loop.time() < deadline, "the server does not listen"
                await asyncio.sleep(0.05)
        await _profile_session(c, "visual_studio_code", tmp_path)
    finally:
        server.terminate()  # SIGTERM ends `gpp lsp` at once
        try:
            assert server.wait(timeout=10) == -signal.SIGTERM
        finally:
            if server.poll() is None:
                server.kill()
                server.wait()


def test_the_codes_page_is_generated_from_the_registry() -> None:
    from lsp.codes_doc import codes_markdown

    page = (ROOT / "docs" / "codes.md").read_text(encoding="utf-8")
    assert page == codes_markdown(), "docs/codes.md is out of date: regenerate it with `python -m lsp.codes_doc`"


# ---------------------------------------------------------------- the features, wired


FEATURES = """\
symbol domain Loc = {kitchen, hall}
// Where the robot is.
Loc fluent at() { initially: () = kitchen; }
action go(Loc to) { effect: at() = to; }
procedure main() {
    /* é😀 */ go(hall);
    go(kitchen);
}
"""
# `go` in `go(hall)`: after `    /* é😀 */ ` (13 characters, 14 UTF-16 units).
GO_LINE, GO_CHAR = 5, 14
GO_OFFSET = FEATURES.index("go(hall)")


def plain(value: object) -> object:
    """An LSP value as JSON data (what the client received and what the function returned
    compare equal whatever sequences they hold)."""
    return json.loads(json.dumps(converters.get_converter().unstructure(value)))


def direct(workspace: Path) -> tuple[CheckResult, Path]:
    path = (workspace / "features.gpp").resolve()
    return check_program(path, overrides={path: FEATURES}), path


async def features_doc(client: LanguageClient, workspace: Path) -> str:
    uri = (workspace / "features.gpp").as_uri()
    if uri not in {p.uri for p in published(client).items}:
        open_doc(client, workspace / "features.gpp", FEATURES)
        assert await diagnostics(client, uri, 1) == []
    return uri


def at_go(uri: str) -> tuple[types.TextDocumentIdentifier, types.Position]:
    return types.TextDocumentIdentifier(uri), types.Position(GO_LINE, GO_CHAR)


def go_range(line: int, char: int) -> dict[str, dict[str, int]]:
    return {"start": {"line": line, "character": char}, "end": {"line": line, "character": char + 2}}


@in_module_loop
async def test_hover(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    got = await client.text_document_hover_async(types.HoverParams(*at_go(uri)))
    result, path = direct(workspace)
    assert plain(got) == plain(features.hover(result, path, GO_OFFSET))
    assert got is not None and isinstance(got.contents, types.MarkupContent)
    assert got.contents.value == "```gpp\naction go(Loc to)\n```"
    assert plain(got.range) == go_range(GO_LINE, GO_CHAR)


@in_module_loop
async def test_definition(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    got = await client.text_document_definition_async(types.DefinitionParams(*at_go(uri)))
    assert plain(got) == [{"uri": uri, "range": go_range(3, 7)}]


@in_module_loop
async def test_references_and_highlight(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    doc, pos = at_go(uri)
    refs = await client.text_document_references_async(
        types.ReferenceParams(context=types.ReferenceContext(include_declaration=True), text_document=doc, position=pos)
    )
    assert plain(refs) == [{"uri": uri, "range": go_range(*at)} for at in ((3, 7), (GO_LINE, GO_CHAR), (6, 4))]
    uses = await client.text_document_references_async(
        types.ReferenceParams(
            context=types.ReferenceContext(include_declaration=False), text_document=doc, position=pos
        )
    )
    result, path = direct(workspace)
    assert plain(uses) == plain(features.references(result, path, GO_OFFSET, False))
    highlights = await client.text_document_document_highlight_async(
        types.DocumentHighlightParams(text_document=doc, position=pos)
    )
    assert [h["range"] for h in plain(highlights)] == [r["range"] for r in plain(refs)]  # type: ignore[union-attr,index]


@in_module_loop
async def test_rename(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    doc, pos = at_go(uri)
    prepared = await client.text_document_prepare_rename_async(
        types.PrepareRenameParams(text_document=doc, position=pos)
    )
    assert plain(prepared) == {"range": go_range(GO_LINE, GO_CHAR), "placeholder": "go"}
    edit = await client.text_document_rename_async(types.RenameParams(text_document=doc, position=pos, new_name="move"))
    assert plain(edit) == {
        "changes": {uri: [{"range": go_range(*at), "newText": "move"} for at in ((3, 7), (GO_LINE, GO_CHAR), (6, 4))]}
    }
    # A keyword cannot be renamed: the client is told why.
    with pytest.raises(JsonRpcException, match="`procedure` is a keyword of golog\\+\\+ and cannot be renamed"):
        await client.text_document_prepare_rename_async(
            types.PrepareRenameParams(text_document=doc, position=types.Position(4, 2))
        )


@in_module_loop
async def test_completion(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    got = await client.text_document_completion_async(
        types.CompletionParams(types.TextDocumentIdentifier(uri), types.Position(6, 5))
    )
    result, path = direct(workspace)
    offset = FEATURES.index("go(kitchen)") + 1
    assert isinstance(got, types.CompletionList)
    assert plain(got) == plain(features.completion_list(result, path, offset))
    # After `g`: the items with a `g` in their name, of all those that fit here; the editor is
    # told that the list is incomplete, to ask again as the word changes.
    everything = features.completion(result, path, offset)
    assert {"at", "go", "main", "while"} <= {i.label for i in everything}
    assert [i.label for i in got.items] == [i.label for i in everything if "g" in i.label.casefold()]
    assert "go" in {i.label for i in got.items} and got.is_incomplete


@in_module_loop
async def test_signature_help(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    got = await client.text_document_signature_help_async(
        types.SignatureHelpParams(types.TextDocumentIdentifier(uri), types.Position(GO_LINE, GO_CHAR + 3))
    )
    assert got is not None
    assert [s.label for s in got.signatures] == ["action go(Loc to)"]
    assert got.active_parameter == 0


@in_module_loop
async def test_document_and_workspace_symbols(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    symbols = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(types.TextDocumentIdentifier(uri))
    )
    result, path = direct(workspace)
    assert plain(symbols) == plain(features.document_symbols(result, path))
    assert [s.name for s in symbols or ()] == ["Loc", "at", "go", "main"]
    # The open documents of the workspace: `go` is declared in another one too (agent.gpp, which
    # an earlier test of this module may have opened, declares it as well).
    other = await open_checked(client, workspace / "symbols_too.gpp", AGENT)
    found = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="go"))
    agent = (workspace / "agent.gpp").as_uri()
    got = sorted((s.name, s.location.uri) for s in found or ())  # type: ignore[union-attr]
    assert got in ([("go", agent), ("go", uri), ("go", other)], [("go", uri), ("go", other)])


@in_module_loop
async def test_semantic_tokens(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    legend = INIT["result"].capabilities.semantic_tokens_provider
    assert isinstance(legend, types.SemanticTokensOptions)
    assert plain(legend.legend) == plain(features.SEMANTIC_TOKENS_LEGEND)
    got = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(types.TextDocumentIdentifier(uri))
    )
    result, path = direct(workspace)
    assert got is not None and list(got.data) == features.semantic_tokens(result, path)
    assert list(got.data[:5]) == [0, 0, 6, legend.legend.token_types.index("keyword"), 0]


@in_module_loop
async def test_folding_ranges_and_inlay_hints(client: LanguageClient, workspace: Path) -> None:
    uri = await features_doc(client, workspace)
    doc = types.TextDocumentIdentifier(uri)
    folds = await client.text_document_folding_range_async(types.FoldingRangeParams(doc))
    assert [(f.start_line, f.end_line) for f in folds or ()] == [(4, 6)]
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(doc, types.Range(types.Position(5, 0), types.Position(6, 0)))
    )
    # After `go(` on line 5: a parameter hint `to:` (only the first call is in the range).
    assert [(h.position.line, h.position.character, h.label) for h in hints or ()] == [(5, 17, "to:")]


@in_module_loop
async def test_formatting(client: LanguageClient, workspace: Path) -> None:
    messy = "procedure   main( ) {\r\n  /* 😀 */ test( true ) ;}\n"
    uri = open_doc(client, workspace / "messy.gpp", messy)
    await diagnostics(client, uri, 1)
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(types.TextDocumentIdentifier(uri), types.FormattingOptions(4, True))
    )
    assert plain(edits) == [
        {
            "range": {"start": {"line": 0, "character": 0}, "end": {"line": 2, "character": 0}},
            "newText": format_text(messy),
        }
    ]
    broken = open_doc(client, workspace / "broken.gpp", "procedure main( {\n")
    none = await client.text_document_formatting_async(
        types.DocumentFormattingParams(types.TextDocumentIdentifier(broken), types.FormattingOptions(4, True))
    )
    assert none == ()


# ---------------------------------------------------------------- robustness


CORPUS = [p.read_text(encoding="utf-8") for p in sorted((ROOT / "examples").glob("*.gpp"))]
# Some text editors produce and no program has: other line ends, characters beyond U+FFFF.
CORPUS.append('\r\nstring fluent s() { initially: () = "😀\r"; }\r/* é */ procedure main() { s() = "x"; }\u2028\x0c')


@st.composite
def edits(draw: st.DrawFn) -> tuple[str, list[tuple[float, float, str]]]:
    """A starting text and edits: (where, how much of the text after it to delete, what to
    insert), as fractions of the text at the time of the edit."""
    base = draw(st.sampled_from(CORPUS))
    a = draw(st.integers(0, len(base)))
    start_text = base[a : a + draw(st.integers(0, 1500))]
    steps: list[tuple[float, float, str]] = []
    for _ in range(draw(st.integers(1, 4))):
        where = draw(st.floats(0, 1))
        delete = draw(st.sampled_from([0.0, 0.0, 0.01, 0.05, 0.3]))
        kind = draw(st.sampled_from(["paste", "type", "delete"]))
        if kind == "paste":
            other = draw(st.sampled_from(CORPUS))
            i = draw(st.integers(0, len(other)))
            insert = other[i : i + draw(st.integers(1, 300))]
        elif kind == "type":
            insert = draw(st.text(alphabet='(){};,.=!<>&|+- \n"abcxyz019é😀\r', max_size=8))
        else:
            insert = ""
        steps.append((where, delete, insert))
    return start_text, steps


@in_module_loop
async def test_random_edits_never_break_the_server(client: LanguageClient, workspace: Path) -> None:
    """Random edit sequences (slices of other programs pasted in, text typed, text deleted):
    every request answers without an error response and without an internal error logged, and
    the final diagnostics are what `gpp check` says of the final text."""
    loop = asyncio.get_running_loop()
    counter = iter(range(10**6))
    path = workspace / "random.gpp"

    def run(coro: Coroutine[object, object, None]) -> None:
        asyncio.run_coroutine_threadsafe(coro, loop).result(timeout=120)

    @settings(
        max_examples=examples(25),
        deadline=None,
        derandomize=True,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )
    @given(edits())
    def example(case: tuple[str, list[tuple[float, float, str]]]) -> None:
        run(_replay(client, path, next(counter), *case))

    await asyncio.to_thread(example)
    errors = [m.message for m in client.log_messages if m.type == types.MessageType.Error]
    assert errors == []


async def _replay(client: LanguageClient, path: Path, n: int, text: str, steps: list[tuple[float, float, str]]) -> None:
    uri = path.with_name(f"random{n}.gpp").as_uri()
    open_doc(client, Path(uri.removeprefix("file://")), text)
    version = 1
    for where, delete, insert in steps:
        source = Source(text)
        start = round(where * len(text))
        end = min(len(text), start + round(delete * (len(text) - start)))
        (l1, c1), (l2, c2) = source.lsp_position(start), source.lsp_position(end)
        # A position inside `\r\n` or a surrogate pair is not one an editor sends.
        start, end = source.lsp_offset(l1, c1), source.lsp_offset(l2, c2)
        (l1, c1), (l2, c2) = source.lsp_position(start), source.lsp_position(end)
        text = text[:start] + insert + text[end:]
        version += 1
        change(client, uri, version, [((l1, c1, l2, c2), insert)])
        await _ask_everything(client, uri, Source(text), start + len(insert))
    found = await diagnostics(client, uri, version)
    assert keys(found) == expected(Path(uri.removeprefix("file://")), text)
    client.text_document_did_close(types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(uri)))


async def _ask_everything(client: LanguageClient, uri: str, source: Source, offset: int) -> None:
    doc = types.TextDocumentIdentifier(uri)
    line, char = source.lsp_position(min(offset, len(source.text)))
    pos = types.Position(line, char)
    end = types.Position(*source.lsp_position(len(source.text)))
    whole = types.Range(types.Position(0, 0), end)
    await asyncio.gather(
        client.text_document_completion_async(types.CompletionParams(doc, pos)),
        client.text_document_hover_async(types.HoverParams(doc, pos)),
        client.text_document_definition_async(types.DefinitionParams(doc, pos)),
        client.text_document_references_async(
            types.ReferenceParams(context=types.ReferenceContext(True), text_document=doc, position=pos)
        ),
        client.text_document_document_highlight_async(types.DocumentHighlightParams(text_document=doc, position=pos)),
        client.text_document_signature_help_async(types.SignatureHelpParams(doc, pos)),
        client.text_document_document_symbol_async(types.DocumentSymbolParams(doc)),
        client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(doc)),
        client.text_document_folding_range_async(types.FoldingRangeParams(doc)),
        client.text_document_inlay_hint_async(types.InlayHintParams(doc, whole)),
        client.text_document_code_action_async(
            types.CodeActionParams(doc, whole, types.CodeActionContext(diagnostics=[]))
        ),
        client.text_document_formatting_async(types.DocumentFormattingParams(doc, types.FormattingOptions(4, True))),
    )


def test_an_installed_gpp_links_to_a_page_in_the_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from lsp import codes_doc

    monkeypatch.setattr(codes_doc, "_CHECKOUT_PAGE", tmp_path / "no-checkout" / "codes.md")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    codes_doc._page.cache_clear()
    try:
        page = tmp_path / "cache" / "gpp" / f"codes-{gpp.__version__}.md"
        assert codes_doc.code_url("E0011") == page.as_uri() + "#e0011"
        assert page.read_text(encoding="utf-8") == codes_doc.codes_markdown()
        assert codes_doc.code_url("E9999") is None
    finally:
        codes_doc._page.cache_clear()
