"""Campbell diagrams in a reduced basis (issue 16): the same eigenvalues as the full solve at
every speed, a residual for each mode, and a fall back to the full solve where it is needed.

Oracle: agreement between methods, the full-model damped eigen solve being the reference
(itself validated against the dissertation's table and closed forms in tests/test_unity_gearbox.py
and tests/test_rotor_analytic.py). Tolerance 1e-6 relative on the damped frequency and on the
log decrement (issue 16's requirement), plus 1e-9 absolute on the log decrement: undamped
axial/torsional modes have log decs of round-off size (~1e-12) whose relative change means
nothing.
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses import campbell
from gearrotor.assembly import assemble
from gearrotor.io import load_model

RPM = np.pi / 30
FMAX = 80000 * RPM
RADIUS = 1.5 * FMAX


def _assert_same_modes(reduced, full):
    """Every tracked mode of ``reduced`` at every speed equals the nearest eigenvalue of the
    full solve there (the reduced speeds' results hold only the tracked modes), and the two
    diagrams track the same modes in the same columns."""
    assert len(reduced.modal_results) == len(full.modal_results)
    for k, rb in enumerate(full.modal_results):
        keep = ~rb.overdamped & (np.abs(rb.eigenvalues) <= RADIUS)
        lb, ldb = rb.eigenvalues[keep], rb.log_dec[keep]
        for f, ld in zip(reduced.damped_frequency[k], reduced.log_dec[k], strict=True):
            j = int(np.argmin(np.abs(lb.imag - f)))
            assert abs(f / lb[j].imag - 1) <= 1e-6, (rb.speed / RPM, f / RPM)
            assert abs(ld - ldb[j]) <= 1e-6 * abs(ldb[j]) + 1e-9, (rb.speed / RPM, ld, ldb[j])
    np.testing.assert_allclose(reduced.damped_frequency, full.damped_frequency, rtol=1e-6)
    np.testing.assert_allclose(reduced.log_dec, full.log_dec, rtol=1e-6, atol=1e-9)


@pytest.fixture(scope="module")
def flagship(examples):
    return assemble(load_model(examples / "unity_gearbox.toml"))


def test_flagship_campbell_reduced_matches_full(flagship):
    """The flagship's 60-speed Campbell to 80,000 cpm (issue 16): two full eigen solves, the
    other 58 speeds in the span of the tracked shapes of those two, every tracked mode within
    1e-6 of the full solve, the residuals reported and below the tolerance."""
    speeds = np.linspace(0, 12000, 60) * RPM
    red = campbell(flagship, speeds=speeds, max_frequency=FMAX, keep_results=True)
    full = campbell(flagship, speeds=speeds, max_frequency=FMAX, keep_results=True, reduced=False)
    assert red.solver[0] == "full"
    # measured 2: 0 rpm (where forward and backward modes coincide and their shapes are any
    # combination) and 610 rpm, whose shapes with those of 0 rpm span the rest of the range
    assert red.full_solves <= 3
    assert full.full_solves == 60
    assert red.residual.shape == red.damped_frequency.shape
    is_red = np.array(red.solver) == "reduced"
    assert np.all(red.residual[is_red] <= 1e-4)
    # ARPACK's converged Ritz pairs (shift-invert, default tolerance): residuals ~1e-6
    assert np.all(full.residual < 1e-5)
    _assert_same_modes(red, full)
    d = red.to_dict()
    assert d["full_solves"] == red.full_solves and len(d["solver"]) == 60


def test_speed_dependent_bearings_reduced_matches_dense(examples):
    """Tabulated bearing coefficients (SPEC 6.2's train, 2,000–16,000 rpm): the matrices
    change with speed; the reduced basis still reproduces the dense solve at every speed."""
    asm = assemble(load_model(examples / "steam_turbine_gearbox.toml"))
    speeds = np.linspace(2000, 16000, 25) * RPM
    red = campbell(asm, speeds=speeds, max_frequency=FMAX, keep_results=True, method="dense")
    full = campbell(
        asm, speeds=speeds, max_frequency=FMAX, keep_results=True, method="dense", reduced=False
    )
    assert red.full_solves < len(speeds) // 2
    _assert_same_modes(red, full)


def test_failed_residual_check_falls_back_to_full_solve(flagship):
    """A residual tolerance no reduced solve can meet: every speed is solved on the full model
    and the diagram is the full one exactly."""
    speeds = np.linspace(1000, 3000, 4) * RPM
    red = campbell(flagship, speeds=speeds, max_frequency=FMAX, method="dense", residual_tol=0.0)
    full = campbell(flagship, speeds=speeds, max_frequency=FMAX, method="dense", reduced=False)
    assert red.solver == ("full",) * 4
    np.testing.assert_array_equal(red.damped_frequency, full.damped_frequency)
    np.testing.assert_array_equal(red.log_dec, full.log_dec)
