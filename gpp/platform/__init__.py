"""Platforms that agents run on: looked up by name, also through the `gpp.platforms`
entry-point group (a third-party package registers `name = "module:Class"`)."""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module
from importlib.metadata import entry_points

from gpp.platform.base import Platform, PlatformError

_BUILTIN: dict[str, str] = {
    "dummy": "gpp.platform.dummy:DummyPlatform",
    "sim": "gpp.platform.sim:SimPlatform",
}


def available() -> list[str]:
    names = set(_BUILTIN)
    names.update(ep.name for ep in entry_points(group="gpp.platforms"))
    return sorted(names)


def platform_class(name: str) -> Callable[..., Platform]:
    """The platform class registered under `name`; PlatformError if there is none."""
    target = _BUILTIN.get(name)
    if target is None:
        for ep in entry_points(group="gpp.platforms"):
            if ep.name == name:
                loaded = ep.load()
                return loaded  # type: ignore[no-any-return]
        raise PlatformError(f"unknown platform `{name}` (available: {', '.join(available())})")
    module_name, _, class_name = target.partition(":")
    try:
        module = import_module(module_name)
    except ModuleNotFoundError as e:
        raise PlatformError(f"platform `{name}` is not installed here ({e.name} is missing)") from None
    cls: Callable[..., Platform] = getattr(module, class_name)
    return cls
