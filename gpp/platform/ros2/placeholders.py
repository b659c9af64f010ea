"""Placeholders in a mapped ROS name: `"/{r}/navigate"` stands for one ROS name per value of
parameter `r` (`/robot1/navigate`, `/robot2/navigate`), so one declaration of an action,
exogenous action or exogenous function serves many robots.

A placeholder is a parameter's name in braces, in the name part of a mapped name (not in its
type). Its parameter's type is a domain, whose values are known before the run and are the
names' parts: symbols by name, whole numbers and strings as written. Every name a mapping
stands for is made when the program attaches (`instances`) and served as a mapping of its
own; `problems` is what `gpp check` and the platform report of a placeholder that cannot be
served. Kept free of rclpy, as gpp.platform.ros2.names is.
"""

from __future__ import annotations

import dataclasses
import itertools
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

from gpp.base.source import Span
from gpp.base.suggest import did_you_mean
from gpp.codes import R0007
from gpp.model.declarations import PLACEHOLDER, fill_placeholders, placeholders_in
from gpp.model.types import DomainType, Sym
from gpp.platform.base import ActionBinding, ExogActionBinding, Parameter, Problem, ProgramInterface
from gpp.platform.ros2.names import NameError_, parse_mapped
from gpp.runtime.values import Value

_PLACEHOLDER = PLACEHOLDER
_TOKEN = re.compile(r"^[A-Za-z0-9_]+$")


@dataclass(frozen=True)
class Instance:
    """One name a mapped name with placeholders stands for."""

    text: str  # the mapped name with its placeholders filled ("/robot1/navigate : pkg/action/T")
    values: Mapping[str, Value] = field(default_factory=dict)  # parameter -> its value in the name

    @property
    def key(self) -> tuple[str | None, ...]:
        """What tells this name from the others of its mapping: its placeholders' values, in
        the order of the placeholders (`instance_key` of a call with these values)."""
        return tuple(name_text(v) for v in self.values.values())


def has_braces(text: str) -> bool:
    return "{" in text or "}" in text


def _name_part(text: str) -> tuple[str, str]:
    """The name part of a mapped name and the rest (`" : pkg/kind/Type"`, or "")."""
    at = text.find(":")
    return (text, "") if at < 0 else (text[:at], text[at:])


def placeholders(text: str) -> tuple[str, ...]:
    """The parameters named in the name part of `text`, each once, in order."""
    return placeholders_in(text)


def name_text(value: Value) -> str | None:
    """What a value stands for in a ROS name (a symbol by its name, a whole number as written,
    a string itself), or None when it cannot be a part of one."""
    if isinstance(value, Sym):
        text = value.name
    elif isinstance(value, bool) or value is None:
        return None
    elif isinstance(value, int | float):
        if not float(value).is_integer() or value < 0:
            return None
        text = str(int(value))
    elif isinstance(value, str):
        text = value
    else:
        return None
    return text if _TOKEN.match(text) else None


def expand(text: str, values: Mapping[str, Value]) -> str:
    """`text` with each placeholder in its name part replaced by its parameter's value."""
    for placeholder in placeholders(text):
        if name_text(values[placeholder]) is None:
            raise ValueError(f"{values[placeholder]!s} cannot be a part of a ROS name")
    return fill_placeholders(text, values)


def instances(text: str, params: Sequence[Parameter]) -> list[Instance]:
    """Every name `text` stands for: one per combination of its placeholders' values (just
    `text` without placeholders). Its placeholders have no `problems`."""
    names = placeholders(text)
    if not names:
        return [Instance(text)]
    types = {p.name: p.type for p in params}
    domains: list[tuple[Value, ...]] = []
    for name in names:
        t = types[name]
        assert isinstance(t, DomainType)
        domains.append(t.values)
    found: list[Instance] = []
    for combination in itertools.product(*domains):
        values = dict(zip(names, combination, strict=True))
        found.append(Instance(expand(text, values), values))
    return found


