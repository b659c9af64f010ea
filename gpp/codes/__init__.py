"""Every diagnostic code gpp reports, defined in one place.

Each code has a short name (used by `--allow NAME` for lints), a one-line summary and, for
`gpp explain CODE`, an explanation with a small example. Codes are stable: a code keeps its
meaning forever; retired codes are not reused.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, replace


@dataclass(frozen=True, slots=True)
class CodeInfo:
    code: str
    name: str
    summary: str
    explanation: str = ""

    @property
    def is_lint(self) -> bool:
        return self.code.startswith("W")

    @property
    def is_warning(self) -> bool:
        """Lints, and the run-time warnings (a run goes on after them)."""
        return self.is_lint or self.code in RUN_TIME_WARNINGS


_CODES: list[CodeInfo] = [
    # ---------------------------------------------------------------- syntax
    CodeInfo("E0001", "unexpected-character", "a character that cannot start any token"),
    CodeInfo("E0002", "unterminated", "a string literal or block comment that is never closed"),
    CodeInfo("E0003", "underscore-name", "a name that starts with '_'"),
    CodeInfo("E0004", "number-too-large", "a number literal beyond the range of numbers (about ±1.8e308)"),
    CodeInfo("E0005", "non-ascii-name", "a name with letters outside ASCII (names are ASCII in golog++)"),
    CodeInfo("E0006", "not-text", "a file that is not UTF-8 text: a NUL byte, or bytes that are not UTF-8"),
    CodeInfo("E0010", "unexpected-token", "a token where the grammar does not allow it"),
    CodeInfo("E0011", "missing-semicolon", "a statement or declaration that is not ended by ';'"),
    CodeInfo("E0012", "unexpected-eof", "the file ends inside a declaration"),
    CodeInfo("E0013", "reserved-word", "a reserved word used as a name"),
    CodeInfo("E0014", "nesting-too-deep", "a declaration nested more than 2,000 levels deep"),
    CodeInfo("E0020", "duplicate-section", "an action section (`effect:`, ...) given twice"),
    CodeInfo("E0021", "duplicate-handler", "a `during` handler given twice"),
    CodeInfo("E0040", "legacy-type-sigil", "a type written as a sigil (`%fluent`, `?function`, `§x`): legacy golog++"),
    CodeInfo("E0041", "legacy-mapping-name", "an unquoted mapped name (`move_base { ... }`): legacy golog++"),
    CodeInfo("E0042", "legacy-senses", "`senses: f()` without an assignment: legacy golog++"),
    CodeInfo("E0043", "legacy-domain-section", "a `domain:` section restricting parameters: legacy golog++"),
    CodeInfo("E0044", "legacy-function-body", "a function with a block body of `return`s: legacy golog++"),
    CodeInfo("E0045", "legacy-exog-function-body", "an `exog_function` with a body: legacy golog++"),
    CodeInfo("E0030", "include-not-found", "an `#include` whose file cannot be found or read"),
    CodeInfo("E0031", "include-cycle", "files that include each other"),
    # ---------------------------------------------------------------- names
    CodeInfo("E0101", "unknown-name", "a name that is neither a variable nor a symbol"),
    CodeInfo("E0102", "missing-call", "a fluent or function used without `()`"),
    CodeInfo("E0103", "unknown-callable", "a call of something that is not declared"),
    CodeInfo("E0104", "wrong-kind", "a declaration used where its kind is not allowed"),
    CodeInfo("E0105", "unknown-type", "a type name that is not declared"),
    CodeInfo("E0106", "unknown-field", "a field that the compound type does not have"),
    CodeInfo("E0107", "unknown-platform-name", "an unknown component, state or clock in the platform model"),
    # ---------------------------------------------------------------- types
    CodeInfo("E0201", "wrong-arity", "a call with the wrong number of arguments"),
    CodeInfo("E0202", "type-mismatch", "an expression of the wrong type"),
    CodeInfo("E0203", "not-in-domain", "a literal that is not a member of the domain it must belong to"),
    CodeInfo("E0204", "bad-operands", "an operator applied to operands of the wrong types"),
    CodeInfo("E0205", "chained-comparison", "comparisons written as a chain, such as `a < b < c`"),
    CodeInfo("E0206", "void-data", "`void` used as the type of data"),
    CodeInfo("E0207", "not-indexable", "a field taken of a non-compound, or an index of a non-list"),
    CodeInfo("E0208", "compound-fields", "a compound literal with missing or repeated fields"),
    CodeInfo("E0209", "not-comparable", "compound or list values compared"),
    CodeInfo("E0210", "infinite-range", "a quantifier or `pick` over a type with infinitely many values"),
    CodeInfo("E0211", "branch-types", "a conditional expression whose branches have different types"),
    CodeInfo("E0212", "solve-arguments", "a `solve` whose horizon or reward is not what it needs"),
    CodeInfo("E0213", "literal-required", "an expression where only a literal value may stand"),
    # ---------------------------------------------------------------- declarations
    CodeInfo("E0301", "redefinition", "a second definition of the same name"),
    CodeInfo("E0302", "kind-clash", "one name declared as two different kinds of things"),
    CodeInfo("E0303", "forward-mismatch", "a definition that does not match its forward declaration"),
    CodeInfo("E0304", "predefined-name", "a declaration of a name gpp predefines"),
    CodeInfo("E0305", "duplicate-name", "a parameter, field, mapping argument or variable declared twice in one list"),
    CodeInfo("E0306", "bad-assignment-target", "an assignment to something that is not a fluent"),
    CodeInfo("E0307", "bad-initial-value", "an `initially:` entry that does not fit the fluent's parameters"),
    CodeInfo("E0308", "exog-mapping", "an exogenous action mapping that does not bind every parameter to itself"),
    CodeInfo("E0309", "section-not-allowed", "a section an exogenous action cannot have"),
    CodeInfo("E0310", "main-twice", "a legacy main block and a `procedure main` in one program"),
    CodeInfo("E0311", "bad-domain", "a domain definition that refers to itself or mixes element types"),
    CodeInfo("E0312", "bad-duration", "a `duration:` or `silent:` section with values it cannot have"),
    # ---------------------------------------------------------------- lints
    CodeInfo("W0101", "unused", "a fluent, action, function or procedure that is never used"),
    CodeInfo("W0102", "unused-variable", "a parameter or variable that is never used"),
    CodeInfo("W0103", "uninitialized-fluent", "fluent instances that have no initial value"),
    CodeInfo("W0104", "double-effect", "an action that assigns the same fluent instance twice"),
    CodeInfo("W0105", "online-nondeterminism", "a `pick` or `choose` outside `solve`/`search`"),
    CodeInfo("W0106", "busy-loop", "a `while (true)` loop whose body executes no action"),
    CodeInfo("W0107", "constant-condition", "a condition that is always true or always false"),
    CodeInfo("W0108", "unreachable-else", "an `else` branch that can never run"),
    CodeInfo("W0109", "solve-without-choice", "a `solve` whose program has no `pick` or `choose`"),
    CodeInfo("W0110", "mixed-precedence", "an operator chain that the original golog++ reads differently"),
    CodeInfo("W0111", "shadowed-symbol", "a parameter or variable named like a domain symbol"),
    CodeInfo("W0112", "quantifier-scope", "a quantifier whose body runs on into operands that do not use its variable"),
    CodeInfo(
        "W0113", "shared-sensing-result", "two exogenous functions in one `senses:` section: both get the same value"
    ),
    CodeInfo("W0114", "unended-activity", "a `start` whose activity no `end`, `finish`, `fail` or `cancel` refers to"),
    CodeInfo("W0115", "busy-wait", "a `while` loop whose body cannot change what its condition reads"),
    CodeInfo("W0116", "unused-suppression", "a `// gpp: allow` comment that allows nothing"),
    CodeInfo("W0117", "invalid-suppression", "a `// gpp: allow` comment naming an error or an unknown lint"),
    # ---------------------------------------------------------------- run time
    # Reported by `gpp run` and `gpp test` when the program runs. R0099 (an internal error) is
    # not registered: it reports a bug in gpp, not a problem of the program.
    CodeInfo("R0001", "bad-arithmetic", "an arithmetic operation without a result: division by zero and the like"),
    CodeInfo("R0002", "null-value", "an operation on `null`, the value of a fluent instance without a value"),
    CodeInfo("R0003", "bad-index", "a list index out of range or not a whole number"),
    CodeInfo("R0004", "domain-violation", "a value outside its domain, stored or passed at run time"),
    CodeInfo("R0005", "conflicting-effects", "effects of one action that give one fluent instance different values"),
    CodeInfo("R0006", "pop-empty-list", "`pop_front` or `pop_back` on an empty list"),
    CodeInfo("R0007", "platform-failure", "the platform cannot do what the program asks of it"),
    CodeInfo("R0008", "missing-definition", "a procedure or function declared but never defined, or no `main`"),
    CodeInfo("R0009", "started-twice", "an activity started again before the previous identical one was ended"),
    CodeInfo("R0010", "planning-aborted", "`solve` or `search` that cannot plan: endless free steps, bad horizon"),
    CodeInfo("R0011", "blocked", "the program cannot make a step and nothing can change that"),
    CodeInfo("R0012", "recursion-too-deep", "procedure or function calls nested too deeply"),
    CodeInfo("R0013", "timeout", "the run reached the time limit given by `--timeout`"),
    CodeInfo("R0014", "plan-unfinished", "a `solve` whose plan stops at its horizon with the program unfinished"),
]

# Run-time codes that are warnings: the run goes on.
RUN_TIME_WARNINGS = frozenset({"R0014"})

# `gpp explain CODE`: what the problem is, in plain words, and a small example with its fix
# (examples are indented by 4 spaces; tests/test_explain.py checks that each one does what it says).
_EXPLANATIONS: dict[str, str] = {
    "E0001": """
