"""E01xx: names (unknown, misspelt or misused)."""

from __future__ import annotations

from gpp.codes.registry import Code, Kind, Message


class E0101(Code, name="unknown-name", summary="a name that is neither a variable nor a symbol"):
    @classmethod
    def unknown(cls, name: str) -> Message:
        return Message(cls.code, f"unknown name `{name}`")


class E0102(Code, name="missing-call", summary="a fluent, function, action or procedure named without `()`"):
    @classmethod
    def missing_call(cls, name: str, kind: Kind) -> Message:
        return Message(cls.code, f"`{name}` is {kind.article} {kind.value}; call it with `{name}(...)`")


class E0103(Code, name="unknown-callable", summary="a call of something that is not declared"):
    @classmethod
    def unknown(cls, what: str, name: str) -> Message:
        """`what` is the kind of declaration the call needs ("action or procedure")."""
        return Message(cls.code, f"unknown {what} `{name}`")


class E0104(Code, name="wrong-kind", summary="a declaration used where its kind is not allowed"):
    @classmethod
    def not_a_statement(cls) -> Message:
        return Message(cls.code, "this expression is not a statement")

    @classmethod
    def hook_needs_action(cls, hook: str) -> Message:
        return Message(cls.code, f"`{hook}` needs an action call such as `{hook}(go(kitchen))`")

    @classmethod
    def in_expression(cls, name: str, kind: Kind) -> Message:
        return Message(
            cls.code, f"`{name}` is {kind.article} {kind.value}; only fluents and functions can be used in expressions"
        )

    @classmethod
    def as_statement(cls, name: str, kind: Kind) -> Message:
        return Message(cls.code, f"`{name}` is {kind.article} {kind.value} and cannot be executed as a statement")

    @classmethod
    def hook_of(cls, name: str, kind: Kind, hook: str) -> Message:
        return Message(cls.code, f"`{name}` is {kind.article} {kind.value}; `{hook}` needs an action")


class E0105(Code, name="unknown-type", summary="a type name that is not declared"):
    @classmethod
    def unknown_type(cls, name: str) -> Message:
        return Message(cls.code, f"unknown type `{name}`")

    @classmethod
    def unknown_compound(cls, name: str) -> Message:
        return Message(cls.code, f"unknown compound type `{name}`")

    @classmethod
    def not_compound(cls, name: str) -> Message:
        return Message(cls.code, f"`{name}` is not a compound type")

    @classmethod
    def unknown_domain(cls, name: str) -> Message:
        return Message(cls.code, f"unknown domain `{name}`")

    @classmethod
    def not_domain(cls, name: str) -> Message:
        return Message(cls.code, f"`{name}` is not a domain")


class E0106(Code, name="unknown-field", summary="a field that the compound type does not have"):
    @classmethod
    def no_field(cls, compound: object, field: str) -> Message:
        return Message(cls.code, f"`{compound}` has no field `{field}`")


class E0107(Code, name="unknown-platform-name", summary="an unknown component, state or clock in the platform model"):
    @classmethod
    def no_member(cls, component: str, kind: Kind, name: str) -> Message:
        return Message(cls.code, f"component `{component}` has no {kind.value} `{name}`")

    @classmethod
    def unknown_component(cls, name: str) -> Message:
        return Message(cls.code, f"unknown component `{name}`")
