"""Time integrators of the transient and the :func:`transient` driver (SPEC 2.6).

Contract of an integrator option object (:class:`RK4`, :class:`ModalRK4`): it is frozen data;
:func:`transient` prepares the compiled kernel's arrays from it once, then advances the state in
chunks (progress, checkpoints) with a fixed step ``dt``. Work is counted: ``steps`` and
``rhs_evaluations`` (4 per RK4 step) are reported in :class:`~.results.SolverStats`.

* :class:`RK4` — classical fixed-step 4th-order Runge–Kutta on the first-order state
  (q, q̇) of the full (active-DOF) model: the reference. Explicit, so every eigenvalue λ of the
  model linearised at the nominal speeds must satisfy ``|R(λ Δt)| ≤ 1``,
  ``R(z) = 1 + z + z²/2 + z³/6 + z⁴/24`` (``ω Δt ≤ 2√2`` for an undamped mode,
  ``|λ| Δt ≤ 2.785`` for an overdamped one: heavily damped journals of tilting-pad bearings
  can set the limit); this is checked before the run and a step that violates it raises
  :class:`~gearrotor.errors.SolverError` with the largest stable step (:func:`rk4_max_step`).
* :class:`ModalRK4` — the same RK4 on a modal reduction: the undamped modes of the
  constant-speed linear model (meshes at Kg, bearings at the nominal speeds) up to a cut-off
  frequency, always including the rigid-body rotation, so θz stays the absolute angle. Damping,
  gyroscopics (Σ Ω_s(t) Φᵀ G_s Φ), the angular-acceleration and unbalance θ̈ terms (exact
  Woodbury solve with M_r = I) and every nonlinear force (mesh minus its Kg part, unbalance,
  torques, speed-dependent bearings) are evaluated through the rows Φ_sel of the DOFs they act
  on. The modes are those of the symmetric part of K; its skew part (cross-coupled bearings,
  seals) acts through the rows of its DOFs too. Dropping the modes above the cut-off removes
  the stiff shear/axial modes, so the step is set by accuracy, not by stability (the same
  stability check applies to the reduced system).

Divergence (non-finite state, or a lateral displacement above ``blowup`` m / torsional deviation
above 1 rad from rigid rotation) stops the run with a SolverError that names the time.
"""

from __future__ import annotations

import hashlib
import os
import sys
import time as _time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components

from ...assembly import Assembly
from ...errors import ModelError, SolverError
from ...model import Train
from . import kernels as kn
from .equations import TransientSystem, build_system, static_state

if TYPE_CHECKING:
    from .results import TransientResult

__all__ = ["RK4", "ModalRK4", "Save", "Checkpoint", "transient", "rk4_max_step"]


@dataclass(frozen=True)
class RK4:
    """Classical RK4 on the full active-DOF model. dt : s (at most :func:`rk4_max_step`).
    ``check_stability`` checks the eigenvalues of the linearised model against RK4's
    stability region before the run (raises SolverError when a step is outside)."""

    dt: float
    check_stability: bool = True
    name: str = field(default="rk4", init=False)


@dataclass(frozen=True)
class ModalRK4:
    """RK4 on the modal reduction of the linear part.

    dt : s (default: ``accuracy / ω_k``, ω_k the highest kept mode, or 0.95× the reduced
    system's stability limit when its damped eigenvalues set a smaller one); cutoff : Hz, keep
    the undamped modes up to this frequency (default: ``cutoff_factor`` × the highest excitation
    frequency, which is the highest mesh frequency |N Ω| or, without meshes, 10× the highest
    shaft speed); accuracy : ω_k·dt of the default step; separated_modes : also include the
    modes of the train with the meshes removed (each shaft free, with its rigid rotation) up to
    the cut-off, so that teeth separation (backlash) is represented; the combined basis is
    re-diagonalised (Ritz) on the engaged model. Default: when a mesh has backlash;
    static_correction : add the static deflection shapes under each mesh's normal force and
    each external torque (the modes alone miss much of the mesh compliance, ~20 % for SPEC 6.1,
    so a transmitted torque would load the mesh wrongly); this raises the highest Ritz
    frequency (≈ 9 kHz for SPEC 6.1) and so shortens the default step. Default: when the model
    has external torques; tolerance : without an explicit ``cutoff``, the cut-off is raised
    (×1.25 at a time) until the reduced model's linear 1x unbalance response at the recorded
    lateral DOFs is within ``tolerance`` (relative to its largest amplitude) of the full
    model's; the achieved value is reported as ``stats.harmonic_error``.

    The defaults (1.25, 0.9) were measured on the SPEC 6.1 gearbox against RK4
    (benchmarks/transient_app2.py): 1x within 0.5 %, speed fluctuation within 0.5 %.
    """

    dt: float | None = None
    cutoff: float | None = None
    cutoff_factor: float = 1.25
    accuracy: float = 0.9
    separated_modes: bool | None = None
    static_correction: bool | None = None
    tolerance: float = 0.005
    name: str = field(default="modal-rk4", init=False)


