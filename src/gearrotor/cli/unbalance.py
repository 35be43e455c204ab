"""``gearrotor unbalance``: steady-state unbalance response with the API 684 / API 617 checks
(:func:`gearrotor.analyses.unbalance_response`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..files import check_output
from .errors import cli_errors
from .options import (
    MAX_SPEEDS,
    RPM,
    FormatOpt,
    McsOpt,
    OperatingPointOpt,
    OperatingRangeOpt,
    SetOpt,
    check_format,
    check_operating_point,
    count,
    operating_range_from_options,
    rpm,
    speed_grid,
    sweep_range,
)

__all__ = ["unbalance_command"]


@cli_errors()
def unbalance_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    min_speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0),
            help="rpm (default 100, or the lowest speed of the model's bearing tables)",
        ),
    ] = None,
    max_speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True),
            help="rpm (default 1.5 × nominal, at most the highest speed of the bearing tables)",
        ),
    ] = None,
    n_speeds: Annotated[
        int, typer.Option(parser=count(2, MAX_SPEEDS), help="number of speeds")
    ] = 400,
    operating_range: OperatingRangeOpt = None,
    mcs: McsOpt = None,
    api: Annotated[
        bool,
        typer.Option(help="replace the amounts by API 617 unbalance (4 × 6350 W/N g·mm per plane)"),
    ] = False,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None, typer.Option(help="write Bode and orbit plots to this directory")
    ] = None,
    operating_point: OperatingPointOpt = None,
    set_: SetOpt = None,
) -> None:
    """Steady-state unbalance response: Bode, peaks, critical speeds, API 684 AF and margins."""
    from ..analyses import model_operating_range, unbalance_response
    from ..analyses.api617 import api617_unbalances
    from ..assembly import assemble
    from ..io import load_model, parse_overrides

    check_format(format)
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    train = load_model(model, parse_overrides(set_))
    check_operating_point(train, operating_point)
    # --operating-range / --mcs override the model's; the response takes the range from the
    # train (model_operating_range; the nominal speed when the model states none)
    train = operating_range_from_options(train, operating_range, mcs)
    lo, hi = sweep_range(train, min_speed, max_speed, 100.0, 1.5 * abs(train.speed) / RPM)
    speeds = speed_grid(lo, hi, n_speeds, "--min-speed/--max-speed")
    # the operating range's ends (the nominal speed without one) are sweep points: the orbits
    # are drawn at the maximum continuous speed itself, not at the nearest grid speed (7211 rpm
    # for a range to 7200)
    op = model_operating_range(train) or (abs(train.speed), abs(train.speed))
    speeds = np.union1d(speeds, [v for v in op if speeds[0] <= v <= speeds[-1]])
    asm = assemble(train)
    unb = list(train.unbalances)
    if api:
        top = model_operating_range(train)
        unb = api617_unbalances(asm, top[1] if top else abs(train.speed))
    res = unbalance_response(asm, speeds=speeds, unbalances=unb, operating_point=operating_point)
    if format == "json":
        d = res.to_dict()
        d["unbalances"] = [
            {
                "shaft": u.shaft,
                "amount_g_mm": u.amount * 1e6,
                "phase_deg": float(np.rad2deg(u.phase)),
            }
            for u in unb
        ]
        typer.echo(json.dumps(d, indent=1))
    else:
        typer.echo(f"{train.name}: unbalance response {lo:.0f}..{hi:.0f} rpm")
        for u in unb:
            typer.echo(
                f"  unbalance {u.amount * 1e6:.1f} g·mm at {u.shaft} "
                f"phase {np.rad2deg(u.phase):.0f}°"
            )
        typer.echo(res.table())
    if plot is not None:
        from ..plots import plot_bode, plot_orbits

        plot.mkdir(parents=True, exist_ok=True)
        plot_bode(res, path=plot / "bode.png")
        k = int(np.argmin(np.abs(res.speeds - res.operating_range[1])))
        plot_orbits(res, k, path=plot / "orbits_operating.png")
        typer.echo(f"plots written to {plot}/", err=format == "json")
