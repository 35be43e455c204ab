"""``gearrotor unbalance``: steady-state unbalance response with the API 684 / API 617 checks
(:func:`gearrotor.analyses.unbalance_response`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import ModelError
from .errors import cli_errors
from .options import RPM, FormatOpt, SetOpt, check_format, speed_grid

__all__ = ["unbalance_command"]


@cli_errors()
def unbalance_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    min_speed: Annotated[float, typer.Option(help="rpm")] = 100.0,
    max_speed: Annotated[float | None, typer.Option(help="rpm (default 1.5 × nominal)")] = None,
    n_speeds: Annotated[int, typer.Option(help="number of speeds")] = 400,
    operating_range: Annotated[
        str | None,
        typer.Option(
            help="MIN,MAX operating speeds of the reference shaft, rpm (default: nominal)"
        ),
    ] = None,
    api: Annotated[
        bool,
        typer.Option(help="replace the amounts by API 617 unbalance (4 × 6350 W/N g·mm per plane)"),
    ] = False,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None, typer.Option(help="write Bode and orbit plots to this directory")
    ] = None,
    set_: SetOpt = None,
) -> None:
    """Steady-state unbalance response: Bode, peaks, critical speeds, API 684 AF and margins."""
    from ..analyses import unbalance_response
    from ..analyses.api617 import api617_unbalances
    from ..assembly import assemble
    from ..io import load_model, parse_overrides

    check_format(format)
    train = load_model(model, parse_overrides(set_))
    hi = max_speed if max_speed is not None else 1.5 * abs(train.speed) / RPM
    speeds = speed_grid(min_speed, hi, n_speeds, "--min-speed/--max-speed")
    op = None
    if operating_range:
        try:
            lo_op, hi_op = (float(x) * RPM for x in operating_range.split(","))
        except ValueError:
            raise ModelError(
                "cannot read the operating range",
                field="--operating-range",
                value=operating_range,
                expected="MIN,MAX in rpm",
            ) from None
        op = (lo_op, hi_op)
    if op is not None:
        # the operating range's ends are sweep points: the orbits are drawn at the maximum
        # continuous speed itself, not at the nearest grid speed (7211 rpm for a range to 7200)
        ends = [v for v in op if speeds[0] <= v <= speeds[-1]]
        speeds = np.union1d(speeds, ends)
    asm = assemble(train)
    unb = list(train.unbalances)
    if api:
        unb = api617_unbalances(asm, op[1] if op else abs(train.speed))
    res = unbalance_response(asm, speeds=speeds, unbalances=unb, operating_range=op)
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
        typer.echo(f"{train.name}: unbalance response {min_speed:.0f}..{hi:.0f} rpm")
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
