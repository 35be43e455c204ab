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
from ..files import check_output, make_directory, output_set
from .errors import cli_errors
from .options import (
    FormatOpt,
    OperatingPointOpt,
    SetOpt,
    check_format,
    check_operating_point,
    choice,
    duration,
)

__all__ = ["transient_command", "plot_command"]


def transient_command(
    model: Annotated[Path, typer.Argument(help="model file (TOML)")],
    t_end: Annotated[
        float, typer.Option("--t-end", parser=duration(), help="end time, s (optional)")
    ] = 1.0,
    dt: Annotated[
        float | None,
        typer.Option(
            "--dt",
            parser=duration(),
            help="time step, s (default: rk4 0.95× its stability limit; modal: automatic)",
        ),
    ] = None,
    method: Annotated[
        str,
        typer.Option(
            "--method", parser=choice("modal", "rk4"), help="'modal' (fast) or 'rk4' (reference)"
        ),
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
        str | None,
        typer.Option(
            "--initial",
            parser=choice("zero", "static", "rest"),
            help="'zero', 'static' (deflection under the torques) or 'rest' (standstill: a "
            "start-up by the model's torsional drives); default 'zero', or 'static' with "
            "--operating-point",
        ),
    ] = None,
    checkpoint: Annotated[
        Path | None,
        typer.Option(
            "--checkpoint",
            help="checkpoint file: the state is saved there during the run (see "
            "--checkpoint-every), the run resumes from it if present; removed at the end",
        ),
    ] = None,
    checkpoint_every: Annotated[
        float | None,
        typer.Option(
            "--checkpoint-every",
            parser=duration(),
            help="simulated seconds between checkpoints (default: 5 % of --t-end)",
        ),
    ] = None,
    checkpoint_wall: Annotated[
        float,
        typer.Option(
            "--checkpoint-wall",
            parser=duration(),
            help="and at the latest every this many seconds of wall time",
        ),
    ] = 60.0,
    operating_point: OperatingPointOpt = None,
) -> None:
    """Nonlinear transient (time-varying mesh, backlash, free speed) of a train."""

    def kept() -> str | None:  # what Ctrl-C leaves: the checkpoint to resume from, if any
        if checkpoint is not None and checkpoint.exists():
            return f"the state is saved in {checkpoint}; run the same command again to resume"
        return None

    with cli_errors(interrupted=kept):
        check_format(format)
        ck = _checkpoint(checkpoint, checkpoint_every, checkpoint_wall)
        for path, kind, field in (
            (output, "file", "--output"),
            (plot, "directory", "--plot"),
            (checkpoint, "file", "--checkpoint"),
        ):
            if path is not None:  # also removes what a killed run left being written there
                check_output(path, kind, field=field)
        from ..io import load_model, parse_overrides

        train = load_model(model, parse_overrides(set_))
        check_operating_point(train, operating_point)
        from ..analyses.transient import (
            RK4,
            ModalRK4,
            build_system,
            rk4_max_step,
            transient,
            transient_at_operating_point,
        )
        from ..analyses.transient.plots import standard_figures

        if method == "rk4":
            if dt is None:
                if operating_point is None:
                    system = build_system(train)
                else:
                    run, extra = transient_at_operating_point(train, operating_point)
                    extra.pop("name")
                    system = build_system(run, **extra)
                dt = 0.95 * rk4_max_step(system)
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
            checkpoint=ck,
            operating_point=operating_point,
        )
        with output_set():  # the result file and the figures appear together or not at all
            if output is not None:
                res.save(output)
            if plot is not None:
                make_directory(plot, field="--plot")
                standard_figures(res, plot)
    if format == "json":
        typer.echo(json.dumps(res.summary(), default=_jsonable))
    else:
        typer.echo(res.table())
    sys.stdout.flush()


def _checkpoint(path: Path | None, every: float | None, wall: float):
    """The :class:`Checkpoint` of the options, checked."""
    if path is None:
        if every is not None:
            raise ModelError(
                "--checkpoint-every needs a checkpoint file",
                field="--checkpoint-every",
                value=every,
                expected="--checkpoint FILE as well",
            )
        return None
    from ..analyses.transient import Checkpoint  # the transient package: only when used

    if every is not None and not (np.isfinite(every) and every > 0):
        raise ModelError(
            "the checkpoint interval must be positive",
            field="--checkpoint-every",
            value=every,
            expected="simulated seconds > 0",
        )
    if not (np.isfinite(wall) and wall >= 0):
        raise ModelError(
            "the checkpoint wall-time interval must be finite and >= 0",
            field="--checkpoint-wall",
            value=wall,
            expected="seconds >= 0",
        )
    return Checkpoint(path, every=wall, simulated=every)


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

    out = output if output is not None else file.with_name(file.stem + "_plots")
    check_output(out, "directory", field="--output")
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
    typer.echo(f"writing the standard figures of {file} to {out}/ ...", err=True)
    with output_set():  # the figures appear together or not at all
        make_directory(out, field="--output")
        paths = standard_figures(ds, out, prefix=file.stem)
    for p in paths:
        typer.echo(str(p))
