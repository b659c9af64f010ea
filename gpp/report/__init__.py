"""Diagnostics written out: rustc-style text and JSON (text), a line each or GitHub
annotations (concise), SARIF 2.1.0 (sarif)."""
