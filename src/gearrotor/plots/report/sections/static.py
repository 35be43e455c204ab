"""Operating-points section (issue 11): the static solution at each requested operating point
(bearing loads, journal equilibria), the least-stable mode of the train at each point (modal
with the fluid-film bearings at that point's loads), and three figures: the bearing-load locus,
the journal eccentricity locus and the least-stable log dec against power."""

from __future__ import annotations

import numpy as np

from ....errors import ModelError
from ..base import Context, Part, Section
from ..blocks import LOG_DEC_THRESHOLD, RPM, _badge, _e, _fmt
from .stability import modal_criteria

__all__ = ["OperatingPointsSection"]


class OperatingPointsSection(Section):
    analysis = "operating_points"
    default = False

    def check(self, ctx: Context) -> None:
        train = ctx.base_train or ctx.train
        if not ctx.operating_points:
            raise ModelError(
                "the operating-points section needs operating points",
                field="--all-operating-points",
                expected="[[operating_points]] in the model, and --all-operating-points or "
                "--operating-point NAME",
            )
        for name in ctx.operating_points:
            try:
                train.operating_point(name)
            except ModelError as exc:
                raise ModelError(
                    exc.message, field="--operating-point", value=name, expected=exc.expected
                ) from None

    def run(self, ctx: Context) -> None:
        from ....analyses.lateral.modal import modal
        from ....analyses.static import static

        train = ctx.base_train or ctx.train
        rows = []
        for name in ctx.operating_points:
            st = static(train, name)
            md = modal(train, operating_point=name, max_frequency=ctx.max_frequency)
            # the modes API 617 Level II judges, as the stability section (one definition:
            # analyses.audit.stability.criterion_class; undamped torsional modes of a model without
            # torsional damping would sit at log dec 0 at every point and hide the lateral
            # trend), and any growing mode, whatever it is
            rows.append((st, md, _least_stable(md)))
        ctx.results["operating_points"] = rows

    def write(self, ctx: Context) -> list[Part]:
        rows = ctx.results.get("operating_points")
        if not rows:
            return []
        from ...static import plot_bearing_loads, plot_eccentricity_locus, plot_log_dec_vs_power

        statics = [r[0] for r in rows]
        least = [
            (float(md.log_dec[k]), float(md.frequency_rpm[k])) if k is not None else (None, None)
            for _, md, k in rows
        ]
        summary = []
        for (st, _, _), (ld, f) in zip(rows, least, strict=True):
            summary.append(
                {
                    "operating_point": st.operating_point,
                    "speed_rpm": st.speed * RPM,
                    "power_kW": st.power / 1e3,
                    "least_stable_log_dec": ld,
                    "least_stable_frequency_rpm": f,
                    "bearings": [b.to_dict() for b in st.bearings],
                }
            )
        ctx.summary["operating_points"] = summary
        lds = [ld for ld, _ in least if ld is not None]
        ok = bool(lds) and min(lds) >= LOG_DEC_THRESHOLD
        ctx.verdict(
            "operating_points_stability",
            "least-stable log dec over the operating points (the modes API 617 Level II "
            "judges, and any growing mode)",
            ok,
            f"min {min(lds):.3g} (threshold {LOG_DEC_THRESHOLD})" if lds else "-",
        )
        imgs = []
        ctx.png(plot_bearing_loads, "op_bearing_loads.png", statics)
        imgs.append("op_bearing_loads.png")
        if any(b.kind == "fluid-film" for b in statics[0].bearings):
            ctx.png(plot_eccentricity_locus, "op_eccentricity_locus.png", statics)
            imgs.append("op_eccentricity_locus.png")
        ctx.png(
            plot_log_dec_vs_power,
            "op_log_dec.png",
            [s.power for s in statics],
            [np.nan if ld is None else ld for ld, _ in least],
            names=[s.operating_point for s in statics],
            threshold=LOG_DEC_THRESHOLD,
        )
        imgs.append("op_log_dec.png")
        return [("operating-points", "Operating points", _html(ctx, rows, least, ok, imgs))]


def _least_stable(md) -> int | None:
    """The mode of least log dec among those the stability criteria judge at this point and
    the growing ones (None: none)."""
    from ....analyses.audit.stability import is_unstable

    crit = modal_criteria(md)
    el = [
        i
        for i in range(len(md))
        if not md.overdamped[i] and (crit[i] == "judged" or is_unstable(md.log_dec[i]))
    ]
    return min(el, key=lambda i: md.log_dec[i]) if el else None


def _img(ctx: Context, name: str) -> str:
    data = ctx.png_data(name)
    return (
        f'<p><img alt="{_e(name)}" src="data:image/png;base64,{data}" style="max-width:100%"></p>'
    )


def _html(ctx, rows, least, ok, imgs) -> str:
    radial = [b.name for b in rows[0][0].bearings if b.kind != "thrust"]
    head = "".join(f"<th>{_e(n)}: |F| N (ecc.)</th>" for n in radial)
    body = []
    for (st, _, _), (ld, f) in zip(rows, least, strict=True):
        cells = "".join(
            f"<td>{_fmt(b.magnitude, ',.0f')} ({_fmt(b.eccentricity_ratio, '.3f')})</td>"
            for b in st.bearings
            if b.kind != "thrust"
        )
        body.append(
            f"<tr><td>{_e(st.operating_point)}</td><td>{_fmt(st.speed * RPM, ',.0f')}</td>"
            f"<td>{_fmt(st.power / 1e3, ',.0f')}</td>{cells}<td>{_fmt(ld, '.3f')}</td>"
            f"<td>{_fmt(f, ',.0f')}</td></tr>"
        )
    return (
        "<p>The static operating point (weight, tooth forces from the power, fluid-film "
        "journals solved to equilibrium with the shafts) at each point, and the least-stable "
        "mode the API 617 Level II criterion judges (forward whirl, at least half of the "
        "kinetic energy lateral, up to 3× the fastest shaft speed; or any growing mode) with "
        "the fluid-film bearings at that point's loads (docs/static.md). "
        f"{_badge(ok)} log dec ≥ {LOG_DEC_THRESHOLD} at every point.</p>"
        f"<table><tr><th>point</th><th>rpm</th><th>kW</th>{head}<th>least-stable log dec</th>"
        f"<th>its frequency, rpm</th></tr>{''.join(body)}</table>"
        + "".join(_img(ctx, n) for n in imgs)
    )
