"""Periodic steady state of a geared train over speed: the response to the mesh excitation
(transmission error and time-varying mesh stiffness) and to unbalance, by harmonic balance of
the linear time-periodic equations (issue 27).

At constant shaft speeds and with the teeth in contact, the equations of the transient
(SPEC 2.5, :mod:`.transient.equations`) are linear with periodic coefficients:

    M q̈ + (C + G(Ω) + Σ_k c_k w_k w_kᵀ) q̇ + (K + Σ_k k_k(t) w_k w_kᵀ) q
        = Σ_k [k_k(t) e_k(t) + c_k ė_k(t)] w_k + f_unbalance(t) + f_static,

k_k(t) = k_k(φ_k), e_k(t) = e_k(φ_k) the stiffness and transmission error of mesh k as laws of
its mesh angle φ_k = N_i Ω_i t (the tooth geometry's TVMS and STE, :mod:`gearrotor.gears`, or
the square wave and tables of SPEC 2.4). Their harmonics are multiples of Ω_p = 2π/T, T the
common period of the meshes (:func:`.floquet._common_period`). A periodic coefficient couples a
response at frequency ω to ω ± jΩ_p, so the steady response to a forcing at ν is

    q(t) = Re Σ_{n=−H..H} Q_n e^{i(ν + nΩ_p)t},

and the Q_n solve one sparse linear system (the harmonic balance: the equations projected on
every e^{i(ν+nΩ_p)t}; the rows n couple through the harmonics of k_k, truncated at ±H; the
harmonics of a product k·e are their convolution). There are independent forcing families:

* the mesh excitation (ν = 0): the transmission errors through k e + c ė, and the static loads
  (the model's constant torques; without torques, each geometry mesh loaded by its own pair's
  operating torque applied at its two gear nodes). The static deflection under load times the
  stiffness variation is the parametric excitation of a square-wave mesh. The train's free
  rigid rotation is removed at n = 0 (the response orthogonal to it in the mass metric, with
  the uniform angular acceleration of unbalanced torques as an unknown, as in the static
  initial state of the transient);
* unbalance, one family per distinct shaft speed Ω_s (ν = |Ω_s|): the 1x response and its
  sidebands |Ω_s| ± nΩ_p.

The truncation is exact for the truncated laws (``harmonics`` mesh harmonics; the tests show
the response converged in it) and needs no time stepping: a speed costs one sparse LU per
family. Contact loss (the dynamic mesh force falling below zero) makes the equations nonlinear:
the speeds where the linear periodic response loses contact are flagged, and the transient
(:func:`gearrotor.analyses.transient.transient`, backlash) is the reference there.

Reported per speed: the dynamic transmission error (DTE: the mesh deflection δ = w·q about its
mean, rms; from the mesh excitation and in total with unbalance), the mesh force's mean, maximum
and minimum and the dynamic factor max F / mean F (compare ISO 6336-1's K_v,
:func:`gearrotor.gears.iso6336.dynamic_factor`), probe amplitudes (0-peak) at the probe shaft's
1x and at 1x and 2x of each mesh frequency, and the bearings' dynamic forces at the same
frequencies (the semi-major axis of the force ellipse). Bearings keep their coefficients at the
shaft speed for every harmonic (synchronous coefficients, as in the transient).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from ...errors import ModelError, SolverError
from ...model import Train
from ...threads import managed
from ..transient.equations import TransientSystem, build_system
from ..transient.mesh import stiffness as law_stiffness
from .floquet import _common_period

__all__ = ["MeshResponseResult", "mesh_response", "MESH_HARMONICS"]

#: Mesh harmonics kept by default in the response (of the highest mesh frequency).
MESH_HARMONICS = 10
_RPM = 30 / np.pi


@dataclass(frozen=True)
class MeshResponseResult:
    """Periodic steady state over speed (SI units; amplitudes 0-peak).

    speed : (s,) reference-shaft speed, rad/s; meshes : mesh names; mesh_frequency : (s, m)
    rad/s; static_force, force_max, force_min : (s, m) N, mean, largest and smallest mesh force
    over a period of the mesh excitation; dynamic_factor : (s, m) force_max / static_force;
    contact_loss : (s, m) bool, force_min < 0 (the linear response is invalid there);
    dte_rms : (s, m) m, rms of the mesh deflection about its mean under the mesh excitation;
    dte_rms_total : (s, m) m, with the unbalance response; probes : probe names;
    probe_1x : (s, p) m at the probe shaft's speed (unbalance); probe_mesh : (s, p, m, 2) m at
    1x and 2x of each mesh frequency; bearings : names; bearing_1x : (s, b) N at the bearing
    shaft's speed; bearing_mesh : (s, b, m, 2) N; operating_force : (m,) N the normal force a
    geometry mesh's curves were computed for (NaN for other meshes); harmonics : mesh harmonics
    kept; notes : what the user should know (loads applied, contact loss).
    """

    speed: NDArray
    meshes: tuple[str, ...]
    mesh_frequency: NDArray
    static_force: NDArray
    force_max: NDArray
    force_min: NDArray
    dynamic_factor: NDArray
    contact_loss: NDArray
    dte_rms: NDArray
    dte_rms_total: NDArray
    probes: tuple[str, ...]
    probe_1x: NDArray
    probe_mesh: NDArray
    bearings: tuple[str, ...]
    bearing_1x: NDArray
    bearing_mesh: NDArray
    operating_force: NDArray
    harmonics: int
    notes: tuple[str, ...] = ()
    laws: tuple[str, ...] = field(default=())
    #: ISO 6336-1 method B K_v of the geometry meshes (NaN for others), (s, m), and the
    #: reference-shaft speed at which the pinion runs at its resonance speed n_E1 (rad/s)
    #: the largest Floquet growth rate at each speed (1/s; NaN without the check): where it is
    #: positive the time-periodic equations are parametrically unstable (SPEC 2.4: the mesh
    #: stiffness pumps a mode pair), a free vibration grows and the periodic response is not
    #: what the machine does
    floquet_growth: NDArray | None = None
    iso_kv: NDArray | None = None
    iso_resonance_speed: NDArray | None = None
    #: nonlinear solution (``nonlinear=True``): (s, m) fractions of the mesh period with the
    #: teeth apart and on the back flank, the linear DTE rms for comparison (m), and (s,)
    #: whether Newton's method converged
    nonlinear: bool = False
    separation_fraction: NDArray | None = None
    back_contact_fraction: NDArray | None = None
    dte_rms_linear: NDArray | None = None
    converged: NDArray | None = None

    @property
    def speed_rpm(self) -> NDArray:
        return self.speed * _RPM

    @property
    def unstable(self) -> NDArray:
        """(s,) bool: parametrically unstable speeds (Floquet growth > 0)."""
        if self.floquet_growth is None:
            return np.zeros(len(self.speed), bool)
        return np.nan_to_num(self.floquet_growth, nan=0.0) > 0

    def to_dict(self) -> dict:
        """JSON-ready numbers, units in the key names."""

        def lst(a, scale=1.0):
            return [None if not np.isfinite(x) else float(x * scale) for x in np.ravel(a)]

        meshes = []
        for k, name in enumerate(self.meshes):
            meshes.append(
                {
                    "mesh": name,
                    "law": self.laws[k] if k < len(self.laws) else None,
                    "operating_force_N": None
                    if not np.isfinite(self.operating_force[k])
                    else float(self.operating_force[k]),
                    "mesh_frequency_cpm": lst(self.mesh_frequency[:, k], _RPM),
                    "dte_rms_um": lst(self.dte_rms[:, k], 1e6),
                    "dte_rms_total_um": lst(self.dte_rms_total[:, k], 1e6),
                    "static_force_N": lst(self.static_force[:, k]),
                    "max_force_N": lst(self.force_max[:, k]),
                    "min_force_N": lst(self.force_min[:, k]),
                    "dynamic_factor": lst(self.dynamic_factor[:, k]),
                    "contact_loss": [bool(x) for x in self.contact_loss[:, k]],
                    **(
                        {
                            "separation_fraction": lst(self.separation_fraction[:, k]),
                            "back_contact_fraction": lst(self.back_contact_fraction[:, k]),
                            "dte_rms_linear_um": lst(self.dte_rms_linear[:, k], 1e6),
                        }
                        if self.nonlinear
                        else {}
                    ),
                    "iso6336_kv": None if self.iso_kv is None else lst(self.iso_kv[:, k]),
                    "iso6336_resonance_speed_rpm": None
                    if self.iso_resonance_speed is None
                    or not np.isfinite(self.iso_resonance_speed[k])
                    else float(self.iso_resonance_speed[k] * _RPM),
                }
            )
        probes = []
        for p, name in enumerate(self.probes):
            probes.append(
                {
                    "probe": name,
                    "amplitude_1x_um": lst(self.probe_1x[:, p], 1e6),
                    "amplitude_mesh_1x_um": [
                        lst(self.probe_mesh[:, p, k, 0], 1e6) for k in range(len(self.meshes))
                    ],
                    "amplitude_mesh_2x_um": [
                        lst(self.probe_mesh[:, p, k, 1], 1e6) for k in range(len(self.meshes))
                    ],
                }
            )
        bearings = []
        for b, name in enumerate(self.bearings):
            bearings.append(
                {
                    "bearing": name,
                    "force_1x_N": lst(self.bearing_1x[:, b]),
                    "force_mesh_1x_N": [
                        lst(self.bearing_mesh[:, b, k, 0]) for k in range(len(self.meshes))
                    ],
                    "force_mesh_2x_N": [
                        lst(self.bearing_mesh[:, b, k, 1]) for k in range(len(self.meshes))
                    ],
                }
            )
        return {
            "speed_rpm": lst(self.speed, _RPM),
            "floquet_growth_1_s": None if self.floquet_growth is None else lst(self.floquet_growth),
            "unstable": [bool(x) for x in self.unstable],
            "harmonics": self.harmonics,
            "nonlinear": self.nonlinear,
            **(
                {"converged": [bool(x) for x in self.converged]}
                if self.nonlinear and self.converged is not None
                else {}
            ),
            "meshes": meshes,
            "probes": probes,
            "bearings": bearings,
            "notes": list(self.notes),
        }

    def table(self) -> str:
        lines = [
            f"periodic response over {len(self.speed)} speeds, "
            f"{self.speed_rpm.min():.0f}-{self.speed_rpm.max():.0f} rpm, "
            f"{self.harmonics} mesh harmonics"
        ]
        for k, name in enumerate(self.meshes):
            i = int(np.nanargmax(self.dte_rms[:, k]))
            j = int(np.nanargmax(self.dynamic_factor[:, k]))
            lines.append(
                f"  {name}: DTE rms max {self.dte_rms[i, k] * 1e6:.4g} um at "
                f"{self.speed_rpm[i]:.0f} rpm (mesh {self.mesh_frequency[i, k] * _RPM:.0f} cpm); "
                f"dynamic factor max {self.dynamic_factor[j, k]:.4g} at "
                f"{self.speed_rpm[j]:.0f} rpm"
                + (
                    f"; contact loss at {int(self.contact_loss[:, k].sum())} speeds"
                    if self.contact_loss[:, k].any()
                    else ""
                )
                + (
                    f" (teeth apart up to {100 * np.max(self.separation_fraction[:, k]):.3g} % "
                    "of the mesh period; nonlinear)"
                    if self.nonlinear and self.contact_loss[:, k].any()
                    else ""
                )
            )
        for p, name in enumerate(self.probes):
            a = self.probe_mesh[:, p, :, 0]
            i, k = np.unravel_index(int(np.nanargmax(a)), a.shape)
            lines.append(
                f"  probe {name}: 1x max {np.nanmax(self.probe_1x[:, p]) * 1e6:.4g} um; mesh 1x "
                f"max {a[i, k] * 1e6:.4g} um at {self.speed_rpm[i]:.0f} rpm ({self.meshes[k]})"
            )
        for b, name in enumerate(self.bearings):
            a = self.bearing_mesh[:, b, :, 0]
            if not np.isfinite(a).any():
                continue
            i, k = np.unravel_index(int(np.nanargmax(a)), a.shape)
            lines.append(
                f"  bearing {name}: 1x max {np.nanmax(self.bearing_1x[:, b]):.4g} N; mesh 1x max "
                f"{a[i, k]:.4g} N at {self.speed_rpm[i]:.0f} rpm"
            )
        if self.unstable.any():
            lines.append(
                "  parametrically unstable at "
                + ", ".join(f"{x:.0f}" for x in self.speed_rpm[self.unstable][:8])
                + (" ..." if self.unstable.sum() > 8 else "")
                + " rpm"
            )
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)


def _iso_kv(train: Train, asm, m, speeds: NDArray) -> tuple[NDArray, float]:
    """ISO 6336-1 method B K_v of a geometry mesh over the reference speeds, and the reference
    speed (rad/s) at which the pinion reaches the resonance speed n_E1."""
    from ...gears.iso6336 import dynamic_factor
    from ...gears.model_mesh import model_mesh

    mm = model_mesh(train, m.spec_index)
    spec = train.meshes[m.spec_index]
    sides = (spec.gear, spec.mate) if mm.pinion_is_gear else (spec.mate, spec.gear)
    dens, mods = [], []
    for side in sides:
        si = train.shaft_index(side.shaft, "meshes")
        mat = train.materials[train.shafts[si].material]
        dens.append(mat.density)
        mods.append(side.E if side.E is not None else mat.E)
    pinion_shaft = m.shafts[0] if mm.pinion_is_gear else m.shafts[1]
    relief = max(
        (r.amount for f in (mm.spec.modifications.pinion, mm.spec.modifications.gear)
         for r in (f.tip_relief,) if r is not None),
        default=0.0,
    )  # fmt: skip
    res = dynamic_factor(
        mm.curves,
        speeds * asm.speed_ratio[pinion_shaft],
        tuple(dens),
        mm.spec.bore_diameter,
        modulus=tuple(mods),
        tip_relief=relief,
    )
    return res.kv, res.resonance_speed / abs(asm.speed_ratio[pinion_shaft])


def _law_harmonics(law, S: int) -> tuple[NDArray, NDArray]:
    """Two-sided Fourier coefficients s = −S..S of a mesh law's stiffness and transmission
    error in its mesh angle φ (N/m, m)."""
    n = max(1024, 8 * S + 8)
    phi = np.arange(n) * 2 * np.pi / n
    kc = np.fft.fft(law_stiffness(law, phi)) / n
    k2 = np.zeros(2 * S + 1, complex)
    for s in range(-S, S + 1):
        k2[s + S] = kc[s % n]
    e2 = np.zeros(2 * S + 1, complex)
    for s in range(1, min(S, len(law.te)) + 1):
        c, si = law.te[s - 1]
        e2[S + s] = (c - 1j * si) / 2
        e2[S - s] = (c + 1j * si) / 2
    return k2, e2


def _ellipse_major(X: NDArray, Y: NDArray) -> NDArray:
    """Semi-major axis of the ellipse x = Re(X e^{iωt}), y = Re(Y e^{iωt})."""
    a2 = np.abs(X) ** 2 + np.abs(Y) ** 2
    return np.sqrt(0.5 * (a2 + np.abs(X**2 + Y**2)))


@dataclass(frozen=True)
class _Blocks:
    """The harmonic-balance operator at one speed: K, M, C + G (mean meshes included), the
    periodic part P, the harmonic indices, Ω_p, H, the rigid rotation's M r."""

    K: sp.csr_array
    M: sp.csr_array
    C: sp.csr_array
    P: sp.csr_array
    hidx: NDArray
    Wp: float
    H: int
    Mr: NDArray
    speed: float


