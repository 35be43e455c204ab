"""Step-size limits of the explicit RK4 integrators: RK4's stability region, the largest stable
step of a linearised model, and the error a step outside it raises."""

from __future__ import annotations

import numpy as np
import scipy.linalg as la
from numpy.typing import NDArray

from ...errors import ModelError, SolverError
from ...threads import limit
from .equations import TransientSystem

__all__ = ["rk4_max_step"]


def _rk4_amplification(z: NDArray) -> NDArray:
    """|R(z)| of classical RK4, R(z) = 1 + z + z²/2 + z³/6 + z⁴/24 (z = λ Δt)."""
    return np.abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))))


def _rk4_step_limit(M: NDArray, K: NDArray, C: NDArray) -> tuple[float, complex]:
    """Largest RK4 step (s) for the linear system M q̈ + C q̇ + K q = 0, and the eigenvalue λ
    (1/s) of its first-order form that sets it.

    Every eigenvalue must satisfy |R(λ Δt)| ≤ 1. In the closed left half-plane the region is
    star-shaped about 0 with radius 2.62 (at 122°) to 2.96 (checked numerically): 2√2 on the
    imaginary axis, 2.785 on the negative real axis; the radius along each λ is found by
    bisection. A growing mode (Re λ > 0, a physical instability) is checked as its decaying
    mirror image −|Re λ| + i Im λ. Eigenvalues of [[0, I], [−M⁻¹K, −M⁻¹C]] through the
    Cholesky factor of M (L⁻¹ K L⁻ᵀ, the same spectrum)."""
    n = M.shape[0]
    try:
        L = la.cholesky(M, lower=True)
    except la.LinAlgError:
        raise ModelError(
            "the mass matrix is not positive definite on some DOFs (a node without mass or "
            "inertia?)"
        ) from None

    def scaled(A):
        return la.solve_triangular(L, la.solve_triangular(L, A, lower=True).T, lower=True).T

    A = np.block([[np.zeros((n, n)), np.eye(n)], [-scaled(K), -scaled(C)]])
    with limit(2 * n, "eig"):
        lam = la.eigvals(A)
    lam = -np.abs(lam.real) + 1j * np.abs(lam.imag)
    lam = lam[np.abs(lam) > 0.0]
    if not len(lam):
        return np.inf, 0j
    d = lam / np.abs(lam)
    lo, hi = np.zeros(len(d)), np.full(len(d), 3.0)
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        out = _rk4_amplification(mid * d) > 1.0
        hi = np.where(out, mid, hi)
        lo = np.where(out, lo, mid)
    h = lo / np.abs(lam)
    i = int(np.argmin(h))
    return float(h[i]), complex(lam[i])


def _linearised(system: TransientSystem) -> tuple[NDArray, NDArray, NDArray]:
    """Dense (M, K, C) of the model linearised at the nominal speeds, as the kernels apply it:
    meshes at Kg with their contact damping, bearings at the nominal speeds, and the
    gyroscopic matrices (in C)."""
    M, K, C = system.linear_matrices()
    for law, d in zip(system.meshes, system.mesh_dofs, strict=True):
        ok = d >= 0
        C[np.ix_(d[ok], d[ok])] += law.damping * np.outer(law.w[ok], law.w[ok])
    return M, K, C + system.gyroscopic()


def rk4_max_step(system: TransientSystem) -> float:
    """Largest stable step (s) of :class:`RK4` on the full model: every eigenvalue of the
    first-order system linearised at the nominal speeds (stiffness, bearing and mesh damping,
    gyroscopics) inside RK4's stability region (:func:`_rk4_step_limit`). Heavily damped
    bearings give real eigenvalues −c/m that can set a smaller limit than the highest
    natural frequency."""
    return _rk4_step_limit(*_linearised(system))[0]


def _unstable_step(what: str, dt: float, limit: float, lam: complex, fix: str) -> SolverError:
    zeta = -lam.real / abs(lam)
    return SolverError(
        f"{what} step dt = {dt:.4g} s is outside RK4's stability region for the eigenvalue "
        f"λ = {lam.real:.4g} ± {abs(lam.imag):.4g}i 1/s of the model linearised at the nominal "
        f"speeds ({abs(lam.imag) / 2 / np.pi:.5g} Hz, damping ratio {zeta:.3g}; |λ|·dt = "
        f"{abs(lam) * dt:.3f}); use dt ≤ {0.99 * limit:.4g} s{fix}"
    )


def _etd_amplification(om: NDArray, C: NDArray, Bk: NDArray, Bc: NDArray) -> NDArray:
    """One-step matrix (2m, 2m) of the exponential RK4 step of :func:`.kernels.etd_modal` on
    the linear system ζ̈ + diag(ω²) ζ = Bk ζ + Bc ζ̇ (``C`` its weights,
    :func:`.kernels.etd_coefficients`): the kernel's stages with N(x) = [[0, 0], [Bk, Bc]] x."""
    m = len(om)
    Z = np.zeros((m, m))

    def block(a, b):  # F(L) = α I + β L on (ζ, v)
        return np.block([[np.diag(a), np.diag(b)], [np.diag(-(om**2) * b), np.diag(a)]])

    def forcing(a, b):  # F(L) applied to (0, g): (β g, α g)
        return np.block([[Z, np.diag(b)], [Z, np.diag(a)]])

    Eh, E = block(C[0], C[1]), block(C[4], C[5])
    Ph = forcing(C[2], C[3])
    F1, F2, F3 = forcing(C[6], C[7]), forcing(C[8], C[9]), forcing(C[10], C[11])
    N = np.block([[Z, Z], [Bk, Bc]])
    A = Eh + Ph @ N
    B = Eh + Ph @ N @ A
    Cm = Eh @ A + Ph @ (2.0 * N @ B - N)
    return E + F1 @ N + 2.0 * F2 @ N @ (A + B) + F3 @ N @ Cm


def _etd_unstable(om: NDArray, C: NDArray, Bk: NDArray, Bc: NDArray, dt: float) -> float:
    """How far the exponential RK4 step leaves the linear system's own growth: the spectral
    radius of its one-step matrix over that of the exact flow (at least 1); > 1 + 1e-6 means the
    step amplifies a mode the system does not (unstable step)."""
    rho = np.max(np.abs(la.eigvals(_etd_amplification(om, C, Bk, Bc))))
    m = len(om)
    A = np.block([[np.zeros((m, m)), np.eye(m)], [-np.diag(om**2) + Bk, Bc]])
    exact = np.exp(dt * np.max(la.eigvals(A).real))
    return float(rho / max(1.0, exact))