A character appears that no golog++ token starts with, such as `$`, `@`, `#` (outside
`#include`), `^` or `?`. gpp skips the character and goes on checking.

For example:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = count() $ 1;
    }

Remove the character, or write the operator golog++ has:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = count() + 1;
    }
""",
    "E0004": """
Numbers range from -1.8e308 to 1.8e308, the range of a 64-bit float; whole numbers are exact
in all of it. A number literal beyond that range, such as `1e400` or a whole number of more
than 309 digits, is an error: it has no value. (A literal too small to tell from 0, such as
`1e-400`, is 0.)

For example:

    number fluent limit() { initially: () = 1e400; }
    procedure main() {
        limit() = limit() - 1;
    }

Write a number within the range:

    number fluent limit() { initially: () = 1e300; }
    procedure main() {
        limit() = limit() - 1;
    }
""",
    "E0005": """
Names in golog++ (of fluents, actions, procedures, parameters, symbols, ...) are written in
ASCII: letters `a`-`z` and `A`-`Z`, digits and `_`. Strings and comments may hold any text.
gpp reports each such name once, at its first appearance, and checks the rest of the program
with the name as written, so its uses are not reported again.

For example:

    number fluent größe() { initially: () = 1; }
    procedure main() {
        größe() = größe() + 1;
    }

Rename it everywhere it is used:

    number fluent groesse() { initially: () = 1; }
    procedure main() {
        groesse() = groesse() + 1;
    }
""",
    "E0040": """
Early golog++ (2018) wrote types as a sign before a name: `%` for `number`, `?` for `bool`,
`$` for `string` and `§` for `symbol`, on declarations (`%fluent`, `?function`,
`§domain`), on parameters (`§r`) and on the parameters' uses (`count(§r)`). golog++ writes
types as words. gpp reports all the signs of a file as one error, whose fix writes the type
words and drops the signs before uses (`gpp check` then checks the file as if it had).

For example:

    §domain rooms = {kitchen, hall}
    %fluent count(§r) {
    initially:
        (§r) = 0;
    }
    ?function busy(§r) = count(§r) > 1
    procedure main() { test(!busy(hall)); }

Write the types as words:

    symbol domain rooms = {kitchen, hall}
    number fluent count(symbol r) {
    initially:
        (r) = 0;
    }
    bool function busy(symbol r) = count(r) > 1
    procedure main() { test(!busy(hall)); }
""",
    "E0041": """
The name an action is mapped to is a string, so that it can be any name of the platform
(`"/move_base"`, `"speech"`). Older agents wrote a bare name.

For example:

    action go(number x) {
    mapping:
        move_base { goal = x }
    }
    procedure main() { go(1); }

Quote the name:

    action go(number x) {
    mapping:
        "move_base" { goal = x }
    }
    procedure main() { go(1); }
""",
    "E0042": """
Older golog++ wrote `senses: f();` to put the result of an action into the fluent `f`.
golog++ assigns the fluent, and the value comes from an exogenous function: the platform
answers the exogenous function of a `senses:` section with the action's result, whatever the
function is called. The fix declares one, `sensed_f`, of the fluent's type.

For example:

    number fluent temperature() { initially: () = 0; }
    action read_thermometer() {
    senses:
        temperature();
    }
    procedure main() { read_thermometer(); }

Assign the result of an exogenous function:

    number fluent temperature() { initially: () = 0; }
    number exog_function sensed_temperature();
    action read_thermometer() {
    senses:
        temperature() = sensed_temperature();
    }
    procedure main() { read_thermometer(); }
""",
    "E0043": """
Early golog++ restricted a parameter to a domain with a `domain:` section
(`domain: r in rooms;`). golog++ gives the parameter the domain as its type instead: a
domain is a type.

For example:

    symbol domain Room = {kitchen, hall}
    action go(symbol r) {
    domain:
        r in Room;
    }
    procedure main() { go(kitchen); }

Type the parameter with the domain:

    symbol domain Room = {kitchen, hall}
    action go(Room r) {
    }
    procedure main() { go(kitchen); }
