"""E02xx: types (what fits where, what an operator applies to)."""

from __future__ import annotations

from gpp.codes.registry import Code, Kind, Message

# Types are shown as the checker writes them (`str()` of a type), hence `object`.


class E0201(Code, name="wrong-arity", summary="a call with the wrong number of arguments"):
    @classmethod
    def arity(cls, name: str, expected: int, given: int) -> Message:
        return Message(
            cls.code,
            f"`{name}` takes {expected} argument{'s' * (expected != 1)} "
            f"but {given} {'were' if given != 1 else 'was'} given",
        )


class E0202(Code, name="type-mismatch", summary="an expression of the wrong type"):
    @classmethod
    def mismatch(cls, expected: object, found: object) -> Message:
        return Message(cls.code, f"expected `{expected}`, found `{found}`")

    @classmethod
    def symbol_name_expected(cls) -> Message:
        return Message(cls.code, "expected a symbol name")


class E0203(Code, name="not-in-domain", summary="a literal that is not a member of the domain it must belong to"):
    @classmethod
    def not_in_domain(cls, value: str, domain: object) -> Message:
        return Message(cls.code, f"`{value}` is not in domain `{domain}`")


# The verb of each arithmetic operator in "cannot add `a` and `b`" (`**` reads "raise ... to").
_VERBS = {"+": "add", "-": "subtract", "*": "multiply", "/": "divide", "%": "take the remainder of"}


class E0204(Code, name="bad-operands", summary="an operator applied to operands of the wrong types"):
    @classmethod
    def needs_list(cls, op: str, found: object) -> Message:
        """A list operation (`push_back`, `length`, ...) on something else."""
        return Message(cls.code, f"`{op}` needs a list, found `{found}`")

    @classmethod
    def not_convertible(cls, found: object) -> Message:
        return Message(cls.code, f"`to_string` converts numbers, bools, symbols and strings, not `{found}`")

    @classmethod
    def null_operand(cls, op: str) -> Message:
        return Message(cls.code, f"`{op}` cannot be applied to `null`")

    @classmethod
    def operand_type(cls, op: str, expected: object, found: object) -> Message:
        return Message(cls.code, f"`{op}` needs `{expected}` operands, found `{found}`")

    @classmethod
    def arithmetic(cls, op: str, left: object, right: object) -> Message:
        if op == "**":
            return Message(cls.code, f"cannot raise `{left}` to `{right}`")
        return Message(cls.code, f"cannot {_VERBS.get(op, 'raise')} `{left}` and `{right}`")

    @classmethod
    def not_equatable(cls, left: object, right: object) -> Message:
        return Message(cls.code, f"cannot compare `{left}` with `{right}`")

    @classmethod
    def order_null(cls, op: str) -> Message:
        return Message(cls.code, f"`{op}` cannot compare with `null`")

    @classmethod
    def not_ordered(cls, left: object, right: object, op: str) -> Message:
        return Message(cls.code, f"cannot order `{left}` and `{right}` with `{op}`")

    @classmethod
    def clock_bound(cls) -> Message:
        return Message(cls.code, "a clock bound uses `<=` or `>=`")


class E0205(Code, name="chained-comparison", summary="comparisons written as a chain, such as `a < b < c`"):
    @classmethod
    def chained(cls) -> Message:
        return Message(cls.code, "comparison operators cannot be chained")


class E0206(Code, name="void-data", summary="`void` used as the type of data"):
    @classmethod
    def void_data(cls) -> Message:
        return Message(cls.code, "`void` is not a type of data")


class E0207(Code, name="not-indexable", summary="a field taken of a non-compound, or an index of a non-list"):
    @classmethod
    def not_indexable(cls, subject: object) -> Message:
        return Message(cls.code, f"`{subject}` cannot be indexed")

    @classmethod
    def no_fields(cls, subject: object) -> Message:
        return Message(cls.code, f"`{subject}` has no fields")


class E0208(Code, name="compound-fields", summary="a compound literal with missing or repeated fields"):
    @classmethod
    def field_twice(cls, field: str) -> Message:
        return Message(cls.code, f"field `{field}` is given twice")

    @classmethod
    def missing_fields(cls, missing: list[str], compound: object) -> Message:
        names = ", ".join(f"`{m}`" for m in missing)
        return Message(cls.code, f"missing field{'s' * (len(missing) != 1)} {names} in `{compound}` literal")


class E0209(Code, name="not-comparable", summary="compound or list values compared"):
    @classmethod
    def not_comparable(cls, type_: object, op: str) -> Message:
        return Message(cls.code, f"values of type `{type_}` cannot be compared with `{op}`")


class E0210(Code, name="infinite-range", summary="a quantifier or `pick` over a type with infinitely many values"):
    @classmethod
    def pick(cls, type_: object) -> Message:
        return Message(cls.code, f"`pick` over `{type_}` needs a list of values")

    @classmethod
    def quantifier(cls, quantifier: str, type_: object) -> Message:
        return Message(cls.code, f"`{quantifier}` over `{type_}` cannot be evaluated")


class E0211(Code, name="branch-types", summary="a conditional expression whose branches have different types"):
    @classmethod
    def branches(cls, then: object, otherwise: object) -> Message:
        return Message(cls.code, f"the branches of this conditional have different types: `{then}` and `{otherwise}`")


class E0212(Code, name="solve-arguments", summary="a `solve` whose horizon or reward is not what it needs"):
    @classmethod
    def reward_not_function(cls, name: str, kind: Kind) -> Message:
        return Message(
            cls.code, f"the reward of `solve` must be a function, but `{name}` is {kind.article} {kind.value}"
        )

    @classmethod
    def reward_not_number(cls, found: object) -> Message:
        return Message(cls.code, f"the reward of `solve` must be a number, found `{found}`")

    @classmethod
    def reward_not_call(cls) -> Message:
        return Message(cls.code, "the reward of `solve` is a call of a number function")


class E0213(Code, name="literal-required", summary="an expression where only a literal value may stand"):
    # The places where only literals may stand, as the messages name them.
    INITIAL_VALUES = "initial values must be literals"
    PICK_VALUES = "`pick ... in {...}` lists literal values"
    CONSTRAINT_PATTERNS = "constraint patterns take literals or `*`"

    @classmethod
    def not_literal(cls, rule: str) -> Message:
        """`rule` is one of the places above."""
        return Message(cls.code, rule)

    @classmethod
    def names_non_symbol(cls, rule: str, name: str, kind: Kind) -> Message:
        return Message(cls.code, f"{rule}; `{name}` is {kind.article} {kind.value}")

    @classmethod
    def domain_element(cls, element: object) -> Message:
        return Message(cls.code, f"a `{element}` domain lists {element} literals")

    @classmethod
    def wildcard(cls) -> Message:
        return Message(cls.code, "`*` stands only in constraint patterns")
