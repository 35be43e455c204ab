"""Figures of the static analysis (issue 11): the deflected shape and internal loads of every
shaft at an operating point, and the bearing loads over operating points as a polar plot."""

from __future__ import annotations

import numpy as np

from .figures import _plt, _save, place_labels

__all__ = [
    "plot_bearing_loads",
    "plot_eccentricity_locus",
    "plot_log_dec_vs_power",
    "plot_static_shafts",
]


def plot_static_shafts(result, path=None):
    """Per shaft (columns): deflection x and y (µm) with the bearings marked, bending moment
    magnitude (N·m) and torque (N·m), and von Mises stress (MPa) along the shaft, at one
    operating point (a :class:`~gearrotor.analyses.static.StaticResult`)."""
    plt = _plt()
    ns = len(result.shafts)
    fig, axes = plt.subplots(3, ns, figsize=(4.6 * ns + 0.6, 7.4), squeeze=False, sharex="col")
    for col, s in enumerate(result.shafts):
        ax = axes[0, col]
        ax.plot(s.z, s.deflection[:, 0] * 1e6, "C0-", lw=1.6, label="x")
        ax.plot(s.z, s.deflection[:, 1] * 1e6, "C3-", lw=1.6, label="y")
        ax.axhline(0.0, color="0.6", lw=0.8)
        for b in result.bearings:
            if b.shaft == s.name and b.kind != "thrust":
                ax.axvline(s.z[b.node], color="0.3", lw=0.8, ls=":")
        ax.set_title(f"{s.name}: deflection", fontsize=10)
        ax.set_ylabel("µm")
        ax.legend(fontsize=8, loc="best")
        ax = axes[1, col]
        ax.plot(s.z_section, np.hypot(s.moment[:, 0], s.moment[:, 1]), "C2-", label="|M| bending")
        ax.plot(s.z_section, np.abs(s.torque), "C1--", label="|T| torque")
        ax.set_ylabel("N·m")
        ax.legend(fontsize=8, loc="best")
        ax = axes[2, col]
        ax.plot(s.z_section, s.von_mises / 1e6, "C4-")
        ax.set_ylabel("von Mises, MPa")
        ax.set_xlabel("z, m")
    fig.suptitle(
        f"Static operating point {result.operating_point}: {result.speed * 30 / np.pi:.0f} rpm, "
        f"{result.power / 1e3:,.0f} kW",
        fontsize=11,
    )
    fig.tight_layout()
    return _save(fig, path)


def plot_bearing_loads(results, path=None, bearings=None):
    """Polar plot of the load each radial bearing carries (the force the journal puts on it,
    N; angle from +x towards +y) over a sequence of static results, one locus per bearing
    with the operating points labelled. ``bearings``: names to show (default: all radial)."""
    plt = _plt()
    results = list(results)
    names = [b.name for b in results[0].bearings if b.kind != "thrust"]
    if bearings is not None:
        names = [n for n in names if n in set(bearings)]
    fig = plt.figure(figsize=(7.2, 6.4))
    ax = fig.add_subplot(projection="polar")
    loci = []
    for i, name in enumerate(names):
        loads = [r.bearing(name) for r in results]
        ang = np.array([b.angle for b in loads])
        mag = np.array([b.magnitude for b in loads]) / 1e3
        ax.plot(ang, mag, "o-", color=f"C{i % 10}", ms=4, lw=1.2, label=name)
        loci.append((ang, mag))
    ax.set_title("Bearing loads over operating points (kN; angle from +x)", fontsize=10)
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(-0.15, -0.12))
    fig.tight_layout()
    _label_loci(ax, loci, [r.operating_point for r in results])
    return _save(fig, path)


def _label_loci(ax, loci, points: list[str]) -> None:
    """Label the operating points of each locus (x, y arrays) without overlaps
    (:func:`~.figures.place_labels`); a locus whose points lie (median) within 15 % of the
    axes' size of those of one already labelled (two bearings of one shaft) is not labelled
    again: its points follow the same order."""
    ax.figure.canvas.draw()
    done: list = []
    xy_all = [ax.transData.transform(np.column_stack([x, y])) for x, y in loci]
    size = max(ax.get_window_extent().width, ax.get_window_extent().height)
    every = [(a, b) for x, y in loci for a, b in zip(x, y, strict=True)]
    for i, (x, y) in enumerate(loci):
        if any(np.median(np.hypot(*(xy_all[i] - xy_all[j]).T)) < 0.15 * size for j in done):
            continue
        done.append(i)
        place_labels(ax, x, y, points, color=f"C{i % 10}", avoid=every)


def plot_eccentricity_locus(results, path=None):
    """Journal centre positions of every fluid-film bearing over a sequence of static results,
    as fractions of the clearance (x/c, y/c), inside the clearance circle; the operating points
    labelled. ``None`` when the results have no fluid-film bearing."""
    plt = _plt()
    results = list(results)
    names = [b.name for b in results[0].bearings if b.kind == "fluid-film"]
    if not names:
        return None
    fig, ax = plt.subplots(figsize=(6.4, 6.2))
    t = np.linspace(0, 2 * np.pi, 241)
    ax.plot(np.cos(t), np.sin(t), color="0.5", lw=1.0)
    ax.plot([0], [0], "k+", ms=10)
    loci = []
    for i, name in enumerate(names):
        bs = [r.bearing(name) for r in results]
        x = np.array([b.journal[0] / b.clearance for b in bs])
        y = np.array([b.journal[1] / b.clearance for b in bs])
        ax.plot(x, y, "o-", color=f"C{i % 10}", ms=4, lw=1.2, label=name)
        loci.append((x, y))
    ax.set_aspect("equal")
    ax.set_xlim(-1.05, 1.05)
    ax.set_ylim(-1.05, 1.05)
    ax.set_xlabel("x / c")
    ax.set_ylabel("y / c")
    ax.grid(alpha=0.3)
    ax.set_title(
        "Journal eccentricity locus over operating points (bearing clearance circle)", fontsize=10
    )
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    _label_loci(ax, loci, [r.operating_point for r in results])
    return _save(fig, path)


def plot_log_dec_vs_power(power, log_dec, names=(), threshold=None, path=None):
    """Least-stable log decrement against transmitted power (kW) over operating points."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    p = np.asarray(power, float) / 1e3
    ax.plot(p, log_dec, "o-", color="C0")
    if threshold is not None:
        ax.axhline(threshold, color="C3", ls="--", lw=1.0, label=f"log dec {threshold}")
        ax.legend(fontsize=8)
    ax.axhline(0.0, color="0.4", lw=0.8)
    ax.set_xlabel("power, kW")
    ax.set_ylabel("least-stable log dec")
    ax.grid(alpha=0.3)
    ax.set_title("Least-stable mode over operating points", fontsize=10)
    ax.margins(x=0.08, y=0.12)  # room for the labels of the end points
    fig.tight_layout()
    n = min(len(names), len(p))
    if n:
        place_labels(ax, p[:n], np.asarray(log_dec, float)[:n], list(names)[:n])
    return _save(fig, path)