def instance_key(text: str, params: Sequence[Parameter], args: Sequence[Value]) -> tuple[str | None, ...]:
    """The `Instance.key` of the name that mapped name `text` stands for when the parameters
    have the values `args` (in order): () without placeholders."""
    values = dict(zip((p.name for p in params), args, strict=False))
    return tuple(name_text(values.get(p)) for p in placeholders(text))


Bound = TypeVar("Bound", ActionBinding, ExogActionBinding)


def bound_instances(binding: Bound, resolve: Callable[[str], str] | None = None) -> list[tuple[Instance, Bound]]:
    """The mapping of an action or exogenous action once per name it stands for, each with
    that name as its mapped name (resolved by `resolve` when given: a name is resolved once its
    placeholders are filled)."""
    if not has_braces(binding.mapped_name):
        return [(Instance(binding.mapped_name), binding)]
    return [
        (instance, dataclasses.replace(binding, mapped_name=resolve(instance.text) if resolve else instance.text))
        for instance in instances(binding.mapped_name, binding.params)
    ]


def mapping_problems(interface: ProgramInterface) -> dict[str, list[Problem]]:
    """The placeholder problems of the program's mappings, by action (and exogenous action)
    name; those without problems are left out."""
    found: dict[str, list[Problem]] = {}
    for name, action in interface.actions.items():
        if own := problems(f"action `{name}`", action.mapped_name, action.params, action.span):
            found[name] = own
    for name, exog in interface.exog_actions.items():
        what = f"exogenous action `{name}`"
        if own := problems(what, exog.mapped_name, exog.params, exog.span, exog.fields):
            found[name] = own
    return found


def problems(
    what: str, text: str, params: Sequence[Parameter], span: Span | None, from_fields: Mapping[str, str] | None = None
) -> list[Problem]:
    """Why the placeholders of mapped name `text` cannot be served (`what`: whose mapping it
    is): braces that are not placeholders, a placeholder in the type, one that is not a
    parameter, a parameter that is not of a domain, or a value that makes no ROS name;
    `from_fields` (message field -> parameter, an exogenous action's mapping): a parameter
    filled from the name as well as from a field."""
    if not has_braces(text):
        return []
    name, rest = _name_part(text)
    if has_braces(rest):
        return [Problem(R0007.placeholder_not_here(what, "the type after `:`").text, span, "the same for every name")]
    if has_braces(_PLACEHOLDER.sub("x", name)):
        return [Problem(R0007.placeholder_malformed(what, text).text, span, "not a placeholder")]
    types = {p.name: p.type for p in params}
    found: list[Problem] = []
    for placeholder in placeholders(text):
        t = types.get(placeholder)
        if t is None:
            found.append(
                Problem(
                    R0007.placeholder_unknown(what, placeholder, tuple(types)).text,
                    span,
                    "not a parameter",
                    help=did_you_mean(placeholder, types),
                )
            )
        elif not isinstance(t, DomainType):
            found.append(Problem(R0007.placeholder_not_a_domain(what, placeholder, str(t)).text, span, "not a domain"))
        else:
            found.extend(_value_problems(what, text, placeholder, t, span))
    for backend, param in (from_fields or {}).items():
        if param in types and param in placeholders(text):
            found.append(Problem(R0007.placeholder_and_field(what, param, backend).text, span, "filled twice"))
    return found


def _value_problems(what: str, text: str, placeholder: str, domain: DomainType, span: Span | None) -> list[Problem]:
    """The first value of `domain` that makes no ROS name in `text`, as a problem."""
    for value in domain.values:
        shown = _show(value)
        filled = name_text(value)
        if filled is None:
            why = "a part of a ROS name is letters, digits and `_`"
        else:
            parts = {p: filled if p == placeholder else "x" for p in placeholders(text)}
            made = _name_part(expand(text, parts))[0].strip()
            try:
                parse_mapped(made)
                continue
            except NameError_:
                why = f'it makes "{made}", not a ROS name (a part begins with a letter or `_`)'
        message = R0007.placeholder_bad_value(what, placeholder, shown, domain.name, why).text
        return [Problem(message, span, "not a ROS name for every value")]
    return []


def _show(value: Value) -> str:
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value).lower() if isinstance(value, bool) else str(value)