""",
    "E0044": """
Early golog++ functions had a block body with `return` statements. A golog++ function is one
expression after `=`; a choice between values is a conditional expression,
`if (c) a else b`. The fix rewrites bodies made of `return`s and `if`/`else`; other bodies
(loops, assignments) have to be rewritten by hand, perhaps as a procedure.

For example:

    number function sign(number x) {
        if (x < 0)
            return -1;
        return 1;
    }
    procedure main() { test(sign(-5) == -1); }

Write the body as one expression:

    number function sign(number x) = if (x < 0) -1 else 1
    procedure main() { test(sign(-5) == -1); }
""",
    "E0045": """
An exogenous function is answered by the platform (a scenario, the simulator, a robot's
service), so it is only declared. Older agents gave it a body.

For example:

    number exog_function battery() {
    }
    procedure main() { test(battery() >= 0); }

End the declaration with `;`:

    number exog_function battery();
    procedure main() { test(battery() >= 0); }
""",
    "E0002": """
A string literal must be closed by `"` on the same line, and a block comment `/* ... */`
must be closed by `*/` before the end of the file.

For example:

    string fluent greeting() {
    initially:
        () = "hello;
    }

Close the string:

    string fluent greeting() {
    initially:
        () = "hello";
    }
""",
    "E0003": """
Names (of fluents, actions, parameters, symbols, ...) start with a letter; `_` may appear
inside a name but not at its start.

For example:

    number fluent _count() { initially: () = 0; }

Rename it:

    number fluent count() { initially: () = 0; }
""",
    "E0010": """
The parser found a token where the grammar does not allow it. The message lists what could
stand there instead. Common causes: a missing operand, a missing `)` or `}`, or a misspelled
keyword.

For example:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = count() + ;
    }

Complete the expression:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = count() + 1;
    }
""",
    "E0011": """
Every statement, every effect and every initial value ends with `;`. The error points just
after the token where the `;` is missing.

For example:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = 1
    }

Add the `;`:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = 1;
    }
""",
    "E0012": """
The file ends in the middle of a declaration, usually because a `}` or `)` is missing. The
error shows where the unclosed construct was opened.

For example:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = 1;

Close the procedure:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = 1;
    }
""",
    "E0013": """
Keywords such as `if`, `while`, `pick`, `search`, `solve`, `test`, `exists` or `true` are
reserved and cannot be used as names.

For example:

    number fluent search() { initially: () = 0; }

Choose another name:

    number fluent searches() { initially: () = 0; }
""",
    "E0014": """
gpp reads declarations nested up to 2,000 levels deep. Each statement inside another counts as
a level, and so does each operand of an operator chain (`a + b + c` is `(a + b) + c`), each
call, field access, index, `!`, `-`, quantifier and domain operator (parentheses do not). The
parser also stops at 20,000 brackets, operators and statements open at once (parentheses
around parentheses count there). A declaration nested deeper is left out of the program, so
that no later phase has to follow it. Programs written by hand never come near the limit;
generated ones may.

For example, a condition negated 2,001 times (in lines of 80):

    bool function never() =
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    !true

Say it once:

    bool function never() = !true
""",
    "E0020": """
Each section of an action (`precondition:`, `effect:`, `senses:`, `mapping:`, `silent:`,
`duration:`) may appear only once. Put everything into one section: an `effect:` section
holds any number of effects.

For example:

    number fluent count() { initially: () = 0; }
    bool fluent done() { initially: () = false; }
    action step() {
    effect:
        count() = count() + 1;
    effect:
        done() = true;
    }

Merge the sections:

    number fluent count() { initially: () = 0; }
    bool fluent done() { initially: () = false; }
    action step() {
    effect:
        count() = count() + 1;
        done() = true;
    }
""",
    "E0021": """
A `during` statement has at most one `on_fail` and one `on_cancel` handler. Use a block to
run several statements in one handler.

For example:

    action drive() { }
    action say(string text) { }
    procedure main() {
        during (drive()) say("driving");
        on_fail say("drive failed");
        on_fail say("trying again");
    }

Join the handlers in one block:

    action drive() { }
    action say(string text) { }
    procedure main() {
        during (drive()) say("driving");
        on_fail { say("drive failed"); say("trying again"); }
    }
""",
    "E0006": """
gpp reads every program file, and every file it `#include`s, as UTF-8 text (a byte-order
mark at the start is allowed and skipped). A file with a NUL byte, or with bytes that are not
UTF-8, is most likely a binary file named by mistake, or text saved in another encoding such
as Latin-1. gpp does not parse such a file: it reports this error once, at the first bad byte
(or at the `#include` that names the file), instead of a syntax error for every byte.

For example, this file saved in Latin-1, where `é` is the single byte 0xe9:

    // example.gpp (latin-1)
    // the robot's café
    procedure main() { }

Save the file as UTF-8 (most editors offer it under "encoding"; on the command line,
`iconv -f latin1 -t utf-8 old.gpp > new.gpp`):

    // the robot's café
    procedure main() { }
""",
    "E0030": """
An `#include "path.gpp"` is looked up relative to the including file and then in gpp's
standard library. The file must exist there and be readable.

For example:

    #include "helpers.gpp"
    procedure main() { }

Fix the path, or create the file; without it, remove the line:

    procedure main() { }
""",
    "E0031": """
Files that include each other, directly or through other files, form a cycle. Every file is
included once, so a cycle is always a mistake: move what both need into a third file that
both include.

For example, `a.gpp` includes `b.gpp`, and `b.gpp` includes `a.gpp`:

    // a.gpp
    #include "b.gpp"
    procedure main() { beep(); }
    // b.gpp
    #include "a.gpp"
    action beep() { }

Move the shared declarations into `common.gpp` and include it from both:

    // common.gpp
    action beep() { }
    // a.gpp
    #include "common.gpp"
    #include "b.gpp"
    procedure main() { beep(); twice(); }
    // b.gpp
    #include "common.gpp"
    procedure twice() { beep(); beep(); }
""",
    "E0101": """
A bare name in an expression is a variable (a parameter, a `pick` or quantifier variable) in
scope, else a symbol of a domain. A name that is neither is an error; the help suggests
similar names.

For example:

    symbol domain Room = {hall, kitchen}
    action go(Room r) { }
    procedure main() {
        go(kitchn);
    }

Fix the spelling:

    symbol domain Room = {hall, kitchen}
    action go(Room r) { }
    procedure main() {
        go(kitchen);
    }
""",
    "E0102": """
Fluents, functions and exogenous functions are always called with parentheses, even without
parameters: `door_open()`, not `door_open`.

For example:

    bool fluent door_open() { initially: () = false; }
    procedure main() {
        test(door_open);
    }

Add the parentheses:

    bool fluent door_open() { initially: () = false; }
    procedure main() {
        test(door_open());
    }
""",
    "E0103": """
A call names something that is not declared: an action or procedure as a statement, a fluent
or function in an expression. The help suggests similar names.

