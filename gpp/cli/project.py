"""`gpp config` (the project's settings, resolved) and `gpp new` (a starter project).
Registered on the app by gpp.cli.app."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer


def register(app: typer.Typer) -> None:
    app.command(name="config")(config_command)
    app.command(name="new")(new_command)


def config_command(
    path: Annotated[
        Path | None,
        typer.Argument(
            metavar="PATH", help="A file or folder whose settings to show (default: the working directory)."
        ),
    ] = None,
) -> None:
    """Show the settings that apply to PATH and the file they come from (gpp.toml, or the
    `[tool.gpp]` table of pyproject.toml, the nearest going up)."""
    from gpp.cli.common import EXIT_OK, load_config, usage_error
    from gpp.project.config import describe

    start = path if path is not None else Path.cwd()
    if not start.exists():
        usage_error(f"no such file or folder: '{start}'")
    print(describe(load_config(start)), end="")
    raise typer.Exit(EXIT_OK)


def new_command(
    name: Annotated[Path, typer.Argument(metavar="NAME", help="The folder to create for the project.")],
) -> None:
    """Create a starter agent project in the folder NAME: an agent, a robot library, a test
    program with its scenario, gpp.toml and a README. NAME must not exist or be empty."""
    from gpp.cli.common import EXIT_OK, usage_error
    from gpp.project.scaffold import ScaffoldError, create_project

    try:
        written = create_project(name)
    except ScaffoldError as e:
        usage_error(str(e))
    except OSError as e:
        usage_error(f"cannot create '{name}': {e.strerror or e}")
    here = name.resolve() == Path.cwd().resolve()
    print(f"created {'the project here' if here else f'{name}/'} with {len(written)} files:")
    for path in written:
        print(f"  {path.relative_to(name).as_posix()}")
    print("next: gpp check && gpp test" if here else f"next: cd {name} && gpp check && gpp test")
    raise typer.Exit(EXIT_OK)
