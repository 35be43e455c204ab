"""Options, unit constants and small parsers shared by the ``gearrotor`` command modules.

The parsers check an option's value when the command line is read, before anything runs
(finite, in range, a known choice); a bad value is one line naming the option and the value
(``error: --speed: ...``, exit status 2). Speeds accept units: ``6500`` (rpm), ``6500rpm``,
``"680 rad/s"``, ``"108 Hz"``.
"""

from __future__ import annotations

import contextlib
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
    "ProgressOpt",
    "ThreadsOpt",
    "check_format",
    "check_operating_point",
    "McsOpt",
    "OperatingRangeOpt",
    "check_png",
    "operating_range_from_options",
    "parse_range",
    "MAX_SPEEDS",
    "choice",
    "option_fields",
    "sweep_at_operating_point",
    "count",
    "duration",
    "number",
    "rpm",
    "show_units_in_help",
    "speed_grid",
    "sweep_range",
    "table_speed_range",
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
        metavar="SPEED",
        help="maximum continuous speed of the reference shaft, rpm (overrides the model's "
        "max_continuous_speed)",
    ),
]


@contextlib.contextmanager
def option_fields(**options: str):
    """Name command-line options in the errors of an analysis called with them: a
    :class:`ModelError` whose field is an analysis argument (``excitations[0].shaft``) is
    re-raised naming the option (``--torque[0].shaft``). Keywords: argument name -> option."""
    try:
        yield
    except ModelError as exc:
        field = exc.field or ""
        for arg, option in options.items():
            if field == arg or field.startswith((arg + "[", arg + ".")):
                raise ModelError(
                    exc.message,
                    field=option + field[len(arg) :],
                    value=exc.value,
                    expected=exc.expected,
                ) from None
        raise


@contextlib.contextmanager
def sweep_at_operating_point(train, name: str | None):
    """A speed sweep at an operating point: a journal that cannot carry the point's load at
    some speed of the sweep (12.5 MW held down to 2,000 rpm is 5.4 times the rated torque)
    says which option and which model field change that."""
    try:
        yield
    except ModelError as exc:
        if name is None or "cannot carry its load" not in exc.message:
            raise
        points = list(train.operating_points)
        k = next(i for i, p in enumerate(points) if p.name == name)
        held = points[k].held
        raise ModelError(
            exc.message,
            field=exc.field,
            value=exc.value,
            expected=f"{exc.expected}; the sweep at --operating-point {name} holds the point's "
            f"{held} at every speed: start it nearer the point's speed (--min-speed), or hold "
            f'the torque (operating_points[{k}].hold = "torque")',
            file=exc.file,
        ) from None


ProgressOpt = Annotated[
    bool | None,
    typer.Option(
        "--progress/--no-progress",
        help="progress on stderr (default: when stderr is a terminal, for work over a second)",
        show_default=False,
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


def table_speed_range(train) -> tuple[float, float, str | None, str | None]:
    """(lowest, highest, bearing setting the lowest, bearing setting the highest): the
    reference-shaft speeds (rpm) at which every bearing and seal with a coefficient table
    (a table, a table file or fluid-film coefficients over ``speeds``) has coefficients; a
    table with ``extrapolate = "hold"`` limits nothing. ``(0, inf, None, None)`` without
    tables."""
    from ..assembly import assemble

    asm = assemble(train)  # cached by value: the analysis that follows reuses it
    lo, hi, lo_name, hi_name = 0.0, math.inf, None, None
    for b in asm.bearings:
        table = b.element.table
        ratio = abs(asm.speed_ratio[b.shaft])
        if table is None or table.extrapolate == "hold" or len(table.speed) < 2 or ratio == 0:
            continue
        b_lo, b_hi = table.speed[0] / ratio / RPM, table.speed[-1] / ratio / RPM
        if b_lo > lo:
            lo, lo_name = b_lo, b.name
        if b_hi < hi:
            hi, hi_name = b_hi, b.name
    return lo, hi, lo_name, hi_name


def sweep_range(
    train, min_speed: float | None, max_speed: float | None, default_min: float, default_max: float
) -> tuple[float, float]:
    """(lowest, highest) speed (rpm) of a speed sweep: ``--min-speed`` / ``--max-speed`` when
    given, else the defaults clipped to the speeds the model's bearing tables cover
    (:func:`table_speed_range`: a steam turbine with tables from 2,000 to 16,000 rpm sweeps
    2,000 .. min(default, 16,000) rpm). A speed given outside the tables is an input error that
    names the option and the bearing."""
    lo_t, hi_t, lo_name, hi_name = table_speed_range(train)
    tol = 1e-6
    hint = 'leave the option out, or extend the table or set its extrapolate = "hold"'
    if min_speed is not None and min_speed < lo_t * (1 - tol):
        raise ModelError(
            f"below the speed range of bearing '{lo_name}'",
            field="--min-speed",
            value=f"{min_speed:g} rpm",
            expected=f"at least {lo_t:.6g} rpm of the reference shaft, where the bearing's "
            f"coefficient table starts ({hint})",
        )
    if max_speed is not None and max_speed > hi_t * (1 + tol):
        raise ModelError(
            f"above the speed range of bearing '{hi_name}'",
            field="--max-speed",
            value=f"{max_speed:g} rpm",
            expected=f"at most {hi_t:.6g} rpm of the reference shaft, where the bearing's "
            f"coefficient table ends ({hint})",
        )
    lo = min_speed if min_speed is not None else max(default_min, lo_t)
    hi = max_speed if max_speed is not None else min(default_max, hi_t)
    return lo, hi


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

    parse.metavar = "SPEED"  # the help shows SPEED, not <float> (show_units_in_help)
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

    parse.metavar = "TIME"
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


#: What the help's SPEED and TIME stand for (the epilog of a command that has such options).
UNITS_HELP = {
    "SPEED": "SPEED: rpm, or a value with units ('6500rpm', '680 rad/s', '108 Hz')",
    "TIME": "TIME: s, or a value with units ('250 ms')",
}


def show_units_in_help(command) -> None:
    """Help of ``command`` and the commands below it: an option parsed by :func:`rpm` or
    :func:`duration` shows SPEED or TIME instead of ``<float>``, and the command's epilog
    says what they accept. Called once on the ``gearrotor`` group when it is built."""
    for sub in getattr(command, "commands", {}).values():
        show_units_in_help(sub)
    used = []
    for param in getattr(command, "params", []):
        info = getattr(getattr(param, "type_descriptor", None), "parameter_info", None)
        metavar = getattr(getattr(info, "parser", None), "metavar", None) or param.metavar
        if metavar in UNITS_HELP:
            param.metavar = metavar
            if metavar not in used:
                used.append(metavar)
    if used and not getattr(command, "_units_help", False):
        note = "; ".join(UNITS_HELP[m] for m in used) + "."
        command.epilog = f"{note}\n\n{command.epilog}" if command.epilog else note
        command._units_help = True