For example:

    symbol domain Room = {hall, kitchen}
    action go_to(Room r) { }
    procedure main() {
        go_too(kitchen);
    }

Fix the name, or declare what it calls:

    symbol domain Room = {hall, kitchen}
    action go_to(Room r) { }
    procedure main() {
        go_to(kitchen);
    }
""",
    "E0104": """
Each place takes one kind of thing: statements call actions and procedures, expressions call
fluents and functions, `start`/`end`/`during`/... take an action call. Using something of
another kind there is an error; to change a fluent, assign it; to wait for a condition, use
`test(...)`.

For example:

    bool fluent door_open() { initially: () = false; }
    procedure main() {
        door_open();
    }

Wait for the fluent instead:

    bool fluent door_open() { initially: () = false; }
    procedure main() {
        test(door_open());
    }
""",
    "E0105": """
Types are the built-in `bool`, `number`, `string` and `symbol`, the declared domains and
compound types, and `list[T]` of those. Any other type name is unknown.

For example:

    symbol domain Room = {hall, kitchen}
    Rom fluent robot_at() { initially: () = hall; }

Fix the type name:

    symbol domain Room = {hall, kitchen}
    Room fluent robot_at() { initially: () = hall; }
""",
    "E0106": """
A field access `e.f`, or a field in a compound literal, must name a field of the compound
type; the note lists the fields it has.

For example:

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0, y = 0 }; }
    number function height() = pose().z

Use one of the fields:

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0, y = 0 }; }
    number function height() = pose().y
""",
    "E0107": """
The platform model (`component` and `constraints` declarations) refers to components,
their states and their clocks by name. These names must be declared in the component.

For example:

    component camera {
    states:
        off, on
    transitions:
        off => on,
        on => standby
    }

Use a declared state, or declare it:

    component camera {
    states:
        off, on, standby
    transitions:
        off => on,
        on => standby
    }
""",
    "E0201": """
A call must give exactly one argument per parameter of what it calls; the note shows the
signature.

For example:

    symbol domain Room = {hall, kitchen}
    action go(Room from, Room to) { }
    procedure main() {
        go(kitchen);
    }

Give every argument:

    symbol domain Room = {hall, kitchen}
    action go(Room from, Room to) { }
    procedure main() {
        go(hall, kitchen);
    }
""",
    "E0202": """
An expression has a type that the place it stands in does not accept: an argument of a
parameter's type, a value assigned to a fluent of its type, a `bool` condition. Numbers are
converted to strings only explicitly, with `to_string(...)`.

For example:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = "three";
    }

Give a value of the right type:

    number fluent count() { initially: () = 0; }
    procedure main() {
        count() = 3;
    }
""",
    "E0203": """
A literal stands where a domain type is expected, but it is not one of the domain's members.
Computed values are checked when the program runs; literals are checked right away.

For example:

    number domain Level = {1, 2, 3}
    Level fluent level() { initially: () = 4; }

Use a member of the domain, or add the value to it:

    number domain Level = {1, 2, 3}
    Level fluent level() { initially: () = 3; }
""",
    "E0204": """
An operator is applied to operands it does not work on: arithmetic needs numbers, `+` also
joins two strings, `&`, `|`, `->` and `!` need bools, `<` and friends compare two numbers,
strings or symbols, and nothing but `==`/`!=` applies to `null`.

For example:

    number fluent count() { initially: () = 0; }
    action say(string text) { }
    procedure main() {
        say("count: " + count());
    }

Convert the number to a string first:

    number fluent count() { initially: () = 0; }
    action say(string text) { }
    procedure main() {
        say("count: " + to_string(count()));
    }
""",
    "E0205": """
Comparisons do not chain: `a < b < c` does not mean "b lies between a and c". Compare each
pair and join the comparisons with `&`.

For example:

    number fluent x() { initially: () = 5; }
    bool function in_range() = 0 < x() < 10

Write two comparisons:

    number fluent x() { initially: () = 5; }
    bool function in_range() = 0 < x() & x() < 10
""",
    "E0206": """
`void` is the type of nothing: actions and procedures have it, but a fluent, function,
parameter or variable cannot, since it could hold no value.

For example:

    void fluent ready() { initially: () = null; }

Give it a type of data:

    bool fluent ready() { initially: () = false; }
""",
    "E0207": """
Only compound values have fields (`e.f`), and only lists can be indexed (`e[i]`).

For example:

    number fluent count() { initially: () = 0; }
    number function first() = count()[0]

Index a list, or use the value directly:

    list[number] fluent counts() { initially: () = list[number] [0]; }
    number function first() = counts()[0]
""",
    "E0208": """
A compound literal gives every field of its type exactly once. A field without a value is
written as `null` explicitly.

For example:

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0 }; }

Give every field:

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0, y = null }; }
""",
    "E0209": """
Compound and list values cannot be compared with `==` or `!=`. Compare their fields or
elements instead.

For example:

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0, y = 0 }; }
    Pose fluent goal() { initially: () = Pose { x = 1, y = 1 }; }
    bool function arrived() = pose() == goal()

Compare the fields:

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0, y = 0 }; }
    Pose fluent goal() { initially: () = Pose { x = 1, y = 1 }; }
    bool function arrived() = pose().x == goal().x & pose().y == goal().y
""",
    "E0210": """
