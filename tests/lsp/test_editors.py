"""The editor set-ups of docs/editor.md and the editor files of editors/: the generated files are
current, the Neovim 0.7 set-up works in Debian's headless Neovim against the real `gpp lsp`
(diagnostics arrive, the syntax file colours the keywords), the dap-mode set-up debugs an agent
in Debian's Emacs against the real `gpp dap`, and the other snippets parse and start `gpp lsp`
or `gpp dap` as the VS Code extension does.

Neovim, Emacs and dap-mode come from Debian's packages (`make neovim`, `make emacs` install them
as root with apt-get): without them their tests are skipped and say so.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import pytest

from gpp.syntax.editor_files import GENERATED
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, SECTION_WORDS
from gpp.syntax.vocabulary import section_words, word_classes
from tests.support.lsp_client import expected

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "editor.md"
NVIM = shutil.which("nvim")
needs_nvim = pytest.mark.skipif(
    NVIM is None, reason="nvim is not installed: `make neovim` installs Debian's package (as root with apt-get)"
)


def snippet(name: str) -> str:
    """The code block of docs/editor.md after `<!-- editor: NAME -->`."""
    text = GUIDE.read_text(encoding="utf-8")
    found = re.search(rf"<!-- editor: {re.escape(name)} -->\n```\w*\n(.*?)\n```", text, re.DOTALL)
    assert found is not None, f"docs/editor.md has no `{name}` snippet"
    return found.group(1) + "\n"


# ---------------------------------------------------------------- the word list and its files


@pytest.mark.parametrize("path", list(GENERATED), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_the_generated_editor_files_are_current(path: Path) -> None:
    assert path.read_text(encoding="utf-8") == GENERATED[path](), (
        f"{path.relative_to(ROOT)} is out of date: regenerate it with `python -m gpp.syntax.editor_files`"
    )


def test_the_word_list_holds_every_keyword_of_the_lexer_once() -> None:
    words = [w for c in word_classes() for w in c.words]
    assert len(words) == len(set(words))
    assert set(words) == set(KEYWORDS) | set(PLATFORM_KEYWORDS)
    assert set(section_words()) == set(SECTION_WORDS)
    assert all(c.words and c.scope.endswith(".golog") for c in word_classes())


# ---------------------------------------------------------------- Neovim

PROGRAM = """\
// a program with an error
symbol domain Room = {lobby, hall}
action go(Room r) { }
procedure main() {
    while (false) { go(lobby); }
    guide(hall);
}
"""

# Run after the documented init.lua has opened the file: wait for the server's diagnostics,
# then write them, the buffer's filetype and the highlight groups at a few places to a file.
PROBE = """\
local buf = vim.api.nvim_get_current_buf()
local arrived = vim.wait(60000, function() return #vim.diagnostic.get(buf) > 0 end, 50)
local out = { filetype = vim.bo.filetype, arrived = arrived, diagnostics = {}, groups = {} }
for _, d in ipairs(vim.diagnostic.get(buf)) do
  table.insert(out.diagnostics, { line = d.lnum, col = d.col, code = d.code, source = d.source, message = d.message })
end
for _, at in ipairs(PLACES) do
  local id = vim.fn.synID(at[1], at[2], 1)
  out.groups[at[3]] = vim.fn.synIDattr(vim.fn.synIDtrans(id), "name")
end
vim.fn.writefile({ vim.fn.json_encode(out) }, OUT)
vim.cmd("qa!")
"""


def _place(needle: str) -> tuple[int, int]:
    """(line, column), 1-based as Vim counts, of `needle` in PROGRAM."""
    offset = PROGRAM.index(needle)
    line = PROGRAM.count("\n", 0, offset)
    return line + 1, offset - (PROGRAM.rfind("\n", 0, offset) + 1) + 1


def run_nvim(tmp_path: Path, init: str, probe: str, file: Path) -> subprocess.CompletedProcess[str]:
    assert NVIM is not None
    (tmp_path / "init.lua").write_text(init, encoding="utf-8")
    (tmp_path / "probe.lua").write_text(probe, encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CONFIG_HOME": str(tmp_path / "config")}
    env |= {"XDG_DATA_HOME": str(tmp_path / "data"), "XDG_STATE_HOME": str(tmp_path / "state")}
    return subprocess.run(
        [NVIM, "--headless", "-i", "NONE", "-u", "init.lua", "-c", "luafile probe.lua", str(file)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )


@needs_nvim
def test_the_neovim_07_set_up_shows_the_servers_diagnostics_and_colours_keywords(tmp_path: Path) -> None:
    init = snippet("neovim-0.7")
    # The checkout's files and this Python's gpp, where the user writes their own paths.
    init = init.replace('"/path/to/gpp/.venv/bin/gpp", "lsp"', f'{json.dumps(sys.executable)}, "-m", "gpp", "lsp"')
    init = init.replace("/path/to/gpp", str(ROOT))
    assert "/path/to" not in init
    places = {"declaration": "action", "statement": "while", "type": "symbol", "constant": "false"}
    places |= {"comment": "a program", "name": "go(lobby)"}
    lua_places = ", ".join(
        f'{{{line}, {col}, "{what}"}}' for what, (line, col) in ((w, _place(n)) for w, n in places.items())
    )
    out = tmp_path / "result.json"
    probe = f"local PLACES = {{ {lua_places} }}\nlocal OUT = {json.dumps(str(out))}\n" + PROBE
    program = tmp_path / "agent.gpp"
    program.write_text(PROGRAM, encoding="utf-8")
    done = run_nvim(tmp_path, init, probe, program)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Error" not in done.stdout + done.stderr, done.stdout + done.stderr
    result = json.loads(out.read_text(encoding="utf-8"))
    assert result["filetype"] == "golog"
    assert result["arrived"], "no diagnostics from gpp lsp"
    # What `gpp check` finds, among it the unknown `guide`.
    found = [(d["code"], d["line"], d["col"], d["message"].split("\n")[0]) for d in result["diagnostics"]]
    assert found == [(code, line, col, message) for code, (line, col, _, _), message in expected(program)]
    assert ("E0103", 5, 4) in [f[:3] for f in found]
    assert {d["source"] for d in result["diagnostics"]} == {"gpp"}
    assert result["groups"] == {
        "declaration": "Type",  # (Structure, which Vim links to Type)
        "statement": "Statement",
        "type": "Type",
        "constant": "Constant",
        "comment": "Comment",
        "name": "",
    }


@needs_nvim
@pytest.mark.parametrize("name", ["neovim-0.7", "neovim-0.10", "neovim-0.11"])
def test_the_neovim_snippets_are_lua(tmp_path: Path, name: str) -> None:
    """Each Lua snippet compiles (what it calls is tested where this Neovim has it: 0.7)."""
    code = snippet(name)
    assert '"/path/to/gpp/.venv/bin/gpp", "lsp"' in code and "/path/to/gpp/editors/vim" in code
    (tmp_path / "snippet.lua").write_text(code, encoding="utf-8")
    out = tmp_path / "compiled.txt"
    probe = (
        'local f = assert(io.open("snippet.lua")); local chunk, err = loadstring(f:read("*a")); f:close()\n'
        f"vim.fn.writefile({{ chunk and 'ok' or ('error: ' .. err) }}, {json.dumps(str(out))})\n"
        'vim.cmd("qa!")\n'
    )
    done = run_nvim(tmp_path, "", probe, tmp_path / "snippet.lua")
    assert done.returncode == 0, done.stderr
    assert out.read_text(encoding="utf-8").strip() == "ok"


# ---------------------------------------------------------------- Emacs, Helix, VS Code


def read_sexps(text: str) -> list[object]:
    """Emacs Lisp forms as nested lists of atoms (strings as ('str', text)); ValueError when a
    parenthesis or string is not closed."""
    tokens = re.findall(r'"(?:[^"\\]|\\.)*"|;[^\n]*|\?\\?.|[()]|\'|`|,@?|[^\s()"\';`,]+', text)
    if "".join(tokens).replace(" ", "") != re.sub(r"\s+", "", text):
        raise ValueError("text that is not Emacs Lisp")
    stack: list[list[object]] = [[]]
    for token in tokens:
        if token.startswith(";"):
            continue
        if token == "(":
            stack.append([])
        elif token == ")":
            if len(stack) == 1:
                raise ValueError("a `)` without its `(`")
            done = stack.pop()
            stack[-1].append(done)
        elif token.startswith('"'):
            stack[-1].append(("str", token[1:-1]))
        else:
            stack[-1].append(token)
    if len(stack) != 1:
        raise ValueError("a `(` without its `)`")
    return stack[0]


def test_the_emacs_snippet_loads_the_mode_and_starts_gpp_lsp_with_eglot() -> None:
    forms = read_sexps(snippet("emacs"))
    assert ["require", "'", "golog-mode"] in forms
    flat = json.dumps(forms)
    assert json.dumps(["golog-mode", ["str", "/path/to/gpp/.venv/bin/gpp"], ["str", "lsp"]]) in flat
    assert "eglot-server-programs" in flat and "eglot-ensure" in flat
    assert json.dumps(["str", "/path/to/gpp/editors/emacs"]) in flat
    assert (ROOT / "editors" / "emacs" / "golog-mode.el").is_file()


def test_the_emacs_mode_is_lisp_and_provides_golog_mode() -> None:
    forms = read_sexps((ROOT / "editors" / "emacs" / "golog-mode.el").read_text(encoding="utf-8"))
    heads = [f[0] for f in forms if isinstance(f, list) and f]
    assert heads == ["defconst", "defvar", "define-derived-mode", "add-to-list", "provide"]
    assert ["provide", "'", "golog-mode"] in forms
    for word in ("procedure", "while", "exists", "true", "initially"):
        assert json.dumps(["str", word]) in json.dumps(forms)


def test_the_helix_snippet_is_toml_that_starts_gpp_lsp_for_gpp_files() -> None:
    config = tomllib.loads(snippet("helix"))
    server = config["language-server"]["gpp"]
    assert (Path(server["command"]).name, server["args"]) == ("gpp", ["lsp"])
    (language,) = config["language"]
    assert language["file-types"] == ["gpp"] and language["language-servers"] == ["gpp"]
    assert language["name"] == "golog"


def vscode_manifest() -> dict[str, Any]:
    loaded: dict[str, Any] = json.loads((ROOT / "editors" / "vscode" / "package.json").read_text(encoding="utf-8"))
    return loaded


def test_the_vscode_snippet_sets_the_extensions_gpp_command() -> None:
    settings = json.loads(snippet("vscode"))
    assert Path(settings["gpp.path"]).name == "gpp"
    assert set(settings) <= set(vscode_manifest()["contributes"]["configuration"]["properties"])


def test_the_vscode_launch_json_is_what_the_extension_writes() -> None:
    launch = json.loads(snippet("vscode-launch"))
    (debugger,) = vscode_manifest()["contributes"]["debuggers"]
    assert launch["configurations"] == debugger["initialConfigurations"]


# The launches every editor's set-up offers: the program in the editor and a trace to replay.
LAUNCH_ATTRIBUTES = [
    {"type", "request", "name", "program", "stopOnEntry", "cwd"},
    {"type", "request", "name", "trace", "cwd"},
]


@needs_nvim
def test_the_nvim_dap_snippet_defines_the_adapter_and_the_launches(tmp_path: Path) -> None:
    """The snippet runs (in Debian's Neovim 0.7, with a stand-in for nvim-dap, which needs 0.9)
    and gives nvim-dap the adapter `gpp dap` and the two launches of the VS Code extension."""
    code = snippet("nvim-dap")
    out = tmp_path / "dap.json"
    stub = (
        "local calls = {}\n"
        "local dap = { adapters = {}, configurations = {}, repl = { open = function() end } }\n"
        "for _, name in ipairs({ 'continue', 'toggle_breakpoint', 'step_over', 'step_into', 'step_out', "
        "'set_breakpoint' }) do dap[name] = function() end end\n"
        "package.preload['dap'] = function() return dap end\n"
    )
    probe = (
        stub
        + "dofile('snippet.lua')\n"
        + "local launches = {}\n"
        + "for i, c in ipairs(dap.configurations.golog) do\n"
        + "  local copy = {}\n"
        + "  for k, v in pairs(c) do copy[k] = type(v) == 'function' and '<asked>' or v end\n"
        + "  launches[i] = copy\n"
        + "end\n"
        + "local result = vim.fn.json_encode({ adapter = dap.adapters.gpp, launches = launches })\n"
        + f"vim.fn.writefile({{ result }}, {json.dumps(str(out))})\n"
        + 'vim.cmd("qa!")\n'
    )
    (tmp_path / "snippet.lua").write_text(code, encoding="utf-8")
    done = run_nvim(tmp_path, "", probe, tmp_path / "snippet.lua")
    assert done.returncode == 0, done.stdout + done.stderr
    result = json.loads(out.read_text(encoding="utf-8"))
    assert result["adapter"] == {"type": "executable", "command": "/path/to/gpp/.venv/bin/gpp", "args": ["dap"]}
    assert [set(launch) for launch in result["launches"]] == LAUNCH_ATTRIBUTES
    program, replay = result["launches"]
    (debugger,) = vscode_manifest()["contributes"]["debuggers"]
    assert program == debugger["initialConfigurations"][0]
    assert replay == {**debugger["initialConfigurations"][1], "trace": "<asked>"}


def test_the_emacs_dap_snippet_registers_gpp_dap_and_the_launches() -> None:
    forms = read_sexps(snippet("emacs-dap"))
    flat = json.dumps(forms)
    assert ["require", "'", "dap-mode"] in forms
    assert json.dumps([["str", "/path/to/gpp/.venv/bin/gpp"], ["str", "dap"]]) in flat
    templates = [f for f in forms if isinstance(f, list) and f[:1] == ["dap-register-debug-template"]]
    assert len(templates) == 2
    for template, attributes in zip(templates, LAUNCH_ATTRIBUTES, strict=True):
        plist = template[2]
        assert isinstance(plist, list) and plist[0] == "list"
        keys = {str(k).removeprefix(":") for k in plist[1::2]}
        assert keys == attributes
        assert plist[plist.index(":type") + 1] == ("str", "gpp")


EMACS = shutil.which("emacs")
needs_emacs = pytest.mark.skipif(
    EMACS is None, reason="emacs is not installed: `make emacs` installs Debian's emacs-nox and elpa-dap-mode (as root)"
)

# A program to debug, and what Emacs does after the documented init.el: set a breakpoint on
# `go(office);`, start the launch "golog++: Debug the agent" (stopped on entry), continue to the
# breakpoint, ask for the stack and evaluate an expression there, and write what it got.
DEBUGGED = """\
symbol domain Room = {office, kitchen}
Room fluent robot_at() { initially: () = office; }
number fluent cups() { initially: () = 0; }
action go(Room r) { precondition: robot_at() != r effect: robot_at() = r; }
action take() { effect: cups() = cups() + 1; }
procedure main() {
    go(kitchen);
    take();
    go(office);
}
"""
DAP_PROBE = """\
(unless (require 'dap-mode nil t)
  (with-temp-file OUT (insert "{\\"missing\\": \\"dap-mode\\"}"))
  (kill-emacs 0))
(defvar probe-stops 0)
(add-hook 'dap-stopped-hook (lambda (_session) (setq probe-stops (1+ probe-stops))))
(defun probe-wait (what)
  (let ((i 0))
    (while (and (< i 600) (not (funcall what)))
      (accept-process-output nil 0.1)
      (setq i (1+ i)))))
(defun probe-request (command arguments)
  (let ((answer nil) (session (dap--cur-session)))
    (dap--send-message (dap--make-request command arguments)
                       (dap--resp-handler (lambda (response) (setq answer (gethash "body" response))))
                       session)
    (probe-wait (lambda () answer))
    answer))
(find-file PROGRAM)
(goto-char (point-min))
(search-forward "go(office);")
(dap-breakpoint-add)
(dap-debug (cdr (assoc "golog++: Debug the agent" dap-debug-template-configurations)))
(probe-wait (lambda () (= probe-stops 1)))
(dap-continue (dap--cur-session) (dap--debug-session-thread-id (dap--cur-session)))
(probe-wait (lambda () (= probe-stops 2)))
(let* ((top (car (gethash "stackFrames" (probe-request "stackTrace" (list :threadId 1)))))
       (value (probe-request "evaluate" (list :expression "cups() + 1" :frameId (gethash "id" top)
                                              :context "repl"))))
  (with-temp-file OUT
    (insert (json-encode (list (cons "stops" probe-stops)
                               (cons "top" (list (gethash "name" top) (gethash "line" top)))
                               (cons "evaluated" (gethash "result" value)))))))
(dap-disconnect (dap--cur-session))
(kill-emacs 0)
"""


@needs_emacs
def test_the_emacs_dap_snippet_debugs_with_dap_mode(tmp_path: Path) -> None:
    """Debian's Emacs and dap-mode with the documented set-up, against the real `gpp dap`."""
    init = snippet("emacs-dap").replace("/path/to/gpp/.venv/bin/gpp", str(Path(sys.executable).with_name("gpp")))
    assert "/path/to" not in init
    program = tmp_path / "agent.gpp"
    program.write_text(DEBUGGED, encoding="utf-8")
    out = tmp_path / "result.json"
    names = f"(defvar PROGRAM {json.dumps(str(program))})\n(defvar OUT {json.dumps(str(out))})\n"
    (tmp_path / "probe.el").write_text("(package-initialize)\n" + init + "\n" + names + DAP_PROBE, encoding="utf-8")
    assert EMACS is not None
    env = {**os.environ, "PYTHONPATH": str(ROOT), "HOME": str(tmp_path)}
    done = subprocess.run(
        [EMACS, "--batch", "-l", "probe.el"], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=180
    )
    assert done.returncode == 0, done.stdout + done.stderr
    result = json.loads(out.read_text(encoding="utf-8"))
    if result.get("missing"):
        pytest.skip("Emacs has no dap-mode: `make emacs` installs Debian's elpa-dap-mode (as root)")
    line = DEBUGGED.splitlines().index("    go(office);") + 1
    assert result == {"stops": 2, "top": ["main()", line], "evaluated": "2"}


def test_the_helix_debugger_extends_the_golog_language_with_gpp_dap() -> None:
    config = tomllib.loads(snippet("helix") + "\n" + snippet("helix-dap"))
    (language,) = config["language"]
    debugger = language["debugger"]
    assert (Path(debugger["command"]).name, debugger["args"], debugger["transport"]) == ("gpp", ["dap"], "stdio")
    program, replay = debugger["templates"]
    assert program["args"] == {"program": "{0}", "stopOnEntry": True}
    assert replay["args"] == {"trace": "{0}"}
    assert {t["request"] for t in debugger["templates"]} == {"launch"}


def test_the_vim_files_detect_gpp_files_and_colour_them() -> None:
    vim = ROOT / "editors" / "vim"
    assert "*.gpp setfiletype golog" in (vim / "ftdetect" / "golog.vim").read_text(encoding="utf-8")
    assert 'let b:current_syntax = "golog"' in (vim / "syntax" / "golog.vim").read_text(encoding="utf-8")
