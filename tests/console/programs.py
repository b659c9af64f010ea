"""Programs the console's tests run, made for each test (the page must show what it was never
told of: a fluent named anew each time)."""

from __future__ import annotations

import secrets
from pathlib import Path


def hidden_program(folder: Path) -> tuple[Path, str]:
    """(path, fluent name): a program whose fluent name is new; it waits for the exogenous
    event `ping(n)` with n > 2, then sets its fluent to `done`."""
    name = "hidden_" + secrets.token_hex(4)
    path = folder / f"{name}.gpp"
    path.write_text(
        f"""symbol domain Room = {{kitchen, hall}}
symbol domain Progress = {{waiting, done}}

Progress fluent {name}(Room r) {{
initially:
    (r) = waiting;
}}

number fluent pinged() {{
initially:
    () = 0;
}}

exog_action ping(number n, Room r) {{
effect:
    pinged() = n;
}}

action tick() {{
duration: [1, 1]
}}

procedure main() {{
    tick();
    test(pinged() > 2);
    {name}(kitchen) = done;
    tick();
}}
""",
        encoding="utf-8",
    )
    return path, name


def endless_program(folder: Path) -> Path:
    """A program that ticks (one second of virtual time each) until the event `halt`."""
    path = folder / "endless.gpp"
    path.write_text(
        """number fluent rounds() {
initially:
    () = 0;
}

bool fluent halted() {
initially:
    () = false;
}

exog_action halt() {
effect:
    halted() = true;
}

action tick() {
effect:
    rounds() = rounds() + 1;
duration: [1, 1]
}

procedure main() {
    while (!halted())
        tick();
}
""",
        encoding="utf-8",
    )
    return path