def _factor(hb: _Blocks, nu: float, border: bool):
    """The harmonic-balance operator at ν factorised once: a function taking the forcing
    F (2H+1, n[, r]) at frequencies ν + nΩ_p and returning Q_n (2H+1, n[, r]); with ``border``
    the n = 0 response is kept M-orthogonal to the rigid rotation (its acceleration an
    unknown)."""
    n = hb.K.shape[0]
    nh = 2 * hb.H + 1
    om = nu + hb.hidx * hb.Wp
    A = (
        sp.kron(sp.eye(nh), hb.K)
        + sp.kron(sp.diags(-(om**2)), hb.M)
        + sp.kron(sp.diags(1j * om), hb.C)
        + hb.P
    )
    if border:
        c = np.zeros(nh * n)
        c[hb.H * n : (hb.H + 1) * n] = hb.Mr
        A = sp.bmat([[A, sp.csr_array(c[:, None])], [sp.csr_array(c[None, :]), None]])
    try:
        lu = spla.splu(sp.csc_array(A))
    except RuntimeError as exc:
        raise SolverError(
            f"harmonic balance singular at {hb.speed * _RPM:.1f} rpm: {exc}"
        ) from None

    def solve(F: NDArray) -> NDArray:
        extra = F.shape[2:]
        rhs = F.reshape((nh * n,) + extra).astype(complex)
        if border:
            rhs = np.concatenate([rhs, np.zeros((1,) + extra, complex)])
        x = lu.solve(rhs)
        if not np.all(np.isfinite(x)):
            raise SolverError(f"harmonic balance failed at {hb.speed * _RPM:.1f} rpm")
        return x[: nh * n].reshape((nh, n) + extra)

    return solve


