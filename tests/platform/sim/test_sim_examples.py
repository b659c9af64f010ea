"""Agents on the sim platform end to end: the examples reach their postcond() with real
physics; the program's mappings are checked against what the sim serves; worlds load from
data; runs are reproducible; frames are recorded."""

from __future__ import annotations

import time
import tomllib
from pathlib import Path
from typing import TypeVar

import pytest
from PIL import Image

from gpp.platform.base import PlatformConfig
from gpp.platform.sim import SimPlatform, World, WorldError
from gpp.platform.sim.platform import run_action
from gpp.run.runner import RunOptions, RunOutcome, RunSetupError, run_program
from gpp.runtime.events import EventBase, ExogEvent, PlanEvent, SenseEvent, UpdateEvent
from gpp.runtime.executor import RunStatus
from gpp.syntax.directives import file_directives

E = TypeVar("E", bound=EventBase)

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples"


def sim_run(name: str, record: Path | None = None, snapshot: Path | None = None) -> RunOutcome:
    files = {k: v for k, v in {"record": record, "snapshot": snapshot}.items() if v is not None}
    outcome = run_program(EXAMPLES / name, RunOptions(record=True, platform="sim", platform_options=files))
    messages = [d.message + " " + " ".join(d.notes) for d in outcome.diagnostics]
    assert outcome.result is not None, messages
    assert outcome.result.status is RunStatus.FINISHED, messages
    assert outcome.postcond is True, messages
    return outcome


def events(outcome: RunOutcome, kind: type[E]) -> list[E]:
    assert outcome.recording is not None
    return outcome.recording.of(kind)


def test_blocksworld_senses_plans_and_builds_the_tower() -> None:
    outcome = sim_run("blocksworld.gpp")
    plans = events(outcome, PlanEvent)
    assert plans[0].policy == ("stack(c,t3)", "stack(a,t2)", "stack(b,c)", "stack(a,b)")
    ends = [r for r in events(outcome, UpdateEvent) if r.action.startswith("stack")]
    assert [r.status for r in ends] == ["final"] * 4
    senses = {r.fluent: r.value for r in events(outcome, SenseEvent)}  # the last reading wins
    assert senses == {"loc(a)": {"symbol": "b"}, "loc(b)": {"symbol": "c"}, "loc(c)": {"symbol": "t3"}}
    assert outcome.result is not None
    assert 20 < outcome.result.platform_time < 60


def test_blocksworld_faults_recovers_from_slips() -> None:
    outcome = sim_run("blocksworld_faults.gpp")
    failed = [r for r in events(outcome, UpdateEvent) if r.status == "failed"]
    assert failed and all("the grasp slipped" in (r.reason or "") for r in failed)
    assert len(events(outcome, PlanEvent)) >= 2  # planned again from what it saw


def test_rescue_finds_the_victims_and_returns_home() -> None:
    outcome = sim_run("rescue.gpp")
    exogs = [r.action for r in events(outcome, ExogEvent)]
    assert "victim_detected(v1)" in exogs and "victim_detected(v2)" in exogs
    # It reacted to the second victim by giving up its drive and heading home.
    cancelled = [r for r in events(outcome, UpdateEvent) if r.status == "cancelled"]
    assert [r.action for r in cancelled] == ["navigate_to_frame(room3)"]
    batteries = [a for a in exogs if a.startswith("battery_report")]
    assert batteries[0] == "battery_report(100)" and len(batteries) > 5


def test_the_world_option_overrides_the_directive() -> None:
    outcome = run_program(
        EXAMPLES / "rescue.gpp", RunOptions(record=True, platform="sim", platform_options={"world": "blocksworld"})
    )
    assert outcome.result is None  # did not start
    messages = [d.message for d in outcome.diagnostics]
    assert any('"/victim_detected", which world `blocksworld` does not produce' in m for m in messages)