@dataclass(frozen=True)
class Save:
    """What to record: every ``dt`` seconds (default: 4 samples per period of the highest
    mesh frequency, or 64 per revolution without meshes); ``full_state`` records every active
    DOF (for checks; memory grows with the model)."""

    dt: float | None = None
    full_state: bool = False


@dataclass(frozen=True)
class Checkpoint:
    """Write the state to ``path`` every ``every`` seconds of wall time (atomic replace) and
    resume from it when it exists and matches the run (model, method, step)."""

    path: Path
    every: float = 60.0


# ------------------------------------------------------------------------------------------
def _mass_factor(M: sp.csr_array) -> tuple[NDArray, ...]:
    """Sparse Cholesky factor of M, block by block (M's connected components, each banded in
    node order): returns perm, L (CSR, diagonal last in each row), U = Lᵀ (CSR, diagonal first),
    with ``M[perm][:, perm] = L Lᵀ``, and the component label of every DOF."""
    nb, labels = connected_components(M, directed=False)
    perm = np.argsort(labels, kind="stable")
    counts = np.bincount(labels, minlength=nb)
    ptr = np.concatenate([[0], np.cumsum(counts)])
    Md = M.toarray()
    L = np.zeros((M.shape[0], M.shape[0]))
    for b in range(nb):
        idx = perm[ptr[b] : ptr[b + 1]]
        try:
            L[ptr[b] : ptr[b + 1], ptr[b] : ptr[b + 1]] = la.cholesky(
                Md[np.ix_(idx, idx)], lower=True
            )
        except la.LinAlgError:
            raise ModelError(
                "the mass matrix is not positive definite on some DOFs (a node "
                "without mass or inertia?)"
            ) from None
    Ls = sp.csr_array(L)
    Ls.sort_indices()
    Us = sp.csr_array(L.T)
    Us.sort_indices()
    return (
        perm.astype(np.int64),
        Ls.indptr.astype(np.int64),
        Ls.indices.astype(np.int64),
        Ls.data.copy(),
        Us.indptr.astype(np.int64),
        Us.indices.astype(np.int64),
        Us.data.copy(),
        labels,
    )


def _csr(A: sp.csr_array) -> tuple[NDArray, NDArray, NDArray]:
    A = sp.csr_array(A)
    A.sort_indices()
    return A.indptr.astype(np.int64), A.indices.astype(np.int64), A.data.astype(float)


def _output_dofs(system: TransientSystem, full_state: bool) -> NDArray:
    """Active indices recorded: gear nodes, probes, unbalances, bearings, couplings, torques."""
    if full_state:
        return np.arange(system.n, dtype=np.int64)
    asm, train = system.assembly, system.train
    glob = []
    for m in asm.meshes:
        glob.extend(m.dofs)
    for b in asm.bearings:
        glob.extend(b.dofs)
        if b.support_dofs is not None:
            glob.extend(b.support_dofs)
    for group, prefix in (
        (train.unbalances, "unbalances"),
        (train.probes, "probes"),
        (train.torques, "torques"),
    ):
        for k, it in enumerate(group):
            si, node = train.node_index(it, f"{prefix}[{k}]")
            glob.extend(asm.node_offset[si][node] + np.arange(6))
    for k, c in enumerate(train.couplings):
        for ref, nm in ((c.node_i, "node_i"), (c.node_j, "node_j")):
            si, node = train.node_index(ref, f"couplings[{k}].{nm}")
            glob.extend(asm.node_offset[si][node] + np.arange(6))
    idx = {system.index(int(g)) for g in glob}
    idx.discard(-1)
    return np.array(sorted(idx), dtype=np.int64)


