"""Generators of large golog++ programs for the benchmarks (valid syntax, every construct)."""

from __future__ import annotations

import random


def unit(i: int, nesting: int, rng: random.Random) -> list[str]:
    """One group of declarations (about 60 lines) using every kind of declaration and statement."""
    k = rng.randint(2, 9)
    nested = "(" * nesting + f"x + {k}" + ")" * nesting
    return [
        f"symbol domain obj{i} = {{o{i}a, o{i}b, o{i}c}}",
        f"symbol domain place{i} = obj{i} | {{table{i}}} \\ {{o{i}c}}",
        f"compound Pose{i} {{ number x, number y, string frame }}",
        f"list[Pose{i}] fluent path{i}() {{",
        "initially:",
        f'    () = list[Pose{i}] [Pose{i} {{ x = 1, y = 2.5, frame = "map" }}];',
        "}",
        f"number fluent count{i}(obj{i} o) {{",
        "initially:",
        "    (o) = 0;",
        f"    (o{i}a) = {k};",
        "}",
        f"place{i} fluent at{i}(obj{i} o) {{ initially: (o) = table{i}; }}",
        f"string exog_function sense{i}(string topic);",
        f"action move{i}(obj{i} o, place{i} p) {{",
        "precondition:",
        f"      o != p & count{i}(o) >= 0",
        f"    & !exists(obj{i} z) at{i}(z) == o",
        "effect:",
        f"    at{i}(o) = p;",
        f"    if (p == table{i}) count{i}(o) = count{i}(o) + 1;",
        "senses:",
        f"    count{i}(o) = length(path{i}());",
        "mapping:",
        f'    "/move{i}" {{ what = o, where = p, speed = 0.5 * {k} }}',
        "duration: [1, 30]",
        "}",
        f"exog_action bump{i}(obj{i} o, number n) {{",
        "mapping:",
        f'    "/bump{i}" {{ o = o, n = n }}',
        "effect:",
        f"    count{i}(o) = n;",
        "}",
        f"number function score{i}(number x) = {nested} * 2 - x / 3 % 7 ** 2",
        f"bool function done{i}() = forall(obj{i} o) at{i}(o) != table{i} | count{i}(o) > {k}",
        f"number function reward{i}() = if (done{i}()) 100 else -1 - score{i}(count{i}(o{i}a))",
        f"procedure run{i}(obj{i} o) {{",
        f"    if (count{i}(o) > {k}) move{i}(o, table{i}); else {{ move{i}(o, o{i}b); }}",
        f"    while (!done{i}()) pick (obj{i} y in {{o{i}a, o{i}b}}) move{i}(y, table{i});",
        f"    solve({k}, reward{i}()) choose {{ move{i}(o, o{i}b); test(count{i}(o) == 2); }}",
        f"    search pick (place{i} p) move{i}(o, p);",
        "    concurrent {",
        f"        start(move{i}(o, table{i}));",
        f"        end(move{i}(o, table{i}));",
        "    }",
        f"    during (move{i}(o, o{i}b)) {{",
        f"        path{i}()[0].x = score{i}({k});",
        f"        push_back(path{i}(), Pose{i} {{ x = 0, y = 0, frame = to_string({k}) }});",
        f"    }} on_fail pop_front(path{i}()); on_cancel cancel(move{i}(o, o{i}b));",
        f'    test(sense{i}("/camera") != null);',
        "}",
    ]


def generate_program(lines: int, seed: int = 1, nesting: int = 4) -> str:
    """A program of about `lines` lines (never fewer), every 60 lines or so one `unit`."""
    rng = random.Random(seed)
    out: list[str] = []
    i = 0
    while len(out) < lines:
        out.extend(unit(i, nesting, rng))
        out.append("")
        i += 1
    out.append("procedure main() { run0(o0a); }")
    return "\n".join(out) + "\n"


def nested_expression_program(depth: int) -> str:
    """One function whose body nests `depth` parentheses, and one `depth`-deep block."""
    expr = "(" * depth + "1" + " + 1)" * depth
    blocks = "{ " * depth + "a();" + " }" * depth
    return f"number function deep() = {expr}\naction a() {{}}\nprocedure main() {blocks}\n"


def callers_of_a_renamed_action(n: int) -> str:
    """`go_to` was `goto`: n procedures still call `goto`, each an error with a did-you-mean."""
    return "action go_to() {}\n" + "".join(f"procedure caller_{i}() {{ goto(); }}\n" for i in range(n))


PICK = "pick (bool b) if (b) a();"


def chain_of_procedures(n: int, first: str, main: str, backwards: bool = False) -> str:
    """p0 .. pn, each calling the one before, p0's body `first`, main's body `main` (where `pn`
    is the last of the chain), declared from p1 up (or `backwards`, from pn down): what the
    lints find follows the chain, one call at a time."""
    links = [f"procedure p{i + 1}() {{ p{i}(); }}\n" for i in range(n)]
    chain = "".join(reversed(links) if backwards else links)
    head = f"action a() {{}}\nnumber function r() = 1\nprocedure p0() {{ {first} }}\n"
    return head + chain + "procedure main() {\n" + main.replace("pn", f"p{n}") + "\n}\n"
