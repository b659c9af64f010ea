"""The formatter behind `gpp fmt` and the language server's formatting request.

`format_text` lays a program out canonically and keeps every comment where it was. The layout
is the pretty-printer's (printer.format_program), so the formatted program parses to the same
tree; the formatter then lines up the program's tokens with the printed ones (the same but for
the spelling of literals and the redundant parentheses the printer drops), writes the comments
and blank lines of each gap between two tokens into the matching gap of the printed text, and
breaks lines longer than `WIDTH` at their loosest break points. A byte-order mark at the start
is kept (and, as `gpp check` does, not read as part of the program), and so are the line
endings of the file's first line (`\r\n` or `\n`) for all lines. The rules for comments, blank
lines and line breaks, as users see them: docs/format.md.
"""

from __future__ import annotations

import difflib
import re
from bisect import bisect_left
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum
from itertools import pairwise

from gpp.base.diagnostics import Diagnostic
from gpp.base.source import BOM, Source
from gpp.syntax import ast
from gpp.syntax.directives import SUPPRESSION
from gpp.syntax.lexer import SECTION_WORDS, Token, tokenize, unescape_string
from gpp.syntax.parser import parse
from gpp.syntax.printer import INDENT, format_program
from gpp.syntax.walk import walk

# Printed lines longer than this are wrapped where the code allows it.
WIDTH = 100


class FormatError(Exception):
    """The text has syntax errors, so it cannot be formatted; `diagnostics` lists them."""

    def __init__(self, diagnostics: Sequence[Diagnostic]) -> None:
        self.diagnostics = list(diagnostics)
        first = next((d for d in self.diagnostics if d.is_error), None)
        super().__init__(first.message if first is not None else "syntax error")


def format_text(text: str, path: str = "<input>") -> str:
    """`text` formatted: the canonical layout with its comments, its byte-order mark if it has
    one, its first line's line ending on every line. Raises FormatError when the text has
    syntax errors (the text is then not formatted); their positions count from after the
    byte-order mark, as `gpp check`'s do."""
    bom = BOM if text.startswith(BOM) else ""
    body = text[len(bom) :]
    formatted = _format(body, path)
    if _first_line_ending(body) == "\r\n":
        formatted = _crlf(formatted, path)
    return bom + formatted


def _first_line_ending(text: str) -> str:
    """The line ending of the first line: `\r\n` or `\n` (also when there is no line break)."""
    at = text.find("\n")
    return "\r\n" if at > 0 and text[at - 1] == "\r" else "\n"


def _crlf(text: str, path: str) -> str:
    """Formatted `text` with `\r\n` line endings: every `\n` but those inside a string literal
    (whose value must not change) becomes `\r\n`."""
    tokens, _ = tokenize(Source(text, path))
    parts: list[str] = []
    pos = 0
    for t in tokens:
        if t.type == "STRING" and "\n" in t.value:
            parts += [text[pos : t.start].replace("\n", "\r\n"), t.value]
            pos = t.end
    parts.append(text[pos:].replace("\n", "\r\n"))
    return "".join(parts)


def _format(text: str, path: str) -> str:
    """`text` (without a byte-order mark) formatted, with `\n` line endings but in literals."""
    source = Source(text, path)
    result = parse(source)
    if not result.ok:
        raise FormatError([d for d in result.diagnostics if d.is_error])
    printed = format_program(result.program)
    out_tokens, errors = tokenize(Source(printed, path))
    assert not errors, errors
    token_map = _token_map(result.tokens, out_tokens)
    printed, out_tokens = _keep_literal_spelling(printed, path, result.tokens, out_tokens, token_map)
    gaps = _gaps(text, result.tokens)
    placed: list[list[_Comment]] = [[] for _ in range(len(out_tokens) + 1)]
    blank_before = [False] * (len(out_tokens) + 1)
    newline_before = [False] * (len(out_tokens) + 1)
    for gap, target in zip(gaps, token_map, strict=True):
        placed[target].extend(gap.comments)
        blank_before[target] |= gap.blank_before_token
        newline_before[target] |= gap.newline
    declarations = {d.span.start for d in result.program.declarations}
    kept = _SuppressedLines.find(text, result.tokens, declarations).printed(token_map, len(out_tokens))
    greedy = [g.printed(token_map) for g in _greedy_forms(result.program, result.tokens)]
    return _Writer(printed, out_tokens, placed, blank_before, newline_before, kept, greedy).run()