def _pack_forces(system: TransientSystem, sel: NDArray, *, modal: bool, bearing_ref: bool) -> tuple:
    """Parameter arrays of :func:`kernels.nl_forces` with indices into ``sel``."""
    loc = -np.ones(system.n + 1, np.int64)
    loc[sel] = np.arange(len(sel))

    def at(idx):
        idx = np.asarray(idx, np.int64)
        return np.where(idx >= 0, loc[np.where(idx >= 0, idx, system.n)], -1)

    laws = system.meshes
    nm = len(laws)
    S = max([len(law.coef_a) for law in laws] + [1])
    Se = max([len(law.te) for law in laws] + [1])
    m_sel = np.array([at(d) for d in system.mesh_dofs], np.int64).reshape(nm, 12)
    m_w = np.array([[law.w, law.w_back] for law in laws], float).reshape(nm, 2, 12)
    m_par = np.array(
        [
            [law.kg, law.ka, law.backlash, law.damping, law.teeth, law.kg if modal else 0.0, 0.0]
            for law in laws
        ],
        float,
    ).reshape(nm, 7)
    m_ab = np.zeros((nm, S, 2))
    m_ns = np.zeros(nm, np.int64)
    m_te = np.zeros((nm, Se, 2))
    m_nte = np.zeros(nm, np.int64)
    tptr = [0]
    tphi, tk = [], []
    for k, law in enumerate(laws):
        m_ab[k, : len(law.coef_a), 0] = law.coef_a
        m_ab[k, : len(law.coef_b), 1] = law.coef_b
        m_ns[k] = len(law.coef_a)
        m_te[k, : len(law.te)] = law.te
        m_nte[k] = len(law.te)
        tphi.append(law.table_phi)
        tk.append(law.table_k)
        tptr.append(tptr[-1] + len(law.table_phi))
    mesh = (
        m_sel,
        m_w,
        m_par,
        m_ab,
        m_ns,
        np.array(tptr, np.int64),
        np.concatenate(tphi + [np.zeros(1)]),
        np.concatenate(tk + [np.zeros(1)]),
        m_te,
        m_nte,
    )
    u_sel = np.array([at(d) for d in system.unbalance_dofs], np.int64).reshape(-1, 3)
    unb = (u_sel, system.unbalance_me.astype(float), system.unbalance_phase.astype(float))
    train = system.train
    t_par, t_ptr, t_time, t_vals = [], [0], [], []
    for tq in train.torques:
        t_par.append([tq.value, tq.speed_exponent, tq.reference_speed or 1.0])
        if tq.time is not None:
            t_time.extend(tq.time)
            t_vals.extend(tq.values)
        t_ptr.append(len(t_time))
    torq = (
        at(system.torque_dof).astype(np.int64),
        np.array(t_par, float).reshape(-1, 3),
        np.array(t_ptr, np.int64),
        np.array(t_time + [0.0], float),
        np.array(t_vals + [0.0], float),
    )
    b_sel, b_shaft, b_ptr, b_speed, b_coef, b_ref = [], [], [0], [], [], []
    for j, info in enumerate(system.assembly.bearings):
        if not system.bearing_dynamic[j]:
            continue
        tab = info.element.table
        b_sel.append(at(system.bearing_dofs[j]))
        b_shaft.append(system.bearing_shaft[j])
        b_speed.extend(tab.speed)
        b_coef.append(np.asarray(tab.values, float))
        b_ptr.append(len(b_speed))
        b_ref.append(
            info.element.coefficients(system.nominal_speeds[system.bearing_shaft[j]])
            if bearing_ref
            else np.zeros(8)
        )
    brg = (
        np.array(b_sel, np.int64).reshape(-1, 4),
        np.array(b_shaft, np.int64),
        np.array(b_ptr, np.int64),
        np.array(b_speed + [0.0], float),
        np.concatenate(b_coef + [np.zeros((1, 8))]),
        np.array(b_ref, float).reshape(-1, 8),
    )
    return mesh + unb + torq + brg


