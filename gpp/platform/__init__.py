"""Platforms that agents run on: looked up by name, also through the `gpp.platforms`
entry-point group (a third-party package registers `name = "module:Class"`, a subclass of
gpp.platform.base.Platform).

The runner and the CLI know platforms only through this registry: `platform_class(name)` to
create one, `choose_platform(directives)` to pick one for a program from its `// key:` lines.
"""

from __future__ import annotations

from collections.abc import Mapping
from importlib import import_module
from importlib.metadata import entry_points

from gpp.base.suggest import did_you_mean
from gpp.platform.base import Platform, PlatformError

_BUILTIN: dict[str, str] = {
    "dummy": "gpp.platform.dummy:DummyPlatform",
    "sim": "gpp.platform.sim:SimPlatform",
    "ros2": "gpp.platform.ros2:Ros2Platform",
}

# Where a program runs when no directive selects a platform.
DEFAULT_PLATFORM = "dummy"


def available() -> list[str]:
    names = set(_BUILTIN)
    names.update(ep.name for ep in entry_points(group="gpp.platforms"))
    return sorted(names)


def platform_class(name: str) -> type[Platform]:
    """The platform class registered under `name`; PlatformError if there is none, or if it
    cannot be loaded here."""
    target = _BUILTIN.get(name)
    if target is None:
        for ep in entry_points(group="gpp.platforms"):
            if ep.name == name:
                return _checked(name, ep.load())
        hint = did_you_mean(name, available())
        raise PlatformError(
            f"unknown platform `{name}`" + (f"; {hint}" if hint else "") + f" (available: {', '.join(available())})"
        )
    module_name, _, class_name = target.partition(":")
    try:
        module = import_module(module_name)
    except ModuleNotFoundError as e:
        raise PlatformError(f"platform `{name}` is not installed here ({e.name} is missing)") from None
    return _checked(name, getattr(module, class_name))


def _checked(name: str, loaded: object) -> type[Platform]:
    if not (isinstance(loaded, type) and issubclass(loaded, Platform)):
        raise PlatformError(f"platform `{name}` is registered as {loaded!r}, which is not a gpp Platform class")
    return loaded


def choose_platform(directives: Mapping[str, str]) -> str:
    """The platform a program runs on when none is named: the first (by name) whose
    `selected_by` directive the program has, else the default. A platform that cannot be loaded
    here is passed over."""
    for name in available():
        try:
            cls = platform_class(name)
        except PlatformError:
            continue
        if cls.selected_by is not None and cls.selected_by in directives:
            return name
    return DEFAULT_PLATFORM
