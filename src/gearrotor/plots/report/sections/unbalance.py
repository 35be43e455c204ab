"""Unbalance section: the unbalance response over 0.02..1.5× the operating speed
(:func:`gearrotor.analyses.unbalance_response`) with the model's unbalance or, ``api``, the API 617
unbalance of the edition the report uses (:attr:`~..base.Context.api_edition`: ``--edition``,
else the model's ``[api_audit] edition``, else the 8th): the 8th edition's 4 × 6350 W/N g·mm at
the model's planes (:func:`gearrotor.analyses.audit.api_unbalance.api617_unbalances`), the
9th edition's 2 × 6350 W/N g·mm at the antinodes of the reference shaft's first forward mode
(:func:`gearrotor.analyses.audit.api_unbalance.mode_unbalances`) with its close-clearance check
(:func:`gearrotor.analyses.audit.api_unbalance.clearance_check`; the clearances of
:func:`gearrotor.analyses.audit.api_unbalance.close_clearances`). Bode plot and orbits
(interactive and
PNG); then its checks, the API 684 separation margins, the API 617 vibration limit in the
operating range and the close clearances, a page part of their own and their verdicts."""

from __future__ import annotations

import numpy as np

from ....errors import ModelError
from ..base import Context, Part, Section
from ..blocks import RPM, _badge, _color, _e, _figure_html, _fmt, _go
from ..verdicts import _range_words

__all__ = ["UnbalanceSection", "bode_figure", "orbit_figure"]


class UnbalanceSection(Section):
    analysis = "unbalance"
    default = True

    def check(self, ctx: Context) -> None:
        train = ctx.train
        if not train.unbalances:
            raise ModelError(
                "the unbalance analysis needs an unbalance",
                field="unbalances",
                expected="at least one [[unbalances]] entry, or leave 'unbalance' "
                "out of --analyses",
            )
        if not train.probes:
            raise ModelError(
                "the unbalance analysis needs probes",
                field="probes",
                expected="at least one [[probes]] entry, or leave 'unbalance' out of --analyses",
            )

    def run(self, ctx: Context) -> None:
        from ....analyses import unbalance_response

        top = max(ctx.speed, ctx.api_range[1])
        speeds = ctx.sweep(0.02 * top, 1.5 * top, ctx.n_unbalance, "unbalance sweep")
        # the orbits at the operating range's top (the maximum continuous speed) itself
        ends = [v for v in ctx.api_range if speeds[0] <= v <= speeds[-1]]
        speeds = np.union1d(speeds, ends)
        ctx.results["unbalance"] = unbalance_response(
            ctx.assembly,
            speeds=speeds,
            unbalances=_unbalances(ctx),
            operating_range=ctx.api_range,
        )
        _clearances(ctx, speeds)

    def write(self, ctx: Context) -> list[Part]:
        from ...figures import plot_bode, plot_orbits

        unb = ctx.results.get("unbalance")
        if unb is None:
            return []
        used = _unbalances_used(ctx)
        checks = _api_checks(unb, ctx)
        checks["unbalance"] = used
        ctx.summary["api684"] = checks
        d = unb.to_dict()
        ctx.summary["unbalance"] = {
            "operating_range_rpm": d["operating_range_rpm"],
            "basis": used["basis"],
            "unbalances": used["planes"],
            "probes": [
                {k: v for k, v in p.items() if k not in ("amplitude_um", "phase_deg")}
                for p in d["probes"]
            ],
        }
        _verdicts(ctx, checks)
        ctx.png(plot_bode, "bode.png", unb)
        k_op = int(np.argmin(np.abs(unb.speeds - unb.operating_range[1])))
        ctx.png(plot_orbits, "orbits_operating.png", unb, k_op)
        body = _unbalance_intro(unb, used)
        body += _figure_html(bode_figure(unb), "fig-bode")
        body += _figure_html(orbit_figure(unb), "fig-orbits")
        return [
            ("unbalance", "Unbalance response", body),
            ("api684", "API 684 / API 617 checks", _api_html(checks)),
        ]


