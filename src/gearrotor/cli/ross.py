"""``gearrotor import-ross`` and ``gearrotor export``: rotors from and to ROSS
(:mod:`gearrotor.io.ross`)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output, make_directory, write_text
from .errors import cli_errors
from .options import RPM, SetOpt, choice, number, rpm

__all__ = ["import_ross_command", "export_command"]


@cli_errors()
def import_ross_command(
    rotor: Annotated[Path, typer.Argument(help="rotor file saved by ROSS 3.x (Rotor.save, TOML)")],
    output: Annotated[Path, typer.Option(help="the gearrotor model file to write (TOML)")],
    speed: Annotated[
        float, typer.Option(parser=rpm(), metavar="SPEED", help="the model's speed, rpm")
    ] = 0.0,
    mesh_stiffness: Annotated[
        float | None,
        typer.Option(
            parser=number(0, strict=True),
            help="gear mesh stiffness, N/m, for a MultiRotor's gear pair (ROSS's file does not "
            "hold it)",
        ),
    ] = None,
    orientation: Annotated[
        float,
        typer.Option(
            parser=number(),
            help="ROSS's orientation_angle of the gear pair, deg (gearrotor's line-of-centres "
            "angle is its negative)",
        ),
    ] = 0.0,
    name: Annotated[str | None, typer.Option(help="the model's name")] = None,
) -> None:
    """Read a rotor saved by ROSS and write it as a gearrotor model file with units and
    comments (shaft elements, materials, disks and gears, bearings and seals with their
    coefficient tables, pedestals, thrust coefficients; a MultiRotor's two shafts and gear
    mesh). What gearrotor cannot represent is refused with one line naming the element."""
    import numpy as np

    from ..inputs import parse_toml
    from ..interop.ross import import_ross, model_toml
    from ..io import model_from_file_data

    if output.suffix.lower() != ".toml":
        raise ModelError(
            "the model is written as TOML",
            field="--output",
            value=str(output),
            expected="a .toml file",
        )
    check_output(output, "file", field="--output", parents=True)
    imported = import_ross(
        rotor,
        speed=speed * RPM,
        mesh_stiffness=mesh_stiffness,
        orientation=np.radians(orientation),
        name=name,
    )
    text = model_toml(imported, rotor.name)
    # the text must load as a model before it is written (nothing half-done)
    train = model_from_file_data(parse_toml(text, str(output), "model"), output)
    make_directory(output.parent, field="--output")
    write_text(output, text)
    typer.echo(
        f"{output}: {len(train.shafts)} shaft(s), "
        f"{sum(len(s.disks) for s in train.shafts)} disks, {len(train.bearings)} bearings, "
        f"{len(train.seals)} seals, {len(train.meshes)} gear mesh(es)"
    )
    for n in imported.notes:
        typer.echo(f"note: {n}")


@cli_errors()
def export_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    to: Annotated[
        str, typer.Option("--to", parser=choice("ross-python"), help="ross-python")
    ] = "ross-python",
    output: Annotated[
        Path | None, typer.Option(help="write the script here (default: standard output)")
    ] = None,
    set_: SetOpt = None,
) -> None:
    """Write a Python script that builds the model in ROSS 3.x (a Rotor, or a MultiRotor for two
    shafts joined by one gear mesh) and prints its damped modes at the model's speed, so that
    anyone can cross-check gearrotor's results in ROSS."""
    from ..assembly import assemble
    from ..interop.ross import ross_script
    from ..io import load_model, parse_overrides

    if output is not None:
        check_output(output, "file", field="--output", parents=True)
    train = load_model(model, parse_overrides(set_))
    text = ross_script(assemble(train))
    if output is None:
        typer.echo(text, nl=False)
    else:
        make_directory(output.parent, field="--output")
        write_text(output, text)
        typer.echo(f"ROSS script written to {output}")