`exists`, `forall` and a `pick` without `in {...}` try every value of the variable's type,
so the type must be finite: a domain, `bool`, or `symbol` (whose values are the symbols the
program's domains declare). Over `number` or `string`, list the values with
`pick (number n in {1, 2, 3})` or declare a domain.

For example:

    action wait(number seconds) { }
    procedure main() {
        solve(2, reward()) pick (number n) wait(n);
    }
    number function reward() = 0

List the values to try:

    action wait(number seconds) { }
    procedure main() {
        solve(2, reward()) pick (number n in {1, 5, 10}) wait(n);
    }
    number function reward() = 0
""",
    "E0211": """
Both branches of a conditional expression `if (c) a else b` must have types that fit
together, since the expression has one type.

For example:

    bool fluent urgent() { initially: () = false; }
    number function priority() = if (urgent()) 1 else "low"

Give both branches the same type:

    bool fluent urgent() { initially: () = false; }
    number function priority() = if (urgent()) 1 else 0
""",
    "E0212": """
`solve(horizon, reward())` needs a number as horizon and, as reward, a call of a function
that returns a number.

For example:

    number fluent score() { initially: () = 0; }
    action work() { effect: score() = score() + 1; }
    procedure main() {
        solve(3, score()) choose { work(); { } }
    }

Wrap the value in a reward function:

    number fluent score() { initially: () = 0; }
    action work() { effect: score() = score() + 1; }
    number function reward() = score()
    procedure main() {
        solve(3, reward()) choose { work(); { } }
    }
""",
    "E0213": """
Some places take only values written out (literals): initial values, the members of a
domain, the values of `pick ... in {...}`, the arguments of constraint patterns.
Computations belong in procedures.

For example:

    number fluent count() { initially: () = 1 + 1; }

Write the value:

    number fluent count() { initially: () = 2; }
""",
    "E0301": """
A name can be defined only once: a second fluent, action, function, procedure, domain or
compound type with the same name is an error. (A forward declaration without a body, followed
by the definition, is fine.)

For example:

    number fluent count() { initially: () = 0; }
    number fluent count() { initially: () = 1; }

Remove one definition, or rename one:

    number fluent count() { initially: () = 0; }
    number fluent total() { initially: () = 1; }
""",
    "E0302": """
One name cannot be two kinds of thing, such as a fluent and a procedure: calls would be
ambiguous.

For example:

    bool fluent charge() { initially: () = false; }
    procedure charge() { }

Rename one of them:

    bool fluent charging() { initially: () = false; }
    procedure charge() { }
""",
    "E0303": """
A forward declaration and the definition of the same thing must agree: the same type,
the same number of parameters, and the same parameter types and names.

For example:

    number function double(number x);
    number function double(number y) = 2 * y

Use the same signature in both:

    number function double(number x);
    number function double(number x) = 2 * x
""",
    "E0304": """
gpp predefines a few names (`context_time`, `step_context_time`, `switch_state`); a program
cannot declare them again.

For example:

    number fluent context_time() { initially: () = 0; }

Use the predefined one, or choose another name:

    number fluent start_time() { initially: () = 0; }
""",
    "E0305": """
In one list of parameters, fields, mapping arguments or component states and clocks, each
name may appear only once.

For example:

    symbol domain Room = {hall, kitchen}
    action go(Room r, Room r) { }

Give each one its own name:

    symbol domain Room = {hall, kitchen}
    action go(Room from, Room to) { }
""",
    "E0306": """
Only fluents hold changing values: an assignment (and `push_back`, ...) changes a fluent
instance, or a field or element of one. Parameters, variables, functions and other things
cannot be assigned.

For example:

    number fluent count() { initially: () = 0; }
    procedure bump(number n) {
        n = n + 1;
    }

Assign a fluent instead:

    number fluent count() { initially: () = 0; }
    procedure bump(number n) {
        count() = n + 1;
    }
""",
    "E0307": """
Each `initially:` entry gives one argument per parameter of the fluent. An argument is a
literal, or the parameter's own name in its own position, which stands for every value.

For example:

    symbol domain Room = {hall, kitchen}
    bool fluent lit(Room r) { initially: () = false; }

Give one argument per parameter:

    symbol domain Room = {hall, kitchen}
    bool fluent lit(Room r) { initially: (r) = false; }
""",
    "E0308": """
An exogenous action's mapping is read backwards: the platform's event fields set the
parameters. So each mapping entry must be a bare parameter, and every parameter must appear.

For example:

    exog_action battery_report(number level) {
    mapping:
        "/battery" { percentage = level * 100 }
    }

Map each field to a parameter:

    exog_action battery_report(number level) {
    mapping:
        "/battery" { percentage = level }
    }
""",
    "E0309": """
Exogenous actions are events the platform reports; they are never executed, so they cannot
have the sections of an execution: `senses:` and `duration:`.

For example:

    exog_action door_opened() {
    duration: [0, 1]
    }

Remove the section:

    exog_action door_opened() {
    mapping:
        "/door" { }
    }
""",
    "E0310": """
A trailing anonymous block `{ ... }` at the end of a file is the legacy form of
`procedure main()`. A program cannot have both.

For example:

    action beep() { }
    procedure main() { beep(); }
    { beep(); }

Keep one of them:

    action beep() { }
    procedure main() { beep(); beep(); }
""",
    "E0311": """
A domain is a set of literal values of one element type (symbols, numbers, strings or
bools), possibly built from other domains with `|`, `&` and `\\`. It cannot be defined in
terms of itself, nor mix domains of different element types.

For example:

    symbol domain Room = {hall} | Room

List its members, or build it from other domains:

    symbol domain Corridor = {hall}
    symbol domain Room = {kitchen} | Corridor
""",
    "E0312": """
`duration: [low, high]` gives the bounds of an action's duration in seconds: two
non-negative number literals with `low <= high`. `silent:` takes `true`, `false` or `null`.

For example:

    action drive() {
    duration: [60, 5]
    }

Write the smaller bound first:

    action drive() {
    duration: [5, 60]
    }
""",
    "W0101": """
A fluent, action, function or procedure that nothing refers to is dead code, or a sign that
a call was forgotten. Calls from inside its own body do not count. `main`, `postcond`,
exogenous actions and predefined names are never reported.

For example:

    number fluent count() { initially: () = 0; }
    procedure main() { }

Use it, or remove it:

    number fluent count() { initially: () = 0; }
    procedure main() { count() = 1; }
""",
    "W0102": """
A parameter of a function, procedure or action, or a `pick` or quantifier variable, that is
never used. Parameters of an action with an explicit `mapping:` count as used when the
mapping passes them on; an action without `mapping:` passes all of them to the platform.

For example:

    action say(string text) { }
    procedure greet(string name) { say("hello"); }
    procedure main() { greet("Ada"); }

Use the parameter, or remove it:

    action say(string text) { }
    procedure greet(string name) { say("hello " + name); }
    procedure main() { greet("Ada"); }
""",
    "W0103": """
Fluent instances not covered by any `initially:` entry start as `null`, and reading them
in arithmetic or comparisons is a run-time error. gpp enumerates the instances of fluents
over domains and `bool`; a parameter of type `number` or `string` needs an entry with the
parameter's name in its position to cover all values. A fluent that is only forward-declared
has no initial values at all. Writing `null` explicitly counts as an initial value.

For example:

    symbol domain Room = {hall, kitchen, office}
    bool fluent lit(Room r) { initially: (hall) = true; }
    procedure main() { test(lit(office)); }

Add a default entry first (later entries override it):

    symbol domain Room = {hall, kitchen, office}
    bool fluent lit(Room r) { initially: (r) = false; (hall) = true; }
    procedure main() { test(lit(office)); }
""",
    "W0104": """
The effects of an action are evaluated in the state before it and applied together, so two
unconditional effects on the same fluent instance conflict: if their values differ, the
action fails when it runs. Effects with an `if (...)` condition are not reported.

For example:

    number fluent count() { initially: () = 0; }
    action step() {
    effect:
        count() = count() + 1;
        count() = 0;
    }
    procedure main() { step(); }

Keep one assignment:

    number fluent count() { initially: () = 0; }
    action step() {
    effect:
        count() = count() + 1;
    }
    procedure main() { step(); }
""",
    "W0105": """
Outside `solve` and `search`, `pick` and `choose` do not plan: they take the first value or
alternative that can make a step now and never come back to try another, even if it leads
to a dead end. A procedure that is only called from inside `solve`/`search` is not reported,
nor a `choose` whose alternatives all start by waiting (`test(...)`, `finish(...)`,
`fail(...)`, `end(...)`), which selects by what happens.

For example:

    symbol domain Room = {hall, kitchen}
    action go(Room r) { }
    procedure main() {
        pick (Room r) go(r);
    }

Plan the choice with `search` (or `solve`), or write the value:

    symbol domain Room = {hall, kitchen}
    action go(Room r) { }
    procedure main() {
        search { pick (Room r) go(r); }
    }
""",
    "W0106": """
A `while (true)` loop whose body executes no action, hook, `during`, test, assignment, list
statement or procedure call can never make progress: nothing in it waits for the world or
changes it, so the program is stuck.

For example:

    bool fluent busy() { initially: () = false; }
    procedure main() {
        while (true) {
            if (busy()) { }
        }
    }

Wait for what should happen, or act in the loop:

    bool fluent busy() { initially: () = false; }
    procedure main() {
        while (true) {
            test(busy());
        }
    }
""",
    "W0107": """
A condition of an `if`, `while`, `test`, precondition or conditional effect that does not
depend on the state, such as `1 < 2` or `false`, is always true or always false: the code it
guards always or never runs. `while (true)`, `test(true)` and `precondition: true` are
idioms and are not reported.

For example:

    action beep() { }
    procedure main() {
        while (false) beep();
    }

Fix the condition, or remove the dead code:

    action beep() { }
    procedure main() {
        beep();
    }
""",
    "W0108": """
An `if` whose condition is constant runs only one of its branches: with `if (true)` the
`else` branch never runs, with `if (false)` the `if` branch never runs.

For example:

    action beep() { }
    action wait() { }
    procedure main() {
        if (true) beep(); else wait();
    }

Keep the branch that runs:

    action beep() { }
    action wait() { }
    procedure main() {
        beep();
    }
""",
    "W0109": """
`solve(horizon, reward())` plans the choices of the `pick` and `choose` statements in its
program (also in the procedures it calls). Without any, there is nothing to plan and `solve`
only runs the program.

For example:

    action work() { }
    number function reward() = 0
    procedure main() {
        solve(3, reward()) work();
    }

Give `solve` a choice to make:

    action work() { }
    action rest() { }
    number function reward() = 0
    procedure main() {
        solve(3, reward()) choose { work(); rest(); }
    }
""",
    "W0110": """
The original golog++ builds operator chains with a faulty algorithm: when a tighter operator
follows a looser one and the chain goes on, it groups differently from standard precedence,
e.g. it reads `1 * 2 + 3 * 4` as `((1 * 2) + 3) * 4`. gpp uses standard precedence, so the
same program computes different values in the two. Parentheses make the chain mean the same
in both.

For example:

    number fluent x() { initially: () = 2; }
    number function area() = x() * 2 + x() * 3

Add parentheses:

    number fluent x() { initially: () = 2; }
    number function area() = (x() * 2) + (x() * 3)
""",
    "W0111": """
A parameter or variable named like a domain symbol hides the symbol in its scope: there,
the name means the parameter, which is easy to misread (and in `initially:` it stands for
every value, not for the symbol).

For example:

    symbol domain Room = {hall, kitchen}
    action go(Room hall) { }
    procedure main() { go(kitchen); }

Rename the parameter:

    symbol domain Room = {hall, kitchen}
    action go(Room target) { }
    procedure main() { go(kitchen); }
""",
    "W0112": """
The body of `exists` and `forall` extends as far right as it can: `exists(Block z) on(z, x) &
clear(x)` is `exists(Block z) (on(z, x) & clear(x))`. When the operands at the end of the body
do not use the quantifier's variable, they were probably meant to stand outside it; with `!`
in front of the quantifier, or with `->`, the two readings give different results. gpp warns
when the trailing operands of the `&`, `|` or `->` chain that forms the body do not use the
variable. Parentheses around the body do not help: they make one operand of a body that still
extends to the right. Put the quantifier itself in parentheses.

For example, `free(x)` is meant to be "nothing is on `x`, and `x` is not held":

    symbol domain Block = {a, b, c}
    bool fluent on(Block x, Block y) { initially: (x, y) = false; }
    bool fluent holding(Block x) { initially: (x) = false; }
    bool function free(Block x) = !exists(Block z) on(z, x) & !holding(x)
    procedure main() { test(free(a)); }

End the quantifier where its variable is no longer used:

    symbol domain Block = {a, b, c}
    bool fluent on(Block x, Block y) { initially: (x, y) = false; }
    bool fluent holding(Block x) { initially: (x) = false; }
    bool function free(Block x) = !(exists(Block z) on(z, x)) & !holding(x)
    procedure main() { test(free(a)); }
""",
    "W0113": """
When an activity ends with a result (the goal's result, the service's response, a scenario's
`result`), that one result answers every exogenous function evaluated in the action's
`senses:` section, whatever its name and arguments. Two different exogenous function calls in
one `senses:` section therefore get the same value. gpp warns at each call that differs from
the first one.

For example, both coordinates get the whole result:

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0, y = 0 }; }
    number exog_function sensed_x();
    number exog_function sensed_y();
    action locate() {
    senses:
        pose() = Pose { x = sensed_x(), y = sensed_y() };
    }
    procedure main() { locate(); }

