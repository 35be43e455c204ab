"""API audit section (API 617 / API RP 684 lateral audit): the undamped critical speed map
(:func:`gearrotor.analyses.audit.ucs.ucs_map`), the unbalance response's critical speeds with their
amplification factors and separation margins over the model's operating range, Level I
stability (log dec against the applied cross-coupling, Q_0/Q_A, the screening chart, the
verdict) and Level II (every forward lateral mode with the model's destabilisers at the
operating range's ends and the MCS) (:func:`gearrotor.analyses.stability_audit`).

Needs the model's ``operating_speed_range`` and ``max_continuous_speed``, its ``[api_audit]``
table (the Level I inputs), unbalance and probes; requested with ``--analyses ...,audit``.
The response is the unbalance section's when it ran (with ``--api`` the API 617 unbalance),
else the section runs it with the same settings.
"""

from __future__ import annotations

from ....errors import ModelError
from ..base import Context, Part, Section
from ..blocks import RPM, _badge, _e, _fmt
from ..verdicts import LEVEL2_REQUIRED, _range_words, result_badge
from .unbalance import (
    UnbalanceSection,
    _api_checks,
    _api_html,
    _clearance_verdict,
    _clearances,
    _unbalances,
    _unbalances_used,
)

__all__ = ["AuditSection"]

FIGURES = ("audit_ucs.png", "audit_level1.png", "audit_screening.png", "audit_level2.png")


class AuditSection(Section):
    analysis = "audit"
    default = False

    def check(self, ctx: Context) -> None:
        from ....analyses.audit.stability_audit import level1_inputs

        train = ctx.train
        if train.operating_speed_range is None or train.max_continuous_speed is None:
            missing = [
                f
                for f in ("operating_speed_range", "max_continuous_speed")
                if getattr(train, f) is None
            ]
            raise ModelError(
                "the API audit needs the model's operating range and maximum continuous speed",
                field=", ".join(missing),
                expected="operating_speed_range = ['MIN rpm', 'MAX rpm'] and "
                "max_continuous_speed = 'MCS rpm' in the model",
            )
        if ctx.operating_range is None:
            raise ModelError(
                "the API audit uses the model's operating range: leave out --speed",
                field="--speed",
                expected="no --speed with the audit section",
            )
        level1_inputs(train)  # the [api_audit] table (raises without one)
        UnbalanceSection().check(ctx)

    def run(self, ctx: Context) -> None:
        from ....analyses import unbalance_response
        from ....analyses.audit.stability_audit import stability_audit
        from ....analyses.audit.ucs import ucs_map

        unb = ctx.results.get("unbalance")
        if unb is None:
            top = max(ctx.speed, ctx.api_range[1])
            speeds = ctx.sweep(0.02 * top, 1.5 * top, ctx.n_unbalance, "unbalance sweep")
            unb = unbalance_response(
                ctx.assembly,
                speeds=speeds,
                unbalances=_unbalances(ctx),
                operating_range=ctx.api_range,
            )
            _clearances(ctx, speeds)
        ctx.results["audit"] = {
            "ucs": ucs_map(ctx.assembly, n_modes=3),
            # the edition the report uses (--edition, else the model's [api_audit] edition)
            "stability": stability_audit(ctx.train, edition=ctx.api_edition.key),
            "unbalance": unb,
        }

    def write(self, ctx: Context) -> list[Part]:
        res = ctx.results.get("audit")
        if res is None:
            return []
        from ...audit import plot_level1, plot_level2, plot_screening, plot_ucs_map

        ucs, audit, unb = res["ucs"], res["stability"], res["unbalance"]
        checks = _api_checks(unb, ctx)
        checks["unbalance"] = _unbalances_used(ctx)
        st = audit.to_dict()
        ctx.summary["api_audit"] = {
            "edition": st["edition"],
            "operating_range_rpm": [v * RPM for v in ctx.api_range],
            "max_continuous_speed_rpm": ctx.train.max_continuous_speed * RPM,
            "ucs": {k: v for k, v in ucs.to_dict().items() if k in ("shafts", "intersections")},
            "response": checks,
            "stability": st,
        }
        _verdicts(ctx, checks, audit)
        ctx.png(plot_ucs_map, FIGURES[0], ucs)
        ctx.png(plot_level1, FIGURES[1], audit.level1)
        ctx.png(plot_screening, FIGURES[2], audit.level1)
        ctx.png(plot_level2, FIGURES[3], audit.level2)
        return [("api-audit", "API audit", _html(ctx, ucs, audit, checks))]


def _verdicts(ctx: Context, checks: dict, audit) -> None:
    """One line per check: the separation margins (the unbalance section's line when it ran:
    the same response), Level I (pass, or "Level II required": not a failure) and Level II
    (pass/FAIL when Level I sent the audit there, "not required" when Level I passed; the
    audit's verdict is the deciding level's)."""
    nf = sum(c["result"] == "fail" for c in checks["criticals"])
    lo, hi = checks["operating_range_rpm"]
    ctx.verdict(
        "separation_margins",
        "API 684 separation margins from the " + _range_words(lo, hi),
        nf == 0,
        f"{len(checks['criticals'])} critical peaks, {nf} fail, "
        f"{checks['undetermined']} with AF not determined",
    )
    _clearance_verdict(ctx, checks)
    l1, l2 = audit.level1, audit.level2
    ratio = "> search limit" if l1.ratio is None else f"{l1.ratio:.3f}"
    ctx.verdict(
        "api617_level1",
        "API 617 Level I stability",
        True if l1.passed else None,
        f"Q_0/Q_A = {ratio} (>= 2), log dec at Q_A {l1.log_dec_at_qa:.3f} (>= 0.1)"
        + ("" if l1.passed else ": Level II decides"),
        result="pass" if l1.passed else LEVEL2_REQUIRED,
    )
    low = _fmt(audit.min_level2_log_dec, ".3f")
    if audit.decided_by == "Level I":
        ctx.verdict(
            "api617_level2",
            "API 617 Level II stability",
            None,
            f"Level I passes; least forward log dec {low} (>= 0.1, for information)",
            result="not required",
        )
    else:
        ctx.verdict(
            "api617_level2",
            "API 617 Level II stability",
            l2.passed,
            f"least forward log dec {low} (>= 0.1): the audit's verdict, {audit.verdict}",
        )


