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
