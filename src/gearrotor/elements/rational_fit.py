"""A rational function of the Laplace variable fitted to a journal impedance sampled over whirl
frequency (issue 24): the frequency-dependent bearing or seal of a speed × whirl table, in a
form the eigenproblem can carry exactly.

A bearing's eight coefficients at whirl frequency ω give its impedance on the imaginary axis,
``Z(iω) = K(ω) + iω C(ω)`` (2×2, the force on the journal is ``−Z u`` for ``u ∝ e^{iωt}``). A
damped mode λ = σ + iω needs Z off that axis, at s = λ; the table alone does not define it. The
fit here does:

    Z(s) ≈ D + s E + s² F + Σ_k R_k / (s − p_k),

D, E, F real 2×2, the poles p_k real or in complex-conjugate pairs with Re p_k < 0 and real
(pairs: conjugate) residues R_k, so that Z(s̄) = conj Z(s) as for every real system. Its state
realization ``Z(s) = D + sE + s²F + C_s (sI − A_s)⁻¹ B_s`` adds first-order states to the
rotor's equations, and the eigenvalues of the augmented system are exactly the roots of
``det(P(λ) + Z(λ)) = 0`` for the fitted Z (``gearrotor.analyses.lateral.whirl``).

Method: vector fitting (Gustavsen & Semlyen 1999, "Rational approximation of frequency domain
responses by vector fitting", IEEE Trans. Power Delivery 14(3):1052–1061) with the relaxed
non-triviality constraint (Gustavsen 2006, IEEE Trans. Power Delivery 21(3):1587–1592), the
four entries sharing their poles, their residues eliminated by a QR factorisation per entry
(Deschrijver, Mrozowski, Dhaene & De Zutter 2008, IEEE Microwave Wireless Compon. Lett.
18(6):383–385), unstable poles reflected into the left half-plane. The frequency is scaled by
the largest tabulated whirl frequency and the samples weighted by 1/‖Z(iω_j)‖, so the misfit is
relative at every frequency. The order is the lowest (number of poles N, then whether an s²
term is needed) whose misfit ``max_j ‖Z_fit(iω_j) − Z_j‖_F / ‖Z_j‖_F`` is within the tolerance;
at most N + 3 ≤ n_w unknowns per entry (half of the 2 n_w real equations), so a coarse table is
not over-fitted. An s² term is an added mass (Childs' liquid seals: K − Mω²); a fit whose added
mass has a negative symmetric part is not taken (it would continue a stiffening beyond the
table as a spurious growing root): poles take that stiffening. Nor is a fit that dissipates
less than nothing where the table does not: when the table's damping ``C(ω)`` has a positive
semidefinite symmetric part at every sample, a fit's must too at the samples and at 61
frequencies from 10⁻³ to 10³ times the highest one (else a coarse table's fit may trade a far
pole against a negative high-frequency damping, which shows as spurious growing roots).

An impedance that is exactly rational is recovered to round-off once the table has a few more
whirl frequencies than unknowns: a tilting-pad bearing (the pads' equations, Lund's
condensation), a bearing on a pedestal, a spring–damper in series (``tests/whirl``).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
from numpy.typing import NDArray

__all__ = ["RationalImpedance", "fit_impedance", "fit_row", "impedance_samples"]

#: relative pole movement between two vector-fitting iterations at which the poles are final
_POLE_TOL = 1e-11
_ITERATIONS = 40
#: poles beyond this many times the largest whirl frequency act as constants over the table:
#: dropped (the polynomial part takes their share), else they would add eigenvalues at 1e7 ω
_FAR = 1e6
MAX_POLES = 12


@dataclass(frozen=True)
class RationalImpedance:
    """``Z(s) = D + sE + s²F + C (sI − A)⁻¹ B`` (2×2 complex for complex s), SI units.

    D (N/m), E (N·s/m), F (kg): (2, 2) real; A (m, m) real with eigenvalues ``poles`` (1/s,
    Re < 0), B (m, 2), C (2, m) real; the states are scaled so that for |s − p| ~ |p| their
    amplitude is that of the journal motion (B ~ |p|, C ~ N/m). ``misfit``: the largest
    relative misfit at the samples; ``whirl``: (lowest, highest) sampled whirl frequency, rad/s.
    """

    D: NDArray
    E: NDArray
    F: NDArray
    A: NDArray
    B: NDArray
    C: NDArray
    poles: NDArray
    misfit: float
    whirl: tuple[float, float]

    @property
    def n_states(self) -> int:
        return self.A.shape[0]

    @property
    def n_poles(self) -> int:
        return len(self.poles)

    def at(self, s: complex) -> NDArray:
        """Z(s), (2, 2) complex."""
        z = self.D + s * self.E + s * s * self.F
        if self.n_states:
            z = z + self.C @ np.linalg.solve(s * np.eye(self.n_states) - self.A, self.B)
        return np.asarray(z, complex)

    def coefficients(self, whirl: float) -> NDArray:
        """The eight coefficients at whirl frequency ``whirl`` (rad/s, > 0): K = Re Z(iω),
        C = Im Z(iω)/ω."""
        z = self.at(1j * whirl)
        return np.concatenate([z.real.ravel(), (z.imag / whirl).ravel()])


def impedance_samples(whirl: NDArray, values: NDArray) -> NDArray:
    """Z(iω_j) = K_j + iω_j C_j, (n_w, 4) complex (xx, xy, yx, yy), from ``values`` (n_w, 8)
    kxx kxy kyx kyy cxx cxy cyx cyy."""
    v = np.asarray(values, float)
    return v[:, :4] + 1j * np.asarray(whirl, float)[:, None] * v[:, 4:]


def _basis(s: NDArray, poles: list[complex]) -> NDArray:
    """(n, N) real-coefficient partial fractions: 1/(s − p) for a real pole; for a pair
    (listed once, Im p > 0) 1/(s − p) + 1/(s − p̄) and i/(s − p) − i/(s − p̄)."""
    cols = []
    for p in poles:
        if p.imag == 0.0:
            cols.append(1.0 / (s - p.real))
        else:
            a, b = 1.0 / (s - p), 1.0 / (s - np.conj(p))
            cols += [a + b, 1j * a - 1j * b]
    return np.array(cols).T if cols else np.zeros((len(s), 0), complex)


def _blocks(poles: list[complex]) -> tuple[NDArray, NDArray]:
    """(A, b) with ``c (sI − A)⁻¹ b`` = the basis of :func:`_basis` weighted by c."""
    n = sum(1 if p.imag == 0.0 else 2 for p in poles)
    A, b = np.zeros((n, n)), np.zeros(n)
    i = 0
    for p in poles:
        if p.imag == 0.0:
            A[i, i], b[i] = p.real, 1.0
            i += 1
        else:
            A[i : i + 2, i : i + 2] = [[p.real, p.imag], [-p.imag, p.real]]
            b[i] = 2.0
            i += 2
    return A, b


def _canonical(z: NDArray) -> list[complex]:
    """Eigenvalues as poles: real ones, then one representative (Im > 0) per conjugate pair."""
    z = np.asarray(z, complex)
    tol = 1e-10 * np.maximum(np.abs(z), 1e-300)
    real = [complex(v.real, 0.0) for v in z[np.abs(z.imag) <= tol]]
    pairs = [complex(v) for v in z[z.imag > tol]]
    return sorted(real, key=lambda p: p.real) + sorted(pairs, key=lambda p: p.imag)


def _realify(a: NDArray) -> NDArray:
    return np.vstack([a.real, a.imag])


def _lstsq(A: NDArray, B: NDArray) -> NDArray:
    """Least squares with the columns scaled to unit norm."""
    sc = np.linalg.norm(A, axis=0)
    sc[sc == 0] = 1.0
    return (np.linalg.lstsq(A / sc, B, rcond=None)[0].T / sc).T


def _polynomial(s: NDArray, npoly: int) -> NDArray:
    return np.column_stack([s**k for k in range(npoly)]) if npoly else np.zeros((len(s), 0))


def _relocate(s, F, w, poles, npoly):
    """Vector-fitting pole relocation to convergence (:data:`_POLE_TOL`)."""
    n = len(s)
    for _ in range(_ITERATIONS):
        Phi = _basis(s, poles)
        P = _polynomial(s, npoly)
        ones = np.ones((n, 1))
        k1 = Phi.shape[1] + npoly
        rows = []
        for j in range(F.shape[1]):
            A1 = np.hstack([Phi, P]) * w[:, None]
            A2 = -(F[:, j : j + 1] * np.hstack([Phi, ones])) * w[:, None]
            A = _realify(np.hstack([A1, A2]))
            sc = np.linalg.norm(A, axis=0)
            sc[sc == 0] = 1.0
            R = la.qr(A / sc, mode="r")[0]
            rows.append(R[k1 : A.shape[1], k1:] * sc[k1:])
        rows = np.vstack(rows)
        # relaxed non-triviality: Σ_j Re σ(s_j) = n, weighted like the other rows
        relax = np.hstack([Phi, ones]).real.sum(axis=0)
        scale = np.linalg.norm(rows) / np.sqrt(max(rows.shape[0], 1))
        A = np.vstack([rows, scale * relax / n])
        b = np.zeros(A.shape[0])
        b[-1] = scale
        x = _lstsq(A, b)
        c, d = x[:-1], x[-1]
        if abs(d) < 1e-8:
            d = 1e-8 if d >= 0 else -1e-8
        Ap, bp = _blocks(poles)
        z = la.eigvals(Ap - np.outer(bp, c) / d)
        z = np.where(z.real > 0, -z.real + 1j * z.imag, z)  # reflect unstable poles
        new = _canonical(z)
        moved = max(
            (min(abs(q - p) for q in poles) / max(abs(p), 1e-300) for p in new), default=0.0
        )
        poles = new
        if moved < _POLE_TOL:
            break
    return poles


def _fit(s, F, w, N, npoly):
    """(poles, coefficients (N_basis + npoly, 4), misfit) of one order."""
    if N:
        k = N // 2
        poles = [complex(-0.01 * (i + 1) / (k + 1), (i + 1) / (k + 1)) for i in range(k)]
        if N % 2:
            poles.append(complex(-1.0, 0.0))
        start = _canonical(np.array(poles + [np.conj(p) for p in poles[:k]]))
        poles = _relocate(s, F, w, start, npoly)
        # poles at ~0 (an integrator) or far beyond the table: not kept
        poles = [p for p in poles if 1e-9 < abs(p) < _FAR and p.real < 0]
    else:
        poles = []
    A = np.hstack([_basis(s, poles), _polynomial(s, npoly)]) * w[:, None]
    X = _lstsq(_realify(A), _realify(F * w[:, None]))
    fitted = np.hstack([_basis(s, poles), _polynomial(s, npoly)]) @ X
    misfit = float(np.max(np.linalg.norm(fitted - F, axis=1) * w))
    return poles, X, misfit


def fit_impedance(
    whirl: NDArray, values: NDArray, *, tolerance: float, max_poles: int = MAX_POLES
) -> tuple[RationalImpedance, float]:
    """Fit the impedance of one speed's row of a speed × whirl table (module docstring).

    whirl : (n_w,) rad/s, ≥ 0, increasing; values : (n_w, 8) kxx … cyy at those whirl
    frequencies. Returns (the fit of the lowest order with misfit ≤ ``tolerance``, or of the
    smallest misfit when none reaches it; that misfit): the caller decides whether a misfit
    above the tolerance is an error.
    """
    whirl = np.asarray(whirl, float)
    Zs = impedance_samples(whirl, values)
    top = float(whirl.max()) if whirl.max() > 0 else 1.0
    s = 1j * whirl / top
    norms = np.linalg.norm(Zs, axis=1)
    w = 1.0 / np.where(norms > 0, norms, 1.0)
    n_w = len(whirl)
    # the table's damping: when it dissipates at every sample (C's symmetric part ≥ 0), a fit
    # must too, at every frequency (module docstring)
    c_data = _damping_min(Zs[s.imag > 0], s.imag[s.imag > 0])
    dissipative = c_data is not None and c_data[0] >= -1e-12 * c_data[1]
    check = np.concatenate([s.imag[s.imag > 0], np.logspace(-3, 3, 61)])
    best = None
    for N in range(0, max_poles + 1):
        for npoly in (2, 3):
            if N + npoly > max(n_w, 2) or (npoly == 3 and n_w < 3):
                continue
            poles, X, misfit = _fit(s, Zs, w, N, npoly)
            if npoly == 3 and _negative_mass(X[-1], norms.max()):
                continue
            if dissipative:
                fitted = np.hstack([_basis(1j * check, poles), _polynomial(1j * check, npoly)])
                c_fit = _damping_min(fitted @ X, check)
                if c_fit[0] < -1e-6 * c_data[1]:
                    continue
            if best is None or misfit < best[3] * (1 - 1e-12):
                best = (poles, X, npoly, misfit)
            if misfit <= tolerance:
                return _realization(poles, X, npoly, top, misfit, whirl), misfit
    poles, X, npoly, misfit = best
    return _realization(poles, X, npoly, top, misfit, whirl), misfit


def _damping_min(Z: NDArray, w: NDArray) -> tuple[float, float] | None:
    """(smallest eigenvalue of the damping's symmetric part, largest damping norm) over the
    impedances Z (n, 4) at the (normalised, > 0) frequencies w; None without any."""
    if not len(w):
        return None
    C = (Z.imag / w[:, None]).reshape(-1, 2, 2)
    sym = 0.5 * (C + np.transpose(C, (0, 2, 1)))
    return float(np.linalg.eigvalsh(sym).min()), float(np.abs(C).max())


def _negative_mass(f: NDArray, z_max: float) -> bool:
    """Whether the s² coefficient (normalised frequency: its contribution at the highest whirl
    frequency) has a negative symmetric part beyond round-off: a negative added mass, which
    would fit a stiffening over the table but continue beyond it as a spurious instability
    (m λ² + k = 0 with m < 0 has a growing root). Such a fit is not taken."""
    F = f.reshape(2, 2)
    return bool(np.linalg.eigvalsh(0.5 * (F + F.T)).min() < -1e-8 * z_max)


def _realization(poles, X, npoly, top, misfit, whirl) -> RationalImpedance:
    """The fitted function in SI units and a minimal real state form: per pole p (1/s) with
    residue R (2×2; complex for a pair) of rank r, R = U Wᵀ with the columns of W of norm |p|
    (so that near the rotor's frequencies a state's amplitude is that of the journal motion),
    r states ``ξ̇ = p ξ + Wᵀ u``, output ``U ξ`` (a real pole) or 2r real states for the
    real and imaginary parts of ξ, output ``2 Re(U ξ)`` (a pair)."""
    nb = sum(1 if p.imag == 0.0 else 2 for p in poles)
    coef, poly = X[:nb], X[nb:]
    D = poly[0].reshape(2, 2)
    E = (poly[1] / top).reshape(2, 2) if npoly > 1 else np.zeros((2, 2))
    F = (poly[2] / top**2).reshape(2, 2) if npoly > 2 else np.zeros((2, 2))
    A_parts, B_parts, C_parts, full = [], [], [], []
    i = 0
    for q in poles:
        # 1/(s/top − q) = top/(s − top q): the pole top·q, the residue top·R
        p = q * top
        if q.imag == 0.0:
            R = top * coef[i].reshape(2, 2)
            i += 1
        else:
            R = top * (coef[i] + 1j * coef[i + 1]).reshape(2, 2)
            i += 2
        u, sv, vh = np.linalg.svd(R)
        r = int(np.sum(sv > 1e-12 * sv[0])) if sv[0] > 0 else 0
        if r == 0:
            continue
        U = u[:, :r] * sv[:r] / abs(p)
        W = vh[:r].T * abs(p)  # R = U Wᵀ
        if q.imag == 0.0:
            A_parts.append(p.real * np.eye(r))
            B_parts.append(W.T.real)
            C_parts.append(U.real)
            full.append(p.real)
        else:
            pr, pi = p.real, p.imag
            I = np.eye(r)
            A_parts.append(np.block([[pr * I, -pi * I], [pi * I, pr * I]]))
            B_parts.append(np.vstack([W.T.real, W.T.imag]))
            C_parts.append(np.hstack([2 * U.real, -2 * U.imag]))
            full += [p, np.conj(p)]
    A = la.block_diag(*A_parts) if A_parts else np.zeros((0, 0))
    m = A.shape[0]
    return RationalImpedance(
        D=D,
        E=E,
        F=F,
        A=np.asarray(A, float).reshape(m, m),
        B=np.vstack(B_parts) if B_parts else np.zeros((0, 2)),
        C=np.hstack(C_parts) if C_parts else np.zeros((2, 0)),
        poles=np.array(full, complex),
        misfit=misfit,
        whirl=(float(whirl.min()), float(whirl.max())),
    )


def fit_row(whirl: NDArray, values: NDArray, tolerance: float) -> tuple[RationalImpedance, float]:
    """:func:`fit_impedance` of one table row, computed once per (row, tolerance): the model's
    check when it is read and the assembly share it."""
    w = np.ascontiguousarray(whirl, float)
    v = np.ascontiguousarray(values, float)
    return _fit_cached(w.tobytes(), v.tobytes(), len(w), float(tolerance))


@functools.lru_cache(maxsize=256)
def _fit_cached(whirl: bytes, values: bytes, n: int, tolerance: float):
    w = np.frombuffer(whirl, float)
    v = np.frombuffer(values, float).reshape(n, 8)
    return fit_impedance(w, v, tolerance=tolerance)
