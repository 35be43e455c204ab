"""``gearrotor report``: the HTML report of a model.

A thin layer over :func:`gearrotor.plots.report.make_report`: rpm at the boundary, rad/s inside.
Exit statuses are those of :mod:`.errors`: input errors print one line to stderr
and exit with status 2 (a missing optional dependency, plotly, matplotlib, xarray, too, naming
the extra to install); solver failures exit with status 3.
"""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from .errors import cli_errors
from .options import RPM, OperatingPointOpt, SetOpt, check_operating_point, rpm
from .progress import current

__all__ = ["report_command"]


@cli_errors()
def report_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    output: Annotated[
        Path,
        typer.Option(
            "--output", "-o", help="report directory (report.html, PNG figures, report.json)"
        ),
    ],
    analyses: Annotated[
        str,
        typer.Option(
            help="comma-separated: modal, campbell, unbalance, audit (the API 617 lateral audit: "
            "needs the model's operating range, MCS and [api_audit]), operating_points, "
            "torsional (the torsional audit; not by default), mesh_response (the periodic "
            "gear-mesh response over speed; not by default); transient: give --transient"
        ),
    ] = "modal,campbell,unbalance",
    speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(), help="operating speed of the reference shaft, rpm (default: the model's)"
        ),
    ] = None,
    max_frequency: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True),
            help="highest damped frequency of modes and Campbell, cpm (default: every mode an "
            "excitation can reach, 1.1 × 1.26 × the highest excitation at the top operating "
            "speed, at least 5 × that speed)",
        ),
    ] = None,
    api: Annotated[
        bool,
        typer.Option(
            help="unbalance section with the API 617 unbalance instead of the model's amounts: "
            "8th edition 4 × 6350 W/N g·mm per plane at the MCS; 9th edition 2 × 6350 W/N g·mm "
            "at the antinodes of the first forward mode, with the close-clearance check"
        ),
    ] = False,
    edition: Annotated[
        str | None,
        typer.Option(
            help="API 617 edition of --api and the audit section: 8th (2014) or 9th (2022); "
            "default: the model's [api_audit] edition, else 8th"
        ),
    ] = None,
    transient: Annotated[
        Path | None,
        typer.Option(help="saved transient result (NetCDF) to add spectra, waterfall, whirl power"),
    ] = None,
    operating_point: OperatingPointOpt = None,
    all_operating_points: Annotated[
        bool,
        typer.Option(
            help="add the operating-points section: every operating point's bearing loads, "
            "eccentricity locus and least-stable log dec against power"
        ),
    ] = False,
    set_: SetOpt = None,
) -> None:
    """Self-contained HTML report: modes (3-D), stability, Campbell, Bode, orbits, API 684 checks,
    and a saved transient result's spectra, waterfall and whirl power; plus PNG figures."""
    from ..io import load_model, parse_overrides

    train = load_model(model, parse_overrides(set_))
    check_operating_point(train, operating_point)
    from ..plots.report import make_report

    if all_operating_points and not train.operating_points:
        raise ModelError(
            "the model has no operating points",
            field="--all-operating-points",
            expected="[[operating_points]] entries in the model",
        )
    rep = make_report(
        train,
        output,
        analyses=analyses,
        speed=None if speed is None else speed * RPM,
        max_frequency=None if max_frequency is None else max_frequency * RPM,
        transient=transient,
        api=api,
        edition=edition,
        source=str(model),
        command=shlex.join(["gearrotor", *sys.argv[1:]]) if sys.argv else None,
        operating_point=operating_point,
        operating_points=[p.name for p in train.operating_points] if all_operating_points else None,
        progress=current(),
    )
    typer.echo(f"report written to {rep.html}")
    for v in rep.summary.get("verdicts", []):
        typer.echo(f"  {v['result']}  {v['check']}: {v['detail']}")
