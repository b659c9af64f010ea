"""R00xx: run time (reported by `gpp run` and `gpp test` when the program runs)."""

from __future__ import annotations

from gpp.codes.registry import Code, Message


class R0001(
    Code, name="bad-arithmetic", summary="an arithmetic operation without a result: division by zero and the like"
):
    @classmethod
    def division_by_zero(cls) -> Message:
        return Message(cls.code, "division by zero")

    @classmethod
    def modulo_by_zero(cls) -> Message:
        return Message(cls.code, "modulo by zero")

    @classmethod
    def modulo_not_whole(cls, left: str, right: str) -> Message:
        return Message(cls.code, f"`%` needs whole numbers, got {left} and {right}")

    @classmethod
    def power_divides_by_zero(cls, base: str, exponent: str) -> Message:
        return Message(cls.code, f"`{base} ** {exponent}` divides by zero")

    @classmethod
    def power_too_large(cls, base: str, exponent: str) -> Message:
        return Message(cls.code, f"`{base} ** {exponent}` is too large")

    @classmethod
    def power_not_real(cls, base: str, exponent: str) -> Message:
        return Message(cls.code, f"`{base} ** {exponent}` is not a real number")

    @classmethod
    def too_large(cls, op: str) -> Message:
        return Message(cls.code, f"the result of `{op}` is too large for a number")


class R0002(Code, name="null-value", summary="an operation on `null`, the value of a fluent instance without a value"):
    @classmethod
    def applied_to_null(cls, op: str) -> Message:
        return Message(cls.code, f"`{op}` applied to `null`")

    @classmethod
    def compares_null(cls, op: str) -> Message:
        return Message(cls.code, f"`{op}` compares `null`")

    @classmethod
    def field_of_null(cls, field: str) -> Message:
        return Message(cls.code, f"field `{field}` of `null`")

    @classmethod
    def length_of_null(cls) -> Message:
        return Message(cls.code, "`length` of `null`")

    @classmethod
    def indexing_null(cls) -> Message:
        return Message(cls.code, "indexing `null`")

    @classmethod
    def assignment_into_null(cls) -> Message:
        return Message(cls.code, "assignment into a `null` value")

    @classmethod
    def null_list(cls, op: str) -> Message:
        return Message(cls.code, f"`{op}` on a `null` list")

    @classmethod
    def reward_not_number(cls) -> Message:
        return Message(cls.code, "the reward is not a number")


class R0003(Code, name="bad-index", summary="a list index out of range or not a whole number"):
    @classmethod
    def not_whole(cls, index: str) -> Message:
        return Message(cls.code, f"list index `{index}` is not a whole number")

    @classmethod
    def out_of_range(cls, index: int, length: int) -> Message:
        return Message(cls.code, f"list index {index} is out of range (the list has {length} elements)")


class R0004(Code, name="domain-violation", summary="a value outside its domain, stored or passed at run time"):
    @classmethod
    def not_in_domain(cls, value: str, domain: str) -> Message:
        return Message(cls.code, f"`{value}` is not in domain `{domain}`")


class R0005(
    Code, name="conflicting-effects", summary="effects of one action that give one fluent instance different values"
):
    @classmethod
    def conflict(cls, action: str, where: str) -> Message:
        return Message(cls.code, f"`{action}` assigns {where} two different values")


class R0006(Code, name="pop-empty-list", summary="`pop_front` or `pop_back` on an empty list"):
    @classmethod
    def empty(cls, op: str) -> Message:
        return Message(cls.code, f"`{op}` on an empty list")


