"""What every layer uses: source text and spans, diagnostics, did-you-mean suggestions, the
range of numbers, where the grammar and stdlib are, and small performance helpers."""
