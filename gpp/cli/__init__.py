"""The `gpp` command line: `main` dispatches, `common` holds what the commands share, one
module per command."""