class R0007(Code, name="platform-failure", summary="the platform cannot do what the program asks of it"):
    @classmethod
    def not_asked_explaining(cls) -> Message:
        return Message(cls.code, "not asked while explaining a wait")

    @classmethod
    def exog_function_failed(cls, name: str, error: object) -> Message:
        return Message(cls.code, f"exogenous function `{name}` failed: {error}")

    @classmethod
    def no_answer(cls, name: str, why: object) -> Message:
        """An exogenous function without a current answer (what a waiting program waits for)."""
        return Message(cls.code, f"exogenous function `{name}` has no answer: {why}")

    @classmethod
    def exog_function_offline(cls, name: str) -> Message:
        return Message(cls.code, f"exogenous function `{name}` cannot be asked offline")

    @classmethod
    def cannot_start(cls, action: str, error: object) -> Message:
        return Message(cls.code, f"the platform cannot start `{action}`: {error}")

    @classmethod
    def unfit(cls, problem: str) -> Message:
        """A problem the platform found in the program when it attached (its own text)."""
        return Message(cls.code, problem)

    # Placeholders in a mapped ROS name (`"/{r}/navigate"`): `gpp check`, the language server
    # and the ros2 platform report them at the mapped name.

    @classmethod
    def placeholder_malformed(cls, what: str, name: str) -> Message:
        return Message(
            cls.code,
            f'{what}: "{name}": a placeholder is a parameter\'s name in braces, such as "/{{r}}/navigate" '
            "(braces that do not pair, or are empty)",
        )

    @classmethod
    def placeholder_unknown(cls, what: str, placeholder: str, params: tuple[str, ...]) -> Message:
        known = f"its parameters: {', '.join(params)}" if params else "it has no parameters"
        return Message(cls.code, f"{what}: the placeholder `{{{placeholder}}}` is not a parameter ({known})")

    @classmethod
    def placeholder_not_a_domain(cls, what: str, placeholder: str, type_name: str) -> Message:
        return Message(
            cls.code,
            f"{what}: the placeholder `{{{placeholder}}}` is a parameter of type `{type_name}`, whose values are not "
            "known before the run: a placeholder takes a parameter of a domain, whose values make the names",
        )

    @classmethod
    def placeholder_bad_value(cls, what: str, placeholder: str, value: str, domain: str, why: str) -> Message:
        return Message(
            cls.code, f"{what}: the placeholder `{{{placeholder}}}` takes the value {value} of domain `{domain}`: {why}"
        )

    @classmethod
    def placeholder_not_here(cls, what: str, where: str) -> Message:
        return Message(cls.code, f"{what}: {where} cannot have a placeholder")

    @classmethod
    def placeholder_and_field(cls, what: str, placeholder: str, field: str) -> Message:
        return Message(
            cls.code,
            f"{what}: parameter `{placeholder}` is filled from the topic's name (the placeholder "
            f"`{{{placeholder}}}`), so the mapping cannot fill it from the message field `{field}` too",
        )


class R0008(
    Code, name="missing-definition", summary="a procedure or function declared but never defined, or no `main`"
):
    @classmethod
    def procedure(cls, name: str) -> Message:
        return Message(cls.code, f"procedure `{name}` is declared but never defined")

    @classmethod
    def function(cls, name: str) -> Message:
        return Message(cls.code, f"function `{name}` is declared but never defined")

    @classmethod
    def no_main(cls) -> Message:
        return Message(cls.code, "the program has no `procedure main()` to run")


class R0009(
    Code, name="started-twice", summary="an activity started again before the previous identical one was ended"
):
    @classmethod
    def started_again(cls, action: str) -> Message:
        return Message(cls.code, f"`{action}` is started again before its previous activity was ended")


class R0010(
    Code, name="planning-aborted", summary="`solve` or `search` that cannot plan: endless free steps, bad horizon"
):
    @classmethod
    def free_loop(cls) -> Message:
        return Message(cls.code, "this loop can run forever without a costed step")

    @classmethod
    def free_run(cls, limit: int) -> Message:
        return Message(cls.code, f"planning followed more than {limit} steps in a row without a costed step")

    @classmethod
    def too_deep(cls) -> Message:
        return Message(
            cls.code, "planning went too deep: a recursion that makes no costed step, or a horizon too large"
        )

    @classmethod
    def search_bound(cls, bound: int) -> Message:
        return Message(cls.code, f"`search` exceeded its bound of {bound} steps without finding an end")

    @classmethod
    def no_planner(cls, kind: str) -> Message:
        return Message(cls.code, f"`{kind}` cannot plan: this run has no planner")

    @classmethod
    def bad_horizon(cls, horizon: str) -> Message:
        return Message(cls.code, f"the horizon of `solve` must be a whole number >= 0, got {horizon}")


