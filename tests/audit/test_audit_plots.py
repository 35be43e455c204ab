"""The audit figures draw the result's own numbers."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from gearrotor.analyses import level1, level2, ucs_map  # noqa: E402
from gearrotor.plots.audit import (  # noqa: E402
    plot_level1,
    plot_level2,
    plot_screening,
    plot_ucs_map,
)
from helpers import single_shaft  # noqa: E402

RPM = 30 / np.pi


@pytest.fixture(scope="module")
def rotor():
    return single_shaft(
        length=1.0,
        diameter=0.05,
        elements=10,
        bearings=[{"node": 0, "k": 2e6, "c": 3e3}, {"node": 10, "k": 2e6, "c": 3e3}],
        speed=600.0,
        max_continuous_speed=630.0,
        operating_speed_range=[500.0, 600.0],
    )


def test_ucs_figure(rotor, tmp_path):
    res = ucs_map(rotor, stiffness=(1e5, 1e9), n_stiffness=9, n_modes=2)
    fig = plot_ucs_map(res, path=tmp_path / "ucs.png")
    assert (tmp_path / "ucs.png").stat().st_size > 0
    ax = fig.axes[0]
    first = next(ln for ln in ax.get_lines() if ln.get_label() == "critical 1")
    np.testing.assert_allclose(first.get_ydata(), res.shafts[0].critical_speeds[:, 0] * RPM)
    assert ax.get_ylabel() == "s speed (rpm)"


def test_level1_and_screening_figures(rotor, tmp_path):
    r = level1(rotor, qa=2e5, at=[("s", 5)], average_density=12.0)
    fig = plot_level1(r, path=tmp_path / "l1.png")
    ax = fig.axes[0]
    curve = ax.get_lines()[0]
    np.testing.assert_allclose(curve.get_xdata(), r.curve_q)
    np.testing.assert_allclose(curve.get_ydata(), r.curve_log_dec)
    q0 = next(ln for ln in ax.get_lines() if ln.get_label().startswith("Q_0"))
    assert q0.get_xdata()[0] == r.threshold_q
    fig = plot_screening(r, path=tmp_path / "scr.png")
    point = next(ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("CSR"))
    assert (point.get_xdata()[0], point.get_ydata()[0]) == (12.0, r.csr)


def test_level2_figure(rotor, tmp_path):
    r = level2(rotor, speeds=[500.0, 630.0])
    fig = plot_level2(r, path=tmp_path / "l2.png")
    label = f"{500.0 * RPM:.0f} rpm forward"
    fwd = next(ln for ln in fig.axes[0].get_lines() if ln.get_label() == label)
    expect = [m.frequency * RPM for m in r.evaluations[0].modes if m.forward]
    np.testing.assert_allclose(fwd.get_xdata(), expect)


def test_screening_chart_shows_the_machine_without_a_density(rotor, tmp_path):
    """Q_A given directly, no gas density (a gearbox, a steam turbine): the machine's CSR is
    drawn across the chart (it was left off: the chart was empty, and its CSR below the axis
    range), and the legend says the region is not evaluated."""
    r = level1(rotor, qa=2e5, at=[("s", 5)], n_curve=3)
    fig = plot_screening(r, path=tmp_path / "scr.png")
    ax = fig.axes[0]
    line = next(ln for ln in ax.get_lines() if ln.get_label().startswith("CSR"))
    assert np.all(np.asarray(line.get_ydata()) == r.csr)
    assert "not evaluated" in line.get_label()
    lo, hi = ax.get_ylim()
    assert lo < r.csr < hi


def test_level1_chart_draws_the_least_forward_log_dec(tmp_path):
    """When another forward mode is weaker than the followed one, its log dec is drawn."""
    from test_stability import disk_rotor

    r = level1(disk_rotor(), qa=1e4, at=[("s", 2)])
    fig = plot_level1(r, path=tmp_path / "l1.png")
    ax = fig.axes[0]
    least = next(ln for ln in ax.get_lines() if ln.get_label().startswith("least"))
    np.testing.assert_allclose(least.get_ydata(), r.curve_least_log_dec)
    followed = ax.get_lines()[0]
    assert followed.get_label() == "first forward mode of s (followed)"
    assert r.edition in ax.get_title()
