"""Bearings section: the coefficients of the tabulated (fluid-film) bearings against journal
speed, interactive and as PNG; shown whenever the model has such a bearing."""

from __future__ import annotations

from pathlib import Path

from ..base import Context, Part, Section
from ..blocks import RPM, _color, _figure_html, _go, _mpl_figure, _savefig

__all__ = ["BearingsSection", "bearing_coefficient_figure", "plot_bearing_coefficients"]


class BearingsSection(Section):
    def write(self, ctx: Context) -> list[Part]:
        speed = ctx.sign * ctx.speed
        fig = bearing_coefficient_figure(ctx.assembly, speed=speed)
        if fig is None:
            return []
        plot_bearing_coefficients(ctx.assembly, path=ctx.directory / "bearings.png", speed=speed)
        ctx.figures.append(ctx.directory / "bearings.png")
        return [("bearings", "Bearing coefficients", _figure_html(fig, "fig-bearings"))]


_NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


def _tabulated(assembly) -> list:
    return [b for b in assembly.bearings if b.element.speed_dependent]


def _journal_speed(assembly, b, speed: float | None) -> float | None:
    """rpm: the bearing's journal speed at the reference-shaft ``speed`` (rad/s), or None."""
    if speed is None:
        return None
    return abs(float(assembly.speed_ratio[b.shaft] * speed)) * RPM


def bearing_coefficient_figure(assembly, speed: float | None = None):
    """Stiffness and damping coefficients against journal speed of every tabulated
    (speed-dependent) bearing of an assembly, one row of panels per bearing (a pinion's
    coefficients are not flattened by a bull gear's tens of times larger ones), the journal
    speed at the reference-shaft ``speed`` (rad/s) marked; ``None`` when no bearing is
    tabulated."""
    go = _go()
    from plotly.subplots import make_subplots

    tab = _tabulated(assembly)
    if not tab:
        return None
    titles = [f"{b.name}: {q}" for b in tab for q in ("stiffness (N/m)", "damping (N·s/m)")]
    fig = make_subplots(
        rows=len(tab), cols=2, subplot_titles=titles, vertical_spacing=0.3 / len(tab)
    )
    for bi, b in enumerate(tab):
        t = b.element.table
        sp = t.speed * RPM
        for j, nm in enumerate(_NAMES):
            fig.add_trace(
                go.Scatter(
                    x=sp,
                    y=t.values[:, j],
                    mode="lines+markers",
                    line=dict(color=_color(j % 4)),
                    name=nm,
                    legendgroup=nm,
                    showlegend=bi == 0,
                    hovertemplate=f"{b.name}: {nm}<br>%{{x:.0f}} rpm<br>%{{y:.4g}}<extra></extra>",
                ),
                row=bi + 1,
                col=1 if j < 4 else 2,
            )
        n = _journal_speed(assembly, b, speed)
        if n is not None:
            for col in (1, 2):
                fig.add_vline(
                    x=n, line=dict(color="black", dash="dot", width=1), row=bi + 1, col=col
                )
    fig.update_xaxes(title_text="journal speed (rpm)", row=len(tab))
    fig.update_layout(
        title="Tabulated bearing coefficients (dotted: journal speed at the operating speed)",
        height=260 * len(tab) + 120,
        meta=dict(kind="bearings"),
    )
    return fig


def plot_bearing_coefficients(assembly, path=None, speed: float | None = None):
    """Tabulated bearing coefficients (matplotlib) against journal speed, one row of panels
    (stiffness, damping) per bearing, the journal speed at the reference-shaft ``speed`` (rad/s)
    dotted; ``None`` when no bearing of the assembly is tabulated."""
    tab = _tabulated(assembly)
    if not tab:
        return None
    fig = _mpl_figure((11, 2.4 * len(tab) + 1.0))
    axes = fig.subplots(len(tab), 2, squeeze=False, sharex="row")
    for bi, b in enumerate(tab):
        t = b.element.table
        n = _journal_speed(assembly, b, speed)
        for col, lab in enumerate(("stiffness (N/m)", "damping (N·s/m)")):
            ax = axes[bi, col]
            for j in range(4):
                k = 4 * col + j
                ax.plot(t.speed * RPM, t.values[:, k], marker=".", color=f"C{j}", label=_NAMES[k])
            if n is not None:
                ax.axvline(n, color="k", ls=":", lw=1, label="journal speed at operating speed")
            ax.axhline(0.0, color="0.3", lw=0.6)
            ax.set_title(f"{b.name}: {lab}", fontsize=9)
            ax.grid(alpha=0.3)
            if bi == len(tab) - 1:
                ax.set_xlabel("journal speed (rpm)")
    for col in (0, 1):
        axes[0, col].legend(fontsize=7, ncol=5, loc="lower left", bbox_to_anchor=(0, 1.12))
    fig.suptitle("Tabulated bearing coefficients")
    if path is not None:
        _savefig(fig, Path(path))
    return fig
