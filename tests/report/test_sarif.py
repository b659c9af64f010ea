"""SARIF 2.1.0 output: the structure GitHub code scanning reads, checked against a hand-written
subset of the SARIF schema (property names as in the standard, since the schema forbids
unknown ones), with positions, rules and relative URIs."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import gpp
from gpp.base.diagnostics import Diagnostic
from gpp.check import check_paths, check_program, merged_diagnostics
from gpp.codes import CODES
from gpp.report.sarif import render_sarif, to_sarif
from tests.support.cli import Result, run

# ---------------------------------------------------------------- a small structural schema

Schema = dict[str, Any]


def obj(allowed: dict[str, Schema], required: tuple[str, ...] = ()) -> Schema:
    return {"type": dict, "properties": allowed, "required": required}


def array(items: Schema, min_items: int = 0) -> Schema:
    return {"type": list, "items": items, "min_items": min_items}


ANY: Schema = {}
STRING: Schema = {"type": str}
POSITIVE: Schema = {"type": int, "minimum": 1}
INDEX: Schema = {"type": int, "minimum": 0}
PROPERTIES: Schema = {"type": dict}
MESSAGE = obj({"text": STRING, "markdown": STRING, "id": STRING, "arguments": ANY, "properties": PROPERTIES}, ("text",))
MULTIFORMAT = obj({"text": STRING, "markdown": STRING, "properties": PROPERTIES}, ("text",))
ARTIFACT_LOCATION = obj(
    {"uri": STRING, "uriBaseId": STRING, "index": INDEX, "description": MESSAGE, "properties": PROPERTIES}, ("uri",)
)
REGION = obj(
    {
        "startLine": POSITIVE,
        "startColumn": POSITIVE,
        "endLine": POSITIVE,
        "endColumn": POSITIVE,
        "charOffset": INDEX,
        "charLength": INDEX,
        "byteOffset": INDEX,
        "byteLength": INDEX,
        "snippet": ANY,
        "message": MESSAGE,
        "sourceLanguage": STRING,
        "properties": PROPERTIES,
    },
    ("startLine",),
)
PHYSICAL_LOCATION = obj(
    {
        "address": ANY,
        "artifactLocation": ARTIFACT_LOCATION,
        "region": REGION,
        "contextRegion": REGION,
        "properties": PROPERTIES,
    },
    ("artifactLocation",),
)
LOCATION = obj(
    {
        "id": INDEX,
        "physicalLocation": PHYSICAL_LOCATION,
        "logicalLocations": ANY,
        "message": MESSAGE,
        "annotations": ANY,
        "relationships": ANY,
        "properties": PROPERTIES,
    }
)
LEVEL: Schema = {"type": str, "enum": ("none", "note", "warning", "error")}
RULE = obj(
    {
        "id": STRING,
        "deprecatedIds": ANY,
        "guid": STRING,
        "deprecatedGuids": ANY,
        "name": STRING,
        "deprecatedNames": ANY,
        "shortDescription": MULTIFORMAT,
        "fullDescription": MULTIFORMAT,
        "messageStrings": ANY,
        "defaultConfiguration": obj(
            {"enabled": {"type": bool}, "level": LEVEL, "rank": ANY, "parameters": ANY, "properties": PROPERTIES}
        ),
        "helpUri": STRING,
        "help": MULTIFORMAT,
        "relationships": ANY,
        "properties": PROPERTIES,
    },
    ("id",),
)
REPLACEMENT = obj(
    {
        "deletedRegion": REGION,
        "insertedContent": obj({"text": STRING, "binary": STRING, "rendered": ANY, "properties": PROPERTIES}),
        "properties": PROPERTIES,
    },
    ("deletedRegion",),
)
ARTIFACT_CHANGE = obj(
    {"artifactLocation": ARTIFACT_LOCATION, "replacements": array(REPLACEMENT, 1), "properties": PROPERTIES},
    ("artifactLocation", "replacements"),
)
FIX = obj(
    {
        "description": MESSAGE,
        "artifactChanges": array(ARTIFACT_CHANGE, 1),
        "properties": PROPERTIES,
    },
    ("artifactChanges",),
)
RESULT_PROPERTIES = [
    "rule",
    "kind",
    "analysisTarget",
    "guid",
    "correlationGuid",
    "occurrenceCount",
    "partialFingerprints",
    "fingerprints",
    "stacks",
    "codeFlows",
    "graphs",
    "graphTraversals",
    "suppressions",
    "baselineState",
    "rank",
    "attachments",
    "hostedViewerUri",
    "workItemUris",
    "provenance",
    "taxa",
    "webRequest",
    "webResponse",
    "properties",
]
RESULT = obj(
    {
        **dict.fromkeys(RESULT_PROPERTIES, ANY),
        "ruleId": STRING,
        "ruleIndex": INDEX,
        "level": LEVEL,
        "message": MESSAGE,
        "locations": array(LOCATION),
        "relatedLocations": array(LOCATION),
        "fixes": array(FIX),
    },
    ("message",),
)
DRIVER_PROPERTIES = [
    "guid",
    "organization",
    "product",
    "productSuite",
    "shortDescription",
    "fullDescription",
    "fullName",
    "dottedQuadFileVersion",
    "releaseDateUtc",
    "downloadUri",
    "globalMessageStrings",
    "notifications",
    "taxa",
    "locations",
    "language",
    "contents",
    "isComprehensive",
    "localizedDataSemanticVersion",
    "minimumRequiredLocalizedDataSemanticVersion",
    "associatedComponent",
    "translationMetadata",
    "supportedTaxonomies",
    "properties",
]
DRIVER = obj(
    {
        **dict.fromkeys(DRIVER_PROPERTIES, ANY),
        "name": STRING,
        "version": STRING,
        "semanticVersion": STRING,
        "informationUri": STRING,
        "rules": array(RULE),
    },
    ("name",),
)
RUN_PROPERTIES = [
    "invocations",
    "conversion",
    "language",
    "versionControlProvenance",
    "artifacts",
    "logicalLocations",
    "graphs",
    "automationDetails",
    "runAggregates",
    "baselineGuid",
    "redactionTokens",
    "defaultEncoding",
    "defaultSourceLanguage",
    "newlineSequences",
    "externalPropertyFileReferences",
    "threadFlowLocations",
    "taxonomies",
    "addresses",
    "translations",
    "policies",
    "webRequests",
    "webResponses",
    "specialLocations",
    "properties",
]
RUN = obj(
    {
        **dict.fromkeys(RUN_PROPERTIES, ANY),
        "tool": obj({"driver": DRIVER, "extensions": ANY, "properties": PROPERTIES}, ("driver",)),
        "originalUriBaseIds": {"type": dict, "values": ARTIFACT_LOCATION},
        "columnKind": {"type": str, "enum": ("utf16CodeUnits", "unicodeCodePoints")},
        "results": array(RESULT),
    },
    ("tool",),
)
SARIF_LOG = obj(
    {
        "$schema": STRING,
        "version": {"type": str, "enum": ("2.1.0",)},
        "runs": array(RUN, 1),
        "inlineExternalProperties": ANY,
        "properties": PROPERTIES,
    },
    ("version", "runs"),
)


def validate(value: object, schema: Schema, where: str = "$") -> list[str]:
    """What is wrong with `value` under `schema` (empty when it fits)."""
    problems: list[str] = []
    expected = schema.get("type")
    wrong_type = expected is not None and (
        (expected is int and isinstance(value, bool)) or not isinstance(value, expected)
    )
    if wrong_type:
        return [f"{where}: expected {expected.__name__}, found {type(value).__name__}"]
    if "enum" in schema and value not in schema["enum"]:
        problems.append(f"{where}: {value!r} is not one of {schema['enum']}")
    if "minimum" in schema and isinstance(value, int) and value < schema["minimum"]:
        problems.append(f"{where}: {value} < {schema['minimum']}")
    if isinstance(value, dict):
        if "properties" in schema:
            allowed: dict[str, Schema] = schema["properties"]
            problems += [f"{where}: missing `{k}`" for k in schema.get("required", ()) if k not in value]
            for k, v in value.items():
                if k not in allowed:
                    problems.append(f"{where}: unknown property `{k}`")
                else:
                    problems += validate(v, allowed[k], f"{where}.{k}")
        if "values" in schema:
            for k, v in value.items():
                problems += validate(v, schema["values"], f"{where}.{k}")
    if isinstance(value, list) and "items" in schema:
        if len(value) < schema.get("min_items", 0):
            problems.append(f"{where}: fewer than {schema['min_items']} items")
        for i, item in enumerate(value):
            problems += validate(item, schema["items"], f"{where}[{i}]")
    return problems


def test_the_schema_check_catches_mistakes() -> None:
    assert validate({"version": "2.1.0", "runs": []}, SARIF_LOG) == ["$.runs: fewer than 1 items"]
    bad_run = {"tool": {"driver": {"name": "gpp"}}, "results": [{"message": {}, "region": {}}]}
    assert sorted(validate({"version": "2.1.0", "runs": [bad_run]}, SARIF_LOG)) == [
        "$.runs[0].results[0].message: missing `text`",
        "$.runs[0].results[0]: unknown property `region`",
    ]


# ---------------------------------------------------------------- programs

PROGRAM = """\
symbol domain Room = {hall, kitchen}
number fluent unused_one() { initially: () = 0; }
action go(Room hall) { }
number function cost() = 1 * 2 + 3 * 4
procedure main() {
    test(cost() > 0);
    go(kitchn);
}
"""
BROKEN = "procedure main() {\n    test(true)\n}\n"


@pytest.fixture
def project(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A working directory with `src/agent.gpp` (errors and warnings), `src/broken.gpp` (a
    syntax error) and `clean.gpp`."""
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "agent.gpp").write_text(PROGRAM)
    (tmp_path / "src" / "broken.gpp").write_text(BROKEN)
    (tmp_path / "clean.gpp").write_text("procedure main() { }\n")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def diagnostics_of(*paths: str) -> list[Diagnostic]:
    return merged_diagnostics(check_paths([Path(p) for p in paths]))