def _solve(hb: _Blocks, nu: float, F: NDArray, border: bool) -> NDArray:
    """Q_n (2H+1, n) for the forcing F (2H+1, n) at frequencies ν + nΩ_p (see
    :func:`_factor`)."""
    return _factor(hb, nu, border)(F)


@dataclass(frozen=True)
class _Contact:
    """The nonlinear periodic solution of one speed: the response harmonics Q (2H+1, n), the
    mesh deflections δ(t) and forces F(t) (m, N; (meshes, samples)), the fraction of the period
    each mesh spends with its teeth apart and in back-flank contact, Newton's iterations and
    whether it converged, and δ̂ (meshes, 2H+1) to continue from."""

    Q: NDArray
    delta: NDArray
    force: NDArray
    separated: NDArray
    back: NDArray
    iterations: int
    converged: bool
    x: NDArray


def _contact_law(de, dde, k, c, b):
    """The transient's mesh law (:mod:`.transient.mesh`) against the drive-flank linear law
    F_L = k (δ_e − b) + c δ̇_e: the difference D = F − F_L and its derivatives in δ_e and δ̇_e,
    and the contact states (separated, back flank)."""
    FL = k * (de - b) + c * dde
    drive = de > b
    back = de < -b
    sep = ~(drive | back)
    D = np.where(drive, 0.0, np.where(back, 2 * k * b, -FL))
    return D, np.where(sep, -k, 0.0), np.where(sep, -c, 0.0), sep, back


