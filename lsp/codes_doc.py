"""The page an editor opens for a diagnostic's code (the LSP `codeDescription`).

Every code is documented in one Markdown page, docs/codes.md, generated from gpp.codes and its
explanation files gpp/codes/explain/CODE.md (the text `gpp explain CODE` prints); a test keeps
the committed page in step with the registry.
Each code is a heading of its own, so `codes.md#e0011` links to it. In a source checkout the
link points at docs/codes.md; an installed gpp writes the same page into the user's cache
directory once per version and points there.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from gpp import __version__, codes
from gpp.base.resources import cache_dir, write_cache_file

_CHECKOUT_PAGE = Path(__file__).resolve().parent.parent / "docs" / "codes.md"


def codes_markdown() -> str:
    """docs/codes.md: every diagnostic code with its name, summary and explanation."""
    out = [
        "# Diagnostic codes",
        "",
        "Generated from `gpp/codes/` and `gpp/codes/explain/CODE.md` (`gpp explain CODE` prints the same text);",
        "do not edit by hand.",
        "Codes are stable: `E00xx` syntax, `E01xx` names, `E02xx` types, `E03xx` declarations,",
        "`W01xx` lints (allowed with `gpp check --allow CODE`), `R00xx` run time.",
        "",
    ]
    for info in codes.CODES.values():
        kind = "lint" if info.is_lint else "warning" if info.is_warning else "error"
        out += [f"## {info.code}", "", f"`{info.name}` ({kind}): {info.summary}", ""]
        if info.explanation:
            out += [info.explanation.strip("\n"), ""]
    return "\n".join(out)


@cache
def _page() -> Path | None:
    if _CHECKOUT_PAGE.is_file():
        return _CHECKOUT_PAGE
    page = cache_dir() / f"codes-{__version__}.md"
    if not page.is_file():
        write_cache_file(page, codes_markdown().encode("utf-8"))
    return page if page.is_file() else None


def code_url(code: str) -> str | None:
    """The link to the documentation of `code` (None for a code gpp does not register, or when
    no page can be written)."""
    if code not in codes.CODES:
        return None
    page = _page()
    return None if page is None else f"{page.as_uri()}#{code.lower()}"


if __name__ == "__main__":  # python -m lsp.codes_doc: regenerate docs/codes.md
    _CHECKOUT_PAGE.write_text(codes_markdown(), encoding="utf-8")
