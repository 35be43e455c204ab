"""``gearrotor mesh-response MODEL [--min-speed RPM] [--max-speed RPM] [--n-speeds N]
[--harmonics H] [--nonlinear [--sweep up|down]] [--format table|json] [--plot DIR]``: the
periodic steady state of the train under its mesh excitation and unbalance over a speed
range, by harmonic balance (:func:`gearrotor.analyses.lateral.mesh_response.mesh_response`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..files import check_output, write_json
from .errors import cli_errors
from .options import (
    MAX_SPEEDS,
    RPM,
    FormatOpt,
    SetOpt,
    check_format,
    choice,
    count,
    rpm,
    speed_grid,
    sweep_range,
)

__all__ = ["mesh_response_command"]


@cli_errors()
def mesh_response_command(
    model: Annotated[Path, typer.Argument(help="TOML model file with at least one gear mesh")],
    min_speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True),
            help="rpm (default 5 % of the maximum, or the lowest speed of the bearing tables)",
        ),
    ] = None,
    max_speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True),
            help="rpm (default 1.25 × nominal, at most the highest speed of the bearing tables)",
        ),
    ] = None,
    n_speeds: Annotated[
        int, typer.Option(parser=count(2, MAX_SPEEDS), help="number of speeds")
    ] = 60,
    harmonics: Annotated[
        int,
        typer.Option(parser=count(1, 200), help="mesh harmonics kept (of each mesh law)"),
    ] = 10,
    nonlinear: Annotated[
        bool,
        typer.Option(
            "--nonlinear",
            help="solve with the meshes' backlash law (teeth separating, back-flank contact) "
            "instead of the linear one, continued from speed to speed",
        ),
    ] = False,
    sweep: Annotated[
        str,
        typer.Option(
            parser=choice("up", "down"),
            help="with --nonlinear: the direction the solution is continued in (down: the "
            "resonant branch of a softening mesh, as a run-down or a start from rest reaches it)",
        ),
    ] = "down",
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None,
        typer.Option(
            help="write mesh_response.png, bearing_forces.png and mesh_response.json to this "
            "directory"
        ),
    ] = None,
    set_: SetOpt = None,
) -> None:
    """Periodic response over speed to the gear-mesh excitation (transmission error and
    time-varying mesh stiffness) and unbalance, by harmonic balance of the linear time-periodic
    equations: DTE rms, dynamic mesh force and dynamic factor (with ISO 6336-1 K_v), probe
    amplitudes and bearing forces at 1x, 1x and 2x mesh frequency."""
    from ..io import load_model, parse_overrides

    check_format(format)
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    train = load_model(model, parse_overrides(set_))
    from ..analyses.lateral.mesh_response import mesh_response

    default_max = 1.25 * abs(train.speed) / RPM
    lo, hi = sweep_range(train, min_speed, max_speed, 0.0, default_max)
    if min_speed is None:
        lo = max(lo, 0.05 * hi)
    speeds = speed_grid(lo, hi, n_speeds, "--min-speed/--max-speed")
    res = mesh_response(train, speeds=speeds, harmonics=harmonics, nonlinear=nonlinear, sweep=sweep)
    doc = {"model": str(model), **res.to_dict()}
    if format == "json":
        typer.echo(json.dumps(doc, indent=1))
    else:
        typer.echo(f"{train.name}: mesh response {lo:.0f}..{hi:.0f} rpm")
        typer.echo(res.table())
    if plot is not None:
        from ..files import make_directory
        from ..plots.mesh_response import plot_bearing_forces, plot_mesh_response

        make_directory(plot, field="--plot")
        plot_mesh_response(res, plot / "mesh_response.png", title=train.name)
        plot_bearing_forces(res, plot / "bearing_forces.png")
        write_json(plot / "mesh_response.json", doc)
        typer.echo(f"plots written to {plot}/", err=format == "json")
