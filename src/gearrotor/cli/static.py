"""``gearrotor static``: static deflection, bearing loads and tooth forces at operating points
(:func:`gearrotor.analyses.static.static`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output, make_directory, output_set, unique_names, write_text
from ..progress import steps
from .errors import cli_errors
from .options import (
    RPM,
    FormatOpt,
    OperatingPointOpt,
    SetOpt,
    check_format,
    check_operating_point,
    rpm,
)
from .progress import current

__all__ = ["static_command"]


@cli_errors()
def static_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    operating_point: OperatingPointOpt = None,
    all_: Annotated[
        bool, typer.Option("--all", help="every operating point of the model, in order")
    ] = False,
    speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(),
            help="reference shaft speed, rpm, instead of the point's (its 'hold' kept)",
        ),
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None,
        typer.Option(help="write the deflected shapes and the bearing-load polar plot here"),
    ] = None,
    set_: SetOpt = None,
) -> None:
    """Static operating point: bearing loads (and fluid-film journal equilibria), tooth forces,
    misalignment, shaft deflection, bending moment, torque and stress. Without an operating
    point: the weight alone at the model's speed."""
    from ..io import load_model, parse_overrides

    check_format(format)
    train = load_model(model, parse_overrides(set_))
    if all_ and operating_point is not None:
        raise ModelError(
            "give --operating-point or --all, not both",
            field="--all",
            expected="one operating point, or all of them",
        )
    check_operating_point(train, operating_point)
    from ..analyses.static import static

    if all_ and not train.operating_points:
        raise ModelError(
            "the model has no operating points",
            field="--all",
            expected="[[operating_points]] entries in the model",
        )
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    names = [p.name for p in train.operating_points] if all_ else [operating_point]
    w = None if speed is None else speed * RPM
    from ..assembly import assemble

    asm = assemble(train)
    results = [
        static(asm, n, speed=w)
        for n in steps(current(), names, lambda i, k, name: f"operating point {name} ({i}/{k})")
    ]
    if format == "json":
        out = (
            results[0].to_dict()
            if not all_
            else {"operating_points": [r.to_dict() for r in results]}
        )
        typer.echo(json.dumps(out, indent=1))
    else:
        typer.echo(f"{train.name}: static operating point{'s' if all_ else ''}")
        typer.echo("\n\n".join(r.table() for r in results))
    if plot is not None:
        from ..plots.static import plot_bearing_loads, plot_static_shafts

        # one file per point; distinct names stay distinct ("a/b", "a_b": static_a_b.png and
        # static_a_b-2.png; static.json says which is which)
        stems = unique_names([r.operating_point for r in results])
        with output_set():  # the figures and static.json appear together or not at all
            make_directory(plot, field="--plot")
            points = []
            for r, stem in zip(results, stems, strict=True):
                plot_static_shafts(r, path=plot / f"static_{stem}.png")
                points.append({**r.to_dict(), "figure": f"static_{stem}.png"})
            plot_bearing_loads(results, path=plot / "bearing_loads.png")
            write_text(plot / "static.json", json.dumps({"operating_points": points}, indent=1))
        typer.echo(f"plots written to {plot}/", err=format == "json")
