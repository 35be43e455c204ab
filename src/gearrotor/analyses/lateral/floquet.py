"""Parametric stability of a geared train under its time-varying mesh stiffness (Floquet).

At constant shaft speeds and with the teeth in contact, the transient equations (SPEC 2.5) are
linear with periodic coefficients:

    M q̈ + (C + G(Ω) + Σ_k c_k w_k w_kᵀ) q̇ + (K + Σ_k k_k(φ_k(t)) w_k w_kᵀ) q = f(t),

with φ_k = N_k Ω_k t the mesh angle of mesh k and k_k its stiffness law (the Fourier
rectangular wave of SPEC 2.4 or a table). The variation pumps energy between modes: a mode
pair (a, b) is unstable near the *combination resonances* ω_a + ω_b ≈ n Ω_m (and the principal
ones 2 ω_a ≈ n Ω_m), Ω_m the mesh frequency, once the pumping beats the pair's damping. Such a
free vibration grows at a frequency that is no harmonic of the running speed — the
response a harmonic analysis cannot show.

Method: the Floquet multipliers μ are the eigenvalues of the monodromy matrix, the state
transition over one period T of the coefficients (the common period of all meshes; meshes
with incommensurate frequencies are refused). The state is reduced to the undamped modes of the
mean system up to ``cutoff`` (rigid-body modes, which the meshes do not strain, are dropped);
the transition matrix is the product of 4th-order Magnus steps (two Gauss points per slice,
``exp`` of the commutator-corrected generator), which is stable for any step and converges
as h⁴: ``slices`` is doubled until the multipliers move by less than ``tol``. The Floquet
exponent λ = ln μ / T has a real part (growth rate σ, 1/s; σ > 0 is unstable) and an imaginary
part defined modulo Ω_p = 2π/T; each exponent is placed at the frequency of the mode that
dominates its eigenvector (the alias closest to that mode's natural frequency), so the
reported frequency is the one a spectrum of the growing motion shows.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np
import scipy.linalg as la
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from ...errors import ModelError, SolverError
from ...model import Train
from ...threads import managed
from ..transient.equations import TransientSystem, build_system
from ..transient.mesh import fourier_coefficients, stiffness

__all__ = ["check_ka_ratio", "FloquetResult", "floquet"]


@dataclass(frozen=True)
class FloquetResult:
    """Floquet exponents of the train at one speed, least stable first.

    growth : (n,) 1/s, real parts σ (positive: the motion grows as e^{σt});
    frequency : (n,) rad/s, ≥ 0, the frequency of the dominant mode's alias;
    multipliers : (n,) complex Floquet multipliers;
    mode : (n,) index of the dominant undamped mode of the mean system (into ``mode_frequency``);
    partner : (n,) the second-largest modal contribution (−1 when a single mode dominates
    with more than 90 % of the eigenvector's energy);
    mode_frequency : (m,) rad/s, undamped natural frequencies of the kept modes;
    period : s, the period of the coefficients; mesh_frequency : rad/s per mesh;
    ka_ratio : the Ka/Kg used per mesh (None: the model's own law, e.g. a table);
    slices : steps per period; change : the largest multiplier change on the last
    doubling.
    """

    speed: float
    growth: NDArray
    frequency: NDArray
    multipliers: NDArray
    mode: NDArray
    partner: NDArray
    mode_frequency: NDArray
    period: float
    mesh_frequency: NDArray
    ka_ratio: tuple[float | None, ...]
    slices: int
    change: float
    n_modes: int
    # per mesh: the stiffness law used ({"mesh", "law", "ka_ratio", "contact_ratio", "terms"})
    mesh_laws: tuple[dict, ...] = ()

    @property
    def log_dec(self) -> NDArray:
        """Equivalent logarithmic decrement −2πσ/ω (positive: stable)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.frequency > 0, -2 * np.pi * self.growth / self.frequency, np.nan)

    @property
    def frequency_cpm(self) -> NDArray:
        return self.frequency * 60 / (2 * np.pi)

    @property
    def neutral_tolerance(self) -> float:
        """1/s: growth rates within ± this are neutral (undamped modes the meshes do not
        pump): the multipliers are converged to ``max(change, 1e-9)``, i.e. σ to that / T."""
        return max(self.change, 1e-9) / self.period

    @property
    def stable(self) -> bool:
        """No exponent grows beyond the convergence tolerance (neutral modes count as
        stable)."""
        return bool(self.growth[0] <= self.neutral_tolerance) if len(self.growth) else True

    def to_dict(self, n: int = 10) -> dict:
        """The ``n`` least stable exponents as plain Python values."""
        rows = []
        mf = self.mode_frequency * 60 / (2 * np.pi)
        for i in range(min(n, len(self.growth))):
            rows.append(
                {
                    "growth_1_s": float(self.growth[i]),
                    "frequency_cpm": float(self.frequency_cpm[i]),
                    "log_dec": float(self.log_dec[i]),
                    "order": float(self.frequency[i] / abs(self.speed)) if self.speed else None,
                    "mode_cpm": float(mf[self.mode[i]]),
                    "partner_cpm": float(mf[self.partner[i]]) if self.partner[i] >= 0 else None,
                    "multiplier_abs": float(abs(self.multipliers[i])),
                }
            )
        return {
            "speed_rpm": self.speed * 60 / (2 * np.pi),
            "period_s": self.period,
            "mesh_frequency_cpm": [float(x * 60 / (2 * np.pi)) for x in self.mesh_frequency],
            "ka_ratio": list(self.ka_ratio),
            "mesh_laws": [dict(d) for d in self.mesh_laws],
            "n_modes": self.n_modes,
            "slices": self.slices,
            "multiplier_change": self.change,
            "neutral_tolerance_1_s": self.neutral_tolerance,
            "stable": self.stable,
            "exponents": rows,
        }


def check_ka_ratio(system, ratios) -> None:
    """Refuse a Ka/Kg that cannot act (a ModelError naming the mesh field): on a mesh whose
    stiffness is a table, or whose Fourier law has no terms (``variation.terms = 0``: the
    stiffness would stay Kg and every Ka give the same result). ``ratios``: one per mesh or
    one for all (None keeps the model's law)."""
    laws = system.meshes
    if not isinstance(ratios, (list, tuple)):
        ratios = [ratios] * len(laws)
    for k, (law, r) in enumerate(zip(laws, ratios, strict=False)):
        if r is not None and not 0 <= r < 1:
            raise ModelError(
                "Ka/Kg out of range", field="ka_ratio", value=r, expected="0 ≤ Ka/Kg < 1"
            )
        if r is None or r == 0:
            continue
        idx = system.assembly.meshes[k].spec_index
        if law.has_table:
            raise ModelError(
                "Ka/Kg cannot act on a mesh whose stiffness is a table (the table is the law)",
                field=f"meshes[{idx}].stiffness_table",
                value=f"Ka/Kg {r:g}",
                expected="no --ka for this model, or remove the table",
            )
        if system.train.meshes[idx].variation.terms == 0:
            raise ModelError(
                "Ka/Kg cannot act: the mesh stiffness law has no Fourier terms, so the "
                "stiffness does not vary",
                field=f"meshes[{idx}].variation.terms",
                value=0,
                expected=f"≥ 1, e.g. --set meshes[{idx}].variation.terms=5 (with .contact_ratio)",
            )


def _common_period(rates: list[float]) -> float:
    """Common period (s) of mesh cycles with angular rates ``rates`` (rad/s); the ratios must
    be rational with small denominators (≤ 64), else the coefficients are not periodic."""
    base = max(rates)
    mult = 1
    for r in rates:
        frac = Fraction(r / base).limit_denominator(64)
        if abs(float(frac) - r / base) > 1e-9:
            raise ModelError(
                "the mesh frequencies are incommensurate: the coefficients have no common "
                "period and Floquet theory does not apply",
                field="meshes",
                value=", ".join(f"{x * 60 / 2 / np.pi:.6g} cpm" for x in rates),
                expected="mesh frequencies in a ratio of small integers",
            )
        mult = np.lcm(mult, frac.denominator)
    return float(2 * np.pi / base * mult)


@managed
def floquet(
    model: Train | TransientSystem,
    *,
    ka_ratio: float | list[float] | None = None,
    speed: float | None = None,
    cutoff: float | None = None,
    cutoff_factor: float = 2.5,
    slices: int = 32,
    tol: float = 1e-6,
    max_slices: int = 4096,
    method: str = "auto",
    operating_point=None,
) -> FloquetResult:
    """Floquet exponents of the train at its model speed (constant speeds, teeth in contact).

    ka_ratio : Ka/Kg for every mesh's Fourier law (a list: per mesh); None keeps the model's.
        Meshes with a stiffness table keep the table.
    speed : rad/s, reference-shaft speed (default: the model's); every shaft turns at its
        speed ratio times this, and speed-dependent bearings take their coefficients there.
    cutoff : Hz, keep the undamped modes up to this frequency (default ``cutoff_factor`` × the
        highest mesh frequency: the combination partners of the modes below the mesh frequency
        lie up to about one mesh frequency above them).
    slices : initial steps per period, doubled until the multipliers change by less than
        ``tol`` (absolute; the multipliers of interest have |μ| ≈ 1) or ``max_slices``.
    method : ``"lawson"``, ``"magnus"`` or ``"auto"`` (Lawson unless the mean system's
        eigenvector matrix has a condition number above 1e8).

    Backlash is ignored (the teeth are taken in contact); mesh damping acts at all times.

    operating_point : name or :class:`~gearrotor.model.OperatingPoint` (a Train model only):
    fluid-film bearings at the coefficients of the point's static loads at ``speed`` (default
    the point's speed), meshes on the loaded flank
    (:func:`~gearrotor.analyses.static.at_operating_point`).
    """
    if operating_point is not None:
        from ..static.operating_point import model_at_operating_point

        if isinstance(model, TransientSystem):
            raise ModelError(
                "an operating point needs the model, not a built system",
                field="operating_point",
                value=str(operating_point),
                expected="floquet(train, operating_point=...)",
            )
        at = None if speed is None else [float(speed)]
        model, w_op = model_at_operating_point(model, operating_point, at)
        speed = abs(w_op) if speed is None else speed
    if method not in ("auto", "lawson", "magnus"):
        raise ModelError(
            "unknown Floquet method",
            field="method",
            value=method,
            expected="'auto', 'lawson' or 'magnus'",
        )
    system = model if isinstance(model, TransientSystem) else build_system(model)
    if speed is not None:
        if not speed > 0:
            raise ModelError("speed must be positive", field="speed", value=speed, expected="> 0")
        system = system.at_speed(speed)
    laws = system.meshes
    if not laws:
        raise ModelError("Floquet analysis needs at least one gear mesh", field="meshes")
    nm = len(laws)
    if ka_ratio is None:
        ratios: list[float | None] = [None] * nm
    else:
        ratios = list(ka_ratio) if isinstance(ka_ratio, (list, tuple)) else [ka_ratio] * nm
        if len(ratios) != nm:
            raise ModelError(
                "one Ka/Kg per mesh expected", field="ka_ratio", value=ratios, expected=f"{nm}"
            )
        for r in ratios:
            if not (r is None or 0 <= r < 1):
                raise ModelError(
                    "Ka/Kg out of range", field="ka_ratio", value=r, expected="0 ≤ Ka/Kg < 1"
                )
    rates = system.mesh_rates()  # φ_m = N_i θ_i advances at N_i Ω_i (rad/s, signed)
    if np.any(rates == 0):
        raise ModelError("a gear of a mesh does not turn (zero speed)", field="speed")
    T = _common_period([abs(r) for r in rates])
    omega_m = float(np.abs(rates).max())

    # ---- reduced mean system ----------------------------------------------------------------
    M, K, C = system.linear_matrices()
    Ct = C + system.gyroscopic()
    for law, d in zip(laws, system.mesh_dofs, strict=True):
        ok = d >= 0
        Ct[np.ix_(d[ok], d[ok])] += law.damping * np.outer(law.w[ok], law.w[ok])
    # basis: the undamped modes of the symmetric part (cross-coupled bearings and
    # CrossCoupling make K non-symmetric); the whole K, skew part included, is projected
    # (tilting pads with pad dynamics: their indefinite symmetric film block is made
    # semidefinite for the basis, and every pad coordinate is added to it, as in ModalRK4)
    from ..transient.prepare import _pad_shapes
    from ..transient.reduction import basis_stiffness

    Ks = basis_stiffness(system, K)
    w2, V = la.eigh(Ks, M)
    om = np.sqrt(np.clip(w2, 0.0, None))
    wcut = 2 * np.pi * cutoff if cutoff is not None else cutoff_factor * omega_m
    keep = (om <= wcut) & (om > 1e-6 * max(om.max(), 1.0))
    if not keep.any():
        raise ModelError("no elastic mode below the cut-off", field="cutoff", value=wcut)
    Phi = V[:, keep]
    lam = w2[keep]
    E = _pad_shapes(system)
    if E.shape[1]:
        for _ in range(2):  # M-orthogonal to the kept modes and to each other
            E = E - Phi @ (Phi.T @ (M @ E))
            gw, gv = la.eigh(E.T @ M @ E)
            ok = gw > 1e-10 * gw.max()
            E = E @ (gv[:, ok] / np.sqrt(gw[ok]))
        Phi = np.hstack([Phi, E])
        lam = np.concatenate([lam, np.einsum("ij,ij->j", E, Ks @ E)])
    m = Phi.shape[1]
    Cr = Phi.T @ Ct @ Phi
    Kr = Phi.T @ K @ Phi
    # per mesh: modal mesh vector and the stiffness variation about Kg over the period
    wm = []
    for law, d in zip(laws, system.mesh_dofs, strict=True):
        ok = d >= 0
        wm.append(Phi[d[ok]].T @ law.w[ok])
    wm = np.array(wm)  # (nm, m)
    check_ka_ratio(system, ratios)
    laws_eff, used = [], []
    for k, (law, r) in enumerate(zip(laws, ratios, strict=True)):
        idx = system.assembly.meshes[k].spec_index
        v = system.train.meshes[idx].variation
        if r is not None and not law.has_table:
            a, b = fourier_coefficients(v.contact_ratio, v.phase, v.terms)
            law = replace(law, ka=r * law.kg, coef_a=a, coef_b=b)
        laws_eff.append(law)
        used.append(
            {
                "mesh": law.name,
                "law": (
                    "geometry" if system.train.meshes[idx].excitation_law == "geometry" else "table"
                )
                if law.has_table
                else ("fourier" if law.ka and len(law.coef_a) else "constant"),
                "ka_ratio": None if law.has_table else float(law.ka / law.kg),
                "contact_ratio": float(v.contact_ratio),
                "terms": int(v.terms),
            }
        )

    A0 = np.zeros((2 * m, 2 * m))
    A0[:m, m:] = np.eye(m)
    A0[m:, :m] = -Kr
    A0[m:, m:] = -Cr

    def kv(t: float) -> NDArray:
        return np.array(
            [float(stiffness(lw, rt * t)) - lw.kg for lw, rt in zip(laws_eff, rates, strict=True)]
        )

    Lam, S = la.eig(A0)
    if method == "lawson" or (method == "auto" and np.linalg.cond(S) < 1e8):
        # the variation −kv w wᵀ in the lower-left block is rank one per mesh: in the
        # eigen-coordinates of the mean system it is u_k v_kᵀ
        Si = la.inv(S)
        U = -Si[:, m:] @ wm.T  # (2m, nm)
        Vt = wm @ S[:m, :]  # (nm, 2m)

        def monodromy(ns: int) -> NDArray:
            return S @ _lawson_monodromy(Lam, U, Vt, kv, T, ns) @ Si

    else:

        def monodromy(ns: int) -> NDArray:
            return _magnus_monodromy(A0, wm, kv, T, ns)

    ns = slices
    mu, vec = la.eig(monodromy(ns))
    change = np.inf
    while ns < max_slices:
        ns *= 2
        mu2, vec2 = la.eig(monodromy(ns))
        change = _match_change(mu, mu2)
        mu, vec = mu2, vec2
        if change < tol:
            break
    if change >= tol:
        raise SolverError(
            f"Floquet multipliers not converged with {ns} steps per period "
            f"(last change {change:.2e} ≥ {tol:.1e}); lower the cut-off"
        )

    # ---- exponents, placed at the dominant mode's alias ----------------------------------------
    om_k = np.sqrt(np.clip(lam, 0.0, None))
    omega_p = 2 * np.pi / T
    growth = np.log(np.abs(mu)) / T
    base = np.angle(mu) / T
    freq = np.zeros(len(mu))
    dom = np.zeros(len(mu), int)
    partner = np.full(len(mu), -1)
    for i in range(len(mu)):
        v = vec[:, i]
        energy = om_k**2 * np.abs(v[:m]) ** 2 + np.abs(v[m:]) ** 2
        order = np.argsort(energy)[::-1]
        dom[i] = order[0]
        if energy[order[0]] < 0.9 * energy.sum():
            partner[i] = order[1]
        target = om_k[dom[i]]
        cands = [b + np.round((target - b) / omega_p) * omega_p for b in (base[i], -base[i])]
        freq[i] = min((abs(c) for c in cands), key=lambda c: abs(c - target))
    # one entry per conjugate pair: keep the exponents with Im μ ≥ 0 (real μ count once)
    sel = np.imag(mu) >= -1e-12 * np.abs(mu)
    idx = np.flatnonzero(sel)
    idx = idx[np.lexsort((freq[idx], -growth[idx]))]
    return FloquetResult(
        speed=float(system.train.speed if speed is None else speed),
        growth=growth[idx],
        frequency=freq[idx],
        multipliers=mu[idx],
        mode=dom[idx],
        partner=partner[idx],
        mode_frequency=om_k,
        period=T,
        mesh_frequency=np.abs(rates),
        ka_ratio=tuple(ratios),
        slices=ns,
        change=float(change),
        n_modes=m,
        mesh_laws=tuple(used),
    )


def _lawson_monodromy(Lam, U, Vt, kv, T: float, ns: int) -> NDArray:
    """Transition matrix over one period of ż = (Λ + Σ_k kv_k(t) u_k v_kᵀ) z by the Lawson
    (integrating-factor) RK4 method: the diagonal Λ is integrated exactly, the rank-one
    variation by RK4, so the step is set by the variation's harmonics, not by the stiffness of
    the highest modes."""
    h = T / ns
    E = np.exp(Lam * h / 2)[:, None]
    n = len(Lam)
    Z = np.eye(n, dtype=complex)

    def N(t, Y):
        return U @ (kv(t)[:, None] * (Vt @ Y))

    for i in range(ns):
        t = i * h
        k1 = N(t, Z)
        k2 = N(t + h / 2, E * (Z + h / 2 * k1))
        k3 = N(t + h / 2, E * Z + h / 2 * k2)
        EZ = E * Z
        k4 = N(t + h, E * (EZ + h * k3))
        Z = E * (EZ + h / 6 * (E * k1 + 2 * (k2 + k3))) + h / 6 * k4
    return Z


def _magnus_monodromy(A0, wm, kv, T: float, ns: int) -> NDArray:
    """Transition matrix over one period by 4th-order Magnus steps (two Gauss points per
    step); used when the mean system's eigenvectors are too ill-conditioned for Lawson."""
    m = wm.shape[1]
    h = T / ns
    g = np.sqrt(3) / 6
    P = np.eye(2 * m)

    def A(t):
        out = A0.copy()
        out[m:, :m] -= (wm.T * kv(t)) @ wm
        return out

    for i in range(ns):
        A1 = A((i + 0.5 - g) * h)
        A2 = A((i + 0.5 + g) * h)
        Om = 0.5 * h * (A1 + A2) + (np.sqrt(3) / 12) * h**2 * (A2 @ A1 - A1 @ A2)
        P = la.expm(Om) @ P
    return P


def _match_change(mu1: NDArray, mu2: NDArray) -> float:
    """Largest distance between two multiplier sets matched one-to-one (Hungarian)."""
    d = np.abs(mu1[:, None] - mu2[None, :])
    r, c = linear_sum_assignment(d)
    return float(d[r, c].max())
