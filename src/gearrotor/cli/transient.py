"""``gearrotor transient`` and ``gearrotor transient-plot``: the nonlinear transient
(:func:`gearrotor.analyses.transient.transient`) and the standard figures of a saved result.

Exit statuses are those of :mod:`.errors`: 2 invalid input, 3 solver failure (a diverging run,
a step above the stability limit).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import ModelError
from .errors import cli_errors
from .options import FormatOpt, SetOpt, check_format

__all__ = ["transient_command", "plot_command"]


def transient_command(
    model: Annotated[Path, typer.Argument(help="model file (TOML)")],
    t_end: Annotated[float, typer.Option("--t-end", help="end time, s (optional)")] = 1.0,
    dt: Annotated[
        float | None,
        typer.Option(
            "--dt", help="time step, s (default: rk4 0.95× its stability limit; modal: automatic)"
        ),
    ] = None,
    method: Annotated[
        str, typer.Option("--method", help="'modal' (fast) or 'rk4' (reference)")
    ] = "modal",
    set_: SetOpt = None,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="write the result (NetCDF)")
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[Path | None, typer.Option("--plot", help="directory for PNG figures")] = None,
    reactions: Annotated[
        bool,
        typer.Option(
            help="reaction torques of the θ̈ terms (Lagrangian form); --no-reactions: dissertation"
        ),
    ] = True,
    progress: Annotated[bool, typer.Option(help="progress on stderr")] = True,
    initial: Annotated[
        str, typer.Option("--initial", help="'zero' or 'static' (deflection under the torques)")
    ] = "zero",
    checkpoint: Annotated[
        Path | None,
        typer.Option(
            "--checkpoint", help="checkpoint file: written every minute, resumed from if present"
        ),
    ] = None,
) -> None:
    """Nonlinear transient (time-varying mesh, backlash, free speed) of a train."""
    from ..analyses.transient import (
        RK4,
        Checkpoint,
        ModalRK4,
        build_system,
        rk4_max_step,
        transient,
    )
    from ..analyses.transient.plots import standard_figures

    with cli_errors():
        check_format(format)
        from ..io import load_model, parse_overrides

        train = load_model(model, parse_overrides(set_))
        if method == "rk4":
            if dt is None:
                dt = 0.95 * rk4_max_step(build_system(train))
                unit = 10.0 ** (np.floor(np.log10(dt)) - 1)
                dt = float(f"{np.floor(dt / unit) * unit:.2g}")  # 2 digits, rounded down
            integ = RK4(dt=dt)
        elif method == "modal":
            integ = ModalRK4(dt=dt)
        else:
            raise ModelError(
                "unknown method", field="--method", value=method, expected="'modal' or 'rk4'"
            )
        if dt is not None and not dt > 0:
            raise ModelError("the time step must be positive", field="--dt", value=dt)
        res = transient(
            train,
            t_end=t_end,
            integrator=integ,
            reactions=reactions,
            progress=progress,
            initial=initial,
            checkpoint=Checkpoint(checkpoint) if checkpoint is not None else None,
        )
        if output is not None:
            res.save(output)
        if plot is not None:
            standard_figures(res, plot)
    if format == "json":
        typer.echo(json.dumps(res.summary(), default=_jsonable))
    else:
        typer.echo(res.table())
    sys.stdout.flush()


def _jsonable(x):
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(type(x))


@cli_errors()
def plot_command(
    file: Annotated[Path, typer.Argument(help="a transient result (NetCDF)")],
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="directory for the PNGs (default: next to the file)"),
    ] = None,
) -> None:
    """Standard figures of a saved transient result."""
    from ..analyses.transient import load_result
    from ..analyses.transient.plots import standard_figures

    try:
        ds = load_result(file)
    except ModelError:
        raise
    except (OSError, ValueError) as exc:
        raise ModelError(
            f"cannot read the result file: {exc}",
            file=str(file),
            expected="a NetCDF file written by 'gearrotor transient --output'",
        ) from None
    out = output if output is not None else file.with_name(file.stem + "_plots")
    typer.echo(f"writing the standard figures of {file} to {out}/ ...", err=True)
    standard_figures(ds, out, prefix=file.stem, progress=lambda p: typer.echo(str(p)))