def test_sarif_log_has_the_required_structure(project: Path) -> None:
    log = to_sarif(diagnostics_of("src/agent.gpp"))
    assert validate(log, SARIF_LOG) == []
    assert log["$schema"] == "https://json.schemastore.org/sarif-2.1.0.json"
    assert log["version"] == "2.1.0"
    [run] = log["runs"]
    driver = run["tool"]["driver"]
    assert (driver["name"], driver["version"]) == ("gpp", gpp.__version__)
    assert "informationUri" not in driver  # optional, and gpp has no web page of its own
    assert run["columnKind"] == "unicodeCodePoints"
    assert run["originalUriBaseIds"]["%SRCROOT%"]["uri"] == project.resolve().as_uri() + "/"


def test_results_carry_code_level_message_and_region(project: Path) -> None:
    diagnostics = diagnostics_of("src/agent.gpp")
    [run] = to_sarif(diagnostics)["runs"]
    results = run["results"]
    assert [r["ruleId"] for r in results] == [d.code for d in diagnostics]
    assert [r["ruleId"] for r in results] == ["W0101", "W0111", "W0110", "E0101"]
    assert [r["level"] for r in results] == ["warning", "warning", "warning", "error"]
    unknown = results[3]
    [location] = unknown["locations"]
    assert location["physicalLocation"]["artifactLocation"] == {"uri": "src/agent.gpp", "uriBaseId": "%SRCROOT%"}
    # `kitchn` on line 7, columns 8 to 13; the end column is exclusive.
    assert location["physicalLocation"]["region"] == {"startLine": 7, "startColumn": 8, "endLine": 7, "endColumn": 14}
    assert unknown["message"]["text"] == "unknown name `kitchn`\nhelp: did you mean `kitchen`?"
    precedence = results[2]
    assert precedence["message"]["text"] == (
        "the original C++ golog++ reads this as `((1 * 2) + 3) * 4`\n"
        "note: gpp uses standard precedence: `(1 * 2) + (3 * 4)`"
    )


