"""``gearrotor unbalance``: steady-state unbalance response with the API 684 / API 617 checks
(:func:`gearrotor.analyses.unbalance_response`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..files import check_output, make_directory, output_set
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
    sweep_at_operating_point,
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
        typer.Option(
            help="API 617 unbalance: 8th edition 4 × 6350 W/N g·mm at the model's planes; 9th "
            "edition 2 × 6350 W/N g·mm at the antinodes of a forward mode (--mode)"
        ),
    ] = False,
    edition: Annotated[
        str | None,
        typer.Option(
            help="API 617 edition of --api: 8th (2014) or 9th (2022); default: the model's "
            "[api_audit] edition, else 8th"
        ),
    ] = None,
    mode: Annotated[
        int,
        typer.Option(
            parser=count(0, 1000),
            help="9th edition: the forward mode (0: the first) of the reference shaft whose "
            "antinodes carry the unbalance",
        ),
    ] = 0,
    clearance: Annotated[
        list[str] | None,
        typer.Option(
            help="9th edition close-clearance check: SHAFT:NODE:DIAMETRAL[:NAME], the minimum "
            "diametral running clearance at a node (e.g. 'pinion:3:0.3 mm:labyrinth'), "
            "repeatable (default: the model's [api_audit] clearances, else twice the radial "
            "clearance of each fluid-film journal bearing's file)"
        ),
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None, typer.Option(help="write Bode and orbit plots to this directory")
    ] = None,
    operating_point: OperatingPointOpt = None,
    set_: SetOpt = None,
) -> None:
    """Steady-state unbalance response: Bode, peaks, critical speeds, API 684 AF and margins."""
    from ..analyses import model_operating_range, unbalance_response
    from ..analyses.audit.api_unbalance import (
        CloseClearance,
        api617_unbalances,
        clearance_check,
        close_clearances,
        mode_unbalances,
    )
    from ..analyses.audit.stability import edition as pick_edition
    from ..assembly import assemble
    from ..errors import ModelError
    from ..io import load_model, parse_overrides

    check_format(format)
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    ed = None if edition is None else pick_edition(edition, "--edition")
    clearances = [_parse_clearance(c) for c in clearance or ()]
    if (ed is not None or clearances or mode) and not api:
        raise ModelError(
            "--edition, --mode and --clearance choose the API 617 unbalance: give --api too",
            field="--api",
            expected="--api with --edition/--mode/--clearance",
        )
    train = load_model(model, parse_overrides(set_))
    if ed is None and train.api_audit is not None:
        ed = pick_edition(train.api_audit.edition, "api_audit.edition")
    ed = pick_edition(None) if ed is None else ed
    if not clearances and api and ed.key == "9th":
        # the model's [api_audit] clearances, else its fluid-film journal bearings'
        clearances = [(c.shaft, c.node, c.diametral, c.name) for c in close_clearances(train)]
    if clearances and ed.key != "9th":
        raise ModelError(
            "the close-clearance check is the 9th edition's (6.8.2.10-6.8.2.11)",
            field="--clearance",
            expected="--edition 9th",
        )
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
    placed = check = None
    if api:
        top = model_operating_range(train)
        mcs_ref = top[1] if top else abs(train.speed)
        if ed.key == "9th":
            placed = mode_unbalances(asm, mode=mode, max_continuous_speed=mcs_ref)
            unb = placed.unbalances()
        else:
            unb = api617_unbalances(asm, mcs_ref)
    with sweep_at_operating_point(train, operating_point):
        res = unbalance_response(
            asm, speeds=speeds, unbalances=unb, operating_point=operating_point
        )
    if clearances:
        check = clearance_check(
            res.assembly,
            [CloseClearance(*c) for c in clearances],
            speeds=speeds,
            operating_range=op,
            unbalance=placed,
        )
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
        if api:
            d["api617_edition"] = ed.name
        if placed is not None:
            d["api617_mode_unbalance"] = placed.to_dict()
        if check is not None:
            d["close_clearance_check"] = check.to_dict()
        typer.echo(json.dumps(d, indent=1))
    else:
        typer.echo(f"{train.name}: unbalance response {lo:.0f}..{hi:.0f} rpm")
        if api:
            typer.echo(f"  API 617 unbalance: {ed.name}, {ed.unbalance}")
        for u in unb:
            typer.echo(
                f"  unbalance {u.amount * 1e6:.1f} g·mm at {u.shaft} node {u.node} "
                f"phase {np.rad2deg(u.phase):.0f}°"
            )
        typer.echo(res.table())
        if check is not None:
            typer.echo(check.table())
    if plot is not None:
        from ..plots import plot_bode, plot_orbits

        k = int(np.argmin(np.abs(res.speeds - res.operating_range[1])))
        with output_set():  # both figures or neither
            make_directory(plot, field="--plot")
            plot_bode(res, path=plot / "bode.png")
            plot_orbits(res, k, path=plot / "orbits_operating.png")
        typer.echo(f"plots written to {plot}/", err=format == "json")


def _parse_clearance(text: str) -> tuple[str, int, float, str]:
    """``SHAFT:NODE:DIAMETRAL[:NAME]`` -> (shaft, node, diametral clearance in m, name)."""
    from ..errors import ModelError
    from ..units import to_si

    parts = text.split(":")
    bad = ModelError(
        "cannot read the close clearance",
        field="--clearance",
        value=text,
        expected="SHAFT:NODE:DIAMETRAL[:NAME], e.g. 'pinion:3:0.3 mm:labyrinth'",
    )
    if len(parts) not in (3, 4) or not parts[0]:
        raise bad
    try:
        node = int(parts[1])
        gap = to_si(parts[2], "length")
    except ValueError:
        raise bad from None
    if node < 0 or not gap > 0:
        raise bad
    return parts[0], node, float(gap), parts[3] if len(parts) == 4 else ""
