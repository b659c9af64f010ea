"""E03xx: declarations (redefinitions, forward declarations, sections, initial values)."""

from __future__ import annotations

from gpp.codes.registry import Code, Kind, Message


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'s' * (n != 1)}"


class E0301(Code, name="redefinition", summary="a second definition of the same name"):
    @classmethod
    def defined_twice(cls, name: str) -> Message:
        return Message(cls.code, f"`{name}` is defined twice")


class E0302(Code, name="kind-clash", summary="one name declared as two different kinds of things"):
    @classmethod
    def kind_clash(cls, name: str, first: Kind) -> Message:
        return Message(cls.code, f"`{name}` is already declared as {first.article} {first.value}")


class E0303(Code, name="forward-mismatch", summary="a definition that does not match its forward declaration"):
    @classmethod
    def element_type(cls, name: str, first: object, here: object) -> Message:
        return Message(cls.code, f"`{name}` has element type `{first}` in one declaration and `{here}` here")

    @classmethod
    def type_(cls, name: str, declared: object, defined: object) -> Message:
        return Message(cls.code, f"`{name}` is declared with type `{declared}` but defined with type `{defined}`")

    @classmethod
    def parameter_count(cls, name: str, declared: int, defined: int) -> Message:
        return Message(
            cls.code, f"`{name}` is declared with {_plural(declared, 'parameter')} but defined with {defined}"
        )

    @classmethod
    def parameter_type(cls, name: str, here: object, forward: object) -> Message:
        return Message(
            cls.code, f"parameter `{name}` has type `{here}` here but `{forward}` in the forward declaration"
        )

    @classmethod
    def parameter_name(cls, name: str, forward: str) -> Message:
        return Message(cls.code, f"parameter `{name}` is called `{forward}` in the forward declaration")


class E0304(Code, name="predefined-name", summary="a declaration of a name gpp predefines"):
    @classmethod
    def predefined(cls, name: str) -> Message:
        return Message(cls.code, f"`{name}` is predefined and cannot be declared")


class E0305(
    Code,
    name="duplicate-name",
    summary="a parameter, field, mapping argument or variable declared twice in one list",
):
    @classmethod
    def in_list(cls, name: str) -> Message:
        return Message(cls.code, f"`{name}` is declared twice in this list")

    @classmethod
    def in_component(cls, name: str, component: str) -> Message:
        return Message(cls.code, f"`{name}` is declared twice in component `{component}`")

    @classmethod
    def mapping_argument(cls, name: str) -> Message:
        return Message(cls.code, f"mapping argument `{name}` is given twice")


class E0306(Code, name="bad-assignment-target", summary="an assignment to something that is not a fluent"):
    @classmethod
    def declaration(cls, name: str, kind: Kind) -> Message:
        return Message(cls.code, f"cannot assign to `{name}`: it is {kind.article} {kind.value}")

    @classmethod
    def local(cls, kind: Kind, name: str) -> Message:
        """A parameter or variable."""
        return Message(cls.code, f"cannot assign to {kind.value} `{name}`")

    @classmethod
    def expression(cls) -> Message:
        return Message(cls.code, "cannot assign to this expression")


class E0307(Code, name="bad-initial-value", summary="an `initially:` entry that does not fit the fluent's parameters"):
    @classmethod
    def argument_count(cls, fluent: str, params: int, given: int) -> Message:
        return Message(
            cls.code,
            f"fluent `{fluent}` has {_plural(params, 'parameter')}, "
            f"but this initial value gives {_plural(given, 'argument')}",
        )

    @classmethod
    def parameter_position(cls, name: str, position: int, expected: str) -> Message:
        return Message(
            cls.code,
            f"`{name}` is the parameter in position {position}; here only `{expected}` or a literal can stand",
        )


class E0308(
    Code,
    name="exog-mapping",
    summary="an exogenous action mapping that does not bind every parameter to itself",
):
    @classmethod
    def not_a_parameter(cls) -> Message:
        return Message(cls.code, "an exogenous action's mapping entry must be one of its parameters")

    @classmethod
    def unbound(cls, action: str, missing: list[str]) -> Message:
        names = ", ".join(f"`{m}`" for m in missing)
        return Message(cls.code, f"the mapping of exogenous action `{action}` does not bind {names}")


class E0309(Code, name="section-not-allowed", summary="a section an exogenous action cannot have"):
    @classmethod
    def exogenous(cls, word: str) -> Message:
        return Message(cls.code, f"an exogenous action cannot have a `{word}:` section")


class E0310(Code, name="main-twice", summary="a legacy main block and a `procedure main` in one program"):
    @classmethod
    def main_twice(cls) -> Message:
        return Message(cls.code, "a legacy main block and `main` in one program")


class E0311(Code, name="bad-domain", summary="a domain definition that refers to itself or mixes element types"):
    @classmethod
    def element_kind(cls, element: object) -> Message:
        return Message(cls.code, f"a domain's elements must be symbols, numbers, strings or bools, not `{element}`")

    @classmethod
    def recursive(cls, name: str) -> Message:
        return Message(cls.code, f"domain `{name}` is defined in terms of itself")

    @classmethod
    def mixed(cls, other: str, other_element: object, name: str, element: object) -> Message:
        return Message(
            cls.code,
            f"domain `{other}` has `{other_element}` elements, but `{name}` has `{element}` elements",
        )


class E0312(Code, name="bad-duration", summary="a `duration:` or `silent:` section with values it cannot have"):
    @classmethod
    def silent(cls) -> Message:
        return Message(cls.code, "`silent:` takes `true`, `false` or `null`")

    @classmethod
    def bound(cls) -> Message:
        return Message(cls.code, "a duration bound is a non-negative number literal (seconds)")

    @classmethod
    def bounds_order(cls) -> Message:
        return Message(cls.code, "the lower duration bound is greater than the upper one")
