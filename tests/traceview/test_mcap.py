"""`gpp trace mcap`: a run's trace as an MCAP file for Foxglove, read back with the `mcap`
package's own reader: every record in order on the channel of its kind, each channel with the
JSON Schema of its kind (made from gpp/trace.schema.json, in the subset Foxglove reads: no
`$ref`, one type per field), log times from the trace; a split trace converts as one run."""

from __future__ import annotations

import json
import os
from datetime import datetime
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from mcap.reader import make_reader

from bench import soak
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import EVENT_TYPES, HeaderEvent, encode, load_schema
from gpp.runtime.trace import TraceSplit, trace_parts
from gpp.traceview.mcapfile import record_schemas, schema_name
from gpp.traceview.model import load_trace
from tests.support.cli import run

ROOT = Path(__file__).resolve().parents[2]


def foxglove_problems(schema: dict[str, Any], path: str = "") -> list[str]:
    """What Foxglove would refuse in a channel's JSON Schema: it reads an object's
    `properties`, each field's one `type` (or a `oneOf` of numbers) and an array's `items`, and
    refuses the channel on anything else (foxglove/studio, mcap-support/parseJsonSchema.ts)."""
    if schema.get("type") != "object" or not isinstance(schema.get("properties"), dict):
        return [f"{path or 'the record'}: not an object with properties"]
    problems = []
    for name, field in schema["properties"].items():
        where = f"{path}.{name}" if path else name
        kind = field.get("type")
        if kind == "object":
            problems += foxglove_problems(field, where)
        elif kind == "array":
            items = field.get("items", {})
            if items.get("type") == "object":
                problems += foxglove_problems(items, where)
            elif items.get("type") not in ("boolean", "string", "number", "integer"):
                problems.append(f"{where}: array items of type {items.get('type')!r}")
        elif kind not in ("boolean", "string", "number", "integer"):
            problems.append(f"{where}: type {kind!r}")
    return problems


def nullable(schema: Any) -> Any:
    """The schema with null allowed wherever it names a type: Foxglove types a field that may
    be null (`at`) by its other type."""
    if isinstance(schema, list):
        return [nullable(item) for item in schema]
    if not isinstance(schema, dict):
        return schema
    copy = {key: nullable(value) for key, value in schema.items()}
    if isinstance(copy.get("type"), str):
        copy["type"] = [copy["type"], "null"]
        if "const" in copy or "enum" in copy:
            copy["enum"] = [*copy.pop("enum", [copy.pop("const", None)]), None]
    return copy


def read_mcap(path: Path) -> list[tuple[Any, Any, Any]]:
    """(schema, channel, message) of every message, in the order they are in the file."""
    with path.open("rb") as file:
        return list(make_reader(file).iter_messages(log_time_order=False))


def check_conversion(trace: Path, mcap: Path, prefix: str = "/gpp") -> set[str]:
    """The MCAP file holds the run's records, one message each, in order, on the channel of
    its kind with that kind's schema, logged at the run's start plus the record's time; the
    record kinds it has."""
    events = load_trace(trace).events
    messages = read_mcap(mcap)
    assert [m.data.decode("utf-8") for _, _, m in messages] == [encode(e) for e in events]
    header = events[0]
    assert isinstance(header, HeaderEvent)
    start = int(datetime.fromisoformat(header.started).timestamp()) * 10**9
    schemas = record_schemas()
    sequence: dict[str, int] = {}
    for (schema, channel, message), event in zip(messages, events, strict=True):
        kind = event.EVENT
        assert channel.topic == f"{prefix}/{kind}"
        assert channel.message_encoding == "json"
        assert (schema.name, schema.encoding) == (schema_name(kind), "jsonschema")
        assert json.loads(schema.data) == schemas[kind]
        record = json.loads(message.data)
        validator = jsonschema.Draft202012Validator(nullable(schemas[kind]))
        errors = [e.message for e in validator.iter_errors(record)]
        assert not errors, (record, errors)
        assert message.log_time == message.publish_time == start + round(event.t * 10**9)
        assert message.sequence == sequence.get(kind, 0)
        sequence[kind] = message.sequence + 1
    # One channel per kind.
    assert len({c.id for _, c, _ in messages}) == len({e.EVENT for e in events})
    return set(sequence)


