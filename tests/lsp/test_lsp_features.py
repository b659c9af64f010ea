"""The language server's editor features (lsp.features), called as functions on real checked
programs: what each answers at a position, with exact names, kinds and LSP ranges (0-based
lines, UTF-16 columns). Positions are found with `text.index(...)`, so each test says in words
where it points; expected ranges are computed from the text independently of gpp.base.source."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest
from lsprotocol import types

import lsp.features as F
from gpp.base.resources import stdlib_dir
from gpp.check import CheckResult, check_program, check_text
from lsp.features.completion import DECLARATION_SNIPPETS, _plain
from lsp.features.tokens import TOKEN_MODIFIERS, TOKEN_TYPES

ROOT = Path(__file__).resolve().parents[2]


@dataclass
class Doc:
    """A checked program and one of its files, with position helpers for that file's text."""

    result: CheckResult
    path: Path
    text: str

    @classmethod
    def check(cls, text: str, path: Path, errors_allowed: bool = False) -> Doc:
        path = path.resolve()
        result = check_program(path, lint=False, overrides={path: text})
        if not errors_allowed:
            assert [d.message for d in result.diagnostics if d.is_error] == []
        return cls(result, path, text)

    @classmethod
    def load(cls, path: Path) -> Doc:
        path = path.resolve()
        return cls(check_program(path, lint=False), path, path.read_text(encoding="utf-8"))

    def at(self, needle: str, nth: int = 0, delta: int = 0) -> int:
        offset = -1
        for _ in range(nth + 1):
            offset = self.text.index(needle, offset + 1)
        return offset + delta

    def pos(self, offset: int) -> tuple[int, int]:
        return lsp_pos(self.text, offset)

    def rng(self, needle: str, nth: int = 0, length: int | None = None) -> tuple[tuple[int, int], tuple[int, int]]:
        start = self.at(needle, nth)
        return self.pos(start), self.pos(start + (len(needle) if length is None else length))

    @property
    def uri(self) -> str:
        return self.path.as_uri()


def lsp_pos(text: str, offset: int) -> tuple[int, int]:
    line_start = text.rfind("\n", 0, offset) + 1
    return text.count("\n", 0, offset), len(text[line_start:offset].encode("utf-16-le")) // 2


def rng(r: types.Range) -> tuple[tuple[int, int], tuple[int, int]]:
    return (r.start.line, r.start.character), (r.end.line, r.end.character)


def loc(location: types.Location) -> tuple[str, tuple[tuple[int, int], tuple[int, int]]]:
    return Path(location.uri.removeprefix("file://")).name, rng(location.range)


BLOCKS = """\
symbol domain block = {a, b, c}
symbol domain place = {table} | block

// Where a block rests.
// Null until sensed.
place fluent loc(block x) {
initially:
    (a) = table;
    (b) = a;
}

bool fluent clear(block x) {
initially:
    (a) = false;
    (b) = true;
    (c) = true;
}

action stack(block x, place y) {
precondition:
    clear(x) & x != y
effect:
    loc(x) = y;
}

procedure build(block x) {
    pick (place y in {table, c}) {
        stack(x, y);
    }
}

procedure main() {
    build(a);
    pick (block x) build(x);
}
"""


@pytest.fixture(scope="module")
def blocks(tmp_path_factory: pytest.TempPathFactory) -> Doc:
    return Doc.check(BLOCKS, tmp_path_factory.mktemp("blocks") / "blocks.gpp")


# ---------------------------------------------------------------- hover


def test_hover_on_a_fluent_shows_signature_doc_comment_and_initial_values(blocks: Doc) -> None:
    h = F.hover(blocks.result, blocks.path, blocks.at("loc(x) = y", delta=1))
    assert h is not None and isinstance(h.contents, types.MarkupContent)
    assert h.contents.kind is types.MarkupKind.Markdown
    assert h.contents.value == (
        "```gpp\nplace fluent loc(block x)\n```\n\n"
        "Where a block rests.\nNull until sensed.\n\n"
        "Initially:\n```gpp\n(a) = table;\n(b) = a;\n```"
    )
    assert h.range is not None and rng(h.range) == blocks.rng("loc(x) = y", length=3)


def test_hover_on_a_domain_element_a_parameter_and_a_pick_variable(blocks: Doc) -> None:
    def value(offset: int) -> str:
        h = F.hover(blocks.result, blocks.path, offset)
        assert h is not None and isinstance(h.contents, types.MarkupContent)
        return h.contents.value

    assert value(blocks.at("(b) = a", delta=6)) == "```gpp\nsymbol a\n```\n\nelement of `block`, `place`"
    assert value(blocks.at("x != y")) == "```gpp\nblock x\n```\n\nparameter of action `stack`"
    assert value(blocks.at("stack(x, y)", delta=9)) == "```gpp\nplace y\n```\n\npick variable"
    assert value(blocks.at("domain place", delta=7)) == ("```gpp\nsymbol domain place = {table, a, b, c}\n```")
    assert value(blocks.at("precondition")) == "`precondition:` the condition under which the action can start."
    assert F.hover(blocks.result, blocks.path, blocks.at("procedure build")) is None


def test_hover_range_counts_utf16_units_after_non_ascii_text(tmp_path: Path) -> None:
    doc = Doc.check(
        "bool fluent ready() { initially: () = true; }\n"
        "string function greet(string s) = s\n"
        'procedure main() { test(greet("🤖 é") == "x" & ready()); } // ü\n',
        tmp_path / "m.gpp",
    )
    h = F.hover(doc.result, doc.path, doc.at("ready());"))
    assert h is not None and h.range is not None
    # `🤖` is two UTF-16 units: the column is one more than the character count.
    line_start = doc.text.rindex("\n", 0, doc.at("ready());")) + 1
    assert rng(h.range) == ((2, doc.at("ready());") - line_start + 1), (2, doc.at("ready());") - line_start + 6))
    assert rng(h.range) == doc.rng("ready());", length=5)


