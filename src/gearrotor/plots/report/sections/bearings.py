"""Bearings section: the coefficients of the tabulated (fluid-film) bearings against journal
speed, interactive and as PNG; shown whenever the model has such a bearing."""

from __future__ import annotations

from pathlib import Path

from ..base import Context, Part, Section
from ..blocks import RPM, _color, _figure_html, _go, _mpl_figure, _savefig

__all__ = ["BearingsSection", "bearing_coefficient_figure", "plot_bearing_coefficients"]


class BearingsSection(Section):
    def write(self, ctx: Context) -> list[Part]:
        fig = bearing_coefficient_figure(ctx.assembly)
        if fig is None:
            return []
        plot_bearing_coefficients(ctx.assembly, path=ctx.directory / "bearings.png")
        ctx.figures.append(ctx.directory / "bearings.png")
        return [("bearings", "Bearing coefficients", _figure_html(fig, "fig-bearings"))]


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


def plot_bearing_coefficients(assembly, path=None):
    """Tabulated bearing coefficients (matplotlib) against journal speed; ``None`` when no
    bearing of the assembly is tabulated."""
    tab = [b for b in assembly.bearings if b.element.speed_dependent]
    if not tab:
        return None
    fig = _mpl_figure((11, 4.5))
    ax = fig.subplots(1, 2)
    names = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
    styles = ("-", "--", ":", "-.")
    for bi, b in enumerate(tab):
        t = b.element.table
        for j, nm in enumerate(names):
            ax[j // 4].plot(
                t.speed * RPM,
                t.values[:, j],
                styles[bi % 4],
                marker=".",
                color=f"C{j % 4}",
                label=f"{b.name}: {nm}",
            )
    for a, lab in zip(ax, ("stiffness (N/m)", "damping (N·s/m)"), strict=True):
        a.set_xlabel("journal speed (rpm)")
        a.set_ylabel(lab)
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.suptitle("Tabulated bearing coefficients")
    if path is not None:
        _savefig(fig, Path(path))
    return fig
