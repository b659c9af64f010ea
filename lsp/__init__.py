"""The golog++ language server (built on gpp.model)."""