def _force_dofs(system: TransientSystem) -> NDArray:
    idx = set(system.mesh_dofs[system.mesh_dofs >= 0].tolist())
    idx |= set(system.unbalance_dofs.ravel().tolist())
    idx |= set(system.torque_dof.tolist())
    for j in range(len(system.bearing_dofs)):
        if system.bearing_dynamic[j]:
            idx |= set(system.bearing_dofs[j][system.bearing_dofs[j] >= 0].tolist())
    idx.discard(-1)
    return np.array(sorted(idx), dtype=np.int64)


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


def excitation_frequency(system: TransientSystem) -> float:
    """Highest excitation frequency (rad/s): mesh frequency |N_i Ω_i|, else 10× shaft speed."""
    if system.meshes:
        return float(np.abs(system.mesh_rates()).max())
    return 10.0 * float(np.max(np.abs(system.nominal_speeds)))


# ------------------------------------------------------------------------------------------
@dataclass
class _Prepared:
    kind: str
    dt: float
    n_state: int
    P: tuple
    W: tuple
    K1: tuple
    out: NDArray  # active output DOFs
    Phi_out: NDArray | None
    info: dict


def _unstable_step(what: str, dt: float, limit: float, lam: complex, fix: str) -> SolverError:
    zeta = -lam.real / abs(lam)
    return SolverError(
        f"{what} step dt = {dt:.4g} s is outside RK4's stability region for the eigenvalue "
        f"λ = {lam.real:.4g} ± {abs(lam.imag):.4g}i 1/s of the model linearised at the nominal "
        f"speeds ({abs(lam.imag) / 2 / np.pi:.5g} Hz, damping ratio {zeta:.3g}; |λ|·dt = "
        f"{abs(lam) * dt:.3f}); use dt ≤ {0.99 * limit:.4g} s{fix}"
    )


def _prepare_physical(system: TransientSystem, integ: RK4, out: NDArray, frozen: bool) -> _Prepared:
    n = system.n
    sel = _force_dofs(system)
    G = sum((g for g in system.G), sp.csr_array((n, n)))
    *fac, comp = _mass_factor(system.M)
    if integ.check_stability:
        limit, lam = _rk4_step_limit(*_linearised(system))
        if integ.dt >= 0.995 * limit:
            raise _unstable_step(
                "RK4",
                integ.dt,
                limit,
                lam,
                ", or the modal integrator (ModalRK4), which drops the stiff modes",
            )
    ns = len(system.a_weights)
    a_idx, a_w, a_ptr = [], [], [0]
    for a in system.a_weights:
        nz = np.flatnonzero(a)
        a_idx.extend(nz)
        a_w.extend(a[nz])
        a_ptr.append(len(a_idx))
    Md = system.M.toarray()
    Minv_a = np.array([la.solve(Md, a, assume_a="pos") for a in system.a_weights]).reshape(ns, n)

    def minv_unit(col):
        e = np.zeros(n)
        e[col] = 1.0
        return la.solve(Md, e, assume_a="pos")

    ud = system.unbalance_dofs
    Minv_u = [np.array([minv_unit(d[c]) for d in ud]).reshape(-1, n) for c in range(3)]

    def support(dofs):
        return np.flatnonzero(np.isin(comp, np.unique(comp[np.asarray(dofs, int)])))

    g_rows = [np.flatnonzero(np.diff(sp.csr_array(g).indptr) > 0) for g in system.G]
    z_sup = []
    for s in range(ns):
        z_sup.append(support(g_rows[s]) if len(g_rows[s]) else np.zeros(0, int))
        z_sup.append(support(np.flatnonzero(system.a_weights[s])))
    for d in ud:
        z_sup.append(support(d[:2]))
        z_sup.append(support(d[2:]))
    if not system.reactions:
        z_sup = z_sup[0::2]
    z_ptr = np.concatenate([[0], np.cumsum([len(z) for z in z_sup])]).astype(np.int64)
    z_idx = np.concatenate(z_sup + [np.zeros(0, int)]).astype(np.int64)
    g_ptr = np.concatenate([[0], np.cumsum([len(g) for g in g_rows])]).astype(np.int64)
    g_idx = np.concatenate(g_rows + [np.zeros(0, int)]).astype(np.int64)
    P = (
        *_csr(system.K),
        *_csr(system.C),
        *_csr(G),
        system.shaft_of_row.astype(np.int64),
        *fac,
        np.array(a_idx, np.int64),
        np.array(a_w, float),
        np.array(a_ptr, np.int64),
        np.flatnonzero(system.torsion).astype(np.int64),
        bool(frozen),
        bool(system.reactions),
        sel,
        *_pack_forces(system, sel, modal=False, bearing_ref=False),
        Minv_a,
        *Minv_u,
        system.unbalance_dofs.astype(np.int64).reshape(-1, 3),
        z_ptr,
        z_idx,
        g_ptr,
        g_idx,
    )
    r = 2 * (ns + len(ud))
    W = (
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(len(sel)),
        np.zeros(len(sel)),
        np.zeros(len(sel)),
        np.zeros(ns),
        np.zeros((max(r, 1), n)),
        np.zeros((r, r)),
        np.zeros(r),
        np.zeros(r, np.int64),
        np.zeros(n),
    )
    K1 = tuple(np.zeros(n) for _ in range(10))
    return _Prepared("physical", integ.dt, n, P, W, K1, out, None, {"n_dof": n})


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


