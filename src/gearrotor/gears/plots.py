"""Gear-mesh plots (matplotlib): the loaded mesh over the mesh cycle (TVMS, STE, load sharing)
and the harmonics of the STE and the TVMS. Each function returns the Figure and, when ``path``
is given, saves it atomically; nothing is changed at import.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..files import save_figure
from .loaded import MeshCurves

__all__ = ["plot_mesh_cycle", "plot_harmonics"]


def _figure(**kw):
    from matplotlib.figure import Figure

    return Figure(**kw)


def _save(fig, path: str | Path | None):
    if path is not None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
        save_figure(fig, path, dpi=120)
    return fig


def _title(c: MeshCurves) -> str:
    g = c.geometry
    helix = np.rad2deg(g.pinion.helix_angle)
    kind = f"helical {helix:.4g}°" if helix else "spur"
    ratios = f"εα {c.contact_ratio:.3f}" + (f", εβ {c.overlap_ratio:.3f}" if helix else "")
    return (
        f"{g.pinion.teeth}/{g.gear.teeth} teeth, {kind}, m {g.pinion.module * 1e3:g} mm, "
        f"b {g.face_width * 1e3:g} mm, {ratios}; {c.torque:.4g} N·m on the pinion"
    )


def plot_mesh_cycle(c: MeshCurves, path: str | Path | None = None, cycles: int = 2):
    """Three panels over ``cycles`` mesh cycles: the mesh stiffness (N/m, its mean dashed),
    the loaded STE and the unloaded TE of the modifications (µm), and the normal load on each
    tooth pair against its roll position along the path of contact (load sharing)."""
    fig = _figure(figsize=(8.4, 8.0), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(3, 1)
    tau = np.concatenate([c.position + k for k in range(cycles)] + [[cycles]])
    rep = np.concatenate([np.tile(c.stiffness, cycles), c.stiffness[:1]])
    ax1.plot(tau, rep / 1e9, color="C0")
    ax1.axhline(c.mean_stiffness / 1e9, color="C0", ls="--", lw=1)
    ax1.set_ylabel("mesh stiffness (GN/m)")
    ax1.set_xlabel("mesh cycles (1 = one base pitch of roll)")
    ax1.set_title(_title(c), fontsize=9)
    ax1.text(
        0.01,
        0.04,
        f"mean {c.mean_stiffness:.4g}, max {c.max_stiffness:.4g}, min {c.min_stiffness:.4g} N/m",
        transform=ax1.transAxes,
        fontsize=8,
    )
    ste = np.concatenate([np.tile(c.ste, cycles), c.ste[:1]]) * 1e6
    nl = np.concatenate([np.tile(c.nlte, cycles), c.nlte[:1]]) * 1e6
    ax2.plot(tau, ste, color="C3", label=f"loaded STE ({c.ste_peak_to_peak * 1e6:.3g} µm p-p)")
    if np.ptp(nl) > 0 or nl.any():
        ax2.plot(tau, nl, color="0.5", ls=":", label="unloaded TE (modifications)")
    ax2.set_ylabel("transmission error (µm)")
    ax2.set_xlabel("mesh cycles")
    ax2.legend(fontsize=8, loc="best")
    g = c.geometry
    # one tooth pair's load along its whole engagement: the pairs' pieces of the cycle joined
    roll, load = c.pair_roll.ravel(), c.pair_load.ravel()
    ok = np.isfinite(roll) & (load > 0)
    order = np.argsort(roll[ok], kind="stable")
    ax3.plot((roll[ok][order] - g.s_A) * 1e3, load[ok][order] / c.force, color="C2", lw=1.2)
    ax3.set_xlabel(
        "roll position of a tooth pair along the path of contact, mid-face (mm from the start)"
    )
    ax3.set_ylabel("share of the mesh load")
    ax3.set_ylim(bottom=0)
    return _save(fig, path)


def plot_harmonics(c: MeshCurves, path: str | Path | None = None, n: int | None = None):
    """Amplitudes of the mesh harmonics of the loaded STE (µm) and of the TVMS (N/m)."""
    n = min(n or c.harmonics, c.harmonics)
    h = np.arange(1, n + 1)
    fig = _figure(figsize=(8.0, 5.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.bar(h, c.ste_harmonics(n) * 1e6, color="C3")
    ax1.set_ylabel("STE amplitude (µm)")
    ax1.set_title(_title(c), fontsize=9)
    ax2.bar(h, c.stiffness_harmonics(n) / 1e6, color="C0")
    ax2.set_ylabel("TVMS amplitude (MN/m)")
    ax2.set_xlabel("mesh harmonic")
    ax2.set_xticks(h)
    return _save(fig, path)