def _api_unbalance(ctx: Context) -> dict:
    """The unbalance the response uses (computed once, kept in ``ctx.results["api617"]``):
    ``unbalances`` (the model's, or the API 617 unbalance of :attr:`~..base.Context.api_edition`
    at the maximum continuous speed, the operating speed when the model states none),
    ``edition`` and, for the 9th edition, ``placement`` (its
    :class:`~gearrotor.analyses.audit.api_unbalance.ModeUnbalance`)."""
    got = ctx.results.get("api617")
    if got is not None:
        return got
    from ....analyses.audit.api_unbalance import api617_unbalances, mode_unbalances

    ed, placed = ctx.api_edition, None
    if not ctx.api:
        unb = list(ctx.train.unbalances)
    elif ed.key == "9th":
        placed = mode_unbalances(ctx.assembly, max_continuous_speed=ctx.api_range[1])
        unb = placed.unbalances()
    else:
        unb = api617_unbalances(ctx.assembly, ctx.api_range[1])
    ctx.results["api617"] = out = {"unbalances": unb, "edition": ed, "placement": placed}
    return out


def _unbalances(ctx: Context) -> list:
    """The unbalance the response uses (:func:`_api_unbalance`)."""
    return _api_unbalance(ctx)["unbalances"]


def _clearances(ctx: Context, speeds) -> None:
    """The 9th edition's close-clearance check with the ``--api`` unbalance (once, into
    ``ctx.results["clearance"]``), when the model has close clearances: its ``[api_audit]
    clearances``, else its fluid-film journal bearings'."""
    from ....analyses.audit.api_unbalance import clearance_check, close_clearances

    api = _api_unbalance(ctx)
    if "clearance" in ctx.results or api["placement"] is None:
        return
    found = close_clearances(ctx.train)
    if found:
        ctx.results["clearance"] = clearance_check(
            ctx.assembly,
            found,
            speeds=speeds,
            operating_range=ctx.api_range,
            unbalance=api["placement"],
        )


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


def _api_checks(unb, ctx: Context | None = None) -> dict:
    crit = []
    amp = []
    s = unb.speeds
    lo, hi = unb.operating_range
    in_op = (s >= lo * (1 - 1e-9)) & (s <= hi * (1 + 1e-9))
    if not np.any(in_op):
        in_op = np.zeros(len(s), bool)
        in_op[int(np.argmin(np.abs(s - hi)))] = True
    for p, lim in zip(unb.probes, unb.vibration_limit, strict=True):
        for c in p.criticals:
            crit.append(
                {
                    "probe": p.name,
                    "shaft": unb.shaft_names[p.shaft],
                    "speed_rpm": c.speed * RPM,
                    "probe_shaft_speed_rpm": c.probe_speed * RPM,
                    "amplitude_um": c.amplitude * 1e6,
                    "amplification_factor": c.amplification_factor,
                    "separation_margin_pct": c.separation_margin,
                    "required_margin_pct": c.required_margin,
                    "result": {True: "pass", False: "fail", None: "not determined"}[c.ok],
                }
            )
        pp = 2 * float(np.max(p.amplitude[in_op]))
        amp.append(
            {
                "probe": p.name,
                "max_pp_in_operating_range_um": pp * 1e6,
                "limit_pp_um": float(lim * 1e6),
                "result": "pass" if pp <= lim else "fail",
            }
        )
    check = None if ctx is None else ctx.results.get("clearance")
    return {
        "operating_range_rpm": [lo * RPM, hi * RPM],
        "criticals": crit,
        "amplitudes": amp,
        "ok": all(c["result"] != "fail" for c in crit) and all(a["result"] == "pass" for a in amp),
        "undetermined": sum(c["result"] == "not determined" for c in crit),
        # the 9th edition's close-clearance check (None: not run)
        "close_clearance": None if check is None else check.to_dict(),
    }


