"""``gearrotor mesh GEARPAIR.toml [--torque N*m] [--format table|json] [--plot DIR]``: the
loaded mesh of a gear pair from its tooth geometry (:func:`gearrotor.gears.mesh_curves`):
mean, maximum and minimum mesh stiffness, contact ratios, the TVMS and loaded STE over one mesh
cycle and the STE harmonics."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output, write_json
from .errors import cli_errors
from .options import FormatOpt, _bad, _number, check_format

__all__ = ["mesh_command"]


def _torque(text: str) -> float:
    value = _number(text, "torque", "N*m", 1.0)
    if value < 0:
        raise _bad(text, "out of range", ">= 0 N*m (the pinion torque's magnitude)")
    return value


_torque.metavar = "TORQUE"


@cli_errors()
def mesh_command(
    path: Annotated[Path, typer.Argument(help="gear-pair TOML file (docs/gears.md)")],
    torque: Annotated[
        float | None,
        typer.Option(
            parser=_torque,
            help="pinion torque, N*m or with units (default: the file's 'torque')",
        ),
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None,
        typer.Option(
            help="write the mesh cycle (stiffness, STE, load sharing) and the harmonics (PNG) "
            "and mesh.json to this directory"
        ),
    ] = None,
) -> None:
    """Gear mesh from the tooth geometry (spur or helical): loaded static transmission error
    and time-varying mesh stiffness over one mesh cycle under the operating torque, contact
    ratios and the STE harmonics."""
    from ..gears import load_gear_pair, mesh_curves

    check_format(format)
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    spec = load_gear_pair(path)
    try:
        res = mesh_curves(spec, torque)
    except ModelError as exc:  # the geometry's checks name the gear-pair file
        raise (exc if exc.file else exc.with_file(str(path))) from None
    doc = {"file": str(path), **res.to_dict()}
    if format == "json":
        typer.echo(json.dumps(doc, indent=1))
    else:
        typer.echo(res.table())
    if plot is not None:
        from ..files import make_directory
        from ..gears.plots import plot_harmonics, plot_mesh_cycle

        make_directory(plot, field="--plot")
        plot_mesh_cycle(res, plot / "mesh_cycle.png")
        plot_harmonics(res, plot / "harmonics.png")
        write_json(plot / "mesh.json", doc)
        typer.echo(f"plots written to {plot}/", err=format == "json")
