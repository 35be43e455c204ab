"""Issue 14 item 8: a tilting-pad bearing with unloaded pads and no pad inertia (the default)
gives coefficients instead of LinAlgError: Singular matrix."""

from __future__ import annotations

import numpy as np

from gearrotor.bearings import coefficients
from gearrotor.bearings.film import Grid, SolverOptions
from gearrotor.bearings.geometry import tilting_pad

RPM = np.pi / 30
OPTS = SolverOptions(grid=Grid(n_theta=24, n_z=6))  # the examples' grid


def _bearing(inertia: float = 0.0):
    # 5 pads, load on pad (pivot at 270°, the load along −y), no preload: the top pads unload
    return tilting_pad(
        0.28,
        0.18,
        147e-6,
        0.0152,
        [np.radians(a) for a in (270, 342, 54, 126, 198)],
        np.radians(60),
        inertia=inertia,
    )


def test_unloaded_pads_without_inertia():
    load, w = (0.0, -20e3), 5700 * RPM
    res = coefficients(_bearing(), load, w, options=OPTS)
    free = np.abs(res.K_full).sum(axis=1)[2:] == 0
    assert free.any()  # at least one pad carries no film force (the case that crashed)
    assert np.all(np.isfinite(res.K)) and np.all(np.isfinite(res.C))
    assert np.all(np.diag(res.K) > 0) and np.all(np.diag(res.C) > 0)
    # a free pad does not couple to the journal: the condensed coefficients equal those of the
    # same bearing with a vanishing pad inertia (1e-9 kg·m², which makes Z_pp invertible and
    # changes a loaded pad's impedance by ω²J ~ 4e-4 N·m/rad against ~1e6)
    ref = coefficients(_bearing(1e-9), load, w, options=OPTS)
    np.testing.assert_allclose(res.K, ref.K, rtol=1e-8, atol=1e-8 * np.abs(ref.K).max())
    np.testing.assert_allclose(res.C, ref.C, rtol=1e-8, atol=1e-8 * np.abs(ref.C).max())
