"""Pathological programs: families of programs of a size n (deep nesting, long chains, unclosed
brackets, many declarations or errors), each with the n it is checked at."""

from __future__ import annotations

from collections.abc import Callable

from bench.genprog import PICK, callers_of_a_renamed_action, chain_of_procedures


def main_body(statement: str) -> str:
    return "procedure main() {\n" + statement + "\n}\n"


# Each family: (generator of a program of size n, n). 8n stays within the nesting limit.
FAMILIES: dict[str, tuple[Callable[[int], str], int]] = {
    "unclosed braces": (lambda n: "procedure main() " + "{" * n + "\n", 500),
    "unclosed parentheses": (lambda n: "number function f() = " + "(" * n + "\n", 500),
    "unclosed parentheses in a statement": (lambda n: "procedure main() { x = " + "(" * n + "\n}\n", 500),
    "unclosed strings": (lambda n: "".join(f'procedure p{i}() {{ x = "abc\n}}\n' for i in range(n)), 40),
    "unclosed comment": (lambda n: "procedure main() {}\n/*" + "x\n" * n, 2000),
    "a syntax error in every declaration": (
        lambda n: "".join(f"procedure p{i}() {{ x = = 1; }}\n" for i in range(n)),
        40,
    ),
    "a missing `;` on every line": (
        lambda n: "number fluent k() { initially: () = 0; }\n" + main_body("k() = 1\n" * n),
        100,
    ),
    "nested if": (lambda n: main_body("if (true) " * n + "{}"), 200),
    "nested if-else": (lambda n: main_body("if (true) {} else " * n + "{}"), 200),
    "nested while": (lambda n: main_body("while (true) " * n + "{}"), 200),
    "nested blocks": (lambda n: main_body("{" * n + "}" * n), 200),
    "nested choose": (lambda n: main_body("choose {" * n + "{}" + "}" * n), 200),
    "nested concurrent": (lambda n: main_body("concurrent {" * n + "{}" + "}" * n), 200),
    "nested pick": (lambda n: main_body("pick (bool b) " * n + "{}"), 200),
    "nested solve": (
        lambda n: "action a() {}\nnumber function r() = 1\n" + main_body("solve (3, r()) " * n + "a();"),
        200,
    ),
    "nested during": (lambda n: "action a() {}\n" + main_body("during (a()) " * n + "{}"), 200),
    "unary minus": (lambda n: "number function f() = " + "- " * n + "1\n", 200),
    "negation": (lambda n: "bool function f() = " + "!" * n + "true\n", 200),
    "nested calls": (
        lambda n: "number function f(number x) = x\nnumber function g() = " + "f(" * n + "1" + ")" * n,
        200,
    ),
    "field chain": (
        lambda n: (
            "compound C { number x }\nC fluent c() { initially: () = C{x = 1}; }\n"
            "number function g() = c()" + ".x" * n + "\n"
        ),
        200,
    ),
    "sum over lines": (lambda n: "number function g() =\n" + " +\n".join(["1"] * n) + "\n", 200),
    "conjunction over lines": (lambda n: "bool function g() =\n" + " &\n".join(["true"] * n) + "\n", 200),
    "nested exists": (lambda n: "symbol domain D = {a}\nbool function g() = " + "exists (D x) " * n + "true\n", 200),
    "nested conditionals": (lambda n: "number function g() = " + "if (true) " * n + "1" + " else 2" * n + "\n", 200),
    "declarations nested beyond the limit": (
        lambda n: "".join(f"procedure p{i}() {{\n" + "if (true) {} else " * 3_500 + "{}\n}\n" for i in range(n)),
        1,
    ),
    "long domain": (lambda n: "symbol domain D = {" + ", ".join(f"e{i}" for i in range(n)) + "}\n", 200),
    "long union": (lambda n: "symbol domain A = {a}\nsymbol domain D = " + " | ".join(["A"] * n) + "\n", 200),
    "many declarations": (lambda n: "".join(f"number function f{i}() = {i}\n" for i in range(n)), 100),
    "callers of a renamed action": (callers_of_a_renamed_action, 250),
    # Which procedures run only while planning: none, found from main back along the chain
    # (the `pick` in p0 is online: W0105).
    "a chain of procedures called online": (lambda n: chain_of_procedures(n, PICK, "pn();"), 500),
    # Which procedures reach a choice: all, found from p0's `pick` forward along the chain.
    "a chain of procedures reaching a pick": (
        lambda n: chain_of_procedures(n, PICK, "solve (2, r()) pn();", backwards=True),
        1000,
    ),
}
