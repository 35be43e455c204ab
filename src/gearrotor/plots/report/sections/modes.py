"""Modes section: the damped modes at the operating speed (:func:`gearrotor.analyses.modal`), the
table of modes, interactive 3-D mode shapes and the mode-shape PNGs.

:func:`mode_shape_figure` – 3-D deflected shaft lines of every shaft at the phase of the mode, a
dropdown over the modes and a slider over the phase (0–330° in 30° steps). Lateral deflection is
drawn to scale relative to the other modes (normalised shapes, max = 1, drawn as ``scale``
metres); torsion is drawn as a spoke at every node whose angle swings with the normalised
torsional surface displacement θz·r.
"""

from __future__ import annotations

import numpy as np

from ....analyses.lateral.modal import format_log_dec, format_zeta
from ..base import Context, Part, Section
from ..blocks import LOG_DEC_THRESHOLD, RPM, _color, _e, _figure_html, _go
from ..verdicts import model_undamped_kinds, status_row_class
from .stability import modal_statuses, summary_mode_names

__all__ = ["ModesSection", "mode_shape_figure", "shown_modes"]


class ModesSection(Section):
    analysis = "modal"
    default = True

    def run(self, ctx: Context) -> None:
        from ....analyses import modal

        ctx.results["modal"] = modal(
            ctx.assembly, speed=ctx.sign * ctx.speed, max_frequency=ctx.max_frequency
        )

    def write(self, ctx: Context) -> list[Part]:
        from ...figures import plot_mode_shape_pages

        res = ctx.results.get("modal")
        if res is None:
            return []
        status = modal_statuses(res, model_undamped_kinds(ctx.assembly, res.speed))
        d = res.to_dict()
        for row, st in zip(d["modes"], status, strict=True):
            row["status"] = st  # the words of the table, the stability checks and the figures
        ctx.summary["modal"] = d
        el = shown_modes(res, status, named=summary_mode_names(ctx))
        pages = [el[k : k + 8] for k in range(0, len(el), 8)]
        names = [f"modes_{i + 1}.png" for i in range(len(pages))]
        ctx.pngs(plot_mode_shape_pages, names, res, pages=pages, statuses=status)
        body = _modes_table(res, status)
        if el:
            body += _figure_html(mode_shape_figure(res, el, statuses=status), "fig-modes")
        else:
            body += (
                "<p>Every mode below the maximum frequency is over-damped: no shape to draw.</p>"
            )
        return [("modes", f"Modes at {res.speed * RPM:.0f} rpm", body)]


def shown_modes(
    res, status: list[str], first: int = 16, *, named: set[int] | frozenset[int] = frozenset()
) -> list[int]:
    """The modes the figures draw: the ``first`` elastic (not over-damped) modes, every later
    one with a status other than ``stable`` (low damping, unstable, not judged) and every mode
    ``named`` (the summary's lines name them: :func:`.stability.summary_mode_names`), in
    frequency order. Every mode the summary or the stability tables point at is drawn."""
    el = [i for i in range(len(res)) if not res.overdamped[i]]
    later = [i for i in el[first:] if status[i] != "stable" or i in named]
    return sorted(set(el[:first] + later) | {int(i) for i in named if 0 <= i < len(res)})