def _contact_balance(
    solve0,
    Qlin: NDArray,
    W: NDArray,
    kt: NDArray,
    et: NDArray,
    det: NDArray,
    damping: NDArray,
    backlash: NDArray,
    E: NDArray,
    om0: NDArray,
    guesses: list[NDArray],
    *,
    tol: float = 1e-9,
    max_iter: int = 30,
) -> _Contact:
    """Harmonic balance with the backlash law by alternating frequency and time, condensed on
    the mesh deflections (the only nonlinear coordinates).

    The linear operator A (every mesh in drive-flank contact, F_L = k(t)(δ_e − b) + c δ̇_e)
    gives Q_lin; the law's departure D(t) = F(t) − F_L(t) (zero in drive contact, −F_L apart,
    2 k b on the back flank) acts along each mesh's w, so δ̂ = δ̂_lin − R D̂(δ̂) with the
    receptance R = (I ⊗ wᵀ) A⁻¹ (I ⊗ w) between the harmonics of the mesh deflections.
    D̂ from δ̂: δ(t) at N samples, D(t) there, the discrete Fourier transform back. The law is
    piecewise linear, so Newton's method on the real and imaginary parts of δ̂ with the exact
    (semi-smooth) Jacobian converges in a few steps once the contact pattern settles; a
    backtracking line search keeps it from wandering. ``guesses``: starting δ̂ tried in turn
    (continuation along the sweep: the secant prediction from the last two speeds, the last
    speed's solution), then the linear solution."""
    nh, n = Qlin.shape
    nm = len(W)
    N = E.shape[0]
    m = nm * nh
    # receptance between the mesh deflections' harmonics
    rhs = np.zeros((nh, n, m), complex)
    for k in range(nm):
        for j in range(nh):
            rhs[j, :, k * nh + j] = W[k]
    X = solve0(rhs)  # (nh, n, m)
    R = np.einsum("jnc,kn->kjc", X, W).reshape(m, m)
    Rr = np.block([[R.real, -R.imag], [R.imag, R.real]])
    xlin = (Qlin @ W.T).T.reshape(m)  # (nm·nh,) δ̂ of the linear law
    Ed = E * (1j * om0)
    Tr = np.hstack([E.real, -E.imag])  # δ(t) from [Re δ̂, Im δ̂]
    Td = np.hstack([Ed.real, -Ed.imag])
    Fm = np.vstack([E.conj().T.real, E.conj().T.imag]) / N  # [Re, Im] of the DFT

    def split(z):
        return z[:m] + 1j * z[m:]

    def residual(x, mu=1.0):
        xs = x.reshape(nm, nh)
        d = np.real(xs @ E.T)  # (nm, N)
        dd = np.real(xs @ Ed.T)
        D, gk, gc, sep, back = _contact_law(
            d - et, dd - det, kt, damping[:, None], backlash[:, None]
        )
        Dh = (D @ E.conj()) / N  # (nm, nh)
        r = x - xlin + mu * (R @ Dh.reshape(m))
        return r, (D, gk, gc, sep, back, d, dd)

    scale = max(float(np.linalg.norm(xlin)), float(np.max(backlash)) * np.sqrt(nh), 1e-12)
    count = [0]

    def newton(x, mu, iters):
        """Newton's method at homotopy parameter μ from x: (x, residual, state, converged)."""
        r, st = residual(x, mu)
        for _ in range(iters):
            nr = float(np.linalg.norm(r))
            if nr <= tol * scale:
                return x, r, st, True
            count[0] += 1
            _, gk, gc, *_ = st
            Jd = np.zeros((2 * m, 2 * m))
            for k in range(nm):
                ik = np.r_[k * nh : (k + 1) * nh, m + k * nh : m + (k + 1) * nh]
                Jd[np.ix_(ik, ik)] = Fm @ (gk[k][:, None] * Tr + gc[k][:, None] * Td)
            try:
                dz = np.linalg.solve(np.eye(2 * m) + mu * (Rr @ Jd), -np.r_[r.real, r.imag])
            except np.linalg.LinAlgError:
                break
            dx = split(dz)
            lam = 1.0
            while lam >= 1 / 64:
                xn = x + lam * dx
                rn, stn = residual(xn, mu)
                if np.linalg.norm(rn) < (1 - 1e-4 * lam) * nr:
                    break
                lam /= 2
            else:
                break  # no descent: a kink or a fold of the piecewise-linear residual
            x, r, st = xn, rn, stn
        return x, r, st, float(np.linalg.norm(r)) <= tol * scale

    best = None

    def keep(x, r, st):
        nonlocal best
        nr = float(np.linalg.norm(r))
        if best is None or nr < best[0]:
            best = (nr, x, r, st)

    done = False
    for start in [*guesses, xlin.reshape(nm, nh)]:
        x, r, st, done = newton(np.array(start, complex).reshape(m), 1.0, max_iter)
        keep(x, r, st)
        if done:
            break
    nr, x, r, st = best
    D, _, _, sep, back, d, dd = st
    Dh = (D @ E.conj()) / N
    F = np.zeros((nh, n), complex)
    for k in range(nm):
        F -= Dh[k][:, None] * W[k][None, :]
    Q = Qlin + solve0(F)
    force = kt * (d - et - backlash[:, None]) + damping[:, None] * (dd - det) + D
    return _Contact(
        Q=Q,
        delta=d,
        force=force,
        separated=sep.mean(axis=1),
        back=back.mean(axis=1),
        iterations=count[0],
        converged=nr <= tol * scale,
        x=x.reshape(nm, nh),
    )


