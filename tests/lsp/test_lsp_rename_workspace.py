"""Rename over a whole workspace, through the real server (`python -m gpp lsp` over stdio): a
declaration of a file that two programs of two projects include is renamed in both, also in
the files no editor has open, and a refused rename is an error answer with its reason, never a
traceback on the server's stderr or in its log.

Each test gets a server of its own, so that what it wrote on stderr is its own.
"""

from __future__ import annotations

import re
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pygls.lsp.client import LanguageClient

from gpp.base.source import Source
from tests.support.cli import run
from tests.support.lsp_client import CONFIG, diagnostics, open_doc

# The user's layout: src/guiding.gpp is included by src/sim_reception.gpp (beside it, in the
# workspace's own project) and by robot/reception.gpp (through the include folders of the
# robot's project).
GUIDING = """\
symbol domain Room = {lobby, room1, room2}
action guide_to(Room r) { }
number fluent visits() { initially: () = 0; }
procedure escort(Room r) {
    // escort: say hello first
    guide_to(r);
    visits() = visits() + 1;
}
"""
SIM_RECEPTION = """\
#include "guiding.gpp"
procedure main() {
    escort(room1);
    escort(room2);
}
"""
RECEPTION = """\
#include "guiding.gpp"
procedure main() {
    escort(lobby);
    guide_to(room1);
}
"""


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    ws = tmp_path / "ws"
    (ws / "src").mkdir(parents=True)
    (ws / "robot").mkdir()
    (ws / "gpp.toml").write_text('paths = ["src"]\n', encoding="utf-8")
    (ws / "src" / "guiding.gpp").write_text(GUIDING, encoding="utf-8")
    (ws / "src" / "sim_reception.gpp").write_text(SIM_RECEPTION, encoding="utf-8")
    (ws / "robot" / "gpp.toml").write_text('include = ["../src"]\n', encoding="utf-8")
    (ws / "robot" / "reception.gpp").write_text(RECEPTION, encoding="utf-8")
    return ws


@pytest_lsp.fixture(config=CONFIG)
async def client(lsp_client: LanguageClient, workspace: Path) -> AsyncIterator[None]:
    await lsp_client.initialize_session(
        types.InitializeParams(
            capabilities=types.ClientCapabilities(),
            workspace_folders=[types.WorkspaceFolder(uri=workspace.as_uri(), name="ws")],
        )
    )
    yield
    await lsp_client.shutdown_session()


def position(text: str, needle: str) -> types.Position:
    line, character = Source(text).lsp_position(text.index(needle))
    return types.Position(line=line, character=character)


def apply(edit: types.WorkspaceEdit) -> None:
    """Write the edit's changes to the files, as an editor saves them."""
    for uri, edits in (edit.changes or {}).items():
        path = Path(uri.removeprefix("file://"))
        text = path.read_text(encoding="utf-8")
        source = Source(text)
        spans = [
            (
                source.lsp_offset(e.range.start.line, e.range.start.character),
                source.lsp_offset(e.range.end.line, e.range.end.character),
                e.new_text,
            )
            for e in edits
        ]
        for start, end, new in sorted(spans, reverse=True):
            text = text[:start] + new + text[end:]
        path.write_text(text, encoding="utf-8")


async def test_a_rename_changes_every_program_of_the_workspace_that_includes_the_file(
    client: LanguageClient, workspace: Path
) -> None:
    guiding = workspace / "src" / "guiding.gpp"
    uri = open_doc(client, guiding, GUIDING)
    assert await diagnostics(client, uri, 1) == []
    doc = types.TextDocumentIdentifier(uri=uri)
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=doc, position=position(GUIDING, "escort"), new_name="accompany")
    )
    assert edit is not None
    changed = {
        Path(u.removeprefix("file://")).relative_to(workspace).as_posix(): len(e)
        for u, e in (edit.changes or {}).items()
    }
    assert changed == {"src/guiding.gpp": 1, "src/sim_reception.gpp": 2, "robot/reception.gpp": 1}
    apply(edit)
    # Saved: both programs are clean, as `gpp check` sees them in their projects.
    for project in (workspace, workspace / "robot"):
        checked = run("check", cwd=project)
        assert (checked.returncode, checked.stderr) == (0, ""), checked.stdout
    assert "accompany(room2)" in (workspace / "src" / "sim_reception.gpp").read_text(encoding="utf-8")
    # The log has nothing but one-line messages: no traceback.
    assert not [m.message for m in client.log_messages if "\n" in m.message]  # type: ignore[attr-defined]


