"""Placeholders in mapped names (`"/{r}/navigate"`, gpp.platform.ros2.placeholders): `gpp check`
reports every placeholder the ros2 platform could not serve at the mapped name, without ROS;
a parameter that is a placeholder is used (no W0102) and binds an exogenous action's
parameter (no E0308); the runner fills the placeholders of the name a goal goes to; the
binding file's placeholders are checked when the program attaches. The two-robot example runs
against two robot processes in test_ros2_processes.py."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from gpp.model.declarations import fill_placeholders, placeholders_in
from gpp.model.types import Sym
from gpp.run.runner import RunOptions, run_program
from tests.support.cli import run

DOMAINS = """symbol domain Robot = {robot1, robot2}
number domain Id = {1, 2}
string domain Label = {"left", "right arm"}
"""


def check(tmp_path: Path, program: str) -> list[str]:
    """The concise R0007 lines `gpp check` reports for the program."""
    (tmp_path / "agent.gpp").write_text(DOMAINS + program + "procedure main() { }\n", encoding="utf-8")
    result = run("check", "--format", "concise", "agent.gpp", cwd=tmp_path)
    lines = [line for line in result.stdout.splitlines() if "R0007" in line or "W0102" in line or "E0308" in line]
    assert result.returncode == (1 if lines else 0), result.stdout + result.stderr
    return lines


@pytest.mark.parametrize(
    ("program", "expected"),
    [
        (
            'action go(Robot r) {\nmapping:\n    "/{robot}/go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the placeholder `{robot}` is not a parameter (its parameters: r)",
        ),
        (
            'action go(number n) {\nmapping:\n    "/robot{n}/go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the placeholder `{n}` is a parameter of type `number`, whose "
            "values are not known before the run: a placeholder takes a parameter of a domain, whose values make "
            "the names",
        ),
        (
            'action go(Label l) {\nmapping:\n    "/{l}/go" { }\n}\n',
            'agent.gpp:6:5: error[R0007] action `go`: the placeholder `{l}` takes the value "right arm" of domain '
            "`Label`: a part of a ROS name is letters, digits and `_`",
        ),
        (
            'action go(Id n) {\nmapping:\n    "/{n}/go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the placeholder `{n}` takes the value 1 of domain `Id`: it makes "
            '"/1/go", not a ROS name (a part begins with a letter or `_`)',
        ),
        (
            'action go(Robot r) {\nmapping:\n    "/{r}/go : {r}_msgs/action/Go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the type after `:` cannot have a placeholder",
        ),
        (
            'action go(Robot r) {\nmapping:\n    "/{r/go" { }\n}\n',
            'agent.gpp:6:5: error[R0007] action `go`: "/{r/go": a placeholder is a parameter\'s name in braces, '
            'such as "/{r}/navigate" (braces that do not pair, or are empty)',
        ),
        (
            'exog_action bumped(Robot r) {\nmapping:\n    "/{r}/bumper" { id = r }\n}\n',
            "agent.gpp:6:5: error[R0007] exogenous action `bumped`: parameter `r` is filled from the topic's name "
            "(the placeholder `{r}`), so the mapping cannot fill it from the message field `id` too",
        ),
        (
            'exog_action bumped(Robot r, number v) {\nmapping:\n    "/{x}/bumper" { data = v, id = r }\n}\n',
            "agent.gpp:6:5: error[R0007] exogenous action `bumped`: the placeholder `{x}` is not a parameter "
            "(its parameters: r, v)",
        ),
    ],
    ids=["unknown", "not-a-domain", "not-a-token", "leading-digit", "in-the-type", "malformed", "twice", "exog"],
)
def test_check_reports_each_placeholder_the_platform_cannot_serve(tmp_path: Path, program: str, expected: str) -> None:
    lines = check(tmp_path, program)
    assert [line for line in lines if "R0007" in line] == [expected]


def test_placeholders_of_domains_are_fine_and_use_their_parameters(tmp_path: Path) -> None:
    program = """action go(Robot r, Id n, number x) {
mapping:
    "/{r}/arm{n}/go" { x = x }
}
exog_action bumped(Robot r, number v) {
mapping:
    "/{r}/bumper" { data = v }
}
"""
    assert check(tmp_path, program) == []


def test_a_typed_mapping_with_placeholders_is_checked_once_against_its_type(tmp_path: Path) -> None:
    pytest.importorskip("rclpy")
    program = """action count(Robot r, number n) {
mapping:
    "/{r}/fib : test_msgs/action/Fibonacci" { ordr = n }
}
"""
    [line] = check(tmp_path, program)
    assert "agent.gpp:6:47" in line and '"/robot1/fib"' in line and "has no field `ordr` (its fields: order)" in line


def test_the_runner_fills_the_placeholders_of_the_mapped_name() -> None:
    assert placeholders_in("/{r}/arm{n}/{r}/go : pkg/action/Go") == ("r", "n")
    filled = fill_placeholders("/{r}/arm{n}/go : pkg/action/Go", {"r": Sym("robot1"), "n": 2.0})
    assert filled == "/robot1/arm2/go : pkg/action/Go"


def test_the_dummy_platform_sees_the_filled_name(tmp_path: Path) -> None:
    path = tmp_path / "agent.gpp"
    path.write_text(
        DOMAINS + 'action go(Robot r) {\nmapping:\n    "/{r}/go" { }\n}\n' + "procedure main() { go(robot2); }\n",
        encoding="utf-8",
    )
    from gpp.runtime.events import StartEvent

    outcome = run_program(path, RunOptions(record=True, platform="dummy"))
    assert outcome.recording is not None
    assert [e.mapped for e in outcome.recording.of(StartEvent)] == ["/robot2/go"]


# ---------------------------------------------------------------- the binding file, at attach


FUNCTION = (
    DOMAINS
    + """number exog_function level(Robot r);