def test_runs_are_reproducible() -> None:
    def trace() -> list[tuple[object, ...]]:
        outcome = run_program(EXAMPLES / "blocksworld_faults.gpp", RunOptions(record=True, platform="sim"))
        assert outcome.recording is not None
        return [
            (r.t, r.EVENT, getattr(r, "action", None), getattr(r, "reason", None)) for r in outcome.recording.records
        ]

    assert trace() == trace()


def test_mappings_are_checked_against_what_the_sim_serves() -> None:
    outcome = run_program(EXAMPLES / "blocks_planning.gpp", RunOptions(record=True, platform="sim"))
    assert outcome.result is None
    (error,) = [d for d in outcome.diagnostics if d.code == "R0007"]
    # At the mapping, not at `main()`.
    assert error.message == 'action `stack` is mapped to "stack_block", which the sim does not serve'
    assert error.span.text == '"stack_block"'
    assert error.help == "did you mean `/stack`?"
    assert error.notes == (
        'the sim serves "/get_block_pose" {block}, "/gripper_home" {}, "/navigate_to_frame" {frame}, '
        '"/stack" {block, location}',
        'a scenario (`--scenario`) serves what the world does not model: an `[[action]]` rule `match = "stack"` '
        "(or no `mapping:` at all) makes it the scenario's",
        "the program does not fit platform `sim`",
    )


def test_unknown_arguments_and_fields_are_problems(tmp_path: Path) -> None:
    program = tmp_path / "wrong.gpp"
    program.write_text(
        """
symbol domain block = {a, b, c}
symbol domain spot = {t1, t2, t3}
action put(block x, spot y) {
mapping:
    "/stack" { blok = x, location = y }
}
exog_action low(number l) {
mapping:
    "/battery" { levl = l }
}
procedure main() { put(a, t3); }
""",
        encoding="utf-8",
    )
    outcome = run_program(program, RunOptions(record=True, platform="sim"))
    # Every problem at once, each where the mapping says it, before anything runs.
    assert outcome.result is None
    found = [(d.code, d.span.text, d.message, d.help) for d in outcome.diagnostics]
    assert found == [
        (
            "R0007",
            "blok = x",
            'action `put`: "/stack" has no argument `blok` (its arguments: `block`, `location`)',
            "did you mean `block`?",
        ),
        ("R0007", '"/stack"', 'action `put`: the mapping to "/stack" must give `block`', None),
        (
            "R0007",
            "levl = l",
            'exogenous action `low`: "/battery" has no field `levl` (its fields: `level`)',
            "did you mean `level`?",
        ),
    ]


def test_the_program_domains_must_hold_the_world_names(tmp_path: Path) -> None:
    program = tmp_path / "small.gpp"
    program.write_text(
        """
#include "sim/blocksworld.gpp"
#include "sim/rescue.gpp"
symbol domain block = {a, b}
symbol domain slot = {t1, t2, t3}
symbol domain frame = {home, table}
symbol domain victim = {v1}
procedure main() { get_block_pose(a); }
""",
        encoding="utf-8",
    )
    world = tmp_path / "both.toml"
    world.write_text(
        (World.directory() / "blocksworld.toml").read_text(encoding="utf-8")
        + '[[map.region]]\nname = "v2"\ncircle = [2, 2, 1]\nevent = "/victim_detected"\nfields = { id = "v2" }\n',
        encoding="utf-8",
    )
    outcome = run_program(program, RunOptions(record=True, platform="sim", platform_options={"world": str(world)}))
    messages = [d.message for d in outcome.diagnostics]
    assert messages == [
        'action `get_block_pose` senses into type `location`, which lacks `c`: "/get_block_pose" can report these '
        "in world `blocksworld`",
        "exogenous action `victim_detected`: region `v2` sends id: v2 is not in domain `victim`",
    ]


