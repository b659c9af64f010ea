"""The editor features of the language server, as pure functions on a checked program
(gpp.check.CheckResult) and one of its files: each is a query on the code model. Offsets are
character offsets into the file's text; ranges and positions are LSP ones (0-based lines,
UTF-16 columns). None of them raises, except `rename`/`prepare_rename` with RenameError."""

from lsp.features.completion import (
    COMPLETION_TRIGGER_CHARACTERS,
    completion,
    completion_after_edit,
    completion_list,
)
from lsp.features.info import SIGNATURE_TRIGGER_CHARACTERS, hover, inlay_hints, signature_help
from lsp.features.navigation import (
    RenameError,
    definition,
    document_highlight,
    prepare_rename,
    references,
    rename,
    rename_scope,
)
from lsp.features.outline import document_symbols, folding_ranges, workspace_symbols
from lsp.features.tokens import SEMANTIC_TOKENS_LEGEND, semantic_tokens

__all__ = [
    "COMPLETION_TRIGGER_CHARACTERS",
    "SEMANTIC_TOKENS_LEGEND",
    "SIGNATURE_TRIGGER_CHARACTERS",
    "RenameError",
    "completion",
    "completion_after_edit",
    "completion_list",
    "definition",
    "document_highlight",
    "document_symbols",
    "folding_ranges",
    "hover",
    "inlay_hints",
    "prepare_rename",
    "references",
    "rename",
    "rename_scope",
    "semantic_tokens",
    "signature_help",
    "workspace_symbols",
]
