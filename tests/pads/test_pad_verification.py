"""Tilting-pad full coefficients verified (issue 24): published numbers, closed-form limits,
symmetry and energy.

* ROSS 3.1 (petrobras/ross, ``ross/tests/data/fluid_film/tilt_5pad_isoviscous.json``): an
  isoviscous 5-pad bearing, D = 400 mm, L = 263 mm, load 112.8 kN, 900 rpm; its synchronously
  condensed coefficients (pads condensed at 1x with their inertia, ROSS's
  ``dynamic_reduction``) against ours from the full matrices. ROSS solves a 20 × 10 finite-
  element film, we a 72 × 16 finite-volume one (ours move 0.6 % from 36 × 8 to 72 × 16): the
  stiffness agrees within 3.2 %, the damping within 0.5 %, the eccentricity within 0.1 %.
* Infinitely stiff pivots: the flexible-pivot model tends to the rigid-pivot one at every whirl
  frequency, the error falling as 1/k_p (the pivot is a spring in series).
* Lund 1964: with moment-free, centred pivots and the load between pads, the reduced
  cross-coupled terms vanish (to O(e/R)) at every whirl frequency, not only at 1x.
* Energy: the film damping is symmetric (for a fixed cavitated set the Reynolds squeeze
  operator is self-adjoint) and dissipative (positive semidefinite), and the pads alone, the
  journal held, are stable (they cannot feed energy).
"""

import numpy as np
import pytest

from gearrotor.bearings import Grid, SolverOptions, coefficients, tilting_pad
from gearrotor.elements import condense

DEG = np.pi / 180


def test_ross_5pad_isoviscous_synchronous_coefficients():
    D, t, L = 0.39999919999999994, 0.149614636, 0.263144
    arc = 60 * DEG
    # ROSS's pad inertia (its dynamic_reduction): m = l t L ρ, I = m (t² + l²)/12
    l_pad = arc * (D / 2 + t / 2)
    m = l_pad * t * L * 7835.631544657211
    b = tilting_pad(
        D,
        L,
        0.000194564,
        0.01901574061455835,  # the supply-temperature viscosity (isoviscous run)
        [54 * DEG + k * 72 * DEG for k in range(5)],
        arc,
        0.3,
        0.5,
        inertia=m * (t**2 + l_pad**2) / 12,
        thickness=t,
    )
    co = coefficients(
        b, (0.0, -112814.90696191376), 94.24777960769379, options=SolverOptions(grid=Grid(72, 16))
    )
    assert co.equilibrium.eccentricity_ratio == pytest.approx(0.6180221076013335, rel=1e-3)
    ross_k = np.array([[322066640.7, -984629.6], [-445193.7, 2571076993.9]])
    ross_c = np.array([[5415171.5, 433.7], [-2947.3, 19394951.8]])
    assert co.K[0, 0] == pytest.approx(ross_k[0, 0], rel=0.04)
    assert co.K[1, 1] == pytest.approx(ross_k[1, 1], rel=0.04)
    assert co.C[0, 0] == pytest.approx(ross_c[0, 0], rel=0.01)
    assert co.C[1, 1] == pytest.approx(ross_c[1, 1], rel=0.01)
    # cross terms: both near zero against the direct ones (load on the pads' symmetry line)
    assert abs(co.K[0, 1]) < 1e-3 * co.K[1, 1] and abs(ross_k[0, 1]) < 1e-3 * ross_k[1, 1]
    # and they are the condensation of the full matrices at 1x
    z = condense(co.K_full, co.C_full, co.M_full, 1j * 94.24777960769379)
    np.testing.assert_allclose(z.real, co.K, rtol=1e-12, atol=1e-9 * abs(co.K).max())


def _bearing(kp=None):
    return tilting_pad(
        0.1,
        0.05,
        80e-6,
        0.02,
        [45 * DEG, 135 * DEG, 225 * DEG, 315 * DEG],
        70 * DEG,
        0.3,
        0.5,
        inertia=2e-4,
        mass=0.4,
        thickness=0.015,
        pivot_stiffness=kp,
    )


OPTS = SolverOptions(grid=Grid(16, 4))
W = 6000 * np.pi / 30


@pytest.fixture(scope="module")
def rigid():
    return coefficients(_bearing(), (0.0, -2500.0), W, options=OPTS)


def test_stiff_pivot_limit_is_the_rigid_pivot(rigid):
    errs = []
    for kp in (1e10, 1e11):
        co = coefficients(_bearing(kp), (0.0, -2500.0), W, options=OPTS)
        e = 0.0
        for r in (0.3, 1.0, 3.0):
            z = condense(co.K_full, co.C_full, co.M_full, 1j * r * W)
            z0 = condense(rigid.K_full, rigid.C_full, rigid.M_full, 1j * r * W)
            e = max(e, float(np.abs(z - z0).max() / np.abs(z0).max()))
        errs.append(e)
    # series spring: the error ∝ 1/k_p (ratio 10 for a decade; the equilibrium shifts too)
    assert errs[1] < 2e-2
    assert errs[0] / errs[1] == pytest.approx(10.0, rel=0.2)


def test_load_between_pads_no_cross_coupling_at_any_whirl(rigid):
    for r in (0.1, 0.5, 1.0, 2.0, 5.0, 10.0):
        z = condense(rigid.K_full, rigid.C_full, rigid.M_full, 1j * r * W)
        scale = np.abs(z).max()
        assert abs(z[0, 1]) < 1e-2 * scale and abs(z[1, 0]) < 1e-2 * scale
        assert abs(z[0, 0] - z[1, 1]) < 1e-2 * scale


def test_film_damping_symmetric_dissipative_and_pads_passive(rigid):
    C = rigid.C_full
    # the velocity perturbation keeps the cavitated set: symmetric to its round-off (1e-6)
    np.testing.assert_allclose(C, C.T, rtol=0, atol=1e-6 * np.abs(C).max())
    assert np.linalg.eigvalsh(0.5 * (C + C.T)).min() > -1e-9 * np.abs(C).max()
    # journal held: M p̈ + C_pp ṗ + K_pp p = 0 decays
    K, M = rigid.K_full[2:, 2:], rigid.M_full[2:, 2:]
    n = len(K)
    A = np.block(
        [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C[2:, 2:])]]
    )
    assert np.linalg.eigvals(A).real.max() < 0


def test_whirl_table_is_the_condensation(tmp_path, rigid):
    """The speed × whirl table holds the pad assembly at each whirl frequency: its synchronous
    column is the synchronously reduced coefficients, and the CSV round-trips."""
    import csv

    from gearrotor.bearings.pads import save_whirl_table, whirl_table

    t = whirl_table(_bearing(), (0.0, -2500.0), [6000.0], [3000.0, 6000.0, 60000.0], options=OPTS)
    np.testing.assert_allclose(t.values[0, 1, :4], rigid.K.ravel(), rtol=1e-9)
    np.testing.assert_allclose(t.values[0, 1, 4:], rigid.C.ravel(), rtol=1e-9)
    z = condense(rigid.K_full, rigid.C_full, rigid.M_full, 1j * 10 * W)
    np.testing.assert_allclose(t.values[0, 2, :4], z.real.ravel(), rtol=1e-9)
    path = save_whirl_table(t, tmp_path / "w.csv")
    with path.open() as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].startswith("#")]
    assert rows[0][:3] == ["speed_rpm", "whirl_rpm", "kxx"] and len(rows) == 4
    assert float(rows[3][2]) == pytest.approx(t.values[0, 2, 0], rel=1e-12)
