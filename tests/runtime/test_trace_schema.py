"""The trace format is documented and versioned: gpp/trace.schema.json (JSON Schema, draft
2020-12, shipped in the package) describes every record the executor writes, agrees with the
event dataclasses of gpp.runtime.events field for field, and every event survives its JSON
encoding unchanged."""

from __future__ import annotations

import dataclasses
import json
import unittest.mock
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gpp.platform.base import MessageDropped, PlatformConfig, PlatformWarning, Problem, ProgramInterface
from gpp.platform.dummy import DummyPlatform
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import (
    ABSENT,
    EVENT_TYPES,
    TRACE_SCHEMA_VERSION,
    ErrorEvent,
    EventBase,
    JsonValue,
    TraceEvent,
    decode,
    encode,
    load_schema,
    to_json_dict,
)
from gpp.runtime.executor import RunStatus
from gpp.runtime.state import ActivityStatus
from tests.support.budget import examples

ROOT = Path(__file__).resolve().parents[2]
PROGRAMS = ROOT / "tests" / "programs"
ERRORS = ROOT / "tests" / "runtime_errors"
EXAMPLES = ROOT / "examples"
SCENARIOS = ROOT / "tests" / "planner_scenarios"


@pytest.fixture(scope="module")
def schema() -> dict[str, Any]:
    schema = load_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return schema


@pytest.fixture(scope="module")
def validator(schema: dict[str, Any]) -> jsonschema.Draft202012Validator:
    return jsonschema.Draft202012Validator(schema)


# ---------------------------------------------------------------- the schema itself


def test_the_schema_is_versioned_and_shipped_in_the_package(schema: dict[str, Any]) -> None:
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert schema["$id"] == f"urn:gpp:trace-schema:{TRACE_SCHEMA_VERSION}"
    assert f"version {TRACE_SCHEMA_VERSION}" in schema["title"]
    assert (ROOT / "gpp" / "trace.schema.json").is_file()
    major, minor = TRACE_SCHEMA_VERSION.split(".")
    assert major.isdigit() and minor.isdigit()
    doc = (ROOT / "docs" / "trace.md").read_text(encoding="utf-8")
    assert f"version {TRACE_SCHEMA_VERSION}" in doc
    for kind in EVENT_TYPES:
        assert f"### `{kind}`" in doc, kind


def test_schema_and_event_dataclasses_agree(schema: dict[str, Any]) -> None:
    defs = schema["$defs"]
    assert schema["properties"]["event"]["enum"] == list(EVENT_TYPES)
    assert [ref["$ref"] for ref in schema["oneOf"]] == [f"#/$defs/{kind}" for kind in EVENT_TYPES]
    for kind, cls in EVENT_TYPES.items():
        record = defs[kind]
        fields = [f for f in dataclasses.fields(cls) if f.name != "t"]
        # Every field is a property (in the same order), and there is no other property.
        assert list(record["properties"]) == ["t", "event", *(f.name for f in fields)], kind
        assert record["properties"]["event"] == {"const": kind}
        optional = {f.name for f in fields if f.metadata.get("optional")}
        assert set(record["required"]) == {"t", "event"} | {f.name for f in fields} - optional, kind
        # An optional field has a default; a required one has none.
        for f in fields:
            has_default = f.default is not dataclasses.MISSING or f.default_factory is not dataclasses.MISSING
            assert has_default == (f.name in optional), (kind, f.name)
        assert record["additionalProperties"] is False


def test_schema_enums_are_the_interpreters_values(schema: dict[str, Any]) -> None:
    defs = schema["$defs"]
    assert defs["finish"]["properties"]["status"]["enum"] == [s.value for s in RunStatus]
    terminal = [s.value for s in ActivityStatus if s.terminal]
    assert defs["update"]["properties"]["status"]["enum"] == terminal
    assert defs["end"]["properties"]["status"]["enum"] == terminal


# ---------------------------------------------------------------- real traces


# Event kinds that the dummy and sim platforms never cause, and those only a split trace has
# (tests/runtime/test_trace_split.py validates its parts).
ROBOT_ONLY = {"notice"}
SPLIT_ONLY = {"snapshot"}


