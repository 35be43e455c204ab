"""Issue 14 item 2: mode shapes are signed (a second bending mode is an S, not a V)."""

from __future__ import annotations

import numpy as np
from tests.helpers import single_shaft

from gearrotor.analyses import modal
from gearrotor.plots.figures import mode_shape_curves, plot_mode_shapes


def test_second_bending_mode_changes_sign(tmp_path):
    # a uniform shaft on stiff short bearings at its ends: the second bending mode is
    # antisymmetric, sin(2πz/L) (Euler-Bernoulli, pinned-pinned): the signed curve crosses zero
    # at mid-span and reaches ±1 near the quarter points; the orbit size is |·| ≥ 0
    t = single_shaft(
        length=1.0, elements=20, bearings=[{"node": 0, "k": 1e12}, {"node": 20, "k": 1e12}]
    )
    res = modal(t, n_modes=8)
    lat = [i for i in range(len(res)) if res.mode_type[i] == "L"]
    second = lat[2]  # modes 0, 1: first bending (two planes); 2: second bending
    c = mode_shape_curves(res, second, 0)
    z, y = c["z"], c["lateral"]
    assert y.min() < -0.9 and y.max() > 0.9
    assert abs(y[10]) < 1e-6  # the node at mid-span
    np.testing.assert_allclose(
        y / y[5], np.sin(2 * np.pi * z) / np.sin(2 * np.pi * z[5]), atol=0.02
    )
    o = mode_shape_curves(res, second, 0, orbit=True)
    assert o["lateral"].min() >= 0 and o["lateral"].max() > 0.9
    fig = plot_mode_shapes(res, modes=[second], path=tmp_path / "m.png")
    assert "max 1" in fig.axes[0].get_ylabel()
    assert (tmp_path / "m.png").stat().st_size > 0
