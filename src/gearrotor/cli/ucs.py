"""``gearrotor ucs``: the undamped critical speed map (:func:`gearrotor.analyses.ucs_map`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from .errors import cli_errors
from .options import (
    RPM,
    FormatOpt,
    McsOpt,
    OperatingPointOpt,
    OperatingRangeOpt,
    SetOpt,
    check_format,
    check_operating_point,
    check_png,
    choice,
    count,
    operating_range_from_options,
)
from .progress import current

__all__ = ["ucs_command"]


def _stiffness(text: str | None, field: str) -> float | None:
    from ..units import to_si

    if text is None:
        return None
    try:
        k = to_si(text, "stiffness")
    except ValueError as exc:
        raise ModelError(str(exc), field=field, value=text) from None
    if not k > 0:
        raise ModelError("the stiffness must be positive", field=field, value=text)
    return k


@cli_errors()
def ucs_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    min_stiffness: Annotated[
        str | None,
        typer.Option(
            help="lowest bearing stiffness, N/m or with units (default: a decade "
            "below the model's bearings)"
        ),
    ] = None,
    max_stiffness: Annotated[
        str | None,
        typer.Option(help="highest bearing stiffness (default: a decade above the bearings)"),
    ] = None,
    n_points: Annotated[
        int, typer.Option(parser=count(2, 10_000), help="stiffness values, log spaced")
    ] = 31,
    n_modes: Annotated[
        int,
        typer.Option(
            parser=count(1),
            help="critical speeds of each shaft kept at each stiffness, the lowest (a few: "
            "a map is read for its first modes; the bound is in the error)",
        ),
    ] = 4,
    method: Annotated[
        str,
        typer.Option(
            parser=choice("auto", "dense", "sparse"), help="auto, dense or sparse eigensolver"
        ),
    ] = "auto",
    operating_range: OperatingRangeOpt = None,
    mcs: McsOpt = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None, typer.Option(help="write the map (one panel per shaft) to this PNG")
    ] = None,
    set_: SetOpt = None,
    operating_point: OperatingPointOpt = None,
) -> None:
    """Undamped critical speed map: criticals of every shaft against the bearing stiffness
    (modes followed by shape; a critical of a shaft where the mode's forward whirl on it holds
    the share of its energy that unbalance there excites), each shaft's own bearings' Kxx/Kyy
    over speed and the exact intersections, the rigid-support criticals. With
    --operating-point the bearing curves are at the point's static loads (its torque held)
    at every speed of the curve."""
    from ..analyses.audit.ucs import MAX_MODES, ucs_map
    from ..io import load_model, parse_overrides

    check_format(format)
    check_png(plot)
    if n_modes > MAX_MODES:
        raise ModelError(
            "too many critical speeds per shaft (every one asked for widens the band of modes "
            "followed at every stiffness)",
            field="--n-modes",
            value=n_modes,
            expected=f"an integer 1..{MAX_MODES}",
        )
    if n_points < 2:
        raise ModelError(
            "too few stiffness values", field="--n-points", value=n_points, expected="at least 2"
        )
    train = load_model(model, parse_overrides(set_))
    train = operating_range_from_options(train, operating_range, mcs)
    check_operating_point(train, operating_point)
    lo = _stiffness(min_stiffness, "--min-stiffness")
    hi = _stiffness(max_stiffness, "--max-stiffness")
    if (lo is None) != (hi is None):
        raise ModelError(
            "give both ends of the stiffness sweep or neither",
            field="--min-stiffness/--max-stiffness",
            value=min_stiffness if hi is None else max_stiffness,
            expected="both --min-stiffness and --max-stiffness",
        )
    if lo is not None and not hi > lo:
        raise ModelError(
            "the stiffness sweep is empty",
            field="--max-stiffness",
            value=max_stiffness,
            expected=f"more than --min-stiffness {min_stiffness}",
        )
    res = ucs_map(
        train,
        stiffness=None if lo is None else (lo, hi),
        n_stiffness=n_points,
        n_modes=n_modes,
        method=method,
        operating_point=operating_point,
        progress=current(),
    )
    if format == "json":
        typer.echo(json.dumps({"model": train.name, **res.to_dict()}, indent=1))
    else:
        typer.echo(
            f"{train.name}: undamped critical speed map, bearing stiffness "
            f"{res.stiffness[0]:.3g}..{res.stiffness[-1]:.3g} N/m ({len(res.stiffness)} points, "
            f"{res.method} eigensolver, {res.n_solves} solves)"
        )
        if res.operating_range is not None:
            a, b = (v / RPM for v in res.operating_range)
            typer.echo(f"operating range {a:.0f}..{b:.0f} rpm (reference shaft)")
        if res.max_continuous_speed is not None:
            typer.echo(f"maximum continuous speed {res.max_continuous_speed / RPM:.0f} rpm")
        typer.echo(res.table())
    if plot is not None:
        import matplotlib.pyplot as plt

        from ..plots.audit import plot_ucs_map

        plt.close(plot_ucs_map(res, path=plot))
        typer.echo(f"map written to {plot}", err=format == "json")
