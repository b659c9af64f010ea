"""gpp: a toolchain for the golog++ agent language."""

__version__ = "0.1.0"
