"""Figures of the torsional analyses: mode shapes along the train, interference diagram, forced
response, transient torque and stress histories, fatigue damage per element."""

from __future__ import annotations

import numpy as np

from .figures import _plt, _save

__all__ = [
    "plot_torsional_modes",
    "plot_interference",
    "plot_torsional_response",
    "plot_torsional_transient",
    "plot_fatigue_damage",
]

RPM = 30 / np.pi


def plot_torsional_modes(result, modes=None, path=None, max_modes: int = 6):
    """Twist of every shaft along z per mode, referred to the reference shaft: θ / (Ω_s/Ω_ref)
    with the signed speed ratio of the mesh kinematics, so a rigid rotation of the train is
    uniform and a shape is continuous through a mesh; normalised to a largest value of 1; gear
    nodes dotted, the largest-stress element shaded."""
    plt = _plt()
    tm = result.model
    if modes is None:
        modes = list(result.elastic[:max_modes])
    modes = list(modes)
    fig, axes = plt.subplots(
        len(modes), 1, figsize=(8.5, 1.9 * len(modes) + 0.8), sharex=True, squeeze=False
    )
    ratio = tm.kinematic_ratio  # the meshes' radii: a rigid rotation is exactly flat
    for row, i in enumerate(modes):
        ax = axes[row, 0]
        ref = result.shapes[i] / ratio[tm.node_shaft]
        ref = ref / np.max(np.abs(ref))
        for s, name in enumerate(tm.shaft_names):
            idx = np.flatnonzero(tm.node_shaft == s)
            ax.plot(
                tm.node_z[idx],
                ref[idx],
                "o-",
                ms=3,
                lw=1.6,
                color=f"C{s}",
                label=name if row == 0 else None,
            )
        for k in range(len(tm.mesh_names)):
            for d in tm.mesh_dofs[k]:
                ax.axvline(tm.node_z[d], color="0.6", lw=0.8, ls=":")
        e = int(result.max_stress_element[i])
        if e >= 0:
            z = tm.node_z[tm.el_dofs[e]].mean()
            ax.axvspan(*tm.node_z[tm.el_dofs[e]], color="C3", alpha=0.25)
            ax.annotate("max τ", (z, 0.9), fontsize=7, color="C3", ha="center")
        ax.axhline(0, color="k", lw=0.6)
        ax.set_ylim(-1.15, 1.15)
        ax.grid(alpha=0.3)
        ax.set_ylabel(
            f"{result.frequency_hz[i]:.2f} Hz\nζ={result.damping_ratio[i]:.3f}", fontsize=8
        )
    axes[-1, 0].set_xlabel("z (m)")
    axes[0, 0].legend(fontsize=7, ncol=len(tm.shaft_names), loc="lower left")
    fig.suptitle(
        f"{tm.train.name}: torsional modes ({tm.mesh} meshes; twist referred to "
        f"{tm.train.reference}, ⋮ gear, shaded: largest shear stress)",
        fontsize=9,
    )
    fig.tight_layout()
    return _save(fig, path)


