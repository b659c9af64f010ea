"""W01xx: lints (warnings about programs that are valid but probably wrong)."""

from __future__ import annotations

from gpp.codes.registry import Code, Kind, Message


class W0101(Code, name="unused", summary="a fluent, action, function or procedure that is never used"):
    @classmethod
    def unused(cls, kind: Kind, name: str) -> Message:
        return Message(cls.code, f"{kind.value} `{name}` is never used")


class W0102(Code, name="unused-variable", summary="a parameter or variable that is never used"):
    @classmethod
    def parameter(cls, name: str, owner_kind: Kind, owner: str) -> Message:
        return Message(cls.code, f"parameter `{name}` of {owner_kind.value} `{owner}` is never used")

    @classmethod
    def variable(cls, name: str) -> Message:
        return Message(cls.code, f"variable `{name}` is never used")


class W0103(Code, name="uninitialized-fluent", summary="fluent instances that have no initial value"):
    @classmethod
    def no_initial_values(cls, fluent: str) -> Message:
        return Message(cls.code, f"fluent `{fluent}` has no initial values")

    @classmethod
    def missing_instances(cls, fluent: str, instances: str, open_params: list[str]) -> Message:
        """`instances` lists the instances without a value; `open_params` the parameters that
        no entry lists."""
        text = f"fluent `{fluent}` has no initial value for {instances}"
        if open_params:
            text += " with " + ", ".join(f"`{p}`" for p in open_params) + " not listed in `initially:`"
        return Message(cls.code, text)


class W0104(Code, name="double-effect", summary="an action that assigns the same fluent instance twice"):
    @classmethod
    def twice(cls, action: str, target: str) -> Message:
        return Message(cls.code, f"action `{action}` assigns `{target}` twice")


class W0105(Code, name="online-nondeterminism", summary="a `pick` or `choose` outside `solve`/`search`"):
    @classmethod
    def pick(cls) -> Message:
        return Message(cls.code, "`pick` outside `solve` or `search` takes the first value that works now")

    @classmethod
    def choose(cls) -> Message:
        return Message(cls.code, "`choose` outside `solve` or `search` takes the first alternative that works now")


class W0106(Code, name="busy-loop", summary="a `while (true)` loop whose body executes no action"):
    @classmethod
    def busy_loop(cls) -> Message:
        return Message(cls.code, "this `while (true)` loop never executes an action, a test or an assignment")


class W0107(Code, name="constant-condition", summary="a condition that is always true or always false"):
    @classmethod
    def constant(cls, what: str, value: bool) -> Message:
        """`what` names the condition ("`if` condition")."""
        return Message(cls.code, f"{what} is always {'true' if value else 'false'}")


class W0108(Code, name="unreachable-else", summary="an `else` branch that can never run"):
    @classmethod
    def else_never_runs(cls) -> Message:
        return Message(cls.code, "the `else` branch can never run")

    @classmethod
    def if_never_runs(cls) -> Message:
        return Message(cls.code, "the `if` branch can never run, only the `else` branch")


class W0109(Code, name="solve-without-choice", summary="a `solve` whose program has no `pick` or `choose`"):
    @classmethod
    def no_choice(cls) -> Message:
        return Message(cls.code, "`solve` has nothing to decide: its program has no `pick` or `choose`")


class W0110(Code, name="mixed-precedence", summary="an operator chain that the original golog++ reads differently"):
    @classmethod
    def reads_as(cls, shape: str) -> Message:
        return Message(cls.code, f"the original C++ golog++ reads this as `{shape}`")


class W0111(Code, name="shadowed-symbol", summary="a parameter or variable named like a domain symbol"):
    @classmethod
    def shadows(cls, what: str, name: str) -> Message:
        """`what` is "parameter" or "variable"."""
        return Message(cls.code, f"{what} `{name}` shadows the symbol `{name}`")


class W0112(
    Code,
    name="quantifier-scope",
    summary="a quantifier whose body runs on into operands that do not use its variable",
):
    @classmethod
    def runs_on(cls, rest: str, head: str, variable: str) -> Message:
        return Message(cls.code, f"`{rest}` is part of the `{head}` body but does not use `{variable}`")


class W0113(
    Code,
    name="shared-sensing-result",
    summary="two exogenous functions in one `senses:` section: both get the same value",
):
    @classmethod
    def shared(cls, call: str, first: str) -> Message:
        return Message(cls.code, f"`{call}` gets the same value as `{first}` in this `senses:` section")


class W0114(
    Code,
    name="unended-activity",
    summary="a `start` whose activity no `end`, `finish`, `fail` or `cancel` refers to",
):
    @classmethod
    def never_ended(cls, started: str, action: str) -> Message:
        return Message(
            cls.code,
            f"`{started}` is started, but the program has no `end`, `finish`, `fail` or `cancel` of `{action}`",
        )


class W0115(Code, name="busy-wait", summary="a `while` loop whose body cannot change what its condition reads"):
    @classmethod
    def busy_waits(cls) -> Message:
        return Message(cls.code, "this `while` loop busy-waits: nothing in its body changes what its condition reads")

    @classmethod
    def does_not_wait(cls) -> Message:
        return Message(
            cls.code,
            "this `while` loop does not wait for its condition: its body does nothing, so it ends at once",
        )


class W0116(Code, name="unused-suppression", summary="a `// gpp: allow` comment that allows nothing"):
    @classmethod
    def unused(cls, name: str, code: str, where: str) -> Message:
        """`where` is the suppression's reach ("on this line")."""
        return Message(cls.code, f"unused suppression: no `{name}` ({code}) to allow {where}")


class W0117(Code, name="invalid-suppression", summary="a `// gpp: allow` comment naming an error or an unknown lint"):
    @classmethod
    def names_nothing(cls) -> Message:
        return Message(cls.code, "a suppression that names no lint")

    @classmethod
    def not_a_lint(cls, text: str, error: bool) -> Message:
        """`error`: the named code is an error (else a run-time problem)."""
        return Message(
            cls.code, f"`{text}` is {'an error' if error else 'a run-time problem'}: only lints can be allowed"
        )

    @classmethod
    def unknown(cls, text: str) -> Message:
        return Message(cls.code, f"unknown lint `{text}` in a suppression")


class W0118(
    Code,
    name="goal-paid-again",
    summary="a `solve` reward that pays a goal again for each step made after it holds",
):
    @classmethod
    def paid_again(cls, goal: str, bonus: str) -> Message:
        return Message(
            cls.code, f"the reward pays `{bonus}` again after this step: `{goal}` still holds in the state it makes"
        )


class W0119(
    Code,
    name="unwatched-activity",
    summary="a `during` whose body waits for a condition and then cancels the activity",
):
    @classmethod
    def hangs(cls, condition: str, action: str) -> Message:
        return Message(
            cls.code,
            f"this `during` waits for `{condition}` even after `{action}` has ended: "
            "if the activity ends or fails first, the program waits for ever",
        )


class W0120(
    Code,
    name="unrun-watch-body",
    summary="a `during ... until` inside `solve` or `search` whose body never runs",
):
    @classmethod
    def never_runs(cls) -> Message:
        return Message(cls.code, "the body of this `during ... until` never runs: it is planned by `solve` or `search`")
