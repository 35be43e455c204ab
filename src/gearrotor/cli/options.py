"""Options, unit constants and small parsers shared by the ``gearrotor`` command modules."""

from __future__ import annotations

import os
from pathlib import Path
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
    "McsOpt",
    "OperatingRangeOpt",
    "check_png",
    "operating_range_from_options",
    "parse_range",
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


OperatingRangeOpt = Annotated[
    str | None,
    typer.Option(
        "--operating-range",
        help="MIN,MAX operating speeds of the reference shaft, rpm (overrides the model's "
        "operating_speed_range)",
    ),
]
McsOpt = Annotated[
    float | None,
    typer.Option(
        "--mcs",
        help="maximum continuous speed of the reference shaft, rpm (overrides the model's "
        "max_continuous_speed)",
    ),
]


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


def parse_range(text: str, field: str = "--operating-range") -> tuple[float, float]:
    """``"MIN,MAX"`` in rpm -> (min, max) in rad/s, with 0 < min <= max."""
    try:
        lo, hi = (float(x) for x in text.split(","))
    except ValueError:
        raise ModelError(
            "cannot read the speed range", field=field, value=text, expected="MIN,MAX in rpm"
        ) from None
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo <= hi):
        raise ModelError(
            "invalid speed range", field=field, value=text, expected="0 < MIN <= MAX rpm"
        )
    return lo * RPM, hi * RPM


def operating_range_from_options(train, operating_range: str | None, mcs: float | None):
    """The train with ``--operating-range`` / ``--mcs`` (rpm) in place of the model's
    ``operating_speed_range`` / ``max_continuous_speed`` (unchanged without them); the
    combination is checked as the model file's is (maximum operating speed <= MCS)."""
    if operating_range is None and mcs is None:
        return train
    update = {}
    if operating_range is not None:
        update["operating_speed_range"] = parse_range(operating_range)
    if mcs is not None:
        if not (np.isfinite(mcs) and mcs > 0):
            raise ModelError(
                "the maximum continuous speed must be positive",
                field="--mcs",
                value=mcs,
                expected="a speed > 0 rpm",
            )
        update["max_continuous_speed"] = mcs * RPM
    op = update.get("operating_speed_range", train.operating_speed_range)
    top = update.get("max_continuous_speed", train.max_continuous_speed)
    if op is not None and top is not None and op[1] > top * (1 + 1e-9):
        field = "--operating-range" if operating_range is not None else "--mcs"
        raise ModelError(
            "the maximum operating speed exceeds the maximum continuous speed",
            field=field,
            value=f"{op[1] / RPM:.6g} rpm > MCS {top / RPM:.6g} rpm",
            expected="MAX of the operating range <= the maximum continuous speed",
        )
    return train.model_copy(update=update)


def check_png(path: Path | None, field: str = "--plot") -> None:
    """An output PNG path that can be written (checked before anything runs)."""
    if path is None:
        return
    if path.suffix.lower() != ".png":
        raise ModelError(
            "the figure is written as PNG", field=field, value=str(path), expected="a .png file"
        )
    if path.is_dir():
        raise ModelError(
            "the figure path is a directory", field=field, value=str(path), expected="a file"
        )
    parent = path.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise ModelError(
            "cannot write the figure here",
            field=field,
            value=str(path),
            expected=f"a path in a writable directory ({parent} is not)",
        )
