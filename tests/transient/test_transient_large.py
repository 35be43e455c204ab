"""Issue 28: the modal transient's setup on a large model solves sparsely (the modes below the
cut-off by shift-invert Lanczos, the static and harmonic responses by a sparse LU;
``reduction.SPARSE_FROM`` DOFs on). Checked here on a 4-shaft chain (504 DOFs) and a
2-shaft one with backlash, against the dense setup (the threshold raised), which the examples
(≤ 252 DOFs) use."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la

from gearrotor.analyses.transient import reduction, transient
from gearrotor.analyses.transient.equations import build_system
from gearrotor.io import model_from_dict
from gearrotor.threads import scope
from helpers import chain


@pytest.fixture(scope="module")
def train():
    return model_from_dict(chain(4, 20))


def test_lanczos_modes_are_the_dense_ones(train, monkeypatch):
    """Below the cut-off the sparse spectrum holds the dense solve's modes: eigenvalues within
    1e-9 (relative; ARPACK at machine precision, then Rayleigh–Ritz), the same span (the
    identical shafts give 4-fold frequencies, whose vectors any solver may rotate: compared
    by principal angles, cosines 1 to 1e-10) and M-orthonormal to round-off."""
    system = build_system(train)
    M, K, _ = system.linear_matrices()
    Ks = reduction.basis_stiffness(system, K)
    monkeypatch.setattr(reduction, "SPARSE_FROM", 0)  # (the small ones too)
    wcut = 2 * np.pi * 4000.0
    with scope():  # one BLAS thread, as in an analysis
        w2d, Vd = la.eigh(Ks, M)
        spec = reduction.Spectrum(Ks, M)
        w2s, Vs = spec.upto(wcut)
        more = spec.upto(2 * wcut)[0]
    assert not spec.dense and not spec.complete and w2s[-1] > wcut**2
    kd = w2d <= wcut**2
    ks = w2s <= wcut**2
    assert kd.sum() == ks.sum() > 40
    a, b = w2d[kd][1:], w2s[ks][1:]  # (the rigid rotation: 0 to round-off in both)
    np.testing.assert_allclose(b, a, rtol=1e-9)
    cos = np.linalg.svd(Vd[:, kd].T @ M @ Vs[:, ks], compute_uv=False)
    assert cos.min() > 1 - 1e-10
    np.testing.assert_allclose(Vs.T @ M @ Vs, np.eye(Vs.shape[1]), atol=1e-12)
    # a higher cut-off solves again with more modes
    assert more[-1] > (2 * wcut) ** 2 and len(more) > len(w2s)


def test_sparse_setup_runs_the_same_transient(train, monkeypatch):
    """The whole transient with the sparse setup against the dense one: same modal basis
    (count, step, cut-off), the shaft speeds and recorded DOFs within 1e-8 and the forces
    within 1e-4 of their peaks. The forces' tolerance is the problem's own: a 1e-15 relative
    perturbation of Ks moves the dense result's mesh force by 2e-4 (the chain's near-equal
    frequencies make its single mode shapes depend on round-off, measured), and the sparse
    setup's differ by 2.5e-6."""
    monkeypatch.setattr(reduction, "SPARSE_FROM", 10**9)
    ref = transient(train, t_end=0.01)
    monkeypatch.setattr(reduction, "SPARSE_FROM", 0)
    r = transient(train, t_end=0.01)
    assert r.stats.n_modes == ref.stats.n_modes
    assert r.stats.dt == pytest.approx(ref.stats.dt, rel=1e-12)
    assert r.stats.harmonic_error == pytest.approx(ref.stats.harmonic_error, rel=1e-6)

    def close(x, y, tol):
        assert np.max(np.abs(x - y)) <= tol * np.max(np.abs(y))

    close(r.shaft_speed, ref.shaft_speed, 1e-8)
    close(r.q, ref.q, 1e-8)
    close(r.mesh_force, ref.mesh_force, 1e-4)
    close(r.bearing_force, ref.bearing_force, 1e-4)


def test_sparse_setup_with_backlash(monkeypatch):
    """With backlash the basis adds the free shafts' torsional modes (a second spectrum, of the
    train without meshes) and static shapes: the sparse setup gives the dense one's basis and
    run (2-shaft chain, 0.02 s, backlash 0.1 mm). The contact changes make this run more
    sensitive to round-off: a 1e-15 relative perturbation of Ks moves the dense result's shaft
    speeds by 1.3e-8, q by 2.2e-10, the mesh force by 1.9e-5 (measured); the sparse setup's
    differ by 9.5e-8, 8.3e-10 and 1.4e-4. Bounds: 10× those."""
    data = chain(2, 40)
    data["meshes"][0]["backlash"] = {"value": "0.1 mm", "convention": "total"}
    train = model_from_dict(data)
    monkeypatch.setattr(reduction, "SPARSE_FROM", 10**9)
    ref = transient(train, t_end=0.02)
    monkeypatch.setattr(reduction, "SPARSE_FROM", 0)
    r = transient(train, t_end=0.02)
    assert r.stats.n_modes == ref.stats.n_modes
    assert r.stats.dt == pytest.approx(ref.stats.dt, rel=1e-12)
    for x, y, tol in (
        (r.shaft_speed, ref.shaft_speed, 1e-6),
        (r.q, ref.q, 1e-8),
        (r.mesh_force, ref.mesh_force, 1e-3),
    ):
        assert np.max(np.abs(x - y)) <= tol * np.max(np.abs(y))