procedure main() { }
"""
)


@pytest.mark.parametrize(
    ("binding", "expected"),
    [
        (
            '[exog_function.level]\ntopic = "/{robot}/battery : std_msgs/msg/Float64"\n',
            "binding file: [exog_function.level] topic: the placeholder `{robot}` is not a parameter "
            "(its parameters: r)",
        ),
        (
            '[exog_function.level]\ntopic = "/battery : std_msgs/msg/Float64"\n',
            "binding file: [exog_function.level]: `level` has parameters (r); a topic answers only a function whose "
            'parameters are placeholders of its name (such as "/{r}/battery"; use a service for other parameters)',
        ),
    ],
    ids=["unknown", "not-a-placeholder"],
)
def test_the_binding_files_placeholders_are_checked_at_attach(
    ros: Any, tmp_path: Path, binding: str, expected: str
) -> None:
    path = tmp_path / "agent.gpp"
    path.write_text(FUNCTION, encoding="utf-8")
    (tmp_path / "binding.toml").write_text(binding, encoding="utf-8")
    options = {"binding": str(tmp_path / "binding.toml")}
    outcome = run_program(path, RunOptions(platform="ros2", platform_options=options, timeout=10))
    messages = [d.message for d in outcome.diagnostics if d.severity.name.lower() == "error"]
    assert [m.replace(str(tmp_path) + "/", "") for m in messages] == [expected]


def test_a_binding_file_table_cannot_have_a_placeholder(tmp_path: Path) -> None:
    from gpp.platform.ros2.binding import Binding, BindingError

    path = tmp_path / "binding.toml"
    path.write_text('["/{r}/battery"]\nqos = { depth = 1 }\n', encoding="utf-8")
    with pytest.raises(BindingError) as raised:
        Binding.load(path)
    assert str(raised.value) == (
        f'{path}:1: ["/{{r}}/battery"]: a table of the binding file is for one ROS name and cannot have a '
        'placeholder: write a table for each name the mapping stands for, such as ["/robot1/navigate"]'
    )
