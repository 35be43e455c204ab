"""Modal reduction of the transient model (:class:`~.options.ModalRK4`): the static correction
shapes, the reduced basis (modes up to a cut-off, the free-shaft modes, the static shapes;
Ritz re-diagonalisation) and the harmonic accuracy check against the full model."""

from __future__ import annotations

import numpy as np
import scipy.linalg as la
from numpy.typing import NDArray

from ...errors import ModelError


def basis_stiffness(system, K: NDArray) -> NDArray:
    """The symmetric stiffness the modal basis is built from (its remainder ``K − Ks`` acts as
    a force on its few DOFs): the symmetric part of K, except on the tilting pads with pad
    dynamics, whose symmetric film block is indefinite (the Couette terms couple the journal
    and the pad tilts one-sidedly) and is replaced by its positive semidefinite part (negative
    eigenvalues of the block set to 0). A basis from an indefinite Ks would have modes of
    negative ω², which the reduced model cannot keep as oscillators."""
    Ks = 0.5 * (K + K.T)
    asm = system.assembly
    for b in asm.bearings:
        if b.pad_dofs is None:
            continue
        d, T = b.local()
        idx = np.array([system.index(int(g)) for g in d])
        on = idx >= 0
        kf = b.element.pads.at(system.nominal_speeds[b.shaft])[0]
        S = 0.5 * (kf + kf.T)
        mu, V = la.eigh(S)
        A = T.T @ ((V * np.clip(mu, 0.0, None)) @ V.T - S) @ T
        Ks[np.ix_(idx[on], idx[on])] += A[np.ix_(on, on)]
    return Ks


def _static_shapes(system, M, K) -> NDArray:
    """Static correction shapes (n, k): the deflection, in the frame of the train's rigid
    rotation, under each mesh's unit normal force pattern w and each external torque."""
    ratio = system.assembly.speed_ratio
    r = np.zeros(system.n)
    for s, a in enumerate(system.a_weights):
        r[a != 0] = ratio[s]
    Mr = M @ r
    pats = []
    for law, d in zip(system.meshes, system.mesh_dofs, strict=True):
        b = np.zeros(system.n)
        b[d[d >= 0]] = law.w[d >= 0]
        pats.append(b)
    for dof in system.torque_dof:
        b = np.zeros(system.n)
        b[dof] = 1.0
        pats.append(b)
    if getattr(system, "constant_force", None) is not None:
        pats.append(np.asarray(system.constant_force, float))
    if not pats:
        return np.zeros((system.n, 0))
    A = np.block([[K, Mr[:, None]], [Mr[None, :], np.zeros((1, 1))]])
    rhs = np.vstack([np.array(pats).T, np.zeros((1, len(pats)))])
    return la.solve(A, rhs)[:-1]


def _modal_basis(M, Ks, V, w2, wcut, separated, shapes):
    """M-orthonormal basis with Ks diagonal: the modes (V, w2 of (Ks, M)) up to ``wcut``
    (rad/s), extended by ``separated`` (w2, V of the train without meshes, or None: its modes up
    to the cut-off) and the static correction ``shapes`` (n, k).

    The extra vectors are made M-orthogonal to the kept modes and to each other, then
    re-diagonalised (Ritz) among themselves: the kept modes keep their exact frequencies (the
    rigid rotation stays at zero). Directions with less than 1e-5 of their M-norm outside the
    span of the others add nothing and are dropped. Returns (Φ, ω² in rad²/s²), by frequency."""
    om = np.sqrt(np.clip(w2, 0.0, None))
    keep = om <= wcut
    if not keep.any():
        raise ModelError("no mode below the modal cut-off", value=f"{wcut / 2 / np.pi:.4g} Hz")
    B = V[:, keep]
    E = shapes
    if separated is not None:
        w2s, Vs = separated
        E = np.hstack([Vs[:, np.sqrt(np.clip(w2s, 0.0, None)) <= wcut], E])
    if not E.shape[1]:
        return B, w2[keep]
    E = E / np.sqrt(np.einsum("ij,ij->j", E, M @ E))
    # two passes: the first loses orthogonality in proportion to the norm removed, the
    # second restores it to round-off ("twice is enough")
    for _ in range(2):
        E = E - B @ (B.T @ (M @ E))
        gw, gv = la.eigh(E.T @ M @ E)
        ok = gw > 1e-10
        E = E @ (gv[:, ok] / np.sqrt(gw[ok]))
    if not E.shape[1]:
        return B, w2[keep]
    w2e, Y = la.eigh(E.T @ Ks @ E)
    Phi = np.hstack([B, E @ Y])
    w2r = np.concatenate([w2[keep], w2e])
    order = np.argsort(w2r, kind="stable")
    return Phi[:, order], w2r[order]


