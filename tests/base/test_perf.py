"""gpp.base.perf.cached_dataclass_code: dataclasses made with the cached code of their methods
are the dataclasses Python makes without it, and the cache is written, reused and mended."""

from __future__ import annotations

import dataclasses
import json
import marshal
import subprocess
import sys
from pathlib import Path

import pytest

from gpp.base.perf import cached_dataclass_code

METHODS = ("__init__", "__repr__", "__eq__", "__hash__", "__setattr__", "__delattr__")

# A fingerprint of every generated method of every dataclass of the given modules: what the
# code does (byte code, constants, names), not where it was compiled.
FINGERPRINT = """
import dataclasses, importlib, json, sys
{prelude}
found = {{}}
for name in sys.argv[1:]:
    module = importlib.import_module(name)
    for cls in vars(module).values():
        if isinstance(cls, type) and dataclasses.is_dataclass(cls) and cls.__module__ == name:
            for method in {methods!r}:
                code = getattr(vars(cls).get(method), "__code__", None)
                if code is not None:
                    found[f"{{name}}.{{cls.__qualname__}}.{{method}}"] = repr(
                        (code.co_code, code.co_consts, code.co_names, code.co_varnames, code.co_freevars)
                    )
print(json.dumps(found))
"""
PLAIN = "import contextlib, gpp.base.perf\ngpp.base.perf.cached_dataclass_code = lambda name: contextlib.nullcontext()"


def fingerprint(cache: Path, modules: list[str], prelude: str = "") -> dict[str, str]:
    script = FINGERPRINT.format(prelude=prelude, methods=METHODS)
    env = {"XDG_CACHE_HOME": str(cache), "PATH": "/usr/bin:/bin", "PYTHONDONTWRITEBYTECODE": "1"}
    done = subprocess.run(
        [sys.executable, "-c", script, *modules], env=env, capture_output=True, text=True, timeout=120, check=True
    )
    result: dict[str, str] = json.loads(done.stdout)
    return result


@pytest.mark.slow
def test_the_syntax_tree_and_runtime_classes_are_the_same_with_and_without_the_cache(tmp_path: Path) -> None:
    modules = ["gpp.syntax.ast", "gpp.runtime.events", "gpp.runtime.semantics", "gpp.runtime.contract"]
    plain = fingerprint(tmp_path / "plain", modules, PLAIN)
    assert len(plain) > 400  # the measurement sees the classes
    assert not (tmp_path / "plain").exists()
    first = fingerprint(tmp_path / "cache", modules)  # compiles, writes the cache
    written = sorted(p.name for p in (tmp_path / "cache" / "gpp").glob("dataclasses-*"))
    assert [name.split("-cpython")[0] for name in written] == ["dataclasses-runtime", "dataclasses-syntax-ast"]
    again = fingerprint(tmp_path / "cache", modules)  # reads the cache
    assert first == plain
    assert again == plain


def test_cached_classes_behave_as_plain_ones(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))

    def make() -> type:
        @dataclasses.dataclass(frozen=True, slots=True, kw_only=True)
        class Point:
            x: int
            y: int = dataclasses.field(default=0, compare=False)

        return Point

    made = []
    for _ in range(2):  # the first compiles and writes the cache, the second reads it
        with cached_dataclass_code("test"):
            made.append(make())
    plain = make()
    assert "exec" not in vars(dataclasses)
    for cls in [*made, plain]:
        p = cls(x=1, y=2)
        assert p == cls(x=1, y=5) and hash(p) == hash(cls(x=1, y=7))
        assert repr(p).endswith(".Point(x=1, y=2)")
        with pytest.raises(dataclasses.FrozenInstanceError):
            p.x = 3
        with pytest.raises(TypeError):
            cls(1, 2)
        assert cls.__init__.__code__.co_code == plain.__init__.__code__.co_code


def test_a_broken_or_stale_cache_file_is_written_again(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    path = tmp_path / "gpp" / f"dataclasses-test-{sys.implementation.cache_tag}.marshal"
    path.parent.mkdir()
    path.write_bytes(b"not marshal data")

    def make() -> None:
        @dataclasses.dataclass(frozen=True)
        class Pair:
            a: int
            b: str

        assert Pair(1, "x") == Pair(1, "x")

    with cached_dataclass_code("test"):
        make()
    stored = marshal.loads(path.read_bytes())
    assert stored[""] == sys.version and len(stored) > 1
    stored[""] = "another Python"
    path.write_bytes(marshal.dumps(stored))
    with cached_dataclass_code("test"):
        make()
    assert marshal.loads(path.read_bytes())[""] == sys.version


def test_nested_caches_put_back_the_outer_one(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    with cached_dataclass_code("outer"):
        outer = vars(dataclasses)["exec"]
        with cached_dataclass_code("inner"):
            assert vars(dataclasses)["exec"] is not outer
        assert vars(dataclasses)["exec"] is outer
    assert "exec" not in vars(dataclasses)
