"""The dummy platform: scenario files (parsing and checking against the program), scripted
outcomes, durations and results, exogenous events on the virtual clock, exogenous function
answers, random mode, preemption."""

from __future__ import annotations

import itertools
import math
from pathlib import Path
from typing import Any

import pytest

import gpp.runtime.events as ev
from gpp.check import check_text
from gpp.model.types import NUMBER, STRING, Sym
from gpp.platform.base import Activity, ActivityUpdate, ExogOccurrence, PlatformError
from gpp.platform.dummy import DummyPlatform, Scenario, ScenarioError, random_value
from gpp.platform.values import ConversionError, to_value
from gpp.run.runner import RunOptions, RunSetupError, run_program
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.contract import program_interface
from gpp.runtime.executor import Executor, RunResult, RunStatus
from gpp.runtime.state import ActivityStatus, GroundAction
from gpp.runtime.trace import Recording, Trace
from gpp.syntax.directives import file_directives

ROOT = Path(__file__).resolve().parents[3]

PROGRAM = """
symbol domain Room = {hall, kitchen}
compound Pose { number x, number y }

Room fluent at() { initially: () = hall; }
number fluent temperature() { initially: () = null; }
number fluent visits() { initially: () = 0; }
number fluent bells() { initially: () = 0; }
string fluent last_bell() { initially: () = null; }

number exog_function thermometer(Room r, string unit);
string exog_function name();
Pose exog_function pose();
number exog_function ticket();

exog_action bell(string who) { effect: bells() = bells() + 1; last_bell() = who; }
exog_action visit(Room r, number n) {
mapping:
    "/visits" { room = r, count = n }
effect:
    visits() = visits() + n;
}

action go(Room r) { effect: at() = r; duration: [3, 8] }
action measure() { senses: temperature() = thermometer(at(), "C"); }
action say(string text) { }
"""


def scenario(**sections: Any) -> Scenario:
    return Scenario.from_data(sections)


def run(
    main: str, scn: Scenario | None = None, *, seed: int = 1, random_mode: bool = False
) -> tuple[RunResult, Recording]:
    check = check_text(PROGRAM + "\nprocedure main() {\n" + main + "\n}\n", lint=False)
    assert not check.errors, [d.message for d in check.diagnostics if d.is_error]
    platform = DummyPlatform(scn, seed, random_mode)
    trace = Recording()
    program = CompiledProgram(check.model)
    executor = Executor(program, platform, Trace(listeners=[trace]), timeout=1000)
    problems = platform.attach(program_interface(program))
    assert problems == []
    return executor.run(), trace


def attach_problems(scn: Scenario) -> list[str]:
    check = check_text(PROGRAM + '\nprocedure main() { say("hi"); }\n', lint=False)
    platform = DummyPlatform(scn)
    return [p.message for p in platform.attach(program_interface(CompiledProgram(check.model)))]


def events(trace: Recording, *kinds: type[ev.EventBase]) -> list[tuple[float, str, str]]:
    return [(r.t, r.EVENT, getattr(r, "action", "")) for r in trace.records if isinstance(r, kinds)]


