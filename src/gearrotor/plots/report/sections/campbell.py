"""Campbell section: the Campbell diagram over 0..1.25× the operating speed
(:func:`gearrotor.analyses.campbell`), interactive and as PNG, with the table of crossing
speeds."""

from __future__ import annotations

import numpy as np

from ....errors import ModelError
from ..base import Context, Part, Section
from ..blocks import RPM, _color, _e, _figure_html, _go

__all__ = ["CampbellSection", "campbell_figure"]


class CampbellSection(Section):
    analysis = "campbell"
    default = True

    def run(self, ctx: Context) -> None:
        from ....analyses import campbell

        speeds = ctx.sweep(0.0, 1.25 * ctx.speed, ctx.n_campbell, "Campbell sweep")
        if speeds[0] <= ctx.speed <= speeds[-1]:
            # the operating speed is a sweep point: the stability checks name a Campbell track
            # by its row of the modal table there (one numbering)
            speeds = np.union1d(speeds, [ctx.speed])
        try:
            ctx.results["campbell"] = campbell(
                ctx.assembly, speeds=speeds, max_frequency=ctx.max_frequency
            )
        except ModelError:
            raise
        except ValueError as exc:  # e.g. no mode below max_frequency: an input problem
            raise ModelError(
                f"the Campbell diagram cannot be made: {exc}",
                field="--max-frequency",
                value=f"{ctx.max_frequency * RPM:.6g} cpm",
                expected="a maximum frequency above the lowest modes of the train",
            ) from None

    def write(self, ctx: Context) -> list[Part]:
        from ...figures import plot_campbell

        camp = ctx.results.get("campbell")
        if camp is None:
            return []
        ctx.summary["campbell"] = {
            "crossings": camp.to_dict()["crossings"],
            "orders": camp.to_dict()["orders"],
        }
        ctx.png(plot_campbell, "campbell.png", camp, max_frequency=ctx.max_frequency)
        body = _figure_html(campbell_figure(camp, max_frequency=ctx.max_frequency), "fig-campbell")
        body += _crossings_table(camp)
        return [("campbell", "Campbell diagram", body)]


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


def _crossings_table(camp) -> str:
    if not camp.crossings:
        return "<p>No mode crosses an excitation line in the speed range.</p>"
    rows = [
        "<h3>Crossing speeds</h3><table><tr><th>mode</th><th class='l'>excitation</th>"
        "<th>speed (rpm)</th><th>frequency (cpm)</th><th>log dec</th><th>whirl</th>"
        "<th>type</th></tr>"
    ]
    for c in camp.crossings:
        rows.append(
            f"<tr><td>{c.mode}</td><td class='l'>{_e(c.order)}</td><td>{c.speed * RPM:.0f}</td>"
            f"<td>{c.frequency * RPM:.0f}</td><td>{c.log_dec:.3g}</td><td>{_e(c.whirl)}</td>"
            f"<td>{_e(c.mode_type)}</td></tr>"
        )
    rows.append("</table>")
    return "\n".join(rows)