def _keep_literal_spelling(
    printed: str, path: str, original: list[Token], out_tokens: list[Token], token_map: list[int]
) -> tuple[str, list[Token]]:
    """The printed text with each number and string literal spelled as the author wrote it
    (`1e308`, `0.50`, `"\u00e9"` stay as they are): the printer spells a literal by its value,
    which is the same value but not always the same text."""
    replaced: list[tuple[Token, str]] = []
    for i, token in enumerate(original):
        j = token_map[i]
        if token.type in _LITERALS and j < len(out_tokens):
            out = out_tokens[j]
            if out.type == token.type and out.value != token.value and _key(out) == _key(token):
                replaced.append((out, token.value))
    if not replaced:
        return printed, out_tokens
    parts: list[str] = []
    pos = 0
    for out, spelling in replaced:
        parts += [printed[pos : out.start], spelling]
        pos = out.end
    parts.append(printed[pos:])
    text = "".join(parts)
    tokens, errors = tokenize(Source(text, path))
    assert not errors and len(tokens) == len(out_tokens), errors
    return text, tokens


# ---------------------------------------------------------------- comments of the program


@dataclass(frozen=True, slots=True)
class _Comment:
    text: str
    own_line: bool  # nothing but whitespace before it on its line
    ends_line: bool  # nothing but whitespace after it on its line
    blank_before: bool  # a blank line right above it
    column: int  # where it started on its line
    after_comment: bool  # it follows another comment on its line


@dataclass(frozen=True, slots=True)
class _Gap:
    """What lies between two tokens (or before the first, or after the last)."""

    comments: list[_Comment]
    blank_before_token: bool  # a blank line between the last comment (or token) and the token
    newline: bool  # a line break anywhere in the gap


_COMMENT = re.compile(r"//[^\n]*|/\*[\s\S]*?\*/")


def _gaps(text: str, tokens: list[Token]) -> list[_Gap]:
    """The gap before each token, and the one after the last token."""
    gaps: list[_Gap] = []
    previous_end = 0
    for i in range(len(tokens) + 1):
        end = tokens[i].start if i < len(tokens) else len(text)
        comments: list[_Comment] = []
        pos = previous_end
        for m in _COMMENT.finditer(text, previous_end, end):
            line_start = text.rfind("\n", 0, m.start()) + 1
            following = text[m.end() : end]
            space = following[: len(following) - len(following.lstrip())]
            comments.append(
                _Comment(
                    text="\n".join(line.rstrip() for line in m.group().split("\n")),
                    own_line=not text[line_start : m.start()].strip(),
                    ends_line=m.group().startswith("//") or "\n" in space or m.end() + len(space) == len(text),
                    blank_before=text[pos : m.start()].count("\n") >= 2,
                    column=m.start() - line_start,
                    after_comment=bool(comments) and "\n" not in text[pos : m.start()],
                )
            )
            pos = m.end()
        gaps.append(_Gap(comments, text[pos:end].count("\n") >= 2, "\n" in text[previous_end:end]))
        if i < len(tokens):
            previous_end = tokens[i].end
    return gaps


_SECTION_TYPES = frozenset(SECTION_WORDS.values())


def _key(t: Token) -> tuple[str, object]:
    if t.type == "NUMBER":
        return t.type, float(t.value)
    if t.type == "STRING":
        return t.type, unescape_string(t.value)
    if t.type in _SECTION_TYPES:
        return t.type, ""  # `effect :` is `effect:`
    return t.type, t.value


def _token_map(original: list[Token], printed: list[Token]) -> list[int]:
    """For the gap before each original token (and the one after the last): the gap of the
    printed text that gets its comments. The printed tokens are the program's own but for the
    spelling of literals and redundant parentheses, which the printer drops (`((x))` is
    `(x)`); the gap before a dropped token goes before the next printed token."""
    a = [_key(t) for t in original]
    b = [_key(t) for t in printed]
    target = [0] * (len(a) + 1)
    i = j = 0
    while i < len(a):
        if j < len(b) and (a[i] == b[j] or a[i][0] == b[j][0] in _LITERALS):
            target[i] = j
            i += 1
            j += 1
        elif a[i][0] in _PARENS:
            target[i] = j
            i += 1
        elif j < len(b) and b[j][0] in _PARENS:
            j += 1
        else:
            return _diff_map(a, b)
    target[len(a)] = len(b)
    return target