# ---------------------------------------------------------------- parsing


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"actions": []}, "unknown section(s) actions (known: action, defaults, exog, exog_function)"),
        ({"action": [{"match": "go(hall)", "outcome": "crash"}]}, 'outcome must be final, fail or cancel, not "crash"'),
        ({"action": [{"match": "go(hall"}]}, "pattern 'go(hall' must look like"),
        ({"action": [{"match": "go(a b)"}]}, "pattern 'go(a b)' must look like"),
        ({"action": [{"match": "1go"}]}, "pattern '1go' must look like"),
        ({"action": [{"match": 'say("unclosed)'}]}, "must look like"),
        ({"action": [{"outcome": "fail"}]}, '`match = "name(args)"` is required'),
        ({"action": [{"match": "go(*)", "outcom": "fail"}]}, "unknown key(s) outcom (known: duration, match"),
        ({"action": [{"match": "go(*)", "times": 0}]}, "times must be a whole number >= 1, not 0"),
        ({"action": [{"match": "go(*)", "times": "2"}]}, 'times must be a whole number >= 1, not "2"'),
        (
            {"action": [{"match": "go(*)", "duration": -1}]},
            "duration must be a number of seconds from 0 to 1e9, not -1",
        ),
        ({"action": [{"match": "go(*)", "duration": "slow"}]}, 'must be a number of seconds from 0 to 1e9, not "slow"'),
        ({"action": {"match": "go(*)"}}, "`action` must be an array of tables, written [[action]]"),
        ({"defaults": {"duration": True}}, "[defaults] duration must be a number of seconds from 0 to 1e9, not true"),
        ({"defaults": {"speed": 1}}, "[defaults]: unknown key(s) speed"),
        (
            {"defaults": {"duration": math.nan}},
            "[defaults] duration must be a number of seconds from 0 to 1e9, not nan",
        ),
        (
            {"action": [{"match": "go(*)", "duration": 2e9}]},
            "#1 duration must be a number of seconds from 0 to 1e9, not 2000000000.0",
        ),
        (
            {"exog": [{"at": math.inf, "action": "bell"}]},
            "[[exog]] #1 at must be a number of seconds from 0 to 1e9, not inf",
        ),
        (
            {"exog": [{"at": 10**400, "action": "bell"}]},
            "[[exog]] #1 at must be a number of seconds from 0 to 1e9, not a whole number of 401 digits",
        ),
        ({"exog": [{"action": "bell"}]}, '`at = <seconds>` and `action = "name"` are required'),
        ({"exog": [{"at": 1, "action": "bell", "args": "ann"}]}, 'args must be a list of values, not "ann"'),
        ({"exog": [{"at": 1, "action": "ring the bell"}]}, "action must be the name of an exogenous action"),
        ({"exog_function": [{"name": "name"}]}, "`name` and `value` (or `values = [...]`) are required"),
        ({"exog_function": [{"name": "name", "values": []}]}, "values must be a non-empty list of answers"),
        ({"exog_function": [{"name": "name", "value": "a", "values": ["b"]}]}, "give either `value` or `values`"),
        ({"exog_function": [{"name": "name", "value": "a", "args": ["x"]}]}, "args must be a table"),
    ],
)
def test_bad_scenario_gives_a_clear_message(data: dict[str, Any], message: str) -> None:
    with pytest.raises(ScenarioError) as caught:
        Scenario.from_data(data, "s.toml")
    assert message in str(caught.value)
    assert str(caught.value).startswith("s.toml")


def test_scenario_entries_say_which_entry_is_wrong() -> None:
    data = {"action": [{"match": "go(*)"}, {"match": "say(*)", "outcome": "explode"}]}
    with pytest.raises(ScenarioError, match=r"s.toml: \[\[action\]\] #2: outcome"):
        Scenario.from_data(data, "s.toml")


