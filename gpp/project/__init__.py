"""A project: its settings (`gpp.toml`, config) and the starter project of `gpp new`
(scaffold)."""
