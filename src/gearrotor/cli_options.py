"""Options and unit constants shared by every ``gearrotor`` command module (``cli``,
``transient_cli``, ``report_cli``, ``floquet_cli``)."""

from __future__ import annotations

from typing import Annotated

import numpy as np
import typer

from .errors import ModelError

__all__ = ["RPM", "FormatOpt", "SetOpt", "check_format"]

RPM = np.pi / 30  # rpm -> rad/s

SetOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        help="Override a model value: PATH=VALUE, e.g. 'meshes[0].stiffness=3e7 N/m' (repeatable).",
    ),
]
FormatOpt = Annotated[str, typer.Option("--format", help="table or json")]


def check_format(fmt: str) -> None:
    """``--format`` must be ``table`` or ``json``."""
    if fmt not in ("table", "json"):
        raise ModelError(
            "unknown output format", field="--format", value=fmt, expected="'table' or 'json'"
        )