def _level1_words(l1) -> str:
    """Level I's verdict in the summary's words: ``pass`` or ``Level II required``."""
    return "pass" if l1.passed else LEVEL2_REQUIRED


def _criterion_badge(ok: bool | None) -> str:
    """A Level I criterion that is not met sends the rotor to Level II: not a failure."""
    return result_badge({True: "pass", False: LEVEL2_REQUIRED, None: "n/a"}[ok])


def _img(ctx: Context, name: str, alt: str) -> str:
    data = ctx.png_data(name)
    return (
        f"<div class='plot'><img alt='{_e(alt)}' src='data:image/png;base64,{data}' "
        "style='max-width:100%'></div>"
    )


def _html(ctx: Context, ucs, audit, checks: dict) -> str:
    l1, l2 = audit.level1, audit.level2
    lo, hi = (v * RPM for v in ctx.api_range)
    parts = [
        f"<p>{_e(l1.edition)}. Operating range {lo:.0f}..{hi:.0f} rpm, maximum continuous "
        f"speed {ctx.train.max_continuous_speed * RPM:.0f} rpm (reference shaft, from the "
        "model).</p>",
        "<h3>Undamped critical speed map</h3>",
        "<p>Every radial bearing replaced by the same stiffness k; the gear meshes, couplings "
        "and pedestals kept. Each branch is a mode followed by its shape, solid where it is a "
        "critical of the panel's shaft (its forward whirl there holds at least "
        f"{ucs.min_share:g} of the mode's kinetic energy), dotted where the mode has moved to "
        "another shaft or the mesh. The shaft's own bearings' Kxx (solid) and Kyy (dashed) "
        "over speed; circles: intersections (exact roots); grey dotted: rigid supports; band "
        "and dash-dot line: operating range and MCS.</p>",
        _img(ctx, FIGURES[0], "critical speed map"),
        "<table><tr><th class='l'>shaft</th><th>rigid-support criticals (rpm)</th></tr>",
    ]
    for s in ucs.shafts:
        vals = ", ".join(f"{v * RPM:.0f}" for v in s.rigid_critical_speeds if v == v)
        parts.append(f"<tr><td class='l'>{_e(s.name)}</td><td>{vals or '–'}</td></tr>")
    parts.append("</table>")
    parts += ["<h3>Unbalance response over the operating range</h3>", _api_html(checks)]
    ratio = "–" if l1.ratio is None else f"{l1.ratio:.3f}"
    q0 = "none up to the search limit" if l1.threshold_q is None else f"{l1.threshold_q:.4g}"
    parts += [
        "<h3>Level I</h3>",
        f"<p>Q_A = {l1.qa:.4g} N/m at "
        + ", ".join(f"{_e(s.shaft)} node {s.node} ({s.weight:.3g})" for s in l1.sites)
        + f", at {abs(l1.speed) * RPM:.0f} rpm. Threshold Q_0 = {q0} N/m (root search, "
        f"rtol {l1.rtol:g}), Q_0/Q_A = {ratio}, log dec at Q_A {l1.log_dec_at_qa:.3f}. "
        f"Verdict: <b>{_e(_level1_words(l1))}</b>.</p>",
        "<table><tr><th class='l'>criterion</th><th>value</th><th class='l'>requirement</th>"
        "<th>result</th></tr>",
    ]
    for c in l1.criteria:
        parts.append(
            f"<tr><td class='l'>{_e(c.name)}</td><td>{_fmt(c.value, '.4g')}</td>"
            f"<td class='l'>{_e(c.requirement)}</td><td>{_criterion_badge(c.ok)}</td></tr>"
        )
    parts += [
        "</table>",
        _img(ctx, FIGURES[1], "Level I log dec against Q"),
        _img(ctx, FIGURES[2], "Level I screening chart"),
        "<h3>Level II</h3>",
        "<p>Damped modes with every destabiliser of the model (cross-couplings, bearing and "
        "seal tables, rotating shaft damping); forward lateral modes need log dec &ge; 0.1.</p>",
        "<table><tr><th>speed (rpm)</th><th>frequency (rpm)</th><th>log dec</th>"
        "<th>whirl</th><th>type</th><th>forward lateral</th><th>result</th></tr>",
    ]
    for ev in l2.evaluations:
        for m in ev.modes:
            cls = "" if m.ok else "bad"
            parts.append(
                f"<tr class='{cls}'><td>{abs(ev.speed) * RPM:.0f}</td>"
                f"<td>{m.frequency * RPM:.0f}</td><td>{m.log_dec:.3f}</td>"
                f"<td>{_e('/'.join(m.whirl_per_shaft))}</td><td>{_e(m.mode_type)}</td>"
                f"<td>{'yes' if m.forward else '–'}</td><td>{_badge(m.ok)}</td></tr>"
            )
    parts += [
        "</table>",
        _img(ctx, FIGURES[3], "Level II log dec"),
        f"<p>Stability audit: <b>{_e(audit.verdict)}</b> (decided by {_e(audit.decided_by)}; "
        f"Level I {_e(_level1_words(l1))}, Level II {_e(l2.verdict)}).</p>",
    ]
    return "\n".join(parts)