@managed
def mesh_response(
    model: Train | TransientSystem,
    *,
    speeds: NDArray,
    harmonics: int = MESH_HARMONICS,
    unbalance: bool = True,
    samples: int | None = None,
    stability: bool = True,
    nonlinear: bool = False,
    sweep: str = "down",
) -> MeshResponseResult:
    """Periodic steady state at each reference-shaft speed of ``speeds`` (rad/s, > 0).

    harmonics : mesh harmonics kept (of each mesh law, and in the response, of the highest mesh
        frequency); unbalance : include the unbalance families; samples : time samples per
        period for the mesh force's extremes (default 16 per kept harmonic); stability : check
        the parametric stability at every speed (:func:`.floquet.floquet`, the same equations
        and laws), reported as ``floquet_growth`` and ``unstable``; nonlinear : solve the mesh
        excitation with the transient's backlash law (teeth separating and meeting the back
        flank; :func:`_contact_balance`), continuing the solution from speed to speed in the
        order of ``speeds``; the unbalance response stays linear and is added to the DTE.
    """
    system = model if isinstance(model, TransientSystem) else build_system(model)
    speeds = np.atleast_1d(np.asarray(speeds, float))
    if not len(speeds) or np.any(~np.isfinite(speeds)) or np.any(speeds <= 0):
        raise ModelError(
            "the speeds of a mesh response must be positive",
            field="speeds",
            value=speeds.tolist()[:5],
            expected="> 0 rad/s",
        )
    if not 1 <= harmonics <= 200:
        raise ModelError(
            "mesh harmonics out of range", field="harmonics", value=harmonics, expected="1..200"
        )
    laws = system.meshes
    if not laws:
        raise ModelError("a mesh response needs at least one gear mesh", field="meshes")
    train, asm = system.train, system.assembly
    n = system.n
    nm = len(laws)
    backlash = np.array([law.backlash for law in laws])
    damping = np.array([law.damping for law in laws])
    if sweep not in ("up", "down"):
        raise ModelError("unknown sweep direction", field="sweep", value=sweep,
                         expected="'up' or 'down'")  # fmt: skip
    if nonlinear and not np.any(backlash > 0):
        raise ModelError(
            "a nonlinear mesh response needs a mesh backlash (with none the back flank takes "
            "the load at once and the mesh law is linear)",
            field="meshes[0].backlash",
            value=0.0,
            expected="> 0 on at least one mesh",
        )

    # ---- mesh laws as harmonics (speed independent) ----------------------------------------
    S = harmonics
    khat, ehat, W = [], [], []
    for law, d in zip(laws, system.mesh_dofs, strict=True):
        k2, e2 = _law_harmonics(law, S)
        khat.append(k2)
        ehat.append(e2)
        ok = d >= 0
        w = np.zeros(n)
        w[d[ok]] = law.w[ok]
        W.append(w)
    W = np.array(W)  # (nm, n)
    Wsp = [sp.csr_array(np.outer(w, w)) for w in W]
    kinds = []
    for m in asm.meshes:
        spec = train.meshes[m.spec_index]
        kinds.append(spec.excitation_law)

    # operating loads of geometry meshes (their pair's normal force)
    op_force = np.full(nm, np.nan)
    for k, m in enumerate(asm.meshes):
        if kinds[k] == "geometry":
            from ...gears.model_mesh import model_mesh

            op_force[k] = model_mesh(train, m.spec_index).curves.force

    iso_kv = np.full((len(speeds), nm), np.nan)
    iso_res = np.full(nm, np.nan)
    for k, m in enumerate(asm.meshes):
        if kinds[k] == "geometry":
            iso_kv[:, k], iso_res[k] = _iso_kv(train, asm, m, speeds)

    # ---- static loads ------------------------------------------------------------------------
    notes = []
    f_static = np.zeros(n)
    if train.torques:
        for j, tq in enumerate(train.torques):
            dof = system.torque_dof[j]
            if tq.time is not None:
                val = float(np.interp(0.0, tq.time, tq.values))
            else:
                val = tq.value
            f_static[dof] += val  # speed dependence applied per speed below
        notes.append("static loads: the model's constant torques")
    elif np.isfinite(op_force).any():
        for k in np.flatnonzero(np.isfinite(op_force)):
            d = system.mesh_dofs[k]
            for idx in (5, 11):
                if d[idx] >= 0:
                    f_static[d[idx]] += op_force[k] * laws[k].w[idx]
        notes.append(
            "static loads: each geometry mesh carries its gear pair's operating torque, applied "
            "at its two gear nodes (the model has no torques)"
        )
    # rigid rotation of the train (θz of every shaft at its speed ratio)
    r = np.zeros(n)
    for s_, a in enumerate(system.a_weights):
        r[a != 0] = asm.speed_ratio[s_]

    probes = list(train.probes)
    probe_idx, probe_dir, probe_shaft = [], [], []
    for k, p in enumerate(probes):
        si, node = train.node_index(p, f"probes[{k}]")
        g0 = asm.node_offset[si][node]
        probe_idx.append((system.index(g0), system.index(g0 + 1)))
        probe_dir.append((np.cos(p.angle), np.sin(p.angle)))
        probe_shaft.append(si)
    brg = [b for b in asm.bearings]

    ns = len(speeds)
    out = {
        "freq": np.zeros((ns, nm)),
        "F0": np.zeros((ns, nm)),
        "Fmax": np.zeros((ns, nm)),
        "Fmin": np.zeros((ns, nm)),
        "dte": np.zeros((ns, nm)),
        "dte_tot": np.zeros((ns, nm)),
        "p1": np.zeros((ns, len(probes))),
        "pm": np.zeros((ns, len(probes), nm, 2)),
        "b1": np.array([[np.nan if b.pad_dofs is not None else 0.0 for b in brg]] * ns).reshape(
            ns, len(brg)
        ),
        "bm": np.zeros((ns, len(brg), nm, 2)),
        "sep": np.zeros((ns, nm)),
        "back": np.zeros((ns, nm)),
        "dte_lin": np.zeros((ns, nm)),
        "conv": np.ones(ns, bool),
    }
    solved: list[tuple[float, NDArray]] = []  # (speed, δ̂) converged along the sweep
    sys0 = system
    growth = np.full(len(speeds), np.nan)
    order = np.argsort(speeds)
    if sweep == "down":
        order = order[::-1]
    for i_s in order:
        speed = speeds[i_s]
        sysw = sys0.at_speed(float(speed))
        rates = sysw.mesh_rates()
        if np.any(rates == 0):
            raise ModelError("a gear of a mesh does not turn at this speed", field="speed")
        T = _common_period([abs(x) for x in rates])
        Wp = 2 * np.pi / T
        mk = np.round(rates / Wp).astype(int)  # mesh rate in units of Ω_p (signed)
        H = S * int(np.abs(mk).max())
        nh = 2 * H + 1
        M, K, C = sysw.linear_matrices(meshes=False)
        Cg = C + sysw.gyroscopic()
        Kbar = K.copy()
        for law, Wk in zip(laws, Wsp, strict=True):
            Kbar = Kbar + law.kg * Wk.toarray()
            Cg = Cg + law.damping * Wk.toarray()
        Ms, Ks, Cs = sp.csr_array(M), sp.csr_array(Kbar), sp.csr_array(Cg)
        hidx = np.arange(-H, H + 1)
        # the periodic part: Σ_k Σ_{s≠0} k_s W_k at block offset s m_k
        P = sp.csr_array((nh * n, nh * n), dtype=complex)
        for k in range(nm):
            for s in range(-S, S + 1):
                j = s * mk[k]
                if s == 0 or abs(j) > 2 * H or abs(khat[k][s + S]) == 0:
                    continue
                shift = sp.eye(nh, k=-j, dtype=complex, format="csr")
                P = P + sp.kron(shift, khat[k][s + S] * Wsp[k], format="csr")
        # the speed-dependent torques (load ∝ Ω^p)
        f0 = f_static.copy()
        for j, tq in enumerate(train.torques):
            if tq.speed_exponent:
                sh = sysw.shaft_of_row[sysw.torque_dof[j]]
                f0[sysw.torque_dof[j]] *= (
                    abs(sysw.nominal_speeds[sh]) / tq.reference_speed
                ) ** tq.speed_exponent
        rigid = np.linalg.norm(Kbar @ r) <= 1e-9 * np.abs(Kbar).max() * np.linalg.norm(r)

        hb = _Blocks(Ks, Ms, Cs, P, hidx, Wp, H, M @ r, float(speed))

        def solve(nu: float, F: NDArray, border: bool, hb: _Blocks = hb) -> NDArray:
            return _solve(hb, nu, F, border)

        solve_mesh = _factor(hb, 0.0, rigid)

        # ---- mesh family --------------------------------------------------------------------
        om0 = hidx * Wp
        F = np.zeros((nh, n), complex)
        F[H] += f0
        for k in range(nm):
            ke = np.convolve(khat[k], ehat[k])  # harmonics −2S..2S of k·e
            for s in range(-2 * S, 2 * S + 1):
                j = s * mk[k]
                if abs(j) > H:
                    continue
                val = ke[s + 2 * S]
                if abs(s) <= S:
                    val = val + 1j * om0[j + H] * laws[k].damping * ehat[k][s + S]
                F[j + H] += val * W[k]
                if nonlinear and abs(s) <= S:
                    # the drive-flank law k (δ − e − b): the backlash's offset
                    F[j + H] += khat[k][s + S] * backlash[k] * W[k]
        Q = solve_mesh(F)
        ns_t = samples or (32 if nonlinear else 16) * nh
        t = np.arange(ns_t) * T / ns_t
        E = np.exp(1j * np.outer(t, om0))  # (nt, nh)
        KT, ET, DET = np.zeros((nm, ns_t)), np.zeros((nm, ns_t)), np.zeros((nm, ns_t))
        for k in range(nm):
            kk = np.zeros(nh, complex)
            ee = np.zeros(nh, complex)
            for s in range(-S, S + 1):
                j = s * mk[k]
                if abs(j) <= H:
                    kk[j + H] += khat[k][s + S]
                    ee[j + H] += ehat[k][s + S]
            KT[k], ET[k] = np.real(E @ kk), np.real(E @ ee)
            DET[k] = np.real(E @ (1j * om0 * ee))
        contact = None
        if nonlinear:
            for k in range(nm):
                Dl = Q @ W[k]
                Dl[H] = 0
                out["dte_lin"][i_s, k] = np.sqrt(np.sum(np.abs(Dl) ** 2))
            guesses = [x for _, x in solved[-1:]]
            if len(solved) >= 2:
                (w1, x1), (w2, x2) = solved[-2:]
                guesses.insert(0, x2 + (x2 - x1) * (speed - w2) / (w2 - w1))
            contact = _contact_balance(
                solve_mesh, Q, W, KT, ET, DET, damping, backlash, E, om0, guesses
            )
            out["conv"][i_s] = contact.converged
            out["sep"][i_s] = contact.separated
            out["back"][i_s] = contact.back
            if contact.converged:
                solved.append((float(speed), contact.x))
            Q = contact.Q
        for k in range(nm):
            D = Q @ W[k]  # (nh,) harmonics of δ
            if contact is not None:
                force = contact.force[k]
            else:
                delta = np.real(E @ D)
                ddelta = np.real(E @ (1j * om0 * D))
                kt, et, det = KT[k], ET[k], DET[k]
                force = kt * (delta - et) + laws[k].damping * (ddelta - det)
            out["F0"][i_s, k] = force.mean()
            out["Fmax"][i_s, k] = force.max()
            out["Fmin"][i_s, k] = force.min()
            Dn = D.copy()
            Dn[H] = 0
            out["dte"][i_s, k] = np.sqrt(np.sum(np.abs(Dn) ** 2))
            out["freq"][i_s, k] = abs(rates[k])
            for p, (ix, iy) in enumerate(probe_idx):
                cx, cy = probe_dir[p]
                for order in (1, 2):
                    j = order * mk[k]
                    if abs(j) > H:
                        continue
                    X = Q[j + H, ix] if ix >= 0 else 0.0
                    Y = Q[j + H, iy] if iy >= 0 else 0.0
                    out["pm"][i_s, p, k, order - 1] = 2 * abs(cx * X + cy * Y)
            for b, info in enumerate(brg):
                if info.pad_dofs is not None:
                    continue
                spd = sysw.nominal_speeds[info.shaft]
                for order in (1, 2):
                    j = order * mk[k]
                    if abs(j) > H:
                        continue
                    qg = np.zeros(asm.n_dof, complex)
                    qg[sysw.active] = Q[j + H]
                    f = info.journal_force(qg, 1j * om0[j + H] * qg, spd)
                    out["bm"][i_s, b, k, order - 1] = 2 * _ellipse_major(f[0], f[1])
        dte2 = out["dte"][i_s] ** 2

        # ---- unbalance families (one per distinct shaft speed) ------------------------------
        if unbalance and len(sysw.unbalance_me):
            shaft_speed = sysw.nominal_speeds
            fam: dict[float, list[int]] = {}
            for u in range(len(sysw.unbalance_me)):
                sh = sysw.shaft_of_row[sysw.unbalance_dofs[u, 0]]
                key = round(abs(float(shaft_speed[sh])), 9)  # shafts at the same |speed|
                fam.setdefault(key, []).append(u)
            for nu, members in fam.items():
                F = np.zeros((nh, n), complex)
                for u in members:
                    om_s = shaft_speed[sysw.shaft_of_row[sysw.unbalance_dofs[u, 0]]]
                    me = sysw.unbalance_me[u]
                    ph = sysw.unbalance_phase[u]
                    dx, dy, _ = sysw.unbalance_dofs[u]
                    if om_s > 0:
                        F[H, dx] += me * om_s**2 * np.exp(1j * ph)
                        F[H, dy] += -1j * me * om_s**2 * np.exp(1j * ph)
                    else:
                        F[H, dx] += me * om_s**2 * np.exp(-1j * ph)
                        F[H, dy] += 1j * me * om_s**2 * np.exp(-1j * ph)
                Qu = solve(nu, F, False)
                for k in range(nm):
                    dte2[k] += 0.5 * np.sum(np.abs(Qu @ W[k]) ** 2)
                for p, (ix, iy) in enumerate(probe_idx):
                    if round(abs(float(shaft_speed[probe_shaft[p]])), 9) != nu:
                        continue
                    cx, cy = probe_dir[p]
                    X = Qu[H, ix] if ix >= 0 else 0.0
                    Y = Qu[H, iy] if iy >= 0 else 0.0
                    out["p1"][i_s, p] = abs(cx * X + cy * Y)
                for b, info in enumerate(brg):
                    spd = sysw.nominal_speeds[info.shaft]
                    if info.pad_dofs is not None or round(abs(float(spd)), 9) != nu:
                        continue
                    qg = np.zeros(asm.n_dof, complex)
                    qg[sysw.active] = Qu[H]
                    f = info.journal_force(qg, 1j * nu * qg, spd)
                    out["b1"][i_s, b] = _ellipse_major(f[0], f[1])
        out["dte_tot"][i_s] = np.sqrt(dte2)
        if stability:
            from .floquet import floquet

            try:
                fl = floquet(sysw)
            except ModelError as exc:
                if exc.field != "cutoff":
                    raise
                # no elastic mode below 2.5x the mesh frequency (a low speed): none the mesh
                # pumps into a combination resonance of its first harmonics
                growth[i_s] = 0.0
            else:
                growth[i_s] = fl.growth[0] if fl.growth[0] > fl.neutral_tolerance else 0.0

    with np.errstate(divide="ignore", invalid="ignore"):
        dyn = np.where(out["F0"] > 0, out["Fmax"] / out["F0"], np.nan)
    loss = (out["sep"] > 0) | (out["back"] > 0) if nonlinear else out["Fmin"] < 0
    unstable = growth > 0
    if unstable.any() and nonlinear:
        notes.append(
            f"the equations with the teeth in contact are parametrically unstable at "
            f"{int(unstable.sum())} of {ns} speeds (Floquet growth up to "
            f"{np.nanmax(growth):.4g} 1/s): the nonlinear solution there is bounded by the "
            "separation; its own stability is not checked (the transient)"
        )
    elif unstable.any():
        notes.append(
            f"parametrically unstable at {int(unstable.sum())} of {ns} speeds (Floquet growth "
            f"up to {np.nanmax(growth):.4g} 1/s): there a free vibration grows and the periodic "
            "response is not what the train does (gearrotor floquet; the transient)"
        )
    if nonlinear and loss.any():
        notes.append(
            f"teeth separate at {int(loss.any(axis=1).sum())} of {ns} speeds (up to "
            f"{100 * out['sep'].max():.3g} % of the mesh period apart"
            + (f", {100 * out['back'].max():.3g} % on the back flank" if out["back"].any() else "")
            + "): the nonlinear periodic solution with the backlash law (harmonic balance, "
            "continued along the sweep: where two solutions coexist it follows one branch)"
        )
    if nonlinear and not out["conv"].all():
        notes.append(
            f"the nonlinear harmonic balance did not converge at {int((~out['conv']).sum())} "
            "speeds (their numbers are Newton's best iterate; more harmonics, or the transient)"
        )
    if nonlinear and unbalance:
        notes.append("nonlinear: the unbalance response is linear, added to the DTE (total)")
    if not nonlinear and loss.any():
        notes.append(
            f"contact loss at {int(loss.any(axis=1).sum())} of {ns} speeds (the mesh force "
            "falls below zero): the teeth separate there and the linear periodic response does "
            "not hold; run the transient with backlash at those speeds"
        )
    if any(b.pad_dofs is not None for b in brg):
        notes.append("bearings with pad dynamics: their dynamic forces are not reported")
    for k in np.flatnonzero(np.isfinite(op_force)):
        ratio = float(np.nanmedian(out["F0"][:, k]) / op_force[k])
        if abs(ratio - 1) > 0.01:
            notes.append(
                f"{laws[k].name}: the mean mesh force is {ratio:.3g} times the load its tooth "
                "geometry's curves were computed for (set the pair's 'torque' to the load)"
            )
    return MeshResponseResult(
        speed=speeds,
        meshes=tuple(law.name for law in laws),
        mesh_frequency=out["freq"],
        static_force=out["F0"],
        force_max=out["Fmax"],
        force_min=out["Fmin"],
        dynamic_factor=dyn,
        contact_loss=loss,
        dte_rms=out["dte"],
        dte_rms_total=out["dte_tot"],
        probes=tuple(p.name for p in probes),
        probe_1x=out["p1"],
        probe_mesh=out["pm"],
        bearings=tuple(b.name for b in brg),
        bearing_1x=out["b1"],
        bearing_mesh=out["bm"],
        operating_force=op_force,
        floquet_growth=growth,
        nonlinear=nonlinear,
        separation_fraction=out["sep"] if nonlinear else None,
        back_contact_fraction=out["back"] if nonlinear else None,
        dte_rms_linear=out["dte_lin"] if nonlinear else None,
        converged=out["conv"] if nonlinear else None,
        iso_kv=iso_kv,
        iso_resonance_speed=iso_res,
        harmonics=S,
        notes=tuple(notes),
        laws=tuple(kinds),
    )