def plot_interference(result, path=None):
    """Interference diagram: natural frequencies with their ±margin bands, excitation lines,
    the operating range, and each listed crossing (○ passes, × fails the margin)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8.5, 6))
    tm = result.modes.model
    top = result.diagram_speed
    s = np.linspace(0, top, 200)
    lo, hi = result.speed_range
    for k, ln in enumerate(result.lines):
        f = result.line_frequency(ln, s) / (2 * np.pi)
        style = "-." if ln.kind == "fixed" else "--"
        ax.plot(s * RPM, f, style, lw=1.1, color=f"C{k % 10}", label=ln.label)
    modes_hz = result.modes.frequency_hz[result.modes.elastic]
    ytop = 1.1 * result.max_frequency / (2 * np.pi)
    m = result.required_margin
    for k, f in enumerate(modes_hz):
        if f > ytop:
            break
        ax.axhline(f, color="k", lw=1.0, label="natural frequency" if k == 0 else None)
        ax.axhspan(f / (1 + m), f / (1 - m) if m < 1 else f * 2, color="0.5", alpha=0.12)
        ax.annotate(f"{f:.1f} Hz", (top * RPM, f), fontsize=7, ha="right", va="bottom")
    # a line through the origin crossing a mode at speed s_c fails the margin when
    # |s_c / s − 1| < m somewhere in the range: s_c in (lo (1 − m), hi (1 + m))
    ax.axvspan(
        lo * RPM * (1 - m),
        hi * RPM * (1 + m),
        color="C2",
        alpha=0.08,
        label=f"crossings here fail the ±{m:.0%} margin",
    )
    ax.axvspan(lo * RPM, hi * RPM * 1.0005, color="C2", alpha=0.35, label=result.range_label)
    for c in result.crossings:
        if c.speed is None:
            continue
        ax.plot(
            c.speed * RPM,
            c.natural_frequency / (2 * np.pi),
            "o" if c.passes else "x",
            color="C2" if c.passes else "C3",
            ms=7,
            mew=2,
            mfc="none",
        )
    ax.set_xlim(0, top * RPM)
    ax.set_ylim(0, ytop)
    ax.set_xlabel(f"speed of {tm.train.reference} (rpm)")
    ax.set_ylabel("frequency (Hz)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", ncol=2)
    ax.set_title(
        f"Torsional interference diagram: {len(result.failures)} of {len(result.crossings)} "
        f"listed crossings inside the ±{m:.0%} margin",
        fontsize=10,
    )
    fig.tight_layout()
    return _save(fig, path)


def plot_torsional_response(result, path=None, n_elements: int = 4):
    """Alternating shear stress of the most stressed elements and dynamic against mean mesh
    force over the speed sweep."""
    plt = _plt()
    tm = result.model
    nm = len(tm.mesh_names)
    fig, axes = plt.subplots(
        1 + (nm > 0), 1, figsize=(8, 3.2 * (1 + (nm > 0))), sharex=True, squeeze=False
    )
    s = result.speeds * RPM
    labels = tm.element_labels()
    top = np.argsort(-result.element_stress.max(axis=0))[:n_elements]
    ax = axes[0, 0]
    for k in top:
        ax.plot(s, result.element_stress[:, k] / 1e6, label=labels[k])
    ax.set_ylabel("alternating shear stress\n0-pk (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    if nm:
        ax = axes[1, 0]
        for k, name in enumerate(tm.mesh_names):
            ax.plot(s, result.mesh_force[:, k] / 1e3, color=f"C{k}", label=f"{name} dynamic")
            if result.mean_mesh_force is not None:
                ax.axhline(
                    abs(result.mean_mesh_force[k]) / 1e3,
                    color=f"C{k}",
                    ls="--",
                    label=f"{name} mean (rated)",
                )
                lost = result.contact_loss[:, k]
                if lost.any():
                    ax.fill_between(
                        s,
                        0,
                        result.mesh_force[:, k] / 1e3,
                        where=lost,
                        color="C3",
                        alpha=0.3,
                        label="contact loss",
                    )
        ax.set_ylabel("mesh force (kN)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[-1, 0].set_xlabel(f"speed of {tm.train.reference} (rpm)")
    fig.suptitle("Torsional forced response", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def plot_torsional_transient(result, path=None, elements=None):
    """Speeds, drive and load torques, shaft torque (per unit of rated where known) of the most
    loaded element of each shaft, and the mesh force with its contact state."""
    plt = _plt()
    tm = result.model
    t = result.time
    nm = len(tm.mesh_names)
    n_ax = 3 + (nm > 0)
    fig, axes = plt.subplots(n_ax, 1, figsize=(9, 2.4 * n_ax + 0.5), sharex=True)
    ax = axes[0]
    for s, name in enumerate(tm.shaft_names):
        ax.plot(t, result.speed[:, s] * RPM, label=name, color=f"C{s}")
    for j in range(len(result.laws)):
        if not np.isnan(result.pull_in_time[j]) and result.pull_in_time[j] > 0:
            ax.axvline(result.pull_in_time[j], color="k", ls=":", lw=0.8)
            ax.annotate(" pull-in", (result.pull_in_time[j], 0), fontsize=7)
    ax.set_ylabel("speed (rpm)")
    ax.legend(fontsize=7, ncol=len(tm.shaft_names))
    ax = axes[1]
    for j, name in enumerate(result.laws.names):
        ax.plot(
            t,
            result.law_torque[:, j] / 1e3,
            lw=0.8,
            label=f"{name} ({'drive' if result.laws.is_drive[j] else 'load'})",
        )
    ax.set_ylabel("torque (kN·m)")
    ax.legend(fontsize=7)
    ax = axes[2]
    if elements is None:
        elements = []
        for s in range(len(tm.shaft_names)):
            idx = np.flatnonzero(tm.el_shaft == s)
            elements.append(int(idx[np.argmax(result.peak_element_torque[idx])]))
    labels = tm.element_labels()
    rated = result.rated_element_torque
    for e in elements:
        # per unit of the signed rated torque: +1 is the rated torque in every shaft, whichever
        # way the shaft turns and whichever end the power enters (the sign of GJ/L Δθ about
        # +z depends on both)
        r = rated[e] if rated is not None and abs(rated[e]) > 1e-6 * np.abs(rated).max() else None
        y = result.element_torque[:, e] / r if r else result.element_torque[:, e] / 1e3
        ax.plot(t, y, lw=0.8, label=f"{labels[e]}" + (" / rated" if r else " (kN·m)"))
    ax.set_ylabel("shaft torque\n(p.u. of rated)")
    ax.legend(fontsize=7)
    if nm:
        ax = axes[3]
        for k, name in enumerate(tm.mesh_names):
            ax.plot(t, result.mesh_force[:, k] / 1e3, lw=0.8, color=f"C{k}", label=name)
            off = result.mesh_state[:, k] != 1
            if off.any():
                ax.fill_between(
                    t,
                    0,
                    1,
                    where=off,
                    transform=ax.get_xaxis_transform(),
                    color="C3",
                    alpha=0.2,
                    label="off the drive flank",
                )
        ax.set_ylabel("mesh force (kN)")
        ax.legend(fontsize=7)
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(f"{tm.train.name}: torsional transient", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def plot_fatigue_damage(result, path=None):
    """Miner damage per event of every shaft element (log scale), with the allowable number of
    events of the governing element."""
    plt = _plt()
    tm = result.transient.model
    labels = tm.element_labels()
    fig, ax = plt.subplots(figsize=(max(6.0, 0.22 * len(result.elements) + 2), 4))
    d = np.where(result.damage > 0, result.damage, np.nan)
    colors = [f"C{tm.el_shaft[e]}" for e in result.elements]
    ax.bar(np.arange(len(d)), d, color=colors)
    ax.set_yscale("log")
    ax.set_xticks(np.arange(len(d)), [labels[e] for e in result.elements], rotation=90, fontsize=6)
    ax.set_ylabel("Miner damage per event")
    ax.grid(alpha=0.3, axis="y")
    g = result.governing
    n = result.allowable_starts
    ax.set_title(
        f"Fatigue damage per event: governing {labels[result.elements[g]]}, allowable events "
        f"{'unlimited' if np.isinf(n) else f'{n:.3g}'}",
        fontsize=10,
    )
    fig.tight_layout()
    return _save(fig, path)
