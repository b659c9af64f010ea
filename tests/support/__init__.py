"""Helpers the tests share: the CLI runner (cli), golden files (golden), hypothesis budgets
(budget), the language server client (lsp_client), fingerprints of models and parses, lint
triggers, random planning worlds, pathological inputs and xdist workers' resources (workers)."""