def _harmonic_error(system, M, K, C, Phi, w2r, out) -> float:
    """Largest relative error of the reduced model's linear 1x unbalance response at the
    recorded lateral DOFs (per distinct shaft speed), against the full model."""
    kind = system.assembly.dof_kind()[system.active]
    obs = out[kind[out] == 0]
    if not len(system.unbalance_dofs) or not len(obs):
        return 0.0
    G = system.gyroscopic()
    speeds = system.nominal_speeds
    err = 0.0
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
        X = la.solve(K - w**2 * M + 1j * w * (C + G), F)[obs]
        A = (
            np.diag(w2r)
            + Phi.T @ (0.5 * (K - K.T)) @ Phi
            - w**2 * np.eye(len(w2r))
            + 1j * w * (Phi.T @ (C + G) @ Phi)
        )
        Xr = Phi[obs] @ la.solve(A, Phi.T @ F)
        err = max(err, float(np.abs(Xr - X).max() / np.abs(X).max()))
    return err


def _prepare_modal(system: TransientSystem, integ: ModalRK4, out: NDArray) -> _Prepared:
    M, K, C = system.linear_matrices()
    # modes of the symmetric part of K; its skew part (cross-coupled bearings and seals) acts
    # as a force on its few DOFs (kernel: k_idx, k_skew)
    Ks = 0.5 * (K + K.T)
    Ka = K - Ks
    w2, V = la.eigh(Ks, M)
    om_all = np.sqrt(np.clip(w2, 0.0, None))
    wcut = (
        2 * np.pi * integ.cutoff
        if integ.cutoff is not None
        else (integ.cutoff_factor * excitation_frequency(system))
    )
    separated = integ.separated_modes
    if separated is None:
        separated = any(law.backlash > 0 for law in system.meshes)
    if separated and system.meshes:
        _, Kf, _ = system.linear_matrices(meshes=False)
        separated = la.eigh(0.5 * (Kf + Kf.T), M)
    else:
        separated = None
    static = integ.static_correction
    if static is None:
        static = len(system.torque_dof) > 0
    shapes = _static_shapes(system, M, K) if static else np.zeros((system.n, 0))
    Phi, w2r = _modal_basis(M, Ks, V, w2, wcut, separated, shapes)
    check = _harmonic_error(system, M, K, C, Phi, w2r, out)
    while integ.cutoff is None and check > integ.tolerance and wcut < om_all.max():
        wcut *= 1.25
        Phi, w2r = _modal_basis(M, Ks, V, w2, wcut, separated, shapes)
        check = _harmonic_error(system, M, K, C, Phi, w2r, out)
    if integ.cutoff is None and check > integ.tolerance:
        raise SolverError(
            f"the modal reduction cannot reach the requested 1x accuracy: with every mode "
            f"kept the reduced model's linear unbalance response is {check:.3g} off the full "
            f"model's (tolerance {integ.tolerance:g}); use the RK4 method"
        )
    lam = np.clip(w2r, 0.0, None)
    om = np.sqrt(lam)
    lam[om < 1e-6 * max(om.max(), 1.0)] = 0.0  # rigid-body modes exactly
    m = Phi.shape[1]
    limit, lam_lim = _rk4_step_limit(
        np.eye(m), np.diag(lam) + Phi.T @ Ka @ Phi, Phi.T @ _linearised(system)[2] @ Phi
    )
    dt = integ.dt
    if dt is None:
        dt = min(integ.accuracy / max(float(om.max()), 1e-9), 0.95 * limit)
    if dt >= 0.995 * limit:
        raise _unstable_step("modal RK4", dt, limit, lam_lim, " or lower the cut-off")
    k_dofs = np.flatnonzero(np.any(Ka != 0, axis=1))
    sel = np.union1d(_force_dofs(system), k_dofs).astype(np.int64)
    Cr = Phi.T @ C @ Phi
    Gr = np.array([Phi.T @ g.toarray() @ Phi for g in system.G]).reshape(-1, m, m)
    alpha = np.array([Phi.T @ a for a in system.a_weights])  # Ω_s = a_sᵀ Φ η̇
    ns = len(system.a_weights)
    nu = len(system.unbalance_dofs)
    r = 2 * (ns + nu)
    P = (
        lam,
        np.ascontiguousarray(Cr),
        np.ascontiguousarray(Gr),
        np.ascontiguousarray(alpha),
        np.ascontiguousarray(Phi[sel]),
        np.ascontiguousarray(Phi[sel].T),
        bool(system.reactions),
        np.searchsorted(sel, k_dofs).astype(np.int64),
        np.ascontiguousarray(Ka[np.ix_(k_dofs, k_dofs)]),
        *_pack_forces(system, sel, modal=True, bearing_ref=True),
    )
    W = (
        np.zeros(len(sel)),
        np.zeros(len(sel)),
        np.zeros(len(sel)),
        np.zeros(ns),
        np.zeros((2 * max(r, 1), m)),
        np.zeros((r, r)),
        np.zeros(r),
        np.zeros(r, np.int64),
        np.zeros((ns, m)),
    )
    K1 = tuple(np.zeros(m) for _ in range(10))
    info = {
        "n_modes": m,
        "cutoff_hz": wcut / 2 / np.pi,
        "harmonic_error": check,
        "highest_mode_hz": float(om.max() / 2 / np.pi),
        "Phi": Phi,
        "M": M,
    }
    return _Prepared("modal", dt, m, P, W, K1, out, np.ascontiguousarray(Phi[out]), info)


