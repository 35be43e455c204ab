"""Options, unit constants and small parsers shared by the ``gearrotor`` command modules."""

from __future__ import annotations

from typing import Annotated

import numpy as np
import typer

from ..errors import ModelError

__all__ = [
    "RPM",
    "FormatOpt",
    "OperatingPointOpt",
    "SetOpt",
    "check_format",
    "check_operating_point",
    "speed_grid",
]

RPM = np.pi / 30  # rpm -> rad/s

SetOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        help="Override a model value: PATH=VALUE, e.g. 'meshes[0].stiffness=3e7 N/m' (repeatable).",
    ),
]
FormatOpt = Annotated[str, typer.Option("--format", help="table or json")]
OperatingPointOpt = Annotated[
    str | None,
    typer.Option(
        "--operating-point",
        help="run at this operating point of the model ([[operating_points]] name): fluid-film "
        "bearings at the coefficients of its static loads, meshes on the loaded flank",
    ),
]


def check_operating_point(train, name: str | None) -> None:
    """``--operating-point`` must name one of the model's operating points."""
    if name is None:
        return
    try:
        train.operating_point(name)
    except ModelError as exc:
        raise ModelError(
            exc.message, field="--operating-point", value=name, expected=exc.expected
        ) from None


def check_format(fmt: str) -> None:
    """``--format`` must be ``table`` or ``json``."""
    if fmt not in ("table", "json"):
        raise ModelError(
            "unknown output format", field="--format", value=fmt, expected="'table' or 'json'"
        )


def speed_grid(lo: float, hi: float, n: int, field: str) -> np.ndarray:
    """``n`` evenly spaced speeds from ``lo`` to ``hi`` rpm, in rad/s (a speed sweep option)."""
    if n < 2 or hi <= lo:
        raise ModelError(
            "invalid speed range",
            field=field,
            value=f"{lo}..{hi} rpm, {n} points",
            expected="max > min and at least 2 points",
        )
    return np.linspace(lo, hi, n) * RPM
