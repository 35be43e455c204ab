"""Campbell section: the Campbell diagram over 0..1.25× the operating speed
(:func:`gearrotor.analyses.campbell`), interactive and as PNG, with the table of crossing
speeds."""

from __future__ import annotations

from functools import partial

import numpy as np

from ....errors import ModelError
from ..base import Context, Part, Section
from ..blocks import RPM, _color, _e, _figure_html, _go
from ..verdicts import model_undamped_kinds, track_name, track_rows

__all__ = ["CampbellSection", "campbell_figure"]


class CampbellSection(Section):
    analysis = "campbell"
    default = True

    def run(self, ctx: Context) -> None:
        speeds = ctx.sweep(0.0, 1.25 * ctx.speed, ctx.n_campbell, "Campbell sweep")
        if speeds[0] <= ctx.speed <= speeds[-1]:
            # the operating speed is a sweep point: the stability checks name a Campbell track
            # by its row of the modal table there (one numbering)
            speeds = np.union1d(speeds, [ctx.speed])
        ctx.later("campbell", partial(_campbell, ctx, speeds))

    def write(self, ctx: Context) -> list[Part]:
        from ...figures import plot_campbell

        camp = ctx.results.get("campbell")
        if camp is None:
            return []
        rows = track_rows(ctx.results.get("modal"), camp)
        d = camp.to_dict()
        crossings = []
        for c, row in zip(d["crossings"], camp.crossings, strict=True):
            # one numbering: the modal table's row (None for a track without one), and the track
            crossings.append({**c, "mode": rows[row.mode], "track": row.mode})
        ctx.summary["campbell"] = {"crossings": crossings, "orders": d["orders"]}
        from .stability import campbell_statuses

        marks = _marks(ctx)
        ctx.png(plot_campbell, "campbell.png", camp, max_frequency=ctx.max_frequency, **marks)
        # the status of each tracked mode at each speed, in the stability checks' words
        _, status = campbell_statuses(
            camp, model_undamped_kinds(ctx.assembly, ctx.sign * ctx.speed)
        )
        fig = campbell_figure(
            camp, max_frequency=ctx.max_frequency, mode_rows=rows, statuses=status, **marks
        )
        body = _figure_html(fig, "fig-campbell")
        body += _crossings_table(camp, rows)
        return [("campbell", "Campbell diagram", body)]


def _campbell(ctx: Context, speeds):
    """The section's Campbell diagram (a job of the report's helper process)."""
    from ....analyses import campbell

    try:
        return campbell(ctx.assembly, speeds=speeds, max_frequency=ctx.max_frequency)
    except ModelError as exc:
        if exc.field != "max_frequency":
            raise
        # the analysis' argument is the report's --max-frequency
        raise ModelError(
            f"the Campbell diagram cannot be made: {exc.message}",
            field="--max-frequency",
            value=f"{ctx.max_frequency * RPM:.6g} cpm",
            expected="a maximum frequency above the lowest modes of the train",
        ) from None
    except ValueError as exc:  # e.g. no mode below max_frequency: an input problem
        raise ModelError(
            f"the Campbell diagram cannot be made: {exc}",
            field="--max-frequency",
            value=f"{ctx.max_frequency * RPM:.6g} cpm",
            expected="a maximum frequency above the lowest modes of the train",
        ) from None


def _marks(ctx: Context) -> dict:
    """The operating speed, the MCS and the operating range (rad/s) the figures mark."""
    train = ctx.train
    op = ctx.operating_range
    return {
        "operating_speed": ctx.speed,
        "max_continuous_speed": None
        if op is None or train.max_continuous_speed is None
        else abs(float(train.max_continuous_speed)),
        "operating_range": op,
    }