def test_unknown_worlds_are_setup_errors() -> None:
    with pytest.raises(RunSetupError, match=r"no world `rescu` \(available: .*rescue.*; did you mean `rescue`\?"):
        run_program(
            EXAMPLES / "rescue.gpp", RunOptions(record=True, platform="sim", platform_options={"world": "rescu"})
        )


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('name = "x"', "a world needs a [workbench] or a [map]"),
        (
            '[workbench]\n[[workbench.slot]]\nname = "t1"\nx = 160\n[[workbench.block]]\nname = "a"\non = "t9"',
            "block `a` is on `t9`, which is no slot or block (did you mean `t1`?)",
        ),
        ("[map]\nsize = [4, 4]\n[map.robot]\nstart = 'hom'\n[[map.frame]]\nname = 'home'\nat = [1, 1]", "`home`"),
        ("[map]\nsize = [4, 4]\nwals = []", "unknown key(s) `wals` (did you mean `walls`?)"),
        ('[workbench]\n[[workbench.block]]\nname = "a"\non = "b"\n[[workbench.block]]\nname = "b"\non = "a"', "cycle"),
    ],
)
def test_bad_world_files_say_what_is_wrong(text: str, message: str) -> None:
    with pytest.raises(WorldError) as error:
        World.from_data(tomllib.loads(text))
    assert message in str(error.value)


MAP = "[map]\nsize = [4, 4]\n"
BENCH = '[workbench]\n[[workbench.slot]]\nname = "t1"\nx = 160\n'


@pytest.mark.parametrize(
    ("text", "message"),
    [
        # docs/semantics.md, "Numbers": every number of a world is finite and within its range.
        ("dt = nan\n" + MAP, "world: `dt` must be between 0.0001 and 0.1, not nan"),
        ("dt = inf\n" + MAP, "world: `dt` must be between 0.0001 and 0.1, not inf"),
        (
            "[map]\nsize = [1e9, 1e9]\n",
            "world [map]: `size` must be a list of 2 numbers between 0.1 and 10000, not 1000000000.0",
        ),
        ("[map]\nsize = [4, nan]\n", "world [map]: `size` must be a list of 2 numbers between 0.1 and 10000, not nan"),
        (
            "[map]\nsize = [5000, 5000]\n",
            "world [map]: a map of 5000 x 5000 m at a `resolution` of 0.1 m has 2500000000 grid cells, at most 4000000 "
            "are allowed (make the map smaller or the resolution coarser)",
        ),
        (MAP + "resolution = -inf\n", "world [map]: `resolution` must be between 0.01 and 1, not -inf"),
        (
            MAP + "walls = [[0, 0, inf, 1]]\n",
            "world [map]: `walls` must hold coordinates between -10000 and 10000, not inf",
        ),
        (MAP + "[map.robot]\nspeed = nan\n", "world [map] [robot]: `speed` must be between 0.01 and 100, not nan"),
        (
            MAP + "[map.battery]\nreport_every = 1e10\n",
            "world [map] [battery]: `report_every` must be between 0.1 and 1e9, not 10000000000.0",
        ),
        (
            MAP + "[[map.frame]]\nname = 'home'\nat = [nan, 1]\n",
            "world [map] [[frame]] #1: `at` must be a list of 2 numbers between -10000 and 10000, not nan",
        ),
        (
            MAP + "[[map.region]]\nname = 'r'\nevent = 'e'\ncircle = [1, 1, inf]\n",
            "world [map] [[region]] #1: `circle` must be a list of 3 numbers between -10000 and 10000, not inf",
        ),
        (
            MAP + "[faults]\n[[faults.obstacle]]\nat = nan\nrect = [0, 0, 1, 1]\n",
            "world [faults] [[obstacle]] #1: `at` must be between 0 and 1e9, not nan",
        ),
        (MAP + "[faults]\ngrasp_slip = nan\n", "world [faults]: `grasp_slip` must be between 0 and 1, not nan"),
        ("[workbench]\ngravity = inf\n", "world [workbench]: `gravity` must be between 0 and 10000, not inf"),
        (
            BENCH + "[workbench.table]\nleft = -inf\n",
            "world [workbench] [table]: `left` must be between 0 and 10000, not -inf",
        ),
        (
            BENCH + "[workbench.gripper]\nhome = [nan, 0]\n",
            "world [workbench] [gripper]: `home` must be a list of 2 numbers between -10000 and 10000, not nan",
        ),
        (
            BENCH + '[[workbench.block]]\nname = "a"\non = "t1"\nsize = [40, 1e300]\n',
            "world [workbench] [[block]] #1: `size` must be a list of 2 numbers between 1 and 1000, not 1e+300",
        ),
        (
            BENCH + '[[workbench.block]]\nname = "a"\non = "t1"\nmass = nan\n',
            "world [workbench] [[block]] #1: `mass` must be between 0.01 and 1000, not nan",
        ),
        (
            BENCH + "[[workbench.slot]]\nname = 't2'\nx = " + "9" * 400 + "\n",
            "world [workbench] [[slot]] #2: `x` must be between -10000 and 10000, not a whole number of 400 digits",
        ),
    ],
)
def test_every_number_of_a_world_is_checked_against_its_range(text: str, message: str) -> None:
    with pytest.raises(WorldError) as error:
        World.from_data(tomllib.loads(text))
    assert str(error.value) == message


