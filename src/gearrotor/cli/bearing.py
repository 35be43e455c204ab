"""``gearrotor bearing BEARING.toml [--load FX,FY] [--speed RPM] [--format table|json]
[--plot DIR]``: equilibrium and the 8 dynamic coefficients of a bearing file
(:func:`gearrotor.bearings.coefficients`).

:func:`bearing_command` is the whole command as a Python function (registered through the
Typer signature :func:`bearing_cli`). It prints to stdout and raises
:class:`~gearrotor.errors.ModelError` (bad input) or :class:`~gearrotor.errors.SolverError` (no
equilibrium) for :func:`.errors.cli_errors` to report.
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ..errors import ModelError
from ..files import check_output, make_directory, output_set
from ..progress import part, steps
from .errors import cli_errors
from .options import FormatOpt
from .progress import current

if TYPE_CHECKING:
    from ..bearings.coefficients import Coefficients

__all__ = [
    "bearing_cli",
    "bearing_command",
    "parse_load",
    "parse_speed",
    "format_table",
    "to_json",
]


@cli_errors()
def bearing_cli(
    path: Annotated[Path, typer.Argument(help="bearing TOML file")],
    load: Annotated[
        str | None, typer.Option(help="FX,FY in N (default: the file's load cases)")
    ] = None,
    speed: Annotated[
        str | None, typer.Option(help="journal speed, rpm or with units (default: the file's)")
    ] = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None,
        typer.Option(
            help="write pressure maps, eccentricity locus and coefficient plots to this directory"
        ),
    ] = None,
) -> None:
    """Fluid-film journal bearing: static equilibrium and the 8 dynamic coefficients."""
    bearing_command(path, load=load, speed=speed, fmt=format, plot=plot)


def parse_load(text: str) -> tuple[float, float]:
    """``"FX,FY"`` in N (plain numbers) or with units (``"2 kN,-3.5 kN"``)."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 2:
        raise ModelError(
            "--load takes two comma-separated values",
            field="--load",
            value=text,
            expected="FX,FY in N, e.g. 2,-826 or '2 kN,-3 kN'",
        )
    from ..units import to_si  # pint: only when a command parses units

    try:
        return to_si(_num(parts[0]), "force"), to_si(_num(parts[1]), "force")
    except ValueError as exc:
        raise ModelError(
            str(exc), field="--load", value=text, expected="FX,FY in N, e.g. 2,-826"
        ) from None


def parse_speed(text: str) -> float:
    """``--speed``: a plain number is rpm (signed); a string with units is converted. → rad/s."""
    try:
        value = float(text) * math.pi / 30.0
    except ValueError:
        pass
    else:
        if not math.isfinite(value):
            raise ModelError(
                "not a finite number", field="--speed", value=text, expected="a speed in rpm"
            )
        return value
    from ..units import to_si

    try:
        return to_si(text, "angular_speed")
    except ValueError as exc:
        raise ModelError(
            str(exc),
            field="--speed",
            value=text,
            expected="a speed in rpm (e.g. 10800) or with units",
        ) from None


def _num(s: str) -> float | str:
    try:
        return float(s)
    except ValueError:
        return s


def _row(k: int, name: str, co: Coefficients) -> dict:
    eq = co.equilibrium
    d = {
        "case": k + 1,
        "name": name,
        "fx_N": eq.load[0],
        "fy_N": eq.load[1],
        "speed_rpm": eq.speed_rpm,
        "eccentricity_ratio": eq.eccentricity_ratio,
        "attitude_angle_deg": math.degrees(eq.attitude_angle),
        "x_m": eq.x,
        "y_m": eq.y,
        "min_film_m": eq.min_film,
        "peak_pressure_Pa": eq.peak_pressure,
        "friction_power_W": eq.friction_power,
        "side_flow_m3_per_s": eq.side_flow,
        "sommerfeld": eq.sommerfeld,
        "newton_iterations": eq.iterations,
    }
    ratio, m_crit = co.stability_threshold()
    d["whirl_frequency_ratio"] = None if math.isnan(ratio) else ratio
    d["critical_mass_kg"] = None if math.isinf(m_crit) else m_crit
    for n in ("kxx", "kxy", "kyx", "kyy"):
        d[f"{n}_N_per_m"] = getattr(co, n)
    for n in ("cxx", "cxy", "cyx", "cyy"):
        d[f"{n}_N_s_per_m"] = getattr(co, n)
    return d


def format_table(rows: list[dict], header: str = "") -> str:
    """Two fixed-width tables: equilibrium, then coefficients.

    ``whirl`` and ``m_crit`` are Lund's rigid-rotor threshold whirl frequency ratio and
    critical mass per bearing (``-`` = no threshold, stable for any mass).
    """
    lines = [header] if header else []
    lines.append(
        f"{'case':>4} {'Fx N':>9} {'Fy N':>9} {'rpm':>7} {'ecc':>6} {'att deg':>8} "
        f"{'hmin µm':>8} {'pmax MPa':>8} {'P kW':>7} {'Q l/min':>8} {'S':>8} "
        f"{'whirl':>6} {'m_crit kg':>10}"
    )
    for r in rows:
        lines.append(
            f"{r['case']:>4} {r['fx_N']:>9.1f} {r['fy_N']:>9.1f} {r['speed_rpm']:>7.0f} "
            f"{r['eccentricity_ratio']:>6.3f} {r['attitude_angle_deg']:>8.2f} "
            f"{r['min_film_m'] * 1e6:>8.2f} {r['peak_pressure_Pa'] / 1e6:>8.3f} "
            f"{r['friction_power_W'] / 1e3:>7.3f} {r['side_flow_m3_per_s'] * 6e4:>8.3f} "
            f"{r['sommerfeld']:>8.4g} {_opt(r['whirl_frequency_ratio'], '6.3f')} "
            f"{_opt(r['critical_mass_kg'], '10.4g')}"
        )
    lines.append("")
    names = ["kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"]
    lines.append(
        f"{'case':>4} " + " ".join(f"{n + (' N/m' if n[0] == 'k' else ' Ns/m'):>11}" for n in names)
    )
    for r in rows:
        vals = [r[f"{n}_N_per_m"] for n in names[:4]] + [r[f"{n}_N_s_per_m"] for n in names[4:]]
        lines.append(f"{r['case']:>4} " + " ".join(f"{v:>11.4e}" for v in vals))
    lines.append(
        "ecc: eccentricity ratio; att: attitude angle; S: Sommerfeld number; whirl and m_crit: "
        "Lund's rigid-rotor stability threshold (whirl frequency ratio, critical journal mass); "
        "'-': no threshold, stable for any mass"
    )
    return "\n".join(lines)


