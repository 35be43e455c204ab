"""Static figures of the linear analyses: mode shapes, Campbell diagram, Bode plots, orbits."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..files import make_directory, save_figure

__all__ = [
    "campbell_markers",
    "mode_shape_curves",
    "plot_bode",
    "plot_campbell",
    "plot_mode_shape_pages",
    "plot_mode_shapes",
    "plot_orbits",
    "place_labels",
]

RPM = 30 / np.pi


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path, tight: bool = True):
    """Write ``fig`` to ``path`` (when given) at 130 dpi, cropped to what is drawn (``tight``;
    a figure laid out to its edges saves without the extra layout pass)."""
    if path is not None:
        path = Path(path)
        make_directory(path.parent)  # (within an output set: removed with it on failure)
        save_figure(fig, path, dpi=130, **({"bbox_inches": "tight"} if tight else {}))
    return fig


def place_labels(ax, x, y, texts, *, color="k", fontsize: float = 7, avoid=()) -> list:
    """Label the points (x, y) (data coordinates of ``ax``, polar axes included) with
    ``texts`` so that no two labels overlap and no label covers a point: each label takes
    the first free place among offsets around its point, moving outwards (with a thin leader
    line when it had to move away). ``avoid``: more points (x, y) labels must not cover.
    Call it after the figure's layout is final (``tight_layout``; a constrained layout is
    executed first). Returns the annotations."""
    fig = ax.figure
    fig.canvas.draw()  # the final layout, and a renderer for the text extents
    renderer = fig.canvas.get_renderer()
    px = fig.dpi / 72.0  # pixels per point
    pts = ax.transData.transform(np.column_stack([np.asarray(x, float), np.asarray(y, float)]))
    more = [ax.transData.transform(np.asarray(p, float)[None, :])[0] for p in avoid]
    r = 3.5 * px  # a marker's half size
    taken = [
        (p[0] - r, p[1] - r, p[0] + r, p[1] + r) for p in [*pts, *more] if np.all(np.isfinite(p))
    ]
    for t in ax.texts:  # labels already placed (an earlier call): not covered either
        e = t.get_window_extent(renderer)
        taken.append((e.x0, e.y0, e.x1, e.y1))
    frame = ax.get_window_extent(renderer)
    out = []
    data = list(zip(np.asarray(x, float), np.asarray(y, float), strict=True))
    for (px0, py0), xy, text in zip(pts, data, texts, strict=True):
        if not np.all(np.isfinite(xy)):  # a point that is not drawn gets no label
            continue
        probe = ax.annotate(text, (0, 0), fontsize=fontsize)
        bb = probe.get_window_extent(renderer)
        probe.remove()
        w, h = bb.width, bb.height
        best = None
        for step in range(1, 9):
            d = (5 + 6 * (step - 1)) * px
            for dx, dy in (
                (d, d * 0.4),
                (d, -d * 0.4 - h),
                (-d - w, d * 0.4),
                (-d - w, -d * 0.4 - h),
                (-w / 2, d),
                (-w / 2, -d - h),
                (d, -h / 2),
                (-d - w, -h / 2),
            ):
                box = (px0 + dx, py0 + dy, px0 + dx + w, py0 + dy + h)
                inside = (
                    box[0] >= frame.x0
                    and box[2] <= frame.x1
                    and box[1] >= frame.y0
                    and box[3] <= frame.y1
                )
                free = not any(
                    box[0] < t[2] and t[0] < box[2] and box[1] < t[3] and t[1] < box[3]
                    for t in taken
                )
                if inside and free:
                    best = (dx, dy, box, step)
                    break
            if best is not None:
                break
        if best is None:  # nowhere free: the nearest place, as before
            best = (3 * px, 3 * px, (px0, py0, px0 + w, py0 + h), 1)
        dx, dy, box, step = best
        taken.append(box)
        out.append(
            ax.annotate(
                text,
                xy,
                xytext=(dx / px, dy / px),
                textcoords="offset points",
                ha="left",
                va="bottom",
                fontsize=fontsize,
                color=color,
                arrowprops=None
                if step == 1
                else dict(arrowstyle="-", lw=0.5, color=color, shrinkA=0, shrinkB=2),
            )
        )
    return out


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


def plot_mode_shapes(
    result,
    modes=None,
    path=None,
    max_modes: int = 8,
    orbit: bool = False,
    statuses: list[str] | None = None,
):
    """Mode shapes along every shaft (:func:`mode_shape_curves`): lateral (solid), torsional
    surface displacement θz·r (dashed), axial (dotted, when it shows), normalised as in the
    result (largest physical displacement = 1). Signed real parts by default; ``orbit=True``
    plots the orbit size (semi-major axis) instead. One legend for the figure names every kind
    of curve drawn in any panel, and the bearing and gear marks.

    ``modes``: indices to plot (default: the first ``max_modes`` that are not over-damped).
    ``statuses``: every mode's status (the report's words, e.g. ``stable``, ``no torsional
    damping in the model``), printed under the mode's numbers.
    """
    if modes is None:
        modes = [i for i in range(len(result)) if not result.overdamped[i]][:max_modes]
    fig = _mode_shape_page(result, len(modes))
    _draw_mode_shapes(fig, result, list(modes), orbit, statuses)
    return _save(fig, path, tight=False)


def plot_mode_shape_pages(
    result, pages: list[list[int]], paths: list, *, statuses: list[str] | None = None
) -> None:
    """:func:`plot_mode_shapes` of each page of modes into its path (the report's pages of 8):
    pages of the same number of modes are drawn on one figure, its axes kept and their curves
    replaced (the panels' ticks, made on the first draw, are most of a page's cost)."""
    plt = _plt()
    fig = None
    for modes, path in zip(pages, paths, strict=True):
        if fig is None or len(fig.axes) != len(modes) * len(result.assembly.train.shafts):
            if fig is not None:
                plt.close(fig)
            fig = _mode_shape_page(result, len(modes))
        else:
            for ax in fig.axes:
                for artist in [*ax.lines, *ax.texts]:
                    artist.remove()
            fig.legends.clear()
        _draw_mode_shapes(fig, result, list(modes), False, statuses)
        _save(fig, path, tight=False)
    if fig is not None:
        plt.close(fig)


def _mode_shape_page(result, n_modes: int):
    """The empty figure of :func:`plot_mode_shapes` for ``n_modes`` rows (one column per
    shaft), laid out in inches."""
    plt = _plt()
    ns = len(result.assembly.train.shafts)
    width, height = 4.2 * ns + 1.4, 2.1 * n_modes + 1.0
    # margins in inches, fixed (a constrained layout measured every tick label of every panel
    # three times: 0.5 s of the 0.8 s an 8-mode figure took): the row labels (4 lines of 8 pt
    # and the tick labels) on the left, the title and the column names on top, the axis label
    # and the legend below
    left, right, top, bottom, wgap, hgap = 1.05, 0.12, 0.62, 0.78, 0.42, 0.14
    fig, _ = plt.subplots(
        n_modes,
        ns,
        figsize=(width, height),
        squeeze=False,
        sharex="col",
        gridspec_kw=dict(
            left=left / width,
            right=1 - right / width,
            top=1 - top / height,
            bottom=bottom / height,
            wspace=wgap / ((width - left - right - wgap * (ns - 1)) / ns),
            hspace=hgap / ((height - top - bottom - hgap * (n_modes - 1)) / n_modes),
        ),
    )
    return fig


def _draw_mode_shapes(fig, result, modes: list[int], orbit: bool, statuses) -> None:
    """The curves, marks, labels and legend of :func:`plot_mode_shapes` on the axes of
    :func:`_mode_shape_page` (row per mode, column per shaft)."""
    from matplotlib.lines import Line2D

    asm = result.assembly
    layout = asm.train.layout()
    ns = len(layout.shafts)
    axes = np.array(fig.axes).reshape(len(modes), ns)
    height = fig.get_size_inches()[1]
    drawn = {"lateral"}  # the kinds of curve drawn somewhere, for the legend
    for row, m in enumerate(modes):
        for col, sl in enumerate(layout.shafts):
            ax = axes[row, col]
            offs = asm.node_offset[col]
            c = mode_shape_curves(result, m, col, orbit=orbit)
            z = c["z"]
            lat = "lateral orbit size" if orbit else "lateral"
            ax.plot(z, c["lateral"], "C0-", lw=1.8, label=lat)
            ax.plot(z, c["torsional"], "C3--", lw=1.5, label="torsional θz·r")
            if np.max(np.abs(c["torsional"])) > 0:
                drawn.add("torsional")
            if np.max(np.abs(c["axial"])) > 0.05:
                ax.plot(z, c["axial"], "C2:", lw=1.5, label="axial z")
                drawn.add("axial")
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
                st = f"\n{statuses[m]}" if statuses is not None else ""
                ax.set_ylabel(
                    f"mode {m}: {result.frequency_rpm[m]:.0f} cpm\nδ={result.log_dec[m]:.3g} "
                    f"{ws} {result.mode_type[m]}{st}\n"
                    + ("orbit size (max 1)" if orbit else f"Re({c['dir']}), θz·r (max 1)"),
                    fontsize=8,
                )
            if row == len(modes) - 1:
                ax.set_xlabel("axial position z (m)")
    lat = "lateral orbit size" if orbit else "lateral"
    handles = [
        Line2D([], [], color="C0", ls="-", lw=1.8, label=lat),
        Line2D([], [], color="C3", ls="--", lw=1.5, label="torsional θz·r"),
        Line2D([], [], color="C2", ls=":", lw=1.5, label="axial z"),
        Line2D([], [], color="k", marker="^", ls="none", ms=7, label="bearing"),
        Line2D([], [], color="0.6", lw=0.8, label="gear"),
    ]
    keep = (True, "torsional" in drawn, "axial" in drawn, True, bool(asm.meshes))
    kind = "orbit size" if orbit else "signed real part, largest component real"
    fig.suptitle(
        f"{asm.train.name}: mode shapes at {abs(result.speed) * RPM:.0f} rpm ({kind})",
        fontsize=10,
        y=1 - 0.08 / height,
        va="top",
    )
    fig.legend(
        handles=[h for h, k in zip(handles, keep, strict=True) if k],
        loc="lower center",
        bbox_to_anchor=(0.5, 0.02 / height),
        ncol=5,
        fontsize=8,
        frameon=False,
    )


def campbell_markers(
    result,
    max_frequency=None,
    operating_speed=None,
    max_continuous_speed=None,
    operating_range=None,
) -> dict:
    """What a Campbell diagram of ``result`` draws besides the tracked modes (shared by the PNG
    and the report's interactive figure): ``top`` (cpm, the frequency axis' end),
    ``orders`` ((order, its line in cpm) for the lines that reach into the axes; an order line
    above the axes over the whole sweep is neither drawn nor listed), ``off_scale`` (the labels
    of those), ``speeds`` ((label, rpm) of the operating speed and the MCS inside the sweep)
    and ``band`` (the operating range in rpm, or None)."""
    s = result.speeds * RPM
    f = result.damped_frequency * RPM
    top = max_frequency * RPM if max_frequency else float(np.nanmax(f)) * 1.05
    orders, off = [], []
    for o in result.orders:
        line = result.order_frequency(o) * RPM
        if np.min(line) < top:
            orders.append((o, line))
        else:
            off.append(o.label)
    lo, hi = s[0], s[-1]
    speeds = []
    for label, v in (("operating speed", operating_speed), ("MCS", max_continuous_speed)):
        if v is not None and lo <= abs(v) * RPM <= hi:
            speeds.append((f"{label} {abs(v) * RPM:,.0f} rpm", abs(v) * RPM))
    band = None
    if operating_range is not None and operating_range[1] > operating_range[0]:
        a, b = (max(lo, operating_range[0] * RPM), min(hi, operating_range[1] * RPM))
        band = (a, b) if b > a else None
    return {"top": top, "orders": orders, "off_scale": off, "speeds": speeds, "band": band}


def plot_campbell(
    result,
    path=None,
    max_frequency=None,
    *,
    operating_speed=None,
    max_continuous_speed=None,
    operating_range=None,
):
    """Campbell diagram: tracked damped frequencies (colour = log dec; ○ forward, × backward
    whirl), excitation lines and their crossings, the operating speed and the maximum
    continuous speed (rad/s, vertical lines; the operating range shaded). The legend sits below
    the axes, so it hides no marker, and lists only lines that reach into the axes (the
    off-scale orders are named under it).

    ``max_frequency`` (rad/s): the top of the frequency axis (default: 5 % above the highest
    tracked frequency)."""
    from matplotlib.lines import Line2D

    plt = _plt()
    fig, ax = plt.subplots(figsize=(8.5, 6.8))
    s = result.speeds * RPM
    f = result.damped_frequency * RPM
    ld = np.clip(result.log_dec, -0.5, 3.0)
    mk = campbell_markers(
        result, max_frequency, operating_speed, max_continuous_speed, operating_range
    )
    sc = None
    for j in range(f.shape[1]):
        ax.plot(s, f[:, j], color="0.75", lw=0.8, zorder=1)
        fw = result.whirl[:, j] == "F"
        for sel, marker, size in ((fw, "o", 12), (~fw, "x", 14)):
            sc = ax.scatter(
                s[sel],
                f[sel, j],
                c=ld[sel, j],
                cmap="viridis_r",
                vmin=-0.5,
                vmax=3.0,
                marker=marker,
                s=size,
                zorder=2,
            )
    handles = [
        Line2D([], [], color="0.4", marker="o", ls="none", mfc="none", label="forward whirl"),
        Line2D([], [], color="0.4", marker="x", ls="none", label="backward whirl"),
    ]
    for k, (o, line) in enumerate(mk["orders"]):
        (h,) = ax.plot(s, line, ls="--", lw=1, color=f"C{k % 10}", label=o.label)
        handles.append(h)
    if result.crossings:
        for c in result.crossings:
            ax.plot(c.speed * RPM, c.frequency * RPM, "rs", ms=5, mfc="none", zorder=3)
        handles.append(
            Line2D([], [], color="r", marker="s", ls="none", mfc="none", label="crossing")
        )
    if mk["band"] is not None:
        handles.append(ax.axvspan(*mk["band"], color="C2", alpha=0.12, label="operating range"))
    for (label, v), style in zip(mk["speeds"], ("-", ":"), strict=False):
        handles.append(ax.axvline(v, color="k", ls=style, lw=1.1, label=label))
    ax.set_ylim(0, mk["top"])
    ax.set_xlim(s[0], s[-1])
    ax.set_xlabel("reference shaft speed (rpm)")
    ax.set_ylabel("damped natural frequency (cpm)")
    ax.grid(alpha=0.3)
    if sc is not None:
        fig.colorbar(sc, ax=ax, label="log decrement")
    note = (
        "\norders above the axes, not drawn: " + ", ".join(mk["off_scale"])
        if mk["off_scale"]
        else ""
    )
    ax.set_title("Campbell diagram" + note, fontsize=10)
    fig.legend(
        handles=handles,
        loc="lower center",
        ncol=3,
        fontsize=7,
        frameon=False,
    )
    n_rows = -(-len(handles) // 3)
    fig.tight_layout(rect=(0, 0.02 + 0.024 * n_rows, 1, 1))
    return _save(fig, path, tight=False)  # laid out to the figure's edges


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
    return _save(fig, path, tight=False)  # laid out to the figure's edges


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
    return _save(fig, path, tight=False)  # laid out to the figure's edges
