"""Standard transient figures (matplotlib, object API: no pyplot state, no import side effects).

Every function takes a :class:`~.results.TransientResult` or the ``xarray.Dataset`` of a saved
result and returns the ``matplotlib.figure.Figure``; :func:`standard_figures` writes them all as
PNG files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...files import make_directory, save_figure
from ...signals import DISPLAY_FLOOR, spectrum
from .results import RPM, spectra_one_x_rpm

__all__ = [
    "plot_time_histories",
    "plot_spectra",
    "plot_orbits",
    "plot_speeds",
    "plot_whirl_power",
    "plot_mesh",
    "standard_figures",
]


def _ds(result):
    return result if hasattr(result, "data_vars") else result.to_xarray()


def _figure(nrows=1, ncols=1, size=(9, 6)):  # noqa: D401
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def _steady(ds, fraction=0.5):
    t = ds["time"].values
    return t >= t[0] + (1 - fraction) * (t[-1] - t[0])


def plot_time_histories(result):
    """x and y of every gear/probe node (µm) against time."""
    ds = _ds(result)
    t = ds["time"].values
    nodes = list(ds["node"].values)
    fig, ax = _figure(len(nodes), 1, (10, 2.2 * max(len(nodes), 1) + 0.5))
    for k, node in enumerate(nodes):
        a = ax[k, 0]
        a.plot(t, ds["x"].values[:, k] * 1e6, lw=0.6, label="x")
        a.plot(t, ds["y"].values[:, k] * 1e6, lw=0.6, label="y")
        a.set_ylabel(f"{node}\nµm")
        a.legend(loc="upper right", fontsize=8)
        a.grid(alpha=0.3)
    ax[-1, 0].set_xlabel("time (s)")
    fig.suptitle("Lateral displacement at the gear and probe nodes")
    return fig


def plot_spectra(result, *, segments: int = 4, window: str = "hann"):
    """Spectra (cpm) of gear-node x and shaft-1 speed over the second half of the run: full
    range (log) and zooms near 1x/2x and near the mesh frequency (with ±1x sidebands). A zoom's
    amplitude axis spans at least :data:`~gearrotor.signals.DISPLAY_FLOOR` of the spectrum's
    largest line: content below that (window leakage, round-off, e.g. near the mesh frequency
    of a constant mesh) draws flat and the panel says so."""
    from matplotlib.ticker import MaxNLocator

    ds = _ds(result)
    sl = _steady(ds)
    t = ds["time"].values[sl]
    dt = float(np.median(np.diff(t)))
    # the same 1x as the summary table's "1x cpm" (one function, one window)
    run_cpm = float(spectra_one_x_rpm(ds["time"].values, ds["shaft_speed"].values)[0])
    node0 = str(ds["node"].values[0])
    x = ds["x"].values[sl, 0]
    f, a = spectrum(x, dt, window=window, segments=segments)
    fs, as_ = spectrum(
        np.abs(ds["shaft_speed"].values[sl, 0]) * RPM, dt, window=window, segments=segments
    )
    fig, ax = _figure(2, 3, (14, 7))
    model = _model(ds)
    mesh_cpm = None
    if model is not None and model.get("meshes"):
        mesh_cpm = model["meshes"][0]["gear"]["teeth"] * run_cpm
    for row, (ff, aa, name, unit, scale) in enumerate(
        ((f, a, f"{node0} x", "µm", 1e6), (fs, as_, f"{ds['shaft'].values[0]} speed", "rpm", 1.0))
    ):
        ax[row, 0].semilogy(ff, np.maximum(aa * scale, 1e-12), lw=0.7)
        ax[row, 0].set_title(f"{name}: full range")
        zooms = [(0, 3 * run_cpm, "near 1x / 2x")]
        if mesh_cpm is not None:
            zooms.append((mesh_cpm - 4 * run_cpm, mesh_cpm + 4 * run_cpm, "near mesh frequency"))
        floor = DISPLAY_FLOOR * float(np.max(aa, initial=0.0)) * scale
        for c, (lo, hi, title) in enumerate(zooms, start=1):
            m = (ff >= lo) & (ff <= hi)
            ax[row, c].plot(ff[m], aa[m] * scale, lw=0.8)
            ax[row, c].set_title(f"{name}: {title}")
            shown = float(np.max(aa[m], initial=0.0)) * scale
            if shown < floor:  # leakage and round-off: not drawn as if it were signal
                ax[row, c].set_ylim(0.0, floor)
                ax[row, c].text(
                    0.5,
                    0.95,
                    f"largest {shown:.2g} {unit}: below {DISPLAY_FLOOR:g} of the\n"
                    "spectrum's largest line (leakage, round-off)",
                    transform=ax[row, c].transAxes,
                    ha="center",
                    va="top",
                    fontsize=8,
                )
            else:
                ax[row, c].set_ylim(0.0, 1.05 * shown)
            for order in (1, 2):
                ax[row, c].axvline(order * run_cpm, color="0.7", ls="--", lw=0.6)
            if mesh_cpm is not None:
                for sb in (-1, 0, 1):
                    ax[row, c].axvline(mesh_cpm + sb * run_cpm, color="0.8", ls=":", lw=0.6)
            ax[row, c].set_xlim(lo, hi)
        for c in range(3):
            ax[row, c].xaxis.set_major_locator(MaxNLocator(5))
            ax[row, c].set_xlabel("frequency (cpm)")
            ax[row, c].set_ylabel(f"amplitude 0-pk ({unit})")
            ax[row, c].grid(alpha=0.3)
        if mesh_cpm is None:
            ax[row, 2].set_visible(False)
    fig.suptitle(f"Spectra, {window} window, {segments} averages (1x = {run_cpm:.0f} cpm)")
    return fig


def _model(ds):
    import json

    try:
        return json.loads(ds.attrs["model_json"])
    except (KeyError, ValueError):
        return None


def plot_orbits(result):
    """Orbits (µm) of the gear/probe nodes over the last quarter of the run."""
    ds = _ds(result)
    sl = _steady(ds, 0.25)
    nodes = list(ds["node"].values)
    fig, ax = _figure(1, max(len(nodes), 1), (4 * max(len(nodes), 1), 4))
    for k, node in enumerate(nodes):
        a = ax[0, k]
        a.plot(ds["x"].values[sl, k] * 1e6, ds["y"].values[sl, k] * 1e6, lw=0.5)
        a.set_aspect("equal", "datalim")
        a.set_title(str(node))
        a.set_xlabel("x (µm)")
        a.set_ylabel("y (µm)")
        a.grid(alpha=0.3)
    fig.suptitle("Orbits (last quarter of the run)")
    return fig


def plot_speeds(result):
    """Shaft speed fluctuation (rpm about each shaft's initial speed)."""
    ds = _ds(result)
    t = ds["time"].values
    fig, ax = _figure(1, 1, (10, 4))
    for k, name in enumerate(ds["shaft"].values):
        rpm = np.abs(ds["shaft_speed"].values[:, k]) * RPM
        ax[0, 0].plot(t, rpm - rpm[0], lw=0.6, label=f"{name} (start {rpm[0]:.0f} rpm)")
    ax[0, 0].set_xlabel("time (s)")
    ax[0, 0].set_ylabel("|speed| − initial (rpm)")
    ax[0, 0].legend()
    ax[0, 0].grid(alpha=0.3)
    fig.suptitle("Shaft speed fluctuation")
    return fig


def plot_mesh(result, *, zoom: float = 0.02):
    """Mesh force, stiffness k(t), dynamic transmission error and contact state: the whole run
    (left) and its last ``zoom`` seconds (right), where single mesh cycles are visible."""
    ds = _ds(result)
    t = ds["time"].values
    fig, ax = _figure(4, 2, (14, 9))
    last = t >= t[-1] - zoom
    for col, sl in enumerate((slice(None), last)):
        for k, name in enumerate(ds["mesh"].values):
            ax[0, col].plot(t[sl], ds["mesh_force"].values[sl, k], lw=0.5, label=str(name))
            ax[1, col].plot(t[sl], ds["mesh_stiffness"].values[sl, k], lw=0.5)
            ax[2, col].plot(t[sl], ds["dte"].values[sl, k] * 1e6, lw=0.5)
            ax[3, col].step(t[sl], ds["contact"].values[sl, k], lw=0.6, where="post")
        for a, lab in zip(ax[:, col], ("force (N)", "k (N/m)", "DTE (µm)", "contact"), strict=True):
            a.set_ylabel(lab)
            a.grid(alpha=0.3)
        ax[3, col].set_yticks([-1, 0, 1], ["back", "open", "drive"])
        ax[3, col].set_xlabel("time (s)")
    ax[0, 0].set_title("whole run")
    ax[0, 1].set_title(f"last {zoom * 1e3:.0f} ms")
    ax[0, 0].legend(loc="upper right")
    fig.suptitle("Gear mesh")
    return fig


def plot_whirl_power(result, *, smooth: float = 0.01):
    """Whirl-promoting power P = Fx ẋ + Fy ẏ per component (W), moving average over ``smooth``
    seconds; positive feeds whirl, negative drains it."""
    ds = _ds(result)
    t = ds["time"].values
    dt = float(np.median(np.diff(t)))
    n = max(1, int(round(smooth / dt)))
    ker = np.ones(n) / n
    fig, ax = _figure(1, 1, (10, 5))
    for k, name in enumerate(ds["component"].values):
        x = ds["whirl_power"].values[:, k]
        p = np.convolve(np.pad(x, (n // 2, n - 1 - n // 2), mode="edge"), ker, mode="valid")
        ax[0, 0].plot(t, p, lw=0.8, label=str(name))
    ax[0, 0].axhline(0, color="k", lw=0.5)
    ax[0, 0].set_xlabel("time (s)")
    ax[0, 0].set_ylabel(f"power (W), {smooth * 1e3:.0f} ms average")
    ax[0, 0].legend(fontsize=7, ncol=2)
    ax[0, 0].grid(alpha=0.3)
    fig.suptitle("Whirl-promoting power by component")
    return fig


def standard_figures(
    result, directory: str | Path, prefix: str = "transient", progress=None
) -> list[Path]:
    """Write the standard PNG figures into ``directory``; returns the paths. ``progress``:
    called with each path as it is written (the command line prints it)."""
    directory = Path(directory)
    make_directory(directory)
    ds = _ds(result)
    out = []
    for name, fn in (
        ("time", plot_time_histories),
        ("spectra", plot_spectra),
        ("orbits", plot_orbits),
        ("speeds", plot_speeds),
        ("mesh", plot_mesh),
        ("whirl_power", plot_whirl_power),
    ):
        if name == "mesh" and ds.sizes.get("mesh", 0) == 0:
            continue
        fig = fn(ds)
        path = directory / f"{prefix}_{name}.png"
        save_figure(fig, path, dpi=110)
        out.append(path)
        if progress is not None:
            progress(path)
    return out
