"""A run's trace as an MCAP file (`gpp trace mcap`), to open in Foxglove beside a robot's
recording: one channel per record kind (`/gpp/start`, `/gpp/end`, ...), each message the
record's JSON line, each channel with the JSON Schema of its kind, and each message logged at
the run's start (the header's `started`) plus the record's `t`.

The schemas are made from the trace's one JSON Schema (gpp/trace.schema.json, checked field
for field against gpp.runtime.events), in the subset of JSON Schema Foxglove reads (it turns a
channel's schema into the field types its panels offer, and refuses the channel when a field
has a type it does not know): a kind's definition with every `$ref` written out in place;
each field with one `type` (boolean, string, number, integer, object, array): a field that may
be null has its other type, a `const` or `enum` the type of its values, an object its
`properties` (none for a map such as `args`); a field that holds any golog++ value (`value`,
`result`) has no one type and is left out, with a word in the schema's description.
"""

from __future__ import annotations

import copy
import json
from collections.abc import Iterable, Mapping
from datetime import datetime
from typing import IO, Any

from gpp.runtime.events import EVENT_TYPES, TRACE_SCHEMA_VERSION, HeaderEvent, TraceEvent, encode, load_schema

# What a channel's topic starts with unless the command says otherwise.
DEFAULT_PREFIX = "/gpp"
SCHEMA_ENCODING = "jsonschema"
MESSAGE_ENCODING = "json"


def schema_name(kind: str) -> str:
    """The MCAP schema name of a record kind: `gpp.trace.start`."""
    return f"gpp.trace.{kind}"


# The types Foxglove gives a JSON Schema field, and the keywords kept beside them.
FIELD_TYPES = ("boolean", "string", "number", "integer", "object", "array")
_KEPT = ("title", "description", "const", "enum", "minimum", "pattern", "format")


def record_schemas() -> dict[str, dict[str, Any]]:
    """Every record kind's JSON Schema as Foxglove reads it (see the module's docstring), in
    the trace's order."""
    schema = load_schema()
    definitions: Mapping[str, Any] = schema["$defs"]
    found: dict[str, dict[str, Any]] = {}
    for kind in EVENT_TYPES:
        standalone = _inline(definitions[kind], definitions, (kind,))
        typed = _typed(standalone)
        assert typed is not None and typed["type"] == "object"
        found[kind] = {
            "$schema": schema["$schema"],
            "title": f"gpp trace record `{kind}` (schema {TRACE_SCHEMA_VERSION})",
            **typed,
        }
    return found


def _typed(node: Mapping[str, Any]) -> dict[str, Any] | None:
    """A field's schema with one Foxglove type, or None when its values have no one type."""
    kind = _one_type(node)
    if kind is None:
        return None
    typed: dict[str, Any] = {key: node[key] for key in _KEPT if key in node}
    typed["type"] = kind
    if kind == "object":
        fields = {name: _typed(sub) for name, sub in node.get("properties", {}).items()}
        typed["properties"] = {name: sub for name, sub in fields.items() if sub is not None}
        untyped = ", ".join(f"`{name}`" for name, sub in fields.items() if sub is None)
        if untyped:
            note = f"Not typed here (any golog++ value): {untyped}."
            typed["description"] = f"{typed.get('description', '')} {note}".lstrip()
        required = [name for name in node.get("required", ()) if name in typed["properties"]]
        if required:
            typed["required"] = required
    elif kind == "array":
        items = _typed(node.get("items", {}))
        if items is None:
            return None
        typed["items"] = items
    return typed


def _one_type(node: Mapping[str, Any]) -> str | None:
    """The one type (other than null) a field's values have, if they have one."""
    declared = node.get("type")
    if isinstance(declared, list):
        others = [t for t in declared if t != "null"]
        declared = others[0] if len(others) == 1 else None
    if declared is None and "const" in node:
        declared = _json_type(node["const"])
    if declared is None and "enum" in node:
        kinds = {_json_type(v) for v in node["enum"]}
        declared = kinds.pop() if len(kinds) == 1 else None
    if declared is None:
        alternatives = node.get("anyOf", node.get("oneOf"))
        if isinstance(alternatives, list) and alternatives:
            kinds = {_one_type(a) for a in alternatives}
            declared = kinds.pop() if len(kinds) == 1 else None
            if declared in ("object", "array"):
                declared = None  # alternatives of different shapes
    return declared if declared in FIELD_TYPES else None


def _json_type(value: Any) -> str | None:
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "number"
    if isinstance(value, str):
        return "string"
    return None


def _inline(node: Any, definitions: Mapping[str, Any], expanding: tuple[str, ...]) -> Any:
    """`node` with each `{"$ref": "#/$defs/NAME"}` replaced by that definition (its sibling
    keys kept); a reference to a definition being written out already becomes `{}` (any
    value) with that definition's description."""
    if isinstance(node, list):
        return [_inline(item, definitions, expanding) for item in node]
    if not isinstance(node, dict):
        return node
    ref = node.get("$ref")
    rest = {key: _inline(value, definitions, expanding) for key, value in node.items() if key != "$ref"}
    if not isinstance(ref, str):
        return rest
    name = ref.removeprefix("#/$defs/")
    target = definitions[name]
    if name in expanding:
        recurring = {"description": target["description"]} if "description" in target else {}
        return {**recurring, **rest}
    inlined = _inline(copy.deepcopy(target), definitions, (*expanding, name))
    return {**inlined, **rest}


def start_ns(events: Iterable[TraceEvent]) -> int:
    """The run's wall-clock start (its header's `started`) in nanoseconds since the epoch; 0
    when the trace has no header or its time cannot be read."""
    for event in events:
        if isinstance(event, HeaderEvent):
            try:
                return int(datetime.fromisoformat(event.started).timestamp()) * 1_000_000_000
            except ValueError:
                return 0
        break
    return 0


def write_mcap(events: list[TraceEvent], output: IO[bytes], prefix: str = DEFAULT_PREFIX) -> dict[str, int]:
    """Write the run's records to `output` as MCAP; how many records of each kind (only the
    kinds the run has get a channel)."""
    from mcap.writer import CompressionType, Writer

    from gpp import __version__

    schemas = record_schemas()
    base = start_ns(events)
    writer = Writer(output, compression=CompressionType.ZSTD)
    writer.start(profile="", library=f"gpp {__version__}")
    channels: dict[str, int] = {}
    counts: dict[str, int] = {}
    for event in events:
        kind = event.EVENT
        channel = channels.get(kind)
        if channel is None:
            data = json.dumps(schemas[kind], ensure_ascii=False).encode("utf-8")
            schema_id = writer.register_schema(name=schema_name(kind), encoding=SCHEMA_ENCODING, data=data)
            channel = writer.register_channel(
                topic=f"{prefix}/{kind}", message_encoding=MESSAGE_ENCODING, schema_id=schema_id
            )
            channels[kind] = channel
        stamp = base + round(event.t * 1_000_000_000)
        writer.add_message(
            channel_id=channel,
            log_time=stamp,
            data=encode(event).encode("utf-8"),
            publish_time=stamp,
            sequence=counts.get(kind, 0),
        )
        counts[kind] = counts.get(kind, 0) + 1
    writer.finish()  # type: ignore[no-untyped-call]
    return counts
