"""``gearrotor floquet``: parametric stability under the time-varying mesh stiffness
(:func:`gearrotor.analyses.lateral.floquet.floquet`). rpm and cpm at the boundary, rad/s inside."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output, save_figure
from .errors import cli_errors
from .options import (
    RPM,
    FormatOpt,
    OperatingPointOpt,
    SetOpt,
    check_format,
    check_operating_point,
    count,
    rpm,
)

__all__ = ["floquet_command"]


def _floats(text: str, field: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
        if not all(math.isfinite(v) for v in values):
            raise ValueError
        return values
    except ValueError:
        raise ModelError(
            "expected comma-separated finite numbers",
            field=field,
            value=text,
            expected="e.g. 0,0.25,0.5",
        ) from None


@cli_errors()
def floquet_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    ka: Annotated[
        str | None,
        typer.Option(help="comma-separated Ka/Kg values for every mesh (default: the model's)"),
    ] = None,
    speeds: Annotated[
        str | None,
        typer.Option(help="comma-separated reference-shaft speeds, rpm (default: the model's)"),
    ] = None,
    cutoff: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True),
            help="keep modes up to this frequency, cpm (default 2.5 × mesh frequency)",
        ),
    ] = None,
    n: Annotated[
        int, typer.Option(parser=count(1), help="least stable exponents listed per case")
    ] = 6,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None, typer.Option(help="PNG: largest growth rate against speed (or Ka)")
    ] = None,
    operating_point: OperatingPointOpt = None,
    set_: SetOpt = None,
) -> None:
    """Floquet exponents of the train under its periodic mesh stiffness (teeth in contact,
    constant speed): growth rate (1/s, positive = parametrically unstable), frequency and the
    modes involved, for each Ka/Kg and speed."""
    from ..io import load_model, parse_overrides

    check_format(format)
    if plot is not None:
        check_output(plot, "file", field="--plot", parents=True)
    if n < 1:
        raise ModelError("at least one exponent", field="--n", value=n, expected="≥ 1")
    train = load_model(model, parse_overrides(set_))
    kas: list[float | None] = _floats(ka, "--ka") if ka else [None]
    sp = _floats(speeds, "--speeds") if speeds else [None]
    for v in sp:
        if v is not None and v <= 0:
            raise ModelError(
                "speeds must be positive", field="--speeds", value=v, expected="> 0 rpm"
            )
    check_operating_point(train, operating_point)
    from ..analyses.lateral.floquet import check_ka_ratio, floquet
    from ..analyses.transient import build_system

    if operating_point is not None:
        from ..analyses.static.operating_point import model_at_operating_point

        if sp == [None]:
            w_op = train.operating_point(operating_point).reference_speed(train.speed)
            sp = [abs(w_op) / RPM]
        train = model_at_operating_point(train, operating_point, [v * RPM for v in sp])[0]
    system = build_system(train)
    for k in kas:  # every Ka must be able to act, before anything runs
        check_ka_ratio(system, k)
    cases = []
    for s in sp:
        for k in kas:
            res = floquet(
                system,
                ka_ratio=k,
                speed=None if s is None else s * RPM,
                cutoff=None if cutoff is None else cutoff / 60,
            )
            cases.append(res)
            if format == "table":
                _print_table(res, n)
    if format == "json":
        typer.echo(
            json.dumps({"model": str(model), "cases": [r.to_dict(n) for r in cases]}, indent=1)
        )
    if plot is not None:
        _plot(cases, len(sp), kas, plot)
        typer.echo(f"plot written to {plot}", err=format == "json")


def _print_table(res, n: int) -> None:
    d = res.to_dict(n)
    ka = ", ".join(dict.fromkeys("model" if k is None else f"{k:g}" for k in d["ka_ratio"]))
    typer.echo(
        f"speed {d['speed_rpm']:.1f} rpm, Ka/Kg {ka}: {'stable' if d['stable'] else 'UNSTABLE'} "
        f"(growth within ±{d['neutral_tolerance_1_s']:.1e} 1/s is neutral; "
        f"{d['n_modes']} modes, {d['slices']} steps per period, "
        f"mesh {', '.join(dict.fromkeys(f'{f:,.0f}' for f in d['mesh_frequency_cpm']))} cpm)"
    )
    for law in d["mesh_laws"]:
        typer.echo(f"  mesh '{law['mesh']}': {_law_text(law)}")
    typer.echo(f"  {'growth 1/s':>11} {'cpm':>10} {'order':>7} {'log dec':>9}  modes (cpm)")
    tol = d["neutral_tolerance_1_s"]
    for row in d["exponents"]:
        ld = row["log_dec"] if abs(row["log_dec"]) >= 5e-5 else 0.0
        g = row["growth_1_s"] if abs(row["growth_1_s"]) > tol else 0.0  # neutral: no "-0.000"
        pair = f"{row['mode_cpm']:,.0f}"
        if row["partner_cpm"] is not None:
            pair += f" + {row['partner_cpm']:,.0f}"
        typer.echo(
            f"  {g:11.3f} {row['frequency_cpm']:10,.0f} {row['order']:7.2f} {ld:9.4f}  {pair}"
        )


def _law_text(law: dict) -> str:
    """The stiffness law a mesh ran with, in words (the Ka/Kg, contact ratio and terms used)."""
    if law["law"] == "table":
        return "stiffness table (the model's)"
    if law["law"] == "constant":
        return (
            f"constant stiffness Kg (Ka/Kg {law['ka_ratio']:g}, {law['terms']} Fourier terms): "
            "no parametric excitation"
        )
    return (
        f"Ka/Kg {law['ka_ratio']:g}, contact ratio {law['contact_ratio']:g}, "
        f"{law['terms']} Fourier terms"
    )


def _model_ka(r) -> float | None:
    """The Ka/Kg the first mesh of a case ran with (None for a tabulated law)."""
    laws = r.to_dict().get("mesh_laws") or [{}]
    return laws[0].get("ka_ratio")


def _plot(cases, n_speeds: int, kas: list[float | None], path: Path) -> None:
    """Write :func:`growth_figure` to ``path`` (PNG)."""
    import matplotlib.pyplot as plt

    fig = growth_figure(cases, n_speeds, kas)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig, path, dpi=120)
    plt.close(fig)


def growth_figure(cases, n_speeds: int, kas: list[float | None]):
    """Largest growth rate: one line per Ka/Kg against speed, or against Ka/Kg at one speed
    (a numeric axis: the model's own Ka/Kg at its value, marked "model"). ``cases`` are
    ordered speed-major, Ka/Kg-minor. Returns the pyplot Figure."""
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # growth within the convergence tolerance is neutral (the table says "stable"): drawn as
    # 0 inside a grey band, so that round-off (1e-11 1/s) is not autoscaled into "unstable"
    band = max(r.neutral_tolerance for r in cases)

    def shown(r) -> float:
        g = float(r.growth[0])
        return 0.0 if abs(g) <= r.neutral_tolerance else g

    grid = [cases[i * len(kas) : (i + 1) * len(kas)] for i in range(n_speeds)]
    fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
    if n_speeds > 1:
        for j, k in enumerate(kas):
            ax.plot(
                [row[j].speed / RPM for row in grid],
                [shown(row[j]) for row in grid],
                "o-",
                label="model Ka" if k is None else f"Ka/Kg = {k:g}",
            )
        ax.set_xlabel("reference shaft speed (rpm)")
    else:
        # a numeric Ka/Kg axis: the model's own Ka/Kg (None) at the value its mesh law used
        xs = [k if k is not None else _model_ka(r) for k, r in zip(kas, cases, strict=True)]
        ys = [shown(r) for r in cases]
        if any(x is None for x in xs):  # a tabulated law has no Ka/Kg: categories
            xs = ["model" if k is None else f"{k:g}" for k in kas]
        else:
            order = np.argsort(xs, kind="stable")
            xs, ys = [xs[i] for i in order], [ys[i] for i in order]
            for k, r in zip(kas, cases, strict=True):
                if k is None:
                    ax.annotate(
                        "model",
                        (_model_ka(r), shown(r)),
                        textcoords="offset points",
                        xytext=(4, 6),
                        fontsize=8,
                    )
        ax.plot(xs, ys, "o-", label="largest growth rate")
        ax.set_xlabel("Ka/Kg")
    ax.axhspan(-band, band, color="0.85", zorder=0, label=f"neutral (|growth| ≤ {band:.1e} 1/s)")
    ax.axhline(0.0, color="k", lw=0.8)
    lo, hi = ax.get_ylim()
    span = max(hi, -lo, 10 * band)
    ax.set_ylim(min(lo, -0.1 * span), max(hi, 0.1 * span))
    ax.legend(fontsize=8)
    ax.set_ylabel("largest Floquet growth rate (1/s)")
    ax.set_title("Parametric stability (above the neutral band: unstable)")
    ax.grid(alpha=0.3)
    return fig