def _unbalances_used(ctx: Context) -> dict:
    """Which unbalance the response uses: ``{"basis", "edition", "label", "planes": [...]}``."""
    from ....analyses.audit.api_unbalance import api617_basis

    api = _api_unbalance(ctx)
    ed, placed, unbalances = api["edition"], api["placement"], api["unbalances"]
    train = ctx.train
    planes = []
    if placed is not None:  # 9th edition: at the antinodes of a forward mode
        n_rpm = placed.max_continuous_speed * RPM
        for u, w, kind in zip(unbalances, placed.static_loads, placed.kinds, strict=True):
            planes.append(
                {
                    "shaft": u.shaft,
                    "node": int(u.node),
                    "amount_g_mm": u.amount * 1e6,
                    "phase_deg": float(np.rad2deg(u.phase)),
                    "journal_mass_kg": w,
                    "max_continuous_speed_rpm": n_rpm,
                    "basis": kind,
                }
            )
        label = (
            f"{ed.name} unbalance: 2 × 6350 W/N g·mm at the "
            f"antinodes of the first forward mode of {placed.shaft} "
            f"({placed.mode_frequency * RPM:,.0f} cpm at the maximum continuous speed; W the "
            "static load the antinode's place gives, kg; N the shaft's maximum continuous speed, "
            "rpm, at most 25,000)"
        )
    else:
        basis = (
            api617_basis(ctx.assembly, ctx.api_range[1])
            if ctx.api
            else [(None, None)] * len(unbalances)
        )
        for k, (u, (mass, n)) in enumerate(zip(unbalances, basis, strict=True)):
            d = {
                "shaft": u.shaft,
                "node": train.node_index(u, f"unbalances[{k}]")[1],
                "amount_g_mm": u.amount * 1e6,
                "phase_deg": float(np.rad2deg(u.phase)),
            }
            if ctx.api:
                d["journal_mass_kg"] = mass
                d["max_continuous_speed_rpm"] = n * RPM
            planes.append(d)
        label = (
            f"{ed.name} unbalance: 4 × 6350 W/N g·mm per plane (W its share of "
            "the shaft mass, kg; N its shaft's maximum continuous speed, rpm)"
            if ctx.api
            else "the model's unbalance"
        )
    return {
        "basis": "api617" if ctx.api else "model",
        "edition": ed.name if ctx.api else None,
        "label": label,
        "planes": planes,
    }


def _unbalance_list(used: dict) -> str:
    items = []
    for p in used["planes"]:
        txt = (
            f"{p['amount_g_mm']:.1f} g·mm on {_e(p['shaft'])} node {p['node']} at "
            f"{p['phase_deg']:.0f}°"
        )
        if "journal_mass_kg" in p:
            txt += (
                f" (W = {p['journal_mass_kg']:.2f} kg, N = {p['max_continuous_speed_rpm']:.0f} rpm"
                + (f"; {_e(p['basis'])}" if "basis" in p else "")
                + ")"
            )
        items.append(f"<li>{txt}</li>")
    return "<ul>" + "".join(items) + "</ul>"


def _unbalance_intro(unb, used: dict) -> str:
    return (
        f"<p>Sweep {unb.speeds[0] * RPM:.0f}..{unb.speeds[-1] * RPM:.0f} rpm "
        f"({len(unb.speeds)} speeds) with {_e(used['label'])}:</p>{_unbalance_list(used)}"
        "<p>Amplitudes are zero-to-peak, synchronous with each probe's own shaft.</p>"
    )


