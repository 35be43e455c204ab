"""``gearrotor modal``: damped modes at a speed (:func:`gearrotor.analyses.modal`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..files import check_output, make_directory, output_set, write_json
from .errors import cli_errors
from .options import (
    RPM,
    FormatOpt,
    OperatingPointOpt,
    SetOpt,
    check_format,
    check_operating_point,
    choice,
    count,
    rpm,
)

__all__ = ["modal_command"]


@cli_errors()
def modal_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    speed: Annotated[
        float | None,
        typer.Option(parser=rpm(), help="reference shaft speed, rpm (default: the model's)"),
    ] = None,
    max_frequency: Annotated[
        float | None, typer.Option(parser=rpm(0, strict=True), help="highest damped frequency, rpm")
    ] = None,
    n_modes: Annotated[
        int | None, typer.Option(parser=count(1), help="at most this many modes")
    ] = None,
    method: Annotated[
        str, typer.Option(parser=choice("auto", "dense", "sparse"), help="auto, dense or sparse")
    ] = "auto",
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None, typer.Option(help="write mode-shape plots to this directory")
    ] = None,
    shapes: Annotated[bool, typer.Option(help="include mode shapes in the JSON output")] = False,
    orbit: Annotated[
        bool,
        typer.Option(
            help="plot each shape's orbit size (semi-major axis, ≥ 0) instead of the signed "
            "real part"
        ),
    ] = False,
    operating_point: OperatingPointOpt = None,
    set_: SetOpt = None,
) -> None:
    """Damped eigenvalues at a speed: frequency, log dec, whirl per shaft, mode type."""
    from ..io import load_model, parse_overrides

    check_format(format)
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    train = load_model(model, parse_overrides(set_))
    check_operating_point(train, operating_point)
    from ..analyses import modal as run_modal

    res = run_modal(
        train,
        speed=None if speed is None else speed * RPM,
        max_frequency=None if max_frequency is None else max_frequency * RPM,
        n_modes=n_modes,
        method=method,
        operating_point=operating_point,
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
        from ..plots import plot_mode_shapes

        elastic = [i for i in range(len(res)) if not res.overdamped[i]]
        with output_set():  # the figures and modal.json appear together or not at all
            make_directory(plot, field="--plot")
            for k in range(0, min(len(elastic), 16), 8):
                path = plot / f"modes_{k // 8 + 1}.png"
                plot_mode_shapes(res, modes=elastic[k : k + 8], path=path, orbit=orbit)
            write_json(plot / "modal.json", res.to_dict())
        typer.echo(f"plots written to {plot}/", err=format == "json")
