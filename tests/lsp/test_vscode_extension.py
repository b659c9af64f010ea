"""The VS Code extension (editors/vscode): its manifest declares the language, the grammar and
the debugger consistently; the generated grammar passes its tests under vscode-tmgrammar-test
(VS Code's own TextMate engine); the extension activates under Node with a stand-in for the
`vscode` module, starts the real `gpp lsp` through its language client and `gpp dap` as its
debug adapter; and @vscode/vsce packages it.

The manifest tests need nothing; the others need Node 20 and the npm packages of `make vscode`
and are skipped, saying so, without them (tests.support.node).
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

import pytest

from gpp.syntax.editor_files import GENERATED, TEXTMATE_SCOPE
from tests.support.node import EXTENSION, GPP, needs_node, node, npm_tool

# Node processes: the grammar test, the extension's activation, vsce packaging.
pytestmark = pytest.mark.slow

ROOT = EXTENSION.parents[1]


def manifest() -> dict[str, Any]:
    loaded: dict[str, Any] = json.loads((EXTENSION / "package.json").read_text(encoding="utf-8"))
    return loaded


def debugger() -> dict[str, Any]:
    (found,) = manifest()["contributes"]["debuggers"]
    assert isinstance(found, dict)
    return found


# ---------------------------------------------------------------- the manifest


def test_the_manifest_declares_the_golog_language_with_its_configuration_and_grammar() -> None:
    contributes = manifest()["contributes"]
    (language,) = contributes["languages"]
    assert (language["id"], language["extensions"]) == ("golog", [".gpp"])
    configuration = json.loads((EXTENSION / language["configuration"]).read_text(encoding="utf-8"))
    assert configuration["comments"] == {"lineComment": "//", "blockComment": ["/*", "*/"]}
    (grammar,) = contributes["grammars"]
    assert (grammar["language"], grammar["scopeName"]) == ("golog", TEXTMATE_SCOPE)
    path = (EXTENSION / grammar["path"]).resolve()
    assert path in GENERATED  # generated from the keyword list, and current (test_editors.py)
    assert json.loads(path.read_text(encoding="utf-8"))["scopeName"] == TEXTMATE_SCOPE
    assert contributes["breakpoints"] == [{"language": "golog"}]


def test_the_main_file_exists_and_the_setting_names_the_gpp_command() -> None:
    package = manifest()
    assert (EXTENSION / package["main"]).is_file()
    assert package["contributes"]["configuration"]["properties"]["gpp.path"]["default"] == "gpp"


def test_the_launches_use_only_declared_attributes_for_the_program_and_the_trace_replay() -> None:
    found = debugger()
    assert found["type"] == "gpp" and found["languages"] == ["golog"]
    declared = set(found["configurationAttributes"]["launch"]["properties"]) | {"type", "request", "name"}
    launches = [*found["initialConfigurations"], *(s["body"] for s in found["configurationSnippets"])]
    for launch in launches:
        assert set(launch) <= declared, launch
        assert (launch["type"], launch["request"]) == ("gpp", "launch")
        assert ("program" in launch) != ("trace" in launch), launch
    # The initial configurations: run the file in the editor, replay a trace.
    initial = found["initialConfigurations"]
    assert [("program" in c, "trace" in c) for c in initial] == [(True, False), (False, True)]
    assert initial[0]["program"] == "${file}"
    # A snippet's body is JSON with `^"..."` for a string holding a variable (VS Code's rule).
    for snippet in found["configurationSnippets"]:
        for value in snippet["body"].values():
            if isinstance(value, str) and "${" in value:
                assert value.startswith('^"') and value.endswith('"') and "\\${" in value, value


def test_the_npm_packages_are_pinned_by_the_lock_and_kept_out_of_git() -> None:
    package = manifest()
    lock = json.loads((EXTENSION / "package-lock.json").read_text(encoding="utf-8"))
    wanted = {**package["dependencies"], **package["devDependencies"]}
    for name, version in wanted.items():
        assert version[0].isdigit(), f"{name} {version}: an exact version"
        assert lock["packages"][f"node_modules/{name}"]["version"] == version
    assert wanted["@vscode/vsce"].startswith("3.")
    assert {"vscode-tmgrammar-test", "@vscode/debugadapter-testsupport"} <= set(package["devDependencies"])
    ignored = (EXTENSION / ".gitignore").read_text(encoding="utf-8").split()
    assert "node_modules/" in ignored and "*.vsix" in ignored
    assert "test/**" in (EXTENSION / ".vscodeignore").read_text(encoding="utf-8").split()


# ---------------------------------------------------------------- under Node


@needs_node
def test_the_grammar_passes_its_tests_in_vscode_textmate() -> None:
    # (Not named *.gpp: the repository's programs are formatted and fingerprinted by other tests.)
    grammar_tests = (EXTENSION / "test" / "grammar").glob("*.syntax-test")
    cases = sorted(p.relative_to(EXTENSION).as_posix() for p in grammar_tests)
    assert cases
    done = node(npm_tool("vscode-tmgrammar-test"), *cases)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.count("run successfuly") == len(cases), done.stdout


@needs_node
def test_a_wrong_scope_fails_the_grammar_test(tmp_path: Path) -> None:
    """The grammar test is strict: a case expecting the wrong scope fails."""
    case = tmp_path / "wrong.syntax-test"
    case.write_text(
        f'// SYNTAX TEST "{TEXTMATE_SCOPE}" "wrong"\nwhile (true) {{ }}\n// <----- constant.language.golog\n',
        encoding="utf-8",
    )
    done = node(npm_tool("vscode-tmgrammar-test"), str(case))
    assert done.returncode != 0
    assert "missing required scopes: constant.language.golog" in done.stdout


@needs_node
def test_the_extension_activates_starts_gpp_lsp_and_launches_gpp_dap(tmp_path: Path) -> None:
    program = tmp_path / "agent.gpp"
    done = node("test/activate.js", GPP, str(program))
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["adapter"] == {"command": GPP, "args": ["dap"]}
    launch = {"type": "gpp", "request": "launch"}
    # F5 without a launch.json debugs the golog++ file in the editor, stopped at its start.
    assert report["resolved"]["empty"] == {
        **launch,
        "name": "Debug the agent",
        "program": str(program),
        "stopOnEntry": True,
    }
    assert report["resolved"]["program"] == {**launch, "name": "p", "program": str(program)}
    # Relative paths start from the workspace folder.
    assert report["resolved"]["inFolder"] == {**launch, "name": "f", "program": str(program), "cwd": "/work/space"}
    assert report["resolved"]["neither"] is None
    assert report["refusal"] == ['A golog++ launch needs a "program" to run or a "trace" to replay.']
    # The debugger's hover evaluates a whole call and the fields read from it.
    assert report["hover"] == {"loc": "loc(a)", "a": "a", "table": "table", "pose": "pose().x", "x =": "x", "if": "if"}
    # The language client got the real server running, and stopped it.
    assert report["running"] and report["stopped"], report
    assert report["server"]["name"] == "gpp"
    assert {"hoverProvider", "definitionProvider", "semanticTokensProvider"} <= set(report["capabilities"])
    assert report["messages"] == []


@needs_node
def test_an_unknown_gpp_command_is_reported_to_the_user(tmp_path: Path) -> None:
    done = node("test/activate.js", str(tmp_path / "no-gpp-here"), str(tmp_path / "agent.gpp"))
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert not report["running"]
    assert any('set "gpp.path" to the gpp command' in m for m in report["messages"]), report["messages"]


@needs_node
def test_vsce_packages_the_extension_with_its_language_client_and_without_its_tests(tmp_path: Path) -> None:
    vsix = tmp_path / "gpp-golog.vsix"
    done = node(npm_tool("vsce"), "package", "--allow-missing-repository", "--out", str(vsix))
    assert done.returncode == 0, done.stdout + done.stderr
    names = set(zipfile.ZipFile(vsix).namelist())
    wanted = {"extension.js", "package.json", "language-configuration.json", "syntaxes/golog.tmLanguage.json"}
    assert {f"extension/{name}" for name in wanted} <= names
    assert "extension/node_modules/vscode-languageclient/package.json" in names
    assert not any("/test/" in n or "vscode-tmgrammar-test" in n or "@vscode/vsce" in n for n in names)
    assert not any(n.startswith("extension/node_modules/@vscode/debugadapter") for n in names)