def _runs(tmp_path: Path) -> Iterator[tuple[str, Path]]:
    """Trace files of real runs: scenarios, sim, planning and re-planning, errors, blocked,
    interrupted, a program that does not fit its platform."""
    runs: list[tuple[str, Path, RunOptions]] = [
        *((p.stem, p, RunOptions()) for p in sorted(PROGRAMS.glob("*.gpp"))),
        ("exog_sensing", EXAMPLES / "exog_sensing.gpp", RunOptions()),
        ("blocks_planning", EXAMPLES / "blocks_planning.gpp", RunOptions()),
        ("sim_blocksworld", EXAMPLES / "blocksworld_faults.gpp", RunOptions(platform="sim")),
        # Recorded with steps (--trace-steps): `step` records, with procedure calls and a pick's local.
        ("steps", EXAMPLES / "blocksworld.gpp", RunOptions(platform="sim", trace_steps=True)),
        ("steps_pick", PROGRAMS / "choose_pick.gpp", RunOptions(trace_steps=True)),
        ("sim_does_not_fit", EXAMPLES / "blocks_planning.gpp", RunOptions(platform="sim")),
        ("replan", SCENARIOS / "blocks.gpp", RunOptions(platform_options={"scenario": SCENARIOS / "knocked.toml"})),
        (
            "search_replan",
            SCENARIOS / "search_blocks.gpp",
            RunOptions(platform_options={"scenario": SCENARIOS / "knocked.toml"}),
        ),
        ("error", ERRORS / "division_by_zero.gpp", RunOptions()),
        ("blocked", ERRORS / "blocked_test.gpp", RunOptions()),
        ("blocked_precondition", ERRORS / "blocked_precondition.gpp", RunOptions()),
        ("infeasible", ERRORS / "blocked_solve_infeasible.gpp", RunOptions()),
        ("timeout", ERRORS / "timeout.gpp", RunOptions(time_limit=5)),
        ("recursion", ERRORS / "runaway_recursion.gpp", RunOptions()),
    ]
    for name, program, options in runs:
        options.trace = tmp_path / f"{name}.jsonl"
        run_program(program, options)
        yield name, options.trace

    def ctrl_c(event: TraceEvent) -> None:
        if event.EVENT == "start":
            raise KeyboardInterrupt

    trace = tmp_path / "interrupted.jsonl"
    run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(trace=trace), listeners=[ctrl_c])
    yield "interrupted", trace

    # What a robot's platform reports about messages it dropped (tests/platform/ros2 makes
    # these against real publishers): the dummy, reporting them as a robot would.
    class Dropping(DummyPlatform):
        def attach(self, interface: ProgramInterface) -> list[Problem]:
            problems = super().attach(interface)
            self.queue.put(MessageDropped("/events", "knock", "the message has no field `who`", None, None, 3), 0.0)
            self.queue.put(PlatformWarning("a publisher can lose messages"), 0.0)
            return problems

    def dropping(options: RunOptions, check: Any, path: Path) -> DummyPlatform:
        return Dropping.create(PlatformConfig(path))

    trace = tmp_path / "dropped.jsonl"
    with unittest.mock.patch("gpp.run.runner.make_platform", dropping):
        run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(trace=trace))
    yield "dropped", trace

    # The operator console's records: an event sent through a hub and a Start, given before
    # the run waits for it.
    from tests.support.traces import operator_trace

    yield "operator", operator_trace(tmp_path)


@pytest.mark.slow
def test_every_record_of_real_traces_is_valid(validator: jsonschema.Draft202012Validator, tmp_path: Path) -> None:
    seen: set[str] = set()
    for name, trace in _runs(tmp_path):
        lines = trace.read_text(encoding="utf-8").splitlines()
        assert lines, name
        for line in lines:
            record = json.loads(line)
            errors = [e.message for e in validator.iter_errors(record)]
            assert not errors, (name, line, errors)
            seen.add(record["event"])
            assert encode(decode(line)) == line
        assert json.loads(lines[-1])["event"] == "finish", name
    # Every kind of event appears in these traces, but for those only a robot's platform
    # writes (tests/platform/ros2 validates its `notice` records against the schema).
    assert seen == set(EVENT_TYPES) - ROBOT_ONLY - SPLIT_ONLY


def test_the_schema_rejects_what_the_executor_never_writes(validator: jsonschema.Draft202012Validator) -> None:
    ok = {"t": 0.0, "event": "cancel", "action": "a()", "id": 1}
    assert validator.is_valid(ok)
    assert not validator.is_valid({**ok, "event": "teleport"})
    assert not validator.is_valid({k: v for k, v in ok.items() if k != "id"})
    assert not validator.is_valid({**ok, "colour": "red"})
    assert not validator.is_valid({**ok, "t": -1.0})
    assert not validator.is_valid({"t": 0.0, "event": "error", "code": "R0001", "message": "m"})  # no `at`
    assert validator.is_valid({"t": 0.0, "event": "error", "code": "R0001", "message": "m", "at": None})
    assert not validator.is_valid({"t": 0.0, "event": "exog", "action": "a()", "precondition": True})


# ---------------------------------------------------------------- any event


