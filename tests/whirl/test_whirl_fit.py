"""The rational fit of a journal impedance sampled over whirl (issue 24).

Oracle: vector fitting recovers a rational function exactly when the samples outnumber its
unknowns (Gustavsen & Semlyen 1999, IEEE Trans. Power Delivery 14(3):1052, section V: exact
identification of a known rational function). The functions here are built from closed forms:
partial fractions with a real pole and a complex pair and an added-mass s² term.
"""

import numpy as np
import pytest

from gearrotor.elements.rational_fit import fit_impedance, impedance_samples


def _known(s: complex) -> np.ndarray:
    """A 2×2 impedance: D + sE + s²F + R1/(s − p1) + R2/(s − p2) + conj, p1 real, p2 complex."""
    D = np.array([[3e7, 4e6], [-2e6, 5e7]])
    E = np.array([[2e4, 1e3], [1e3, 3e4]])
    F = np.array([[6.0, 0.5], [-0.5, 6.0]])  # added mass M, m (Childs): Z(iω) = K − Mω² + …
    p1, R1 = -900.0, np.array([[-4e9, 1e9], [0.0, -2e9]])
    p2 = -150.0 + 1100.0j
    R2 = np.array([[-2e9 + 1e9j, 3e8], [-3e8j, -1e9 - 5e8j]])
    return D + s * E + s * s * F + R1 / (s - p1) + R2 / (s - p2) + np.conj(R2) / (s - np.conj(p2))


def _table(fun, whirl):
    vals = []
    for w in whirl:
        z = fun(1j * max(w, 1e-9))
        vals.append([*z.real.ravel(), *(z.imag / max(w, 1e-9)).ravel()])
    return np.array(vals)


def test_a_known_rational_impedance_is_recovered_to_round_off():
    whirl = np.linspace(0.0, 3000.0, 12)
    fit, misfit = fit_impedance(whirl, _table(_known, whirl), tolerance=1e-10)
    # three poles (a real one and a pair), rank-2 residues: 2 + 4 states, an s² term
    assert misfit < 1e-12
    assert sorted(np.round(fit.poles.real, 6)) == [-900.0, -150.0, -150.0]
    assert fit.n_states == 6
    np.testing.assert_allclose(fit.F, [[6.0, 0.5], [-0.5, 6.0]], rtol=1e-8)
    # off the whirl axis too (the point of the fit: damped eigenvalues), and Z(s̄) = conj Z(s)
    for s in (-300 + 500j, -40 + 2500j, -1500 + 10j):
        ref = _known(s)
        assert np.linalg.norm(fit.at(s) - ref) < 1e-10 * np.linalg.norm(ref)
        np.testing.assert_allclose(fit.at(np.conj(s)), np.conj(fit.at(s)), rtol=1e-13)
    # the coefficients at a whirl frequency between the samples
    k = fit.coefficients(1234.0)
    z = _known(1234.0j)
    np.testing.assert_allclose(k[:4], z.real.ravel(), rtol=1e-10)
    np.testing.assert_allclose(k[4:], z.imag.ravel() / 1234.0, rtol=1e-10)


def test_constant_coefficients_need_no_pole():
    whirl = np.linspace(0.0, 2000.0, 5)
    row = np.tile([2e7, 1e6, -1e6, 3e7, 2e4, 0.0, 0.0, 2e4], (5, 1))
    fit, misfit = fit_impedance(whirl, row, tolerance=1e-10)
    assert fit.n_poles == 0 and fit.n_states == 0
    assert misfit < 1e-14
    np.testing.assert_allclose(fit.D.ravel(), row[0, :4], rtol=1e-13)
    np.testing.assert_allclose(fit.E.ravel(), row[0, 4:], rtol=1e-13, atol=1e-9)


def test_the_lowest_order_within_the_tolerance_is_chosen():
    """A looser tolerance takes fewer poles; the misfit falls as the order rises."""
    whirl = np.linspace(0.0, 3000.0, 12)
    vals = _table(_known, whirl)
    coarse, m_coarse = fit_impedance(whirl, vals, tolerance=3e-2)
    fine, m_fine = fit_impedance(whirl, vals, tolerance=1e-10)
    assert coarse.n_poles < fine.n_poles
    assert m_fine < 1e-12 < m_coarse <= 3e-2


def test_a_table_too_coarse_for_the_tolerance_returns_its_best_misfit():
    """Four samples allow at most two unknowns per entry beyond D, E (no over-fitting): the
    three-pole function cannot be met at 1e-10; the caller turns that into an error."""
    whirl = np.linspace(0.0, 3000.0, 4)
    fit, misfit = fit_impedance(whirl, _table(_known, whirl), tolerance=1e-10)
    assert misfit > 1e-6
    assert fit.n_poles <= 2


@pytest.mark.parametrize("n", [6, 9])
def test_samples_are_the_table_coefficients(n):
    """impedance_samples: Z(iω) = K + iωC entry by entry (xx, xy, yx, yy)."""
    whirl = np.linspace(0.0, 100.0, n)
    vals = np.arange(8.0 * n).reshape(n, 8)
    z = impedance_samples(whirl, vals)
    np.testing.assert_array_equal(z.real, vals[:, :4])
    np.testing.assert_array_equal(z.imag, whirl[:, None] * vals[:, 4:])


def test_no_negative_added_mass_and_no_negative_damping():
    """A spring k1 beside a spring k2 in series with a damper c (a Maxwell element): K(ω)
    rises and C(ω) falls with ω, Z(s) = k1 + k2 c s / (k2 + c s), one real pole. An s² term
    could follow the stiffening only with a negative mass, whose continuation m λ² + k = 0
    (m < 0) grows: the fit takes the pole, its added mass and its damping stay positive at
    every frequency, and the function is recovered."""
    k1, k2, c = 2e7, 3e7, 2e4

    def z(s):
        return (k1 + k2 * c * s / (k2 + c * s)) * np.eye(2)

    whirl = np.linspace(0.0, 3000.0, 10)
    fit, misfit = fit_impedance(whirl, _table(z, whirl), tolerance=1e-10)
    assert misfit <= 1e-10
    assert np.linalg.eigvalsh(0.5 * (fit.F + fit.F.T)).min() >= -1e-9
    np.testing.assert_allclose(fit.poles, [-k2 / c], rtol=1e-8)
    for w in np.logspace(0, 6, 13):
        assert fit.coefficients(w)[4] > 0


def test_a_coarse_table_is_not_fitted_with_negative_damping():
    """Three samples: K 1e7, 1.1e7, 1.3e7 N/m at 0, 200, 400 rad/s with C = 1e3 N·s/m (a
    ROSS-style coarse table). The one-pole fit that meets it within 1.5 % does so with a pole at
    −1.1e8 rad/s against a high-frequency damping E = −2e9 N·s/m: C(ω) < 0 from ~5e4 rad/s,
    which in a rotor model gave growing real roots. It is refused: the fit keeps the table's
    positive damping at every frequency (here with no pole, misfit 15 %, which the caller
    judges against its tolerance)."""
    whirl = np.array([0.0, 200.0, 400.0])
    row = np.zeros((3, 8))
    row[:, 0] = row[:, 3] = [1e7, 1.1e7, 1.3e7]
    row[:, 4] = row[:, 7] = 1e3
    fit, misfit = fit_impedance(whirl, row, tolerance=0.02)
    assert misfit > 0.02
    for w in np.logspace(0, 7, 15):
        assert fit.coefficients(w)[4] > 0
    assert np.all(fit.E >= 0)
