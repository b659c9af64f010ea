"""Values are shown as golog++ writes them wherever gpp shows one (the run log, the trace's
readers, messages about values from outside), never as Python writes them; and an exogenous
event whose effect fails is named in the diagnostic and in the trace."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import gpp as gpp_package
from gpp.model.types import NUMBER, Sym
from gpp.platform.values import ConversionError, show_plain, to_value
from gpp.runtime.values import CompoundValue, Value, show, show_json, to_json
from gpp.traceview.model import show_value
from tests.support.cli import Result, run

SHOWN: list[tuple[Value, str]] = [
    (True, "true"),
    (False, "false"),
    (None, "null"),
    (7, "7"),
    (2.0, "2.0"),
    (3.5, "3.5"),
    ('say "hi"', '"say \\"hi\\""'),
    (Sym("kitchen"), "kitchen"),
    ((Sym("a"), Sym("b")), "[a,b]"),
    ((), "[]"),
    (CompoundValue("Pose", (("x", 1.5), ("y", (True, None)))), "Pose{x=1.5,y=[true,null]}"),
]


@pytest.mark.parametrize(("value", "text"), SHOWN, ids=[t for _, t in SHOWN])
def test_a_value_reads_the_same_from_the_program_and_from_the_trace(value: Value, text: str) -> None:
    assert show(value) == text
    assert show_json(to_json(value)) == text
    assert show_value(json.loads(json.dumps(to_json(value)))) == text


def test_values_from_outside_are_shown_as_toml_and_golog_write_them() -> None:
    assert show_plain(True) == "true"
    assert show_plain("abc") == '"abc"'
    assert show_plain({"x": 1, "tags": ["a", None]}) == '{x = 1, tags = ["a", null]}'
    with pytest.raises(ConversionError, match=re.escape('expected a number, got ["1"]')):
        to_value(["1"], NUMBER)
    # not a value a trace can hold: shown as JSON, not as Python
    assert show_json({"weird": True}) == '{"weird": true}'


AGENT = """\
symbol domain Room = {kitchen, hall}
compound Pose { number x, number y }
bool fluent ok() { initially: () = false; }
string fluent said() { initially: () = ""; }
list[symbol] fluent rooms() { initially: () = list[symbol] []; }
Pose fluent pose() { initially: () = Pose { x = 0, y = 0 }; }
number fluent n() { initially: () = 1; }
exog_action ring(bool loud, Pose at, number d) {
effect:
    ok() = loud;
    n() = n() / d;
}
action go(Room r, Pose p, bool fast, string why) { duration: [2, 2] }
procedure main() {
    ok() = true;
    said() = "say \\"hi\\"";
    push_back(rooms(), kitchen);
    pose() = Pose { x = 1.5, y = 2 };
    go(hall, pose(), true, "because");
    go(kitchen, pose(), false, "again");
}
"""
SCENARIO = """\
[[exog]]
at = 1
action = "ring"
args = [true, { x = 1, y = 2 }, 4]

[[exog]]
at = 3
action = "ring"
args = [false, { x = 0, y = 0 }, 0]
"""
PYTHON_ISMS = re.compile(r"\bTrue\b|\bFalse\b|\bNone\b|\{'|\['|'\]|'symbol'|'compound'")


def gpp(*args: str, cwd: Path) -> Result:
    return run(*args, cwd=cwd)


def in_process(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    """The standard output of a gpp command run in this process (it must succeed)."""
    result = run(*args)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_the_run_log_the_trace_and_its_views_show_golog_values(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "agent.gpp").write_text(AGENT)
    (tmp_path / "agent.toml").write_text(SCENARIO)
    run = gpp("run", "agent.gpp", "--scenario", "agent.toml", "--trace", "run.jsonl", cwd=tmp_path)
    assert run.returncode == 1, run.stderr
    log = [line[14:] for line in run.stdout.splitlines() if line.startswith("[")]
    assert log[:6] == [
        "assign ok() = true",
        'assign said() = "say \\"hi\\""',
        "assign rooms() = [kitchen]",
        "assign pose() = Pose{x=1.5,y=2}",
        'start  go(hall,Pose{x=1.5,y=2},true,"because")',
        "exog   ring(true,Pose{x=1,y=2},4)",
    ]
    # the second event's effect divides by zero: the event is named in the log, the trace
    # and the diagnostic
    assert "exog   ring(false,Pose{x=0,y=0},0) (its effect failed)" in log
    assert "error[R0001]: division by zero" in run.stdout
    assert "= note: in the effect of the exogenous event `ring(false,Pose{x=0,y=0},0)`, which arrived at 3.000 s" in (
        run.stdout
    )
    records = [json.loads(line) for line in (tmp_path / "run.jsonl").read_text().splitlines()]
    kinds = [(r["event"], r.get("action"), r.get("failed")) for r in records if r["event"] in ("exog", "error")]
    assert kinds == [
        ("exog", "ring(true,Pose{x=1,y=2},4)", None),
        ("exog", "ring(false,Pose{x=0,y=0},0)", True),
        ("error", None, None),
    ]
    summary = in_process(capsys, "trace", "summary", str(tmp_path / "run.jsonl"), "--color", "never")
    assert "(effect failed)" in summary
    html = in_process(capsys, "trace", "html", str(tmp_path / "run.jsonl"), "-o", "-")
    assert '"value":"[kitchen]"' in html and '"failed":true' in html
    viewer = (Path(gpp_package.__file__).parent / "traceview" / "viewer.js").read_text()
    assert viewer in html  # so that only the page's data is left to look at
    for text in (run.stdout, summary, html.replace(viewer, "")):
        assert PYTHON_ISMS.findall(text) == []


def test_a_bad_horizon_is_shown_as_golog_writes_it(tmp_path: Path) -> None:
    from gpp.run.runner import RunOptions, run_program

    path = tmp_path / "horizon.gpp"
    path.write_text(
        "number fluent h() {\ninitially:\n    () = null;\n}\naction go() { }\n"
        "number function r() = 0\nprocedure main() { solve(h(), r()) go(); }\n"
    )
    outcome = run_program(path, RunOptions(timeout=60))
    assert [(d.code, d.message) for d in outcome.diagnostics if d.is_error] == [
        ("R0010", "the horizon of `solve` must be a whole number >= 0, got null")
    ]
