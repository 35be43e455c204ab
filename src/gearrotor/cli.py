"""Command-line interface: a thin layer over the functions a Python user calls.

Every command maps errors to exit statuses through :func:`gearrotor.cli_errors.cli_errors`:
input errors print one clear message (file, field, value, expectation) and exit with status 2,
without a traceback; solver failures exit with status 3 (see :mod:`gearrotor.cli_errors`).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from .cli_errors import EXIT_CODES_HELP, cli_errors
from .cli_options import RPM, FormatOpt, SetOpt, check_format
from .errors import ModelError
from .floquet_cli import floquet_command
from .io import load_model, parse_overrides
from .report_cli import report_command
from .studies.cli import study_app
from .transient_cli import plot_command, transient_command

__all__ = ["app", "main"]

app = typer.Typer(
    name="gearrotor",
    help="Dynamics of geared rotor-bearing trains: modal, Campbell, unbalance response.",
    epilog=EXIT_CODES_HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _speeds(lo: float, hi: float, n: int, field: str) -> np.ndarray:
    if n < 2 or hi <= lo:
        raise ModelError(
            "invalid speed range",
            field=field,
            value=f"{lo}..{hi} rpm, {n} points",
            expected="max > min and at least 2 points",
        )
    return np.linspace(lo, hi, n) * RPM


@app.command(epilog=EXIT_CODES_HELP)
@cli_errors()
def modal(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    speed: Annotated[
        float | None, typer.Option(help="reference shaft speed, rpm (default: the model's)")
    ] = None,
    max_frequency: Annotated[
        float | None, typer.Option(help="highest damped frequency, rpm")
    ] = None,
    n_modes: Annotated[int | None, typer.Option(help="at most this many modes")] = None,
    method: Annotated[str, typer.Option(help="auto, dense or sparse")] = "auto",
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None, typer.Option(help="write mode-shape plots to this directory")
    ] = None,
    shapes: Annotated[bool, typer.Option(help="include mode shapes in the JSON output")] = False,
    set_: SetOpt = None,
) -> None:
    """Damped eigenvalues at a speed: frequency, log dec, whirl per shaft, mode type."""
    from .analyses import modal as run_modal

    check_format(format)
    train = load_model(model, parse_overrides(set_))
    res = run_modal(
        train,
        speed=None if speed is None else speed * RPM,
        max_frequency=None if max_frequency is None else max_frequency * RPM,
        n_modes=n_modes,
        method=method,
    )
    if format == "json":
        typer.echo(json.dumps(res.to_dict(shapes=shapes), indent=1))
    else:
        typer.echo(
            f"{train.name}: damped modes at {res.speed / RPM:.1f} rpm "
            f"({res.assembly.n_dof} DOF, {res.method} eigensolver)"
        )
        typer.echo(res.table())
    if plot is not None:
        from .plots import plot_mode_shapes

        plot.mkdir(parents=True, exist_ok=True)
        elastic = [i for i in range(len(res)) if not res.overdamped[i]]
        for k in range(0, min(len(elastic), 16), 8):
            plot_mode_shapes(res, modes=elastic[k : k + 8], path=plot / f"modes_{k // 8 + 1}.png")
        (plot / "modal.json").write_text(json.dumps(res.to_dict(), indent=1))
        typer.echo(f"plots written to {plot}/", err=format == "json")


@app.command(epilog=EXIT_CODES_HELP)
@cli_errors()
def campbell(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    min_speed: Annotated[float, typer.Option(help="rpm")] = 0.0,
    max_speed: Annotated[float | None, typer.Option(help="rpm (default 1.25 × nominal)")] = None,
    n_speeds: Annotated[int, typer.Option(help="number of speeds")] = 60,
    max_frequency: Annotated[float | None, typer.Option(help="rpm (default 3 × max speed)")] = None,
    orders: Annotated[
        str | None,
        typer.Option(help="extra excitation orders of the reference shaft, e.g. '10,42'"),
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[Path | None, typer.Option(help="write the Campbell diagram PNG")] = None,
    set_: SetOpt = None,
) -> None:
    """Campbell diagram with MAC mode tracking, excitation orders and crossing speeds."""
    from .analyses import campbell as run_campbell

    check_format(format)
    train = load_model(model, parse_overrides(set_))
    hi = max_speed if max_speed is not None else 1.25 * abs(train.speed) / RPM
    speeds = _speeds(min_speed, hi, n_speeds, "--min-speed/--max-speed")
    fmax = (max_frequency if max_frequency is not None else 3 * hi) * RPM
    extra = ()
    if orders:
        try:
            extra = tuple(float(x) for x in orders.split(","))
        except ValueError:
            raise ModelError(
                "cannot read the orders",
                field="--orders",
                value=orders,
                expected="comma-separated numbers, e.g. '10,42'",
            ) from None
    res = run_campbell(train, speeds=speeds, max_frequency=fmax, extra_orders=extra)
    if format == "json":
        typer.echo(json.dumps(res.to_dict(), indent=1))
    else:
        typer.echo(
            f"{train.name}: Campbell {min_speed:.0f}..{hi:.0f} rpm, "
            f"{res.damped_frequency.shape[1]} modes tracked; crossings:"
        )
        typer.echo(res.table())
    if plot is not None:
        from .plots import plot_campbell

        plot_campbell(res, path=plot, max_frequency=fmax)
        typer.echo(f"plot written to {plot}", err=format == "json")


@app.command(epilog=EXIT_CODES_HELP)
@cli_errors()
def unbalance(
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
    from .analyses import unbalance_response
    from .analyses.api617 import api617_unbalances
    from .assembly import assemble

    check_format(format)
    train = load_model(model, parse_overrides(set_))
    hi = max_speed if max_speed is not None else 1.5 * abs(train.speed) / RPM
    speeds = _speeds(min_speed, hi, n_speeds, "--min-speed/--max-speed")
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
        from .plots import plot_bode, plot_orbits

        plot.mkdir(parents=True, exist_ok=True)
        plot_bode(res, path=plot / "bode.png")
        k = int(np.argmin(np.abs(res.speeds - res.operating_range[1])))
        plot_orbits(res, k, path=plot / "orbits_operating.png")
        typer.echo(f"plots written to {plot}/", err=format == "json")


@app.command(epilog=EXIT_CODES_HELP)
@cli_errors()
def bearing(
    path: Annotated[Path, typer.Argument(help="bearing TOML file")],
    load: Annotated[
        str | None, typer.Option(help="FX,FY in N (default: the file's load cases)")
    ] = None,
    speed: Annotated[
        str | None, typer.Option(help="journal speed, rpm or with units (default: the file's)")
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None,
        typer.Option(
            help="write pressure maps, eccentricity locus and coefficient plots to this directory"
        ),
    ] = None,
) -> None:
    """Fluid-film journal bearing: static equilibrium and the 8 dynamic coefficients."""
    from .bearings.cli import bearing_command

    bearing_command(path, load=load, speed=speed, fmt=format, plot=plot)


app.command("transient", epilog=EXIT_CODES_HELP)(transient_command)
app.command("transient-plot", epilog=EXIT_CODES_HELP)(plot_command)
app.command("report", epilog=EXIT_CODES_HELP)(report_command)
app.command("floquet", epilog=EXIT_CODES_HELP)(floquet_command)
app.add_typer(study_app, name="study")


def main() -> None:
    """Entry point of the ``gearrotor`` command."""
    app(prog_name="gearrotor")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
