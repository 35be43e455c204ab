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
from numpy.typing import NDArray

from ...errors import ModelError

__all__ = ["Contact", "LinearStatic", "solve_static", "rigid_modes"]


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

    K : (n, n) stiffness without the contacts (dense; may be unsymmetric: cross-coupled
    bearings); f : (n,) loads; M : (n, n) mass (identity when None) weighting the constraint;
    rigid : (n, m) rigid-body modes to hold, or None; contacts : the meshes; sides : their
    starting flanks (default all loaded flanks). Raises ``numpy.linalg.LinAlgError`` when the
    system is singular (e.g. a separated mesh leaves a shaft free) and :class:`ModelError`
    (``field``) when the contact state does not settle.
    """
    K = np.asarray(K, float)
    f = np.asarray(f, float)
    n = len(f)
    R = np.zeros((n, 0)) if rigid is None else np.asarray(rigid, float).reshape(n, -1)
    MR = R if M is None else np.asarray(M @ R)
    # scale the constraint rows to the stiffness so that the bordered matrix is well balanced
    scale = np.max(np.abs(K)) / max(np.max(np.abs(MR)), 1e-300) if MR.size else 1.0
    m = R.shape[1]
    side = [1] * len(contacts) if sides is None else [int(s) for s in sides]
    rhs = np.zeros(n + m)
    count = 0
    for _ in range(2 * len(contacts) + 2):
        A = np.zeros((n + m, n + m))
        A[:n, :n] = K
        A[:n, n:] = scale * MR
        A[n:, :n] = scale * MR.T
        rhs[:n] = f
        rhs[n:] = 0.0
        for c, s in zip(contacts, side, strict=True):
            if s == 1:  # F = k (w·q − e − b) along −w
                A[np.ix_(c.dofs, c.dofs)] += c.stiffness * np.outer(c.w, c.w)
                rhs[c.dofs] += c.stiffness * (c.offset + c.gap) * c.w
            elif s == -1:  # F = k (w_b·q + e − b) along −w_b
                A[np.ix_(c.dofs, c.dofs)] += c.stiffness * np.outer(c.w_back, c.w_back)
                rhs[c.dofs] += c.stiffness * (c.gap - c.offset) * c.w_back
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