async def test_a_rename_from_a_program_reaches_the_other_program_too(client: LanguageClient, workspace: Path) -> None:
    reception = workspace / "robot" / "reception.gpp"
    uri = open_doc(client, reception, RECEPTION)
    assert await diagnostics(client, uri, 1) == []
    edit = await client.text_document_rename_async(
        types.RenameParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            position=position(RECEPTION, "guide_to"),
            new_name="lead_to",
        )
    )
    assert edit is not None
    changed = sorted(Path(u.removeprefix("file://")).relative_to(workspace).as_posix() for u in edit.changes or {})
    assert changed == ["robot/reception.gpp", "src/guiding.gpp"]  # sim_reception.gpp does not call it
    apply(edit)
    assert run("check", cwd=workspace / "robot").returncode == 0
    assert run("check", cwd=workspace).returncode == 0


async def test_a_rename_that_would_clash_in_another_program_is_refused(client: LanguageClient, workspace: Path) -> None:
    # `main` of sim_reception.gpp is not visible from robot's program, but renaming `escort`
    # to `main` would clash there (and in robot's own program).
    (workspace / "src" / "sim_reception.gpp").write_text(
        SIM_RECEPTION + "procedure wait_here() { }\n", encoding="utf-8"
    )
    guiding = workspace / "src" / "guiding.gpp"
    uri = open_doc(client, guiding, GUIDING)
    await diagnostics(client, uri, 1)
    with pytest.raises(JsonRpcException, match="`wait_here` is already declared as a procedure"):
        await client.text_document_rename_async(
            types.RenameParams(
                text_document=types.TextDocumentIdentifier(uri=uri),
                position=position(GUIDING, "escort"),
                new_name="wait_here",
            )
        )


async def test_a_rename_is_refused_when_another_program_has_a_syntax_error(
    client: LanguageClient, workspace: Path
) -> None:
    (workspace / "src" / "sim_reception.gpp").write_text(SIM_RECEPTION.replace("room2);", "room2)"), encoding="utf-8")
    guiding = workspace / "src" / "guiding.gpp"
    uri = open_doc(client, guiding, GUIDING)
    await diagnostics(client, uri, 1)
    with pytest.raises(
        JsonRpcException, match=re.escape("`sim_reception.gpp` also includes `guiding.gpp` and has a syntax error")
    ):
        await client.text_document_rename_async(
            types.RenameParams(
                text_document=types.TextDocumentIdentifier(uri=uri),
                position=position(GUIDING, "escort"),
                new_name="accompany",
            )
        )
    assert "escort(room1)" in (workspace / "src" / "sim_reception.gpp").read_text(encoding="utf-8")


@pytest.mark.parametrize(
    ("needle", "reason"),
    [
        ("escort: say", "there is no name to rename here"),
        ("procedure escort", "`procedure` is a keyword of golog++ and cannot be renamed"),
        ("1;", "there is no name to rename here"),
        ("number fluent", "`number` is a keyword of golog++ and cannot be renamed"),
    ],
    ids=["comment", "keyword", "literal", "builtin type"],
)
async def test_a_refused_rename_is_an_error_answer_and_one_line_in_the_log(
    client: LanguageClient, workspace: Path, capfd: pytest.CaptureFixture[str], needle: str, reason: str
) -> None:
    guiding = workspace / "src" / "guiding.gpp"
    uri = open_doc(client, guiding, GUIDING)
    await diagnostics(client, uri, 1)
    doc = types.TextDocumentIdentifier(uri=uri)
    where = position(GUIDING, needle)
    with pytest.raises(JsonRpcException, match=re.escape(reason)):
        await client.text_document_prepare_rename_async(types.PrepareRenameParams(text_document=doc, position=where))
    with pytest.raises(JsonRpcException, match=re.escape(reason)):
        await client.text_document_rename_async(types.RenameParams(text_document=doc, position=where, new_name="fine"))
    # The server is still well: it renames what can be renamed.
    assert await client.text_document_prepare_rename_async(
        types.PrepareRenameParams(text_document=doc, position=position(GUIDING, "escort"))
    )
    logged = [m.message for m in client.log_messages]  # type: ignore[attr-defined]
    assert [m for m in logged if reason in m] and all("\n" not in m for m in logged), logged
    assert "Traceback" not in capfd.readouterr().err