_LITERALS = frozenset({"NUMBER", "STRING"})
_PARENS = frozenset({"LPAR", "RPAR"})


def _diff_map(a: list[tuple[str, object]], b: list[tuple[str, object]]) -> list[int]:
    """The token map by a diff, for printed tokens that differ in ways not foreseen."""
    target = [0] * (len(a) + 1)
    target[len(a)] = len(b)
    for op, i1, i2, j1, j2 in difflib.SequenceMatcher(None, a, b, autojunk=False).get_opcodes():
        for i in range(i1, i2):
            target[i] = j1 + (i - i1) if op != "delete" and j1 + (i - i1) < j2 else j2
    return target


# ---------------------------------------------------------------- conditionals and quantifiers


@dataclass(frozen=True, slots=True)
class _Greedy:
    """A conditional expression `if (c) a else b` or a quantifier `exists(T x) body`, by token
    index: its first token (`if`, `exists`), its break points (before the `then` branch and
    before `else`; before the body), and the token after its last."""

    first: int
    points: tuple[int, ...]
    end: int
    conditional: bool

    def printed(self, token_map: list[int]) -> _Greedy:
        points = tuple(token_map[k] for k in self.points)
        return _Greedy(token_map[self.first], points, token_map[self.end], self.conditional)


def _greedy_forms(program: ast.Program, tokens: list[Token]) -> list[_Greedy]:
    """The conditional expressions and quantifiers of the program, by token."""
    if not any(t.type in ("ELSE", "QUANTIFIER") for t in tokens):
        return []
    starts = [t.start for t in tokens]

    def first(at: int, kind: str) -> int:
        k = bisect_left(starts, at)
        while tokens[k].type != kind:  # after the parentheses around it
            k += 1
        return k

    found: list[_Greedy] = []
    for node in walk(program):
        if type(node) is ast.Conditional:
            then = bisect_left(starts, node.then.span.start)
            points = (then, first(node.then.span.end, "ELSE"))
            found.append(_Greedy(first(node.span.start, "IF"), points, bisect_left(starts, node.span.end), True))
        elif type(node) is ast.Quantified:
            body = bisect_left(starts, node.body.span.start)
            end = bisect_left(starts, node.span.end)
            found.append(_Greedy(first(node.span.start, "QUANTIFIER"), (body,), end, False))
    return found


# ---------------------------------------------------------------- lines that suppressions cover


@dataclass(slots=True)
class _SuppressedLines:
    """The lines of code a `// gpp: allow` comment covers, to be kept as they are: by token
    index, the tokens that must start a line (`first`) and those that must not (`joined`).

    A suppression at the end of a line covers the lints that start on that line, and one on
    a line of its own, above anything but a declaration, those that start on the next line
    from its first token on (gpp.check.suppress). The formatter puts the comment where it was,
    after the same token or above it, so it covers the same code if that line keeps the same
    tokens: its first token starts a line, the others stay on it, and (for the line below a
    comment) the token after its last starts a new line. A comment above a declaration covers
    the declaration, wherever its lines go: nothing to keep."""

    first: set[int]
    joined: set[int]

    @staticmethod
    def find(text: str, tokens: list[Token], declarations: set[int]) -> _SuppressedLines:
        lines = _SuppressedLines(set(), set())
        if "gpp:" not in text:
            return lines
        starts = [t.start for t in tokens]
        previous_end = 0
        for g in range(len(tokens) + 1):
            end = tokens[g].start if g < len(tokens) else len(text)
            if "gpp:" in text[previous_end:end]:
                for m in _COMMENT.finditer(text, previous_end, end):
                    found = SUPPRESSION.match(m.group())
                    if found is None or found.group(1) == "allow-file":
                        continue
                    line_start = text.rfind("\n", 0, m.start()) + 1
                    if text[line_start : m.start()].strip() and previous_end > line_start:
                        # At the end of a line: the tokens from the line's first on.
                        lines.keep(bisect_left(starts, line_start), g)
                    elif g < len(tokens) and tokens[g].start not in declarations:
                        # Above a line: its tokens from the next one on.
                        line_end = text.find("\n", tokens[g].start)
                        last = bisect_left(starts, len(text) if line_end < 0 else line_end)
                        lines.keep(g, last)
                        if last < len(tokens):
                            lines.first.add(last)
            if g < len(tokens):
                previous_end = tokens[g].end
        return lines

    def keep(self, lo: int, hi: int) -> None:
        """Tokens lo..hi-1 stay one line of their own."""
        if lo < hi:
            self.first.add(lo)
            self.joined.update(range(lo + 1, hi))

    def printed(self, token_map: list[int], printed: int) -> _SuppressedLines:
        """The same lines by printed token (`token_map`: original token -> printed one); a
        printed token that must start a line and must not (two tokens map to it when the
        printer drops a parenthesis) starts one."""
        first = {token_map[i] for i in self.first if token_map[i] < printed}
        joined = {token_map[i] for i in self.joined if token_map[i] < printed} - first
        return _SuppressedLines(first, joined)