def test_an_insertion_point_is_an_empty_region(project: Path) -> None:
    [run] = to_sarif(diagnostics_of("src/broken.gpp"))["runs"]
    [result] = run["results"]
    assert (result["ruleId"], result["level"]) == ("E0011", "error")
    assert result["message"]["text"] == "expected `;` after this statement"
    # Right after `test(true)`: line 2, column 15.
    region = result["locations"][0]["physicalLocation"]["region"]
    assert region == {"startLine": 2, "startColumn": 15, "endLine": 2, "endColumn": 15}
    [fix] = result["fixes"]
    assert fix["artifactChanges"] == [
        {
            "artifactLocation": {"uri": "src/broken.gpp", "uriBaseId": "%SRCROOT%"},
            "replacements": [{"deletedRegion": region, "insertedContent": {"text": ";"}}],
        }
    ]


def test_secondary_labels_become_related_locations(project: Path) -> None:
    [run] = to_sarif(diagnostics_of("src/agent.gpp"))["runs"]
    shadowed = next(r for r in run["results"] if r["ruleId"] == "W0111")
    assert shadowed["relatedLocations"] == [
        {
            "id": 1,
            "physicalLocation": {
                "artifactLocation": {"uri": "src/agent.gpp", "uriBaseId": "%SRCROOT%"},
                "region": {"startLine": 1, "startColumn": 23, "endLine": 1, "endColumn": 27},
            },
            "message": {"text": "the symbol is declared here"},
        }
    ]


