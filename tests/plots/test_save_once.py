"""A figure is drawn once when it is saved (:func:`gearrotor.files.figure_bytes`, issue 28):
matplotlib's ``savefig`` draws a figure with a layout engine (a constrained layout, or the
placeholder ``tight_layout()`` leaves) or a tight crop a first time with drawing switched off
to lay it out; ``figure_bytes`` runs the engine and measures the crop itself at the save's dpi
and saves without that pass. The PNG must be matplotlib's own, byte for byte: each figure kind
the commands write is saved both ways here and compared (no timing: benchmarks/figures.py
measures the time).

The spectra figure of ``study report`` measures its text with a renderer of its own, kept
with the figure (the canvas's renderer at the figure's dpi was replaced at every save, at
110 dpi, and its text caches with it): the same layout as measured by the canvas's.
"""

from __future__ import annotations

import io

import numpy as np
import pytest

from gearrotor.files import figure_bytes

RPM = 30.0 / np.pi


def _pyplot():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def _matplotlib_png(fig, **kw) -> bytes:
    """``fig.savefig`` as ``figure_bytes`` called it before (matplotlib's two passes)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", pil_kwargs={"compress_level": 3}, **kw)
    return buf.getvalue()


def _both(build, **kw) -> tuple[bytes, bytes]:
    """PNG of ``figure_bytes`` and of matplotlib's save, each of a figure built anew."""
    plt = _pyplot()
    fig = build()
    ours = figure_bytes(fig, **kw)
    plt.close(fig)
    fig = build()
    theirs = _matplotlib_png(fig, **kw)
    plt.close(fig)
    return ours, theirs


def _constrained_pyplot():
    plt = _pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(7, 5), layout="constrained")
    for k, ax in enumerate(axes.ravel()):
        ax.semilogy(np.arange(1, 50), np.arange(1, 50) ** (k + 1.5), label=f"curve {k}")
        ax.set_xlabel("speed (rpm)")
        ax.set_ylabel("amplitude (µm)")
        ax.set_title(f"panel {k}")
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside lower center")
    fig.suptitle("constrained, pyplot")
    return fig


def _constrained_object_api():
    """A ``Figure`` made without pyplot (its canvas cannot print: the save switches to Agg),
    as the report and the transient figures make theirs."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6, 4), layout="constrained")
    ax = fig.subplots()
    ax.plot([0, 1, 2], [3, 1, 2], "o-")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("force\n(N)")
    fig.suptitle("constrained, object API")
    return fig


def _tight_layout():
    plt = _pyplot()
    fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3))
    a.plot(np.linspace(0, 1, 50), np.sin(np.linspace(0, 6, 50)))
    b.bar(["x", "y", "z"], [3, 1, 2])
    a.set_title("tight_layout() leaves a placeholder engine")
    fig.tight_layout()
    return fig


def _cropped():
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([0, 1], [0, 1])
    ax.annotate("a note outside the axes", (1, 1), xytext=(30, 20), textcoords="offset points")
    ax.set_title("left title", loc="left")
    fig.suptitle("bbox_inches='tight'", x=0.01, ha="left")
    return fig


@pytest.mark.parametrize(
    ("build", "kw"),
    [
        (_constrained_pyplot, dict(dpi=110)),
        (_constrained_object_api, dict(dpi=120)),
        (_tight_layout, dict(dpi=130)),
        (_cropped, dict(dpi=130, bbox_inches="tight")),
        (_tight_layout, dict(dpi=130, bbox_inches="tight")),
        (_constrained_pyplot, dict(dpi=100, bbox_inches="tight")),
    ],
    ids=["constrained", "constrained-object-api", "tight_layout", "crop", "both", "crop+layout"],
)
def test_the_png_of_one_draw_is_matplotlibs(build, kw):
    ours, theirs = _both(build, **kw)
    assert ours == theirs


def test_the_figure_keeps_its_engine_and_canvas():
    """After the save the figure is as before: its layout engine and canvas (a figure saved
    again, or shown, lays itself out as it did)."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    fig = _constrained_object_api()
    canvas = fig.canvas
    first = figure_bytes(fig, dpi=120)
    assert isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine)
    assert fig.canvas is canvas
    assert fig.dpi == 100
    assert figure_bytes(fig, dpi=120) == first


def _save_seen(fig, monkeypatch, **kw) -> dict:
    """What ``figure_bytes`` passes to ``fig.savefig``: its keywords and the figure's layout
    engine while it saves."""
    seen = {}
    real = fig.savefig

    def savefig(buf, **savefig_kw):
        seen.update(savefig_kw, engine=fig.get_layout_engine())
        return real(buf, **savefig_kw)

    monkeypatch.setattr(fig, "savefig", savefig)
    figure_bytes(fig, **kw)
    return seen