# ---------------------------------------------------------------- writing


class _Mode(Enum):
    OWN_LINE = 1  # on a line of its own
    TRAILING = 2  # at the end of a line of code
    INLINE = 3  # between two tokens of one line
    SAME_LINE = 4  # after a comment on a line of its own, on that line


_OPENERS = frozenset({"LPAR", "LBRACKET", "LBRACE", "MAIN_LBRACE"})
_CLOSERS = frozenset({"RPAR", "RBRACKET", "RBRACE"})
# Tokens that open a block or a section: no blank line right after them.
_NO_BLANK_AFTER = frozenset({"LBRACE", "MAIN_LBRACE", *SECTION_WORDS.values()})
# Continuation words that stay at the statement's indentation when a comment ends the line
# before them (`}` / `// c` / `else {`).
_STATEMENT_WORDS = frozenset({"ELSE", "ON_FAIL", "ON_CANCEL"})
# Tokens that need no space before them after an inline comment.
_TIGHT_AFTER = frozenset({"RPAR", "RBRACKET", "COMMA", "SEMI"})
# Operand ends: an ADD_OP after one of these is binary.
_OPERAND_ENDS = frozenset({"NAME", "NUMBER", "STRING", "RPAR", "RBRACKET", "RBRACE", "TRUE", "FALSE", "NULL"})


