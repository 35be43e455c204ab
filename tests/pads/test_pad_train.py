"""Tilting pads with their DOFs in the train (issue 24, item 3): the pad model against the
synchronously reduced model it contains.

Oracles: the condensation identity of Lund's pad assembly method (Lund 1964, "Spring and
damping coefficients for the tilting-pad journal bearing", ASLE Trans. 7; the reduction of
Dimond, Younan & Allaire 2011, "A review of tilting pad bearing theory", IJRM 908469, eq. for
Z_r): eliminating the pad DOFs of ``Z(s) = K + sC + s²M`` leaves the journal impedance
``Z_r(s)``, so (1) the pad model's forced response at ω equals the response of the model whose
bearings carry the coefficients reduced at ω (exact), and (2) every eigenvalue λ of the pad
model makes the rotor's impedance with ``Z_r(λ)`` singular (exact).
"""

import numpy as np
import pytest
from pad_models import reduced_at, rotor_impedance, write

from gearrotor.analyses.lateral.modal import modal
from gearrotor.analyses.lateral.unbalance import unbalance_response
from gearrotor.assembly import assemble

RPM = np.pi / 30


@pytest.fixture(scope="module")
def pad_model(tmp_path_factory):
    train = write(tmp_path_factory.mktemp("pads"))
    return train, assemble(train)


def test_pad_dofs_in_the_global_matrices(pad_model):
    train, asm = pad_model
    # 7 nodes × 6 DOFs, then 4 tilts per bearing
    assert asm.n_dof == 42 + 8
    assert list(asm.pad_dofs) == list(range(42, 50))
    assert asm.dof_labels[42] == "bearings[0].tilt_1"
    assert (asm.dof_kind()[42:] == 3).all()
    M, C, G, K = asm.matrices(train.speed)
    el = asm.bearings[0].element
    # the pads' inertia on their DOFs, the full film matrices on journal + pads
    assert M.toarray()[42, 42] == pytest.approx(2e-4)
    kf, cf = el.pads.at(train.speed)
    d = np.r_[asm.bearings[0].dofs, asm.bearings[0].pad_dofs]
    np.testing.assert_allclose(K.toarray()[np.ix_(d[2:], d)], kf[2:], rtol=1e-12)
    np.testing.assert_allclose(C.toarray()[np.ix_(d[2:], d)], cf[2:], rtol=1e-12)


@pytest.mark.parametrize("rpm", [6000.0, 7500.0])  # a table speed and one between
def test_synchronous_response_equals_the_reduced_model(tmp_path, rpm):
    """The exact identity: the pad model's unbalance response at Ω equals that of the model
    with the coefficients condensed at whirl = Ω (the synchronously reduced ones, also between
    table speeds: both come from the same interpolated full matrices)."""
    train = write(tmp_path, speed=rpm)
    asm = assemble(train)
    w = rpm * RPM
    red = reduced_at(train, asm, w)
    full = unbalance_response(asm, speeds=[w])
    sync = unbalance_response(red, speeds=[w])
    assert len(full.response[0, 0]) == len(sync.response[0, 0]) + 8
    a = full.response[0, 0, :42]
    b = sync.response[0, 0]
    # round-off of two LU solves on matrices with entries from 1e-4 to 1e9: 1e-9
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * np.abs(b).max())
    # and the element's own 2×2 coefficients are that condensation
    k, c = asm.bearings[0].element.K(w), asm.bearings[0].element.C(w)
    kr, cr = asm.bearings[0].element.pads.reduced(w, w)
    np.testing.assert_array_equal(k, kr)
    np.testing.assert_array_equal(c, cr)


def test_eigenvalues_are_roots_of_the_condensed_impedance(pad_model):
    """Every eigenvalue of the pad model is a root of the rotor impedance with Z_r(λ): the
    eigenvector's shaft part is a null vector of it (relative residual at round-off)."""
    train, asm = pad_model
    res = modal(asm, max_frequency=40000 * RPM)
    rotor = [i for i in range(len(res)) if res.mode_type[i] != "P"]
    assert len(rotor) >= 4
    for i in rotor:
        lam = res.eigenvalues[i]
        Z, keep = rotor_impedance(asm, lam, train.speed)
        x = res.mode_shapes[i][keep]
        r = np.linalg.norm(Z @ x) / (np.linalg.norm(Z, 2) * np.linalg.norm(x))
        assert r < 1e-10, (i, r)


def test_modes_away_from_1x_differ_from_the_synchronous_model(pad_model):
    """The synchronously reduced model is the pad model's impedance at s = iΩ only: the
    rotor's lightly damped modes, at 1.6x here, differ from it by the frequency dependence of
    the pads (3 % in λ). The model reduced at each mode's own frequency ω = Im λ is exact for
    an undamped mode; for a damped one it misses Z_r(σ + iω) − Z_r(iω) ≈ σ Z_r'(iω), first
    order in the damping ratio: measured 0.04 ζ, so 0.1 ζ bounds it."""
    train, asm = pad_model
    w = train.speed
    top = 40000 * RPM
    full = modal(asm, max_frequency=top)
    sync = modal(assemble(reduced_at(train, asm, w)), max_frequency=top)
    lightly = [i for i in range(len(full)) if full.damping_ratio[i] < 0.3]
    assert len(lightly) >= 2
    for i in lightly:
        lam = full.eigenvalues[i]
        at = modal(assemble(reduced_at(train, asm, lam.imag)), max_frequency=top)
        err_whirl = np.min(np.abs(at.eigenvalues - lam)) / abs(lam)
        err_sync = np.min(np.abs(sync.eigenvalues - lam)) / abs(lam)
        assert err_whirl < 0.1 * full.damping_ratio[i]
        if abs(lam.imag / w - 1.0) > 0.5:  # away from 1x
            assert err_sync > 3 * err_whirl
