"""A plain `pip install .` works: the wheel carries the grammar and the standard library, and
gpp finds them inside the installed package (not only in a source checkout)."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(out), str(ROOT)],
        check=True,
        capture_output=True,
        text=True,
        timeout=300,
    )
    wheels = list(out.glob("gpp-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


def test_wheel_contains_grammar_and_stdlib(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    assert "gpp/_data/grammar/gpp.lark" in names
    assert "gpp/cli/common.py" in names
    assert "gpp/trace.schema.json" in names  # gpp.runtime.events.load_schema()
    assert {"gpp/codes/explain/E0001.md", "gpp/codes/explain/W0101.md"} <= names  # gpp explain
    assert {f"gpp/traceview/viewer.{ext}" for ext in ("html", "css", "js")} <= names  # gpp trace html
    assert any(n.startswith("gpp/_data/stdlib/") for n in names), sorted(n for n in names if "_data" in n)
    assert not any(n.startswith("tests/") for n in names)


def test_installed_package_checks_a_program_outside_the_source_tree(wheel: Path, tmp_path: Path) -> None:
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    program = tmp_path / "agent.gpp"
    program.write_text("bool fluent done() { initially: () = false; }\nprocedure main() { done() = true; }\n")
    # Only the extracted wheel provides `gpp`; the dependencies come from this environment.
    deps = [p for p in sys.path if p.endswith("site-packages")]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), *deps]), "XDG_CACHE_HOME": str(tmp_path / "cache")}
    script = (
        "import gpp.base.resources as r, sys; "
        "assert '_data' in str(r.grammar_path()), r.grammar_path(); "
        "assert '_data' in str(r.stdlib_dir()), r.stdlib_dir(); "
        "import gpp.runtime.events as ev; assert ev.load_schema()['$id'].endswith(ev.TRACE_SCHEMA_VERSION); "
        "from gpp.codes import CODES; assert CODES['E0204'].explanation.startswith('An operator'); "
        "from gpp.cli.main import main; main(['check', sys.argv[1]])"
    )
    result = subprocess.run(
        [
            sys.executable,
            "-I",
            "-c",
            f"import sys; sys.path[:0] = {str(env['PYTHONPATH']).split(os.pathsep)!r}; {script}",
            str(program),
        ],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "no problems found" in result.stdout


def test_a_lark_replaced_by_lark_parser_is_reported_with_the_repair() -> None:
    import pytest

    from gpp.base.resources import InstallationError, check_lark

    check_lark("1.3.1")
    with pytest.raises(InstallationError, match=r"gpp needs lark 1.x, but lark 0.12.0 is installed") as caught:
        check_lark("0.12.0")
    assert "pip uninstall -y lark-parser" in str(caught.value)
