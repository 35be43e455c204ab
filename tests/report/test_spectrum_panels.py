"""Issue 22: a spectrum panel that zooms into the mesh frequency does not autoscale round-off
and window leakage as if they were signal. The run-up of tests/report/conftest.py has a constant
mesh stiffness: nothing excites the mesh frequency, and the gear's x spectrum there is the Hann
window's leakage of the 1x peak, ~1e-8 of it (1.3e-6 µm against 86 µm). The panel spans at
least :data:`gearrotor.signals.DISPLAY_FLOOR` (1e-6) of the spectrum's largest line and says
so; content above the floor (a time-varying mesh: 4.4e-6 of the peak, see the constant's
comment) is scaled as before."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from gearrotor.signals import DISPLAY_FLOOR

pytest.importorskip("matplotlib")


def test_mesh_panels_of_the_transient_spectra(runup_result):
    from gearrotor.analyses.transient.plots import plot_spectra

    res, _ = runup_result
    fig = plot_spectra(res)
    axes = np.array(fig.axes).reshape(2, 3)
    for row in axes:
        full, near_1x, near_mesh = row
        # the spectrum is each panel's first line (then the order markers)
        peak = float(np.max(full.lines[0].get_ydata()))
        shown = float(np.max(near_mesh.lines[0].get_ydata()))
        assert shown < DISPLAY_FLOOR * peak  # leakage only, in this run
        assert near_mesh.get_ylim()[1] == pytest.approx(DISPLAY_FLOOR * peak, rel=1e-9)
        (note,) = near_mesh.texts
        assert "below 1e-06" in note.get_text()
        # the 1x panel holds the signal: scaled to it, no note
        top = float(np.max(near_1x.lines[0].get_ydata()))
        assert near_1x.get_ylim()[1] == pytest.approx(1.05 * top)
        assert not near_1x.texts


def test_waterfall_band_below_the_floor_is_drawn_flat():
    from gearrotor.plots.waterfall import _gain

    f = np.linspace(0, 200_000, 401)
    amp = np.full((5, 401), 1e-14)
    amp[:, 10] = 1e-4  # the 1x line, 100 µm
    wf = SimpleNamespace(speed_rpm=np.linspace(3000, 5000, 5), amplitude=amp)
    spacing = 500.0
    # the 1x band: the largest line is 4 window spacings tall, no note
    gain, bar, note = _gain(wf, f < 20_000)
    assert (gain * 1e-4, bar, note) == (pytest.approx(4 * spacing), 1e-4, "")
    # near the mesh frequency only 1e-14 m (1e-8 µm): the floor 1e-6 × 100 µm is 4 spacings
    gain, bar, note = _gain(wf, f > 150_000)
    assert bar == pytest.approx(DISPLAY_FLOOR * 1e-4)
    assert gain * 1e-14 == pytest.approx(4 * spacing * 1e-14 / (DISPLAY_FLOOR * 1e-4))
    assert "largest 1e-08 µm" in note
    # real content above the floor is scaled to itself
    amp[:, 350] = 5e-10
    gain, bar, note = _gain(wf, f > 150_000)
    assert (gain * 5e-10, bar, note) == (pytest.approx(4 * spacing), 5e-10, "")
