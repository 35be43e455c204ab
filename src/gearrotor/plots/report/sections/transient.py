"""Transient section: a saved transient result (NetCDF of
:meth:`~gearrotor.analyses.transient.TransientResult.save`; the report reads it, it does not run
the solver): 1x/2x amplitudes per node, speed and mesh-force ranges, spectra, a waterfall over
time, for a run-up or coast-down a waterfall against speed
(:func:`gearrotor.plots.waterfall.speed_waterfall`), and the whirl-promoting power by component;
interactive (plotly) and as PNG."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ....errors import ModelError
from ....signals import order_amplitudes, spectrum
from ..base import Context, Part, Section
from ..blocks import COLORS, RPM, _color, _e, _figure_html, _fmt, _go, _mpl_figure, _savefig

__all__ = [
    "TransientSection",
    "plot_waterfall",
    "speed_waterfall_figure",
    "transient_spectrum_figure",
    "waterfall_data",
    "waterfall_figure",
    "whirl_power_figure",
]


class TransientSection(Section):
    analysis = "transient"

    def check(self, ctx: Context) -> None:
        ctx.results["transient"] = _read_transient(ctx.transient_file)

    def write(self, ctx: Context) -> list[Part]:
        ds = ctx.results.get("transient")
        if ds is None:  # (before the imports: the transient package compiles its kernels)
            return []
        from ....analyses.transient import plots as tplots
        from ...waterfall import plot_speed_waterfall, speed_varies, speed_waterfall

        for name, fn in (
            ("transient_spectra.png", tplots.plot_spectra),
            ("transient_whirl_power.png", tplots.plot_whirl_power),
        ):
            ctx.save(fn(ds), name)
        ctx.save(plot_waterfall(ds), "transient_waterfall.png")
        wf = speed_waterfall(ds) if speed_varies(ds) else None
        if wf is not None:
            plot_speed_waterfall(wf, path=ctx.directory / "transient_waterfall_speed.png")
            ctx.figures.append(ctx.directory / "transient_waterfall_speed.png")
        tsum = _transient_summary(ds)
        if wf is not None:
            tsum["waterfall_vs_speed"] = wf.to_dict()
        ctx.summary["transient"] = tsum
        body = _transient_html(tsum, ctx.transient_file)
        body += _figure_html(transient_spectrum_figure(ds), "fig-spectra")
        body += _figure_html(waterfall_figure(ds), "fig-waterfall")
        if wf is not None:
            body += _speed_waterfall_html(wf)
            body += _figure_html(speed_waterfall_figure(wf), "fig-waterfall-speed")
        body += _figure_html(whirl_power_figure(ds), "fig-whirl-power")
        return [("transient", "Transient", body)]


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

    from ...waterfall import _bands, _gain, _order_lines

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
        gain, peak, note = _gain(wf, m)
        if note:
            xref = "x domain" if col == 1 else f"x{col} domain"
            yref = "y domain" if col == 1 else f"y{col} domain"
            fig.add_annotation(
                x=0.5,
                y=0.99,
                xref=xref,
                yref=yref,
                text=note,
                showarrow=False,
                yanchor="top",
                bgcolor="rgba(255,255,255,0.9)",
                font=dict(size=11),
            )
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


def plot_waterfall(ds, *, node: int = 0, component: str = "x", n_slices: int = 24, path=None):
    """Waterfall (matplotlib) of one node's displacement spectrum over a saved transient run:
    one spectrum (µm 0-pk, cpm) per time slice, offset by the slice time. Returns the Figure."""
    f, amps, tc, sc = waterfall_data(ds, node=node, component=component, n_slices=n_slices)
    run, mesh = _run_and_mesh_cpm(ds)
    top = (mesh + 3 * run) if mesh is not None else 10 * run
    keep = f <= top
    fig = _mpl_figure((10, 6))
    ax = fig.add_subplot(projection="3d")
    for i in range(len(tc)):
        ax.plot(
            f[keep],
            np.full(int(keep.sum()), tc[i]),
            amps[i, keep] * 1e6,
            lw=0.7,
            color=f"C{i % 10}",
        )
    ax.set_xlabel("frequency (cpm)")
    ax.set_ylabel("time (s)")
    ax.set_zlabel("amplitude 0-pk (µm)")
    ax.set_title(f"Waterfall: {ds['node'].values[node]} {component}")
    if path is not None:
        _savefig(fig, Path(path))
    return fig


def _read_transient(path):
    from ....analyses.transient import load_result

    path = Path(path)
    try:
        ds = load_result(path)
    except ModelError:
        raise
    except (OSError, ValueError, KeyError) as exc:
        raise ModelError(
            f"cannot read the transient result ({type(exc).__name__}: {exc})",
            file=str(path),
            expected="a NetCDF file written by the transient analysis",
        ) from None
    need = ("time", "x", "y", "node", "shaft_speed", "whirl_power", "component")
    missing = [v for v in need if v not in ds.variables]
    if missing:
        raise ModelError(
            "not a gearrotor transient result",
            file=str(path),
            value=f"missing {', '.join(missing)}",
            expected="a NetCDF file written by the transient analysis",
        )
    if ds.sizes.get("time", 0) < 64 or ds.sizes.get("node", 0) < 1:
        raise ModelError(
            "the transient result is too short for spectra",
            file=str(path),
            value=f"{ds.sizes.get('time', 0)} samples, {ds.sizes.get('node', 0)} nodes",
            expected="at least 64 time samples and one recorded node",
        )
    return ds


def _transient_summary(ds) -> dict:
    t = ds["time"].values
    half = t >= t[0] + 0.5 * (t[-1] - t[0])
    out: dict = {
        "t_start_s": float(t[0]),
        "t_end_s": float(t[-1]),
        "samples": int(len(t)),
        "status": ds.attrs.get("status"),
        "nodes": {},
        "shafts": {},
        "meshes": {},
        "whirl_power_mean_W": {},
    }
    speed = ds["shaft_speed"].values
    for k, node in enumerate(ds["node"].values):
        si = int(ds["node_shaft"].values[k]) if "node_shaft" in ds else 0
        amps = {
            c: order_amplitudes(t[half], ds[c].values[half, k], speed[half, si]) for c in ("x", "y")
        }
        out["nodes"][str(node)] = {
            f"{c}_{n}x_um": float(amps[c][n - 1]) * 1e6 for c in ("x", "y") for n in (1, 2)
        }
    for k, name in enumerate(ds["shaft"].values):
        rpm = np.abs(speed[:, k]) * RPM
        out["shafts"][str(name)] = {
            "speed_min_rpm": float(rpm.min()),
            "speed_max_rpm": float(rpm.max()),
        }
    if "mesh" in ds.dims and "mesh_force" in ds and "contact" in ds:
        from ....analyses.transient.results import dataset_mesh_extremes

        ext = dataset_mesh_extremes(ds)  # every step (the step envelope), or the samples
        for k, name in enumerate(ds["mesh"].values):
            out["meshes"][str(name)] = {
                "force_min_N": float(ext.least[k]),
                "force_max_N": float(ext.largest[k]),
                "contact_loss_fraction": float(ext.loss[k]),
            }
    elif "mesh" in ds.dims and "mesh_force" in ds:
        for k, name in enumerate(ds["mesh"].values):
            f = ds["mesh_force"].values[:, k]
            out["meshes"][str(name)] = {
                "force_min_N": float(f.min()),
                "force_max_N": float(f.max()),
            }
    P = ds["whirl_power"].values
    for k, name in enumerate(ds["component"].values):
        out["whirl_power_mean_W"][str(name)] = float(np.mean(P[half, k]))
    return out


def _transient_html(tsum: dict, path) -> str:
    parts = [
        f"<p>Result file <code>{_e(Path(path).name)}</code>: "
        f"{tsum['t_start_s']:.4g}..{tsum['t_end_s']:.4g} s, {tsum['samples']} samples, "
        f"status {_e(tsum['status'])}. Amplitudes by least squares over the second half "
        "of the run at each node's mean shaft speed.</p>",
        "<table><tr><th class='l'>node</th><th>x 1x (µm)</th><th>y 1x (µm)</th>"
        "<th>x 2x (µm)</th><th>y 2x (µm)</th></tr>",
    ]
    for n, a in tsum["nodes"].items():
        parts.append(
            f"<tr><td class='l'>{_e(n)}</td><td>{a['x_1x_um']:.4g}</td>"
            f"<td>{a['y_1x_um']:.4g}</td><td>{a['x_2x_um']:.4g}</td>"
            f"<td>{a['y_2x_um']:.4g}</td></tr>"
        )
    parts.append(
        "</table><table><tr><th class='l'>shaft</th><th>min speed (rpm)</th>"
        "<th>max speed (rpm)</th></tr>"
    )
    for n, a in tsum["shafts"].items():
        parts.append(
            f"<tr><td class='l'>{_e(n)}</td><td>{a['speed_min_rpm']:.2f}</td>"
            f"<td>{a['speed_max_rpm']:.2f}</td></tr>"
        )
    parts.append("</table>")
    if tsum["meshes"]:
        parts.append(
            "<table><tr><th class='l'>mesh</th><th>min force (N)</th>"
            "<th>max force (N)</th><th>contact loss (%)</th></tr>"
        )
        for n, a in tsum["meshes"].items():
            cl = a.get("contact_loss_fraction")
            parts.append(
                f"<tr><td class='l'>{_e(n)}</td><td>{a['force_min_N']:.1f}</td>"
                f"<td>{a['force_max_N']:.1f}</td>"
                f"<td>{_fmt(None if cl is None else 100 * cl, '.2f')}</td></tr>"
            )
        parts.append("</table>")
    return "\n".join(parts)


def _speed_waterfall_html(wf) -> str:
    lo, hi = wf.speed_rpm.min(), wf.speed_rpm.max()
    return (
        f"<h3 id='waterfall-speed'>Waterfall against speed</h3><p>The speed of {_e(wf.shaft)} "
        f"changes during the run ({lo:.0f}..{hi:.0f} rpm over the window centres): spectra of "
        f"{_e(wf.signal)} in {len(wf.time)} Hann windows of {wf.window_s * 1e3:.0f} ms (bin "
        f"{wf.bin_cpm:.0f} cpm), each drawn at its mean speed, with the shaft orders as dashed "
        "lines (" + ", ".join(f"{_e(k)} = {v:.4g}×" for k, v in wf.orders) + "). A ridge on a "
        "line is locked to the speed; a ridge at a constant frequency is a resonance the run "
        "sweeps through.</p>"
    )
