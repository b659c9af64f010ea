"""Platforms that agents run on: looked up by name, also through the `gpp.platforms`
entry-point group (a third-party package registers `name = "module:Class"`, a subclass of
gpp.platform.base.Platform).

The runner and the CLI know platforms only through this registry: `platform_class(name)` to
create one, `choose_platform(directives)` to pick one for a program from its `// key:` lines,
`options_of(name)` for the options it takes. A built-in platform is imported only when it is
created: what the registry needs to know of it is declared in gpp.platform.options.
"""

from __future__ import annotations

from collections.abc import Mapping
from importlib import import_module
from typing import TYPE_CHECKING, Any

from gpp.base.suggest import did_you_mean
from gpp.platform.options import BUILTIN

if TYPE_CHECKING:
    from gpp.platform.base import Platform

# Where a program runs when no directive selects a platform.
DEFAULT_PLATFORM = "dummy"


def _plugins() -> dict[str, Any]:
    """The entry points of the `gpp.platforms` group, by name (importlib.metadata is imported
    only when they are asked for)."""
    from importlib.metadata import entry_points

    return {ep.name: ep for ep in entry_points(group="gpp.platforms")}


def available() -> list[str]:
    return sorted(set(BUILTIN) | set(_plugins()))


def platform_class(name: str) -> type[Platform]:
    """The platform class registered under `name`; PlatformError if there is none, or if it
    cannot be loaded here."""
    from gpp.platform.base import PlatformError

    declared = BUILTIN.get(name)
    if declared is None:
        plugin = _plugins().get(name)
        if plugin is not None:
            return _checked(name, plugin.load())
        hint = did_you_mean(name, available())
        raise PlatformError(
            f"unknown platform `{name}`" + (f"; {hint}" if hint else "") + f" (available: {', '.join(available())})"
        )
    module_name, _, class_name = declared.target.partition(":")
    try:
        module = import_module(module_name)
    except ModuleNotFoundError as e:
        raise PlatformError(f"platform `{name}` is not installed here ({e.name} is missing)") from None
    return _checked(name, getattr(module, class_name))


def options_of(name: str) -> type[Any]:
    """The options dataclass of a platform (a built-in one is not imported for it);
    PlatformError as `platform_class`."""
    declared = BUILTIN.get(name)
    return declared.options if declared is not None else platform_class(name).Options


def _checked(name: str, loaded: object) -> type[Platform]:
    from gpp.platform.base import Platform, PlatformError

    if not (isinstance(loaded, type) and issubclass(loaded, Platform)):
        raise PlatformError(f"platform `{name}` is registered as {loaded!r}, which is not a gpp Platform class")
    return loaded


def choose_platform(directives: Mapping[str, str]) -> str:
    """The platform a program runs on when none is named: the first (by name) whose
    `selected_by` directive the program has, else the default. A platform that cannot be loaded
    here is passed over."""
    from gpp.platform.base import PlatformError

    if not directives:  # nothing can select a platform: none is loaded to ask
        return DEFAULT_PLATFORM
    for name in available():
        declared = BUILTIN.get(name)
        if declared is not None:
            selected_by = declared.selected_by
        else:
            try:
                selected_by = platform_class(name).selected_by
            except PlatformError:
                continue
        if selected_by is not None and selected_by in directives:
            return name
    return DEFAULT_PLATFORM
