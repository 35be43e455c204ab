"""Building blocks the report sections share: unit constants and the acceptance threshold,
plotly figures (the module, a colour cycle, embedding a figure in the page), matplotlib figures
(a constrained-layout Figure, an atomic PNG write) and HTML fragments (escaping, numbers,
pass/fail badges)."""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np

from ...files import save_figure

__all__ = ["COLORS", "LOG_DEC_THRESHOLD", "RPM"]

RPM = 30 / np.pi  # rad/s -> rpm
LOG_DEC_THRESHOLD = 0.1  # API 617 (Level II) acceptance: log dec of every mode above 0.1
_PLOTLY_CONFIG = {"displaylogo": False, "responsive": True}
COLORS = (
    "#1f77b4",
    "#d62728",
    "#2ca02c",
    "#9467bd",
    "#ff7f0e",
    "#17becf",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
)


def _go():
    import plotly.graph_objects as go

    return go


def _color(k: int) -> str:
    return COLORS[k % len(COLORS)]


def _mpl_figure(size):
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    return fig


def _savefig(fig, path: Path) -> Path:
    return save_figure(fig, path, dpi=120)


def _e(x) -> str:
    return html.escape(str(x), quote=True)


def _fmt(x, spec=".3g", none="–") -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return none
    return format(x, spec)


def _badge(ok) -> str:
    if ok is None:
        return '<span class="na">n/a</span>'
    return '<span class="ok">pass</span>' if ok else '<span class="fail">FAIL</span>'


def _figure_html(fig, div_id: str) -> str:
    import plotly.io as pio

    if getattr(fig, "_validate", True):
        fig.update_layout(template="plotly_white")
    # else: built without validation (the 3-D mode shapes), with the template in its layout
    h = fig.layout.height or 500
    inner = pio.to_html(
        fig,
        full_html=False,
        include_plotlyjs=False,
        include_mathjax=False,
        div_id=div_id,
        config=_PLOTLY_CONFIG,
        default_height=f"{h}px",
    )
    return f'<div class="plot">{inner}</div>'