Sense one compound value (a result with the fields `x` and `y` fills it):

    compound Pose { number x, number y }
    Pose fluent pose() { initially: () = Pose { x = 0, y = 0 }; }
    Pose exog_function sensed_pose();
    action locate() {
    senses:
        pose() = sensed_pose();
    }
    procedure main() { locate(); }
""",
    "W0114": """
`start(a(...))` starts an activity and goes on at once. The action's effects are applied by
`end(a(...))` or `finish(a(...))` when it ends, and only `end`, `finish` and `fail` tell how
it ended. An activity that no hook refers to runs unobserved: its effects are never applied,
a failure goes unnoticed, and if it still runs when the program ends it is cancelled. gpp
warns at a `start` of an action when no `end`, `finish`, `fail` or `cancel` of the same action
(with any arguments) appears anywhere in the program.

For example:

    bool fluent charged() { initially: () = false; }
    action charge() { effect: charged() = true; }
    action beep() { }
    procedure main() {
        start(charge());
        beep();
        test(charged());
    }

Wait for the activity to end (or call `charge();` to start it and wait in one step):

    bool fluent charged() { initially: () = false; }
    action charge() { effect: charged() = true; }
    action beep() { }
    procedure main() {
        start(charge());
        beep();
        end(charge());
        test(charged());
    }
""",
    "W0115": """
A `while` loop does not wait for its condition. Its body runs as long as the condition holds,
and a loop whose body has nothing left to do is finished, whatever the condition says: a loop
with an empty body (or one made only of `if`s and blocks with nothing in them) ends at once. A
body of assignments (or `test(true)`) that cannot change what the condition reads runs again
and again, until something outside the loop (an exogenous event, the clock, another
`concurrent` branch) makes the condition false. gpp warns about a `while` whose body has no
action, hook, `during`, procedure call, `solve`, `search` or `test` (but `test(true)`), and
assigns no fluent that the condition reads (directly or through the functions it calls). To
wait until a condition holds, use `test`.

