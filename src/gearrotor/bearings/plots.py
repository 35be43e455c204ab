"""Bearing plots (matplotlib): pressure and (THD) temperature maps, eccentricity locus,
coefficients vs load/speed.

Every function returns the :class:`matplotlib.figure.Figure` and, when ``path`` is given, saves
it there (PNG/SVG by suffix). The Agg backend is used for files; nothing is changed at import.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..files import save_figure
from .coefficients import BearingTable, Coefficients
from .equilibrium import Equilibrium
from .geometry import Bearing, TiltingPadBearing

__all__ = ["plot_pressure", "plot_temperature", "plot_locus", "plot_coefficients", "plot_table"]


def _figure(**kw):
    from matplotlib.figure import Figure

    return Figure(**kw)


def _save(fig, path: str | Path | None):
    if path is not None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
        save_figure(fig, path, dpi=120)
    return fig


def _pad_maps(films, values, length: float, *, low, high, cmap, extend, label):
    """The figure of a pad-map plot: a row of contour maps, one per pad, of ``values`` (one
    array per pad over its half-length grid, mirrored here to the full ``length``, m) over
    angle (deg) and axial position (mm), with round contour levels from ``low`` to ``high``
    (0.5, 1, 1.5 ... rather than (high - low)/20 steps, so that the colour bar's ticks are
    round numbers) and one colour bar; below it a free row (the figure's grid spec ``[1, :]``)
    for the mid-plane curves. Returns ``(figure, grid spec)``."""
    from matplotlib.ticker import MaxNLocator

    n = len(films)
    fig = _figure(figsize=(max(8.0, 2.6 * n), 6.4), layout="constrained")
    gs = fig.add_gridspec(2, n, height_ratios=[1.2, 1.0])
    levels = MaxNLocator(nbins=20).tick_values(low, high)
    im = None
    for k, (film, v) in enumerate(zip(films, values, strict=True)):
        ax = fig.add_subplot(gs[0, k])
        z = np.concatenate([film.z, length - film.z[-2::-1]]) * 1e3
        v = np.concatenate([v, v[:, -2::-1]], axis=1)
        th = np.degrees(film.theta)
        im = ax.contourf(th, z, v.T, levels=levels, cmap=cmap, extend=extend)
        ax.set_title(f"pad {k + 1}: {th[0]:.0f}°–{th[-1]:.0f}°", fontsize=9)
        ax.set_xlabel("θ (deg)")
        if k == 0:
            ax.set_ylabel("z (mm)")
    if im is not None:
        fig.colorbar(im, ax=fig.axes, label=label, shrink=0.9)
    return fig, gs


def plot_pressure(eq: Equilibrium, bearing: Bearing, path: str | Path | None = None):
    """Pressure map (MPa) of every pad over angle (deg) and axial position (mm).

    One panel per pad (the full length, mirrored from the symmetric half solved), plus an
    unrolled mid-plane pressure and film thickness over the circumference.
    """
    films = eq.film.pads
    pmax = max(float(f.pressure.max()) for f in films) / 1e6 or 1.0
    fig, gs = _pad_maps(
        films,
        [f.pressure / 1e6 for f in films],
        bearing.length,
        low=0.0,
        high=pmax,
        cmap="viridis",
        extend="neither",
        label="pressure (MPa)",
    )
    ax = fig.add_subplot(gs[1, :])
    ax2 = ax.twinx()
    for k, film in enumerate(films):
        th = np.degrees(film.theta)
        line = ax.plot(th, film.pressure[:, -1] / 1e6, lw=1.8, label=f"pad {k + 1}")[0]
        ax2.plot(th, film.film[:, -1] * 1e6, lw=1.0, ls="--", color=line.get_color())
    ax.set_xlabel("θ (deg, from +x, counter-clockwise)")
    ax.set_ylabel("mid-plane pressure (MPa), solid")
    ax2.set_ylabel("mid-plane film (µm), dashed")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    w = math.hypot(*eq.load)
    fig.suptitle(
        f"{bearing.name}\nW = ({eq.load[0]:.0f}, {eq.load[1]:.0f}) N, |W| = {w:.0f} N, "
        f"{eq.speed_rpm:.0f} rpm, ε = {eq.eccentricity_ratio:.3f}, "
        f"h_min = {eq.min_film * 1e6:.1f} µm, p_max = {eq.peak_pressure / 1e6:.2f} MPa",
        fontsize=10,
    )
    return _save(fig, path)


def plot_temperature(eq: Equilibrium, bearing: Bearing, path: str | Path | None = None):
    """Film (bulk) temperature (°C) of every pad of a THD equilibrium over angle and
    axial position, and the mid-plane temperature over the circumference with each pad's inlet
    and outlet temperatures and the supply temperature; where heat goes to the journal or the
    pads, also the pad surface temperature (dashed), whose hottest value is the bearing's
    reported maximum.

    Raises ValueError for an equilibrium without a THD temperature field.
    """
    th = eq.thermal
    if th is None or th.pads[0].temperature is None:
        raise ValueError("plot_temperature needs a THD equilibrium (thermal model 'thd')")
    films = eq.film.pads
    n = len(films)
    t_s = th.supply_temperature - 273.15
    t_hi = max(float(p.temperature.max()) for p in th.pads) - 273.15
    fig, gs = _pad_maps(
        films,
        [p.temperature - 273.15 for p in th.pads],
        bearing.length,
        low=t_s,
        high=t_hi,
        cmap="inferno",
        extend="both",
        label="film temperature, mean across it (°C)",
    )
    ax = fig.add_subplot(gs[1, :])
    surface = any(
        p.surface_temperature is not None
        and not np.array_equal(p.surface_temperature, p.temperature)
        for p in th.pads
    )
    for k, (film, pt) in enumerate(zip(films, th.pads, strict=True)):
        ang = np.degrees(film.theta)
        line = ax.plot(ang, pt.temperature[:, -1] - 273.15, lw=1.8, label=f"pad {k + 1}")[0]
        if surface:
            ax.plot(
                ang,
                pt.surface_temperature[:, -1] - 273.15,
                lw=1.2,
                ls="--",
                color=line.get_color(),
            )
        if getattr(bearing.pads[k], "periodic", False):
            continue  # a 360° film's inlet is where its cavity ends, not at 0°
        ax.plot(
            [ang[0], ang[-1]],
            [pt.inlet_temperature - 273.15, pt.outlet_temperature - 273.15],
            ls="none",
            marker="o",
            ms=4,
            color=line.get_color(),
        )
    if surface:
        ax.plot([], [], color="0.3", lw=1.2, ls="--", label="pad surface")
    ax.axhline(t_s, color="0.4", lw=1.0, ls=":", label="supply")
    ax.set_xlabel("θ (deg, from +x, counter-clockwise)")
    ax.set_ylabel("mid-plane temperature (°C)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", ncols=min(n + 2, 7))
    hottest = (
        f"hottest film (mean across) {t_hi:.1f} °C, "
        f"pad surface {th.max_temperature - 273.15:.1f} °C"
        if surface
        else f"hottest {t_hi:.1f} °C"
    )
    fig.suptitle(
        f"{bearing.name}\nTHD, supply {t_s:.1f} °C, {hottest}, power loss "
        f"{th.power_loss / 1e3:.3g} kW\n{eq.speed_rpm:.0f} rpm, W = ({eq.load[0]:.0f}, "
        f"{eq.load[1]:.0f}) N, ε = {eq.eccentricity_ratio:.3f}"
        + ("" if getattr(bearing.pads[0], "periodic", False) else " (dots: pad inlet and outlet)"),
        fontsize=10,
    )
    return _save(fig, path)


def _clearance_outline(bearing: Bearing) -> list[np.ndarray]:
    """Journal-centre positions (/c) touching each pad at zero tilt (pad arcs)."""
    out = []
    for pad in bearing.pads:
        m = pad.preload
        cp = 1.0 / (1.0 - m)
        tp = pad.pivot if isinstance(bearing, TiltingPadBearing) else pad.reference_angle
        d = cp - 1.0
        th = np.linspace(pad.start, pad.start + pad.arc, 60)
        out.append(np.stack([-d * np.cos(tp) + cp * np.cos(th), -d * np.sin(tp) + cp * np.sin(th)]))
    return out


def plot_locus(results: Sequence[Equilibrium], bearing: Bearing, path: str | Path | None = None):
    """Journal-centre locus (x/c, y/c) over the load cases, with load arrows and pad outlines."""
    fig = _figure(figsize=(6.4, 6.0), layout="constrained")
    ax = fig.add_subplot()
    for k, arc in enumerate(_clearance_outline(bearing)):
        ax.plot(
            arc[0],
            arc[1],
            color="0.5",
            lw=1.2,
            label="pad surface (journal contact)" if k == 0 else None,
        )
    t = np.linspace(0, 2 * math.pi, 200)
    ax.plot(np.cos(t), np.sin(t), color="0.8", lw=0.8, ls=":", label="ε = 1")
    c = bearing.clearance
    x = np.array([r.x for r in results]) / c
    y = np.array([r.y for r in results]) / c
    ax.plot(x, y, "o-", color="C3", ms=4, label="journal centre")
    wmax = max((math.hypot(*r.load) for r in results), default=1.0) or 1.0
    for r, xi, yi in zip(results, x, y, strict=True):
        ax.annotate(
            "",
            xy=(xi + 0.25 * r.load[0] / wmax, yi + 0.25 * r.load[1] / wmax),
            xytext=(xi, yi),
            arrowprops=dict(arrowstyle="->", color="C0", lw=0.8),
        )
    ax.set_aspect("equal")
    ax.set_xlabel("x / c")
    ax.set_ylabel("y / c")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    rpm = results[0].speed_rpm if results else float("nan")
    ax.set_title(
        f"{bearing.name}\neccentricity locus at {rpm:.0f} rpm "
        "(arrows: load direction, length ∝ |W|)",
        fontsize=9,
    )
    return _save(fig, path)


def plot_coefficients(
    results: Sequence[Coefficients],
    x: ArrayLike | None = None,
    xlabel: str = "load |W| (N)",
    path: str | Path | None = None,
    title: str = "",
):
    """Stiffness (N/m) and damping (N·s/m) coefficients against load (default) or speed."""
    xs = np.asarray([r.load_magnitude for r in results] if x is None else x, dtype=float)
    fig = _figure(figsize=(10.0, 4.4), layout="constrained")
    for col, (mat, unit) in enumerate((("K", "N/m"), ("C", "N·s/m"))):
        ax = fig.add_subplot(1, 2, col + 1)
        for i, a in enumerate("xy"):
            for j, b in enumerate("xy"):
                vals = np.array([getattr(r, mat)[i, j] for r in results])
                ax.plot(xs, vals, "o-" if i == j else "s--", ms=3, label=f"{mat.lower()}{a}{b}")
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"{'stiffness' if mat == 'K' else 'damping'} ({unit})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    return _save(fig, path)


def plot_table(table: BearingTable, path: str | Path | None = None):
    """Coefficients of a :class:`BearingTable` against speed (rpm)."""
    fig = _figure(figsize=(10.0, 4.4), layout="constrained")
    for col, (kind, unit) in enumerate((("k", "N/m"), ("c", "N·s/m"))):
        ax = fig.add_subplot(1, 2, col + 1)
        for a in "xy":
            for b in "xy":
                name = f"{kind}{a}{b}"
                ax.plot(
                    table.speed_rpm,
                    getattr(table, name),
                    "o-" if a == b else "s--",
                    ms=3,
                    label=name,
                )
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_xlabel("speed (rpm)")
        ax.set_ylabel(f"{'stiffness' if kind == 'k' else 'damping'} ({unit})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"{table.name}: load ({table.load[0]:.0f}, {table.load[1]:.0f}) N", fontsize=10)
    return _save(fig, path)
