"""Figures of the API lateral audit: undamped critical speed map, Level I stability (log dec
against the applied cross-coupling, and the CSR / gas density screening chart), Level II modes.

Every number drawn comes from the result object (the same numbers as its ``to_dict()``).
"""

from __future__ import annotations

import numpy as np

from .figures import _plt, _save

__all__ = ["plot_ucs_map", "plot_level1", "plot_screening", "plot_level2"]

RPM = 30 / np.pi
LEVEL2_TOP = 3.0  # log dec: well-damped modes above it are cut off the Level II chart


def plot_ucs_map(result, path=None, shafts=None):
    """Critical speed map, one panel per shaft (rpm of that shaft against the bearing
    stiffness): each branch solid where it is a critical speed of the shaft and dotted where
    its mode lives elsewhere (another shaft, the mesh), the rigid-support criticals (grey
    dotted), the shaft's own bearings' Kxx (solid) and Kyy (dashed) over their table speeds
    (identical curves drawn once), the intersections (circles), and the operating range (band)
    and maximum continuous speed (dash-dot) of the model when given, labelled on the axes."""
    plt = _plt()
    names = [s.name for s in result.shafts] if shafts is None else list(shafts)
    fig, axes = plt.subplots(len(names), 1, figsize=(10.5, 4.8 * len(names)), squeeze=False)
    k = result.stiffness
    for ax, name in zip(axes[:, 0], names, strict=True):
        _ucs_panel(plt, ax, result, result.shaft(name), k)
    fig.tight_layout()
    return _save(fig, path)


def _ucs_panel(plt, ax, result, s, k) -> None:
    ratio = abs(s.speed_ratio)
    shown = []  # every speed drawn in a solid line: the vertical range
    for j in range(s.branch_speeds.shape[1]):
        colour = f"C{j % 10}"
        ax.loglog(k, s.branch_speeds[:, j] * RPM, ":", color=colour, lw=0.9)
        c = s.critical_speeds[:, j] * RPM
        ax.loglog(k, c, "-", marker=".", ms=3, color=colour, lw=1.5, label=f"critical {j + 1}")
        shown.append(c[np.isfinite(c)])
    rigid = s.rigid_critical_speeds[np.isfinite(s.rigid_critical_speeds)] * RPM
    for i, r in enumerate(rigid):
        lab = "rigid supports" if i == 0 else None
        ax.axhline(r, color="0.45", ls=(0, (1, 2)), lw=1.0, label=lab)
    shown.append(rigid)
    curves: dict[tuple, list[tuple[str, str]]] = {}
    for b in result.bearings:
        if b.shaft != s.name:
            continue
        for d, kv in (("Kxx", b.kxx), ("Kyy", b.kyy)):
            key = (None if b.speeds is None else tuple(b.speeds), tuple(kv))
            curves.setdefault(key, []).append((b.name, d))
    groups: dict[str, int] = {}  # one colour per set of bearings sharing a curve
    for (speeds, kv), owners in curves.items():
        kv = np.asarray(kv)
        dirs = list(dict.fromkeys(d for _, d in owners))
        who = ", ".join(dict.fromkeys(n for n, _ in owners))
        lab = f"{who} {' = '.join(dirs)}"
        ls = "-" if "Kxx" in dirs else "--"
        bi = groups.setdefault(who, len(groups))
        colour = "0.15" if speeds is None else plt.get_cmap("Dark2")(bi % 8)
        if speeds is None:
            if kv[0] > 0:
                ax.axvline(kv[0], color=colour, ls=ls, lw=1.0, label=lab)
            continue
        ok = kv > 0
        n = np.asarray(speeds)[ok] * RPM
        ax.loglog(kv[ok], n, ls=ls, color=colour, marker="s", ms=3, lw=1.6, label=lab)
        shown.append(n)
    mine = [x for x in result.intersections if x.shaft == s.name]
    for x in mine:
        ax.plot(x.stiffness, x.speed * RPM, "o", mfc="none", mec="k", ms=9, mew=1.3)
    if mine:
        ax.plot([], [], "o", mfc="none", mec="k", ms=9, mew=1.3, label="intersection")
    marks = []
    if result.operating_range is not None:
        lo, hi = (v * ratio * RPM for v in result.operating_range)
        ax.axhspan(lo, hi, color="tab:red", alpha=0.22, lw=0, label="operating range")
        ax.axhline(lo, color="tab:red", lw=0.8)
        ax.axhline(hi, color="tab:red", lw=0.8)
        marks.append((lo, f"operating range {lo:,.0f}–{hi:,.0f} rpm", "top"))
        shown.append(np.array([lo, hi]))
    if result.max_continuous_speed is not None:
        mcs = result.max_continuous_speed * ratio * RPM
        ax.axhline(mcs, color="tab:red", ls="-.", lw=1.6, label="MCS")
        marks.append((mcs, f"MCS {mcs:,.0f} rpm", "bottom"))
        shown.append(np.array([mcs]))
    vals = np.concatenate(shown)
    vals = vals[vals > 0]
    if len(vals):
        ax.set_ylim(vals.min() / 1.5, vals.max() * 1.5)
    ax.set_xlim(k[0], k[-1])
    for y, text, va in marks:
        ax.annotate(
            text,
            (0.995, y),
            xycoords=("axes fraction", "data"),
            ha="right",
            va=va,
            fontsize=8,
            color="tab:red",
            xytext=(0, -3 if va == "top" else 3),
            textcoords="offset points",
        )
    ax.set_xlabel("bearing stiffness (N/m)")
    ax.set_ylabel(f"{s.name} speed (rpm)")
    ax.set_title(
        f"{s.name}: undamped critical speed map (solid: a critical of {s.name}, forward "
        f"share ≥ {result.min_share:g}; dotted: the same mode elsewhere)",
        fontsize=10,
    )
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)


