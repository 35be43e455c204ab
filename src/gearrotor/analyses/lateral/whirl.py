"""Damped eigenvalues of a train whose bearings or seals depend on the whirl frequency (speed ×
whirl tables, issue 24): every mode sees the coefficients of its own eigenvalue, exactly.

A bearing given by a speed × whirl table (:class:`~gearrotor.elements.WhirlBearing`) presents
the journal impedance ``Z(Ω, s)``: on the whirl axis ``Z(iω) = K(ω) + iω C(ω)``, off it the
rational fit of each table row, ``D + sE + s²F + C_s (sI − A_s)⁻¹ B_s``
(:mod:`gearrotor.elements.rational_fit`). A mode λ of the train solves the nonlinear
eigenproblem

    [λ² M + λ (C + G) + K + Σ_b T_bᵀ Z_b(Ω, λ) T_b] φ = 0,

T_b the journal's motion relative to its housing. Writing each Z_b's pole part with its states
η_b, ``η̇_b = A_b η_b + B_b T_b q``, turns it into one linear eigenproblem of the rotor's
first-order form augmented by those states (z = [q, q̇, η]):

    q̇ = v,   M̃ v̇ = −K̃ q − C̃ v − Σ_b T_bᵀ C_b η_b,   η̇_b = A_b η_b + B_b T_b q,

K̃, C̃, M̃ the rotor's matrices with D_b, E_b, F_b in place of the bearings' synchronous
coefficients. Its eigenvalues are exactly the roots of the nonlinear problem for the fitted
Z — every one of them, at once, with one eigensolve per speed: no per-mode iteration that
could stall or miss a mode that only exists with the frequency dependence.

Why this, and not a per-mode iteration ``λ ← eig(K(Im λ), C(Im λ))`` (the classical use of
frequency-dependent coefficients): the table holds Z only at s = iω, and reading it at ω = Im λ
for a damped mode λ = σ + iω misses ``Z(σ + iω) − Z(iω) ≈ σ Z'(iω)``, an error first order in
the damping ratio. ``benchmarks/whirl.py`` on the tilting-pad test rotor: the iteration from
the synchronous solve takes 76 eigensolves for its 7 damped rotor modes, errs by up to 0.059 ζ
on the lightly damped ones and ends on other modes for the four with ζ ≈ 0.6 (the synchronous
model has no mode like them), where the states take one eigensolve and agree with the pad
model to 3e-13. The rational fit continues Z off the axis; for a bearing whose impedance is
rational (tilting pads, a pedestal) it is exact, and the table model then reproduces the model
with those DOFs to round-off (``tests/whirl``, ``tests/pads/test_pad_whirl_table.py``).

The states are scaled so that, near the rotor's frequencies, their amplitude is that of the
journal motion (``|p| / |λ − p|`` times it for a pole p); a mode whose largest state amplitude
``a`` has ``a² / (a² + d²) ≥ ½``, d the rotor's largest physical displacement (the mode-shape
normalisation). As that amplitude only approximates a displacement (on the pedestal test
model it reads about twice the pedestal's), a mode is bearing-internal (type ``P``, as a
tilting-pad bearing's pad modes, not judged as a lateral mode by Level I/II) only from
``a² / (a² + d²) ≥ 0.9`` (``modal.STATE_SHARE_P``): the rotor barely moves.
``ModalResult.pad_share`` holds the share.

Work: one eigensolve of the augmented system (2n + m states, m = Σ 2 × the poles of the table
rows at the speed); the fits are made once per table row when the model is assembled.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numpy.typing import NDArray

from ...assembly import Assembly, _Triplets
from ...errors import ModelError, SolverError
from ...threads import limit

__all__ = ["frequency_dependent", "WhirlSystem", "whirl_system", "solve", "residuals"]


def frequency_dependent(asm: Assembly) -> bool:
    """True when a bearing or seal of ``asm`` depends on the whirl frequency."""
    return any(getattr(b.element, "whirl_dependent", False) for b in asm.bearings)


@dataclass(frozen=True)
class WhirlSystem:
    """The rotor at one speed with its whirl-dependent bearings in state form.

    M, C, K : (n, n) sparse, C including the gyroscopic matrix; the whirl-dependent bearings
    enter with their fits' D (K), E (C) and F (M) instead of their synchronous coefficients.
    A (m, m), B (m, n), Cs (n, m): the states' dynamics, their input from the journals and
    their force on the rotor (``−Cs η``). elements : per whirl-dependent bearing, its name,
    states, table whirl range and largest fit misfit.
    """

    M: sp.csr_array
    C: sp.csr_array
    K: sp.csr_array
    A: NDArray
    B: sp.csr_array
    Cs: sp.csr_array
    elements: tuple[dict, ...]

    @property
    def n_states(self) -> int:
        return self.A.shape[0]


def whirl_system(asm: Assembly, speed: float) -> WhirlSystem:
    """The augmented system of ``asm`` at reference-shaft speed ``speed`` (rad/s)."""
    M, C, G, K = asm.matrices(speed)
    n = asm.n_dof
    speeds = asm.shaft_speeds(speed)
    Kt, Ct, Mt = _Triplets(), _Triplets(), _Triplets()
    A_parts, B_parts, C_parts, info = [], [], [], []
    for b in asm.bearings:
        el = b.element
        if not getattr(el, "whirl_dependent", False):
            continue
        w = speeds[b.shaft]
        d, T = b.local()
        r = el.realization(w)
        # the assembly scattered the synchronous coefficients: replace them by the fit's
        Kt.add(d, T.T @ (r.D - el.K(w)) @ T)
        Ct.add(d, T.T @ (r.E - el.C(w)) @ T)
        if np.any(r.F):
            Mt.add(d, T.T @ r.F @ T)
        Tg = sp.csr_array((T.ravel(), (np.repeat([0, 1], len(d)), np.tile(d, 2))), shape=(2, n))
        if r.n_states:
            A_parts.append(r.A)
            B_parts.append(sp.csr_array(r.B) @ Tg)
            C_parts.append(Tg.T @ sp.csr_array(r.C))
        lo, hi = el.whirl_range
        info.append(
            {
                "name": b.name,
                "states": int(r.n_states),
                "whirl_range_rpm": [lo * 30 / np.pi, hi * 30 / np.pi],
                "max_misfit": max(row.fit.misfit for row in el.rows),
            }
        )
    m = sum(a.shape[0] for a in A_parts)
    A = la.block_diag(*A_parts) if A_parts else np.zeros((0, 0))
    B = sp.vstack(B_parts, format="csr") if B_parts else sp.csr_array((0, n))
    Cs = sp.hstack(C_parts, format="csr") if C_parts else sp.csr_array((n, 0))
    return WhirlSystem(
        M=sp.csr_array(M + Mt.csr(n)),
        C=sp.csr_array(C + G + Ct.csr(n)),
        K=sp.csr_array(K + Kt.csr(n)),
        A=np.asarray(A, float).reshape(m, m),
        B=sp.csr_array(B),
        Cs=sp.csr_array(Cs),
        elements=tuple(info),
    )


def _mass_solver(M: NDArray, asm: Assembly):
    """A function X ↦ M⁻¹X: Cholesky for a symmetric M, LU when the fits' added mass F is not
    symmetric; a ModelError naming the massless DOFs when M is singular."""
    sym = np.allclose(M, M.T, rtol=0, atol=1e-14 * np.abs(M).max())
    try:
        if sym:
            cho = la.cho_factor(M, lower=True)
            return lambda X: la.cho_solve(cho, X)
        lu = la.lu_factor(M, check_finite=True)
        if np.any(np.abs(np.diag(lu[0])) <= 1e-14 * np.abs(M).max()):
            raise la.LinAlgError
        return lambda X: la.lu_solve(lu, X)
    except (la.LinAlgError, ValueError):
        raise _mass_error(asm) from None


def solve(
    asm: Assembly,
    speed: float,
    *,
    max_frequency: float | None = None,
    method: str = "dense",
    n_modes: int | None = None,
) -> tuple[NDArray, NDArray, sp.csr_array, NDArray, dict]:
    """Eigenvalues of the augmented system (module docstring): ``method="dense"`` every one
    (QR on the (2n + m)-state matrix); ``"sparse"`` those with |λ| ≤ ``max_frequency`` (else the
    ``n_modes`` nearest 0) by shift-invert Arnoldi on the augmented pencil, each pair refined
    by inverse iteration to a relative residual of the nonlinear problem ≤ ``REFINE_TOL``.

    Returns (λ, the rotor part of the eigenvectors (n, k), the stiffness K̃ for the modes'
    strain energy, each eigenvector's largest state amplitude (for the state share, module
    docstring), and the work: ``{"method", "eigensolves", "states", "elements",
    "modes_beyond_whirl_tables"}``; sparse also ``"arnoldi_runs"``, ``"factorizations"``)."""
    sysm = whirl_system(asm, speed)
    m = sysm.n_states
    extra = {}
    if method == "sparse":
        lam, X, eta, extra = _solve_sparse(sysm, asm, max_frequency, n_modes)
    else:
        lam, X, eta = _solve_dense(sysm, asm)
    if not np.all(np.isfinite(lam)):
        raise SolverError("the eigensolver returned non-finite eigenvalues")
    amplitude = np.max(np.abs(eta), axis=0) if m else np.zeros(len(lam))
    hi = max((e["whirl_range_rpm"][1] for e in sysm.elements), default=0.0) * np.pi / 30
    keep = lam.imag > 0
    if max_frequency is not None:
        keep &= lam.imag <= max_frequency
    work = {
        "method": f"{method} (augmented states)",
        "eigensolves": 1,
        "states": int(m),
        "elements": [dict(e) for e in sysm.elements],
        "modes_beyond_whirl_tables": int(np.sum(keep & (lam.imag > hi * (1 + 1e-9)))),
        **extra,
    }
    return lam, X, sysm.K, amplitude, work


def _solve_dense(sysm: WhirlSystem, asm: Assembly):
    n, m = asm.n_dof, sysm.n_states
    solve_m = _mass_solver(sysm.M.toarray(), asm)
    S = np.zeros((2 * n + m, 2 * n + m))
    S[:n, n : 2 * n] = np.eye(n)
    S[n : 2 * n, :n] = -solve_m(sysm.K.toarray())
    S[n : 2 * n, n : 2 * n] = -solve_m(sysm.C.toarray())
    if m:
        S[n : 2 * n, 2 * n :] = -solve_m(sysm.Cs.toarray())
        S[2 * n :, :n] = sysm.B.toarray()
        S[2 * n :, 2 * n :] = sysm.A
    if not np.isfinite(S).all():
        raise SolverError(
            "the state matrix of the model with its whirl tables overflows (non-finite "
            "entries): a coefficient is far beyond the physical range"
        )
    with limit(2 * n + m, "eig"):
        lam, V = la.eig(S, overwrite_a=True, check_finite=False)
    return lam, V[:n], V[2 * n :]


#: relative residual of the nonlinear problem to which sparse eigenpairs are refined (as
#: ``modal.REFINE_TOL``: what the dense solve's pairs reach)
REFINE_TOL = 1e-10
_REFINE_STEPS = 4


def _pencil(sysm: WhirlSystem, scale: float) -> tuple[sp.csc_array, sp.csc_array]:
    """(A, B) of the augmented first-order form with z = [q, q̇/scale, η] (the two rotor halves
    of a mode then have the same size, as in ``modal``'s sparse solve)."""
    n, m = sysm.M.shape[0], sysm.n_states
    I = sp.identity(n, format="csc")
    A = sp.block_array(
        [
            [None, scale * I, None],
            [-sysm.K / scale, -sysm.C, -sysm.Cs / scale if m else None],
            [sysm.B if m else None, None, sp.csc_array(sysm.A) if m else None],
        ],
        format="csc",
    )
    Bm = sp.block_array(
        [[I, None, None], [None, sysm.M, None], [None, None, sp.identity(m) if m else None]],
        format="csc",
    )
    if not m:  # the block rows and columns of η are empty
        A, Bm = A[: 2 * n, : 2 * n], Bm[: 2 * n, : 2 * n]
    return sp.csc_array(A), sp.csc_array(Bm)


def _solve_sparse(sysm: WhirlSystem, asm: Assembly, max_frequency, n_modes):
    """Shift-invert Arnoldi on the augmented pencil about a small negative real shift, asking
    for more eigenvalues (×2) until every one with |λ| ≤ max_frequency is enclosed; then each
    pair refined by inverse iteration with the Rayleigh quotient as shift (one sparse LU per
    step)."""
    import scipy.sparse.linalg as spla

    n = asm.n_dof
    scale = max_frequency if max_frequency else 1.0
    A, Bm = _pencil(sysm, scale)
    N = A.shape[0]
    sigma = -1e-3 * scale
    k = min(max(n_modes or 20, 10), N - 2)
    v0 = np.random.default_rng(20261125).standard_normal(N)  # reproducible (modal does too)
    runs = 0
    while True:
        runs += 1
        try:
            lam, V = spla.eigs(A, k=k, M=Bm, sigma=sigma, which="LM", v0=v0)
        except spla.ArpackNoConvergence as exc:
            raise SolverError(f"sparse eigensolver did not converge for {k} modes: {exc}") from None
        except RuntimeError:
            raise _mass_error(asm) from None
        if max_frequency is None or k >= N - 2 or np.max(np.abs(lam - sigma)) > max_frequency:
            break
        k = min(2 * k, N - 2)
    if max_frequency is not None:
        inside = np.abs(lam) <= max_frequency
        lam, V = lam[inside], V[:, inside]
    lam, V, factorizations = _refine(A, Bm, sysm, lam, V, scale)
    return lam, V[:n], V[2 * n :], {"arnoldi_runs": runs, "factorizations": factorizations}


def _refine(A, Bm, sysm, lam, V, scale):
    """Inverse iteration per pair whose nonlinear residual exceeds REFINE_TOL: y = (A −
    λB)⁻¹ B z, λ ← the Rayleigh quotient zᴴ(Bᴴ A z)/zᴴ(Bᴴ B z) of the new vector, up to
    ``_REFINE_STEPS`` steps; a step is kept only if it lowers the residual."""
    import scipy.sparse.linalg as spla

    n = sysm.M.shape[0]
    lam, V = np.array(lam, complex), np.array(V, complex)
    count = 0

    def resid(a, z):
        x, eta = z[:n], z[2 * n :]
        r = a * a * (sysm.M @ x) + a * (sysm.C @ x) + sysm.K @ x
        if sysm.n_states:
            r = r + sysm.Cs @ eta
            # η of the pair: (a − A_s) η = B x exactly for an eigenpair
            r2 = a * eta - sysm.A @ eta - sysm.B @ x
        else:
            r2 = np.zeros(0)
        den = (
            abs(a) ** 2 * np.linalg.norm(sysm.M @ x)
            + abs(a) * np.linalg.norm(sysm.C @ x)
            + np.linalg.norm(sysm.K @ x)
        )
        scale_eta = np.linalg.norm(sysm.B @ x) + abs(a) * np.linalg.norm(eta)
        return max(
            np.linalg.norm(r) / max(den, 1e-300),
            np.linalg.norm(r2) / max(scale_eta, 1e-300) if len(r2) else 0.0,
        )

    for j in range(len(lam)):
        res = resid(lam[j], V[:, j])
        for _ in range(_REFINE_STEPS):
            if res <= REFINE_TOL:
                break
            try:
                lu = spla.splu(sp.csc_array(A - lam[j] * Bm))
            except RuntimeError:
                break
            count += 1
            y = lu.solve(Bm @ V[:, j])
            if not np.all(np.isfinite(y)):
                break
            y /= np.linalg.norm(y)
            By = Bm @ y
            mu = np.vdot(By, A @ y) / np.vdot(By, By)
            new = resid(mu, y)
            if not new < res:
                break
            lam[j], V[:, j], res = mu, y, new
    return lam, V, count


def _mass_error(asm: Assembly) -> ModelError:
    diag = asm.M.diagonal()
    bad = [asm.dof_labels[i] for i in np.flatnonzero(diag <= 1e-12 * diag.max())][:10]
    return ModelError(
        "singular model: the mass matrix (with the whirl tables' added mass) is not "
        "positive definite",
        field="shafts / disks / supports / bearing tables",
        value=bad or "(no zero diagonal; check densities and the tables' s² terms)",
        expected="mass or inertia on every degree of freedom",
    )


def residuals(asm: Assembly, speed: float, lam: NDArray, phi: NDArray) -> NDArray:
    """Relative residual of each eigenpair (λ_j, φ_j = phi[j]) of the nonlinear problem with
    the fitted impedances: ‖T(λ)φ‖ / (|λ|²‖M̃φ‖ + |λ|‖C̃φ‖ + ‖K̃φ‖ + ‖Z_s(λ)φ‖),
    ``T(λ) = λ²M̃ + λC̃ + K̃ + Z_s(λ)``, ``Z_s(λ) = Cs (λI − A)⁻¹ B``."""
    if not len(lam):
        return np.zeros(0)
    sysm = whirl_system(asm, speed)
    out = np.empty(len(lam))
    for j, (a, x) in enumerate(zip(lam, phi, strict=True)):
        mx, cx, kx = sysm.M @ x, sysm.C @ x, sysm.K @ x
        zx = np.zeros_like(kx, dtype=complex)
        if sysm.n_states:
            zx = sysm.Cs @ la.solve(a * np.eye(sysm.n_states) - sysm.A, sysm.B @ x)
        r = a * a * mx + a * cx + kx + zx
        den = (
            abs(a) ** 2 * np.linalg.norm(mx)
            + abs(a) * np.linalg.norm(cx)
            + np.linalg.norm(kx)
            + np.linalg.norm(zx)
        )
        out[j] = np.linalg.norm(r) / max(den, 1e-300)
    return out