def _api_html(api: dict) -> str:
    lo, hi = api["operating_range_rpm"]
    parts = [
        f"<p>Operating range {lo:.0f}..{hi:.0f} rpm (reference shaft). Amplification factor by "
        "the half-power method (API 684); required separation margin per API 617: none for "
        "AF &lt; 2.5, else 17 (1 − 1/(AF − 1.5)) % below the minimum operating speed and "
        "10 + 17 (1 − 1/(AF − 1.5)) % (at most 26 %) above the maximum continuous speed.</p>",
        "<table><tr><th class='l'>probe</th><th class='l'>shaft</th><th>critical (rpm)</th>"
        "<th>probe shaft (rpm)</th><th>amplitude (µm 0-pk)</th><th>AF</th>"
        "<th>separation margin (%)</th><th>required (%)</th><th>result</th></tr>",
    ]
    if not api["criticals"]:
        parts.append("<tr><td class='l' colspan='9'>no response peak in the sweep</td></tr>")
    for c in api["criticals"]:
        ok = {"pass": True, "fail": False}.get(c["result"])
        cls = "bad" if ok is False else ("warn" if ok is None else "")
        parts.append(
            f"<tr class='{cls}'><td class='l'>{_e(c['probe'])}</td><td class='l'>"
            f"{_e(c['shaft'])}</td><td>{c['speed_rpm']:.0f}</td>"
            f"<td>{c['probe_shaft_speed_rpm']:.0f}</td><td>{c['amplitude_um']:.4g}</td>"
            f"<td>{_fmt(c['amplification_factor'], '.2f')}</td>"
            f"<td>{_fmt(c['separation_margin_pct'], '.1f')}</td>"
            f"<td>{_fmt(c['required_margin_pct'], '.1f')}</td><td>{_badge(ok)}</td></tr>"
        )
    parts.append("</table>")
    if api["undetermined"]:
        parts.append(
            "<p class='note'>n/a: a half-power point lies outside the sweep, so the "
            "amplification factor (and the required margin) is not determined.</p>"
        )
    parts.append(
        "<table><tr><th class='l'>probe</th><th>max pk-pk in operating range (µm)</th>"
        "<th>API 617 limit pk-pk (µm)</th><th>result</th></tr>"
    )
    for a in api["amplitudes"]:
        ok = a["result"] == "pass"
        parts.append(
            f"<tr class='{'' if ok else 'bad'}'><td class='l'>{_e(a['probe'])}</td>"
            f"<td>{a['max_pp_in_operating_range_um']:.4g}</td><td>{a['limit_pp_um']:.2f}</td>"
            f"<td>{_badge(ok)}</td></tr>"
        )
    used = api["unbalance"]
    if used["basis"] == "api617":
        where = (
            "at the planes and phases of the model"
            if not any("basis" in p for p in used["planes"])
            else "at the mode shape's antinodes"
        )
        parts.append(
            "</table><p id='api-unbalance'>Unbalance used for these checks: "
            f"{_e(used['label'])}, {where}:</p>" + _unbalance_list(used)
        )
    else:
        parts.append(
            "</table><p id='api-unbalance'>Unbalance used for these checks: the model's "
            "unbalance (listed under Unbalance response), not the API 617 amount; the API 617 "
            "procedure applies 4× the allowable unbalance, 4 × 6350 W/N g·mm per plane (8th "
            "edition), or 2× at the antinodes of a forward mode with a close-clearance check "
            "(9th edition) (<code>gearrotor report --api [--edition 9th]</code>, "
            "<code>gearrotor unbalance --api</code>).</p>"
        )
    cc = api.get("close_clearance")
    if cc is not None:
        parts.append(_clearance_html(cc))
    elif used.get("edition") and "9th" in used["edition"]:
        parts.append(
            "<p>Close-clearance check (6.8.2.10–6.8.2.11): not run, the model lists no close "
            "clearances (<code>[api_audit] clearances</code>) and has no fluid-film journal "
            "bearing file to take them from.</p>"
        )
    return "\n".join(parts)