# ---------------------------------------------------------------- definition and references


def test_definition_goes_into_an_included_file_and_to_the_included_file(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("// the flag\nbool fluent ready() { initially: () = true; }\n")
    doc = Doc.check('#include "sub.gpp"\nprocedure main() { test(ready()); }\n', tmp_path / "main.gpp")
    found = F.definition(doc.result, doc.path, doc.at("ready()"))
    assert [loc(x) for x in found] == [("sub.gpp", ((1, 12), (1, 17)))]
    assert found[0].uri == (tmp_path / "sub.gpp").resolve().as_uri()
    on_include = F.definition(doc.result, doc.path, doc.at("sub.gpp"))
    assert [loc(x) for x in on_include] == [("sub.gpp", ((0, 0), (0, 0)))]
    assert F.definition(doc.result, doc.path, doc.at("test")) == []


def test_definition_goes_into_the_standard_library() -> None:
    doc = Doc.load(ROOT / "examples" / "blocksworld.gpp")
    found = F.definition(doc.result, doc.path, doc.at("loc(c) == t3"))
    stdlib_file = (stdlib_dir() / "sim" / "blocksworld.gpp").resolve()
    std_text = stdlib_file.read_text(encoding="utf-8")
    name_at = std_text.index("fluent loc(") + len("fluent ")
    assert [(x.uri, rng(x.range)) for x in found] == [
        (stdlib_file.as_uri(), (lsp_pos(std_text, name_at), lsp_pos(std_text, name_at + 3)))
    ]


def test_references_span_included_files_with_or_without_the_declaration(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("action go() {}\nprocedure twice() { go(); go(); }\n")
    doc = Doc.check('#include "sub.gpp"\nprocedure main() { twice(); go(); }\n', tmp_path / "main.gpp")
    with_decl = F.references(doc.result, doc.path, doc.at("go()"), True)
    assert [loc(x) for x in with_decl] == [
        ("sub.gpp", ((0, 7), (0, 9))),
        ("sub.gpp", ((1, 20), (1, 22))),
        ("sub.gpp", ((1, 26), (1, 28))),
        ("main.gpp", ((1, 28), (1, 30))),
    ]
    without = F.references(doc.result, doc.path, doc.at("go()"), False)
    assert [loc(x) for x in without] == [loc(x) for x in with_decl[1:]]


def test_document_highlight_marks_the_assigned_fluent_as_write(blocks: Doc) -> None:
    found = F.document_highlight(blocks.result, blocks.path, blocks.at("loc(x) = y"))
    assert [(rng(h.range), h.kind) for h in found] == [
        (blocks.rng("loc(", 0, length=3), types.DocumentHighlightKind.Text),
        (blocks.rng("loc(", 1, length=3), types.DocumentHighlightKind.Write),
    ]
    # A parameter: declared, then read.
    found = F.document_highlight(blocks.result, blocks.path, blocks.at("x, place y"))
    assert [(rng(h.range), h.kind) for h in found] == [
        (blocks.rng("x, place y", length=1), types.DocumentHighlightKind.Text),
        (blocks.rng("x) & x", length=1), types.DocumentHighlightKind.Read),
        (blocks.rng("x != y", length=1), types.DocumentHighlightKind.Read),
        (blocks.rng("x) = y", length=1), types.DocumentHighlightKind.Read),
    ]
    # An action has no read or write.
    found = F.document_highlight(blocks.result, blocks.path, blocks.at("stack(x, y)"))
    assert {h.kind for h in found} == {types.DocumentHighlightKind.Text}
    assert len(found) == 2


# ---------------------------------------------------------------- rename


def edits(edit: types.WorkspaceEdit | None) -> dict[str, list[tuple[tuple[tuple[int, int], tuple[int, int]], str]]]:
    assert edit is not None and edit.changes is not None
    return {Path(uri).name: [(rng(e.range), e.new_text) for e in es] for uri, es in edit.changes.items()}


def test_rename_of_a_parameter_touches_only_its_own_scope(blocks: Doc) -> None:
    found = edits(F.rename(blocks.result, blocks.path, blocks.at("x) {\n    pick"), "blk"))
    assert found == {
        "blocks.gpp": [
            (blocks.rng("x) {\n    pick", length=1), "blk"),
            (blocks.rng("x, y);\n    }", length=1), "blk"),
        ]
    }


def test_rename_of_a_pick_variable_touches_only_the_pick(blocks: Doc) -> None:
    found = edits(F.rename(blocks.result, blocks.path, blocks.at("build(x)", delta=6), "b2"))
    assert found == {"blocks.gpp": [(blocks.rng("x) build", length=1), "b2"), (blocks.rng("x);\n}", length=1), "b2")]}
    prepared = F.prepare_rename(blocks.result, blocks.path, blocks.at("build(x)", delta=6))
    assert isinstance(prepared, types.PrepareRenamePlaceholder)
    assert (rng(prepared.range), prepared.placeholder) == (blocks.rng("x);\n}", length=1), "x")


def test_rename_across_an_include(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("action go() {}\nprocedure twice() { go(); go(); }\n")
    doc = Doc.check('#include "sub.gpp"\nprocedure main() { twice(); go(); }\n', tmp_path / "main.gpp")
    found = edits(F.rename(doc.result, doc.path, doc.at("go()"), "run"))
    assert found == {
        "sub.gpp": [(((0, 7), (0, 9)), "run"), (((1, 20), (1, 22)), "run"), (((1, 26), (1, 28)), "run")],
        "main.gpp": [(((1, 28), (1, 30)), "run")],
    }


@pytest.mark.parametrize(
    ("needle", "delta", "new_name", "message"),
    [
        ("stack(x, y)", 0, "while", "`while` is a keyword of golog++"),
        ("stack(x, y)", 0, "2go", "`2go` is not a valid name (a letter, then letters, digits or '_')"),
        ("stack(x, y)", 0, "_go", "`_go` is not a valid name (a letter, then letters, digits or '_')"),
        ("stack(x, y)", 0, "clear", "`clear` is already declared as a fluent"),
        ("stack(x, y)", 0, "place", "`place` is already declared as a domain"),
        ("x != y", 0, "y", "`stack` already has a parameter named `y`"),
        # The pick variable `y` is visible where `x` is used inside the pick.
        ("x) {\n    pick", 0, "y", "renaming to `y` would clash with the variable `y` visible at line 28"),
        # Renaming `x` to `table` would hide the domain element used in its scope.
        ("x) {\n    pick", 0, "table", "renaming to `table` would hide the symbol `table` used at line 27"),
        # A domain element renamed to a variable's name, where that variable is in scope (in
        # `initially:`, a fluent's parameter stands for all its values).
        ("(b) = a", 6, "x", "renaming to `x` would clash with the parameter `x` visible at line 8"),
    ],
)
def test_rename_refuses(blocks: Doc, needle: str, delta: int, new_name: str, message: str) -> None:
    with pytest.raises(F.RenameError) as e:
        F.rename(blocks.result, blocks.path, blocks.at(needle, delta=delta), new_name)
    assert str(e.value) == message


def test_rename_refuses_keywords_predefined_and_standard_library_symbols() -> None:
    doc = Doc.load(ROOT / "examples" / "blocksworld.gpp")
    cases = [
        (doc.at("while"), "`while` is a keyword of golog++ and cannot be renamed"),
        (doc.at("gripper_home"), "`gripper_home` is defined in the standard library and cannot be renamed"),
        (doc.at("loc(c)"), "`loc` is defined in the standard library and cannot be renamed"),
        (doc.at("   ", delta=1), "there is no name to rename here"),
    ]
    for offset, message in cases:
        with pytest.raises(F.RenameError) as e:
            F.prepare_rename(doc.result, doc.path, offset)
        assert str(e.value) == message
        with pytest.raises(F.RenameError):
            F.rename(doc.result, doc.path, offset, "fine")


def test_rename_refuses_a_predefined_symbol_and_a_builtin_type(tmp_path: Path) -> None:
    doc = Doc.check("number function now() = context_time()\n", tmp_path / "m.gpp")
    with pytest.raises(F.RenameError, match="`context_time` is predefined and cannot be renamed"):
        F.prepare_rename(doc.result, doc.path, doc.at("context_time"))
    with pytest.raises(F.RenameError, match="`number` is a keyword of golog\\+\\+ and cannot be renamed"):
        F.rename(doc.result, doc.path, doc.at("number"), "num")


# ---------------------------------------------------------------- symbols


def test_document_symbols_are_hierarchical(blocks: Doc) -> None:
    found = F.document_symbols(blocks.result, blocks.path)

    def tree(symbols: list[types.DocumentSymbol]) -> list[object]:
        return [(s.name, s.kind, s.detail, tree(s.children or [])) for s in symbols]

    K = types.SymbolKind
    assert tree(found) == [
        ("block", K.Enum, "symbol domain block = {a, b, c}", [("a", K.EnumMember, "symbol", []),
                                                             ("b", K.EnumMember, "symbol", []),
                                                             ("c", K.EnumMember, "symbol", [])]),
        ("place", K.Enum, "symbol domain place = {table, a, b, c}", [("table", K.EnumMember, "symbol", [])]),
        ("loc", K.Property, "place fluent loc(block x)", [("x", K.Variable, "block x", [])]),
        ("clear", K.Property, "bool fluent clear(block x)", [("x", K.Variable, "block x", [])]),
        ("stack", K.Event, "action stack(block x, place y)",
         [("x", K.Variable, "block x", []), ("y", K.Variable, "place y", [])]),
        ("build", K.Method, "procedure build(block x)", [("x", K.Variable, "block x", [])]),
        ("main", K.Method, "procedure main()", []),
    ]  # fmt: skip
    stack = found[4]
    start = blocks.at("action stack")
    assert rng(stack.range) == (blocks.pos(start), blocks.pos(blocks.at("}\n", 3) + 1))
    assert rng(stack.selection_range) == blocks.rng("stack(block", length=5)


def test_workspace_symbols_match_fuzzily_best_first_and_list_a_shared_include_once(tmp_path: Path) -> None:
    (tmp_path / "shared.gpp").write_text("action stack_up() {}\nbool fluent stacked() { initially: () = false; }\n")
    one = Doc.check('#include "shared.gpp"\naction stack() {}\nprocedure main() { stack(); }\n', tmp_path / "one.gpp")
    two = Doc.check('#include "shared.gpp"\nprocedure restack() { stack_up(); }\n', tmp_path / "two.gpp")
    found = F.workspace_symbols([one.result, two.result], "stack")
    assert [(s.name, s.kind, Path(s.location.uri).name) for s in found] == [
        ("stack", types.SymbolKind.Event, "one.gpp"),
        ("stack_up", types.SymbolKind.Event, "shared.gpp"),
        ("stacked", types.SymbolKind.Property, "shared.gpp"),
        ("restack", types.SymbolKind.Method, "two.gpp"),
    ]
    assert [s.name for s in F.workspace_symbols([one.result, two.result], "stkd")] == ["stacked"]
    assert F.workspace_symbols([one.result], "zzz") == []


# ---------------------------------------------------------------- signature help and inlay hints


def test_signature_help_follows_the_argument_under_the_cursor(blocks: Doc) -> None:
    def active(offset: int) -> tuple[str, int | None, list[str]] | None:
        h = F.signature_help(blocks.result, blocks.path, offset)
        if h is None:
            return None
        sig = h.signatures[0]
        labels = []
        for p in sig.parameters or []:
            assert isinstance(p.label, tuple)
            labels.append(sig.label[p.label[0] : p.label[1]])
        return sig.label, h.active_parameter, labels

    stack = ("action stack(block x, place y)",)
    assert active(blocks.at("stack(x, y)", delta=6)) == (*stack, 0, ["block x", "place y"])
    assert active(blocks.at("stack(x, y)", delta=8)) == (*stack, 1, ["block x", "place y"])
    assert active(blocks.at("stack(x, y)", delta=10)) == (*stack, 1, ["block x", "place y"])
    assert active(blocks.at("clear(x) &", delta=6)) == ("bool fluent clear(block x)", 0, ["block x"])
    assert active(blocks.at("stack(x, y)", delta=11)) is None  # after the ')'
    assert active(blocks.at("precondition")) is None


def test_signature_help_in_a_half_typed_call(tmp_path: Path) -> None:
    text = BLOCKS.replace("    build(a);\n", "    build(a);\n    stack(a, (b\n")
    doc = Doc.check(text, tmp_path / "m.gpp", errors_allowed=True)
    h = F.signature_help(doc.result, doc.path, doc.at("(b\n", delta=2))
    assert h is not None
    assert (h.signatures[0].label, h.active_parameter) == ("action stack(block x, place y)", 1)


def test_inlay_hints_name_parameters_except_for_same_named_variables(blocks: Doc) -> None:
    found = F.inlay_hints(blocks.result, blocks.path, 0, len(blocks.text))
    assert [(h.position.line, h.position.character, h.label, h.kind) for h in found] == [
        (*blocks.pos(blocks.at("a);\n    pick")), "x:", types.InlayHintKind.Parameter),
    ]
    # Within the range given only.
    assert F.inlay_hints(blocks.result, blocks.path, 0, blocks.at("procedure main")) == []


def test_inlay_hints_at_a_call_with_other_argument_names(tmp_path: Path) -> None:
    doc = Doc.check(BLOCKS.replace("stack(x, y);", "stack(x, c);"), tmp_path / "m.gpp")
    found = F.inlay_hints(doc.result, doc.path, 0, len(doc.text))
    assert [(h.position.line, h.position.character, h.label) for h in found] == [
        (*doc.pos(doc.at("c);")), "y:"),
        (*doc.pos(doc.at("a);\n    pick")), "x:"),
    ]


# ---------------------------------------------------------------- semantic tokens and folding


def decode(data: list[int]) -> list[tuple[int, int, int, str, set[str]]]:
    out = []
    line = char = 0
    for i in range(0, len(data), 5):
        dl, dc, length, t, m = data[i : i + 5]
        line += dl
        char = char + dc if dl == 0 else dc
        out.append((line, char, length, TOKEN_TYPES[t], {n for b, n in enumerate(TOKEN_MODIFIERS) if m >> b & 1}))
    return out


def test_the_until_of_a_during_is_a_keyword_and_its_condition_is_read(tmp_path: Path) -> None:
    text = BLOCKS.replace("    build(a);\n", "    during (stack(a, table)) until (clear(a)) {}\n")
    doc = Doc.check(text, tmp_path / "c.gpp")
    found = {(line, char): t for line, char, _, t, _ in decode(F.semantic_tokens(doc.result, doc.path))}
    assert found[doc.pos(doc.at("until ("))] == "keyword"
    assert found[doc.pos(doc.at("clear(a)"))] == "fluent"


def test_semantic_tokens_classify_names_by_kind(blocks: Doc) -> None:
    found = {
        (line, char): (length, t, m)
        for line, char, length, t, m in decode(F.semantic_tokens(blocks.result, blocks.path))
    }

    def at(needle: str, nth: int = 0) -> tuple[int, str, set[str]]:
        return found[blocks.pos(blocks.at(needle, nth))]

    assert at("block = ") == (5, "type", {"declaration"})
    assert at("a, b, c") == (1, "enumMember", {"declaration"})
    assert at("loc(block") == (3, "fluent", {"declaration"})
    assert at("block x) {\ninit") == (5, "type", set())
    assert at("stack(block") == (5, "action", {"declaration"})
    assert at("stack(x, y)") == (5, "action", set())
    assert at("build(a)") == (9 - 4, "procedure", set())
    assert at("x != y") == (1, "parameter", set())
    assert at("x) build") == (1, "variable", {"declaration"})
    assert at("procedure build") == (9, "keyword", set())
    assert at("precondition") == (12, "keyword", set())
    assert at("// Where") == (len("// Where a block rests."), "comment", set())
    assert at("bool fluent") == (4, "keyword", set())
    assert F.SEMANTIC_TOKENS_LEGEND.token_types == TOKEN_TYPES


def test_a_start_effect_section_is_a_keyword_with_a_hover_and_its_targets_are_completed(tmp_path: Path) -> None:
    text = BLOCKS.replace("effect:\n    loc(x) = y;", "start_effect:\n    clear(x) = false;\neffect:\n    loc(x) = y;")
    doc = Doc.check(text, tmp_path / "s.gpp")
    found = {(line, char): (length, t) for line, char, length, t, _ in decode(F.semantic_tokens(doc.result, doc.path))}
    assert found[doc.pos(doc.at("start_effect"))] == (len("start_effect"), "keyword")
    assert found[doc.pos(doc.at("clear(x) = false"))] == (len("clear"), "fluent")
    h = F.hover(doc.result, doc.path, doc.at("start_effect", delta=6))
    assert h is not None and isinstance(h.contents, types.MarkupContent)
    assert h.contents.value.startswith("`start_effect:` assignments applied when the action's activity starts")
    assert h.range is not None and rng(h.range) == doc.rng("start_effect:", length=len("start_effect:"))
    # At the start of a start effect: the fluents it may assign, as in `effect:`.
    items = labels(complete(text.replace("    clear(x) = false;", "    clear(x) = false;\n    @"), tmp_path))
    assert items == labels(complete(BLOCKS.replace("    loc(x) = y;", "    loc(x) = y;\n    @"), tmp_path))


def test_semantic_tokens_count_utf16_units(tmp_path: Path) -> None:
    doc = Doc.check(
        'string function greet(string s) = s\nbool function ok() = greet("🤖") == "é" & true // 🤖 ü\n',
        tmp_path / "m.gpp",
    )
    tokens = decode(F.semantic_tokens(doc.result, doc.path))
    line1 = [(c, n, t) for line, c, n, t, _ in tokens if line == 1]
    assert line1 == [
        (0, 4, "keyword"),
        (5, 8, "keyword"),
        (14, 2, "function"),
        (21, 5, "function"),
        (27, 4, "string"),  # "🤖" is 2 + 2 units
        (33 + 3, 3, "string"),  # after `) == `
        (42, 4, "keyword"),
        (47, 7, "comment"),
    ]


def test_folding_ranges_cover_declarations_blocks_and_comment_runs(blocks: Doc) -> None:
    found = F.folding_ranges(blocks.result, blocks.path)
    comment = types.FoldingRangeKind.Comment
    assert [(r.start_line, r.end_line, r.kind) for r in found] == [
        (3, 4, comment),  # the doc comment
        (5, 8, None),  # loc, up to the line before its '}'
        (11, 15, None),  # clear
        (18, 22, None),  # stack
        (19, 20, None),  # its precondition
        (21, 22, None),  # its effect
        (25, 28, None),  # build
        (26, 27, None),  # its pick's block
        (31, 33, None),  # main
    ]


# ---------------------------------------------------------------- completion


def labels(items: list[types.CompletionItem]) -> list[str]:
    return [i.label for i in sorted(items, key=lambda i: (i.sort_text or "", i.label))]


def complete(text: str, tmp_path: Path, marker: str = "@") -> list[types.CompletionItem]:
    offset = text.index(marker)
    doc = Doc.check(text.replace(marker, "", 1), tmp_path / "c.gpp", errors_allowed=True)
    return F.completion(doc.result, doc.path, offset)


def test_completion_in_statement_position_offers_actions_procedures_and_statement_keywords(tmp_path: Path) -> None:
    items = complete(BLOCKS.replace("    build(a);\n", "    build(a);\n    @\n"), tmp_path)
    assert labels(items)[:9] == [
        "build",
        "clear",
        "context_time",
        "loc",
        "main",
        "stack",
        "switch_state",
        "cancel",
        "choose",
    ]
    by_label = {i.label: i for i in items}
    assert by_label["stack"].kind is types.CompletionItemKind.Event
    assert by_label["stack"].detail == "action stack(block x, place y)"
    assert by_label["loc"].documentation == types.MarkupContent(
        kind=types.MarkupKind.Markdown, value="Where a block rests.\nNull until sensed."
    )
    assert "while" in by_label and "a" not in by_label


def test_completion_offers_the_elements_of_the_expected_domain_first(tmp_path: Path) -> None:
    # The argument of a fluent whose parameter is a `block`.
    items = complete(BLOCKS.replace("clear(x) &", "clear(@x) &"), tmp_path)
    assert labels(items)[:6] == ["a", "b", "c", "x", "y", "clear"]
    assert [i.label for i in items if i.preselect] == ["a", "b", "c", "x"]
    # The right side of `==` with a `place` on the left.
    items = complete(BLOCKS.replace("x != y", "loc(x) == @"), tmp_path)
    assert labels(items)[:7] == ["a", "b", "c", "table", "x", "y", "clear"]
    assert {i.label: i.kind for i in items}["table"] is types.CompletionItemKind.EnumMember


def test_completion_in_a_half_typed_statement_inside_pick_offers_the_pick_variable(tmp_path: Path) -> None:
    broken = BLOCKS.replace("    pick (block x) build(x);\n", "    pick (block zz)\n        if (clear(z@\n")
    items = complete(broken, tmp_path)
    assert labels(items)[:4] == ["a", "b", "c", "zz"]
    zz = next(i for i in items if i.label == "zz")
    assert (zz.kind, zz.detail) == (types.CompletionItemKind.Variable, "block zz")
    # Once the pick's statement has ended, its variable is gone.
    after = BLOCKS.replace("    pick (block x) build(x);\n", "    pick (block zz) build(zz);\n    test(clear(@\n")
    assert "zz" not in labels(complete(after, tmp_path))


def test_completion_of_types_sections_and_effects(tmp_path: Path) -> None:
    assert labels(complete(BLOCKS.replace("build(a);", "pick (@"), tmp_path)) == [
        "block", "place", "bool", "list", "number", "string", "symbol", "void",
    ]  # fmt: skip
    assert labels(complete(BLOCKS.replace("precondition:", "@"), tmp_path)) == [
        "duration", "effect", "mapping", "precondition", "senses", "silent", "start_effect",
    ]  # fmt: skip
    assert labels(complete(BLOCKS.replace("    loc(x) = y;", "    loc(x) = y;\n    @"), tmp_path)) == [
        "clear", "context_time", "loc", "if",
    ]  # fmt: skip
    assert labels(complete(BLOCKS.replace("procedure build(block x)", "procedure build(block @"), tmp_path)) == []
    assert complete(BLOCKS.replace("// Where", "// Wh@ere"), tmp_path) == []


def test_completion_at_top_level_offers_declaration_snippets(tmp_path: Path) -> None:
    items = complete(BLOCKS + "\n@", tmp_path)
    snippets = [i for i in items if i.kind is types.CompletionItemKind.Snippet]
    assert [i.label for i in snippets] == [label for label, _, _ in DECLARATION_SNIPPETS]
    assert {i.insert_text_format for i in snippets} == {types.InsertTextFormat.Snippet}
    assert [i.label for i in items if i.kind is types.CompletionItemKind.Enum] == ["block", "place"]


def test_the_servers_completion_list_keeps_the_names_that_hold_the_typed_word(tmp_path: Path) -> None:
    text = BLOCKS.replace("    build(a);\n", "    build(a);\n    sTk@\n")
    offset = text.index("@")
    doc = Doc.check(text.replace("@", "", 1), tmp_path / "c.gpp", errors_allowed=True)
    everything = F.completion(doc.result, doc.path, offset)
    found = F.completion_list(doc.result, doc.path, offset)
    # `stack` (s..t..k in order, any case) is kept; `build` and the keywords are left out.
    assert [i.label for i in found.items] == ["stack"]
    assert found.is_incomplete and len(everything) > 10
    assert found.items[0] == next(i for i in everything if i.label == "stack")
    # With no word typed (after `(`): everything, and the list is complete.
    at_paren = BLOCKS.index("build(a)") + len("build(")
    whole = F.completion_list(doc.result, doc.path, at_paren)
    assert not whole.is_incomplete
    assert [i.label for i in whole.items] == [i.label for i in F.completion(doc.result, doc.path, at_paren)]


def test_completion_right_after_an_edit_answers_from_the_last_check(tmp_path: Path) -> None:
    checked = BLOCKS.replace("    build(a);\n", "    build(a);\n    c\n")
    doc = Doc.check(checked, tmp_path / "e.gpp", errors_allowed=True)

    def answers(now: str, offset: int) -> set[str]:
        found = F.completion_after_edit(doc.result, doc.path, now, offset)
        assert found is not None and found.is_incomplete
        # The same items as a check of the new text gives there.
        fresh = Doc.check(now, tmp_path / "e.gpp", errors_allowed=True)
        want = F.completion_list(fresh.result, fresh.path, offset)
        assert [i.label for i in found.items] == [i.label for i in want.items]
        return {i.label for i in found.items}

    # `l` typed after `c`: the checked program at `c|`, filtered with `cl`.
    now = checked.replace("    c\n", "    cl\n")
    assert answers(now, now.index("    cl\n") + len("    cl")) == {"clear", "cancel"}
    # A change after the cursor only.
    now = checked.replace("build(x);\n}", "build(x); build(a);\n}")
    assert {"clear", "cancel", "choose", "stack"} <= answers(now, now.index("    c\n") + len("    c"))
    # A bracket typed (the place changed), or a line pasted: the caller must wait.
    now = checked.replace("    c\n", "    clear(\n")
    assert F.completion_after_edit(doc.result, doc.path, now, now.index("    clear(\n") + len("    clear(")) is None
    now = checked.replace("    c\n", "    stack(a, b);\n    c\n")
    assert F.completion_after_edit(doc.result, doc.path, now, now.index("    c\n") + len("    c")) is None
    # (Nothing changed: the check's own answer.)
    offset = checked.index("    c\n") + len("    c")
    same = F.completion_after_edit(doc.result, doc.path, checked, offset)
    assert same is not None and same.items == F.completion_list(doc.result, doc.path, offset).items


@pytest.mark.parametrize(
    ("before", "word"), [("x = count_2", "count_2"), ("f(a1", "a1"), ("12ab", "ab"), ("x + ", ""), ("", "")]
)
def test_the_typed_word_is_the_name_before_the_cursor(before: str, word: str) -> None:
    from lsp.features.completion import typed_word

    assert typed_word(before + " rest", len(before)) == word


def test_completion_items_are_built_once_per_check_and_forgotten_with_it(tmp_path: Path) -> None:
    import gc
    import weakref

    from lsp.features.common import _memos

    doc = Doc.check(BLOCKS, tmp_path / "m.gpp")
    at = doc.at("build(a)") + 2
    first = {i.label: i for i in F.completion(doc.result, doc.path, at)}
    again = {i.label: i for i in F.completion(doc.result, doc.path, at)}
    assert first["stack"] is again["stack"] and first == again
    # A new check of the same text: new items, equal to the old ones.
    other = Doc.check(BLOCKS, tmp_path / "m.gpp")
    fresh = {i.label: i for i in F.completion(other.result, other.path, at)}
    assert fresh["stack"] is not first["stack"] and fresh == first
    # What is remembered for a check does not keep it alive.
    gone = weakref.ref(doc.result)
    key = id(doc.result)
    assert key in _memos
    del doc
    gc.collect()
    assert gone() is None and key not in _memos


@pytest.mark.parametrize(("label", "body"), [(label, body) for label, _, body in DECLARATION_SNIPPETS])
def test_each_declaration_snippet_expands_to_valid_golog(tmp_path: Path, label: str, body: str) -> None:
    text = _plain(body)
    if label == "#include":
        (tmp_path / "file.gpp").write_text("")
    result = check_text(text, tmp_path / "snippet.gpp", lint=False)
    assert [d.message for d in result.diagnostics if d.is_error] == []


def test_completion_after_a_dot_offers_the_fields_of_the_subjects_compound(tmp_path: Path) -> None:
    example = (ROOT / "examples" / "lists_and_compounds.gpp").read_text(encoding="utf-8")
    at = example.index("procedure main")

    def fields(expression: str) -> list[str]:
        text = example[:at] + f"bool function zz(Order o) = {expression}@\n" + example[at:]
        return [i.label for i in complete(text, tmp_path) if i.kind is types.CompletionItemKind.Field]

    assert fields("o.") == ["item", "customer", "place", "priority"]
    assert fields("o.place.") == ["x", "y", "theta"]
    assert fields("queue()[0].place.") == ["x", "y", "theta"]
    assert fields("o.place.x.") == []  # a number has no fields


def test_signature_help_and_completion_in_an_initially_line(tmp_path: Path) -> None:
    text = "symbol domain block = {a, b}\nbool fluent on(block x, block y) {\ninitially:\n    (a, b) = true;\n}\n"
    doc = Doc.check(text, tmp_path / "m.gpp")
    h = F.signature_help(doc.result, doc.path, doc.at("b) = true"))
    assert h is not None
    assert (h.signatures[0].label, h.active_parameter) == ("bool fluent on(block x, block y)", 1)
    items = F.completion(doc.result, doc.path, doc.at("b) = true"))
    # A fluent's parameters stand for all values of their type in `initially:`.
    assert [i.label for i in items if i.preselect] == ["a", "b", "x", "y"]


def test_completion_of_the_action_in_a_hook_and_of_the_next_section(tmp_path: Path) -> None:
    hooked = BLOCKS.replace("    build(a);\n", "    start(@\n")
    assert labels(complete(hooked, tmp_path)) == ["stack", "switch_state"]
    # After a precondition's expression, the next section may start.
    items = labels(complete(BLOCKS.replace("x != y\n", "x != y\n@"), tmp_path))
    assert [w for w in items if w in ("duration", "effect", "mapping", "precondition", "senses", "silent")] == [
        "duration",
        "effect",
        "mapping",
        "precondition",
        "senses",
        "silent",
    ]
    assert "start_effect" in items
    assert "clear" in items


def test_rename_refuses_the_name_of_a_sibling_field(tmp_path: Path) -> None:
    doc = Doc.check("compound Pose { number x, number y }\nnumber function f(Pose p) = p.x\n", tmp_path / "m.gpp")
    with pytest.raises(F.RenameError, match="`Pose` already has a field named `y`"):
        F.rename(doc.result, doc.path, doc.at("p.x", delta=2), "y")
    assert edits(F.rename(doc.result, doc.path, doc.at("p.x", delta=2), "z")) == {
        "m.gpp": [(doc.rng("x,", length=1), "z"), (doc.rng("x\n", length=1), "z")]
    }


@pytest.mark.parametrize(
    ("edit", "expected"),
    [
        # The values of a pick: of the variable's type, without the variable itself.
        (("    build(a);", "    pick (place p in {a, @"), ["a", "b", "c", "table"]),
        # After a type at the top level, what can be declared with it.
        (("procedure main", "bool @\nprocedure main"), ["domain", "exog_function", "fluent", "function"]),
        (("procedure main", "place @\nprocedure main"), ["domain", "exog_function", "fluent", "function"]),
        (("procedure main", "list[place] @\nprocedure main"), ["domain", "exog_function", "fluent", "function"]),
        # A domain's definition: domains between the operators, elements inside braces.
        (("procedure main", "symbol domain d = block | @\nprocedure main"), ["block", "d", "place"]),
        (("procedure main", "symbol domain d = {table, @}\nprocedure main"), ["a", "b", "c", "table"]),
    ],
)
def test_completion_positions(tmp_path: Path, edit: tuple[str, str], expected: list[str]) -> None:
    items = complete(BLOCKS.replace(*edit), tmp_path)
    assert labels(items)[: len(expected)] == expected
    if edit[1].startswith("    pick"):
        assert sorted(i.label for i in items if i.preselect) == expected
    else:
        assert len(items) == len(expected)


def test_completion_of_the_fields_of_a_compound_literal(tmp_path: Path) -> None:
    text = "compound Pose { number x, number theta }\nPose function origin() = Pose{x = 0, @}\n"
    items = complete(text, tmp_path)
    assert [(i.label, i.kind, i.detail) for i in items] == [
        ("x", types.CompletionItemKind.Field, "number x"),
        ("theta", types.CompletionItemKind.Field, "number theta"),
    ]


def test_completion_of_an_include_path_offers_files_beside_then_in_the_standard_library(tmp_path: Path) -> None:
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "util.gpp").write_text("")
    (tmp_path / "other.gpp").write_text("")
    (tmp_path / "notes.txt").write_text("")
    text = '#include "li@\nprocedure main() {}\n'
    items = complete(text, tmp_path)
    found = labels(items)
    assert found[:2] == ["lib/util.gpp", "other.gpp"]  # not c.gpp itself, not notes.txt
    assert {"time.gpp", "sim/blocksworld.gpp"} <= set(found[2:])
    assert all(i.kind is types.CompletionItemKind.File for i in items)
    # The item replaces what is typed of the path (the string is not closed yet).
    edit = items[0].text_edit
    assert isinstance(edit, types.TextEdit)
    assert rng(edit.range) == ((0, 10), (0, 12))
    # In a closed string, up to the closing quote.
    items = complete('#include "o@ther.gpp"\n', tmp_path)
    edit = items[0].text_edit
    assert isinstance(edit, types.TextEdit) and rng(edit.range) == ((0, 10), (0, 19))


def test_rename_of_a_variable_sees_inner_and_outer_variables_of_the_new_name(tmp_path: Path) -> None:
    text = (
        "symbol domain block = {a, b}\naction go(block o) {}\n"
        "procedure p(block x) {\n    go(x);\n    pick (block y) go(y);\n}\n"
        "procedure q(block x) {\n    pick (block y) go(x);\n}\n"
    )
    doc = Doc.check(text, tmp_path / "m.gpp")
    # p's `x` is not used inside the pick: the pick's own `y` shadows the renamed one there.
    assert edits(F.rename(doc.result, doc.path, doc.at("x) {\n    go"), "y")) == {
        "m.gpp": [(doc.rng("x) {\n    go", length=1), "y"), (doc.rng("x);\n    pick", length=1), "y")]
    }
    # q's pick variable renamed to `x` would capture the use of the parameter `x` inside it.
    with pytest.raises(F.RenameError) as e:
        F.rename(doc.result, doc.path, doc.at("y) go(x)"), "x")
    assert str(e.value) == "renaming to `x` would clash with the parameter `x` visible at line 8"


def test_folding_of_comment_runs_block_comments_and_includes(tmp_path: Path) -> None:
    (tmp_path / "a.gpp").write_text("")
    (tmp_path / "b.gpp").write_text("")
    text = (
        '#include "a.gpp"\n'  # 0
        '#include "b.gpp"\n'  # 1
        "/* one\n"  # 2
        "   two */\n"  # 3
        "action go() {} // trailing\n"  # 4
        "// not joined to the trailing comment above\n"  # 5
        "procedure main() { go(); }\n"  # 6
    )
    doc = Doc.check(text, tmp_path / "m.gpp")
    found = F.folding_ranges(doc.result, doc.path)
    assert [(r.start_line, r.end_line, r.kind) for r in found] == [
        (0, 1, types.FoldingRangeKind.Imports),
        (2, 3, types.FoldingRangeKind.Comment),
    ]


def test_hover_on_an_include_shows_the_file_and_its_header_comment(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("// sub.gpp — helpers.\n//\n// More.\n\naction go() {}\n")
    doc = Doc.check('#include "sub.gpp"\nprocedure main() { go(); }\n', tmp_path / "main.gpp")
    h = F.hover(doc.result, doc.path, doc.at("sub.gpp"))
    assert h is not None and isinstance(h.contents, types.MarkupContent)
    assert h.contents.value == f"`{(tmp_path / 'sub.gpp').resolve()}`\n\nsub.gpp — helpers.\n\nMore."


def test_hover_on_a_code_in_an_allow_comment_shows_its_explanation(tmp_path: Path) -> None:
    from gpp import codes

    doc = Doc.check(
        "number fluent count() { initially: () = 0; }\n"
        "procedure main() { count() = 1; } // gpp: allow W0101, busy-wait -- reason\n",
        tmp_path / "m.gpp",
    )
    h = F.hover(doc.result, doc.path, doc.at("W0101", delta=2))
    assert h is not None and isinstance(h.contents, types.MarkupContent) and h.range is not None
    info = codes.lookup("W0101")
    assert info is not None
    assert h.contents.value == f"**W0101** `{info.name}`: {info.summary}\n\n{info.explanation}"
    assert rng(h.range) == doc.rng("W0101", length=5)
    by_name = F.hover(doc.result, doc.path, doc.at("busy-wait"))
    assert by_name is not None and isinstance(by_name.contents, types.MarkupContent)
    assert by_name.contents.value.startswith("**W0115** `busy-wait`: ")
    # The free comment after the codes is not a code.
    assert F.hover(doc.result, doc.path, doc.at("reason")) is None


def test_inlay_hint_for_a_domain_element_named_like_the_parameter(tmp_path: Path) -> None:
    # Only a variable of the parameter's name makes the hint redundant, not an element.
    doc = Doc.check(
        "symbol domain d = {x, z}\naction go(d x) {}\nprocedure main() { go(x); go(z); }\n", tmp_path / "m.gpp"
    )
    found = F.inlay_hints(doc.result, doc.path, 0, len(doc.text))
    assert [(h.position.line, h.position.character, h.label) for h in found] == [(2, 22, "x:"), (2, 29, "x:")]


def test_hover_on_a_long_domain_lists_its_elements(tmp_path: Path) -> None:
    doc = Doc.check("number domain n = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14}\n", tmp_path / "m.gpp")
    h = F.hover(doc.result, doc.path, doc.at("n ="))
    assert h is not None and isinstance(h.contents, types.MarkupContent)
    assert h.contents.value == (
        "```gpp\nnumber domain n = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, ...}\n```\n\n"
        "14 elements: `{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14}`"
    )


def test_every_kind_of_symbol_has_a_completion_kind_a_symbol_kind_and_a_token_type() -> None:
    from gpp.model.symbols import SymbolKind
    from lsp.features.common import COMPLETION_KIND, SYMBOL_KIND
    from lsp.features.tokens import _KIND_TYPE

    assert set(COMPLETION_KIND) == set(SYMBOL_KIND) == set(_KIND_TYPE) == set(SymbolKind)


def test_completion_in_a_platform_model() -> None:
    doc = Doc.load(ROOT / "examples" / "platform_model.gpp")

    def at(needle: str, delta: int) -> list[str]:
        return [i.label for i in F.completion(doc.result, doc.path, doc.at(needle, delta=delta))]

    # In a component: its clocks and states (the implicit `error` too), the section keywords.
    assert at("booting resets", 0) == [
        "boot_time",
        "off",
        "booting",
        "on",
        "error",
        "clocks",
        "states",
        "transitions",
        "resets",
    ]
    # In constraints: the components of `state(`, then the states of the one named.
    assert at("state(depth_cam) = on", 6) == ["depth_cam", "arm"]
    assert at("state(depth_cam) = on", 19) == ["off", "booting", "on", "error"]
    assert at("during(grasp", 7) == ["switch_state", "go_to", "grasp", "put_down"]
    assert at("state(depth_cam) = on", 0)[:3] == ["state", "during", "start"]


def test_completion_after_a_during_head_offers_until(tmp_path: Path) -> None:
    watched = "    during (stack(a, table)) @\n    build(a);\n"
    after_head = labels(complete(BLOCKS.replace("    build(a);\n", watched), tmp_path))
    assert "until" in after_head and "while" in after_head
    # After the `until (..)` clause a statement follows; `until` is not offered again.
    watched = "    during (stack(a, table)) until (clear(a)) @\n    build(a);\n"
    after_until = labels(complete(BLOCKS.replace("    build(a);\n", watched), tmp_path))
    assert "until" not in after_until and "while" in after_until
    elsewhere = labels(complete(BLOCKS.replace("    build(a);\n", "    build(a);\n    @\n"), tmp_path))
    assert "until" not in elsewhere


def test_completion_items_show_parameters_and_type_beside_the_name(tmp_path: Path) -> None:
    items = {i.label: i for i in complete(BLOCKS.replace("clear(x) &", "clear(@x) &"), tmp_path)}
    details = {k: (v.label_details.detail, v.label_details.description) for k, v in items.items() if v.label_details}
    assert details["clear"] == ("(block x)", "bool")
    assert details["loc"] == ("(block x)", "place")
    assert details["x"] == (None, "block")
    assert details["table"] == (None, "symbol")
