"""The `gpp` command line: `main` (the entry point) dispatches, `app` builds the typer app with
the commands, one module per command registers itself, `common` holds what the commands share.
Imports go one way: main, app, the commands, common."""