class R0011(Code, name="blocked", summary="the program cannot make a step and nothing can change that"):
    # Every message starts with PREFIX; those about an activity with AWAITS.
    PREFIX = "the program is blocked: "
    AWAITS = PREFIX + "it waits for `"

    @classmethod
    def no_plan(cls, statement: str) -> Message:
        return Message(cls.code, cls.PREFIX + f"`{statement}` found no plan")

    @classmethod
    def test_false(cls) -> Message:
        return Message(cls.code, cls.PREFIX + "this test is false")

    @classmethod
    def awaits(cls, action: str, what: str) -> Message:
        """`what` is what the activity must do ("to end")."""
        return Message(cls.code, cls.AWAITS + f"{action}` {what}")

    @classmethod
    def awaits_planned(cls, action: str, step: int) -> Message:
        """A planned activity: `step` is the number of its step in the plan (1 for the first)."""
        return Message(cls.code, cls.AWAITS + f"{action}` to end, step {step} of the plan")

    @staticmethod
    def planned_wait(action: str, step: int) -> str:
        """What a `waiting` trace record says of a wait for a planned activity."""
        return f"waiting for `{action}` to end, step {step} of the plan"

    @classmethod
    def precondition_false(cls, action: str) -> Message:
        return Message(cls.code, cls.PREFIX + f"the precondition of `{action}` is false")

    @classmethod
    def no_step(cls) -> Message:
        return Message(cls.code, cls.PREFIX + "nothing can make a step")


class R0012(Code, name="recursion-too-deep", summary="procedure or function calls nested too deeply"):
    @classmethod
    def calls(cls) -> Message:
        return Message(cls.code, "the program nests procedure or function calls too deeply")

    @classmethod
    def postcond(cls) -> Message:
        return Message(cls.code, "`postcond()` nests function calls too deeply")


class R0013(
    Code,
    name="timeout",
    summary="the run reached its bound: `--timeout` (wall-clock time) or `--time-limit` (platform time)",
):
    @classmethod
    def time_limit(cls, seconds: float) -> Message:
        """`--time-limit` / `time_limit`: seconds of platform time."""
        return Message(cls.code, f"the run reached its time limit of {seconds:g} s of platform time (`--time-limit`)")

    @classmethod
    def wall_clock(cls, seconds: float, platform_time: float) -> Message:
        """`--timeout` / `timeout`: seconds of wall-clock time."""
        return Message(
            cls.code,
            f"the run reached its timeout of {seconds:g} s of wall-clock time (`--timeout`; "
            f"platform time: {platform_time:g} s)",
        )


class R0014(
    Code,
    name="plan-unfinished",
    summary="a `solve` whose plan stops at its horizon with the program unfinished",
    run_time_warning=True,
):
    @classmethod
    def unfinished(cls, horizon: object) -> Message:
        return Message(
            cls.code, f"the plan of this `solve` stops at its horizon of {horizon} with the program unfinished"
        )

    @classmethod
    def spent(cls, horizon: int, count: int, steps: str) -> str:
        """A note: where the part of the horizon `horizon` (as written) that the plan could not
        use went: `count` steps already executed, `steps` as text."""
        return (
            f"{count} of its {horizon} step(s) went to the steps of the `solve` already executed: {steps} "
            "(the steps of failed attempts are not counted)"
        )


class R0015(
    Code,
    name="platform-warning",
    summary="the platform dropped a message that does not fit the program, or warns about its setup",
    run_time_warning=True,
):
    @classmethod
    def dropped(cls, source: str, target: str, reason: str) -> Message:
        return Message(cls.code, f"{source}: dropped for `{target}`: {reason}")

    @classmethod
    def platform(cls, platform: str, text: str) -> Message:
        """A platform's own warning (its text)."""
        return Message(cls.code, f"platform `{platform}`: {text}")


class R0099(Code, name="internal-error", summary="a bug in gpp, not a problem of the program", registered=False):
    """Not registered (`gpp explain` does not know it): it reports a bug in gpp."""

    @classmethod
    def internal(cls, error: BaseException) -> Message:
        return Message(cls.code, f"internal error: {type(error).__name__}: {error}")

    @classmethod
    def unchecked(cls, what: str) -> Message:
        """Something the checker should have rejected."""
        return Message(cls.code, f"internal: {what} (the program should not have passed the checker)")

    @classmethod
    def exog_in_initial_value(cls) -> Message:
        return Message(cls.code, "an initial value cannot call an exogenous function")