def test_each_kind_has_a_schema_foxglove_reads_made_from_the_trace_schema() -> None:
    trace_schema = load_schema()
    schemas = record_schemas()
    assert list(schemas) == list(EVENT_TYPES)
    golog_value = {"$ref": "#/$defs/value"}
    for kind, schema in schemas.items():
        jsonschema.Draft202012Validator.check_schema(schema)
        assert '"$ref"' not in json.dumps(schema), kind  # Foxglove does not follow references
        assert foxglove_problems(schema) == [], kind
        definition = trace_schema["$defs"][kind]
        # Every field, in order, but those holding any golog++ value, which the description names.
        untyped = [n for n, f in definition["properties"].items() if f.get("$ref") == golog_value["$ref"]]
        assert list(schema["properties"]) == [n for n in definition["properties"] if n not in untyped], kind
        assert schema["required"] == [n for n in definition["required"] if n not in untyped], kind
        for name in untyped:
            assert f"`{name}`" in schema["description"], (kind, name)
    # A reference is written out with what it refers to; a field that may be null has its other
    # type, a `const` or `enum` the type of its values; a map is an object without properties.
    start = schemas["start"]["properties"]
    assert start["t"] == {**trace_schema["$defs"]["time"], "type": "number"}
    assert start["at"]["type"] == "string" and start["silent"] == {**start["silent"], "type": "boolean"}
    assert start["args"]["properties"] == {} and schemas["end"]["properties"]["status"]["type"] == "string"
    change = schemas["end"]["properties"]["changes"]["items"]
    assert list(change["properties"]) == ["fluent"] and "`value`" in change["description"]


@pytest.mark.parametrize(
    ("name", "program", "options"),
    [
        ("sim", "examples/blocksworld_faults.gpp", RunOptions(platform="sim")),
        (
            "replan",
            "tests/planner_scenarios/blocks.gpp",
            RunOptions(platform_options={"scenario": ROOT / "tests/planner_scenarios/knocked.toml"}),
        ),
        ("exog", "tests/programs/exog_events.gpp", RunOptions()),
        ("sensing", "tests/programs/sensing.gpp", RunOptions()),
        ("error", "tests/runtime_errors/division_by_zero.gpp", RunOptions()),
    ],
)
def test_a_run_converts_record_for_record(tmp_path: Path, name: str, program: str, options: RunOptions) -> None:
    trace = tmp_path / f"{name}.jsonl"
    options.trace = trace
    run_program(ROOT / program, options)
    result = run("trace", "mcap", str(trace))
    mcap = tmp_path / f"{name}.mcap"
    records = len(trace.read_text(encoding="utf-8").splitlines())
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"wrote {mcap} ({records} records on ")
    kinds = check_conversion(trace, mcap)
    assert {"header", "start", "finish"} <= kinds or name == "error"


def test_a_split_trace_converts_as_one_run(tmp_path: Path) -> None:
    program = tmp_path / "loop.gpp"
    program.write_text(soak.PROGRAM, encoding="utf-8")
    trace = tmp_path / "run.jsonl"
    split = TraceSplit(max_bytes=3_000)
    outcome = run_program(program, RunOptions(args={"rounds": 200}, trace=trace, trace_split=split))
    assert outcome.ok
    parts = trace_parts(trace)
    assert len(parts) > 2
    out = tmp_path / "whole.mcap"
    assert run("trace", "mcap", str(trace), "-o", str(out), "--prefix", "/robot1/gpp").returncode == 0
    check_conversion(trace, out, "/robot1/gpp")
    # The run's records: those of every part but the header and snapshot each later part starts with.
    lines = sum(len(p.read_text(encoding="utf-8").splitlines()) for p in parts)
    assert len(read_mcap(out)) == lines - 2 * (len(parts) - 1)


def test_bad_options_are_usage_errors(tmp_path: Path) -> None:
    trace = ROOT / "tests/golden/trace/small.jsonl"
    for args, says in (
        (["--prefix", "gpp"], '--prefix must be a topic name such as /gpp or /robot1/gpp, not "gpp"'),
        (["--prefix", "/gpp/"], "--prefix must be a topic name"),
        (["-o", "-"], "--output: an MCAP file is binary; give a file name"),
        (["-o", str(tmp_path / "nowhere" / "run.mcap")], "does not exist"),
    ):
        result = run("trace", "mcap", str(trace), *args)
        assert result.returncode == 2 and result.stdout == "", args
        assert says in result.stderr and result.stderr.count("\n") == 1, (args, result.stderr)
    assert not list(tmp_path.rglob("*.mcap"))
    assert not [p for p in os.listdir(ROOT / "tests/golden/trace") if p.endswith(".mcap")]
