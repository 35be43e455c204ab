"""Model section (first on the page): the drawing of the train (side views to scale and end
view, PNG), the interactive 3-D model, and the summary of ``gearrotor show`` (mass, inertias,
elements, bearing span, element fineness with its warnings, gear ratios)."""

from __future__ import annotations

from ..base import Context, Part, Section
from ..blocks import RPM, _e, _figure_html, _fmt

__all__ = ["ModelSection"]

_COARSE = ' <span class="fail">coarse</span>'


class ModelSection(Section):
    def early(self, ctx: Context) -> None:
        from ...model_view import plot_model

        ctx.png_early(plot_model, "model.png", ctx.train, speed=ctx.sign * ctx.speed)

    def write(self, ctx: Context) -> list[Part]:
        from ....analyses.model_summary import summarize
        from ...model_view import model_figure_3d, plot_model

        train = ctx.train
        summary = summarize(train)
        ctx.png(plot_model, "model.png", train, speed=ctx.sign * ctx.speed)
        ctx.summary["model"] = summary.to_dict()
        for w in summary.warnings:
            ctx.notes.append(f"model: {w}")
        pos = [sl.position for sl in train.layout().shafts]
        rows = "".join(
            f"<tr><td>{_e(s.name)}</td><td>{s.speed * RPM:,.0f}</td>"
            f"<td>{_fmt(s.length, '.4g')}</td><td>{s.n_elements}</td><td>{s.n_dof}</td>"
            f"<td>{_fmt(s.mass, '.4g')}</td><td>{_fmt(s.polar_inertia, '.4g')}</td>"
            f"<td>{_fmt(s.transverse_inertia, '.4g')}</td><td>({pos[s.index][0]:.4g}, "
            f"{pos[s.index][1]:.4g})</td><td>{_fmt(s.bearing_span, '.4g')}</td>"
            f"<td>{s.coarsest.motion}, {s.coarsest.estimated_error:.1e}"
            f"{_COARSE if s.coarsest.too_coarse else ''}</td></tr>"
            for s in summary.shafts
        )
        table = (
            "<table><tr><th>shaft</th><th>speed (rpm)</th><th>length (m)</th><th>elements</th>"
            "<th>DOF</th><th>mass (kg)</th><th>Ip (kg·m²)</th><th>It (kg·m²)</th>"
            "<th>centre x, y (m)</th><th>bearing span (m)</th>"
            "<th>coarsest element: estimated frequency error at "
            f"{summary.max_frequency * RPM:,.0f} cpm</th></tr>{rows}</table>"
        )
        counts = (
            f"<p>{len(train.bearings)} bearings, {len(train.seals)} seals, {len(train.meshes)} "
            f"gear meshes, {len(train.couplings)} couplings, {len(train.unbalances)} unbalances, "
            f"{len(train.probes)} probes; {summary.n_dof} DOF.</p>"
        )
        img = '<p><img src="model.png" alt="model drawing" style="max-width:100%"></p>'
        fig = model_figure_3d(train, speed=ctx.sign * ctx.speed)
        fig.update_layout(height=560)
        return [("model", "Model", table + counts + img + _figure_html(fig, "fig-model"))]
