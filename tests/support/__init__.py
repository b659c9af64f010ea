"""Helpers the tests share: the CLI runner (cli), golden files (golden), hypothesis budgets
(budget), the language server client (lsp_client), fingerprints of models and parses, lint
triggers, random planning worlds, pathological inputs and xdist workers' resources (workers).
Here: `TYPO_CORPUS`."""

from pathlib import Path

# The fix-it corpus (tests/check/fixits/corpus): a typo per program, checked by its own test
# and left out of the tests that take every program of the repository.
TYPO_CORPUS = Path(__file__).resolve().parents[1] / "check" / "fixits" / "corpus"
