"""``gearrotor bearing BEARING.toml [--load FX,FY] [--speed RPM] [--format table|json]
[--plot DIR]``: equilibrium and the 8 dynamic coefficients of a bearing file
(:func:`gearrotor.bearings.coefficients`); with a thermal model in the file, also the
temperatures, power loss and oil flows of every pad.

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
    "thermal_dict",
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
    if eq.thermal is not None:
        d["thermal"] = thermal_dict(eq.thermal)
    return d


def thermal_dict(th) -> dict:
    """A :class:`~gearrotor.bearings.thermal.ThermalResult` as JSON-ready numbers (SI, K)."""
    pads = [
        {
            "pad": k + 1,
            "inlet_temperature_K": p.inlet_temperature,
            "outlet_temperature_K": p.outlet_temperature,
            "max_temperature_K": p.max_temperature,
            "film_temperature_K": p.film_temperature,
            "power_loss_W": p.power_loss,
            "inlet_flow_m3_per_s": p.inlet_flow,
            "outlet_flow_m3_per_s": p.outlet_flow,
            "side_flow_m3_per_s": p.side_flow,
            "carried_flow_m3_per_s": p.carried_flow,
            "supply_flow_m3_per_s": p.supply_flow,
        }
        for k, p in enumerate(th.pads)
    ]
    return {
        "model": th.model,
        "supply_temperature_K": th.supply_temperature,
        "max_temperature_K": th.max_temperature,
        "journal_temperature_K": None
        if math.isnan(th.journal_temperature)
        else th.journal_temperature,
        "power_loss_W": th.power_loss,
        "side_flow_m3_per_s": th.side_flow,
        "supply_flow_m3_per_s": th.supply_flow,
        "heat_carried_W": th.heat_carried,
        "heat_conducted_W": th.heat_conducted,
        "energy_residual_W": th.energy_residual,
        "iterations": th.iterations,
        "pads": pads,
    }


def _thermal_table(rows: list[dict]) -> list[str]:
    """Per case and pad: temperatures (°C), power loss and flows (l/min)."""
    if not any("thermal" in r for r in rows):
        return []
    lines = [
        "",
        f"{'case':>4} {'pad':>3} {'T_in °C':>8} {'T_out °C':>8} {'T_max °C':>8} "
        f"{'T_film °C':>9} {'P kW':>7} {'Q_in l/min':>10} {'Q_side':>8} {'Q_fresh':>8}",
    ]
    for r in rows:
        th = r.get("thermal")
        if th is None:
            continue
        for p in th["pads"]:
            lines.append(
                f"{r['case']:>4} {p['pad']:>3} {_c(p['inlet_temperature_K']):>8.2f} "
                f"{_c(p['outlet_temperature_K']):>8.2f} {_c(p['max_temperature_K']):>8.2f} "
                f"{_c(p['film_temperature_K']):>9.2f} {p['power_loss_W'] / 1e3:>7.3f} "
                f"{p['inlet_flow_m3_per_s'] * 6e4:>10.3f} {p['side_flow_m3_per_s'] * 6e4:>8.3f} "
                f"{p['supply_flow_m3_per_s'] * 6e4:>8.3f}"
            )
        tj = th["journal_temperature_K"]
        lines.append(
            f"{r['case']:>4} all: {th['model']} model, supply {_c(th['supply_temperature_K']):.1f} "
            f"°C, max {_c(th['max_temperature_K']):.2f} °C, power loss "
            f"{th['power_loss_W'] / 1e3:.3f} kW, fresh oil {th['supply_flow_m3_per_s'] * 6e4:.3f} "
            f"l/min, side leakage {th['side_flow_m3_per_s'] * 6e4:.3f} l/min"
            + (f", journal {_c(tj):.2f} °C" if tj is not None else "")
            + f" ({th['iterations']} iterations)"
        )
    lines.append(
        "T_in: oil entering the pad (carry-over mixed with fresh oil); T_out: leaving it; "
        "T_max: hottest pad surface (THD: from the temperatures across the film); "
        "T_film: effective (or mean) film temperature; "
        "Q_fresh: supply oil drawn"
    )
    return lines


def _c(kelvin: float) -> float:
    return kelvin - 273.15


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
    lines += _thermal_table(rows)
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
        Directory for PNG plots (pressure map per case, with a THD model also a temperature
        map per case, eccentricity locus, coefficients vs load); created if needed.

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
    meta |= _lubricant_meta(case)
    if fmt == "json":
        print(to_json(rows, meta))
    else:
        print(
            format_table(
                rows,
                header=(
                    f"{b.name} ({path}): D = {b.diameter * 1e3:.2f} mm, "
                    f"L = {b.length * 1e3:.1f} mm, "
                    f"c = {b.clearance * 1e6:.1f} µm, {_oil_text(case)}, "
                    f"{w * 30 / math.pi:.0f} rpm; grid {case.options.grid.n_theta}x"
                    f"{case.options.grid.n_z}/pad; {wall:.2f} s"
                ),
            )
        )
    if plot is not None:
        with output_set():  # the figures appear together or not at all
            _plots(case.bearing, results, Path(plot), part(bar, share, 1.0, "figures"))
    return results


def _lubricant_meta(case) -> dict:
    """The lubricant and thermal model of a bearing file, for the JSON header."""
    lub, th = case.lubricant, case.options.thermal
    if lub is None:
        return {}
    out = {
        "lubricant": {
            "name": lub.name,
            "law": lub.law,
            "density_15C_kg_per_m3": lub.density,
            "pour_point_K": lub.pour_point,
            "max_temperature_K": lub.max_temperature,
        },
        "thermal_model": th.model if th is not None else "isoviscous",
    }
    if th is not None:
        out["supply_temperature_K"] = th.supply_temperature
        out["carry_over"] = th.carry_over
    else:
        out["film_temperature_K"] = case.temperature
    return out


def _oil_text(case) -> str:
    b, lub, th = case.bearing, case.lubricant, case.options.thermal
    if lub is None:
        return f"μ = {b.viscosity:.4g} Pa·s"
    name = lub.name or lub.law
    if th is None:
        return f"{name} at {_c(case.temperature):.1f} °C (μ = {b.viscosity:.4g} Pa·s, isoviscous)"
    return f"{name}, {th.model} model, supply {_c(th.supply_temperature):.1f} °C"


def _plots(bearing, results: list[Coefficients], outdir: Path, progress=None) -> list[Path]:
    from ..bearings.plots import plot_coefficients, plot_locus, plot_pressure, plot_temperature

    make_directory(outdir, field="--plot")
    out = []
    for k, co in enumerate(steps(progress, results, "pressure field")):
        p = outdir / f"pressure_case{k + 1:02d}.png"
        plot_pressure(co.equilibrium, bearing, p)
        out.append(p)
        th = co.equilibrium.thermal
        if th is not None and th.pads[0].temperature is not None:
            p = outdir / f"temperature_case{k + 1:02d}.png"
            plot_temperature(co.equilibrium, bearing, p)
            out.append(p)
    p = outdir / "locus.png"
    plot_locus([co.equilibrium for co in results], bearing, p)
    out.append(p)
    if len(results) > 1:
        p = outdir / "coefficients_vs_load.png"
        plot_coefficients(results, path=p, title=f"{bearing.name}")
        out.append(p)
    return out
