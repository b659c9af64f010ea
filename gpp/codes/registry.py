"""The registry's building blocks: a code's entry (CodeInfo), the base of the classes that define
each code and its messages (Code), and the explanation files."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import ClassVar, Protocol

from gpp.base.diagnostics import Message

__all__ = ["Code", "CodeInfo", "Kind", "Message", "explanation"]

_EXPLAIN_DIR = Path(__file__).resolve().parent / "explain"


@cache
def explanation(code: str) -> str:
    """The text of gpp/codes/explain/CODE.md ("" for a code without one): what the code means,
    an example of the problem and its fix (examples are indented by 4 spaces)."""
    try:
        return (_EXPLAIN_DIR / f"{code}.md").read_text(encoding="utf-8").strip()
    except FileNotFoundError:
        return ""


@dataclass(frozen=True, slots=True)
class CodeInfo:
    """A registered code: the code, its short name (used by `--allow NAME` for lints) and a
    one-line summary; `gpp explain CODE` adds the explanation."""

    code: str
    name: str
    summary: str
    # A run-time code that is a warning: the run goes on after it.
    run_time_warning: bool = False

    @property
    def explanation(self) -> str:
        return explanation(self.code)

    @property
    def is_lint(self) -> bool:
        return self.code.startswith("W")

    @property
    def is_warning(self) -> bool:
        """Lints, and the run-time warnings (a run goes on after them)."""
        return self.is_lint or self.run_time_warning


class Code:
    """A diagnostic code: one subclass per code, named as the code (`class E0204(Code, ...)`),
    whose class methods are its messages. A message takes the values it shows and returns a
    Message (the code and the text), which a call site passes to `diag.error`/`diag.warning`:

        diag.error(E0204.cannot_order(left, right, op), span)

    `registered=False` defines a code that `gpp explain` does not list (an internal error)."""

    code: ClassVar[str]
    info: ClassVar[CodeInfo]
    registered: ClassVar[bool]

    def __init_subclass__(
        cls, *, name: str, summary: str, run_time_warning: bool = False, registered: bool = True
    ) -> None:
        super().__init_subclass__()
        cls.code = cls.__name__
        cls.info = CodeInfo(cls.code, name, summary, run_time_warning)
        cls.registered = registered


class Kind(Protocol):
    """What a message shows of a declaration's kind (gpp.model.symbols.SymbolKind): "a fluent"."""

    @property
    def article(self) -> str: ...

    @property
    def value(self) -> str: ...
