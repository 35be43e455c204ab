"""Static figures of the linear analyses: mode shapes, Campbell diagram, Bode plots, orbits."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..files import make_directory, save_figure

__all__ = ["mode_shape_curves", "plot_mode_shapes", "plot_campbell", "plot_bode", "plot_orbits"]

RPM = 30 / np.pi


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path):
    if path is not None:
        path = Path(path)
        make_directory(path.parent)  # (within an output set: removed with it on failure)
        save_figure(fig, path, dpi=130, bbox_inches="tight")
    return fig


def mode_shape_curves(result, m: int, shaft: int, orbit: bool = False) -> dict:
    """The curves :func:`plot_mode_shapes` draws for mode ``m`` on shaft ``shaft``.

    Signed (default): the complex shape, normalised with its largest physical component real
    (the result's normalisation), taken by its real part: lateral in the direction (x or y)
    holding the mode's largest lateral component, torsional θz·r, axial z. A second bending
    mode is an S, not a V. ``orbit=True``: the orbit's semi-major axis (≥ 0) instead of the
    signed lateral curve, and |θz|·r, |z|.
    """
    asm = result.assembly
    sl = asm.train.layout().shafts[shaft]
    phi = result.mode_shapes[m]
    offs = asm.node_offset[shaft]
    X, Y = phi[offs], phi[offs + 1]
    if orbit:
        lateral = 0.5 * (np.abs(X + 1j * Y) + np.abs(X - 1j * Y))
        tors, axial = np.abs(phi[offs + 5]) * sl.outer_radius, np.abs(phi[offs + 2])
        direction = "orbit"
    else:
        allx = np.concatenate([phi[o] for o in asm.node_offset])
        ally = np.concatenate([phi[o + 1] for o in asm.node_offset])
        use_y = np.max(np.abs(ally), initial=0.0) > np.max(np.abs(allx), initial=0.0)
        lateral = (Y if use_y else X).real
        tors, axial = phi[offs + 5].real * sl.outer_radius, phi[offs + 2].real
        direction = "y" if use_y else "x"
    return {"z": sl.z, "lateral": lateral, "torsional": tors, "axial": axial, "dir": direction}


def plot_mode_shapes(result, modes=None, path=None, max_modes: int = 8, orbit: bool = False):
    """Mode shapes along every shaft (:func:`mode_shape_curves`): lateral (solid), torsional
    surface displacement θz·r (dashed), axial (dotted, when it shows), normalised as in the
    result (largest physical displacement = 1). Signed real parts by default; ``orbit=True``
    plots the orbit size (semi-major axis) instead.

    ``modes``: indices to plot (default: the first ``max_modes`` that are not over-damped).
    """
    plt = _plt()
    asm = result.assembly
    layout = asm.train.layout()
    if modes is None:
        modes = [i for i in range(len(result)) if not result.overdamped[i]][:max_modes]
    modes = list(modes)
    ns = len(layout.shafts)
    fig, axes = plt.subplots(
        len(modes),
        ns,
        figsize=(4.2 * ns + 1.4, 2.1 * len(modes) + 0.6),
        squeeze=False,
        sharex="col",
    )
    for row, m in enumerate(modes):
        for col, sl in enumerate(layout.shafts):
            ax = axes[row, col]
            offs = asm.node_offset[col]
            c = mode_shape_curves(result, m, col, orbit=orbit)
            z = c["z"]
            lat = "lateral orbit size" if orbit else "lateral"
            ax.plot(z, c["lateral"], "C0-", lw=1.8, label=lat)
            ax.plot(z, c["torsional"], "C3--", lw=1.5, label="torsional θz·r")
            if np.max(np.abs(c["axial"])) > 0.05:
                ax.plot(z, c["axial"], "C2:", lw=1.5, label="axial z")
            for b in asm.train.bearings:
                if b.shaft == sl.name:
                    _, node = asm.train.node_index(b, "bearings")
                    ax.plot(z[node], 0, "k^", ms=7)
            for mi in asm.meshes:
                for side in (0, 1):
                    if mi.shafts[side] == col:
                        node = int(np.flatnonzero(offs == mi.dofs[6 * side])[0])
                        ax.axvline(z[node], color="0.6", lw=0.8)
            ax.set_ylim(-0.05 if orbit else -1.1, 1.1)
            ax.axhline(0.0, color="0.3", lw=0.6)
            ax.grid(alpha=0.3)
            if row == 0:
                ax.set_title(sl.name)
            if col == 0:
                ws = "/".join(result.whirl_per_shaft[m])
                ax.set_ylabel(
                    f"mode {m}: {result.frequency_rpm[m]:.0f} rpm\nδ={result.log_dec[m]:.3g} "
                    f"{ws} {result.mode_type[m]}\n"
                    + ("orbit size (max 1)" if orbit else f"Re({c['dir']}), θz·r (max 1)"),
                    fontsize=8,
                )
            if row == len(modes) - 1:
                ax.set_xlabel("axial position z (m)")
    axes[0, -1].legend(loc="upper right", fontsize=7)
    kind = "orbit size" if orbit else "signed real part, largest component real"
    fig.suptitle(
        f"{asm.train.name}: mode shapes at {result.speed * RPM:.0f} rpm ({kind}; "
        "▲ bearing, | gear)",
        fontsize=10,
        y=1.0,
    )
    fig.tight_layout()
    return _save(fig, path)


def plot_campbell(result, path=None, max_frequency=None):
    """Campbell diagram: tracked damped frequencies (colour = log dec; ○ forward, × backward
    whirl), excitation lines and their crossings."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    s = result.speeds * RPM
    f = result.damped_frequency * RPM
    ld = np.clip(result.log_dec, -0.5, 3.0)
    sc = None
    for j in range(f.shape[1]):
        ax.plot(s, f[:, j], color="0.75", lw=0.8, zorder=1)
        fw = result.whirl[:, j] == "F"
        sc = ax.scatter(
            s[fw],
            f[fw, j],
            c=ld[fw, j],
            cmap="viridis_r",
            vmin=-0.5,
            vmax=3.0,
            marker="o",
            s=12,
            zorder=2,
        )
        ax.scatter(
            s[~fw],
            f[~fw, j],
            c=ld[~fw, j],
            cmap="viridis_r",
            vmin=-0.5,
            vmax=3.0,
            marker="x",
            s=14,
            zorder=2,
        )
    top = max_frequency * RPM if max_frequency else np.nanmax(f) * 1.05
    for k, o in enumerate(result.orders):
        line = result.order_frequency(o) * RPM
        ax.plot(s, line, ls="--", lw=1, color=f"C{k % 10}", label=o.label)
    for c in result.crossings:
        ax.plot(c.speed * RPM, c.frequency * RPM, "rs", ms=5, mfc="none")
    ax.set_ylim(0, top)
    ax.set_xlim(s[0], s[-1])
    ax.set_xlabel("reference shaft speed (rpm)")
    ax.set_ylabel("damped natural frequency (cpm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    if sc is not None:
        fig.colorbar(sc, ax=ax, label="log decrement (○ forward, × backward)")
    ax.set_title("Campbell diagram (□ crossings)")
    fig.tight_layout()
    return _save(fig, path)


def plot_bode(result, path=None, probes=None):
    """Bode plot (amplitude 0-pk in µm and phase lag) at every probe, with the critical speeds
    (▼, their amplification factors in the legend), the API 617 limit (drawn at half its
    peak-to-peak value, on the 0-pk axis) and the operating range."""
    plt = _plt()
    probes = result.probes if probes is None else probes
    fig, (a1, a2) = plt.subplots(
        2, 1, figsize=(8, 6.5), sharex=True, gridspec_kw={"height_ratios": [2, 1]}
    )
    s = result.speeds * RPM
    for k, p in enumerate(probes):
        # the critical speeds' AF go into the legend: annotations of close peaks overlapped
        crit = [
            f"{c.speed * RPM:.0f} rpm AF {c.amplification_factor:.1f}"
            for c in p.criticals
            if c.amplification_factor is not None
        ]
        label = p.name + (f" (▼ {', '.join(crit)})" if crit else "")
        a1.plot(s, p.amplitude * 1e6, color=f"C{k}", label=label)
        a2.plot(s, np.unwrap(np.deg2rad(p.phase)) * 180 / np.pi, color=f"C{k}")
        for c in p.criticals:
            a1.plot(c.speed * RPM, c.amplitude * 1e6, "v", color=f"C{k}")
    for lim in sorted({float(v) for v in np.atleast_1d(result.vibration_limit) if np.isfinite(v)}):
        a1.axhline(
            lim / 2 * 1e6,
            color="k",
            ls="--",
            lw=0.8,
            label=f"API 617 limit {lim * 1e6:.1f} µm pk-pk (½)",
        )
    lo, hi = result.operating_range
    a1.axvspan(lo * RPM * 0.999, hi * RPM * 1.001, color="C2", alpha=0.2, label="operating")
    a1.set_ylabel("amplitude 0-pk (µm)")
    a1.set_yscale("log")
    a1.grid(alpha=0.3, which="both")
    a1.legend(fontsize=7, loc="lower right")
    a2.set_ylabel("phase lag (deg)")
    a2.set_xlabel("reference shaft speed (rpm)")
    a2.grid(alpha=0.3)
    a1.set_title("Unbalance response")
    fig.tight_layout()
    return _save(fig, path)


def plot_orbits(result, speed_index: int, path=None):
    """Orbits of the probes' nodes at one speed of an unbalance sweep (µm)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    t = np.linspace(0, 2 * np.pi, 200)
    asm = result.assembly
    nodes: list[tuple[int, int]] = []
    for k, p in enumerate(asm.train.probes):
        sn = asm.train.node_index(p, f"probes[{k}]")
        if sn not in nodes:
            nodes.append(sn)
    for si, node in nodes:
        X, Y = result.node_response(si, node)
        x = np.real(X[speed_index] * np.exp(1j * t)) * 1e6
        y = np.real(Y[speed_index] * np.exp(1j * t)) * 1e6
        ax.plot(x, y, label=f"{result.shaft_names[si]} node {node}")
        ax.plot(x[0], y[0], "o", color=ax.lines[-1].get_color())
    ax.set_aspect("equal")
    ax.set_xlabel("x (µm)")
    ax.set_ylabel("y (µm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Orbits at {result.speeds[speed_index] * RPM:.0f} rpm (● keyphasor)")
    fig.tight_layout()
    return _save(fig, path)