def test_fixes_become_sarif_fixes(project: Path) -> None:
    [run] = to_sarif(diagnostics_of("src/agent.gpp"))["runs"]
    precedence = next(r for r in run["results"] if r["ruleId"] == "W0110")
    [fix] = precedence["fixes"]
    assert fix["description"] == {"text": "add parentheses to make it unambiguous"}
    [change] = fix["artifactChanges"]
    assert change["artifactLocation"]["uri"] == "src/agent.gpp"
    inserted = [(r["deletedRegion"]["startColumn"], r["insertedContent"]["text"]) for r in change["replacements"]]
    assert inserted == [(26, "("), (31, ")"), (34, "("), (39, ")")]


def test_one_rule_per_code_used(project: Path) -> None:
    [run] = to_sarif(diagnostics_of("src/agent.gpp", "src/broken.gpp"))["runs"]
    rules = run["tool"]["driver"]["rules"]
    assert [r["id"] for r in rules] == ["E0011", "E0101", "W0101", "W0110", "W0111"]
    for result in run["results"]:
        assert rules[result["ruleIndex"]]["id"] == result["ruleId"]
    unused = rules[2]
    info = CODES["W0101"]
    assert unused["name"] == "unused"
    assert unused["shortDescription"]["text"] == "A fluent, action, function or procedure that is never used."
    assert unused["fullDescription"]["text"] == info.explanation.split("\n\n")[0].replace("\n", " ")
    assert unused["help"]["text"] == info.explanation
    assert unused["defaultConfiguration"] == {"level": "warning"}
    assert rules[0]["defaultConfiguration"] == {"level": "error"}


def test_clean_program_gives_an_empty_run(project: Path) -> None:
    log = to_sarif(diagnostics_of("clean.gpp"))
    assert validate(log, SARIF_LOG) == []
    [run] = log["runs"]
    assert (run["results"], run["tool"]["driver"]["rules"]) == ([], [])


def test_uris_are_relative_with_forward_slashes_or_absolute(
    project: Path, tmp_path_factory: pytest.TempPathFactory
) -> None:
    elsewhere = tmp_path_factory.mktemp("elsewhere") / "far away.gpp"
    elsewhere.write_text("number fluent lonely() { initially: () = 0; }\n")
    [run] = to_sarif(diagnostics_of("src/agent.gpp", str(elsewhere)))["runs"]
    locations = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]: r for r in run["results"]}
    assert "src/agent.gpp" in locations
    far = elsewhere.resolve().as_uri()
    assert far.endswith("/far%20away.gpp")
    assert locations[far]["locations"][0]["physicalLocation"]["artifactLocation"] == {"uri": far}


def test_columns_count_characters(project: Path) -> None:
    # `é` takes two bytes in UTF-8 and `𝄞` two UTF-16 code units; SARIF columns count characters.
    text = 'procedure main() { test("é𝄞" == "x" & missing); }\n'
    (project / "accents.gpp").write_text(text, encoding="utf-8")
    [run] = to_sarif(check_program(Path("accents.gpp")).diagnostics)["runs"]
    [result] = run["results"]
    region = result["locations"][0]["physicalLocation"]["region"]
    start = text.index("missing") + 1
    assert region == {"startLine": 1, "startColumn": start, "endLine": 1, "endColumn": start + len("missing")}


def test_render_sarif_is_json_with_a_final_newline(project: Path) -> None:
    text = render_sarif(diagnostics_of("src/agent.gpp"))
    assert text.endswith("}\n")
    assert json.loads(text) == to_sarif(diagnostics_of("src/agent.gpp"))


# ---------------------------------------------------------------- gpp check --format sarif


def run_gpp(*args: str, cwd: Path) -> Result:
    return run(*args, cwd=cwd)


def test_cli_writes_sarif(project: Path) -> None:
    result = run_gpp("check", "--format", "sarif", "src/agent.gpp", cwd=project)
    assert result.returncode == 1
    log = json.loads(result.stdout)
    assert validate(log, SARIF_LOG) == []
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in log["runs"][0]["results"]}
    assert uris == {"src/agent.gpp"}


def test_cli_sarif_for_a_clean_file_exits_0(project: Path) -> None:
    result = run_gpp("check", "--format", "sarif", "clean.gpp", cwd=project)
    assert result.returncode == 0
    assert json.loads(result.stdout)["runs"][0]["results"] == []


def test_cli_sarif_honours_no_lint(project: Path) -> None:
    result = run_gpp("check", "--format", "sarif", "--no-lint", "src/agent.gpp", cwd=project)
    levels = {r["level"] for r in json.loads(result.stdout)["runs"][0]["results"]}
    assert levels == {"error"}
