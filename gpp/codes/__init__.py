"""Every diagnostic code gpp reports, with its messages, defined in one place.

A code is a class named as the code (`E0204`) in the module of its range: e00 syntax, e01
names, e02 types, e03 declarations, w01 lints, r00 run time. It carries a short name (used by
`--allow NAME` for lints) and a one-line summary, and its class methods are its messages: each
takes the values the text shows and returns a `Message` (code and text) for `diag.error`,
`diag.warning` or a run-time error. A code with several messages has one method per message
(`E0204.arithmetic`, `E0204.null_operand`, ...). Code outside this package names no code by
its literal: it calls a message, or reads `E0204.code`.

`gpp explain CODE` prints the code's explanation, gpp/codes/explain/CODE.md: what the problem
is, an example of it and the fix (examples are indented by 4 spaces; tests/codes/test_explain.py checks
that each one does what it says). docs/codes.md (`python -m lsp.codes_doc`) and the language
server's link for a code show the same text. Codes are stable: a code keeps its meaning forever;
retired codes are not reused.
"""

from __future__ import annotations

import difflib

from gpp.codes import e00, e01, e02, e03, r00, w01
from gpp.codes.e00 import (
    E0001,
    E0002,
    E0003,
    E0004,
    E0005,
    E0006,
    E0010,
    E0011,
    E0012,
    E0013,
    E0014,
    E0020,
    E0021,
    E0030,
    E0031,
    E0040,
    E0041,
    E0042,
    E0043,
    E0044,
    E0045,
    E0046,
    E0047,
    E0048,
    E0049,
    E0050,
    E0051,
)
from gpp.codes.e01 import E0101, E0102, E0103, E0104, E0105, E0106, E0107
from gpp.codes.e02 import E0201, E0202, E0203, E0204, E0205, E0206, E0207, E0208, E0209, E0210, E0211, E0212, E0213
from gpp.codes.e03 import E0301, E0302, E0303, E0304, E0305, E0306, E0307, E0308, E0309, E0310, E0311, E0312
from gpp.codes.r00 import (
    R0001,
    R0002,
    R0003,
    R0004,
    R0005,
    R0006,
    R0007,
    R0008,
    R0009,
    R0010,
    R0011,
    R0012,
    R0013,
    R0014,
    R0015,
    R0099,
)
from gpp.codes.registry import Code, CodeInfo, Message
from gpp.codes.w01 import (
    W0101,
    W0102,
    W0103,
    W0104,
    W0105,
    W0106,
    W0107,
    W0108,
    W0109,
    W0110,
    W0111,
    W0112,
    W0113,
    W0114,
    W0115,
    W0116,
    W0117,
    W0118,
    W0119,
    W0120,
)

# Every registered code, in the order `gpp explain --list` and docs/codes.md show them: by
# module, and in a module as it defines them.
TABLE: list[CodeInfo] = [
    c.info
    for module in (e00, e01, e02, e03, w01, r00)
    for c in vars(module).values()
    if isinstance(c, type) and issubclass(c, Code) and c is not Code and c.registered
]

CODES: dict[str, CodeInfo] = {c.code: c for c in TABLE}
BY_NAME: dict[str, CodeInfo] = {c.name: c for c in TABLE}
# Run-time codes that are warnings: the run goes on.
RUN_TIME_WARNINGS = frozenset(c.code for c in TABLE if c.run_time_warning)

__all__ = [
    "BY_NAME",
    "CODES",
    "E0001",
    "E0002",
    "E0003",
    "E0004",
    "E0005",
    "E0006",
    "E0010",
    "E0011",
    "E0012",
    "E0013",
    "E0014",
    "E0020",
    "E0021",
    "E0030",
    "E0031",
    "E0040",
    "E0041",
    "E0042",
    "E0043",
    "E0044",
    "E0045",
    "E0046",
    "E0047",
    "E0048",
    "E0049",
    "E0050",
    "E0051",
    "E0101",
    "E0102",
    "E0103",
    "E0104",
    "E0105",
    "E0106",
    "E0107",
    "E0201",
    "E0202",
    "E0203",
    "E0204",
    "E0205",
    "E0206",
    "E0207",
    "E0208",
    "E0209",
    "E0210",
    "E0211",
    "E0212",
    "E0213",
    "E0301",
    "E0302",
    "E0303",
    "E0304",
    "E0305",
    "E0306",
    "E0307",
    "E0308",
    "E0309",
    "E0310",
    "E0311",
    "E0312",
    "R0001",
    "R0002",
    "R0003",
    "R0004",
    "R0005",
    "R0006",
    "R0007",
    "R0008",
    "R0009",
    "R0010",
    "R0011",
    "R0012",
    "R0013",
    "R0014",
    "R0015",
    "R0099",
    "RUN_TIME_WARNINGS",
    "W0101",
    "W0102",
    "W0103",
    "W0104",
    "W0105",
    "W0106",
    "W0107",
    "W0108",
    "W0109",
    "W0110",
    "W0111",
    "W0112",
    "W0113",
    "W0114",
    "W0115",
    "W0116",
    "W0117",
    "W0118",
    "W0119",
    "W0120",
    "Code",
    "CodeInfo",
    "Message",
    "close_matches",
    "lints",
    "lookup",
]


def lookup(code_or_name: str) -> CodeInfo | None:
    key = code_or_name.strip()
    return CODES.get(key.upper()) or BY_NAME.get(key.lower())


def lints() -> list[CodeInfo]:
    return [c for c in TABLE if c.is_lint]


def close_matches(code_or_name: str, lints: bool = False) -> list[str]:
    """Codes and names that look like `code_or_name` (for "did you mean ...?"); only lints
    when `lints` is set."""
    pool = [c for c in TABLE if c.is_lint or not lints]
    key = code_or_name.strip()
    by_code = difflib.get_close_matches(key.upper(), [c.code for c in pool], n=3, cutoff=0.6)
    by_name = difflib.get_close_matches(key.lower(), [c.name for c in pool], n=3, cutoff=0.6)
    return [*by_code, *by_name]
