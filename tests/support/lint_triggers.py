"""Programs that trigger each lint, one per code (TRIGGERS), and the programs they are made of."""

from __future__ import annotations

UNUSED = """\
number fluent count() { initially: () = 0; }
action beep() { }
number function fact(number n) = if (n <= 1) 1 else n * fact(n - 1)
procedure main() { }
bool function postcond() = true
exog_action bell() { }
"""


UNUSED_VARIABLES = """\
symbol domain Room = {hall, kitchen}
number function twice(number x, number y) = 2 * x
action go(Room r, number speed) {
mapping:
    "go" { target = r }
}
action wait(number seconds) { }
exog_action arrived(Room room) { }
procedure main() {
    go(hall, 1);
    wait(twice(1, 2));
    search pick (Room r) wait(1);
    test(exists(Room q) true);
}
"""


DOUBLE_EFFECT = """\
symbol domain Room = {hall, kitchen}
number fluent count() { initially: () = 0; }
bool fluent lit(Room r) { initially: (r) = false; }
action step(Room r) {
effect:
    count() = count() + 1;
    lit(r) = true;
    lit(hall) = true;
    count() = 0;
    if (r == hall) lit(r) = false;
}
procedure main() { step(hall); }
"""


ONLINE = """\
symbol domain Room = {hall, kitchen}
action go(Room r) { }
number function reward() = 0
procedure anywhere() { pick (Room r) go(r); }
procedure planned() { choose { go(hall); go(kitchen); } }
procedure main() {
    pick (Room r in {hall}) go(r);
    anywhere();
    solve(2, reward()) { planned(); anywhere(); }
    search { pick (Room r) go(r); }
    choose { go(hall); go(kitchen); }
}
"""


CONSTANT = """\
symbol domain Room = {hall, kitchen}
number fluent count() { initially: () = 0; }
action beep() {
precondition: 1 > 2
effect:
    if (hall == hall) count() = 1;
}
procedure main() {
    if (1 < 2) beep();
    while (false) beep();
    while ("a" != "a") beep();
    test(!true);
    while (hall != kitchen) beep();
}
"""


UNREACHABLE = """\
action beep() { }
action wait() { }
procedure main() {
    if (true) beep(); else wait();
    if (1 > 2) beep();
    else wait();
}
"""


SOLVE = """\
action work() { }
action rest() { }
number function reward() = 0
procedure either() { choose { work(); rest(); } }
procedure indirect() { either(); }
procedure main() {
    solve(3, reward()) work();
    solve(3, reward()) indirect();
    solve(3, reward()) while (true) pick (bool b) if (b) work();
}
"""


FLUENTS = """\
number fluent x() { initially: () = 1; }
bool fluent p() { initially: () = true; }
bool fluent q() { initially: () = true; }
bool fluent r() { initially: () = true; }
bool fluent s() { initially: () = true; }
"""


SHADOWED = """\
symbol domain Room = {hall, kitchen}
action go(Room hall) { }
procedure main() {
    go(kitchen);
    search pick (Room kitchen) go(kitchen);
}
"""


BLOCKS = """\
symbol domain Block = {a, b, c}
bool fluent on(Block x, Block y) { initially: (x, y) = false; }
bool fluent clear(Block x) { initially: (x) = true; }
"""


def scoped(expression: str) -> str:
    return BLOCKS + f"bool function f(Block x) = {expression}\nprocedure main() {{ test(f(a)); }}\n"


QUANTIFIER = scoped("!exists(Block z) on(z, x) & clear(x)")


def sensing(senses: str) -> str:
    return f"""\
compound Pose {{ number x, number y }}
Pose fluent pose() {{ initially: () = Pose {{ x = 0, y = 0 }}; }}
number exog_function sensed(string axis);
number exog_function sensed_x();
action locate() {{
senses:
    {senses}
}}
procedure main() {{ locate(); }}
"""


SHARED_SENSING = sensing('pose() = Pose { x = sensed_x(), y = sensed("y") };')


UNENDED = """\
action scan() { }
action go(number speed) { }
action charge() { }
action beep() { }
procedure stop() { cancel(go(1)); }
procedure main() {
    start(scan());
    start(go(2));
    start(charge());
    stop();
    start(beep());
    finish(charge());
}
"""


def looping(condition: str, body: str) -> str:
    return f"""\
bool fluent done() {{ initially: () = false; }}
number fluent n() {{ initially: () = 0; }}
number fluent other() {{ initially: () = 0; }}
list[number] fluent queue() {{ initially: () = list[number] []; }}
bool function finished() = n() >= 3
action beep() {{ }}
procedure step() {{ n() = n() + 1; }}
procedure main() {{
    while ({condition}) {body}
    step();
    beep();
    test(done() & finished() & other() > 0 & length(queue()) > 0);
}}
"""


GOAL_PAID_AGAIN = """\
symbol domain Desk = {lobby, room1}
Desk fluent at_desk() { initially: () = lobby; }
bool fluent served() { initially: () = false; }
number fluent visits() { initially: () = 0; }
action drive(Desk r) { effect: at_desk() = r; }
number function served_reward() = if (served()) 100 else -1
procedure main() {
    solve(3, served_reward()) {
        pick (Desk r) drive(r);
        served() = at_desk() == room1;
        visits() = visits() + 1;
    }
}
"""

UNWATCHED = """\
bool fluent guest_left() { initially: () = false; }
exog_action guest_leaves() { effect: guest_left() = true; }
action roll(number room) { }
action say_sorry() { }
procedure main() {
    during (roll(1)) {
        test(guest_left());
        cancel(roll(1));
    } on_fail {
        say_sorry();
    }
}
"""

UNRUN_WATCH_BODY = """\
bool fluent path_blocked() { initially: () = false; }
action ride(number room) { }
action announce_ride() { }
number function zero_reward() = 0
procedure main() {
    solve(2, zero_reward()) {
        during (ride(1)) until (path_blocked()) {
            announce_ride();
        }
    }
}
"""


TRIGGERS = {
    "W0101": UNUSED,
    "W0102": UNUSED_VARIABLES,
    "W0103": "number fluent f();\n",
    "W0104": DOUBLE_EFFECT,
    "W0105": ONLINE,
    "W0106": "procedure main() { while (true) { } }\n",
    "W0107": CONSTANT,
    "W0108": UNREACHABLE,
    "W0109": SOLVE,
    "W0110": FLUENTS + "number function f() = x() * 2 + x() * 3\n",
    "W0111": SHADOWED,
    "W0112": QUANTIFIER,
    "W0113": SHARED_SENSING,
    "W0114": UNENDED,
    "W0115": looping("!done()", "{ }"),
    "W0118": GOAL_PAID_AGAIN,
    "W0119": UNWATCHED,
    "W0120": UNRUN_WATCH_BODY,
}