def test_world_with_a_whole_number_too_long_for_toml_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "w.toml"
    path.write_text("dt = " + "1" * 5000 + "\n" + MAP, encoding="utf-8")
    with pytest.raises(WorldError, match="has a whole number beyond the range of numbers"):
        World.load(str(path))


def test_world_file_that_is_not_text_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "w.toml"
    path.write_bytes(b"name = 'caf\xe9'\n" + MAP.encode())
    with pytest.raises(WorldError) as error:
        World.load(str(path))
    assert str(error.value) == f"world '{path}' is not UTF-8 text"


def test_record_and_snapshot(tmp_path: Path) -> None:
    gif, png = tmp_path / "run.gif", tmp_path / "end.png"
    sim_run("blocksworld.gpp", record=gif, snapshot=png)
    with Image.open(gif) as animation:
        frames = getattr(animation, "n_frames", 1)
        size = animation.size
    stats = SimPlatform.last_run
    assert stats is not None
    assert frames >= stats.sim_time / 0.25  # one frame every 0.25 s of sim time
    assert gif.stat().st_size < 1_000_000
    with Image.open(png) as last:
        assert last.size == size
        colors = {c for _, c in last.convert("RGB").getcolors(1 << 16) or []}
    # The three blocks are drawn in their world colours.
    assert {(0xD1, 0x49, 0x5B), (0x2E, 0x86, 0xAB), (0xD4, 0xA0, 0x17)} <= colors


def test_realtime_paces_sim_time_to_wall_time() -> None:
    sim = SimPlatform(World.load("blocksworld"), realtime=True)
    started = time.perf_counter()
    run_action(sim, "/get_block_pose", block="a")
    assert time.perf_counter() - started >= 0.9 * sim.now() > 0.1


def test_create_picks_the_world_and_the_seed() -> None:
    faults = EXAMPLES / "blocksworld_faults.gpp"

    def create(program: Path, **options: str | int) -> SimPlatform:
        return SimPlatform.create(PlatformConfig(program, file_directives(program), options))

    sim = create(faults)
    assert (sim.world.name, sim.seed) == ("blocksworld_faults", 3)  # the directive, the world's seed
    sim = create(faults, seed=5)
    assert sim.seed == 5  # --seed wins over the world's
    sim = create(faults, world="rescue")
    assert sim.world.name == "rescue" and sim.workbench is None
    sim = create(EXAMPLES / "blocks_planning.gpp")
    assert sim.world.name == "blocksworld"  # the default world
