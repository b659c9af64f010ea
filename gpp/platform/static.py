"""Checks that platforms make of a program without running it: `gpp check` and the language
server report what a platform would refuse when the program attaches, where that needs no
robot (e.g. a ROS mapping that names its message type: its fields and value types are known
from the message classes alone).

A built-in platform declares its check in gpp.platform.options (`static_check`, as
`module:function`); the function takes the checked model and returns the problems
(gpp.platform.base.Problem) it finds, each an R0007 error at the mapping it is about. It must
cost nothing for a program it has nothing to say about: its module is imported for every
check, so it imports only what it needs to see that, and the rest when it has work to do.
The checker (gpp.check) does not import platforms: the CLI and the language server call this
module on the checked model.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING

from gpp.platform.options import BUILTIN

if TYPE_CHECKING:
    from gpp.base.diagnostics import Diagnostic
    from gpp.model.model import Model


def static_diagnostics(model: Model) -> list[Diagnostic]:
    """The errors every platform's static check finds in a checked program (one without
    errors: the platforms read its mappings and types)."""
    found: list[Diagnostic] = []
    for name, declared in BUILTIN.items():
        if declared.static_check is None:
            continue
        module, _, function = declared.static_check.partition(":")
        problems = getattr(import_module(module), function)(model)
        if not problems:
            continue
        from gpp.runtime.contract import unfit_error

        fallback = model.main.span if model.main is not None else None
        for problem in problems:
            diagnostic = unfit_error(problem, name, fallback).diagnostic()
            if diagnostic is not None:
                found.append(diagnostic)
    return found
