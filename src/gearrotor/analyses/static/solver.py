"""The one static solver of the package.

:func:`solve_static` solves ``K q + M R a = f`` with ``(M R)ᵀ q = 0``: the linear static
deflection q of a structure whose rigid-body modes R (columns) are held by the mass-weighted
constraint (the deflection is measured in a frame that follows the rigid motion), with ``a``
the rigid-body acceleration the unbalanced part of f gives (d'Alembert; zero when the loads
balance). Gear meshes enter as one-sided contacts: each mesh carries its stiffness on the flank
that is in contact (``w`` the loaded flank, ``w_back`` the other), with a one-side clearance b
and a static transmission error; the contact state is found by iteration (a flank stays in
contact while its approach is within round-off of the clearance, so an unloaded mesh keeps its
flank instead of flickering).

The transient's initial state (:func:`gearrotor.analyses.transient.static_state`) and the
static analysis (:func:`gearrotor.analyses.static.static`) both call it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from ...errors import ModelError

__all__ = ["Contact", "LinearStatic", "solve_static", "rigid_modes", "rigid_modes_in"]


@dataclass(frozen=True)
class Contact:
    """A one-sided contact (a gear mesh) on the DOFs ``dofs`` of q.

    The approach on the loaded flank is ``δ = w·q[dofs] − offset`` and on the back flank
    ``δ_b = w_back·q[dofs] + offset``; a flank carries ``stiffness·(δ − gap)`` (N) once
    ``δ > gap``. ``gap``: one-side clearance b (m); ``offset``: static transmission error (m).
    """

    dofs: NDArray
    w: NDArray
    w_back: NDArray
    stiffness: float
    gap: float = 0.0
    offset: float = 0.0


@dataclass(frozen=True)
class LinearStatic:
    """Solution of :func:`solve_static`: deflection ``q``, rigid-body accelerations
    ``acceleration`` (one per column of R), contact ``sides`` (1 loaded flank, −1 back flank,
    0 separated) and the number of LU ``factorizations``."""

    q: NDArray
    acceleration: NDArray
    sides: tuple[int, ...]
    factorizations: int

    def contact_force(self, contacts: Sequence[Contact]) -> NDArray:
        """Normal force (N, ≥ 0) of each contact on its active flank."""
        out = np.zeros(len(contacts))
        for k, (c, s) in enumerate(zip(contacts, self.sides, strict=True)):
            if s == 1:
                out[k] = c.stiffness * (c.w @ self.q[c.dofs] - c.offset - c.gap)
            elif s == -1:
                out[k] = c.stiffness * (c.w_back @ self.q[c.dofs] + c.offset - c.gap)
        return out


def solve_static(
    K: NDArray,
    f: NDArray,
    *,
    M: NDArray | None = None,
    rigid: NDArray | None = None,
    contacts: Sequence[Contact] = (),
    sides: Sequence[int] | None = None,
    field: str = "meshes",
) -> LinearStatic:
    """Static deflection under ``f`` (see the module docstring).

    K : (n, n) stiffness without the contacts, dense or scipy sparse (may be unsymmetric:
    cross-coupled bearings); f : (n,) loads; M : (n, n) mass (identity when None) weighting
    the constraint; rigid : (n, m) rigid-body modes to hold, or None; contacts : the meshes;
    sides : their starting flanks (default all loaded flanks). A sparse K is solved by sparse
    LU (the bordered matrix stays sparse but for its m constraint rows and columns), a dense
    one by dense LU; both are the same equations. Raises ``numpy.linalg.LinAlgError`` when the
    system is singular (e.g. a separated mesh leaves a shaft free) and :class:`ModelError`
    (``field``) when the contact state does not settle.
    """
    sparse = sp.issparse(K)
    K = sp.csr_array(K, dtype=float) if sparse else np.asarray(K, float)
    f = np.asarray(f, float)
    n = len(f)
    R = np.zeros((n, 0)) if rigid is None else np.asarray(rigid, float).reshape(n, -1)
    MR = R if M is None else np.asarray(M @ R)
    # scale the constraint rows to the stiffness so that the bordered matrix is well balanced
    kmax = float(abs(K).max()) if sparse else float(np.max(np.abs(K)))
    scale = kmax / max(np.max(np.abs(MR)), 1e-300) if MR.size else 1.0
    m = R.shape[1]
    side = [1] * len(contacts) if sides is None else [int(s) for s in sides]
    rhs = np.zeros(n + m)
    count = 0
    for _ in range(2 * len(contacts) + 2):
        rhs[:n] = f
        rhs[n:] = 0.0
        rows, cols, vals = [], [], []
        for c, s in zip(contacts, side, strict=True):
            if s == 0:
                continue
            w = c.w if s == 1 else c.w_back
            r, cc = np.meshgrid(c.dofs, c.dofs, indexing="ij")
            rows.append(r.ravel())
            cols.append(cc.ravel())
            vals.append((c.stiffness * np.outer(w, w)).ravel())
            if s == 1:  # F = k (w·q − e − b) along −w
                rhs[c.dofs] += c.stiffness * (c.offset + c.gap) * c.w
            else:  # F = k (w_b·q + e − b) along −w_b
                rhs[c.dofs] += c.stiffness * (c.gap - c.offset) * c.w_back
        if sparse:
            Kc = K
            if vals:
                Kc = K + sp.coo_array(
                    (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                    shape=(n, n),
                )
            sol = _bordered_sparse_solve(Kc, scale * MR, R, kmax, rhs)
        else:
            A = np.zeros((n + m, n + m))
            A[:n, :n] = K
            A[:n, n:] = scale * MR
            A[n:, :n] = scale * MR.T
            for r, cc, v in zip(rows, cols, vals, strict=True):
                np.add.at(A, (r, cc), v)
            sol = la.solve(A, rhs)
        count += 1
        q = sol[:n]
        new = []
        for c, s in zip(contacts, side, strict=True):
            qd = q[c.dofs]
            de = c.w @ qd - c.offset
            db = c.w_back @ qd + c.offset
            tol = 1e-9 * (np.abs(c.w) @ np.abs(qd) + c.gap + abs(c.offset)) + 1e-300
            if s == 1 and de > c.gap - tol:
                new.append(1)
            elif s == -1 and db > c.gap - tol:
                new.append(-1)
            else:
                new.append(1 if de > c.gap else (-1 if db > c.gap else 0))
        if new == side:
            return LinearStatic(q, scale * sol[n:], tuple(side), count)
        side = new
    raise ModelError("no static state: the mesh contact flank does not settle", field=field)


def _bordered_sparse_solve(K, B: NDArray, R: NDArray, kmax: float, rhs: NDArray) -> NDArray:
    """The bordered system ``[[K, B], [Bᵀ, 0]] [q; a] = rhs`` (K sparse n × n, singular along
    the rigid modes R; B = scale·M R, m columns) without a bordered factorisation, whose m
    dense rows and columns fill the sparse LU in (12 times the time at 24,000 DOF).

    K is grounded instead at m DOFs P where the rigid modes move independently (column-pivoted
    QR of Rᵀ): ``K_g = K + σ P Pᵀ`` (σ = max |K|) is nonsingular and as sparse as K; with
    ``y = Pᵀ q`` the system becomes ``K_g q = f − B a + σ P y``, and y and a follow from a
    2m × 2m capacitance system of ``K_g⁻¹ [f, P, B]`` (Woodbury). One step of iterative
    refinement on the bordered residual brings the solution to the accuracy of the dense LU
    (tested against it to round-off). A singular system raises ``numpy.linalg.LinAlgError``
    as ``scipy.linalg.solve`` does."""
    n, m = B.shape
    try:
        if m == 0:
            lu = spla.splu(sp.csc_array(K), permc_spec="MMD_AT_PLUS_A")
        else:
            piv = la.qr(R.T, pivoting=True, mode="economic")[2][:m]
            ground = sp.coo_array((np.full(m, kmax), (piv, piv)), shape=(n, n))
            lu = spla.splu(sp.csc_array(K + ground), permc_spec="MMD_AT_PLUS_A")
    except RuntimeError as exc:  # "Factor is exactly singular"
        raise np.linalg.LinAlgError(str(exc)) from None
    if m:
        P = np.zeros((n, m))
        P[piv, np.arange(m)] = 1.0
        XP = lu.solve(kmax * P)  # K_g⁻¹ σ P
        XB = lu.solve(B)
        cap = np.block([[XP[piv] - np.eye(m), -XB[piv]], [B.T @ XP, -B.T @ XB]])

    def solve(f: NDArray, c: NDArray) -> NDArray:
        xf = lu.solve(f)
        if m == 0:
            return xf
        ya = np.linalg.solve(cap, np.concatenate([-xf[piv], c - B.T @ xf]))
        return np.concatenate([xf + XP @ ya[:m] - XB @ ya[m:], ya[m:]])

    x = solve(rhs[:n], rhs[n:])
    for _ in range(1):  # iterative refinement on the bordered residual
        q, a = x[:n], x[n:]
        x = x + solve(rhs[:n] - K @ q - B @ a, rhs[n:] - B.T @ q)
    if not np.all(np.isfinite(x)):
        raise np.linalg.LinAlgError("singular matrix (non-finite solution)")
    return x


def rigid_modes_in(K, T: NDArray, *, rtol: float = 1e-9) -> NDArray:
    """Right null space of K (dense or sparse, n × n) within the span of the candidate motions
    ``T`` (n × p, p small): the columns R (each scaled to a largest entry of 1) with K R = 0.

    Exactly :func:`rigid_modes`'s first result when every null vector of K lies in span(T)
    (the rigid motions of the train's shafts and pedestals do), at O(n p²) instead of the
    O(n³) SVD of the whole matrix: with ``D = diag(K)^-½`` and Q an orthonormal basis of
    span(D⁻¹ T), the null vectors are ``D Q v`` for the right singular vectors v of the n × p
    matrix (D K D) Q whose singular values are at most ``rtol`` times the norm of D K D
    (bounded by sqrt(‖·‖₁ ‖·‖∞), which is within a factor √n of the 2-norm
    :func:`rigid_modes` uses; the null singular values are round-off, ~1e-16, far below
    either threshold)."""
    Kc = sp.csr_array(K, dtype=float)
    n = Kc.shape[0]
    d = np.abs(Kc.diagonal()).copy()
    d[d <= 0] = 1.0
    D = 1.0 / np.sqrt(d)
    Ks = sp.csr_array(sp.diags_array(D) @ Kc @ sp.diags_array(D))
    B = np.asarray(T, float).reshape(n, -1) / D[:, None]
    U, sb, _ = np.linalg.svd(B, full_matrices=False)
    Q = U[:, sb > 1e-12 * (sb[0] if len(sb) else 1.0)]
    if Q.shape[1] == 0:
        return np.zeros((n, 0))
    _, s, Vh = np.linalg.svd(Ks @ Q, full_matrices=False)
    absK = abs(Ks)
    norm = float(np.sqrt(absK.sum(axis=0).max() * absK.sum(axis=1).max()))
    null = s <= rtol * norm
    R = D[:, None] * (Q @ Vh[null].T)
    R /= np.maximum(np.max(np.abs(R), axis=0), 1e-300)
    return R


def rigid_modes(K: NDArray, *, rtol: float = 1e-9) -> tuple[NDArray, NDArray]:
    """Right and left null spaces of K, ``(R, L)`` with columns, found by the SVD of the
    diagonally scaled ``D K D`` (``D = diag(K)^-½``, so that translations in m and rotations in
    rad weigh alike). A DOF with zero diagonal is a null direction of its own."""
    K = np.asarray(K, float)
    d = np.abs(np.diag(K)).copy()
    free = d <= 0
    d[free] = 1.0
    D = 1.0 / np.sqrt(d)
    Ks = K * D[:, None] * D[None, :]
    U, s, Vh = la.svd(Ks, lapack_driver="gesvd")
    null = s <= rtol * (s[0] if len(s) else 1.0)
    R = D[:, None] * Vh[null].T
    L = D[:, None] * U[:, null]
    R /= np.maximum(np.max(np.abs(R), axis=0), 1e-300)
    return R, L
