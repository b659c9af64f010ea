"""Typer's conversion of option values without pydantic, for the types gpp's commands use.

Typer 0.2x converts every parameter's value through a pydantic TypeAdapter, and the first one
imports pydantic's validation machinery: about 60 ms, more than the rest of `gpp check`'s
start-up. `install()` makes typer convert values of the plain types (text, whole numbers,
numbers, truth values, paths without constraints, enums, lists and optionals of these) directly, with the
same errors for a bad value; anything else still goes through pydantic. A typer without this
machinery (another version) is left as it is: the commands then work as before, only slower
to start, and tests/cli/test_cli.py says so (`gpp check` imports no pydantic).
"""

from __future__ import annotations

import types
import typing
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any

Converter = Callable[[Any], Any]


def install() -> None:
    """Have typer convert plain values itself (once per process)."""
    try:
        from typer import core
        from typer._click.exceptions import BadParameter
        from typer._coercion import RuntimeParam, TypeDescriptor
        from typer._param_types import coerce_cli_choice
    except ImportError:
        return
    original: Callable[[TypeDescriptor], RuntimeParam] = getattr(core, "build_runtime_param")  # noqa: B009  (not in typer's public names)
    if getattr(original, "plain_values", False):
        return

    @dataclass(frozen=True)
    class PlainRuntimeParam(RuntimeParam):
        convert: Converter

        def _coerce_value(self, value: Any, param: Any, ctx: Any) -> Any:
            try:
                if isinstance(value, list | tuple):
                    return [self.convert(item) for item in value]
                return self.convert(value)
            except ValueError as e:
                raise BadParameter(str(e), ctx=ctx, param=param) from None

    def choice(choices: tuple[Any, ...], case_sensitive: bool) -> Converter:
        return lambda value: coerce_cli_choice(value, choices=choices, case_sensitive=case_sensitive, ctx=None)

    def build(descriptor: TypeDescriptor) -> RuntimeParam:
        convert = _converter(descriptor.annotation, descriptor.parameter_info, choice)
        if convert is None or descriptor.file_annotation is not None:
            return original(descriptor)
        return PlainRuntimeParam(descriptor.parameter_info, descriptor.annotation, convert)

    build.plain_values = True  # type: ignore[attr-defined]
    setattr(core, "build_runtime_param", build)  # noqa: B010


def _converter(annotation: Any, info: Any, choice: Callable[[tuple[Any, ...], bool], Converter]) -> Converter | None:
    """The converter for a parameter of this annotation, or None when typer must do it."""
    if any(getattr(info, name, None) not in (None, False) for name in _CONSTRAINTS) or not (
        getattr(info, "file_okay", True) and getattr(info, "dir_okay", True)
    ):
        return None
    if typing.get_origin(annotation) is list:
        (annotation,) = typing.get_args(annotation)
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        kinds = [a for a in typing.get_args(annotation) if a is not type(None)]
        if len(kinds) != 1:
            return None
        annotation = kinds[0]
    if isinstance(annotation, type) and issubclass(annotation, Enum):
        return choice(tuple(annotation), bool(getattr(info, "case_sensitive", True)))
    return _PLAIN.get(annotation)


# ParameterInfo settings that only typer's own conversion applies.
_CONSTRAINTS = ("parser", "min", "max", "exists", "writable", "resolve_path", "allow_dash", "path_type", "formats")


def _text(value: Any) -> str:
    return value if isinstance(value, str) else str(value)


def _whole(value: Any) -> int:
    if isinstance(value, int) and not isinstance(value, bool):
        return value
    try:
        return int(value)
    except (TypeError, ValueError):
        raise ValueError(f"{value!r} is not a valid integer.") from None


def _number(value: Any) -> float:
    if isinstance(value, float):
        return value
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{value!r} is not a valid float.") from None


def _truth(value: Any) -> bool:
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("1", "true", "t", "yes", "y", "on"):
        return True
    if text in ("0", "false", "f", "no", "n", "off"):
        return False
    raise ValueError(f"{value!r} is not a valid boolean.")


def _path(value: Any) -> Path:
    return value if isinstance(value, Path) else Path(value)


_PLAIN: dict[Any, Converter] = {str: _text, int: _whole, float: _number, bool: _truth, Path: _path}