def _unbalance_1x(system, M, K, C):
    """The linear 1x unbalance response of the full model, per distinct shaft speed: yields
    (Ω rad/s, F (n,) complex force, X (n,) complex response of K − Ω²M + iΩ(C + G))."""
    G = system.gyroscopic()
    speeds = system.nominal_speeds
    for w in np.unique(np.round(np.abs(speeds), 9)):
        F = np.zeros(system.n, complex)
        for u, d in enumerate(system.unbalance_dofs):
            sh = system.shaft_of_row[d[0]]
            if abs(abs(speeds[sh]) - w) > 1e-6 * w:
                continue
            sig = np.sign(speeds[sh])
            f0 = system.unbalance_me[u] * w**2 * np.exp(1j * sig * system.unbalance_phase[u])
            F[d[0]] += f0
            F[d[1]] += -1j * sig * f0
        if not F.any():
            continue
        yield w, F, la.solve(K - w**2 * M + 1j * w * (C + G), F)


def _harmonic_shapes(system, M, K, C) -> NDArray:
    """Real and imaginary parts (n, 2k) of the full model's linear responses to the two
    periodic excitations of a geared train: the 1x unbalance forces
    (:func:`_unbalance_1x`) and, per mesh, a force along its line of action w at its mesh
    frequency (stiffness variation and transmission error act there). With them in the basis
    the reduced model reproduces those responses exactly (a Galerkin projection is exact when
    the solution lies in its span), so the share of the modes above the cut-off in them
    (quasi-static compliance, heavily damped bearings) is kept without keeping those modes."""
    cols = [part for _, _, X in _unbalance_1x(system, M, K, C) for part in (X.real, X.imag)]
    G = system.gyroscopic()
    for law, d, rate in zip(system.meshes, system.mesh_dofs, system.mesh_rates(), strict=True):
        w = abs(float(rate))
        b = np.zeros(system.n)
        b[d[d >= 0]] = law.w[d >= 0]
        X = la.solve(K - w**2 * M + 1j * w * (C + G), b)
        cols += [X.real, X.imag]
    return np.array(cols).T.reshape(system.n, -1)


def _harmonic_error(system, M, K, C, Phi, w2r, out, Ka=None) -> float:
    """Largest relative error of the reduced model's linear 1x unbalance response at the
    recorded lateral DOFs (per distinct shaft speed), against the full model."""
    kind = system.assembly.dof_kind()[system.active]
    obs = out[kind[out] == 0]
    if not len(system.unbalance_dofs) or not len(obs):
        return 0.0
    G = system.gyroscopic()
    err = 0.0
    for w, F, Xf in _unbalance_1x(system, M, K, C):
        X = Xf[obs]
        A = (
            np.diag(w2r)
            + Phi.T @ (0.5 * (K - K.T) if Ka is None else Ka) @ Phi
            - w**2 * np.eye(len(w2r))
            + 1j * w * (Phi.T @ (C + G) @ Phi)
        )
        Xr = Phi[obs] @ la.solve(A, Phi.T @ F)
        err = max(err, float(np.abs(Xr - X).max() / np.abs(X).max()))
    return err
