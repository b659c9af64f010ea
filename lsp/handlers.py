"""The requests that read a checked program: each waits for the check of the document's current
version (GppServer.result_for), converts the LSP position to an offset in that version's text,
and runs the pure function of lsp.features (or the formatter) on the request thread. Hover and
go-to-definition do not wait while a new check runs: they are answered from the last one
(`at_last_check`), as completion is.

Every handler is guarded: an exception is logged to the client and answered with an empty
result. A refused rename is the one error response (LSP `RequestFailed`, with the reason).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

from lsprotocol import types

from gpp.base.source import Source, Span
from gpp.check import CheckResult
from gpp.check.session import IncompleteSearch
from lsp import features
from lsp.features.earlier import EarlierText, Unplaced
from lsp.ranges import lsp_range
from lsp.server import GppServer, RequestFailed, guarded, uri_to_path

R = TypeVar("R")
# Programs of the workspace that `workspace/symbol` checks at most (open documents always).
_MAX_SYMBOL_PROGRAMS = 200


def source_of(result: CheckResult, path: Path, server: GppServer) -> Source:
    parsed = result.loaded.file(path)
    if parsed is not None:
        return parsed.source
    doc = server.session.document(path)
    return Source(doc.text if doc else "")


async def at(
    ls: GppServer, uri: str, position: types.Position, fn: Callable[[CheckResult, Path, int], R], default: R
) -> R:
    """Run `fn(result, path, offset)` for a position in a document on the request thread."""
    found = await ls.result_for(uri)
    if found is None:
        return default
    result, path = found
    offset = source_of(result, path, ls).lsp_offset(position.line, position.character)
    return await ls.on_request_thread(lambda: fn(result, path, offset))


# Places a range of a file (by URI) of an earlier check in the file's current text.
Place = Callable[[str, types.Range], types.Range]


async def at_last_check(
    ls: GppServer,
    uri: str,
    where: types.Position,
    fn: Callable[[CheckResult, Path, int], R],
    default: R,
    relocate: Callable[[R, Place], R],
) -> R:
    """`at`, but while the document's current version is being checked, answered at once from
    its last check: the position mapped into the text that was checked, the answer's ranges
    (`relocate`) back into the current texts. When either lies in text edited since, the last
    check cannot tell: as `at`, it waits for the current one."""
    path = uri_to_path(uri)
    earlier = ls.earlier_check(path)
    if earlier is not None:
        result, doc = earlier
        offset = EarlierText.of(source_of(result, path, ls), doc.source).offset_checked(where)
        if offset is not None:
            checked_offset = offset
            answer = await ls.on_request_thread(lambda: fn(result, path, checked_offset))
            try:
                return relocate(answer, placer(ls, result))
            except Unplaced:
                pass
    return await at(ls, uri, where, fn, default)


def placer(ls: GppServer, result: CheckResult) -> Place:
    """Where the ranges of the files `result` checked are in the files' current texts (the open
    documents edited since; the others are as checked)."""
    texts: dict[Path, EarlierText | None] = {}

    def place(uri: str, r: types.Range) -> types.Range:
        path = uri_to_path(uri)
        if path not in texts:
            doc, parsed = ls.session.document(path), result.loaded.file(path)
            if doc is None or parsed is None or parsed.source.text == doc.text:
                texts[path] = None  # as checked
            else:
                texts[path] = EarlierText.of(parsed.source, doc.source)
        text = texts[path]
        return r if text is None else text.range_now(r)

    return place


def _hover_now(found: types.Hover | None, place: Place, uri: str) -> types.Hover | None:
    if found is None or found.range is None:
        return found
    return types.Hover(contents=found.contents, range=place(uri, found.range))


def _locations_now(found: list[types.Location], place: Place) -> list[types.Location]:
    return [types.Location(uri=loc.uri, range=place(loc.uri, loc.range)) for loc in found]


async def whole(ls: GppServer, uri: str, fn: Callable[[CheckResult, Path], R], default: R) -> R:
    found = await ls.result_for(uri)
    if found is None:
        return default
    result, path = found
    return await ls.on_request_thread(lambda: fn(result, path))


async def ranged(
    ls: GppServer, uri: str, where: types.Range, fn: Callable[[CheckResult, Path, int, int], R], default: R
) -> R:
    """Run `fn(result, path, start, end)` for a range of a document on the request thread."""
    found = await ls.result_for(uri)
    if found is None:
        return default
    result, path = found
    source = source_of(result, path, ls)
    start = source.lsp_offset(where.start.line, where.start.character)
    end = source.lsp_offset(where.end.line, where.end.character)
    return await ls.on_request_thread(lambda: fn(result, path, start, end))


def refusing(fn: Callable[[CheckResult, Path, int], R]) -> Callable[[CheckResult, Path, int], R]:
    """`fn`, with a refused rename (RenameError) answered as LSP RequestFailed with its reason."""

    def run(result: CheckResult, path: Path, offset: int) -> R:
        try:
            return fn(result, path, offset)
        except features.RenameError as e:
            raise RequestFailed(str(e)) from e

    return run


def _checks_seeing(ls: GppServer, declaring: Path) -> list[CheckResult]:
    """The checks of every program that sees the declarations of the file `declaring`
    (RequestFailed when not every file that could was read)."""
    try:
        roots = ls.session.programs_seeing(declaring)
    except IncompleteSearch as e:
        raise RequestFailed(f"cannot rename safely: {e}") from e
    return [ls.session.check(root) for root in roots]


def _none() -> None:
    return None


def _empty() -> list[object]:
    return []


def _no_completion() -> types.CompletionList:
    return types.CompletionList(is_incomplete=False, items=[])


def register_features(server: GppServer) -> None:
    @server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["(", ","]))
    @guarded(_no_completion)
    async def completion(ls: GppServer, params: types.CompletionParams) -> types.CompletionList:
        uri, where = params.text_document.uri, params.position
        path = uri_to_path(uri)
        marks = [("received", time.perf_counter())] if ls.timeline.enabled else None
        earlier = ls.earlier_check(path)
        if earlier is not None:
            # Typed since the last check: answer from it now rather than wait for the next,
            # on the event loop (a millisecond of work): on the request thread it would wait
            # twice more for the running check to hand over the interpreter lock.
            result, doc = earlier
            offset = doc.source.lsp_offset(where.line, where.character)
            if marks is not None:
                marks.append(("offset", time.perf_counter()))
            found = features.completion_after_edit(result, path, doc.text, offset)
            if found is not None:
                if marks is not None:
                    ls.timeline.write("completion from the last check", [*marks, ("answered", time.perf_counter())])
                return found
        answer = await at(ls, uri, where, features.completion_list, _no_completion())
        if marks is not None:
            ls.timeline.write("completion", [*marks, ("answered", time.perf_counter())])
        return answer

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    @guarded(_none)
    async def hover(ls: GppServer, params: types.HoverParams) -> types.Hover | None:
        uri = params.text_document.uri
        return await at_last_check(
            ls, uri, params.position, features.hover, None, lambda found, place: _hover_now(found, place, uri)
        )

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    @guarded(_empty)
    async def definition(ls: GppServer, params: types.DefinitionParams) -> list[types.Location]:
        return await at_last_check(
            ls, params.text_document.uri, params.position, features.definition, [], _locations_now
        )

    @server.feature(types.TEXT_DOCUMENT_REFERENCES)
    @guarded(_empty)
    async def references(ls: GppServer, params: types.ReferenceParams) -> list[types.Location]:
        include = params.context.include_declaration

        def run(result: CheckResult, path: Path, offset: int) -> list[types.Location]:
            return features.references(result, path, offset, include)

        return await at(ls, params.text_document.uri, params.position, run, [])

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
    @guarded(_empty)
    async def highlight(ls: GppServer, params: types.DocumentHighlightParams) -> list[types.DocumentHighlight]:
        return await at(ls, params.text_document.uri, params.position, features.document_highlight, [])

    @server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
    @guarded(_none)
    async def prepare_rename(ls: GppServer, params: types.PrepareRenameParams) -> types.PrepareRenameResult | None:
        return await at(ls, params.text_document.uri, params.position, refusing(features.prepare_rename), None)

    @server.feature(types.TEXT_DOCUMENT_RENAME, types.RenameOptions(prepare_provider=True))
    @guarded(_none)
    async def rename(ls: GppServer, params: types.RenameParams) -> types.WorkspaceEdit | None:
        new_name = params.new_name
        found = await ls.result_for(params.text_document.uri)
        if found is None:
            return None
        result, path = found
        offset = source_of(result, path, ls).lsp_offset(params.position.line, params.position.character)
        declared = await ls.on_request_thread(lambda: refusing(features.rename_scope)(result, path, offset))
        others: list[CheckResult] = []
        if declared is not None:
            # Every program of the workspace and its projects that includes the declaring
            # file, open or not, checked as the diagnostics are (on the analysis thread).
            others = await ls.on_analysis_thread(lambda: _checks_seeing(ls, declared[0]))

        def run(result: CheckResult, path: Path, offset: int) -> types.WorkspaceEdit | None:
            return features.rename(result, path, offset, new_name, [o for o in others if o is not result])

        return await ls.on_request_thread(lambda: refusing(run)(result, path, offset))

    @server.feature(
        types.TEXT_DOCUMENT_SIGNATURE_HELP,
        types.SignatureHelpOptions(trigger_characters=["(", ","], retrigger_characters=[","]),
    )
    @guarded(_none)
    async def signature_help(ls: GppServer, params: types.SignatureHelpParams) -> types.SignatureHelp | None:
        return await at(ls, params.text_document.uri, params.position, features.signature_help, None)

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    @guarded(_empty)
    async def document_symbols(ls: GppServer, params: types.DocumentSymbolParams) -> list[types.DocumentSymbol]:
        return await whole(ls, params.text_document.uri, features.document_symbols, [])

    @server.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
    @guarded(_empty)
    async def folding(ls: GppServer, params: types.FoldingRangeParams) -> list[types.FoldingRange]:
        return await whole(ls, params.text_document.uri, features.folding_ranges, [])

    @server.feature(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, features.SEMANTIC_TOKENS_LEGEND)
    @guarded(_none)
    async def semantic_tokens(ls: GppServer, params: types.SemanticTokensParams) -> types.SemanticTokens | None:
        data = await whole(ls, params.text_document.uri, features.semantic_tokens, None)
        return None if data is None else types.SemanticTokens(data=data)

    @server.feature(types.TEXT_DOCUMENT_INLAY_HINT)
    @guarded(_empty)
    async def inlay_hints(ls: GppServer, params: types.InlayHintParams) -> list[types.InlayHint]:
        return await ranged(ls, params.text_document.uri, params.range, features.inlay_hints, [])

    @server.feature(
        types.TEXT_DOCUMENT_CODE_ACTION,
        types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]),
    )
    @guarded(_empty)
    async def code_action(ls: GppServer, params: types.CodeActionParams) -> list[types.CodeAction]:
        return await ranged(ls, params.text_document.uri, params.range, ls.quick_fixes, [])

    @server.feature(types.WORKSPACE_SYMBOL)
    @guarded(_empty)
    async def workspace_symbols(ls: GppServer, params: types.WorkspaceSymbolParams) -> list[types.WorkspaceSymbol]:
        query = params.query
        session = ls.session

        def programs() -> list[CheckResult]:
            # On the analysis thread: the programs of the open documents and of the workspace's
            # files (checked once, then remembered while unchanged).
            texts = {d.path: d.text for d in session.documents()}
            roots = list(dict.fromkeys([*texts, *session.workspace_files()[:_MAX_SYMBOL_PROGRAMS]]))
            return [session.check(root, texts) for root in roots]

        results = await ls.on_analysis_thread(programs)
        return await ls.on_request_thread(lambda: features.workspace_symbols(results, query))

    @server.feature(types.TEXT_DOCUMENT_FORMATTING)
    @guarded(_empty)
    async def formatting(ls: GppServer, params: types.DocumentFormattingParams) -> list[types.TextEdit]:
        path = uri_to_path(params.text_document.uri)
        doc = ls.session.document(path)
        if doc is None:
            return []
        text = doc.text

        def run() -> list[types.TextEdit]:
            from gpp.syntax.format import FormatError, format_text

            try:
                formatted = format_text(text, str(path))
            except FormatError:
                return []  # syntax errors: nothing to format, the diagnostics say why
            if formatted == text:
                return []
            source = Source(text)
            return [types.TextEdit(range=lsp_range(Span(source, 0, len(text))), new_text=formatted)]

        return await ls.on_request_thread(run)