def _mode_title(result, m: int, statuses: list[str] | None = None) -> str:
    whirl = "/".join(result.whirl_per_shaft[m])
    if statuses is not None:
        state = statuses[m]
    else:
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
    statuses: list[str] | None = None,
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
    statuses : every mode's status (:mod:`~gearrotor.plots.report.verdicts`), shown in the
        title (default: stable or UNSTABLE)
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

    # The traces and the layout are built as plain dicts and the figure is made without
    # plotly's per-property validation (``_validate=False``): validating the ~400 traces and the
    # menus' visibility lists took 0.5 s of the flagship report; tests/report validate the
    # figure once (test_mode_shape_figure_is_valid_plotly).
    data: list[dict] = []
    # static traces: undeformed centre lines, bearings, gear nodes
    n_static = 0
    for k, s in enumerate(shafts):
        data.append(
            dict(
                type="scatter3d",
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
    n_static += _markers(data, bx, by, bz, bt, "bearings", symbol="diamond", size=5, color="black")
    gx, gy, gz, gt = [], [], [], []
    for mi in asm.meshes:
        for side in (0, 1):
            si = mi.shafts[side]
            node = int(np.flatnonzero(asm.node_offset[si] == mi.dofs[6 * side])[0])
            gx.append(pos[si, 0])
            gy.append(pos[si, 1])
            gz.append(shafts[si].z[node])
            gt.append(f"gear of mesh {mi.name} ({shafts[si].name} node {node})")
    n_static += _markers(
        data, gx, gy, gz, gt, "gears", symbol="circle-open", size=9, color="#555555"
    )

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
                # centre line, a gap, then one spoke per node (torsion): (centre, tip, gap)
                xs = _with_spokes(x, x + spoke * np.cos(ang))
                ys = _with_spokes(y, y + spoke * np.sin(ang))
                zs = _with_spokes(s.z, s.z)
                data.append(
                    dict(
                        type="scatter3d",
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
                    {"sliders": [slider_for(m)], "title.text": _mode_title(result, m, statuses)},
                ],
            )
        )
    layout = dict(
        title=dict(
            text=_mode_title(result, modes[0], statuses),
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
            xaxis=dict(title=dict(text="x (m)"), range=ranges[0], autorange=False),
            yaxis=dict(title=dict(text="y (m)"), range=ranges[1], autorange=False),
            zaxis=dict(title=dict(text="z (m)"), range=ranges[2], autorange=False),
            aspectmode="manual",
            aspectratio=aspect,
            camera=dict(eye=dict(x=0.95, y=0.6, z=-0.8), up=dict(x=0, y=1, z=0)),
        ),
        height=620,
        margin=dict(l=10, r=10, t=50, b=10),
        legend=dict(x=1.0, xanchor="right", y=1.0),
        meta=dict(kind="mode-shapes", modes=modes, n_phase=n_phase, scale_m=scale),
        # the report's template, as its dict (without validation a name stays a string)
        template=_template("plotly_white"),
    )
    return go.Figure(data=data, layout=layout, _validate=False)


def _template(name: str) -> dict:
    import plotly.io as pio

    return pio.templates[name].to_plotly_json()


def _with_spokes(centre, tip) -> list:
    """The coordinates of a deflected centre line and its spokes as one line trace: the
    centre line, a gap (None), then per node its centre, its spoke's tip and a gap (Python
    floats: plotly writes them without per-element conversion)."""
    n = len(centre)
    out = np.empty(n + 1 + 3 * n, dtype=object)
    out[:n] = np.asarray(centre, float).tolist()
    out[n + 1 :: 3] = out[:n]
    out[n + 2 :: 3] = np.asarray(tip, float).tolist()
    return out.tolist()


def _markers(data: list[dict], x, y, z, text, name: str, **marker) -> int:
    """Add a static trace of markers (hover: ``text``) when there are any; returns the number
    of traces added."""
    if not x:
        return 0
    data.append(
        dict(
            type="scatter3d",
            x=x,
            y=y,
            z=z,
            mode="markers",
            marker=dict(**marker),
            name=name,
            text=text,
            hoverinfo="text",
        )
    )
    return 1


def _modes_table(res, status: list[str]) -> str:
    head = (
        "<table><tr><th>#</th><th>frequency (cpm)</th><th>frequency (Hz)</th>"
        "<th>log dec</th><th>damping ratio</th><th>whirl "
        + _e("/".join(res.shaft_names))
        + "</th><th>type</th><th>energy share L / T / A (%)</th><th class='l'>status</th></tr>"
    )
    rows = [head]
    for i in range(len(res)):
        st = status[i]
        cls = status_row_class(st)
        fr = res.energy_shares[i] * 100
        rows.append(
            f"<tr class='{cls}'><td>{i}</td><td>{res.frequency_rpm[i]:.1f}</td>"
            f"<td>{res.frequency_hz[i]:.3f}</td><td>{format_log_dec(res.log_dec[i])}</td>"
            f"<td>{format_zeta(res.damping_ratio[i])}</td><td>{_e('/'.join(res.whirl_per_shaft[i]))}</td>"
            f"<td>{_e(res.mode_type[i])}</td><td>{fr[0]:.0f} / {fr[2]:.0f} / {fr[1]:.0f}</td>"
            f"<td class='l'>{_e(st)}</td></tr>"
        )
    rows.append("</table>")
    extra = (
        f"<p>{_e(res.counts_line())} (real eigenvalues are not listed). Whirl per shaft "
        "relative to that shaft's spin (F forward, B backward, – no lateral motion); type "
        "from energy shares (L lateral, T torsional, A axial: the larger of a group's kinetic "
        "and strain energy fractions, the mesh spring's energy shared by the groups that deflect "
        "it; a group with 5 % or more names the mode). Undamped: log dec zero to round-off. "
        f"Status: as in the stability checks (log dec ≥ {LOG_DEC_THRESHOLD} for the modes API "
        "617 Level II judges: forward whirl, at least half of the kinetic energy lateral, up to "
        "3× the fastest shaft speed; any growing mode fails; the other modes below the threshold "
        "are not judged, their status says why).</p>"
    )
    fd = res.frequency_dependence
    if fd is not None:  # speed × whirl tables (gearrotor.analyses.lateral.whirl)
        names = ", ".join(e["name"] for e in fd["elements"])
        misfit = max((e["max_misfit"] for e in fd["elements"]), default=0.0)
        extra += (
            f"<p>Frequency-dependent coefficients (speed × whirl tables: {_e(names)}): every "
            "mode with the coefficients at its own eigenvalue, through the rational fit of the "
            f"tables ({fd['states']} states added to the eigenproblem, largest misfit "
            f"{misfit:.2g}, {fd['eigensolves']} eigensolve). Type P: a mode of those states "
            "(the bearing or seal moves, the rotor barely), not judged as a lateral mode."
            + (
                f" {fd['modes_beyond_whirl_tables']} mode(s) above the tables' highest whirl "
                "frequency see the fit's continuation."
                if fd["modes_beyond_whirl_tables"]
                else ""
            )
            + "</p>"
        )
    return "\n".join(rows) + extra
