"""Figures of the periodic mesh response over speed
(:func:`gearrotor.analyses.lateral.mesh_response.mesh_response`): the dynamic transmission error and
the dynamic factor (with ISO 6336-1's K_v), probe amplitudes at 1x and at 1x and 2x mesh
frequency, and the bearings' dynamic forces. Each function returns the Figure and saves it
atomically when ``path`` is given."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..files import save_figure

__all__ = ["plot_mesh_response", "plot_bearing_forces"]


def _figure(**kw):
    from matplotlib.figure import Figure

    return Figure(**kw)


def _save(fig, path):
    if path is not None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
        save_figure(fig, path, dpi=120)
    return fig


def _spans(ax, x, where, color, label=None):
    """Shade the speeds where ``where`` holds, each point over half a step either side."""
    if not np.any(where):
        return
    edges = np.concatenate([[x[0]], 0.5 * (x[1:] + x[:-1]), [x[-1]]])
    idx = np.flatnonzero(where)
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    for j, run in enumerate(runs):
        ax.axvspan(edges[run[0]], edges[run[-1] + 1], color=color, zorder=0,
                   label=label if j == 0 else None)  # fmt: skip


def _distinct_meshes(res) -> list[int]:
    """The meshes whose frequencies differ (two helices of a double-helical mesh share theirs:
    the probe and bearing responses at that frequency are one, drawn once)."""
    keep: list[int] = []
    for k in range(len(res.meshes)):
        if not any(np.allclose(res.mesh_frequency[:, k], res.mesh_frequency[:, j]) for j in keep):
            keep.append(k)
    return keep


def plot_mesh_response(res, path: str | Path | None = None, title: str | None = None):
    """Three panels against the reference-shaft speed (rpm): DTE rms (µm) under the mesh
    excitation (solid) and with unbalance (dashed), contact loss shaded grey; the dynamic
    factor max F / mean F and ISO 6336-1 method B K_v (dotted); probe amplitudes (µm, 0-pk,
    log) at 1x, 1x mesh and 2x mesh. Parametrically unstable speeds are shaded red and the
    periodic response is not drawn there. A nonlinear result (backlash law) is drawn at every
    speed, with the linear DTE dotted, the speeds where the teeth separate shaded grey and
    those where Newton's method did not converge marked x."""
    nl = bool(getattr(res, "nonlinear", False))
    fig = _figure(figsize=(8.6, 9.6), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True)
    x = res.speed_rpm
    bad = res.unstable if not nl else np.zeros(len(x), bool)
    for ax in (ax1, ax2, ax3):
        _spans(ax, x, bad, "#f4c7c3", "parametrically unstable" if ax is ax2 else None)
        _spans(ax, x, res.contact_loss.any(axis=1) & ~bad, "0.85",
               ("teeth separate (nonlinear solution)" if nl
                else "contact loss (linear response invalid)") if ax is ax2 else None)  # fmt: skip

    def ok(a):  # the periodic response where it is stable (it means nothing elsewhere)
        return np.where(bad, np.nan, a)

    for k, name in enumerate(res.meshes):
        c = f"C{k}"
        ax1.plot(x, ok(res.dte_rms[:, k]) * 1e6, color=c,
                 label=f"{name}: mesh excitation" + (" (backlash law)" if nl else ""))  # fmt: skip
        if nl and res.dte_rms_linear is not None:
            ax1.plot(x, res.dte_rms_linear[:, k] * 1e6, color=c, ls=":", lw=1,
                     label="linear (teeth always in contact)")  # fmt: skip
            miss = ~np.asarray(res.converged, bool)
            if miss.any():
                ax1.plot(x[miss], res.dte_rms[miss, k] * 1e6, "x", color="k", ms=5,
                         label="not converged")  # fmt: skip
        if np.any(res.dte_rms_total[:, k] > res.dte_rms[:, k] * (1 + 1e-6)):
            ax1.plot(x, ok(res.dte_rms_total[:, k]) * 1e6, color=c, ls="--", lw=1,
                     label="+ unbalance")  # fmt: skip
        ax2.plot(x, ok(res.dynamic_factor[:, k]), color=c, label=f"{name}: max F / mean F")
        if res.iso_kv is not None and np.isfinite(res.iso_kv[:, k]).any():
            ax2.plot(x, res.iso_kv[:, k], color=c, ls=":", label=f"{name}: ISO 6336-1 K_v (B)")
    ax1.set_ylabel("DTE rms (µm)")
    ax1.set_yscale("log")
    ax1.legend(fontsize=8)
    ax1.set_title(title or "periodic response to the mesh excitation and unbalance", fontsize=10)
    ax2.set_ylabel("dynamic factor")
    top = np.nanmax(np.where(bad[:, None], np.nan, res.dynamic_factor), initial=1.0)
    if top > 3:
        ax2.set_yscale("log")
    ax2.legend(fontsize=8)
    for p, name in enumerate(res.probes):
        c = f"C{p}"
        ax3.plot(x, ok(res.probe_1x[:, p]) * 1e6, color=c, ls=":", label=f"{name} 1x")
        distinct = _distinct_meshes(res)
        for k in distinct:
            tag = f" ({res.meshes[k]})" if len(distinct) > 1 else ""
            ax3.plot(x, ok(res.probe_mesh[:, p, k, 0]) * 1e6, color=c,
                     label=f"{name} 1x mesh{tag}")  # fmt: skip
            ax3.plot(x, ok(res.probe_mesh[:, p, k, 1]) * 1e6, color=c, ls="--", lw=1,
                     label=f"{name} 2x mesh{tag}")  # fmt: skip
    ax3.set_yscale("log")
    ax3.set_ylabel("probe amplitude (µm, 0-pk)")
    ax3.set_xlabel("reference-shaft speed (rpm)")
    ax3.legend(fontsize=7, ncol=2)
    return _save(fig, path)


def plot_bearing_forces(res, path: str | Path | None = None):
    """Dynamic bearing forces (N, semi-major axis of the force ellipse, log) against speed at
    the bearing shaft's 1x and at 1x and 2x of each mesh frequency."""
    fig = _figure(figsize=(8.6, 5.0), layout="constrained")
    ax = fig.subplots()
    x = res.speed_rpm
    for b, name in enumerate(res.bearings):
        if not np.isfinite(res.bearing_mesh[:, b]).any():
            continue
        c = f"C{b % 10}"
        ax.plot(x, res.bearing_1x[:, b], color=c, ls=":", label=f"{name} 1x")
        for k in _distinct_meshes(res):
            ax.plot(x, res.bearing_mesh[:, b, k, 0], color=c, label=f"{name} 1x mesh")
            ax.plot(x, res.bearing_mesh[:, b, k, 1], color=c, ls="--", lw=1,
                    label=f"{name} 2x mesh")  # fmt: skip
    ax.set_yscale("log")
    ax.set_xlabel("reference-shaft speed (rpm)")
    ax.set_ylabel("dynamic bearing force (N)")
    ax.set_title("bearing forces at 1x, 1x mesh and 2x mesh", fontsize=10)
    ax.legend(fontsize=7, ncol=2)
    return _save(fig, path)