def plot_level1(result, path=None):
    """Level I: log dec of the followed mode (the first forward mode of the loaded shaft, see
    :mod:`gearrotor.analyses.audit.stability`) against the applied cross-coupling Q, the least log
    dec of every forward lateral mode beside it (dotted, where it is lower), Q_A, the threshold Q_0,
    the 0.1 acceptance line, and a shaded band where the followed mode's character changes."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.4, 4.8))
    q, d = result.curve_q, result.curve_log_dec
    shaft = getattr(result, "loaded_shaft", "") or "the loaded shaft"
    ax.plot(q, d, "C0.-", lw=1.6, label=f"first forward mode of {shaft} (followed)")
    least = np.asarray(getattr(result, "curve_least_log_dec", []), float)
    if least.size == q.size and np.any(least < d - 1e-9):
        lab = "least of every forward lateral mode"
        ax.plot(q, least, "C2:", marker=".", ms=4, lw=1.4, label=lab)
    for k, c in enumerate(getattr(result, "mode_changes", ())):
        ax.axvspan(
            c["q_from_N_per_m"],
            c["q_to_N_per_m"],
            color="C4",
            alpha=0.18,
            lw=0,
            label="followed mode changes: " + c["to"] if k == 0 else None,
        )
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axhline(
        result.criterion_log_dec,
        color="C3",
        ls="--",
        lw=1.0,
        label=f"log dec = {result.criterion_log_dec:g}",
    )
    ax.axvline(result.qa, color="C1", ls="--", lw=1.0)
    ax.plot(
        result.qa,
        result.log_dec_at_qa,
        "o",
        color="C1",
        label=f"Q_A = {result.qa:.4g} N/m, log dec {result.log_dec_at_qa:.3f}",
    )
    if result.threshold_q is not None:
        ax.plot(
            result.threshold_q,
            0.0,
            "s",
            mfc="none",
            mec="C3",
            ms=9,
            label=f"Q_0 = {result.threshold_q:.4g} N/m, Q_0/Q_A = {result.ratio:.2f}",
        )
    ax.set_xlabel("applied cross-coupled stiffness Q (N/m)")
    ax.set_ylabel("log decrement")
    ax.set_title(f"Level I stability ({result.edition}): {result.verdict}", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return _save(fig, path)


def plot_screening(result, path=None):
    """The critical speed ratio / average gas density screening chart with the machine's point
    (region A below the boundary, region B above). Without a gas density (a gearbox, a steam
    turbine given Q_A directly) the machine's CSR is drawn as a line across every density: its
    point lies on it, and the chart says the region is not evaluated."""
    from ..analyses.audit.stability import SCREENING_DENSITY_LIMIT, csr_boundary

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4.6))
    rho_max = max(80.0, 1.2 * (result.average_density or 0.0))
    rho = np.linspace(0.0, SCREENING_DENSITY_LIMIT, 200)
    ax.plot(rho, csr_boundary(rho), "k-", lw=1.8, label="region A / B boundary")
    ax.axvline(SCREENING_DENSITY_LIMIT, color="k", lw=1.0, ls=":")
    lo = min(1.0, 0.8 * result.csr) if result.csr is not None else 1.0
    hi = max(3.5, 1.15 * result.csr) if result.csr is not None else 3.5
    ax.text(8, lo + 0.55 * (2.0 - lo), "region A", fontsize=11, color="0.35")
    ax.text(8, 2.75 + 0.3 * (hi - 3.5), "region B", fontsize=11, color="0.35")
    if result.csr is not None and result.average_density is not None:
        ax.plot(
            result.average_density,
            result.csr,
            "o",
            color="C3",
            ms=8,
            label=f"CSR {result.csr:.2f} at {result.average_density:.3g} kg/m³ "
            f"(region {result.region})",
        )
    elif result.csr is not None:
        ax.axhline(
            result.csr,
            color="C3",
            ls="--",
            lw=1.2,
            label=f"CSR {result.csr:.2f}: no gas density given, region not evaluated",
        )
        ax.plot(0.0, result.csr, "o", color="C3", ms=8, clip_on=False)
    ax.set_xlim(0, rho_max)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("average gas density (kg/m³)")
    ax.set_ylabel("critical speed ratio MCS / N_c1,rigid")
    ax.set_title(f"Level I screening ({result.edition})", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    return _save(fig, path)


def plot_level2(result, path=None):
    """Level II: log dec of every mode against its frequency at each speed, forward and
    backward marked, with the acceptance line."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    for i, ev in enumerate(result.evaluations):
        f = np.array([m.frequency for m in ev.modes]) * RPM
        d = np.array([m.log_dec for m in ev.modes])
        fw = np.array([m.forward for m in ev.modes], bool)
        lab = f"{ev.speed * RPM:.0f} rpm"
        ax.plot(f[fw], d[fw], "o", color=f"C{i}", label=f"{lab} forward")
        ax.plot(f[~fw], d[~fw], "x", color=f"C{i}", label=f"{lab} other")
    ax.axhline(
        result.criterion_log_dec,
        color="C3",
        ls="--",
        lw=1.0,
        label=f"log dec = {result.criterion_log_dec:g}",
    )
    ax.axhline(0.0, color="k", lw=0.8)
    every = [m.log_dec for ev in result.evaluations for m in ev.modes]
    top = min(max(every) * 1.05, LEVEL2_TOP)
    ax.set_ylim(min(-0.2, min(every) - 0.1), max(top, 1.0))
    if max(every) > LEVEL2_TOP:
        ax.text(
            0.01,
            0.97,
            f"log dec > {LEVEL2_TOP:g}: above the chart",
            transform=ax.transAxes,
            fontsize=8,
            va="top",
            color="0.4",
        )
    ax.set_xlabel("damped frequency (rpm)")
    ax.set_ylabel("log decrement")
    ax.set_title(f"Level II stability ({result.edition}): {result.verdict}", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return _save(fig, path)
