"""Seal plots (matplotlib): pressure and swirl along the seal, coefficients against speed or
whirl frequency. Each function returns the Figure and, when ``path`` is given, saves it
atomically (PNG/SVG by suffix); nothing is changed at import.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..files import save_figure
from .coefficients import SealResult

__all__ = ["plot_distribution", "plot_coefficients"]


def _figure(**kw):
    from matplotlib.figure import Figure

    return Figure(**kw)


def _save(fig, path: str | Path | None):
    if path is not None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
        save_figure(fig, path, dpi=120)
    return fig


def plot_distribution(res: SealResult, path: str | Path | None = None):
    """Pressure (kPa) and swirl ratio along the seal: the cavities of a labyrinth (steps at the
    teeth), the axial grid of an annular seal."""
    s = res.seal
    fig = _figure(figsize=(8.0, 5.6), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    z = res.z * 1e3
    if s.kind == "labyrinth":
        # cavity i spans teeth i..i+1: a step plot, inlet plenum and outlet at the ends
        ax1.step(z, res.pressure / 1e3, where="post", color="C0", marker="o", ms=3)
        ax2.step(z[:-1], res.swirl[:-1], where="post", color="C1", marker="o", ms=3)
        ax1.set_title(
            f"{s.name}: {s.n_teeth} "
            + (
                "interlocking teeth"
                if s.teeth_on == "interlocking"
                else f"teeth on the {s.teeth_on}"
            )
            + f", {res.speed * 30 / math.pi:.0f} rpm, "
            f"leakage {res.leakage:.4g} kg/s" + (" (last tooth choked)" if res.choked else "")
        )
        ax2.set_xlabel("axial position (mm): inlet at 0, the cavity behind tooth i at i · pitch")
    else:
        ax1.plot(z, res.pressure / 1e3, color="C0")
        ax2.plot(z, res.swirl, color="C1")
        ax1.set_title(
            f"{s.name} ({s.kind}): {res.speed * 30 / math.pi:.0f} rpm, leakage "
            f"{res.leakage:.4g} kg/s"
        )
        ax2.set_xlabel("axial position from the inlet (mm)")
    ax1.set_ylabel("pressure (kPa)")
    ax2.set_ylabel("swirl ratio U/(Rω)")
    ax2.axhline(0.5, color="0.6", lw=0.8, ls="--")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
    return _save(fig, path)


def plot_coefficients(
    results: Sequence[SealResult],
    x: Sequence[float],
    xlabel: str,
    path: str | Path | None = None,
    title: str = "",
):
    """kxx, kxy (N/m) and cxx, cxy (N·s/m) against ``x`` (speeds in rpm or whirl frequencies
    in Hz), with the effective damping cxx − kxy/Ω."""
    fig = _figure(figsize=(9.0, 6.4), layout="constrained")
    axes = fig.subplots(2, 2, sharex=True).ravel()
    a = np.array([r.coefficients for r in results])
    ceff = np.array([r.effective_damping for r in results])
    for ax, j, name, unit in (
        (axes[0], 0, "kxx = kyy", "N/m"),
        (axes[1], 1, "kxy = −kyx", "N/m"),
        (axes[2], 4, "cxx = cyy", "N·s/m"),
        (axes[3], 5, "cxy = −cyx", "N·s/m"),
    ):
        ax.plot(x, a[:, j], marker="o", ms=3, label=name)
        if j == 4:
            ax.plot(x, ceff, marker="s", ms=3, ls="--", label="cxx − kxy/Ω (effective)")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_ylabel(f"{name} ({unit})")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    axes[2].set_xlabel(xlabel)
    axes[3].set_xlabel(xlabel)
    if title:
        fig.suptitle(title)
    return _save(fig, path)
