"""Interactive (plotly) figures for the HTML report.

Every function takes an analysis result and returns a ``plotly.graph_objects.Figure``; nothing is
shown or written here (:mod:`gearrotor.plots.report` assembles the page). plotly is imported
inside the functions, so importing this module needs nothing beyond numpy.

Units on the axes: speeds in rpm, frequencies in cpm, amplitudes in µm zero-to-peak, power in W.

* :func:`mode_shape_figure` – 3-D deflected shaft lines of every shaft at the phase of the mode,
  a dropdown over the modes and a slider over the phase (0–330° in 30° steps). Lateral
  deflection is drawn to scale relative to the other modes (normalised shapes, max = 1, drawn as
  ``scale`` metres); torsion is drawn as a spoke at every node whose angle swings with the
  normalised torsional surface displacement θz·r.
* :func:`campbell_figure`, :func:`bode_figure`, :func:`orbit_figure`: the linear analyses.
* :func:`bearing_coefficient_figure`: tabulated (fluid-film) bearing coefficients against speed.
* :func:`transient_spectrum_figure`, :func:`waterfall_figure`, :func:`whirl_power_figure`: a saved
  transient result (the ``xarray.Dataset`` of ``gearrotor.analyses.transient.load_result``).
* :func:`speed_waterfall_figure`: the waterfall against speed of a run-up or coast-down
  (:func:`gearrotor.plots.waterfall.speed_waterfall`) with the shaft-order lines.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "bearing_coefficient_figure",
    "bode_figure",
    "campbell_figure",
    "mode_shape_figure",
    "orbit_figure",
    "speed_waterfall_figure",
    "transient_spectrum_figure",
    "waterfall_figure",
    "whirl_power_figure",
    "waterfall_data",
]

RPM = 30 / np.pi  # rad/s -> rpm
COLORS = (
    "#1f77b4",
    "#d62728",
    "#2ca02c",
    "#9467bd",
    "#ff7f0e",
    "#17becf",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
)


def _go():
    import plotly.graph_objects as go

    return go


def _color(k: int) -> str:
    return COLORS[k % len(COLORS)]


# ---- mode shapes ---------------------------------------------------------------------------
def _mode_title(result, m: int) -> str:
    whirl = "/".join(result.whirl_per_shaft[m])
    state = "UNSTABLE" if result.unstable[m] else "stable"
    return (
        f"mode {m}: {result.frequency_rpm[m]:.1f} cpm ({result.frequency_hz[m]:.2f} Hz), "
        f"log dec {result.log_dec[m]:.3g}, whirl {whirl}, type {result.mode_type[m]}, {state}"
    )


def mode_shape_figure(
    result,
    modes: list[int] | None = None,
    *,
    n_phase: int = 12,
    scale: float | None = None,
    max_modes: int = 16,
):
    """3-D mode shapes of a :class:`~gearrotor.analyses.ModalResult`.

    Parameters
    ----------
    result : ModalResult
    modes : indices of the modes to offer (default: the first ``max_modes`` modes that are not
        over-damped)
    n_phase : number of phase steps over one period on the slider
    scale : drawn size (m) of a unit normalised deflection (default: 12 % of the longest shaft,
        at most 40 % of the smallest distance between shaft centres)
    """
    go = _go()
    asm = result.assembly
    layout = asm.train.layout()
    if modes is None:
        modes = [i for i in range(len(result)) if not result.overdamped[i]][:max_modes]
    modes = [int(m) for m in modes]
    if not modes:
        raise ValueError("no modes to draw (every mode is over-damped or none was found)")
    shafts = layout.shafts
    pos = np.array([s.position for s in shafts], float)
    if scale is None:
        length = max(float(np.ptp(s.z)) for s in shafts) or 1.0
        scale = 0.12 * length
        if len(shafts) > 1:
            d = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1)
            dmin = float(np.min(d[np.triu_indices(len(shafts), 1)]))
            if dmin > 0:
                scale = min(scale, 0.4 * dmin)
    spoke = 0.45 * scale
    swing = 0.8  # rad of spoke rotation for a unit normalised torsional displacement

    fig = go.Figure()
    # static traces: undeformed centre lines, bearings, gear nodes
    n_static = 0
    for k, s in enumerate(shafts):
        fig.add_trace(
            go.Scatter3d(
                x=np.full(len(s.z), pos[k, 0]),
                y=np.full(len(s.z), pos[k, 1]),
                z=s.z,
                mode="lines",
                line=dict(color="#bbbbbb", width=2, dash="dash"),
                name=f"{s.name} (undeformed)",
                hoverinfo="skip",
                showlegend=False,
            )
        )
        n_static += 1
    bx, by, bz, bt = [], [], [], []
    for b in asm.train.bearings:
        si, node = asm.train.node_index(b, "bearings")
        bx.append(pos[si, 0])
        by.append(pos[si, 1])
        bz.append(shafts[si].z[node])
        bt.append(f"bearing {getattr(b, 'name', '') or ''} ({shafts[si].name} node {node})")
    if bx:
        fig.add_trace(
            go.Scatter3d(
                x=bx,
                y=by,
                z=bz,
                mode="markers",
                marker=dict(symbol="diamond", size=5, color="black"),
                name="bearings",
                text=bt,
                hoverinfo="text",
            )
        )
        n_static += 1
    gx, gy, gz, gt = [], [], [], []
    for mi in asm.meshes:
        for side in (0, 1):
            si = mi.shafts[side]
            node = int(np.flatnonzero(asm.node_offset[si] == mi.dofs[6 * side])[0])
            gx.append(pos[si, 0])
            gy.append(pos[si, 1])
            gz.append(shafts[si].z[node])
            gt.append(f"gear of mesh {mi.name} ({shafts[si].name} node {node})")
    if gx:
        fig.add_trace(
            go.Scatter3d(
                x=gx,
                y=gy,
                z=gz,
                mode="markers",
                marker=dict(symbol="circle-open", size=9, color="#555555"),
                name="gears",
                text=gt,
                hoverinfo="text",
            )
        )
        n_static += 1

    # fixed axes (no rescaling while the phase moves), box proportional to the ranges
    reach = scale + spoke
    zmin = min(float(s.z.min()) for s in shafts)
    zmax = max(float(s.z.max()) for s in shafts)
    ranges = [
        [float(pos[:, 0].min()) - reach, float(pos[:, 0].max()) + reach],
        [float(pos[:, 1].min()) - reach, float(pos[:, 1].max()) + reach],
        [zmin - 0.02 * (zmax - zmin), zmax + 0.02 * (zmax - zmin)],
    ]
    span = np.array([r[1] - r[0] for r in ranges])
    ratio = np.maximum(span / span.max(), 0.25)
    aspect = dict(x=float(ratio[0]), y=float(ratio[1]), z=float(ratio[2]))

    phases = 2 * np.pi * np.arange(n_phase) / n_phase
    trace_index: dict[int, list[int]] = {}
    idx = n_static
    for m in modes:
        phi = result.mode_shapes[m]
        trace_index[m] = []
        for p_i, ph in enumerate(phases):
            rot = np.exp(1j * ph)
            for k, s in enumerate(shafts):
                offs = asm.node_offset[k]
                x = pos[k, 0] + scale * np.real(phi[offs] * rot)
                y = pos[k, 1] + scale * np.real(phi[offs + 1] * rot)
                tz = np.real(phi[offs + 5] * rot) * s.outer_radius
                ang = np.pi / 2 + swing * tz
                # centre line, a gap, then one spoke per node (torsion)
                xs = list(x) + [None]
                ys = list(y) + [None]
                zs = list(s.z) + [None]
                for j in range(len(s.z)):
                    xs += [x[j], x[j] + spoke * np.cos(ang[j]), None]
                    ys += [y[j], y[j] + spoke * np.sin(ang[j]), None]
                    zs += [s.z[j], s.z[j], None]
                fig.add_trace(
                    go.Scatter3d(
                        x=xs,
                        y=ys,
                        z=zs,
                        mode="lines",
                        line=dict(color=_color(k), width=5),
                        name=s.name,
                        legendgroup=s.name,
                        showlegend=True,  # only the visible phase appears in the legend
                        visible=(m == modes[0] and p_i == 0),
                        hovertemplate=f"{s.name}<br>z = %{{z:.3f}} m<extra></extra>",
                    )
                )
                trace_index[m].append(idx)
                idx += 1
    n_traces = idx

    def slider_for(m: int) -> dict:
        ids = trace_index[m]
        steps = []
        for p_i, ph in enumerate(phases):
            vis = [(j // len(shafts)) == p_i for j in range(len(ids))]
            steps.append(
                dict(
                    method="restyle",
                    label=f"{np.degrees(ph):.0f}°",
                    args=[{"visible": vis}, ids],
                )
            )
        return dict(
            active=0,
            currentvalue=dict(prefix="phase ω t = "),
            pad=dict(t=10, b=10),
            steps=steps,
            name=f"phase-mode-{m}",
        )

    buttons = []
    for m in modes:
        vis = [True] * n_static + [False] * (n_traces - n_static)
        for j in trace_index[m][: len(shafts)]:
            vis[j] = True
        buttons.append(
            dict(
                method="update",
                label=f"{m}: {result.frequency_rpm[m]:.0f} cpm {result.mode_type[m]}",
                args=[
                    {"visible": vis},
                    {"sliders": [slider_for(m)], "title.text": _mode_title(result, m)},
                ],
            )
        )
    fig.update_layout(
        title=dict(
            text=_mode_title(result, modes[0]),
            font=dict(size=13),
            x=0.01,
            xanchor="left",
            y=0.985,
            yanchor="top",
        ),
        updatemenus=[
            dict(
                buttons=buttons,
                direction="down",
                x=0.0,
                xanchor="left",
                y=1.0,
                yanchor="top",
                showactive=True,
            )
        ],
        annotations=[
            dict(
                text="mode (dropdown) and phase (slider); spokes show torsion",
                x=1.0,
                xanchor="right",
                y=0.0,
                yanchor="bottom",
                xref="paper",
                yref="paper",
                showarrow=False,
                font=dict(size=10, color="#666666"),
            )
        ],
        sliders=[slider_for(modes[0])],
        scene=dict(
            xaxis=dict(title="x (m)", range=ranges[0], autorange=False),
            yaxis=dict(title="y (m)", range=ranges[1], autorange=False),
            zaxis=dict(title="z (m)", range=ranges[2], autorange=False),
            aspectmode="manual",
            aspectratio=aspect,
            camera=dict(eye=dict(x=0.95, y=0.6, z=-0.8), up=dict(x=0, y=1, z=0)),
        ),
        height=620,
        margin=dict(l=10, r=10, t=50, b=10),
        legend=dict(x=1.0, xanchor="right", y=1.0),
        meta=dict(kind="mode-shapes", modes=modes, n_phase=n_phase, scale_m=scale),
    )
    return fig


# ---- Campbell --------------------------------------------------------------------------------
def campbell_figure(result, max_frequency: float | None = None):
    """Campbell diagram of a :class:`~gearrotor.analyses.CampbellResult`: tracked modes
    (colour = log dec, ● forward, ✕ backward whirl), excitation orders and crossings."""
    go = _go()
    fig = go.Figure()
    s = result.speeds * RPM
    f = result.damped_frequency * RPM
    for j in range(f.shape[1]):
        wh = np.asarray(result.whirl[:, j], dtype=str)
        ty = np.asarray(result.mode_type[:, j], dtype=str)
        ld = result.log_dec[:, j]
        fig.add_trace(
            go.Scatter(
                x=s,
                y=f[:, j],
                mode="lines+markers",
                line=dict(color="#bbbbbb", width=1),
                marker=dict(
                    color=np.clip(ld, -0.5, 3.0),
                    colorscale="Viridis",
                    reversescale=True,
                    cmin=-0.5,
                    cmax=3.0,
                    symbol=["circle" if w == "F" else "x" for w in wh],
                    size=7,
                    showscale=j == 0,
                    colorbar=dict(title=dict(text="log dec"), x=1.02) if j == 0 else None,
                ),
                name=f"mode {j}",
                customdata=np.column_stack([ld, wh, ty]),
                hovertemplate=(
                    f"mode {j}<br>speed %{{x:.0f}} rpm<br>frequency %{{y:.0f}} cpm"
                    "<br>log dec %{customdata[0]:.3g}<br>whirl %{customdata[1]}"
                    "<br>type %{customdata[2]}<extra></extra>"
                ),
                showlegend=False,
            )
        )
    for k, o in enumerate(result.orders):
        fig.add_trace(
            go.Scatter(
                x=s,
                y=result.order_frequency(o) * RPM,
                mode="lines",
                line=dict(dash="dash", width=1.5, color=_color(k)),
                name=o.label,
            )
        )
    if result.crossings:
        fig.add_trace(
            go.Scatter(
                x=[c.speed * RPM for c in result.crossings],
                y=[c.frequency * RPM for c in result.crossings],
                mode="markers",
                marker=dict(symbol="square-open", size=10, color="red"),
                name="crossings",
                text=[
                    f"mode {c.mode} × {c.order}: {c.speed * RPM:.0f} rpm, log dec "
                    f"{c.log_dec:.3g}, {c.whirl}, {c.mode_type}"
                    for c in result.crossings
                ],
                hoverinfo="text",
            )
        )
    top = max_frequency * RPM if max_frequency else float(np.nanmax(f)) * 1.05
    fig.update_layout(
        title="Campbell diagram (● forward, ✕ backward whirl; □ crossings)",
        xaxis=dict(title="reference shaft speed (rpm)", range=[s[0], s[-1]]),
        yaxis=dict(title="damped natural frequency (cpm)", range=[0, top]),
        height=560,
        legend=dict(x=0.01, y=0.99, bgcolor="rgba(255,255,255,0.7)"),
        meta=dict(kind="campbell"),
    )
    return fig


# ---- unbalance response ------------------------------------------------------------------------
def bode_figure(result):
    """Bode plot of an :class:`~gearrotor.analyses.UnbalanceResult`: amplitude (µm 0-pk, log)
    and phase lag at every probe, critical speeds with AF and margins, operating range and the
    API 617 limit (drawn as half the peak-to-peak limit)."""
    go = _go()
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=2, cols=1, shared_xaxes=True, row_heights=[0.65, 0.35])
    s = result.speeds * RPM
    for k, p in enumerate(result.probes):
        c = _color(k)
        fig.add_trace(
            go.Scatter(
                x=s,
                y=p.amplitude * 1e6,
                mode="lines",
                line=dict(color=c),
                name=p.name,
                legendgroup=p.name,
                hovertemplate=f"{p.name}<br>%{{x:.0f}} rpm<br>%{{y:.4g}} µm 0-pk<extra></extra>",
            ),
            row=1,
            col=1,
        )
        fig.add_trace(
            go.Scatter(
                x=s,
                y=np.unwrap(np.deg2rad(p.phase)) * 180 / np.pi,
                mode="lines",
                line=dict(color=c),
                name=p.name,
                legendgroup=p.name,
                showlegend=False,
                hovertemplate=f"{p.name}<br>%{{x:.0f}} rpm<br>%{{y:.1f}}°<extra></extra>",
            ),
            row=2,
            col=1,
        )
        if p.criticals:
            fig.add_trace(
                go.Scatter(
                    x=[cr.speed * RPM for cr in p.criticals],
                    y=[cr.amplitude * 1e6 for cr in p.criticals],
                    mode="markers",
                    marker=dict(symbol="triangle-down", size=10, color=c),
                    name=f"{p.name} criticals",
                    legendgroup=p.name,
                    showlegend=False,
                    text=[_critical_text(cr) for cr in p.criticals],
                    hoverinfo="text",
                ),
                row=1,
                col=1,
            )
    lo, hi = result.operating_range
    fig.add_vrect(
        x0=lo * RPM * 0.999,
        x1=hi * RPM * 1.001,
        fillcolor="green",
        opacity=0.15,
        line_width=0,
        row=1,
        col=1,
    )
    for lim in sorted({float(v) for v in np.atleast_1d(result.vibration_limit) if np.isfinite(v)}):
        fig.add_hline(
            y=lim / 2 * 1e6,
            line=dict(dash="dot", color="red", width=1),
            annotation_text=f"API 617 limit {lim * 1e6:.1f} µm pk-pk",
            annotation_position="top left",
            row=1,
            col=1,
        )
    amps = [p.amplitude[p.amplitude > 0] * 1e6 for p in result.probes]
    amps = np.concatenate(amps) if amps else np.array([])
    if amps.size:
        lims = [v / 2 * 1e6 for v in np.atleast_1d(result.vibration_limit) if np.isfinite(v)]
        lo = min(float(amps.min()), *lims) if lims else float(amps.min())
        hi = max(float(amps.max()), *lims) if lims else float(amps.max())
        fig.update_yaxes(range=[np.log10(lo) - 0.2, np.log10(hi) + 0.3], row=1, col=1)
    fig.update_yaxes(type="log", title_text="amplitude 0-pk (µm)", row=1, col=1)
    fig.update_yaxes(title_text="phase lag (deg)", row=2, col=1)
    fig.update_xaxes(title_text="reference shaft speed (rpm)", row=2, col=1)
    fig.update_layout(
        title="Unbalance response (▼ critical speeds; shaded: operating range)",
        height=640,
        meta=dict(kind="bode"),
    )
    return fig


def _critical_text(c) -> str:
    af = "not determined" if c.amplification_factor is None else f"{c.amplification_factor:.2f}"
    sm = "-" if c.separation_margin is None else f"{c.separation_margin:.1f} %"
    rq = "-" if c.required_margin is None else f"{c.required_margin:.1f} %"
    ok = {True: "pass", False: "FAIL", None: "n/a"}[c.ok]
    return (
        f"critical {c.speed * RPM:.0f} rpm<br>{c.amplitude * 1e6:.4g} µm 0-pk<br>AF {af}"
        f"<br>SM {sm} (required {rq}): {ok}"
    )


def _probe_nodes(result) -> list[tuple[int, int]]:
    train = result.assembly.train
    nodes: list[tuple[int, int]] = []
    for k, p in enumerate(train.probes):
        sn = train.node_index(p, f"probes[{k}]")
        if sn not in nodes:
            nodes.append(sn)
    return nodes


def orbit_figure(result, *, n_speeds: int = 25):
    """Orbits (µm) of the probe nodes of an unbalance sweep, with a slider over ``n_speeds``
    speeds of the sweep plus the maximum operating speed (the initial position)."""
    go = _go()
    nodes = _probe_nodes(result)
    t = np.linspace(0, 2 * np.pi, 121)
    n = len(result.speeds)
    k_op = int(np.argmin(np.abs(result.speeds - result.operating_range[1])))
    picks = sorted(set(np.linspace(0, n - 1, min(n_speeds, n)).round().astype(int)) | {k_op})
    data = {}
    for si, node in nodes:
        X, Y = result.node_response(si, node)
        data[(si, node)] = (X, Y)

    def xy(k):
        xs, ys = [], []
        for key in nodes:
            X, Y = data[key]
            xs.append(np.real(X[k] * np.exp(1j * t)) * 1e6)
            ys.append(np.real(Y[k] * np.exp(1j * t)) * 1e6)
        return xs, ys

    fig = go.Figure()
    xs, ys = xy(k_op)
    for j, (si, node) in enumerate(nodes):
        fig.add_trace(
            go.Scatter(
                x=xs[j],
                y=ys[j],
                mode="lines",
                line=dict(color=_color(j)),
                name=f"{result.shaft_names[si]} node {node}",
            )
        )
    # keyphasor dots (t = 0) as one trace
    fig.add_trace(
        go.Scatter(
            x=[x[0] for x in xs],
            y=[y[0] for y in ys],
            mode="markers",
            marker=dict(size=8, color=[_color(j) for j in range(len(nodes))]),
            name="keyphasor (t = 0)",
        )
    )
    steps = []
    for k in picks:
        xs, ys = xy(k)
        steps.append(
            dict(
                method="restyle",
                label=f"{result.speeds[k] * RPM:.0f}",
                args=[
                    {"x": xs + [[x[0] for x in xs]], "y": ys + [[y[0] for y in ys]]},
                    list(range(len(nodes) + 1)),
                ],
            )
        )
    fig.update_layout(
        title="Orbits of the probe nodes (● keyphasor)",
        xaxis=dict(title="x (µm)"),
        yaxis=dict(title="y (µm)", scaleanchor="x", scaleratio=1),
        sliders=[
            dict(
                active=picks.index(k_op),
                currentvalue=dict(prefix="reference speed (rpm): "),
                steps=steps,
                pad=dict(t=40),
            )
        ],
        height=620,
        meta=dict(kind="orbits"),
    )
    return fig


# ---- bearings ------------------------------------------------------------------------------------
def bearing_coefficient_figure(assembly):
    """Stiffness and damping coefficients against shaft speed of every tabulated (speed-dependent)
    bearing of an assembly; ``None`` when no bearing is tabulated."""
    go = _go()
    from plotly.subplots import make_subplots

    tab = [b for b in assembly.bearings if b.element.speed_dependent]
    if not tab:
        return None
    fig = make_subplots(rows=1, cols=2, subplot_titles=("stiffness (N/m)", "damping (N·s/m)"))
    names = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
    dashes = ("solid", "dash", "dot", "dashdot")
    for bi, b in enumerate(tab):
        t = b.element.table
        sp = t.speed * RPM
        for j, nm in enumerate(names):
            fig.add_trace(
                go.Scatter(
                    x=sp,
                    y=t.values[:, j],
                    mode="lines+markers",
                    line=dict(color=_color(j % 4 + 4 * bi), dash=dashes[bi % 4]),
                    name=f"{b.name}: {nm}",
                ),
                row=1,
                col=1 if j < 4 else 2,
            )
    fig.update_xaxes(title_text="journal speed (rpm)")
    fig.update_layout(
        title="Tabulated bearing coefficients", height=460, meta=dict(kind="bearings")
    )
    return fig


# ---- transient ---------------------------------------------------------------------------------
def _steady(t: NDArray, fraction: float = 0.5) -> NDArray:
    return t >= t[0] + (1 - fraction) * (t[-1] - t[0])


def _run_and_mesh_cpm(ds) -> tuple[float, float | None]:
    import json

    t = ds["time"].values
    sl = _steady(t)
    run = float(np.mean(np.abs(ds["shaft_speed"].values[sl, 0])) * RPM)
    mesh = None
    try:
        model = json.loads(ds.attrs["model_json"])
        if model.get("meshes"):
            mesh = float(model["meshes"][0]["gear"]["teeth"]) * run
    except (KeyError, ValueError, TypeError):
        mesh = None
    return run, mesh


def transient_spectrum_figure(ds, *, segments: int = 4, window: str = "hann"):
    """Averaged amplitude spectra (µm 0-pk, cpm) of x and y of every recorded node over the
    second half of a saved transient run, with 1x, 2x and mesh-frequency markers."""
    go = _go()
    from ..signals import spectrum

    t = ds["time"].values
    sl = _steady(t)
    dt = float(np.median(np.diff(t)))
    run, mesh = _run_and_mesh_cpm(ds)
    fig = go.Figure()
    for k, node in enumerate(ds["node"].values):
        for d, comp in enumerate(("x", "y")):
            f, a = spectrum(ds[comp].values[sl, k], dt, window=window, segments=segments)
            fig.add_trace(
                go.Scatter(
                    x=f,
                    y=np.maximum(a * 1e6, 1e-9),
                    mode="lines",
                    line=dict(width=1, color=_color(k), dash="solid" if d == 0 else "dot"),
                    name=f"{node} {comp}",
                    visible=True if d == 0 else "legendonly",
                )
            )
    lines = [(run, "1x"), (2 * run, "2x")]
    if mesh is not None:
        lines += [(mesh - run, ""), (mesh, "mesh ± 1x"), (mesh + run, "")]
    for fr, lab in lines:
        fig.add_vline(
            x=fr,
            line=dict(dash="dash" if lab else "dot", color="#888888", width=1),
            annotation_text=lab or None,
            annotation_position="top",
        )
    top = (mesh + 3 * run) if mesh is not None else 10 * run
    fig.update_layout(
        title=f"Spectra of the node displacements ({window} window, {segments} averages, "
        f"second half of the run; 1x = {run:.0f} cpm)",
        xaxis=dict(title="frequency (cpm)", range=[0, top]),
        yaxis=dict(title="amplitude 0-pk (µm)", type="log"),
        height=520,
        meta=dict(kind="transient-spectra"),
    )
    return fig


def waterfall_data(ds, *, node: int = 0, component: str = "x", n_slices: int = 24):
    """Spectra of consecutive time slices of one node's displacement.

    Returns ``(frequency_cpm (nf,), amplitude_m (n_slices, nf), time_s (n_slices,),
    speed_rpm (n_slices,))`` with the slice-centre time and the mean |speed| of shaft 0.
    """
    from ..signals import spectrum

    t = ds["time"].values
    x = ds[component].values[:, node]
    w = np.abs(ds["shaft_speed"].values[:, 0]) * RPM
    n = len(t)
    n_slices = max(1, min(n_slices, n // 16))
    edges = np.linspace(0, n, n_slices + 1).astype(int)
    dt = float(np.median(np.diff(t)))
    L = int(np.min(np.diff(edges)))
    amps, tc, sc = [], [], []
    f = None
    for a, _ in zip(edges[:-1], edges[1:], strict=True):
        f, amp = spectrum(x[a : a + L], dt, window="hann")
        amps.append(amp)
        tc.append(float(np.mean(t[a : a + L])))
        sc.append(float(np.mean(w[a : a + L])))
    return f, np.array(amps), np.array(tc), np.array(sc)


def waterfall_figure(ds, *, node: int = 0, component: str = "x", n_slices: int = 24):
    """Waterfall of one node's displacement spectrum over the run (µm 0-pk): one spectrum per
    time slice, against time (the slice's mean speed of shaft 0 is in the hover text)."""
    go = _go()
    f, amps, tc, sc = waterfall_data(ds, node=node, component=component, n_slices=n_slices)
    run, mesh = _run_and_mesh_cpm(ds)
    top = (mesh + 3 * run) if mesh is not None else 10 * run
    keep = f <= top
    fig = go.Figure()
    for i in range(len(tc)):
        fig.add_trace(
            go.Scatter3d(
                x=f[keep],
                y=np.full(int(keep.sum()), tc[i]),
                z=amps[i, keep] * 1e6,
                mode="lines",
                line=dict(color=amps[i, keep] * 1e6, colorscale="Viridis", width=3),
                name=f"t = {tc[i]:.3f} s",
                showlegend=False,
                hovertemplate=(
                    f"t = {tc[i]:.3f} s, {sc[i]:.0f} rpm<br>%{{x:.0f}} cpm<br>"
                    "%{z:.4g} µm<extra></extra>"
                ),
            )
        )
    node_name = str(ds["node"].values[node])
    fig.update_layout(
        title=f"Waterfall: {node_name} {component} (spectrum per time slice)",
        scene=dict(
            xaxis_title="frequency (cpm)",
            yaxis_title="time (s)",
            zaxis_title="amplitude 0-pk (µm)",
            aspectmode="manual",
            aspectratio=dict(x=1.6, y=1.0, z=0.6),
        ),
        height=600,
        margin=dict(l=10, r=10, t=60, b=10),
        meta=dict(kind="waterfall"),
    )
    return fig


def whirl_power_figure(ds, *, smooth: float = 0.01):
    """Whirl-promoting power P = Fx ẋ + Fy ẏ of every component (W, moving average over
    ``smooth`` s) and its mean over the second half of the run (bar: > 0 feeds, < 0 drains)."""
    go = _go()
    from plotly.subplots import make_subplots

    t = ds["time"].values
    dt = float(np.median(np.diff(t)))
    n = max(1, int(round(smooth / dt)))
    ker = np.ones(n) / n
    sl = _steady(t)
    names = [str(c) for c in ds["component"].values]
    P = ds["whirl_power"].values
    stride = max(1, len(t) // 4000)  # keep the page light: at most ~4000 points per line
    fig = make_subplots(
        rows=1,
        cols=2,
        column_widths=[0.68, 0.32],
        horizontal_spacing=0.12,
        subplot_titles=(f"{smooth * 1e3:.0f} ms moving average", "mean over the second half"),
    )
    means = []
    for k, name in enumerate(names):
        p = np.convolve(np.pad(P[:, k], (n // 2, n - 1 - n // 2), mode="edge"), ker, mode="valid")
        fig.add_trace(
            go.Scatter(
                x=t[::stride],
                y=p[::stride],
                mode="lines",
                line=dict(width=1.2, color=_color(k)),
                name=name,
            ),
            row=1,
            col=1,
        )
        means.append(float(np.mean(P[sl, k])))
    fig.add_trace(
        go.Bar(
            x=means,
            y=names,
            orientation="h",
            marker=dict(color=["#d62728" if m > 0 else "#1f77b4" for m in means]),
            showlegend=False,
            hovertemplate="%{y}: %{x:.4g} W<extra></extra>",
        ),
        row=1,
        col=2,
    )
    fig.update_xaxes(title_text="time (s)", row=1, col=1)
    fig.update_yaxes(title_text="power (W)", row=1, col=1)
    fig.update_xaxes(title_text="W (red feeds whirl, blue drains)", row=1, col=2)
    fig.update_layout(
        title="Whirl-promoting power by component", height=520, meta=dict(kind="whirl-power")
    )
    return fig


def speed_waterfall_figure(wf, *, max_frequency: float | None = None):
    """Waterfall against speed of a run-up or coast-down (a
    :class:`~gearrotor.plots.waterfall.SpeedWaterfall`): each window's spectrum on a baseline
    at its speed (rpm), amplitude upwards (µm 0-pk, the scale is in each panel's corner and in
    the hover text), front spectra hiding those behind; shaft orders (1x, 2x, mesh) as dashed
    lines f = order × speed. A panel for 1x/2x and one near the mesh frequency, as
    :func:`~gearrotor.plots.waterfall.plot_speed_waterfall`."""
    go = _go()
    from plotly.subplots import make_subplots

    from .waterfall import _bands, _gain, _order_lines

    bands = _bands(wf, max_frequency)
    fig = make_subplots(
        rows=1,
        cols=len(bands),
        shared_yaxes=True,
        horizontal_spacing=0.05,
        subplot_titles=[b[0] for b in bands],
    )
    f = wf.frequency_cpm
    back_to_front = np.argsort(wf.speed_rpm)[::-1]
    s = np.sort(wf.speed_rpm)
    shown: set[str] = set()
    for col, (_, lo, hi) in enumerate(bands, start=1):
        m = (f >= lo) & (f <= hi)
        fm = f[m]
        gain, peak = _gain(wf, m)
        for i in back_to_front:
            base = float(wf.speed_rpm[i])
            a = wf.amplitude[i, m]
            fig.add_trace(
                go.Scatter(
                    x=np.concatenate([fm, [fm[-1], fm[0]]]),
                    y=np.concatenate([base + gain * a, [base, base]]),
                    customdata=np.concatenate([a * 1e6, [0.0, 0.0]]),
                    mode="lines",
                    fill="toself",
                    fillcolor="white",
                    line=dict(color=COLORS[0], width=1),
                    showlegend=False,
                    hovertemplate=(
                        f"{base:.0f} rpm (t = {wf.time[i]:.3f} s)<br>%{{x:.0f}} cpm: "
                        "%{customdata:.3g} µm<extra></extra>"
                    ),
                ),
                row=1,
                col=col,
            )
        for k, lab, o, side in _order_lines(wf, lo, hi):
            group = wf.orders[k][0] + (" ± 1x" if side else "")
            fig.add_trace(
                go.Scatter(
                    x=o * s,
                    y=s,
                    mode="lines",
                    line=dict(
                        dash="dot" if side else "dash",
                        width=1 if side else 1.5,
                        color=_color(k + 1),
                    ),
                    name=lab if side else f"{lab} ({o:.4g} × {wf.shaft})",
                    legendgroup=group,
                    showlegend=bool(lab) and group not in shown,
                    hovertemplate=f"{o:.4g}x: %{{x:.0f}} cpm at %{{y:.0f}} rpm<extra></extra>",
                ),
                row=1,
                col=col,
            )
            shown.add(group)
        fig.update_xaxes(title_text="frequency (cpm)", range=[lo, hi], row=1, col=col)
        if gain > 0:
            xref = "x" if col == 1 else f"x{col}"
            yref = "y" if col == 1 else f"y{col}"
            xb = hi - 0.04 * (hi - lo)
            fig.add_shape(
                type="line",
                x0=xb,
                x1=xb,
                y0=float(s[-1]),
                y1=float(s[-1]) + gain * peak,
                xref=xref,
                yref=yref,
                line=dict(color="black", width=3),
            )
            fig.add_annotation(
                x=xb,
                y=float(s[-1]) + gain * peak,
                xref=xref,
                yref=yref,
                text=f"{peak * 1e6:.3g} µm",
                showarrow=False,
                xanchor="right",
                yanchor="bottom",
                font=dict(size=11),
            )
    fig.update_yaxes(title_text=f"speed of {wf.shaft} (rpm)", row=1, col=1)
    fig.update_layout(
        title=f"Waterfall against speed: {wf.signal} ({len(wf.time)} windows of "
        f"{wf.window_s * 1e3:.0f} ms, bin {wf.bin_cpm:.0f} cpm)",
        height=650,
        legend=dict(orientation="h", x=0.0, y=-0.14, yanchor="top"),
        margin=dict(b=110),
        meta=dict(kind="waterfall-speed"),
    )
    return fig