def _opt(value: float | None, spec: str) -> str:
    width = int(spec.split(".")[0])
    return f"{'-':>{width}}" if value is None else format(value, spec)


def to_json(rows: list[dict], meta: dict) -> str:
    """JSON document ``{"bearing": meta, "cases": rows}`` (SI, units in the key names)."""
    return json.dumps({"bearing": meta, "cases": rows}, indent=2)


def bearing_command(
    path: Path,
    load: str | None = None,
    speed: str | None = None,
    fmt: str = "table",
    plot: Path | None = None,
) -> list[Coefficients]:
    """Run a bearing file: equilibrium and coefficients for one load or all load cases.

    Parameters
    ----------
    path
        Bearing TOML file.
    load
        ``"FX,FY"`` (N) overriding the file's load cases; None runs every case of the file.
    speed
        Speed in rpm (or with units) overriding the file's speed.
    fmt
        ``"table"`` or ``"json"``.
    plot
        Directory for PNG plots (pressure map per case, eccentricity locus, coefficients vs
        load); created if needed.

    Returns
    -------
    The :class:`Coefficients` of every case (also printed).
    """
    from ..bearings.coefficients import coefficients
    from ..bearings.io import load_bearing

    if fmt not in ("table", "json"):
        raise ModelError(
            "unknown output format", field="--format", value=fmt, expected="table or json"
        )
    if plot is not None:
        check_output(plot, "directory", field="--plot")
    case = load_bearing(path)
    w = parse_speed(speed) if speed is not None else case.speed
    if w is None:
        raise ModelError(
            "no speed given",
            field="bearing.speed",
            value=None,
            expected="speed in the file or --speed RPM",
            file=str(path),
        )
    if load is not None:
        loads, names = [parse_load(load)], ["--load"]
    else:
        loads, names = list(case.loads), list(case.load_names)
        if not loads:
            raise ModelError(
                "no load cases",
                field="bearing.loads",
                value=None,
                expected="[[bearing.loads]] in the file or --load FX,FY",
                file=str(path),
            )
    t0 = time.perf_counter()
    bar = current()
    share = 0.5 if plot is not None else 1.0  # the figures take about as long
    results = [
        coefficients(case.bearing, ld, w, options=case.options)
        for ld in steps(part(bar, 0.0, share), loads, "load case")
    ]
    wall = time.perf_counter() - t0
    rows = [_row(k, n, co) for k, (n, co) in enumerate(zip(names, results, strict=True))]
    b = case.bearing
    meta = {
        "file": str(path),
        "name": b.name,
        "type": type(b).__name__,
        "diameter_m": b.diameter,
        "length_m": b.length,
        "clearance_m": b.clearance,
        "viscosity_Pa_s": b.viscosity,
        "speed_rpm": w * 30 / math.pi,
        "grid": {"n_theta": case.options.grid.n_theta, "n_z": case.options.grid.n_z},
        "cavitation": case.options.cavitation,
        "wall_time_s": wall,
    }
    if fmt == "json":
        print(to_json(rows, meta))
    else:
        print(
            format_table(
                rows,
                header=(
                    f"{b.name} ({path}): D = {b.diameter * 1e3:.2f} mm, "
                    f"L = {b.length * 1e3:.1f} mm, "
                    f"c = {b.clearance * 1e6:.1f} µm, μ = {b.viscosity:.4g} Pa·s, "
                    f"{w * 30 / math.pi:.0f} rpm; grid {case.options.grid.n_theta}x"
                    f"{case.options.grid.n_z}/pad; {wall:.2f} s"
                ),
            )
        )
    if plot is not None:
        with output_set():  # the figures appear together or not at all
            _plots(case.bearing, results, Path(plot), part(bar, share, 1.0, "figures"))
    return results


def _plots(bearing, results: list[Coefficients], outdir: Path, progress=None) -> list[Path]:
    from ..bearings.plots import plot_coefficients, plot_locus, plot_pressure

    make_directory(outdir, field="--plot")
    out = []
    for k, co in enumerate(steps(progress, results, "pressure field")):
        p = outdir / f"pressure_case{k + 1:02d}.png"
        plot_pressure(co.equilibrium, bearing, p)
        out.append(p)
    p = outdir / "locus.png"
    plot_locus([co.equilibrium for co in results], bearing, p)
    out.append(p)
    if len(results) > 1:
        p = outdir / "coefficients_vs_load.png"
        plot_coefficients(results, path=p, title=f"{bearing.name}")
        out.append(p)
    return out
