"""Issue 22, figures: the Campbell diagram marks the operating speed and the MCS and its legend
hides no marker and lists no off-scale line; the mode-shape legend names the axial curve; the
bearing coefficients get one row of panels per bearing; the Floquet Ka axis is numeric; the
operating-point labels do not overlap. Each test fails on the figures before the issue."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from gearrotor import load_model

pytest.importorskip("matplotlib")
RPM = np.pi / 30


def _campbell():
    """A Campbell result by hand: one forward and one backward mode over 2000..8000 rpm, orders
    1x and 30x; with the axis to 50,000 cpm the 30x line (60,000 cpm at 2000 rpm) is above the
    axes over the whole sweep."""
    from gearrotor.analyses.lateral.campbell import CampbellResult, Crossing, ExcitationOrder

    s = np.linspace(2000, 8000, 7) * RPM
    f = np.column_stack([np.full(7, 5000.0), np.full(7, 30000.0)]) * RPM
    return CampbellResult(
        speeds=s,
        damped_frequency=f,
        log_dec=np.full((7, 2), 0.5),
        whirl=np.array([["F", "B"]] * 7),
        mode_type=np.array([["L", "L"]] * 7),
        overdamped=np.zeros((7, 2), bool),
        orders=(ExcitationOrder("1x", 0, 1.0), ExcitationOrder("30x", 0, 30.0)),
        crossings=(Crossing(0, "1x", 5000 * RPM, 5000 * RPM, 0.5, "F", "L"),),
        speed_ratio=np.array([1.0]),
        shaft_names=("s",),
    )


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_campbell_png_marks_speeds_and_its_legend_hides_nothing():
    from gearrotor.plots import plot_campbell

    fig = plot_campbell(
        _campbell(),
        max_frequency=50000 * RPM,
        operating_speed=6000 * RPM,
        max_continuous_speed=6300 * RPM,
        operating_range=(5400 * RPM, 6300 * RPM),
    )
    ax = fig.axes[0]
    (legend,) = fig.legends
    labels = [t.get_text() for t in legend.get_texts()]
    assert "operating speed 6,000 rpm" in labels and "MCS 6,300 rpm" in labels
    assert "operating range" in labels and "crossing" in labels and "1x" in labels
    assert "30x" not in labels  # above the axes at every speed: neither drawn nor listed
    assert "30x" in ax.get_title()  # but named
    assert not any(line.get_label() == "30x" for line in ax.lines)
    # the vertical lines are at the speeds
    xs = {line.get_label(): line.get_xdata()[0] for line in ax.lines if "rpm" in line.get_label()}
    assert xs == pytest.approx({"operating speed 6,000 rpm": 6000.0, "MCS 6,300 rpm": 6300.0})
    # the legend sits outside the axes: it hides no marker
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    assert not _overlap(legend.get_window_extent(r), ax.get_window_extent(r))


def test_campbell_plotly_marks_speeds_and_lists_no_off_scale_line():
    pytest.importorskip("plotly")
    from gearrotor.plots.report.sections.campbell import campbell_figure

    fig = campbell_figure(
        _campbell(),
        max_frequency=50000 * RPM,
        mode_rows=[7, None],
        operating_speed=6000 * RPM,
        max_continuous_speed=6300 * RPM,
    )
    names = [t.name for t in fig.data if t.showlegend is not False]
    assert "30x" not in names and "1x" in names
    assert "operating speed 6,000 rpm" in names and "MCS 6,300 rpm" in names
    assert "30x" in fig.layout.title.text
    # the tracks are named by the modal table's row (a track without one: "track j")
    assert [t.name for t in fig.data[:2]] == ["mode 7", "track 1"]
    assert fig.layout.legend.y < 0  # below the plot area


def test_mode_shape_legend_names_the_axial_curve(examples):
    # the legend was taken from the first row's last panel: an axial curve drawn only in a
    # later row (the flagship's axial mode 26 under its mode 7) was missing from it
    from gearrotor.analyses import modal
    from gearrotor.plots import plot_mode_shapes

    res = modal(
        load_model(examples / "unity_gearbox.toml"), speed=6500 * RPM, max_frequency=2e5 * RPM
    )
    axial = int(np.argmin(abs(res.frequency_rpm - 152255)))
    assert res.mode_type[axial] == "A"
    fig = plot_mode_shapes(res, modes=[7, axial])
    (legend,) = fig.legends
    labels = [t.get_text() for t in legend.get_texts()]
    assert labels == ["lateral", "torsional θz·r", "axial z", "bearing", "gear"]
    fig = plot_mode_shapes(res, modes=[7])  # no axial curve drawn: not listed
    assert "axial z" not in [t.get_text() for t in fig.legends[0].get_texts()]


def test_bearing_coefficients_one_row_per_bearing(examples):
    # the steam turbine's bull-gear coefficients are ~40x the pinion's: on shared axes the
    # pinion's curves were flat lines at the bottom
    from gearrotor.assembly import assemble
    from gearrotor.plots.report import plot_bearing_coefficients

    asm = assemble(load_model(examples / "steam_turbine_gearbox.toml"))
    tab = [b for b in asm.bearings if b.element.speed_dependent]
    assert len(tab) == 4
    fig = plot_bearing_coefficients(asm, speed=abs(asm.train.speed))
    axes = np.array(fig.axes).reshape(len(tab), 2)
    for b, row in zip(tab, axes, strict=True):
        for col, ax in enumerate(row):
            assert ax.get_title().startswith(b.name)
            own = b.element.table.values[:, 4 * col : 4 * col + 4]
            lo, hi = ax.get_ylim()
            # each panel is scaled to its own bearing's values (5 % matplotlib margins)
            span = max(own.max(), 0) - min(own.min(), 0)
            assert hi - lo < 1.2 * span
    pin = axes[0, 0].get_ylim()[1]
    bull = axes[-1, 0].get_ylim()[1]
    assert bull > 10 * pin  # the scales the shared axes had to reconcile


def test_floquet_ka_axis_is_numeric():
    # the Ka/Kg values were categories ("0", "0.2", "0.5" equally spaced, "model" among them)
    from gearrotor.cli.floquet import growth_figure

    def case(g, ka_model=0.3):
        return SimpleNamespace(
            growth=np.array([g]),
            neutral_tolerance=1e-3,
            speed=6500 * RPM,
            to_dict=lambda: {"mesh_laws": [{"ka_ratio": ka_model}]},
        )

    fig = growth_figure([case(0.0), case(0.01), case(0.5), case(0.02)], 1, [0.0, 0.2, 0.5, None])
    (line,) = [ln for ln in fig.axes[0].lines if ln.get_label() == "largest growth rate"]
    assert np.asarray(line.get_xdata(), float).tolist() == [0.0, 0.2, 0.3, 0.5]
    assert np.asarray(line.get_ydata(), float).tolist() == [0.0, 0.01, 0.02, 0.5]
    assert [t.get_text() for t in fig.axes[0].texts] == ["model"]


def _no_two_labels_overlap(fig) -> int:
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    from matplotlib.text import Text

    # the text's own box (an Annotation's extent includes its leader line)
    boxes = [Text.get_window_extent(t, r) for ax in fig.axes for t in ax.texts]
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            assert not _overlap(a, b)
    return len(boxes)


def test_operating_point_labels_do_not_overlap():
    # the steam turbine's LC1..LC4 at 0..1000 kW: the labels were printed on each other
    from gearrotor.plots.static import plot_bearing_loads, plot_log_dec_vs_power

    fig = plot_log_dec_vs_power(
        [0, 50e3, 500e3, 1000e3, 2500e3, 12500e3],
        [0.107, 0.13, 0.265, 0.266, 0.266, -0.002],
        names=[f"LC{i}" for i in range(1, 7)],
        threshold=0.1,
    )
    assert _no_two_labels_overlap(fig) == 6

    def point(name, loads):
        bearings = {
            b: SimpleNamespace(name=b, kind="fluid-film", angle=a, magnitude=m)
            for b, (a, m) in loads.items()
        }
        return SimpleNamespace(
            operating_point=name,
            bearings=list(bearings.values()),
            bearing=lambda b, d=bearings: d[b],
        )

    pts = [
        point(f"LC{i}", {"pin": (1.0, 1e3 + 300 * i), "bull": (4.4, 1e3 + 8000 * i)})
        for i in range(8)
    ]
    fig = plot_bearing_loads(pts)
    assert _no_two_labels_overlap(fig) == 16