def _clearance_html(cc: dict) -> str:
    ratio = cc["vibration_limit_pp_um"] / cc["max_probe_amplitude_pp_um"]
    capped = cc["scale_factor"] < ratio * (1 - 1e-12)
    cap = f", at most {cc['scale_factor_cap']:g}: S_cc = {cc['scale_factor']:.3g}" if capped else ""
    rows = [
        f"<h3>Close clearances ({_e(cc['edition'])}, 6.8.2.10–6.8.2.11)</h3>"
        f"<p>The response to the unbalance above, scaled by S_cc = A_vl / A_max = "
        f"{cc['vibration_limit_pp_um']:.2f} / {cc['max_probe_amplitude_pp_um']:.3f} µm pk-pk "
        f"({_e(cc['max_probe'])}) = {ratio:.3g}{cap}; its major-axis pk-pk "
        "amplitude at each close clearance over the sweep must stay below 75 % of the minimum "
        "diametral running clearance (the model's <code>[api_audit] clearances</code>, else "
        "twice each fluid-film journal bearing file's radial clearance).</p>"
        "<table><tr><th class='l'>location</th><th class='l'>shaft</th><th>node</th>"
        "<th>diametral clearance (µm)</th><th>75 % (µm)</th><th>scaled response pk-pk (µm)</th>"
        "<th>at (rpm)</th><th>result</th></tr>"
    ]
    for c in cc["locations"]:
        rows.append(
            f"<tr class='{'' if c['ok'] else 'bad'}'><td class='l'>{_e(c['name'])}</td>"
            f"<td class='l'>{_e(c['shaft'])}</td><td>{c['node']}</td>"
            f"<td>{c['diametral_clearance_um']:.1f}</td><td>{c['limit_pp_um']:.1f}</td>"
            f"<td>{c['scaled_response_pp_um']:.2f}</td><td>{c['speed_rpm']:.0f}</td>"
            f"<td>{_badge(c['ok'])}</td></tr>"
        )
    rows.append("</table>")
    return "".join(rows)


def _verdicts(ctx: Context, api: dict) -> None:
    """The separation-margin and vibration-limit lines of the summary (the audit section's
    separation margins are the same check: one line)."""
    nf = sum(x["result"] == "fail" for x in api["criticals"])
    lo, hi = api["operating_range_rpm"]
    ctx.verdict(
        "separation_margins",
        "API 684 separation margins from the " + _range_words(lo, hi),
        nf == 0,
        f"{len(api['criticals'])} critical peaks, {nf} fail, "
        f"{api['undetermined']} with AF not determined",
    )
    na = sum(x["result"] == "fail" for x in api["amplitudes"])
    ctx.verdict(
        "vibration_limit",
        "API 617 vibration limit in the operating range",
        na == 0,
        f"{len(api['amplitudes'])} probes, {na} above the limit "
        + (
            f"(with the {api['unbalance']['edition']} unbalance)"
            if api["unbalance"]["basis"] == "api617"
            else "(with the model's unbalance)"
        ),
    )
    _clearance_verdict(ctx, api)


def _clearance_verdict(ctx: Context, api: dict) -> None:
    """The close-clearance line of the summary, when the check ran (the audit section's is
    the same check: one line)."""
    cc = api.get("close_clearance")
    if cc is not None:
        nf = sum(not c["ok"] for c in cc["locations"])
        worst = max(cc["locations"], key=lambda c: c["percent_of_limit"])
        ctx.verdict(
            "close_clearances",
            f"{cc['edition']} close clearances (6.8.2.10-6.8.2.11): scaled response < 75 % of "
            "the diametral clearance",
            nf == 0,
            f"{len(cc['locations'])} locations, {nf} above; largest "
            f"{worst['percent_of_limit']:.0f} % of its limit ({worst['name']}, "
            f"{worst['scaled_response_pp_um']:.1f} µm pk-pk at {worst['speed_rpm']:,.0f} rpm), "
            f"S_cc = {cc['scale_factor']:.3g}",
        )