def campbell_figure(
    result,
    max_frequency: float | None = None,
    *,
    mode_rows: list[int | None] | None = None,
    statuses=None,
    operating_speed: float | None = None,
    max_continuous_speed: float | None = None,
    operating_range: tuple[float, float] | None = None,
):
    """Campbell diagram of a :class:`~gearrotor.analyses.CampbellResult`: tracked modes
    (colour = log dec, ● forward, ✕ backward whirl), excitation orders and crossings, the
    operating speed and MCS (rad/s, vertical lines) and the operating range (shaded).

    ``mode_rows``: per track, its row of the modal table (hover and crossings name the mode
    by it, ``track j`` without one); ``statuses``: (n_speeds, n_modes) the status of each
    tracked mode at each speed (:func:`.stability.campbell_statuses`), shown on hover. Order
    lines above the axes over the whole sweep are not drawn (the title names them)."""
    from ...figures import campbell_markers

    go = _go()
    fig = go.Figure()
    s = result.speeds * RPM
    f = result.damped_frequency * RPM
    n = f.shape[1]
    rows = mode_rows if mode_rows is not None else [None] * n
    mk = campbell_markers(
        result, max_frequency, operating_speed, max_continuous_speed, operating_range
    )
    for j in range(n):
        name = track_name(rows, j)
        wh = np.asarray(result.whirl[:, j], dtype=str)
        ty = np.asarray(result.mode_type[:, j], dtype=str)
        ld = result.log_dec[:, j]
        st = (
            np.asarray(statuses[:, j], dtype=str)
            if statuses is not None
            else np.full(len(s), "", dtype=object)
        )
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
                name=name,
                customdata=np.column_stack([ld, wh, ty, st]),
                hovertemplate=(
                    f"{name}<br>speed %{{x:.0f}} rpm<br>frequency %{{y:.0f}} cpm"
                    "<br>log dec %{customdata[0]:.3g}<br>whirl %{customdata[1]}"
                    "<br>type %{customdata[2]}<br>%{customdata[3]}<extra></extra>"
                ),
                showlegend=False,
            )
        )
    for k, (o, line) in enumerate(mk["orders"]):
        fig.add_trace(
            go.Scatter(
                x=s,
                y=line,
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
                    f"{track_name(rows, c.mode)} × {c.order}: {c.speed * RPM:.0f} rpm, log dec "
                    f"{c.log_dec:.3g}, {c.whirl}, {c.mode_type}"
                    for c in result.crossings
                ],
                hoverinfo="text",
            )
        )
    top = mk["top"]
    if mk["band"] is not None:
        a, b = mk["band"]
        fig.add_trace(
            go.Scatter(
                x=[a, b, b, a, a],
                y=[0, 0, top, top, 0],
                fill="toself",
                mode="none",
                fillcolor="rgba(44,160,44,0.12)",
                name="operating range",
                hoverinfo="skip",
            )
        )
    for (label, v), dash in zip(mk["speeds"], ("solid", "dot"), strict=False):
        fig.add_trace(
            go.Scatter(
                x=[v, v],
                y=[0, top],
                mode="lines",
                line=dict(color="black", width=1.3, dash=dash),
                name=label,
            )
        )
    title = "Campbell diagram (● forward, ✕ backward whirl; □ crossings)"
    if mk["off_scale"]:
        title += "<br><sub>orders above the axes, not drawn: " + ", ".join(mk["off_scale"])
        title += "</sub>"
    fig.update_layout(
        title=title,
        xaxis=dict(title="reference shaft speed (rpm)", range=[s[0], s[-1]]),
        yaxis=dict(title="damped natural frequency (cpm)", range=[0, top]),
        height=620,
        # below the axes: the legend hides no marker
        legend=dict(orientation="h", x=0.0, xanchor="left", y=-0.14, yanchor="top"),
        margin=dict(b=140),
        meta=dict(kind="campbell"),
    )
    return fig


def _crossings_table(camp, rows: list[int | None]) -> str:
    if not camp.crossings:
        return "<p>No mode crosses an excitation line in the speed range.</p>"
    out = [
        "<h3>Crossing speeds</h3><p>Modes numbered as in the modal table at the operating "
        "speed (a Campbell track without a row there: <i>track j</i>).</p><table><tr>"
        "<th>mode</th><th class='l'>excitation</th>"
        "<th>speed (rpm)</th><th>frequency (cpm)</th><th>log dec</th><th>whirl</th>"
        "<th>type</th></tr>"
    ]
    for c in camp.crossings:
        out.append(
            f"<tr><td>{_e(track_name(rows, c.mode))}</td><td class='l'>{_e(c.order)}</td>"
            f"<td>{c.speed * RPM:.0f}</td><td>{c.frequency * RPM:.0f}</td>"
            f"<td>{c.log_dec:.3g}</td><td>{_e(c.whirl)}</td><td>{_e(c.mode_type)}</td></tr>"
        )
    out.append("</table>")
    return "\n".join(out)
