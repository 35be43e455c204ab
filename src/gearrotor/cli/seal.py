"""``gearrotor seal SEAL.toml --speed RPM [--frequency HZ] [--format table|json] [--plot DIR]``:
leakage and the 8 rotordynamic coefficients of a seal file
(:func:`gearrotor.seals.seal_coefficients`)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..files import check_output, write_json
from .errors import cli_errors
from .options import RPM, FormatOpt, check_format, number, rpm

__all__ = ["seal_command"]


@cli_errors()
def seal_command(
    path: Annotated[Path, typer.Argument(help="seal TOML file (docs/seals.md)")],
    speed: Annotated[
        float, typer.Option(parser=rpm(0), help="rotor speed, rpm or with units (e.g. '8000 rpm')")
    ],
    frequency: Annotated[
        float | None,
        typer.Option(parser=number(0), help="whirl frequency, Hz (default: synchronous, speed/60)"),
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None,
        typer.Option(
            help="write the pressure and swirl distribution and the coefficients against speed "
            "and whirl frequency (PNG) and seal.json to this directory"
        ),
    ] = None,
) -> None:
    """Annular seal from geometry (labyrinth, liquid annular, hole-pattern, honeycomb): leakage,
    cavity pressures and swirl, and the 8 stiffness and damping coefficients at a speed and
    whirl frequency."""
    from ..seals import load_seal, seal_coefficients

    check_format(format)
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    seal = load_seal(path)
    w = speed * RPM
    whirl = None if frequency is None else 2 * math.pi * frequency
    res = seal_coefficients(seal, w, whirl)
    doc = {"file": str(path), **res.to_dict()}
    if format == "json":
        typer.echo(json.dumps(doc, indent=1))
    else:
        typer.echo(res.table())
    if plot is not None:
        _plots(seal, res, plot)
        write_json(plot / "seal.json", doc)
        typer.echo(f"plots written to {plot}/", err=format == "json")


def _plots(seal, res, outdir: Path) -> None:
    import numpy as np

    from ..seals import seal_coefficients
    from ..seals.plots import plot_coefficients, plot_distribution

    outdir.mkdir(parents=True, exist_ok=True)
    plot_distribution(res, outdir / "distribution.png")
    top = max(res.speed, 100 * RPM)
    speeds = np.linspace(0.1, 1.5, 15) * top
    by_speed = [seal_coefficients(seal, s) for s in speeds]
    plot_coefficients(
        by_speed,
        speeds / RPM,
        "rotor speed (rpm), synchronous whirl",
        outdir / "coefficients_vs_speed.png",
        title=f"{seal.name}: synchronous coefficients",
    )
    ref = max(res.speed, 100 * RPM)
    whirls = np.linspace(0.1, 2.0, 20) * ref
    by_whirl = [seal_coefficients(seal, res.speed, om) for om in whirls]
    plot_coefficients(
        by_whirl,
        whirls / (2 * math.pi),
        f"whirl frequency (Hz) at {res.speed / RPM:.0f} rpm",
        outdir / "coefficients_vs_frequency.png",
        title=f"{seal.name}: coefficients against whirl frequency",
    )
