"""``gearrotor show``: the model before any analysis — its drawing and its summary
(:func:`gearrotor.analyses.model_summary.summarize`, :func:`gearrotor.plots.model_view`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output, write_text
from .errors import cli_errors
from .options import RPM, FormatOpt, SetOpt, check_format, rpm

__all__ = ["show_command"]

_PLOT_SUFFIXES = (".png", ".svg", ".html")


@cli_errors()
def show_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    plot: Annotated[
        Path | None,
        typer.Option(
            help="write the drawing: FILE.png or FILE.svg (side view of every shaft to scale "
            "and the end view), or FILE.html (interactive 3-D with node and element tooltips)"
        ),
    ] = None,
    format: FormatOpt = "table",
    max_frequency: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True),
            help="frequency range the element fineness refers to, cpm (default: the report's "
            "range: the highest excitation, 1x, 2x or mesh frequency, at the highest speed the "
            "model names, + 26 percent separation margin, x 1.1 headroom, at least 5 x that speed)",
        ),
    ] = None,
    convergence: Annotated[
        bool,
        typer.Option(
            help="also compare the damped modes below --max-frequency with those of the model "
            "with every element halved (two modal solves)"
        ),
    ] = False,
    set_: SetOpt = None,
) -> None:
    """The model before any analysis: per shaft mass, inertias, length, elements, DOFs, bearing
    span and the fineness of its coarsest element (with a warning where the mesh is too coarse
    for the frequency range), gear ratios and operating points; --plot draws it."""
    from ..io import load_model, parse_overrides

    check_format(format)
    if plot is not None:
        if plot.suffix.lower() not in _PLOT_SUFFIXES:
            raise ModelError(
                "unknown drawing format",
                field="--plot",
                value=str(plot),
                expected="a file ending in .png, .svg or .html",
            )
        check_output(plot, "file", field="--plot", parents=True)
    train = load_model(model, parse_overrides(set_))
    from ..analyses.model_summary import summarize

    res = summarize(
        train,
        max_frequency=None if max_frequency is None else max_frequency * RPM,
        convergence=convergence,
    )
    if format == "json":
        typer.echo(json.dumps(res.to_dict(), indent=1))
    else:
        typer.echo(f"{train.name}")
        typer.echo(res.table())
    if plot is not None:
        if plot.suffix.lower() == ".html":
            from ..plots.model_view import model_figure_3d

            fig = model_figure_3d(train)
            write_text(plot, fig.to_html(include_plotlyjs=True, full_html=True))
        else:
            from ..plots.model_view import plot_model

            plot.parent.mkdir(parents=True, exist_ok=True)
            plot_model(train, plot)
        typer.echo(f"drawing written to {plot}", err=format == "json")
