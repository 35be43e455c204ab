"""``gearrotor campbell``: Campbell diagram with mode tracking and crossing speeds
(:func:`gearrotor.analyses.campbell`)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output
from .errors import cli_errors
from .options import (
    MAX_SPEEDS,
    RPM,
    FormatOpt,
    OperatingPointOpt,
    SetOpt,
    check_format,
    check_operating_point,
    count,
    option_fields,
    rpm,
    speed_grid,
    sweep_at_operating_point,
    sweep_range,
)
from .progress import current

__all__ = ["campbell_command", "parse_orders"]


def parse_orders(text: str | None) -> tuple[float, ...]:
    """``--orders '10,42'`` -> (10.0, 42.0): multiples of the reference shaft's speed, each
    finite and positive."""
    if text is None:
        return ()
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        values = ()
    if not values or not all(math.isfinite(v) and v > 0 for v in values):
        raise ModelError(
            "cannot read the orders",
            field="--orders",
            value=text,
            expected="comma-separated positive multiples of the reference shaft speed, "
            "e.g. '10,42'",
        )
    return values


@cli_errors()
def campbell_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    min_speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0),
            help="rpm (default 0, or the lowest speed of the model's bearing tables)",
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
    max_frequency: Annotated[
        float | None,
        typer.Option(parser=rpm(0, strict=True), help="rpm (default 3 × max speed)"),
    ] = None,
    orders: Annotated[
        str | None,
        typer.Option(help="extra excitation orders of the reference shaft, e.g. '10,42'"),
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[Path | None, typer.Option(help="write the Campbell diagram PNG")] = None,
    operating_point: OperatingPointOpt = None,
    set_: SetOpt = None,
) -> None:
    """Campbell diagram with MAC mode tracking, excitation orders and crossing speeds."""
    from ..io import load_model, parse_overrides

    check_format(format)
    if plot is not None:
        check_output(plot, "file", field="--plot", parents=True)
    train = load_model(model, parse_overrides(set_))
    check_operating_point(train, operating_point)
    from ..analyses import campbell as run_campbell

    lo, hi = sweep_range(train, min_speed, max_speed, 0.0, 1.25 * abs(train.speed) / RPM)
    speeds = speed_grid(lo, hi, n_speeds, "--min-speed/--max-speed")
    fmax = (max_frequency if max_frequency is not None else 3 * hi) * RPM
    extra = parse_orders(orders)
    with (
        option_fields(max_frequency="--max-frequency"),
        sweep_at_operating_point(train, operating_point),
    ):
        res = run_campbell(
            train,
            speeds=speeds,
            max_frequency=fmax,
            extra_orders=extra,
            operating_point=operating_point,
            progress=current(),
        )
    if format == "json":
        typer.echo(json.dumps(res.to_dict(), indent=1))
    else:
        typer.echo(
            f"{train.name}: Campbell {lo:.0f}..{hi:.0f} rpm, "
            f"{res.damped_frequency.shape[1]} modes tracked; crossings:"
        )
        typer.echo(res.table())
    if plot is not None:
        from ..model.speed_range import model_operating_range
        from ..plots import plot_campbell

        plot_campbell(
            res,
            path=plot,
            max_frequency=fmax,
            operating_speed=abs(train.speed),
            max_continuous_speed=train.max_continuous_speed,
            operating_range=model_operating_range(train),
        )
        typer.echo(f"plot written to {plot}", err=format == "json")