class _Writer:
    def __init__(
        self,
        printed: str,
        tokens: list[Token],
        comments: list[list[_Comment]],
        blank_before: list[bool],
        newline_before: list[bool],
        kept: _SuppressedLines,
        greedy: list[_Greedy],
    ) -> None:
        self.printed = printed
        self.tokens = tokens
        self.comments = comments
        self.blank_before = blank_before
        self.kept = kept
        n = len(tokens)
        # Per printed token: how many conditionals and quantifiers it is inside, past their
        # first token; their own break points (before a branch or body) count as outside.
        self.nesting = [0] * n
        self.greedy_breaks: dict[int, int] = {}  # break point -> the first token of its form
        self.then_starts: set[int] = set()  # the break points before a conditional's `then`
        self._nest(greedy)
        # Per printed token: does it start a printed line, that line's indentation, and the
        # bracket depth before it relative to the start of its printed line.
        self.starts_line = [False] * n
        self.indent = [""] * n
        self.depth = [0] * n
        self.enclosing: list[tuple[int, ...]] = [()] * n
        self.closer_of: dict[int, int] = {}  # opening bracket -> its closing one, on one printed line
        self.opener_of: dict[int, int] = {}
        self.breaks: set[int] = set()  # tokens that start a line the printer did not start
        self.exploded: set[int] = set()  # opening brackets whose content is laid out one part per line
        self._analyse(newline_before)
        self.lines: list[str] = [""]
        self.trailing_at: dict[int, int] = {}  # line -> column where its trailing comment's gap starts
        self.at_line_start = True
        self.after_opener = False  # the last line written ends with `{` or a section keyword
        self.line_indent = ""  # the indentation of the line being written
        self.opener_indent: dict[int, str] = {}  # exploded bracket -> the indentation of its line

    # ------------------------------------------------ the printed lines

    def _nest(self, greedy: list[_Greedy]) -> None:
        n = len(self.tokens)
        change = [0] * (n + 1)
        for g in greedy:
            change[g.first + 1] += 1
            change[g.end] -= 1
        level = 0
        for k in range(n):
            level += change[k]
            self.nesting[k] = level
        for g in greedy:
            for k in g.points:
                if g.first < k < n:
                    self.greedy_breaks[k] = g.first
            if g.conditional:
                self.then_starts.add(g.points[0])

    def _level(self, k: int) -> int:
        """How deep token k is in conditionals and quantifiers, as a break point."""
        first = self.greedy_breaks.get(k)
        return self.nesting[k] if first is None else self.nesting[first]

    def _analyse(self, newline_before: list[bool]) -> None:
        lines: list[int] = []  # the first token of each printed line
        indent = ""
        depth = 0
        stack: list[int] = []  # the brackets open at a token, opened on its printed line
        for k, t in enumerate(self.tokens):
            sep = self.printed[self.tokens[k - 1].end : t.start] if k else "\n"
            if "\n" in sep and k not in self.kept.joined:
                lines.append(k)
                indent = sep[sep.rfind("\n") + 1 :]
                depth = 0
                stack = []
                self.starts_line[k] = True
            self.indent[k] = indent
            if t.type in _CLOSERS:
                depth -= 1
                if stack:
                    opener = stack.pop()
                    self.closer_of[opener] = k
                    self.opener_of[k] = opener
            self.depth[k] = depth if t.type not in _CLOSERS else depth + 1
            self.enclosing[k] = tuple(stack)
            if t.type in _OPENERS:
                depth += 1
                stack.append(k)
        # The program's own line breaks where a long line could be broken are kept; then
        # what is still too long is wrapped.
        # So are the breaks that keep the lines suppressions cover.
        for lo, hi in zip(lines, [*lines[1:], len(self.tokens)], strict=False):
            kept = [
                k
                for k in range(lo + 1, hi)
                if (newline_before[k] and self._break_rank(k) is not None) or k in self.kept.first
            ]
            self.breaks.update(kept)
            bounds = [lo, *kept, hi]
            for start, end in pairwise(bounds):
                self._wrap(start, end)
        # Brackets broken at their commas put each part on its own lines, closed on a line
        # of its own: `f(` / `a,` / `b` / `)`.
        for k in list(self.breaks):
            if self.tokens[k - 1].type == "COMMA" and self.enclosing[k] and self.enclosing[k][-1] in self.closer_of:
                self.exploded.add(self.enclosing[k][-1])
        for o in self.exploded:
            self.breaks.update((o + 1, self.closer_of[o]))
        self.breaks -= self.kept.joined

    def continuation(self, k: int) -> str:
        """The indentation of token k when a line is broken before it: one step per exploded
        bracket around it, and for a line that continues an expression one step more, plus one
        per other open bracket."""
        t = self.tokens[k]
        groups = self.enclosing[k]
        opener = self.opener_of.get(k)
        if opener in self.exploded:
            return self.opener_indent[opener]
        if groups and groups[-1] in self.exploded and (k - 1 == groups[-1] or self.tokens[k - 1].type == "COMMA"):
            return self.opener_indent[groups[-1]] + INDENT
        statement_word = t.type in ("RBRACE", "LBRACE", "MAIN_LBRACE") or t.type in _STATEMENT_WORDS
        if not groups and statement_word and k not in self.greedy_breaks:  # not an expression's `else`
            return self.indent[k]
        # Inside an exploded bracket, a part's line continues from the part's indentation.
        base, inner = self.indent[k], groups
        for at in range(len(groups) - 1, -1, -1):
            if groups[at] in self.exploded:
                base, inner = self.opener_indent[groups[at]] + INDENT, groups[at + 1 :]
                break
        # A conditional's `then` branch one step deeper than its `else`.
        deeper = 2 if k in self.then_starts and k in self.greedy_breaks else 1
        return base + INDENT * (deeper + len(inner))

    def _span_length(self, lo: int, hi: int) -> int:
        """The length of the longest line of tokens lo..hi-1 as written: the `/* */` comments
        between them counted, with the space before each."""
        text = self.printed[self.tokens[lo].start : self.tokens[hi - 1].end]
        if any(k in self.kept.joined for k in range(lo + 1, hi)):
            text = re.sub(r"\n *", " ", text)  # printed lines joined to keep a suppressed line
        inline = sum(
            len(c.text) + 1
            for k in range(lo + 1, hi)
            for c in self.comments[k]
            if not (c.own_line or c.ends_line or "\n" in c.text)
        )
        return max(len(line) for line in text.split("\n")) + inline

    def _wrap(self, lo: int, hi: int) -> None:
        """Break the tokens lo..hi-1, which start a line, where they are longer than WIDTH."""
        indent = len(self.indent[lo]) + (len(INDENT) * (1 + self.depth[lo]) if lo in self.breaks else 0)
        if indent + self._span_length(lo, hi) <= WIDTH:
            return
        candidates: list[tuple[int, int, int, int]] = []  # (depth, conditional level, rank, token)
        for k in range(lo + 1, hi):
            rank = self._break_rank(k)
            if rank is not None:
                candidates.append((self.depth[k], self._level(k), rank, k))
        if not candidates:
            return
        loosest = min(candidates)[:3]
        chosen = [c[3] for c in candidates if c[:3] == loosest]
        self.breaks.update(chosen)
        bounds = [lo, *chosen, hi]
        for start, end in pairwise(bounds):
            self._wrap(start, end)

    def _break_rank(self, k: int) -> int | None:
        """How loose a line break before token k is (lower is looser), None if no break fits."""
        if k in self.kept.joined:
            return None
        before = self.tokens[k - 1].type
        t = self.tokens[k].type
        if before == "EQ" and not self.indent[k] and not self.depth[k]:
            # A top-level definition: `bool function f() =` / `    body`; the `=` of a field
            # in a compound literal (`Pos { x = 0 }`, inside brackets) is no break point.
            return 0
        if before == "COMMA":
            return 1
        if t == "ARROW":
            return 2
        if t == "BAR":
            return 3
        if t == "AMP":
            return 4
        if t == "CMP_OP":
            return 5
        if t == "ADD_OP" and before in _OPERAND_ENDS:
            return 6
        if t == "MUL_OP":
            return 7
        if k in self.greedy_breaks:
            return 8  # a conditional or quantifier binds tighter than any operator outside it
        return None

    # ------------------------------------------------ output

    def write(self, text: str) -> None:
        if not text:
            return
        if "\n" in text:
            first, *rest = text.split("\n")
            self.lines[-1] += first
            self.lines.extend(rest)
        else:
            self.lines[-1] += text
        self.at_line_start = False

    def newline(self) -> None:
        self.lines[-1] = self.lines[-1].rstrip()
        self.lines.append("")
        self.at_line_start = True

    def blank_line(self) -> None:
        """A blank line, unless at the top, right after an opener, or after a blank line."""
        if self.after_opener or len(self.lines) < 2 or self.lines[-2] == "":
            return
        if self.lines[-1] == "":
            self.lines.append("")

    def run(self) -> str:
        n = len(self.tokens)
        for k in range(n + 1):
            self._gap(k)
            if k < n:
                t = self.tokens[k]
                self.write(self.printed[t.start : t.end])
                self.after_opener = t.type in _NO_BLANK_AFTER
                if k in self.exploded:
                    self.opener_indent[k] = self.line_indent
        if not self.at_line_start:
            self.newline()
        self._align_trailing()
        text = "\n".join(self.lines).rstrip("\n")
        return text + "\n" if text else ""

    def _modes(self, k: int, comments: list[_Comment], line_break: bool) -> list[_Mode]:
        modes: list[_Mode] = []
        at_start = k == 0
        for c in comments:
            if at_start or c.own_line:
                follows = c.after_comment and modes and modes[-1] in (_Mode.OWN_LINE, _Mode.SAME_LINE)
                mode = _Mode.SAME_LINE if follows else _Mode.OWN_LINE
            elif c.ends_line:
                mode = _Mode.TRAILING
            else:
                mode = _Mode.INLINE
            modes.append(mode)
            at_start = mode is not _Mode.INLINE
        # An inline comment followed by a line break ends its line.
        next_on_new_line = line_break
        for i in range(len(modes) - 1, -1, -1):
            if modes[i] is _Mode.INLINE and next_on_new_line:
                modes[i] = _Mode.TRAILING
            next_on_new_line = modes[i] is _Mode.OWN_LINE
        return modes

    def _gap(self, k: int) -> None:
        """The comments of gap k, then the line break or space before token k."""
        n = len(self.tokens)
        printed_break = k == n or self.starts_line[k]
        line_break = printed_break or k in self.breaks
        last_inline = False
        if self.comments[k]:
            line_break, last_inline = self._comments(k, printed_break, line_break)
        if k == n:
            return
        if line_break or self.at_line_start:
            if not self.at_line_start:
                self.newline()
            if printed_break and self.blank_before[k] and self.tokens[k].type != "RBRACE":
                self.blank_line()
            self.line_indent = self.indent[k] if printed_break else self.continuation(k)
            self.write(self.line_indent)
        elif last_inline:
            self.write("" if self.tokens[k].type in _TIGHT_AFTER else " ")
        else:
            separator = self.printed[self.tokens[k - 1].end : self.tokens[k].start]
            self.write(" " if "\n" in separator else separator)  # a line joined to keep a suppression

    def _comments(self, k: int, printed_break: bool, line_break: bool) -> tuple[bool, bool]:
        """Write the comments of gap k; whether token k now starts a line, and whether the
        last comment was written inline."""
        comments = self.comments[k]
        if k == len(self.tokens):
            comment_indent = ""
        else:
            indent = self.indent[k] if printed_break else self.continuation(k)
            closing = self.tokens[k].type == "RBRACE" and indent == self.indent[k]
            comment_indent = indent + INDENT if closing else indent
        last_inline = False
        modes = self._modes(k, comments, line_break)
        for i, (c, mode) in enumerate(zip(comments, modes, strict=True)):
            last_inline = False
            line_ends = i + 1 == len(modes) or modes[i + 1] is not _Mode.SAME_LINE
            if mode is _Mode.OWN_LINE:
                if not self.at_line_start:
                    self.newline()
                if c.blank_before:
                    self.blank_line()
                self.write(comment_indent + _reindent(c, len(comment_indent)))
                if line_ends:
                    self.newline()
                self.after_opener = False
            elif mode is _Mode.SAME_LINE:
                self.write(" " + _reindent(c, len(self.lines[-1]) + 1))
                if line_ends:
                    self.newline()
            elif mode is _Mode.TRAILING:
                if "\n" not in c.text:
                    self.trailing_at[len(self.lines) - 1] = len(self.lines[-1])
                self.write("  " + c.text)
                self.newline()
                line_break = True
            else:
                gap = "" if self.lines[-1].endswith(("(", "[")) or self.at_line_start else " "
                self.write(gap + c.text)
                last_inline = True
        return line_break, last_inline

    def _align_trailing(self) -> None:
        """The trailing comments of consecutive lines start in one column."""
        runs: list[list[int]] = []
        for i in sorted(self.trailing_at):
            if runs and runs[-1][-1] == i - 1:
                runs[-1].append(i)
            else:
                runs.append([i])
        for run in runs:
            column = max(self.trailing_at[j] for j in run)
            for j in run:
                at = self.trailing_at[j]
                self.lines[j] = self.lines[j][:at] + " " * (column - at) + self.lines[j][at:]


def _reindent(c: _Comment, column: int) -> str:
    """A comment moved from its column to `column`: the further lines of a block comment move
    along when they can."""
    lines = c.text.split("\n")
    shift = column - c.column
    if len(lines) == 1 or shift == 0:
        return "\n".join(line.rstrip() for line in lines)
    rest = lines[1:]
    if shift > 0:
        rest = [" " * shift + line if line.strip() else "" for line in rest]
    elif all(not line.strip() or line[:-shift].isspace() for line in rest):
        rest = [line[-shift:] for line in rest]
    return "\n".join(line.rstrip() for line in [lines[0], *rest])
