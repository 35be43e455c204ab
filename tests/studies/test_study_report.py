"""The spectra figure of ``study report`` (:func:`gearrotor.studies.plots.overlay_spectra`) has a
fixed layout (constrained layout measured every tick label twice more per figure): for 1 to 8
cases the legend stays below the lower panels' tick labels and axis labels, and nothing leaves
the figure; each panel draws only its own samples and one beyond each edge, so the curve drawn
is the one of the whole spectrum.

Synthetic cases (a 1x and a 2x sine, a mesh tone, long labels like the seed study's) keep this
module at about ten seconds.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from gearrotor.studies.plots import _pyplot, overlay_spectra, padded_spectrum

RPM = 30.0 / np.pi
LABEL = "unbalance=720 g*mm, ka_ratio=0.2, contact_ratio=1.592, backlash=0.0254 mm, terms=10"


def _case(k: int) -> xr.Dataset:
    """0.5 s at 1e-4 s of a shaft at 6000 rpm: probe = 1x + 2x + mesh tone (30 teeth)."""
    t = np.arange(5000) * 1e-4
    w = 6000 / RPM * (1 + 0.01 * k)
    probe = 1e-4 * np.sin(w * t) + 1e-6 * np.sin(2 * w * t) + 1e-8 * np.sin(30 * w * t)
    speed = w + 0.1 * np.sin(30 * w * t)
    return xr.Dataset(
        {
            "probe_signal": (("time", "probe"), probe[:, None]),
            "probe_shaft": ("probe", [0]),
            "shaft_speed": (("time", "shaft"), speed[:, None]),
            "mesh_frequency": ("mesh", [30 * w * RPM]),
        },
        coords={"time": t, "probe": ["p_x"], "shaft": ["s1"], "mesh": ["m"]},
    )


@pytest.mark.parametrize("n", [1, 2, 5, 8])
def test_legend_below_the_panels_inside_the_figure(n):
    plt = _pyplot()
    cases = {f"{k}: {LABEL}": _case(k) for k in range(n)}
    for channel, name in (("probe", "p_x"), ("speed", "s1")):
        fig = overlay_spectra(cases, channel=channel, name=name, title="a study")
        try:
            fig.canvas.draw()
            r = fig.canvas.get_renderer()
            page = fig.bbox
            legend = fig.legends[0].get_window_extent(r)
            assert len(fig.legends[0].get_texts()) == n
            for ax in fig.axes:
                box = ax.get_tightbbox(r)  # panel, tick labels, axis labels, title
                assert page.x0 <= box.x0 and box.x1 <= page.x1, (channel, ax.get_title())
                assert box.y1 <= page.y1 - 15, (channel, ax.get_title())  # below the suptitle
                assert box.y0 >= legend.y1 + 2, (channel, ax.get_title())  # above the legend
            assert legend.y0 >= page.y0 and page.x0 <= legend.x0 and legend.x1 <= page.x1
        finally:
            plt.close(fig)


def test_each_panel_draws_its_samples_and_one_beyond_each_edge():
    plt = _pyplot()
    cases = {f"{k}: {LABEL}": _case(k) for k in range(3)}
    fig = overlay_spectra(cases, channel="probe", name="p_x")
    try:
        for ax in fig.axes:
            lo, hi = ax.get_xlim()
            lines = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]
            assert len(lines) == 3
            for line, ds in zip(lines, cases.values(), strict=True):
                dt = float(np.median(np.diff(ds["time"].values)))
                f, a = padded_spectrum(ds["probe_signal"].values[:, 0] * 1e6, dt)
                x, y = line.get_xdata(), line.get_ydata()
                inside = np.flatnonzero((f >= lo) & (f <= hi))
                keep = slice(max(inside[0] - 1, 0), min(inside[-1] + 2, len(f)))
                np.testing.assert_array_equal(x, f[keep])
                np.testing.assert_array_equal(y, np.maximum(a, 1e-12)[keep])
                assert x[0] <= lo and (x[-1] >= hi or x[-1] == f[-1])
    finally:
        plt.close(fig)


def _results(scale: float = 1.0) -> xr.Dataset:
    """A collection of three transient cases along one parameter (the layout of ``collect``)."""
    amp = scale * np.array([[1e-6, 2e-6], [2e-6, 3e-6], [4e-6, 5e-6]])
    return xr.Dataset(
        {"amp_1x": (("case", "probe"), amp), "amp_2x": (("case", "probe"), amp / 10)},
        coords={
            "case": [0, 1, 2],
            "label": ("case", ["a", "b", "c"]),
            "unbalance": ("case", [360.0, 720.0, 1080.0], {"units": "g*mm"}),
            "probe": ["p_x", "p_y"],
        },
        attrs={"title": "gearrotor study: t"},
    )


def test_trend_figures_from_the_results_cache(tmp_path, monkeypatch):
    """The PNG is the one ``save_figure`` writes of ``trend_figure``; the second time it comes
    from the cache, byte for byte, without drawing; other values draw again."""
    from gearrotor.files import save_figure
    from gearrotor.studies import plots

    monkeypatch.setenv("GEARROTOR_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("GEARROTOR_CACHE", "on")
    fig = plots.trend_figure(_results(), "unbalance", ["unbalance"])
    save_figure(fig, tmp_path / "direct.png", dpi=110)
    _pyplot().close(fig)
    first = plots.trend_png(_results(), "unbalance", ["unbalance"])
    assert first == (tmp_path / "direct.png").read_bytes()
    drawn = []
    real = plots.trend_figure
    monkeypatch.setattr(plots, "trend_figure", lambda *a: drawn.append(1) or real(*a))
    assert plots.trend_png(_results(), "unbalance", ["unbalance"]) == first
    assert drawn == []
    other = plots.trend_png(_results(2.0), "unbalance", ["unbalance"])
    assert drawn == [1] and other != first