For example, the robot does not wait for the door:

    bool fluent door_open() { initially: () = false; }
    exog_action door_opened() { effect: door_open() = true; }
    action enter() { }
    procedure main() {
        while (!door_open()) { }
        enter();
    }

Wait with `test`:

    bool fluent door_open() { initially: () = false; }
    exog_action door_opened() { effect: door_open() = true; }
    action enter() { }
    procedure main() {
        test(door_open());
        enter();
    }
""",
    # ---------------------------------------------------------------- run time
    "W0116": """
A `// gpp: allow CODE` comment allows a lint where it stands: at the end of a line, on that
line; on its own line above a declaration, in the whole declaration; `// gpp: allow-file CODE`,
in the whole file. When the lint it names is not reported there (the code was changed, or the
comment is in the wrong place), the comment only misleads. `gpp check --fix` removes it.

For example, `go` is used, so nothing is there to allow:

    action go() {}
    // gpp: allow unused
    procedure patrol() {
        go();
    }
    procedure main() {
        patrol();
    }

Remove the comment:

    action go() {}
    procedure patrol() {
        go();
    }
    procedure main() {
        patrol();
    }
""",
    "W0117": """
Only lints (W codes) can be allowed by a `// gpp: allow` comment. An error (E code) means the
program cannot run as written, so it cannot be suppressed: fix it. A name that is no lint's
code or name is most likely misspelled; `gpp check --list-lints` lists them.

For example, the comment tries to allow an error, and misspells `unused`:

    // gpp: allow E0101, unsued
    action spare() {}
    procedure main() {}

Allow the lint by its name and leave the errors out:

    // gpp: allow unused
    action spare() {}
    procedure main() {}
""",
    "R0001": """
An arithmetic operation whose operands have no result stops the run at the expression:
division or `%` by zero, `%` of numbers that are not whole, `0 ** -1` (a division by zero),
a power that is not a real number, such as `(0 - 8) ** 0.5`, or a result too large to be a
number. The checker cannot see these: they depend on values the program computes as it runs.

For example, `seconds()` is 0 when the division runs:

    number fluent distance() { initially: () = 12; }
    number fluent seconds() { initially: () = 0; }
    number fluent speed() { initially: () = 0; }
    procedure main() {
        speed() = distance() / seconds();
    }

Compute only when the operands allow it:

    number fluent distance() { initially: () = 12; }
    number fluent seconds() { initially: () = 0; }
    number fluent speed() { initially: () = 0; }
    procedure main() {
        if (seconds() > 0)
            speed() = distance() / seconds();
    }
""",
    "R0002": """
`null` is the value of a fluent instance that no `initially:` entry covers (or that was
given `null`). It is no number, string, list or compound value: arithmetic, `+` of strings,
`-`, ordering comparisons (`<`, `<=`, `>`, `>=`), `length`, fields, indexes, list operations
and assignments into a field or element of `null` stop the run, as does a `solve` whose reward
is `null`. `==` and `!=` may compare with `null`, and in a condition `null` counts as false.
`gpp check` warns about fluent instances without an initial value (W0103).

For example, `visits(kitchen)` has no initial value:

    symbol domain Room = {hall, kitchen}
    number fluent visits(Room r) { initially: (hall) = 0; }
    procedure main() {
        visits(kitchen) = visits(kitchen) + 1;
    }

Give every instance an initial value (the entry `(r) = 0` covers all rooms):

    symbol domain Room = {hall, kitchen}
    number fluent visits(Room r) { initially: (r) = 0; }
    procedure main() {
        visits(kitchen) = visits(kitchen) + 1;
    }
""",
    "R0003": """
The index of a list must be a whole number from 0 to `length(list) - 1`, both to read an
element and to assign one. Assigning past the end does not grow the list: use `push_back` or
`push_front` to add elements.

For example, a list of three elements has no element 3:

    list[number] fluent readings() { initially: () = list[number] [3, 4, 5]; }
    number fluent last() { initially: () = 0; }
    procedure main() {
        last() = readings()[length(readings())];
    }

Indexes start at 0, so the last element is at `length(...) - 1`:

    list[number] fluent readings() { initially: () = list[number] [3, 4, 5]; }
    number fluent last() { initially: () = 0; }
    procedure main() {
        last() = readings()[length(readings()) - 1];
    }
""",
    "R0004": """
