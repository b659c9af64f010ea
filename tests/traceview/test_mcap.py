"""`gpp trace mcap`: a run's trace as an MCAP file for Foxglove, read back with the `mcap`
package's own reader: every record in order on the channel of its kind, each channel with the
JSON Schema of its kind (made from gpp/trace.schema.json, no `$ref` left), log times from the
trace; a split trace converts as one run."""

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
        errors = [e.message for e in jsonschema.Draft202012Validator(schemas[kind]).iter_errors(record)]
        assert not errors, (record, errors)
        assert message.log_time == message.publish_time == start + round(event.t * 10**9)
        assert message.sequence == sequence.get(kind, 0)
        sequence[kind] = message.sequence + 1
    # One channel per kind.
    assert len({c.id for _, c, _ in messages}) == len({e.EVENT for e in events})
    return set(sequence)


def test_each_kind_has_a_standalone_schema_made_from_the_trace_schema() -> None:
    trace_schema = load_schema()
    schemas = record_schemas()
    assert list(schemas) == list(EVENT_TYPES)
    for kind, schema in schemas.items():
        jsonschema.Draft202012Validator.check_schema(schema)
        assert '"$ref"' not in json.dumps(schema), kind  # Foxglove does not follow references
        definition = trace_schema["$defs"][kind]
        assert list(schema["properties"]) == list(definition["properties"]), kind
        assert schema["required"] == definition["required"], kind
        assert schema["additionalProperties"] is False
    # A reference is written out with what it refers to, and a recursive one allows any value.
    time = schemas["start"]["properties"]["t"]
    assert time["type"] == "number" and time["minimum"] == 0
    value = schemas["sense"]["properties"]["value"]
    assert value["anyOf"][1]["items"] == {"description": trace_schema["$defs"]["value"]["description"]}


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
