"""Options, unit constants and small parsers shared by the ``gearrotor`` command modules.

The parsers check an option's value when the command line is read, before anything runs
(finite, in range, a known choice); a bad value is one line naming the option and the value
(``error: --speed: ...``, exit status 2). Speeds accept units: ``6500`` (rpm), ``6500rpm``,
``"680 rad/s"``, ``"108 Hz"``.
"""

from __future__ import annotations

import functools
import inspect
import math
from collections.abc import Callable
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import ModelError
from ..files import check_output

__all__ = [
    "RPM",
    "FormatOpt",
    "OperatingPointOpt",
    "SetOpt",
    "ThreadsOpt",
    "common_options",
    "check_format",
    "check_operating_point",
    "McsOpt",
    "OperatingRangeOpt",
    "check_png",
    "operating_range_from_options",
    "parse_range",
    "MAX_SPEEDS",
    "choice",
    "count",
    "duration",
    "number",
    "rpm",
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


def _threads(text: str) -> str:
    """``--threads``: ``auto`` or a positive integer (checked when the command line is read)."""
    from ..threads import parse_setting

    try:
        return str(parse_setting(text, "--threads"))
    except ModelError:
        raise _bad(text, "invalid number of threads", "'auto' or an integer >= 1") from None


ThreadsOpt = Annotated[
    str | None,
    typer.Option(
        "--threads",
        parser=_threads,
        metavar="N|auto",
        help="BLAS/LAPACK threads: 'auto' (one, more only for large dense solves on free "
        "cores) or N; default: the GEARROTOR_THREADS environment variable, else auto",
    ),
]


def common_options(fn: Callable) -> Callable:
    """Give a command function the options every command has (``--threads``), keeping the
    parameters Typer reads: the command then runs in a :func:`gearrotor.threads.scope` with
    that setting (a bad ``GEARROTOR_THREADS`` is an input error, before anything runs)."""
    from .errors import cli_errors

    sig = inspect.signature(fn, eval_str=True)
    if "threads" in sig.parameters:
        return fn
    extra = inspect.Parameter(
        "threads", inspect.Parameter.KEYWORD_ONLY, default=None, annotation=ThreadsOpt
    )

    @functools.wraps(fn)
    def command(*args, threads: str | None = None, **kwargs):
        from .. import threads as threads_

        with threads_.using(threads):
            with cli_errors():
                threads_.setting()  # GEARROTOR_THREADS is read (and checked) before anything runs
            with threads_.scope():
                return fn(*args, **kwargs)

    params = list(sig.parameters.values())
    command.__signature__ = sig.replace(parameters=[*params, extra])
    command.__annotations__ = {**fn.__annotations__, "threads": ThreadsOpt}
    return command


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
        parser=lambda text: rpm(0, strict=True)(text),  # rpm() is defined below
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
    if n < 2 or not hi > lo or not (math.isfinite(lo) and math.isfinite(hi)):
        raise ModelError(
            "invalid speed range",
            field=field,
            value=f"{lo}..{hi} rpm, {n} points",
            expected="max > min and at least 2 points",
        )
    return np.linspace(lo, hi, n) * RPM


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
    """A PNG output path in an existing, writable folder (checked before anything runs)."""

    if path is None:
        return
    if path.suffix.lower() != ".png":
        raise ModelError(
            "the figure is written as PNG", field=field, value=str(path), expected="a .png file"
        )
    check_output(path, "file", field=field, parents=True)


#: Most speeds of a sweep (``--n-speeds``): each is an eigenvalue or a linear solve.
MAX_SPEEDS = 20_000


def _bad(text: str, what: str, expected: str):
    return typer.BadParameter(f"{what} (got {text!r}); expected {expected}")


def _number(text: str, kind: str, unit: str, factor: float) -> float:
    """A plain number (in ``unit``) or a value with units of ``kind``, in ``unit``; finite."""
    from ..units import KINDS, to_si

    example = KINDS[kind][2]
    text = str(text).strip()
    try:
        value = float(text)
    except ValueError:
        try:
            value = to_si(text, kind) / factor
        except ValueError as exc:
            raise _bad(
                text, str(exc), f"a number in {unit} or with units, e.g. {example!r}"
            ) from None
    if not math.isfinite(value):
        raise _bad(text, "not a finite number", f"a number in {unit}, e.g. {example!r}")
    return value


def rpm(minimum: float | None = None, *, strict: bool = False) -> Callable[[str], float]:
    """Parser of a speed option: rpm, or with units ("680 rad/s"); finite, and at least
    ``minimum`` (above it when ``strict``)."""

    def parse(text: str) -> float:
        value = _number(text, "angular_speed", "rpm", RPM)
        if minimum is not None and (value <= minimum if strict else value < minimum):
            raise _bad(text, "out of range", f"{'>' if strict else '>='} {minimum:g} rpm")
        return value

    return parse


def number(
    minimum: float | None = None, *, strict: bool = False, maximum: float | None = None
) -> Callable[[str], float]:
    """Parser of a plain-number option (a fraction, an exponent, Hz): finite, at least
    ``minimum`` (above it when ``strict``), at most ``maximum``."""

    def parse(text: str) -> float:
        try:
            value = float(str(text).strip())
        except ValueError:
            raise _bad(text, "not a number", "a number") from None
        if not math.isfinite(value):
            raise _bad(text, "not a finite number", "a finite number")
        low = minimum is not None and (value <= minimum if strict else value < minimum)
        if low or (maximum is not None and value > maximum):
            rng = [f"{'>' if strict else '>='} {minimum:g}"] if minimum is not None else []
            rng += [f"<= {maximum:g}"] if maximum is not None else []
            raise _bad(text, "out of range", " and ".join(rng))
        return value

    return parse


def duration(maximum: float | None = None) -> Callable[[str], float]:
    """Parser of a time option: s, or with units ("250 ms"); finite and positive."""

    def parse(text: str) -> float:
        value = _number(text, "time", "s", 1.0)
        if not value > 0:
            raise _bad(text, "must be positive", "a time > 0 s")
        if maximum is not None and value > maximum:
            raise _bad(text, "too long", f"at most {maximum:g} s")
        return value

    return parse


def count(minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """Parser of a count option: an integer in ``minimum..maximum``."""

    def parse(text: str) -> int:
        try:
            value = int(str(text).strip())
        except ValueError:
            raise _bad(text, "not an integer", f"an integer >= {minimum}") from None
        if value < minimum or (maximum is not None and value > maximum):
            rng = f"{minimum}..{maximum}" if maximum is not None else f">= {minimum}"
            raise _bad(text, "out of range", f"an integer {rng}")
        return value

    return parse


def choice(*names: str) -> Callable[[str], str]:
    """Parser of an option with named values."""

    def parse(text: str) -> str:
        if text not in names:
            raise _bad(text, "unknown value", " or ".join(repr(n) for n in names))
        return text

    return parse


def parse_range(text: str, field: str = "--operating-range") -> tuple[float, float]:
    """``--operating-range MIN,MAX``: rpm (or with units), finite, 0 < MIN <= MAX → rad/s."""
    parts = str(text).split(",")
    if len(parts) != 2:
        raise ModelError(
            "cannot read the operating range",
            field=field,
            value=text,
            expected="MIN,MAX in rpm, e.g. 5800,7200",
        )
    try:
        lo, hi = (rpm()(p) for p in parts)
    except typer.BadParameter as exc:
        raise ModelError(str(exc), field=field) from None
    if not 0 < lo <= hi:
        raise ModelError(
            "the operating range must be ordered and positive",
            field=field,
            value=text,
            expected="MIN,MAX with 0 < MIN <= MAX rpm, e.g. 5800,7200",
        )
    return lo * RPM, hi * RPM