A value computed at run time is checked against its domain when it is stored in a fluent (by
an assignment or an action's effect), passed as an argument of an action or procedure, or
pushed into a list: a value outside the domain stops the run. The checker reports literals
outside a domain (E0203); computed values can only be checked as the program runs.

For example, raising the level from 3 gives 4, which `Level` does not have:

    number domain Level = {1, 2, 3}
    Level fluent level() { initially: () = 3; }
    action raise() {
    effect:
        level() = level() + 1;
    }
    procedure main() {
        raise();
    }

Make sure the value stays in the domain, here with a conditional effect:

    number domain Level = {1, 2, 3}
    Level fluent level() { initially: () = 3; }
    action raise() {
    effect:
        if (level() < 3) level() = level() + 1;
    }
    procedure main() {
        raise();
    }
""",
    "R0005": """
The effects of an action are evaluated in the state before it and applied together, so
effects that give the same fluent instance (or the same field or element of it) different
values contradict each other, and the action stops the run. Effects that give the same value
are fine. `gpp check` warns about unconditional effects on one instance (W0104); effects with
an `if (...)` condition can only conflict when their conditions hold together.

For example, both conditions hold for `drive(60)`:

    number fluent alarm() { initially: () = 0; }
    action drive(number speed) {
    effect:
        if (speed > 30) alarm() = 1;
        if (speed > 50) alarm() = 2;
    }
    procedure main() {
        drive(60);
    }

Make the conditions exclude each other:

    number fluent alarm() { initially: () = 0; }
    action drive(number speed) {
    effect:
        if (speed > 30 & speed <= 50) alarm() = 1;
        if (speed > 50) alarm() = 2;
    }
    procedure main() {
        drive(60);
    }
""",
    "R0006": """
`pop_front` and `pop_back` remove an element of a list; on an empty list there is nothing to
remove, and the run stops rather than going on as if something was removed.

For example, the second `pop_front` finds the list empty:

    list[string] fluent orders() { initially: () = list[string] ["tea"]; }
    procedure main() {
        pop_front(orders());
        pop_front(orders());
    }

Check the length first:

    list[string] fluent orders() { initially: () = list[string] ["tea"]; }
    procedure main() {
        while (length(orders()) > 0)
            pop_front(orders());
    }
""",
    "R0007": """
The platform could not do what the program asked of it: answer an exogenous function, or
start an action. The run also stops before its first step when the program does not fit
the platform (on the dummy platform: when the scenario names actions, exogenous actions or
exogenous functions the program does not have, or gives them arguments or values that do not
fit). The message and its notes give the platform's reason.

For example, the dummy platform answers exogenous functions only from its scenario, and
without one it has no answer:

    number exog_function temperature(string room);
    number fluent reading() { initially: () = 0; }
    procedure main() {
        reading() = temperature("kitchen");
    }

Give the answer in a scenario file (`gpp run --scenario FILE`, or a `// scenario: FILE`
comment at the top of the program):

    // agent.gpp
    // scenario: answers.toml
    number exog_function temperature(string room);
    number fluent reading() { initially: () = 0; }
    procedure main() {
        reading() = temperature("kitchen");
    }
    // answers.toml
    [[exog_function]]
    name = "temperature"
    value = 21
""",
    "R0008": """
A procedure or function may be declared before it is defined (`procedure tidy_up();`), but
calling one that is never defined stops the run at the call. A program without a
`procedure main()` (or legacy main block) has nothing to run at all.

For example:

    action sweep() { }
    procedure tidy_up();
    procedure main() {
        tidy_up();
    }

Define it:

    action sweep() { }
    procedure tidy_up() { sweep(); }
    procedure main() {
        tidy_up();
    }
""",
    "R0009": """
`start(a)` starts an activity of a durative action. When the activity has ended, it stays
until `end(a)`, `finish(a)` or `fail(a)` takes note of it. Starting the same action with the
same arguments again before that stops the run, also when `start` first waited for the
previous activity to end: the new activity could not be told apart from the old one.

For example, `beep()` has ended while the robot drove, but nothing took note of it:

    action beep() { duration: [1, 1] }
    action drive() { duration: [5, 5] }
    procedure main() {
        start(beep());
        drive();
        start(beep());
    }

End each activity before starting the next:

    action beep() { duration: [1, 1] }
    action drive() { duration: [5, 5] }
    procedure main() {
        start(beep());
        drive();
        end(beep());
        start(beep());
        end(beep());
    }
""",
    "R0010": """
`solve` and `search` plan before they act, and planning must come to an end. It stops the
run when it cannot: a loop or recursion in the planned program that can go round without a
costed step (only actions, hooks and assignments use up the horizon of `solve`; tests do not),
planning that nests too deeply, a `search` that takes more than its bound of 10000 steps
without finding an end, or a horizon that is not a whole number >= 0.

For example, choosing `test(true)` over and over never ends the loop and never uses up the
horizon:

    number fluent done() { initially: () = 0; }
    action work() { effect: done() = done() + 1; }
    number function reward() = done()
    procedure main() {
        solve(3, reward())
            while (done() < 3) choose { test(true); work(); }
    }

Let every way around the loop make a costed step, here by resting with an action:

    number fluent done() { initially: () = 0; }
    action work() { effect: done() = done() + 1; }
    action rest() { }
    number function reward() = done()
    procedure main() {
        solve(3, reward())
            while (done() < 3) choose { rest(); work(); }
    }
""",
    "R0011": """
The program cannot make its next step: an action's precondition is false, a `test` is
false, it waits for an activity that will not end as it needs, or a `solve` or `search` finds
no plan. While something can still change that (a running activity, an exogenous event to
come), the program waits; when nothing can, the run stops "blocked". The notes show the false
conditions and the fluent values they read.

For example, there is no parcel to deliver, and nothing brings one:

    number fluent parcels() { initially: () = 0; }
    action deliver() {
    precondition:
        parcels() > 0
    effect:
        parcels() = parcels() - 1;
    }
    procedure main() {
        deliver();
    }

Make the condition true before the step that needs it:

    number fluent parcels() { initially: () = 0; }
    action load() { effect: parcels() = parcels() + 1; }
    action deliver() {
    precondition:
        parcels() > 0
    effect:
        parcels() = parcels() - 1;
    }
    procedure main() {
        load();
        deliver();
    }
""",
    "R0012": """
Procedure and function calls nested too deeply stop the run instead of crashing: almost always
a recursion without a case that ends it.

For example, `steps` calls itself for ever:

    number function steps(number n) = steps(n - 1) + 1
    number fluent total() { initially: () = 0; }
    procedure main() {
        total() = steps(5);
    }

Give the recursion an end:

    number function steps(number n) = if (n <= 0) 0 else steps(n - 1) + 1
    number fluent total() { initially: () = 0; }
    procedure main() {
        total() = steps(5);
    }
""",
    "R0013": """
`gpp run --timeout SECONDS` (and `gpp test`) stop a run when the platform's clock reaches the
timeout: the program waits for an activity or an event too long, or runs for ever. The
diagnostic shows where the program was and what it waited for. On the dummy platform the
clock is virtual, so a long timeout costs no real time.

For example, with a timeout of 60 s, a patrol that never stops:

    action patrol() { duration: [10, 10] }
    procedure main() {
        while (true) patrol();
    }

Let the loop end:

    number fluent rounds() { initially: () = 0; }
    action patrol() {
    duration: [10, 10]
    effect:
        rounds() = rounds() + 1;
    }
    procedure main() {
        while (rounds() < 3) patrol();
    }
""",
    "R0014": """
`solve(h, r) P` plans at most `h` steps of `P`. When the best plan uses all of them and `P` is
not finished after them, the plan is cut at the horizon: its last steps were chosen without
knowing what comes next (padding or truncation), and the rest of `P` is not executed: the run
goes on after the `solve`. The warning says how many more steps `P` needs at least.

For example, five deliveries planned with a horizon of 3:

    number fluent delivered() { initially: () = 0; }
    action deliver() { effect: delivered() = delivered() + 1; }
    number function reward() = delivered()
    procedure main() {
        solve(3, reward()) while (delivered() < 5) deliver();
    }

Give the horizon room for the whole program:

    number fluent delivered() { initially: () = 0; }
    action deliver() { effect: delivered() = delivered() + 1; }
    number function reward() = delivered()
    procedure main() {
        solve(5, reward()) while (delivered() < 5) deliver();
    }
""",
}

_CODES = [replace(c, explanation=_EXPLANATIONS.get(c.code, "").strip()) for c in _CODES]
CODES: dict[str, CodeInfo] = {c.code: c for c in _CODES}
BY_NAME: dict[str, CodeInfo] = {c.name: c for c in _CODES}


def lookup(code_or_name: str) -> CodeInfo | None:
    key = code_or_name.strip()
    return CODES.get(key.upper()) or BY_NAME.get(key.lower())


def lints() -> list[CodeInfo]:
    return [c for c in _CODES if c.is_lint]


def close_matches(code_or_name: str, lints: bool = False) -> list[str]:
    """Codes and names that look like `code_or_name` (for "did you mean ...?"); only lints
    when `lints` is set."""
    pool = [c for c in _CODES if c.is_lint or not lints]
    key = code_or_name.strip()
    by_code = difflib.get_close_matches(key.upper(), [c.code for c in pool], n=3, cutoff=0.6)
    by_name = difflib.get_close_matches(key.lower(), [c.name for c in pool], n=3, cutoff=0.6)
    return [*by_code, *by_name]