def _fingerprint(train: Train, kind: str, dt: float, extra: str) -> str:
    h = hashlib.sha256()
    h.update(train.model_dump_json().encode())
    h.update(f"{kind}|{dt!r}|{extra}".encode())
    return h.hexdigest()


def _write_npz_atomic(path: Path, **arrays) -> None:
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
    os.replace(tmp, path)


def _warn_rotating_damping_speed(system: TransientSystem, speeds: NDArray) -> None:
    """Warn when a shaft with rotating material damping strayed more than 2 % from its
    nominal speed: its circulatory stiffness is applied at the nominal speed."""
    for s, kc in enumerate(system.Kc):
        nominal = abs(float(system.nominal_speeds[s]))
        if not kc.nnz or not len(speeds):
            continue
        dev = float(np.max(np.abs(np.abs(speeds[:, s]) - nominal))) / max(nominal, 1e-12)
        if dev > 0.02:
            warnings.warn(
                f"shaft {system.train.shafts[s].name!r} has rotating material damping, whose "
                f"circulatory stiffness the transient applies at the nominal speed, and its speed "
                f"departed from it by up to {100 * dev:.3g} %: that term is off by as much "
                "(docs/transient.md)",
                stacklevel=3,
            )


def transient(
    model: Train | Assembly,
    *,
    t_end: float,
    integrator: RK4 | ModalRK4 | None = None,
    save: Save | None = None,
    frozen_speed: bool = False,
    reactions: bool = True,
    initial_q: NDArray | None = None,
    initial_qdot: NDArray | None = None,
    initial: str = "zero",
    stiffness_tables: dict[int, tuple[NDArray, NDArray]] | None = None,
    transmission_error: dict[int, NDArray] | None = None,
    back_flank: str = "same",
    blowup: float = 0.05,
    progress: bool = False,
    checkpoint: Checkpoint | None = None,
) -> TransientResult:
    """Nonlinear transient of a train from t = 0 to ``t_end`` (s).

    Parameters
    ----------
    model : Train or its Assembly
    t_end : s
    integrator : :class:`ModalRK4` (fast, the default ``ModalRK4()``) or :class:`RK4` (reference)
    save : what to record (:class:`Save`)
    frozen_speed : keep every θz at nominal rigid rotation (constant speed, SPEC's linear case)
    reactions : include the reaction torques of the gyroscopic and unbalance θ̈ terms (the
        Lagrangian, energy-consistent form); False gives the dissertation's form
    initial : ``"zero"`` displacement, or ``"static"``: the static deflection under the external
        torques at t = 0 (:func:`.equations.static_state`)
    initial_q, initial_qdot : (n_dof,) global perturbations added to the initial displacement and
        the nominal speeds (m, rad, m/s, rad/s)
    stiffness_tables, transmission_error : per mesh index, see :mod:`.mesh`
    back_flank : ``"same"`` (SPEC 2.4) or ``"mirrored"`` line of action for back-flank contact
    blowup : m, a displacement of a recorded non-torsional DOF beyond which the run is declared
        divergent (non-finite values always are)
    progress : print progress to stderr
    checkpoint : :class:`Checkpoint` for long runs (resume when the file matches)

    Returns a :class:`~.results.TransientResult`.
    """
    from .results import build_result

    setup0 = _time.perf_counter()

    if not (t_end > 0):
        raise ModelError("t_end must be positive", field="t_end", value=t_end, expected="> 0 s")
    integ = integrator if integrator is not None else ModalRK4()
    if isinstance(integ, RK4) and not integ.dt > 0:
        raise ModelError("the time step must be positive", field="dt", value=integ.dt)
    save = save or Save()
    system = build_system(
        model,
        frozen_speed=frozen_speed,
        reactions=reactions,
        initial_q=initial_q,
        stiffness_tables=stiffness_tables,
        transmission_error=transmission_error,
        back_flank=back_flank,
    )
    out = _output_dofs(system, save.full_state)
    if isinstance(integ, RK4):
        prep = _prepare_physical(system, integ, out, frozen_speed)
    elif isinstance(integ, ModalRK4):
        if frozen_speed:
            raise ModelError("frozen speed is available with RK4 only", field="frozen_speed")
        prep = _prepare_modal(system, integ, out)
    else:
        raise TypeError(f"unknown integrator {integ!r}; expected RK4(...) or ModalRK4(...)")
    dt = prep.dt
    n_steps = int(np.ceil(t_end / dt - 1e-9))
    fexc = excitation_frequency(system)
    save_dt = (
        save.dt
        if save.dt is not None
        else (2 * np.pi / (4 * fexc) if system.meshes else 2 * np.pi / (64 * fexc / 10))
    )
    save_every = max(1, int(round(save_dt / dt)))
    n_rec = n_steps // save_every + 1

    # initial state
    q0, v0 = system.initial_state()
    if initial == "static":
        q0 += static_state(system)[0]
    elif initial != "zero":
        raise ModelError(
            "unknown initial state", field="initial", value=initial, expected="'zero' or 'static'"
        )
    if initial_q is not None:
        q0 += np.asarray(initial_q, float)[system.active]
    if initial_qdot is not None:
        v0 += np.asarray(initial_qdot, float)[system.active]
    if prep.kind == "physical":
        q, v = q0, v0
    else:
        Phi, M = prep.info["Phi"], prep.info["M"]
        q = Phi.T @ (M @ q0)
        v = Phi.T @ (M @ v0)
    nout = len(out)
    ns = len(system.a_weights)
    rec_q = np.zeros((n_rec, nout))
    rec_v = np.zeros((n_rec, nout))
    rec_a = np.zeros((n_rec, nout))
    rec_om = np.zeros((n_rec, ns))
    rec_t = np.zeros(n_rec)
    # divergence scale per output DOF: lateral → 1/blowup, torsional deviation → 1 rad
    kind = system.assembly.dof_kind()[system.active[out]]
    scale = np.where(kind == 2, 0.0, 1.0 / blowup)

    step0 = 0
    fp = _fingerprint(
        system.train,
        prep.kind,
        dt,
        f"{t_end}|{save_every}|{frozen_speed}|{reactions}|{integ!r}|{initial}|{back_flank}",
    )
    if checkpoint is not None and Path(checkpoint.path).exists():
        with np.load(checkpoint.path, allow_pickle=False) as ck:
            if str(ck["fingerprint"]) == fp:
                step0 = int(ck["step"])
                q, v = ck["q"].copy(), ck["v"].copy()
                nr = step0 // save_every
                rec_q[:nr], rec_v[:nr], rec_a[:nr] = ck["rec_q"], ck["rec_v"], ck["rec_a"]
                rec_om[:nr], rec_t[:nr] = ck["rec_om"], ck["rec_t"]
                if progress:
                    print(
                        f"resuming from {checkpoint.path} at t = {step0 * dt:.4g} s",
                        file=sys.stderr,
                    )
    chunk = save_every * max(1, int(0.05 / (dt * save_every)))  # ~0.05 s of simulated time
    wall0 = _time.perf_counter()
    setup = wall0 - setup0
    last_ck = wall0
    last_pr = wall0
    step = step0
    runner = kn.rk4_physical if prep.kind == "physical" else kn.rk4_modal
    out_arg = out if prep.kind == "physical" else prep.Phi_out
    while step < n_steps:
        nst = min(chunk, n_steps - step)
        status, done = runner(
            step * dt,
            dt,
            nst,
            q,
            v,
            save_every,
            out_arg,
            rec_q,
            rec_v,
            rec_a,
            rec_om,
            rec_t,
            step // save_every,
            scale,
            prep.P,
            prep.W,
            prep.K1,
        )
        if status != kn.STATUS_OK:
            t_bad = (step + done) * dt
            what = (
                "non-finite values"
                if status == kn.STATUS_NONFINITE
                else (f"a lateral displacement above {blowup} m")
            )
            raise SolverError(
                f"the transient diverged at t = {t_bad:.6g} s ({what}); likely causes: a step "
                f"too large for the integrator (dt = {dt:.3g} s), or an unstable mode of the "
                "train (negative damping, e.g. cross-coupling or a mesh parametric resonance); "
                "check modal() at the running speed and try a smaller dt"
            )
        step += nst
        now = _time.perf_counter()
        if progress and (now - last_pr > 2.0 or step == n_steps):
            frac = step / n_steps
            el = now - wall0
            eta = el / max(frac - step0 / n_steps, 1e-12) * (1 - frac)
            print(
                f"t = {step * dt:.4g}/{t_end:.4g} s ({100 * frac:.0f} %), {el:.1f} s elapsed, "
                f"~{eta:.1f} s left",
                file=sys.stderr,
            )
            last_pr = now
        if checkpoint is not None and (now - last_ck > checkpoint.every) and step < n_steps:
            nr = step // save_every
            _write_npz_atomic(
                Path(checkpoint.path),
                fingerprint=np.array(fp),
                step=step,
                q=q,
                v=v,
                rec_q=rec_q[:nr],
                rec_v=rec_v[:nr],
                rec_a=rec_a[:nr],
                rec_om=rec_om[:nr],
                rec_t=rec_t[:nr],
            )
            last_ck = now
    wall = _time.perf_counter() - wall0
    if checkpoint is not None and Path(checkpoint.path).exists():
        Path(checkpoint.path).unlink()
    nr = (n_steps - 1) // save_every + 1
    _warn_rotating_damping_speed(system, rec_om[:nr])
    stats = {
        "method": prep.kind if prep.kind == "physical" else "modal",
        "dt": dt,
        "steps": n_steps,
        "rhs_evaluations": 4 * (n_steps - step0),
        "wall_time_s": wall,
        "setup_time_s": setup,
        "save_every": save_every,
        **{k: v for k, v in prep.info.items() if k not in ("Phi", "M")},
    }
    final = (q.copy(), v.copy())
    if prep.kind == "modal":
        Phi = prep.info["Phi"]
        final = (Phi @ q, Phi @ v)
    return build_result(
        system,
        out,
        rec_t[:nr],
        rec_q[:nr],
        rec_v[:nr],
        rec_a[:nr],
        rec_om[:nr],
        stats=stats,
        final_state=final,
        name=integ.name,
        frozen=frozen_speed,
    )