def json_values() -> st.SearchStrategy[JsonValue]:
    names = st.text(min_size=1, max_size=8)
    scalars: st.SearchStrategy[JsonValue] = st.none() | st.booleans() | st.integers() | st.text(max_size=8)
    scalars = scalars | st.floats(allow_nan=False, allow_infinity=False)

    def extend(inner: st.SearchStrategy[JsonValue]) -> st.SearchStrategy[JsonValue]:
        lists: st.SearchStrategy[JsonValue] = st.lists(inner, max_size=3)
        symbols: st.SearchStrategy[JsonValue] = names.map(lambda n: {"symbol": n})
        compounds: st.SearchStrategy[JsonValue] = st.builds(
            lambda n, f: {"compound": n, "fields": f}, names, st.dictionaries(names, inner, max_size=3)
        )
        return lists | symbols | compounds

    return st.recursive(scalars, extend, max_leaves=8)


TEXT = st.text(max_size=12)
COUNT = st.integers(min_value=0, max_value=10**9)
ID = st.integers(min_value=1, max_value=10**6)
LOCATION = st.none() | st.from_regex(r"\A[a-z/]{1,10}\.gpp:[1-9][0-9]{0,3}:[1-9][0-9]{0,2}\Z")
TERMINAL = st.sampled_from([s.value for s in ActivityStatus if s.terminal])

FIELDS: dict[str, st.SearchStrategy[Any]] = {
    "schema_version": st.just(TRACE_SCHEMA_VERSION),
    "gpp_version": TEXT,
    "program": TEXT,
    "program_sha256": st.from_regex(r"\A[0-9a-f]{64}\Z"),
    "platform": TEXT,
    "world": st.none() | TEXT,
    "scenario": st.none() | TEXT,
    "seed": st.none() | st.integers(),
    "started": st.datetimes(timezones=st.timezones()).map(lambda d: d.isoformat()),
    "action": TEXT,
    "id": ID,
    "mapped": TEXT,
    "args": st.dictionaries(TEXT, json_values(), max_size=3),
    "at": LOCATION,
    "silent": st.booleans(),
    "reason": st.none() | TEXT,
    "result": st.just(ABSENT) | json_values(),
    "hook": st.sampled_from(["end", "finish", "fail", "call", "during"]),
    "unhandled": st.booleans(),
    "precondition": st.booleans(),
    "fluent": TEXT,
    "value": json_values(),
    "kind": st.sampled_from(["solve", "search"]),
    "feasible": st.booleans(),
    "horizon": COUNT,
    "policy": st.lists(TEXT, max_size=4).map(tuple),
    "nodes": COUNT,
    "cache_hits": COUNT,
    "pruned": COUNT,
    "reward_evaluations": COUNT,
    "seconds": st.floats(min_value=0, max_value=1e4),
    "statement": TEXT,
    "condition": TEXT,
    "resumed": st.booleans(),
    "message": TEXT,
    "actions": COUNT,
    "failures": COUNT,
    "unhandled_failures": st.none() | COUNT,
    "exog_events": COUNT,
}
# Fields whose values depend on the event kind.
BY_KIND: dict[tuple[str, str], st.SearchStrategy[Any]] = {
    ("update", "status"): TERMINAL,
    ("end", "status"): TERMINAL,
    ("finish", "status"): st.sampled_from([s.value for s in RunStatus]),
    ("plan", "value"): st.floats(allow_nan=False, allow_infinity=False),
    ("replan", "value"): st.floats(allow_nan=False, allow_infinity=False),
}


def _event(kind: str, cls: type[EventBase]) -> st.SearchStrategy[EventBase]:
    fields = {
        f.name: BY_KIND.get((kind, f.name), FIELDS.get(f.name, st.nothing()))
        for f in dataclasses.fields(cls)
        if f.name != "t"
    }
    if kind == "error":  # `code` and `at` come together (an interrupt has neither)
        fields.pop("at")
        fields.pop("code")
        pair = st.just((None, ABSENT)) | st.tuples(st.from_regex(r"\AR[0-9]{4}\Z"), LOCATION)
        return st.builds(
            lambda t, pair, **rest: ErrorEvent(t=t, code=pair[0], at=pair[1], **rest),
            st.floats(min_value=0, max_value=1e9),
            pair,
            **fields,
        )
    return st.builds(cls, t=st.floats(min_value=0, max_value=1e9), **fields)


EVENTS: st.SearchStrategy[EventBase] = st.one_of([_event(kind, cls) for kind, cls in EVENT_TYPES.items()])


@settings(max_examples=examples(300), deadline=None)
@given(EVENTS)
def test_every_event_round_trips_through_its_json_line(event: EventBase) -> None:
    line = encode(event)
    assert "\n" not in line
    assert decode(line) == event
    assert json.loads(line) == to_json_dict(event)
    assert list(json.loads(line))[:2] == ["t", "event"]


@settings(max_examples=examples(300), deadline=None)
@given(EVENTS)
def test_every_event_encodes_to_a_valid_record(validator: jsonschema.Draft202012Validator, event: EventBase) -> None:
    record = to_json_dict(event)
    errors = [e.message for e in validator.iter_errors(json.loads(json.dumps(record)))]
    assert not errors, (record, errors)