@pytest.mark.parametrize("build", [_constrained_pyplot, _constrained_object_api, _tight_layout])
def test_the_save_is_one_draw(build, monkeypatch):
    """The saves above compare equal because the pass is left out (not because matplotlib's
    own path was taken): savefig sees no engine and a crop box, not "tight"."""
    from matplotlib.transforms import Bbox

    plt = _pyplot()
    fig = build()
    seen = _save_seen(fig, monkeypatch, dpi=110, bbox_inches="tight")
    plt.close(fig)
    assert seen["engine"] is None
    assert isinstance(seen["bbox_inches"], Bbox)


def test_a_gui_canvas_saves_as_matplotlib_does(monkeypatch):
    """A canvas of an interactive backend (a subclass of Agg's) would resize its window with
    the dpi: savefig as it is."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    class Window(FigureCanvasAgg):
        pass

    plt = _pyplot()
    fig = _constrained_pyplot()
    Window(fig)
    seen = _save_seen(fig, monkeypatch, dpi=110, bbox_inches="tight")
    plt.close(fig)
    assert seen["bbox_inches"] == "tight"
    assert seen["engine"] is not None


def test_other_saves_are_matplotlibs():
    """Other formats, a crop given as a box, other keywords: savefig as it is."""
    from matplotlib.transforms import Bbox

    plt = _pyplot()
    fig = _constrained_pyplot()
    svg = figure_bytes(fig, format="svg")
    plt.close(fig)
    assert svg.lstrip().startswith(b"<?xml")
    box = Bbox.from_bounds(0.5, 0.5, 5, 3)
    ours, theirs = _both(_constrained_pyplot, dpi=110, bbox_inches=box)
    assert ours == theirs
    ours, theirs = _both(_cropped, dpi=110, bbox_inches="tight", pad_inches=0.3)
    assert ours == theirs


def test_the_model_view_crop(examples):
    """``show --plot`` (and the report's model.png): the tight crop measured once."""
    from gearrotor.io import load_model
    from gearrotor.plots.model_view import plot_model

    train = load_model(examples / "unity_gearbox.toml")
    ours, theirs = _both(lambda: plot_model(train), dpi=130, bbox_inches="tight")
    assert ours == theirs


def test_the_standard_transient_figures(examples):
    """``transient-plot``: constrained object-API figures at 110 dpi (of a 0.1-s run)."""
    pytest.importorskip("xarray", reason="transient results need xarray (gearrotor[results])")
    from gearrotor.analyses.transient import plots as tp
    from gearrotor.analyses.transient import transient
    from gearrotor.io import load_model

    ds = tp._ds(transient(load_model(examples / "unity_gearbox.toml"), t_end=0.1))
    for fn in (tp.plot_spectra, tp.plot_whirl_power):
        ours, theirs = _both(lambda fn=fn: fn(ds), dpi=110)
        assert ours == theirs, fn.__name__


def test_the_study_trend_figure():
    """``study report``'s trend figures: pyplot, constrained, at 110 dpi."""
    import xarray as xr

    from gearrotor.studies.plots import trend_figure

    amp = np.array([[1e-6, 2e-6], [2e-6, 3e-6], [4e-6, 5e-6]])
    ds = xr.Dataset(
        {"amp_1x": (("case", "probe"), amp), "amp_2x": (("case", "probe"), amp / 10)},
        coords={
            "case": [0, 1, 2],
            "unbalance": ("case", [360.0, 720.0, 1080.0], {"units": "g*mm"}),
            "probe": ["p_x", "p_y"],
        },
        attrs={"title": "t"},
    )
    ours, theirs = _both(lambda: trend_figure(ds, "unbalance", ["unbalance"]), dpi=110)
    assert ours == theirs


def test_the_spectra_figure_measures_as_the_canvas_would(monkeypatch):
    """The spectra layout measured with the figure's own renderer is the one measured with the
    canvas's renderer (the old way): the same PNG."""
    from gearrotor.studies import plots

    plt = _pyplot()
    t = np.arange(4000) * 1e-4
    cases = {}
    for k in range(3):
        w = 6000 / RPM * (1 + 0.01 * k)
        cases[f"{k}: a case label as long as the seed study's, k={k}"] = _spectra_case(t, w)
    new = plots.overlay_spectra(cases, channel="probe", name="p_x", title="t")
    ours = figure_bytes(new, dpi=110)
    plt.close(new)
    monkeypatch.setattr(plots, "_measuring_renderer", lambda fig: fig.canvas.get_renderer())
    old = plots.overlay_spectra(cases, channel="probe", name="p_x", title="t")
    assert figure_bytes(old, dpi=110) == ours
    plt.close(old)


def _spectra_case(t, w):
    import xarray as xr

    probe = 1e-4 * np.sin(w * t) + 1e-6 * np.sin(2 * w * t) + 1e-9 * np.sin(30 * w * t)
    return xr.Dataset(
        {
            "probe_signal": (("time", "probe"), probe[:, None]),
            "probe_shaft": ("probe", [0]),
            "shaft_speed": (("time", "shaft"), np.full((t.size, 1), w)),
            "mesh_frequency": ("mesh", [30 * w * RPM]),
        },
        coords={"time": t, "probe": ["p_x"], "shaft": ["s1"], "mesh": ["m"]},
    )