def test_scenario_file_that_is_not_toml_or_missing(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("[[action]\nmatch = 1\n", encoding="utf-8")
    with pytest.raises(ScenarioError, match="is not valid TOML"):
        Scenario.load(bad)
    with pytest.raises(ScenarioError, match="cannot read scenario"):
        Scenario.load(tmp_path / "missing.toml")


def test_patterns_accept_spaces_strings_numbers_and_wildcards() -> None:
    s = scenario(action=[{"match": ' say( "hello, world" ) '}, {"match": "go( * )"}, {"match": "go"}])
    assert [(r.name, r.args) for r in s.actions] == [
        ("say", ('"hello, world"',)),
        ("go", ("*",)),
        ("go", None),
    ]
    rule = s.actions[0]
    assert rule.matches(GroundAction("say", ("hello, world",)))
    assert not rule.matches(GroundAction("say", ("hello world",)))


@pytest.mark.parametrize(
    ("pattern", "args", "matches"),
    [
        ("go(kitchen)", (Sym("kitchen"),), True),
        ("go(kitchen)", (Sym("hall"),), False),
        ("go(kitchen)", ("kitchen",), False),
        ("m(2)", (2.0,), True),
        ("m(2.5)", (2.5,), True),
        ("m(2)", (3,), False),
        ("m(true)", (True,), True),
        ("m(1)", (True,), False),
        ("m(null)", (None,), True),
        ('m("a\\"b")', ('a"b',), True),
        ("m(*, 3)", (Sym("x"), 3), True),
        ("m(*)", (1, 2), False),
        ("m()", (), True),
    ],
)
def test_pattern_arguments_match_values_by_type(pattern: str, args: tuple[Any, ...], matches: bool) -> None:
    [rule] = scenario(action=[{"match": pattern}]).actions
    assert rule.matches(GroundAction(rule.name, args)) is matches


# ---------------------------------------------------------------- checking against the program


@pytest.mark.parametrize(
    ("data", "problem"),
    [
        ({"action": [{"match": "fly(*)"}]}, "scenario: no action `fly` in the program (pattern `fly(*)`)"),
        ({"exog": [{"at": 1, "action": "storm"}]}, "scenario: no exogenous action `storm` in the program"),
        ({"exog": [{"at": 1, "action": "bell", "args": []}]}, "`bell` takes 1 argument(s), the scenario gives 0"),
        ({"exog": [{"at": 1, "action": "bell", "args": [3]}]}, "`bell` at 1 s: expected a string, got 3"),
        ({"exog": [{"at": 1, "action": "visit", "args": ["garden", 1]}]}, "garden is not in domain `Room`"),
        ({"exog_function": [{"name": "barometer", "value": 1}]}, "no exogenous function `barometer`"),
        ({"exog_function": [{"name": "name", "value": 7}]}, "an answer of `name`: expected a string, got 7"),
        ({"exog_function": [{"name": "pose", "value": [1, 2]}]}, "expected a table for `Pose`"),
        (
            {"exog_function": [{"name": "thermometer", "args": {"room": "hall"}, "value": 1}]},
            "`thermometer` has no parameter `room` (parameters: r, unit)",
        ),
        ({"action": [{"match": "measure()", "result": "warm"}]}, "the result for `measure()`: expected a number"),
        ({"action": [{"match": "say(*)", "result": 1}]}, "`say(*)` gives a result, but `say` senses nothing"),
        # docs/semantics.md, "Numbers": no NaN, infinity or whole number beyond ±1.8e308 comes in.
        (
            {"action": [{"match": "measure()", "result": math.nan}]},
            "scenario: the result for `measure()`: expected a number, got NaN (not a number)",
        ),
        (
            {"exog_function": [{"name": "thermometer", "value": -math.inf}]},
            "scenario: an answer of `thermometer`: -inf is beyond the range of numbers"
            " (numbers range from -1.8e308 to 1.8e308)",
        ),
        (
            {"exog": [{"at": 1, "action": "visit", "args": ["hall", 10**309]}]},
            "scenario: `visit` at 1 s: a whole number of 310 digits is beyond the range of numbers"
            " (numbers range from -1.8e308 to 1.8e308)",
        ),
    ],
)
def test_scenario_that_does_not_fit_the_program_is_reported_when_attached(data: dict[str, Any], problem: str) -> None:
    problems = attach_problems(Scenario.from_data(data))
    assert len(problems) == 1 and problem in problems[0], problems


def test_scenario_that_does_not_fit_stops_run_program_with_a_diagnostic(tmp_path: Path) -> None:
    program = tmp_path / "p.gpp"
    program.write_text("// scenario: s.toml\nexog_action ping() { }\nprocedure main() { }\n", encoding="utf-8")
    (tmp_path / "s.toml").write_text('[[exog]]\nat = 1\naction = "pong"\n', encoding="utf-8")
    outcome = run_program(program, RunOptions(record=True))
    assert outcome.result is None and not outcome.ok
    [d] = [d for d in outcome.diagnostics if d.is_error]
    assert d.code == "R0007" and d.message == "scenario: no exogenous action `pong` in the program"
    # At the scenario's entry, with a did-you-mean from the program's exogenous actions.
    assert (d.span.source.path, d.span.text, d.span.start) == (str(tmp_path / "s.toml"), "[[exog]]", 0)
    assert d.help == "did you mean `ping`?"
    assert outcome.recording is not None and isinstance(outcome.recording.records[-1], ev.FinishEvent)


def test_bad_scenario_file_is_a_setup_error(tmp_path: Path) -> None:
    program = tmp_path / "p.gpp"
    program.write_text("// scenario: s.toml\nprocedure main() { }\n", encoding="utf-8")
    (tmp_path / "s.toml").write_text("[surprise]\n", encoding="utf-8")
    assert file_directives(program) == {"scenario": "s.toml"}
    with pytest.raises(RunSetupError, match="unknown section"):
        run_program(program, RunOptions(record=True))


def test_pattern_with_the_wrong_number_of_arguments_stops_the_run_at_the_action() -> None:
    result, _ = run("go(kitchen);", scenario(action=[{"match": "go(kitchen, fast)", "outcome": "fail"}]))
    assert result.status is RunStatus.ERROR
    [d] = result.diagnostics
    assert d.code == "R0007" and d.span.text == "go(kitchen);"
    assert "pattern `go(kitchen, fast)` has 2 argument(s), `go` takes 1" in d.message


# ---------------------------------------------------------------- outcomes


def test_activity_ends_final_after_its_minimum_duration_by_default() -> None:
    result, trace = run('go(kitchen); say("x");')
    assert events(trace, ev.UpdateEvent) == [(3.0, "update", "go(kitchen)"), (4.0, "update", 'say("x")')]
    assert result.platform_time == 4.0


def test_default_duration_from_the_scenario() -> None:
    result, _ = run('go(kitchen); say("x");', scenario(defaults={"duration": 0.5}))
    assert result.platform_time == 1.0


def test_scripted_outcomes_durations_and_times() -> None:
    scn = scenario(
        action=[
            {"match": "say(*)", "outcome": "fail", "duration": 2, "times": 2},
            {"match": 'say("bye")', "outcome": "cancel"},
            {"match": "go(kitchen)", "duration": 10},
        ]
    )
    result, trace = run('say("a"); say("b"); say("c"); say("bye"); go(kitchen);', scn)
    statuses = [(r.action, r.status, r.t) for r in trace.of(ev.UpdateEvent)]
    assert statuses == [
        ('say("a")', "failed", 2.0),
        ('say("b")', "failed", 4.0),
        ('say("c")', "final", 5.0),
        ('say("bye")', "cancelled", 6.0),
        ("go(kitchen)", "final", 16.0),
    ]
    assert result.failures == 2 and result.status is RunStatus.FINISHED


def test_first_matching_rule_wins() -> None:
    scn = scenario(action=[{"match": "go(kitchen)", "outcome": "fail"}, {"match": "go(*)", "duration": 1}])
    _, trace = run("go(kitchen); go(hall);", scn)
    assert [(r.action, r.status) for r in trace.of(ev.UpdateEvent)] == [
        ("go(kitchen)", "failed"),
        ("go(hall)", "final"),
    ]


def test_sensing_result_only_on_success() -> None:
    scn = scenario(
        action=[{"match": "measure()", "result": 21.5, "times": 1}, {"match": "measure()", "outcome": "fail"}]
    )
    result, trace = run("measure(); measure();", scn)
    [sense] = trace.of(ev.SenseEvent)
    assert sense.value == 21.5 and sense.fluent == "temperature()"
    assert [r.result for r in trace.of(ev.UpdateEvent)] == [21.5, ev.ABSENT]
    assert result.status is RunStatus.FINISHED


# ---------------------------------------------------------------- exogenous events


def test_exog_events_arrive_at_their_times_in_order_with_activity_updates() -> None:
    scn = scenario(
        exog=[
            {"at": 7, "action": "bell", "args": ["cid"]},
            {"at": 1, "action": "bell", "args": ["ann"]},
            {"at": 3, "action": "visit", "args": ["kitchen", 2]},
            {"at": 3, "action": "bell", "args": ["bob"]},
        ],
        action=[{"match": "say(*)", "duration": 5}],
    )
    result, trace = run('say("hello"); test(bells() == 3);', scn)
    assert events(trace, ev.ExogEvent, ev.UpdateEvent) == [
        (1.0, "exog", 'bell("ann")'),
        (3.0, "exog", "visit(kitchen,2)"),
        (3.0, "exog", 'bell("bob")'),
        (5.0, "update", 'say("hello")'),
        (7.0, "exog", 'bell("cid")'),
    ]
    assert result.status is RunStatus.FINISHED and result.exog_events == 4


def test_exog_event_waits_until_the_program_reaches_its_time() -> None:
    scn = scenario(exog=[{"at": 50, "action": "visit", "args": ["hall", 3]}])
    result, trace = run("test(visits() > 0);", scn)
    assert result.status is RunStatus.FINISHED and result.platform_time == 50.0
    assert trace.of(ev.ExogEvent)[0].t == 50.0


# ---------------------------------------------------------------- exogenous functions


def _attached(scn: Scenario) -> DummyPlatform:
    check = check_text(PROGRAM + '\nprocedure main() { say("hi"); }\n', lint=False)
    platform = DummyPlatform(scn)
    assert platform.attach(program_interface(CompiledProgram(check.model))) == []
    return platform


def test_exog_function_answers_by_arguments() -> None:
    platform = _attached(
        scenario(
            exog_function=[
                {"name": "thermometer", "args": {"r": "kitchen"}, "value": 21},
                {"name": "thermometer", "args": {"r": "hall", "unit": "F"}, "value": 60},
                {"name": "thermometer", "value": 18},
            ]
        )
    )

    def ask(room: str, unit: str) -> object:
        return platform.exog_function("thermometer", {"r": Sym(room), "unit": unit}, NUMBER, None)

    assert ask("kitchen", "C") == 21
    assert ask("hall", "F") == 60
    assert ask("hall", "C") == 18


def test_exog_function_sequence_is_given_in_order_and_the_last_answer_repeats() -> None:
    platform = _attached(scenario(exog_function=[{"name": "ticket", "values": [1, 2, 3]}]))
    answers = [platform.exog_function("ticket", {}, NUMBER, None) for _ in range(5)]
    assert answers == [1, 2, 3, 3, 3]


def test_exog_function_answers_of_structured_types() -> None:
    platform = _attached(scenario(exog_function=[{"name": "pose", "value": {"x": 1, "y": 2.5}}]))
    pose_type = CompiledProgram(check_text(PROGRAM, lint=False).model).model.globals["pose"].type
    assert pose_type is not None
    value = platform.exog_function("pose", {}, pose_type, None)
    assert value is not None and show_fields(value) == {"x": 1, "y": 2.5}


def show_fields(value: object) -> dict[str, object]:
    from gpp.runtime.values import CompoundValue

    assert isinstance(value, CompoundValue)
    return dict(value.fields)


def test_exog_function_without_an_answer_is_a_platform_error() -> None:
    platform = _attached(scenario())
    with pytest.raises(PlatformError, match=r"no answer for `name\(\)`"):
        platform.exog_function("name", {}, STRING, None)


def test_exog_function_used_by_the_program_is_asked_each_time() -> None:
    scn = scenario(exog_function=[{"name": "ticket", "values": [5, 6]}])
    result, trace = run("visits() = ticket(); visits() = visits() + ticket();", scn)
    assert [r.value for r in trace.of(ev.AssignEvent)] == [5, 11]
    assert result.status is RunStatus.FINISHED


def test_to_value_converts_toml_values_to_golog_values() -> None:
    assert to_value("kitchen", None) == "kitchen"
    assert to_value({"null": True}, NUMBER) is None
    with pytest.raises(ConversionError, match="expected a number, got true"):
        to_value(True, NUMBER)


# ---------------------------------------------------------------- clock, preemption


def _activity(i: int, name: str = "say") -> Activity:
    return Activity(i, GroundAction(name, ("x",)), name, {"text": "x"})


def test_wait_jumps_to_the_next_happening_and_not_past_the_deadline() -> None:
    platform = DummyPlatform(scenario(defaults={"duration": 4}))
    platform.start(_activity(1))
    assert platform.wait(3) is False and platform.now() == 3.0
    assert platform.live()
    assert platform.wait(None) is True and platform.now() == 4.0
    [(t, update)] = platform.queue.drain()
    assert t == 4.0 and isinstance(update, ActivityUpdate) and update.status is ActivityStatus.FINAL
    # Nothing is scheduled any more: nothing can arrive, and waiting without a deadline does not
    # move the clock; waiting until a deadline (a program waiting for the clock) lets time pass.
    assert platform.wait(None) is False and platform.now() == 4.0
    assert not platform.live()
    assert platform.wait(100) is False and platform.now() == 100.0


def test_preempt_cancels_a_scheduled_activity_at_once() -> None:
    platform = DummyPlatform(scenario(defaults={"duration": 4}))
    platform.start(_activity(1))
    platform.start(_activity(2))
    platform.preempt(_activity(1))
    [(t, update)] = platform.queue.drain()
    assert t == 0.0 and isinstance(update, ActivityUpdate)
    assert (update.activity_id, update.status, update.reason) == (1, ActivityStatus.CANCELLED, "preempted")
    # The scheduled end of the preempted activity never arrives; the other one does.
    assert platform.wait(None) is True
    assert [(e.activity_id, e.status) for _, e in platform.queue.drain() if isinstance(e, ActivityUpdate)] == [
        (2, ActivityStatus.FINAL)
    ]
    assert platform.wait(None) is False
    # Preempting an activity that has already ended changes nothing.
    platform.preempt(_activity(2))
    assert len(platform.queue) == 0


def test_cancel_in_a_program_preempts_the_activity() -> None:
    result, trace = run("start(go(kitchen)); cancel(go(kitchen)); end(go(kitchen));")
    [update] = trace.of(ev.UpdateEvent)
    assert update.status == "cancelled" and update.reason == "preempted" and update.t == 0.0
    assert result.platform_time == 0.0


def test_scenario_rules_count_their_uses_per_platform() -> None:
    scn = scenario(action=[{"match": "say(*)", "outcome": "fail", "times": 1}])
    first, _ = run('say("a");', scn)
    second, _ = run('say("a");', scn)
    assert first.failures == 1 and second.failures == 1


# ---------------------------------------------------------------- random mode


def _comparable(records: list[ev.TraceEvent]) -> list[dict[str, object]]:
    return [{k: v for k, v in ev.to_json_dict(r).items() if k != "seconds"} for r in records]


def test_random_mode_is_reproducible_for_a_seed() -> None:
    main = 'go(kitchen); measure(); say(name()); test(bells() >= 2); visits() = thermometer(hall, "C");'
    a, trace_a = run(main, seed=7, random_mode=True)
    b, trace_b = run(main, seed=7, random_mode=True)
    c, trace_c = run(main, seed=8, random_mode=True)
    assert a.status is b.status is c.status is RunStatus.FINISHED
    assert _comparable(trace_a.records) == _comparable(trace_b.records)
    assert _comparable(trace_a.records) != _comparable(trace_c.records)
    assert a.exog_events >= 2


def test_random_values_have_the_requested_types() -> None:
    import random

    rng = random.Random(3)
    for _ in range(50):
        n = random_value(rng, NUMBER)
        assert isinstance(n, int) and -1000 <= n <= 1000
        s = random_value(rng, STRING)
        assert isinstance(s, str) and len(s) <= 16


def test_random_mode_durations_stay_within_the_action_duration() -> None:
    _, trace = run("go(kitchen); go(hall); go(kitchen);", random_mode=True, seed=4)
    starts = {r.id: r.t for r in trace.of(ev.StartEvent)}
    for update in trace.of(ev.UpdateEvent):
        assert 3 <= update.t - starts[update.id] <= 8


EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.gpp") if "world" not in file_directives(p))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_random_mode_runs_the_examples_to_completion(path: Path) -> None:
    outcome = run_program(
        path, RunOptions(record=True, time_limit=3600, timeout=600, platform_options={"random": True, "seed": 1})
    )
    assert outcome.result is not None
    assert outcome.result.status is RunStatus.FINISHED, [d.message for d in outcome.diagnostics if d.is_error]


def test_random_exog_events_keep_coming_while_the_program_waits() -> None:
    result, trace = run("test(visits() > 5000);", random_mode=True, seed=2)
    # Random `visit` events add up to 1000 visits each; events come every 0-2 s.
    assert result.status is RunStatus.FINISHED
    times = [r.t for r in trace.of(ev.ExogEvent)]
    assert times == sorted(times) and all(b - a <= 2.0 for a, b in itertools.pairwise(times))


def test_exog_event_objects_carry_parameter_order() -> None:
    scn = scenario(exog=[{"at": 0, "action": "visit", "args": ["kitchen", 4]}])
    platform = _attached(scn)
    assert platform.wait(None)
    [(_, event)] = platform.queue.drain()
    assert event == ExogOccurrence("visit", (Sym("kitchen"), 4))


def test_scenario_with_a_whole_number_too_long_for_toml_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "s.toml"
    path.write_text("[defaults]\nduration = " + "1" * 5000 + "\n", encoding="utf-8")
    with pytest.raises(ScenarioError, match="has a whole number beyond the range of numbers"):
        Scenario.load(path)
