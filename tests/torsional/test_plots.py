"""The torsional figures draw what the results hold (files written, the numbers on them)."""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.torsional import (
    SNCurve,
    fatigue,
    interference,
    torsional_modes,
    torsional_response,
    torsional_transient,
)
from gearrotor.plots.torsional import (
    plot_fatigue_damage,
    plot_interference,
    plot_torsional_modes,
    plot_torsional_response,
    plot_torsional_transient,
)
from torsional_helpers import driven_gear_pair

pytest.importorskip("matplotlib")


def test_figures(tmp_path):
    t = driven_gear_pair()
    modes = torsional_modes(t)
    fig = plot_torsional_modes(modes, path=tmp_path / "modes.png")
    assert f"{modes.frequency_hz[1]:.2f} Hz" in fig.axes[0].get_ylabel()
    inter = interference(modes, speed_range=(1000 * np.pi / 30, 1500 * np.pi / 30))
    fig = plot_interference(inter, path=tmp_path / "interference.png")
    assert f"{len(inter.failures)} of {len(inter.crossings)}" in fig.axes[0].get_title()
    resp = torsional_response(
        t,
        excitations=[{"shaft": "g", "node": 0, "amplitude": 20.0, "order": 1.0}],
        speeds=np.linspace(50, 200, 40),
    )
    plot_torsional_response(resp, path=tmp_path / "response.png")
    tr = torsional_transient(t, t_end=0.5)
    fig = plot_torsional_transient(tr, path=tmp_path / "transient.png")
    assert len(fig.axes) == 4
    fa = fatigue(tr, SNCurve.from_point(m=6.0, stress="20 MPa", cycles=1e4))
    fig = plot_fatigue_damage(fa, path=tmp_path / "fatigue.png")
    assert f"{fa.allowable_starts:.3g}" in fig.axes[0].get_title()
    for name in ("modes", "interference", "response", "transient", "fatigue"):
        assert (tmp_path / f"{name}.png").stat().st_size > 10_000
    import matplotlib.pyplot as plt

    plt.close("all")  # pyplot keeps figures: the suite warns (an error) past 20


def test_interference_legend_names_the_bands(tmp_path):
    """Issue 22: the wide band (where a crossing fails the margin) was unlabelled and the
    operating band read "operating range" for a single speed."""
    modes = torsional_modes(driven_gear_pair())
    rpm = np.pi / 30
    one = interference(modes, speed_range=(1500 * rpm, 1500 * rpm))
    labels = [t.get_text() for t in plot_interference(one).axes[0].get_legend().get_texts()]
    assert "operating speed 1500 rpm" in labels
    assert "crossings here fail the ±10% margin" in labels
    rng = interference(modes, speed_range=(1000 * rpm, 1500 * rpm))
    labels = [t.get_text() for t in plot_interference(rng).axes[0].get_legend().get_texts()]
    assert "operating range 1000–1500 rpm" in labels


def test_transient_shaft_torques_share_one_sign_convention():
    """Issue 22: a shaft's torque was drawn with the opposite sign of the others (GJ/L Δθ about
    +z: its sign depends on the sense of rotation and the end the power enters); per unit of
    the signed rated torque every shaft in the load path transmits a positive torque."""
    tr = torsional_transient(driven_gear_pair(), t_end=3.0)
    ax = plot_torsional_transient(tr).axes[2]
    lines = [ln for ln in ax.get_lines() if ln.get_label().endswith("/ rated")]
    assert len(lines) == 2  # the gear's and the pinion's most loaded elements
    ends = [float(np.mean(ln.get_ydata()[-200:])) for ln in lines]
    assert min(ends) > 0.2  # both positive (the gear's was negative)
