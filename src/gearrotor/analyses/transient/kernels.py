"""Compiled (numba) kernels of the transient: forces, accelerations, RK4 loops.

No objects but named tuples of arrays, which numba compiles as one argument each: a kernel's
signature names the physics it reads. Every work array is allocated by the caller once per
run, the step loops allocate nothing. Index conventions: force DOF indices address the vector
of DOFs that carry nonlinear forces (gathered from q, or from Φ_sel η); ``−1`` marks an
inactive DOF.

Cost of a pack: numba counts a reference (an atomic increment, and a decrement later) for
every array of a named tuple a compiled function is passed, used or not, and again when an
inlined function binds the pack to its own name; only some pairs are pruned. So the packs cross
few compiled calls per step: the force laws are inlined into :func:`nonlinear_forces` (one
compiled call per evaluation), the functions called per mesh take arrays. A compiled function
called from several kernels states its fastmath flags: numba compiles a callee without them
with the flags of its first caller, so results depended on which kernel was compiled first.
Against the former flat argument lists the runs cost the same (``benchmarks/kernels.py``;
compiling from an empty cache takes some 20 % more CPU: docs/performance.md).

The packs (built in Python by :mod:`.forces` and :mod:`.prepare`), one per law, each evaluated
by one function here:

* :class:`MeshLaws` — the meshes (SPEC 2.4): :func:`mesh_eval`, :func:`mesh_forces`;
* :class:`Unbalances` — the centrifugal part of the unbalances: :func:`unbalance_forces`;
* :class:`Torques` — external torques and constant loads: :func:`torque_forces`;
* :class:`BearingTables` — speed-dependent bearings: :func:`bearing_forces`;
* :class:`~..torsional.drive_laws.Drives` — the ``[torsional]`` drives and loads, the laws of
  the torsional transient: :func:`~..torsional.drive_laws.drive_torques`;

gathered in :class:`Forces` (:func:`nonlinear_forces`). The models they act in:
:class:`PhysicalModel` (the full model, RK4) and :class:`ModalModel` (the modal reduction),
with :class:`ContactOperators` for the exact-linear modal scheme; the runs record into a
:class:`Record`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ..csr import Csr, row_dot
from ..jit import configure_cache, kernel_only
from ..torsional.drive_laws import Drives, drive_torques

configure_cache()  # before the first @njit(cache=True): numba's cache outside the package

__all__ = [
    "MeshLaws",
    "Unbalances",
    "Torques",
    "BearingTables",
    "Forces",
    "MassFactor",
    "ImplicitTerms",
    "PhysicalModel",
    "ModalModel",
    "ContactOperators",
    "Record",
    "Stages",
    "Woodbury",
    "mesh_eval",
    "nonlinear_forces",
    "rk4_physical",
    "rk4_modal",
    "etd_modal",
    "etd_coefficients",
    "outputs_kernel",
    "STATUS_OK",
    "STATUS_NONFINITE",
    "STATUS_BLOWUP",
]

STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_BLOWUP = 2

_CACHE = True
# reassociation/contraction only: no 'nnan'/'ninf', so divergence checks stay valid
_FAST = {"reassoc", "contract", "arcp", "nsz"}
# the exponential scheme without 'reassoc': with it, the code numba compiled in a process and
# the code it loaded from its cache gave different round-off (1e-13 relative without backlash,
# ~1 % in the chaotic impact metrics with backlash), so a rerun did not reproduce a result
_FAST_ETD = _FAST - {"reassoc"}


# ------------------------------------------------------------------------------------------
# the packs
# ------------------------------------------------------------------------------------------
class MeshLaws(NamedTuple):
    """The meshes' laws (SPEC 2.4), nm meshes, on the force DOFs.

    dofs (nm, 12) int64: the 12 gear DOFs (x, y, z, θx, θy, θz of gear and mate; −1
    inactive); lines (nm, 2, 12): the drive line w (δ = w·q) and the back-flank line w_b;
    kg, ka, backlash b, damping c, teeth N (nm,): average stiffness, its variation's amplitude,
    the clearance, the damping, the pinion's teeth (mesh angle φ_m = N θz); kg_linear,
    kg_back_linear (nm,): the stiffness on the drive and back lines already in the linear part
    of the integrator (subtracted here); fourier (nm, S, 2), n_fourier (nm,): the variation's
    Fourier coefficients; table_ptr (nm + 1) into table_phi, table_k: a tabulated stiffness
    k(φ_m) (it replaces the series); te (nm, Se, 2), n_te (nm,): the transmission error's
    harmonics in φ_m; last (nm, 2) work: F_d − F_b (N) and the contact state of the latest
    evaluation (:func:`mesh_forces` writes it, the step envelope reads it at a step's start,
    :func:`_envelope`)."""

    dofs: NDArray
    lines: NDArray
    kg: NDArray
    ka: NDArray
    backlash: NDArray
    damping: NDArray
    teeth: NDArray
    kg_linear: NDArray
    kg_back_linear: NDArray
    fourier: NDArray
    n_fourier: NDArray
    table_ptr: NDArray
    table_phi: NDArray
    table_k: NDArray
    te: NDArray
    n_te: NDArray
    last: NDArray


class Unbalances(NamedTuple):
    """dofs (nu, 3) int64: x, y, θz of each unbalance's node; me (nu,) kg·m; phase (nu,)
    rad."""

    dofs: NDArray
    me: NDArray
    phase: NDArray


class Torques(NamedTuple):
    """External torques (and constant loads, as constant torques on their DOFs): dof (nt,);
    value (nt,) N·m (or N); speed law ``(|Ω_node| / reference_speed) ** speed_exponent``;
    a time table ``table_ptr`` (nt + 1) into ``time``, ``values`` (it replaces the value)."""

    dof: NDArray
    value: NDArray
    speed_exponent: NDArray
    reference_speed: NDArray
    table_ptr: NDArray
    time: NDArray
    values: NDArray


class BearingTables(NamedTuple):
    """Speed-dependent bearings: dofs (nb, 4) int64: journal x, y and pedestal x, y (−1:
    grounded); shaft (nb,): the shaft whose speed the table is read at; ``ptr`` (nb + 1) into
    ``speed`` and ``coef`` (·, 8): kxx, kxy, kyx, kyy, cxx, cxy, cyx, cyy over speed; ``ref``
    (nb, 8): the coefficients already in the linear part (subtracted)."""

    dofs: NDArray
    shaft: NDArray
    ptr: NDArray
    speed: NDArray
    coef: NDArray
    ref: NDArray


class Forces(NamedTuple):
    """Every nonlinear force of a run (:func:`nonlinear_forces`)."""

    meshes: MeshLaws
    unbalances: Unbalances
    torques: Torques
    bearings: BearingTables
    drives: Drives


class MassFactor(NamedTuple):
    """Sparse Cholesky factor of the permuted mass matrix ``M[perm][:, perm] = L Lᵀ`` (L rows:
    diagonal last; U = Lᵀ rows: diagonal first)."""

    perm: NDArray
    L: Csr
    U: Csr


class ImplicitTerms(NamedTuple):
    """The low-rank implicit part M + P Qᵀ of the physical model (the θ̈ coupling of the
    gyroscopic and unbalance terms, :func:`_accel_physical`): M⁻¹a_s (ns, n); M⁻¹ on the
    unbalances' x, y, θz unit vectors (nu, n) each; the unbalances' DOFs in the full state
    (nu, 3); the support of each row of Zᵀ = (M⁻¹P)ᵀ, ``z_ptr`` into ``z_idx``; the rows of
    each G_s, ``g_ptr`` into ``g_idx``."""

    Minv_a: NDArray
    Minv_ux: NDArray
    Minv_uy: NDArray
    Minv_ut: NDArray
    unbalance_dofs: NDArray
    z_ptr: NDArray
    z_idx: NDArray
    g_ptr: NDArray
    g_idx: NDArray


class PhysicalModel(NamedTuple):
    """The full active-DOF model: K, C, G = Σ G_s (:class:`~..csr.Csr`; G's rows scaled by the
    speed of the row's shaft ``row_shaft``, −1 none), the mass factor, the shaft speeds
    Ω_s = a_sᵀ q̇ (row s of ``speed_rows``), the θz DOFs ``torsion`` (held at frozen speed),
    ``frozen``, ``reactions`` (the θ̈ coupling terms), the force DOFs ``sel``, the forces and
    the implicit terms."""

    K: Csr
    C: Csr
    G: Csr
    row_shaft: NDArray
    mass: MassFactor
    speed_rows: Csr
    torsion: NDArray
    frozen: bool
    reactions: bool
    sel: NDArray
    forces: Forces
    implicit: ImplicitTerms


class ModalModel(NamedTuple):
    """The modal reduction (M_r = I): stiffness ``diag(lam)`` (the symmetric part) plus the
    skew part ``k_skew`` on the force DOFs ``k_idx`` (applied as a force); damping Cr (m, m);
    gyroscopics Gr (ns, m, m); shaft speeds Ω_s = alpha_s η̇ (ns, m); the force DOFs
    q_sel = Phi_sel η (and its transpose); ``reactions``; the forces."""

    lam: NDArray
    Cr: NDArray
    Gr: NDArray
    alpha: NDArray
    Phi_sel: NDArray
    PhiT_sel: NDArray
    reactions: bool
    k_idx: NDArray
    k_skew: NDArray
    forces: Forces


class ContactOperators(NamedTuple):
    """The exact-linear modal scheme's linear operators, one per combination of the meshes'
    contact states (:func:`etd_modal`): eigenvectors ``Ys`` (n_ops, m, m), frequencies
    ``oms``, the step's ETD weights ``coefs`` (n_ops, 12, m); ``pat``/``stride``
    map the contact states to an operator code, ``op_of`` a code to its operator;
    ``n_probe`` (0: contact changes never change the operator) and ``max_sub`` of the event
    location; the modal system in each operator's coordinates (``lams`` … ``PhiTs``), the
    meshes' stiffness each holds (``kg_linear``, ``kg_back_linear`` (n_ops, nm)) and the
    recorded rows ``Phi_outs``."""

    Ys: NDArray
    oms: NDArray
    coefs: NDArray
    pat: NDArray
    stride: NDArray
    op_of: NDArray
    n_probe: int
    max_sub: int
    lams: NDArray
    Crs: NDArray
    Grs: NDArray
    alphas: NDArray
    Phis: NDArray
    PhiTs: NDArray
    kg_linear: NDArray
    kg_back_linear: NDArray
    Phi_outs: NDArray


class Record(NamedTuple):
    """What a run records, one row per saved step: ``out`` the recorded DOFs (their indices
    in the full model; the rows Φ_out of the modal basis), their q, q̇, q̈ (nrec, nout), the
    shaft speeds (nrec, ns), the time (nrec,); ``scale`` (nout,) the divergence scale of each
    output (a |q| · scale above 1 stops the run); ``env`` (nrec, nm, 4) the meshes' envelope
    over each recording interval, tracked at every step (:func:`_envelope`): the least and
    the largest normal force F_d − F_b (N), the time out of contact and the time in back-flank
    contact only (s)."""

    out: NDArray
    q: NDArray
    v: NDArray
    a: NDArray
    speed: NDArray
    time: NDArray
    scale: NDArray
    env: NDArray


class Stages(NamedTuple):
    """RK4's stage work arrays (each of the state's length)."""

    k1q: NDArray
    k1v: NDArray
    k2q: NDArray
    k2v: NDArray
    k3q: NDArray
    k3v: NDArray
    k4q: NDArray
    k4v: NDArray
    qt: NDArray
    vt: NDArray


class Woodbury(NamedTuple):
    """Work of the low-rank implicit solve (the θ̈ terms, M + P Qᵀ, by Woodbury): the factors
    Z, the capacitance matrix S = I + Qᵀ Z (r, r), its right side (r,) and pivots (r,)."""

    Z: NDArray
    S: NDArray
    rhs: NDArray
    piv: NDArray


class PhysicalWork(NamedTuple):
    """Work arrays of :func:`_accel_physical`: the force F, ½Gq and M⁻¹(½Gq) (n,); the
    force DOFs' q, q̇ and forces; the shaft speeds; the Woodbury work (Z = M⁻¹P: (r, n));
    the triangular solves' work y (n,)."""

    F: NDArray
    gq: NDArray
    zq: NDArray
    qs: NDArray
    vs: NDArray
    fs: NDArray
    Om: NDArray
    wb: Woodbury
    y: NDArray


class ModalWork(NamedTuple):
    """Work arrays of :func:`_accel_modal`: the force DOFs' q, q̇ and forces, the shaft
    speeds, the Woodbury work (Z (2r, m): P in rows 0..r−1, Q in rows r..2r−1), ½ G_s η
    (ns, m)."""

    qs: NDArray
    vs: NDArray
    fs: NDArray
    Om: NDArray
    wb: Woodbury
    gq: NDArray


# ------------------------------------------------------------------------------------------
# the forces
# ------------------------------------------------------------------------------------------
@njit(cache=_CACHE, fastmath=False)
def _interp(x, xp, fp, lo, hi):
    """Linear interpolation in xp[lo:hi] (held at the ends). Its flags stated: it is called
    from kernels compiled with and without fastmath (module docstring)."""
    if x <= xp[lo]:
        return fp[lo]
    if x >= xp[hi - 1]:
        return fp[hi - 1]
    a, b = lo, hi - 1
    while b - a > 1:
        mid = (a + b) // 2
        if xp[mid] <= x:
            a = mid
        else:
            b = mid
    f = (x - xp[a]) / (xp[b] - xp[a])
    return fp[a] + f * (fp[b] - fp[a])


@njit(cache=_CACHE, inline="always")
def mesh_deflections(k, qs, vs, dofs, w, teeth, te, n_te):
    """Mesh k: (δ, δ̇, δ_b, δ̇_b, φ_m): the deflections and rates along the drive line w
    (δ = w·q) and the back-flank line w_b, with the transmission error (δ → δ − e on the drive
    line, δ_b → δ_b + e on the back line), and the mesh angle φ_m = N θz of the pinion node
    (the :class:`MeshLaws` arrays dofs, lines, teeth, te, n_te)."""
    delta = 0.0
    ddelta = 0.0
    db = 0.0
    ddb = 0.0
    for j in range(12):
        i = dofs[k, j]
        if i >= 0:
            delta += w[k, 0, j] * qs[i]
            ddelta += w[k, 0, j] * vs[i]
            db += w[k, 1, j] * qs[i]
            ddb += w[k, 1, j] * vs[i]
    it = dofs[k, 5]
    phi = teeth[k] * qs[it] if it >= 0 else 0.0
    dphi = teeth[k] * vs[it] if it >= 0 else 0.0
    # transmission error: δ → δ − e on the drive line, δ_b → δ_b + e on the back line
    for s in range(n_te[k]):
        sp = (s + 1) * phi
        c, sn = np.cos(sp), np.sin(sp)
        e = te[k, s, 0] * c + te[k, s, 1] * sn
        de = (s + 1) * dphi * (-te[k, s, 0] * sn + te[k, s, 1] * c)
        delta -= e
        ddelta -= de
        db += e
        ddb += de
    return delta, ddelta, db, ddb, phi


@njit(cache=_CACHE, inline="always")
def mesh_stiffness(k, phi, kg, ka, fourier, n_fourier, table_ptr, table_phi, table_k):
    """Mesh k's stiffness at the mesh angle φ_m: the table k(φ_m) where it has one, else
    kg + 2 ka Σ (a_s sin sφ + b_s cos sφ) (the :class:`MeshLaws` arrays)."""
    lo, hi = table_ptr[k], table_ptr[k + 1]
    if hi > lo:
        ph = phi - 2.0 * np.pi * np.floor(phi / (2.0 * np.pi))
        return _interp(ph, table_phi, table_k, lo, hi)
    stiff = kg[k]
    ka2 = 2.0 * ka[k]
    ns = n_fourier[k]
    if ns > 0:
        s1, c1 = np.sin(phi), np.cos(phi)
        sn, cn = s1, c1
        for s in range(ns):
            stiff += ka2 * (fourier[k, s, 0] * sn + fourier[k, s, 1] * cn)
            sn, cn = sn * c1 + cn * s1, cn * c1 - sn * s1
    return stiff


@njit(cache=_CACHE, inline="always")
def mesh_contact(delta, ddelta, db, ddb, stiff, b, c):
    """SPEC 2.4's contact law: (F_d, F_b, state) from the deflections on the drive and back
    lines, the stiffness, the backlash b and the damping c (state +1 drive, −1 back, +2 both
    flanks, 0 separated)."""
    state = 0
    Fd = 0.0
    Fb = 0.0
    if delta > b:
        state = 1
        Fd = stiff * (delta - b) + c * ddelta
    if db > b:
        state = 2 if state == 1 else -1
        Fb = stiff * (db - b) + c * ddb
    return Fd, Fb, state


@njit(cache=_CACHE, inline="always")
def mesh_eval(k, qs, vs, meshes):
    """Mesh k: returns (F_d, F_b, stiffness, δ_e, δ̇_e, state, φ_m): :func:`mesh_deflections`,
    :func:`mesh_stiffness`, :func:`mesh_contact` (:func:`mesh_forces` calls the three with
    the arrays it reads once for all meshes).

    ``meshes.lines[k, 0]`` is the drive line w (δ = w·q), ``meshes.lines[k, 1]`` the
    back-flank line w_b (``−w`` for SPEC 2.4's law, the mirrored line of action otherwise).
    F_d ≥ 0 acts along −w, F_b ≥ 0 along −w_b (both N, damping included while in contact)."""
    m = meshes
    delta, ddelta, db, ddb, phi = mesh_deflections(
        k, qs, vs, m.dofs, m.lines, m.teeth, m.te, m.n_te
    )
    stiff = mesh_stiffness(
        k, phi, m.kg, m.ka, m.fourier, m.n_fourier, m.table_ptr, m.table_phi, m.table_k
    )
    Fd, Fb, state = mesh_contact(delta, ddelta, db, ddb, stiff, m.backlash[k], m.damping[k])
    return Fd, Fb, stiff, delta, ddelta, state, phi


@njit(cache=_CACHE, inline="always")
def _along(k, line, x, dofs, w):
    """Mesh k's geometric deflection ``w[k, line] · x`` (line 0 the drive line, 1 the back
    line; no transmission error)."""
    d = 0.0
    for j in range(12):
        i = dofs[k, j]
        if i >= 0:
            d += w[k, line, j] * x[i]
    return d


@njit(cache=_CACHE, inline="always")
def mesh_forces(qs, vs, meshes, fs):
    """The meshes' generalised forces added to fs (:func:`mesh_eval`'s law), minus the linear
    part the integrator already holds (kg_linear δ on the drive line, kg_back_linear δ_b on
    the back line, with the geometric δ: no transmission error). Every array read once, here:
    the per-mesh functions take arrays (module docstring)."""
    (dofs, w, kg, ka, backlash, damping, teeth, kg_linear, kg_back_linear, fourier, n_fourier,
     table_ptr, table_phi, table_k, te, n_te, last) = meshes  # fmt: skip
    for k in range(dofs.shape[0]):
        delta, ddelta, db, ddb, phi = mesh_deflections(k, qs, vs, dofs, w, teeth, te, n_te)
        stiff = mesh_stiffness(k, phi, kg, ka, fourier, n_fourier, table_ptr, table_phi, table_k)
        Fd, Fb, state = mesh_contact(delta, ddelta, db, ddb, stiff, backlash[k], damping[k])
        last[k, 0] = Fd - Fb  # the normal force and state, for the step envelope
        last[k, 1] = state
        # the linear part kept in the modal basis uses the geometric δ (no TE)
        Fd -= kg_linear[k] * _along(k, 0, qs, dofs, w)
        if kg_back_linear[k] != 0.0:
            Fb -= kg_back_linear[k] * _along(k, 1, qs, dofs, w)
        for j in range(12):
            i = dofs[k, j]
            if i >= 0:
                fs[i] -= Fd * w[k, 0, j] + Fb * w[k, 1, j]


@njit(cache=_CACHE, inline="always")
def unbalance_forces(qs, vs, unbalances, fs):
    """The unbalances' centrifugal part m e θ̇² r_u added to fs (the θ̈ part is implicit)."""
    dofs, me, phase = unbalances
    for u in range(dofs.shape[0]):
        it = dofs[u, 2]
        th = qs[it] + phase[u]
        w2 = me[u] * vs[it] * vs[it]
        fs[dofs[u, 0]] += w2 * np.cos(th)
        fs[dofs[u, 1]] += w2 * np.sin(th)


@njit(cache=_CACHE, inline="always")
def torque_forces(t, vs, torques, fs):
    """External torques (a value or a time table, times the speed law) added to fs."""
    dof, value, exponent, reference, ptr, time, values = torques
    for j in range(dof.shape[0]):
        lo, hi = ptr[j], ptr[j + 1]
        val = value[j] if hi == lo else _interp(t, time, values, lo, hi)
        if exponent[j] != 0.0:
            speed = abs(vs[dof[j]]) / reference[j]
            val *= speed ** exponent[j]
        fs[dof[j]] += val


@njit(cache=_CACHE, inline="always")
def bearing_forces(qs, vs, Om, bearings, fs):
    """Speed-dependent bearings: the coefficients at the speed of their shaft minus those in
    the linear part, on the journal's motion relative to its pedestal, added to fs."""
    dofs, shaft, ptr, sp, coef, ref = bearings
    for j in range(dofs.shape[0]):
        lo, hi = ptr[j], ptr[j + 1]
        w = abs(Om[shaft[j]])
        kxx = _interp(w, sp, coef[:, 0], lo, hi) - ref[j, 0]
        kxy = _interp(w, sp, coef[:, 1], lo, hi) - ref[j, 1]
        kyx = _interp(w, sp, coef[:, 2], lo, hi) - ref[j, 2]
        kyy = _interp(w, sp, coef[:, 3], lo, hi) - ref[j, 3]
        cxx = _interp(w, sp, coef[:, 4], lo, hi) - ref[j, 4]
        cxy = _interp(w, sp, coef[:, 5], lo, hi) - ref[j, 5]
        cyx = _interp(w, sp, coef[:, 6], lo, hi) - ref[j, 6]
        cyy = _interp(w, sp, coef[:, 7], lo, hi) - ref[j, 7]
        x, y = qs[dofs[j, 0]], qs[dofs[j, 1]]
        vx, vy = vs[dofs[j, 0]], vs[dofs[j, 1]]
        if dofs[j, 2] >= 0:
            x -= qs[dofs[j, 2]]
            y -= qs[dofs[j, 3]]
            vx -= vs[dofs[j, 2]]
            vy -= vs[dofs[j, 3]]
        fx = -(kxx * x + kxy * y + cxx * vx + cxy * vy)
        fy = -(kyx * x + kyy * y + cyx * vx + cyy * vy)
        fs[dofs[j, 0]] += fx
        fs[dofs[j, 1]] += fy
        if dofs[j, 2] >= 0:
            fs[dofs[j, 2]] -= fx
            fs[dofs[j, 3]] -= fy


@kernel_only(cache=_CACHE, fastmath=False)
def nonlinear_forces(t, qs, vs, Om, forces, fs):
    """Generalised forces on the force DOFs (fs overwritten): meshes, unbalances, torques,
    speed-dependent bearings, drives and loads (:class:`Forces`).

    A synchronous motor pulls into step at the first evaluation with its slip at or below the
    pull-in slip (its state in ``forces.drives`` changes there, within the step: an event
    located to one step, as in the torsional transient)."""
    for i in range(fs.shape[0]):
        fs[i] = 0.0
    # (a law the model does not have is not called: a call counts references to its arrays)
    meshes, unbalances, torques, bearings, drives = forces
    if meshes.dofs.shape[0]:
        mesh_forces(qs, vs, meshes, fs)
    if unbalances.dofs.shape[0]:
        unbalance_forces(qs, vs, unbalances, fs)
    if torques.dof.shape[0]:
        torque_forces(t, vs, torques, fs)
    if bearings.dofs.shape[0]:
        bearing_forces(qs, vs, Om, bearings, fs)
    if drives.dof.shape[0]:
        drive_torques(t, qs, vs, drives, True, fs)


@kernel_only(cache=_CACHE, fastmath=False)
def _lu_solve(A, b, piv):
    """Solve A x = b in place (b ← x) by Gaussian elimination with partial pivoting; A is
    overwritten. Returns False when A is singular."""
    n = A.shape[0]
    for k in range(n):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > big:
                big = abs(A[i, k])
                p = i
        if big == 0.0:
            return False
        piv[k] = p
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            b[k], b[p] = b[p], b[k]
        for i in range(k + 1, n):
            f = A[i, k] / A[k, k]
            if f != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
                b[i] -= f * b[k]
    for k in range(n - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, n):
            s -= A[k, j] * b[j]
        b[k] = s / A[k, k]
    return True


@njit(cache=_CACHE, inline="always")
def _matvec2(A, x, y, ax, ay):
    """ax = A x, ay = A y (one pass over A; each row summed in column order). Inlined: the
    caller's compile flags apply."""
    for i in range(A.shape[0]):
        a = 0.0
        b = 0.0
        for j in range(A.shape[1]):
            a += A[i, j] * x[j]
            b += A[i, j] * y[j]
        ax[i] = a
        ay[i] = b


# ------------------------------------------------------------------------------------------
# RK4's stages (inlined into each integrator: its own compile flags apply)
# ------------------------------------------------------------------------------------------
@njit(cache=_CACHE, inline="always")
def _rk4_stage(h, q, v, src, kq, kv, qt, vt):
    """kq ← src (the stage's velocity), then the next stage's point (qt, vt) = (q, v) +
    h (kq, kv)."""
    for i in range(q.shape[0]):
        kq[i] = src[i]
        qt[i] = q[i] + h * kq[i]
        vt[i] = v[i] + h * kv[i]


@njit(cache=_CACHE, inline="always")
def _rk4_update(dt, q, v, k):
    """k4q ← vt, then RK4's step (q, v) += dt/6 (k1 + 2 k2 + 2 k3 + k4) (``k`` the
    :class:`Stages`)."""
    k1q, k1v, k2q, k2v, k3q, k3v, k4q, k4v, qt, vt = k
    for i in range(q.shape[0]):
        k4q[i] = vt[i]
        q[i] += dt / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i])
        v[i] += dt / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i])


# ------------------------------------------------------------------------------------------
# physical coordinates
# ------------------------------------------------------------------------------------------
@kernel_only(cache=_CACHE)
def _csr_mv(A, x, out, scale_rows, Om, row_shaft, accumulate_sign):
    """out += sign · A x (rows optionally scaled by the speed of the row's shaft)."""
    indptr, indices, data = A
    n = indptr.shape[0] - 1
    for i in range(n):
        s = row_dot(indptr, indices, data, i, x)
        if scale_rows:
            sh = row_shaft[i]
            s = s * Om[sh] if sh >= 0 else 0.0
        out[i] += accumulate_sign * s


@kernel_only(cache=_CACHE)
def _msolve(mass, x, out, y):
    """out = M⁻¹ x with the sparse Cholesky factor ``mass`` (:class:`MassFactor`)."""
    perm = mass.perm
    Lp, Li, Ld = mass.L
    Up, Ui, Ud = mass.U
    n = perm.shape[0]
    for i in range(n):
        y[i] = x[perm[i]]
    for i in range(n):
        acc = y[i]
        d = Lp[i + 1] - 1
        for p in range(Lp[i], d):
            acc -= Ld[p] * y[Li[p]]
        y[i] = acc / Ld[d]
    for i in range(n - 1, -1, -1):
        acc = y[i]
        d = Up[i]
        for p in range(d + 1, Up[i + 1]):
            acc -= Ud[p] * y[Ui[p]]
        y[i] = acc / Ud[d]
    for i in range(n):
        out[perm[i]] = y[i]


@kernel_only(cache=_CACHE)
def _accel_physical(t, q, v, a, P, W):
    """Accelerations of the physical model (a ← q̈): P a :class:`PhysicalModel`, W its
    :class:`PhysicalWork`.

    The low-rank implicit part M + P Qᵀ is solved by Woodbury: a = y − Z (I + QᵀZ)⁻¹ Qᵀ y with
    y = M⁻¹F and the rows of Zᵀ = (M⁻¹P)ᵀ, each nonzero only on its support (z_ptr/z_idx)."""
    K, C, G, row_shaft, mass, speed_rows = (
        P.K,
        P.C,
        P.G,
        P.row_shaft,
        P.mass,
        P.speed_rows,
    )
    torsion, frozen, reactions, sel = P.torsion, P.frozen, P.reactions, P.sel
    F, gq, zq, qs, vs, fs, Om, y = W.F, W.gq, W.zq, W.qs, W.vs, W.fs, W.Om, W.y
    Z, S, rhs, piv = W.wb.Z, W.wb.S, W.wb.rhs, W.wb.piv
    Minv_a, Minv_ux, Minv_uy, Minv_ut, u_full, z_ptr, z_idx, g_ptr, g_idx = P.implicit
    u_me, u_ph = P.forces.unbalances.me, P.forces.unbalances.phase
    n = q.shape[0]
    a_ptr, a_idx, a_w = speed_rows
    ns = a_ptr.shape[0] - 1
    for s in range(ns):
        Om[s] = row_dot(a_ptr, a_idx, a_w, s, v)
    for i in range(n):
        F[i] = 0.0
    _csr_mv(K, q, F, False, Om, row_shaft, -1.0)
    _csr_mv(C, v, F, False, Om, row_shaft, -1.0)
    _csr_mv(G, v, F, True, Om, row_shaft, -1.0)
    for i in range(sel.shape[0]):
        qs[i] = q[sel[i]]
        vs[i] = v[sel[i]]
    nonlinear_forces(t, qs, vs, Om, P.forces, fs)
    for i in range(sel.shape[0]):
        F[sel[i]] += fs[i]
    _msolve(mass, F, a, y)
    if frozen:
        for i in range(torsion.shape[0]):
            a[torsion[i]] = 0.0
        return
    # ---- exact solve of the low-rank implicit terms (Woodbury) ----------------------------
    for i in range(n):
        gq[i] = 0.0
    _csr_mv(G, q, gq, False, Om, row_shaft, 0.5)  # g = ½ G q (all shafts)
    _msolve(mass, gq, zq, y)
    nu = u_me.shape[0]
    per_s = 2 if reactions else 1
    r = per_s * (ns + nu)
    # rows of Zᵀ = (M⁻¹ P)ᵀ on their supports
    for s in range(ns):
        c = per_s * s
        for p in range(z_ptr[c], z_ptr[c + 1]):
            Z[c, z_idx[p]] = zq[z_idx[p]]
        if reactions:
            for p in range(z_ptr[c + 1], z_ptr[c + 2]):
                Z[c + 1, z_idx[p]] = Minv_a[s, z_idx[p]]
    for u in range(nu):
        c = per_s * (ns + u)
        th = q[u_full[u, 2]] + u_ph[u]
        sn, cs = np.sin(th), np.cos(th)
        me = u_me[u]
        for p in range(z_ptr[c], z_ptr[c + 1]):
            i = z_idx[p]
            Z[c, i] = me * (-sn * Minv_ux[u, i] + cs * Minv_uy[u, i])
        if reactions:
            for p in range(z_ptr[c + 1], z_ptr[c + 2]):
                i = z_idx[p]
                Z[c + 1, i] = me * Minv_ut[u, i]
    Q = (speed_rows, g_ptr, g_idx, u_full, u_ph)
    for row in range(r):
        rhs[row] = _qdot(row, a, q, gq, ns, per_s, Q)
        for col in range(r):
            S[row, col] = (1.0 if row == col else 0.0) + _qdot(row, Z[col], q, gq, ns, per_s, Q)
    _lu_solve(S, rhs, piv)
    for c in range(r):
        f = rhs[c]
        for p in range(z_ptr[c], z_ptr[c + 1]):
            i = z_idx[p]
            a[i] -= Z[c, i] * f


@kernel_only(cache=_CACHE)
def _qdot(row, x, q, gq, ns, per_s, Q):
    """Q[:, row]ᵀ x for the low-rank factor Q of the implicit terms (physical model; gq the
    current ½ G q; ``Q`` = (speed rows, g_ptr, g_idx, the unbalances' DOFs, phases))."""
    speed_rows, g_ptr, g_idx, ud, phase = Q
    if row < ns * per_s:
        s = row // per_s
        if row % per_s == 0:  # Q = a_s
            return row_dot(speed_rows.indptr, speed_rows.indices, speed_rows.data, s, x)
        acc = 0.0  # Q = g_s, nonzero on the rows of G_s
        for p in range(g_ptr[s], g_ptr[s + 1]):
            acc += gq[g_idx[p]] * x[g_idx[p]]
        return acc
    u = (row - ns * per_s) // per_s
    if (row - ns * per_s) % per_s == 0:  # Q = c_u
        return x[ud[u, 2]]
    th = q[ud[u, 2]] + phase[u]  # Q = s_u
    return -np.sin(th) * x[ud[u, 0]] + np.cos(th) * x[ud[u, 1]]


@njit(cache=_CACHE, inline="always")
def _envelope_force(row, k, F, first, env):
    """Mesh k's normal force F into the least and the largest of recording interval ``row``
    of the envelope (:class:`Record` ``env``); ``first``: the interval's first step, which
    starts it (its times out of contact and in back-flank contact set to 0)."""
    if first:
        env[row, k, 0] = F
        env[row, k, 1] = F
        env[row, k, 2] = 0.0
        env[row, k, 3] = 0.0
    else:
        if F < env[row, k, 0]:
            env[row, k, 0] = F
        if F > env[row, k, 1]:
            env[row, k, 1] = F


@njit(cache=_CACHE, inline="always")
def _envelope_time(row, h, states, env):
    """A stretch of length h in each mesh's contact state ``states[k]``: to the time out of
    contact (state 0) or in back-flank contact only (−1) of interval ``row``."""
    for k in range(env.shape[1]):
        if states[k] == 0:
            env[row, k, 2] += h
        elif states[k] == -1:
            env[row, k, 3] += h


@njit(cache=_CACHE, inline="always")
def _envelope(row, first, h, last, env):
    """The meshes' envelope (:class:`Record` ``env``) of recording interval ``row`` from the
    meshes' normal force F_d − F_b and contact state at the start of a step of length h
    (``last``, :class:`MeshLaws`, as the step's first force evaluation left it): F enters the
    least and the largest (``first``: the interval's first step, which starts it), and h the
    time out of contact (state 0) or in back-flank contact only (state −1), the contact state
    held over the step (a left Riemann sum: with a record at every step it is the recorded
    samples' count times h). It only reads, so nothing else a run computes changes."""
    for k in range(env.shape[1]):
        _envelope_force(row, k, last[k, 0], first, env)
    _envelope_time(row, h, last[:, 1], env)


@njit(cache=_CACHE, inline="always")
def _rk4_steps(accel, record, t0, dt, n_steps, q, v, save_every, row0, rec, P, W, k):
    """Classical RK4 on (q, q̇) for ``n_steps`` steps from t0 (q, v updated in place):
    ``accel(t, q, q̇, q̈, P, W)`` the accelerations of the model P (work W), k the
    :class:`Stages`. Every ``save_every`` steps (starting with the first) ``record(j, t, q,
    q̇, q̈, rec, Ω)`` writes the state at the step start to row j = ``row0``, ``row0 + 1``, …
    of ``rec`` and returns the divergence status; at every step the meshes' envelope of the
    current recording interval is updated (:func:`_envelope`). Returns (status, steps done).

    One loop for both RK4 kernels, inlined into each (:func:`rk4_physical`,
    :func:`rk4_modal`), so that each keeps its own compile flags."""
    k1q, k1v, k2q, k2v, k3q, k3v, k4q, k4v, qt, vt = k
    Om = W.Om
    last = P.forces.meshes.last
    env = rec.env
    j = row0
    for step in range(n_steps):
        t = t0 + step * dt
        accel(t, q, v, k1v, P, W)
        saved = step % save_every == 0
        # the meshes at the step's start, as its first force evaluation left them
        _envelope(j if saved else j - 1, saved, dt, last, env)
        if saved:
            status = record(j, t, q, v, k1v, rec, Om)
            j += 1
            if status != STATUS_OK:
                return status, step
        _rk4_stage(0.5 * dt, q, v, v, k1q, k1v, qt, vt)
        accel(t + 0.5 * dt, qt, vt, k2v, P, W)
        _rk4_stage(0.5 * dt, q, v, vt, k2q, k2v, qt, vt)
        accel(t + 0.5 * dt, qt, vt, k3v, P, W)
        _rk4_stage(dt, q, v, vt, k3q, k3v, qt, vt)
        accel(t + dt, qt, vt, k4v, P, W)
        _rk4_update(dt, q, v, k)
    return STATUS_OK, n_steps


@njit(cache=_CACHE, inline="always")
def _record_speeds(j, t, rec, Om):
    """Row j of the recorded shaft speeds and time."""
    speed = rec.speed
    for s in range(Om.shape[0]):
        speed[j, s] = Om[s]
    rec.time[j] = t


@njit(cache=_CACHE, inline="always")
def _record_physical(j, t, q, v, a, rec, Om):
    """Row j of ``rec`` (:class:`Record`, ``rec.out`` the recorded DOFs) from the full state;
    the divergence status (any state non-finite, or a recorded |q| beyond its scale)."""
    out, rq, rv, ra, _, _, scale, _ = rec
    for i in range(out.shape[0]):
        rq[j, i] = q[out[i]]
        rv[j, i] = v[out[i]]
        ra[j, i] = a[out[i]]
    _record_speeds(j, t, rec, Om)
    bad = False
    big = 0.0
    for i in range(q.shape[0]):
        if not (np.isfinite(q[i]) and np.isfinite(v[i])):
            bad = True
    for i in range(out.shape[0]):
        x = abs(rq[j, i]) * scale[i]
        if x > big:
            big = x
    if bad:
        return STATUS_NONFINITE
    if big > 1.0:
        return STATUS_BLOWUP
    return STATUS_OK


@njit(cache=_CACHE)
def rk4_physical(t0, dt, n_steps, q, v, save_every, row0, rec, P, W, k):
    """Classical RK4 on the full model (:class:`PhysicalModel` P, work W, stages k;
    :func:`_rk4_steps`), recording the DOFs ``rec.out`` (:class:`Record`) every
    ``save_every`` steps at rows ``row0``, … Returns (status, steps done)."""
    return _rk4_steps(
        _accel_physical,
        _record_physical,
        t0,
        dt,
        n_steps,
        q,
        v,
        save_every,
        row0,
        rec,
        P,
        W,
        k,
    )


# ------------------------------------------------------------------------------------------
# modal coordinates
# ------------------------------------------------------------------------------------------
@kernel_only(cache=_CACHE, fastmath=_FAST)
def _accel_modal(t, e, de, a, P, W):
    """Modal accelerations (a ← η̈) of the :class:`ModalModel` P (M_r = I; work W a
    :class:`ModalWork`); the stiffness's skew part acts as a force on its force DOFs; the
    implicit θ̈ terms by Woodbury on I + P Qᵀ (W.wb.Z holds P in rows 0..r−1, Q in rows
    r..2r−1)."""
    # every array read once, here (each read from a pack counts a reference: module docstring)
    lam, Cr, Gr, alpha, Phi_sel, PhiT_sel, reactions, k_idx, k_skew, forces = P
    qs, vs, fs, Om, wb, gq = W
    Z, S, rhs, piv = wb
    u_dofs, u_me, u_phase = forces.unbalances
    m = e.shape[0]
    ns = alpha.shape[0]
    nsel = Phi_sel.shape[0]
    for s in range(ns):
        o = 0.0
        for i in range(m):
            o += alpha[s, i] * de[i]
        Om[s] = o
    _matvec2(Phi_sel, e, de, qs, vs)
    nonlinear_forces(t, qs, vs, Om, forces, fs)
    nk = k_idx.shape[0]
    for i in range(nk):
        f = 0.0
        for j in range(nk):
            f += k_skew[i, j] * qs[k_idx[j]]
        fs[k_idx[i]] -= f
    for i in range(m):
        acc = -lam[i] * e[i]
        c0 = 0.0
        for j in range(m):
            c0 += Cr[i, j] * de[j]
        acc -= c0
        for s in range(ns):
            g1 = 0.0
            g2 = 0.0
            for j in range(m):
                g1 += Gr[s, i, j] * de[j]
                g2 += Gr[s, i, j] * e[j]
            acc -= Om[s] * g1
            gq[s, i] = 0.5 * g2
        f = 0.0
        for p in range(nsel):
            f += PhiT_sel[i, p] * fs[p]
        a[i] = acc + f
    # Woodbury on I + P Qᵀ
    nu = u_dofs.shape[0]
    per_s = 2 if reactions else 1
    r = per_s * (ns + nu)
    for s in range(ns):
        c = per_s * s
        for i in range(m):
            Z[c, i] = gq[s, i]
            Z[r + c, i] = alpha[s, i]
        if reactions:
            for i in range(m):
                Z[c + 1, i] = alpha[s, i]
                Z[r + c + 1, i] = gq[s, i]
    for u in range(nu):
        c = per_s * (ns + u)
        th = qs[u_dofs[u, 2]] + u_phase[u]
        sn, cs = np.sin(th), np.cos(th)
        me = u_me[u]
        ix, iy, it = u_dofs[u, 0], u_dofs[u, 1], u_dofs[u, 2]
        for i in range(m):
            su = -sn * Phi_sel[ix, i] + cs * Phi_sel[iy, i]
            Z[c, i] = me * su
            Z[r + c, i] = Phi_sel[it, i]
            if reactions:
                Z[c + 1, i] = me * Phi_sel[it, i]
                Z[r + c + 1, i] = su
    for row in range(r):
        acc = 0.0
        for i in range(m):
            acc += Z[r + row, i] * a[i]
        rhs[row] = acc
        for col in range(r):
            acc = 1.0 if row == col else 0.0
            for i in range(m):
                acc += Z[r + row, i] * Z[col, i]
            S[row, col] = acc
    _lu_solve(S, rhs, piv)
    for c in range(r):
        f = rhs[c]
        for i in range(m):
            a[i] -= Z[c, i] * f


@njit(cache=_CACHE, inline="always")
def _record_projected(j, Po, z, v, a, rec):
    """Row j of the recorded outputs Po z, Po v, Po a (``Po`` the rows of the outputs in the
    basis of the coordinates z); the divergence status (a non-finite output, or |q| beyond its
    scale). Inlined: the caller's compile flags apply."""
    _, rq, rv, ra, _, _, scale, _ = rec
    m = z.shape[0]
    big = 0.0
    bad = False
    for i in range(Po.shape[0]):
        x = 0.0
        y = 0.0
        zz = 0.0
        for c in range(m):
            x += Po[i, c] * z[c]
            y += Po[i, c] * v[c]
            zz += Po[i, c] * a[c]
        rq[j, i] = x
        rv[j, i] = y
        ra[j, i] = zz
        if not (np.isfinite(x) and np.isfinite(y)):
            bad = True
        if abs(x) * scale[i] > big:
            big = abs(x) * scale[i]
    if bad:
        return STATUS_NONFINITE
    if big > 1.0:
        return STATUS_BLOWUP
    return STATUS_OK


@njit(cache=_CACHE, fastmath=_FAST, inline="always")
def _record_modal(j, t, e, de, dde, rec, Om):
    """Row j of ``rec`` (:class:`Record`, ``rec.out`` the rows Φ_out of the modal basis): the
    physical outputs Φ_out η, η̇, η̈, the shaft speeds and t; the divergence status."""
    _record_speeds(j, t, rec, Om)
    return _record_projected(j, rec.out, e, de, dde, rec)


@njit(cache=_CACHE, fastmath=_FAST)
def rk4_modal(t0, dt, n_steps, e, de, save_every, row0, rec, P, W, k):
    """Classical RK4 on the reduced modal system (:class:`ModalModel` P, work W, stages k;
    :func:`_rk4_steps`); records the physical output DOFs Φ_out η (``rec.out``) as
    :func:`rk4_physical`."""
    return _rk4_steps(
        _accel_modal,
        _record_modal,
        t0,
        dt,
        n_steps,
        e,
        de,
        save_every,
        row0,
        rec,
        P,
        W,
        k,
    )


# ------------------------------------------------------------------------------------------
# outputs from recorded states
# ------------------------------------------------------------------------------------------
@njit(cache=_CACHE, fastmath=False)
def outputs_kernel(rec_q, rec_v, meshes, mesh_out):
    """Per record and mesh: F = F_d − F_b (N), k (N/m), δ_e (m), δ̇_e, state, φ_m, F_d, F_b
    into mesh_out (nt, nm, 8). ``meshes.dofs`` index the recorded output DOFs here."""
    for j in range(rec_q.shape[0]):
        for k in range(meshes.dofs.shape[0]):
            Fd, Fb, stiff, delta, ddelta, state, phi = mesh_eval(k, rec_q[j], rec_v[j], meshes)
            mesh_out[j, k, 0] = Fd - Fb
            mesh_out[j, k, 6] = Fd
            mesh_out[j, k, 7] = Fb
            mesh_out[j, k, 1] = stiff
            mesh_out[j, k, 2] = delta
            mesh_out[j, k, 3] = ddelta
            mesh_out[j, k, 4] = state
            mesh_out[j, k, 5] = phi


# ------------------------------------------------------------------------------------------
# modal coordinates, linear part exact (integrating factor), contact changes located
# ------------------------------------------------------------------------------------------
@kernel_only(cache=_CACHE, fastmath=False)
def _gap_deflections(k, qs, vs, dofs, w, teeth, te, n_te):
    """:func:`mesh_deflections` for :func:`mesh_gaps`, compiled on its own without fastmath
    (as in :func:`mesh_eval`; inlined into mesh_gaps it would take that function's flags)."""
    return mesh_deflections(k, qs, vs, dofs, w, teeth, te, n_te)


@kernel_only(cache=_CACHE, fastmath=_FAST)
def mesh_gaps(qs, vs, meshes, G):
    """Gap functions of every mesh k into G[k, 0:4]: δ − b, δ̇ (drive line), δ_b − b, δ̇_b
    (back line), with the transmission error, as :func:`mesh_eval` forms them (> 0: that flank
    touches)."""
    dofs, w, teeth, te, n_te, backlash = (
        meshes.dofs,
        meshes.lines,
        meshes.teeth,
        meshes.te,
        meshes.n_te,
        meshes.backlash,
    )
    for k in range(backlash.shape[0]):
        delta, ddelta, db, ddb, _ = _gap_deflections(k, qs, vs, dofs, w, teeth, te, n_te)
        G[k, 0] = delta - backlash[k]
        G[k, 1] = ddelta
        G[k, 2] = db - backlash[k]
        G[k, 3] = ddb


@kernel_only(cache=_CACHE, fastmath=_FAST)
def _gaps_of(e, de, Phi_sel, qs, vs, meshes, G):
    """G[k, 0:4] = :func:`mesh_gaps` of every mesh at the modal state (e, de)."""
    _matvec2(Phi_sel, e, de, qs, vs)
    mesh_gaps(qs, vs, meshes, G)


@kernel_only(cache=_CACHE)
def _op_code(G, pat, stride):
    """Index of the linear operator for the contact state of every mesh (gaps G)."""
    code = 0
    for k in range(G.shape[0]):
        s = (1 if G[k, 0] > 0.0 else 0) + (2 if G[k, 2] > 0.0 else 0)
        code += pat[k, s] * stride[k]
    return code


@kernel_only(cache=_CACHE)
def _hermite(g0, d0, g1, d1, h, s):
    """Cubic Hermite interpolant on [0, h] at s·h (values g, slopes d per second)."""
    s2 = s * s
    s3 = s2 * s
    return (
        (2 * s3 - 3 * s2 + 1) * g0
        + (s3 - 2 * s2 + s) * h * d0
        + (-2 * s3 + 3 * s2) * g1
        + (s3 - s2) * h * d1
    )


@kernel_only(cache=_CACHE)
def _line_crossing(g0, d0, g1, d1, h, n_probe):
    """First zero crossing in (0, 1] (fraction of h) of the cubic Hermite interpolant through
    a gap g and its rate d at both ends of a step h, probed at ``n_probe`` points and bisected;
    2.0 for none."""
    prev = g0
    lo = 0.0
    for p in range(1, n_probe + 1):
        s = p / n_probe
        gs = g1 if p == n_probe else _hermite(g0, d0, g1, d1, h, s)
        if (prev > 0.0) != (gs > 0.0):
            a, b = lo, s
            for _ in range(40):
                mid = 0.5 * (a + b)
                if (_hermite(g0, d0, g1, d1, h, mid) > 0.0) == (g0 > 0.0):
                    a = mid
                else:
                    b = mid
            return b
        prev = gs
        lo = s
    return 2.0


@kernel_only(cache=_CACHE)
def _first_event(G0, G1, h, n_probe, pat, stride, code, Gs):
    """Earliest contact change within a step h that changes the linear operator: returns the
    fraction of h and the operator code just after it, or (2.0, code) for none. A crossing
    that leaves the operator unchanged (e.g. δ through 0 without backlash: drive to back flank,
    the same stiffness) is no event. ``Gs`` (nm, 4) work array."""
    nm = G0.shape[0]
    best = 2.0
    best_code = code
    done = 0.0
    for _ in range(2 * nm):
        # the next crossing after ``done``
        nxt = 2.0
        for k in range(nm):
            for line in range(2):
                c = _line_crossing(
                    G0[k, 2 * line], G0[k, 2 * line + 1], G1[k, 2 * line], G1[k, 2 * line + 1],
                    h, n_probe,
                )  # fmt: skip
                if done < c < nxt:
                    nxt = c
        if nxt > 1.0:
            break
        # the state just after it, every line from its interpolant
        s = min(nxt + 1e-9, 1.0)
        for k in range(nm):
            for line in range(2):
                g = _hermite(
                    G0[k, 2 * line], G0[k, 2 * line + 1], G1[k, 2 * line], G1[k, 2 * line + 1],
                    h, s,
                )  # fmt: skip
                c = _line_crossing(
                    G0[k, 2 * line], G0[k, 2 * line + 1], G1[k, 2 * line], G1[k, 2 * line + 1],
                    h, n_probe,
                )  # fmt: skip
                # the side of a line crossing now is the one it crosses to
                if abs(c - nxt) < 1e-12:
                    g = -G0[k, 2 * line]
                Gs[k, 2 * line] = g
        new = _op_code(Gs, pat, stride)
        if new != code:
            best = nxt
            best_code = new
            break
        done = nxt
    return best, best_code


@kernel_only(cache=_CACHE)
def _phis(z):
    """(e^z, φ1, φ2, φ3)(z) of a complex z, φ_k(z) = Σ_j z^j/(j+k)!: one series for |z| < 0.5
    (terms until they stop changing the sums; no cancellation), else the recurrence
    φ_{k+1} = (φ_k − 1/k!)/z from e^z (cancellation at most ε/|z|³ ≈ 1e-15)."""
    if abs(z) < 0.5:
        p1 = 1.0 + 0.0j
        p2 = 0.5 + 0.0j
        p3 = 1.0 / 6.0 + 0.0j
        zj = 1.0 + 0.0j
        f = 1.0  # 1/(j+1)!
        for j in range(1, 30):
            zj = zj * z
            f = f / (j + 1)
            t1 = zj * f
            t2 = t1 / (j + 2)
            t3 = t2 / (j + 3)
            p1 += t1
            p2 += t2
            p3 += t3
            if abs(t1) < 1e-17 * abs(p1) and abs(t3) < 1e-17 * abs(p3):
                break
        return 1.0 + z * p1, p1, p2, p3
    e = np.exp(z)
    p1 = (e - 1.0) / z
    p2 = (p1 - 1.0) / z
    p3 = (p2 - 0.5) / z
    return e, p1, p2, p3


@njit(cache=_CACHE)
def etd_coefficients(om, tau, C):
    """Weights of one exponential RK4 step (Cox & Matthews 2002, ETDRK4) of length τ for
    oscillators ζ̈ + ω²ζ = g, into C (12, m). A function F of the block L = [[0, 1], [−ω², 0]]
    is F(L) = α I + β L with α = Re F(iω), β = Im F(iω)/ω (F(0), F'(0) at ω = 0: L² = 0);
    rows (α, β) of: E(τ/2) = e^{Lτ/2}, (τ/2)φ1(Lτ/2), E(τ), τ(φ1 − 3φ2 + 4φ3),
    τ(φ2 − 2φ3), τ(4φ3 − φ2) (the last three at Lτ)."""
    for i in range(om.shape[0]):
        w = om[i]
        if w == 0.0:
            C[0, i], C[1, i] = 1.0, 0.5 * tau
            C[2, i], C[3, i] = 0.5 * tau, tau * tau / 8.0
            C[4, i], C[5, i] = 1.0, tau
            C[6, i], C[7, i] = tau / 6.0, tau * tau / 6.0
            C[8, i], C[9, i] = tau / 6.0, tau * tau / 12.0
            C[10, i], C[11, i] = tau / 6.0, 0.0
            continue
        F2, p1, p2, p3 = _phis(1j * w * tau)
        F0, q1, _, _ = _phis(0.5j * w * tau)
        F1 = 0.5 * tau * q1
        F3 = tau * (p1 - 3.0 * p2 + 4.0 * p3)
        F4 = tau * (p2 - 2.0 * p3)
        F5 = tau * (4.0 * p3 - p2)
        C[0, i], C[1, i] = F0.real, F0.imag / w
        C[2, i], C[3, i] = F1.real, F1.imag / w
        C[4, i], C[5, i] = F2.real, F2.imag / w
        C[6, i], C[7, i] = F3.real, F3.imag / w
        C[8, i], C[9, i] = F4.real, F4.imag / w
        C[10, i], C[11, i] = F5.real, F5.imag / w


@njit(cache=_CACHE, fastmath=_FAST_ETD, inline="always")
def _etd_rhs(t, z, v, g, om, P, W):
    """N = ζ̈ + μζ: everything but the operator's oscillators (``P`` the modal system in the
    operator's coordinates, its stiffness diag(μ))."""
    _accel_modal(t, z, v, g, P, W)
    for i in range(z.shape[0]):
        g[i] += om[i] * om[i] * z[i]


@kernel_only(cache=_CACHE, fastmath=_FAST_ETD)
def _etd_substep(t, tau, z, v, om, coef, P, W, L, out_z, out_v):
    """One exponential RK4 step (ETDRK4, Cox & Matthews 2002) of length tau from (z, v) at t
    in the coordinates of a linear operator diag(μ = om²): the oscillators ζ̈ + μζ are
    integrated exactly, the rest N (damping, gyroscopics, the mesh beyond the operator's
    stiffness, unbalance, torques) enters through the φ-functions (:func:`etd_coefficients`;
    exact for a constant N, so the quasi-static response of a high mode is right at any step).
    ``coef`` (12, m): the weights of the full step, or an empty array to compute them for this
    τ. Writes ζ, ζ̇ at t + tau to out_z, out_v."""
    (x, y, acc, g1, g2, g3, g4, ax, av, C) = L
    m = z.shape[0]
    if coef.shape[0] == 12:
        C = coef
    else:
        etd_coefficients(om, tau, C)
    # F(L)(ζ, v) = (αζ + βv, αv − ω²βζ); the forcing (0, g) gives (βg, αg)
    _etd_rhs(t, z, v, g1, om, P, W)
    for i in range(m):
        w2 = om[i] * om[i]
        ez = C[0, i] * z[i] + C[1, i] * v[i]  # E(τ/2) x
        ev = C[0, i] * v[i] - w2 * C[1, i] * z[i]
        ax[i] = ez + C[3, i] * g1[i]
        av[i] = ev + C[2, i] * g1[i]
        x[i] = ez
        y[i] = ev
    _etd_rhs(t + 0.5 * tau, ax, av, g2, om, P, W)
    for i in range(m):
        x[i] += C[3, i] * g2[i]
        y[i] += C[2, i] * g2[i]
    _etd_rhs(t + 0.5 * tau, x, y, g3, om, P, W)
    for i in range(m):
        w2 = om[i] * om[i]
        f = 2.0 * g3[i] - g1[i]
        x[i] = C[0, i] * ax[i] + C[1, i] * av[i] + C[3, i] * f
        y[i] = C[0, i] * av[i] - w2 * C[1, i] * ax[i] + C[2, i] * f
    _etd_rhs(t + tau, x, y, g4, om, P, W)
    for i in range(m):
        w2 = om[i] * om[i]
        g23 = g2[i] + g3[i]
        out_z[i] = (
            C[4, i] * z[i] + C[5, i] * v[i] + C[7, i] * g1[i] + 2.0 * C[9, i] * g23
            + C[11, i] * g4[i]
        )  # fmt: skip
        out_v[i] = (
            C[4, i] * v[i] - w2 * C[5, i] * z[i] + C[6, i] * g1[i] + 2.0 * C[8, i] * g23
            + C[10, i] * g4[i]
        )  # fmt: skip


@kernel_only(cache=_CACHE)
def _op_system(P, X, op):
    """The :class:`ModalModel` of :func:`_accel_modal` in the coordinates of operator op of
    the :class:`ContactOperators` X (the meshes' stiffness it holds not subtracted again)."""
    m = P.forces.meshes
    meshes = MeshLaws(
        m.dofs, m.lines, m.kg, m.ka, m.backlash, m.damping, m.teeth, X.kg_linear[op],
        X.kg_back_linear[op], m.fourier, m.n_fourier, m.table_ptr, m.table_phi, m.table_k,
        m.te, m.n_te, m.last,
    )  # fmt: skip
    f = P.forces
    forces = Forces(meshes, f.unbalances, f.torques, f.bearings, f.drives)
    return ModalModel(
        X.lams[op], X.Crs[op], X.Grs[op], X.alphas[op], X.Phis[op], X.PhiTs[op], P.reactions,
        P.k_idx, P.k_skew, forces,
    )  # fmt: skip


@kernel_only(cache=_CACHE)
def _rotate(Ya, Yb, z, v, tz, tv):
    """(z, v) ← Y_bᵀ Y_a (z, v): coordinates of operator a to those of operator b."""
    _matvec2(Ya, z, v, tz, tv)
    _matvec2(Yb.T, tz, tv, z, v)


@kernel_only(cache=_CACHE, fastmath=_FAST_ETD)
def _record_etd(j, t, z, v, g1, om, Po, alpha, rec, acc):
    """Record row j of the outputs Φ_out η, η̇, η̈ (η̈ = N − μζ, ``g1`` the first stage's N,
    into the work vector ``acc``) and the shaft speeds at t, in an operator's coordinates (its
    rows ``Po`` of Φ_out, ``alpha`` of the speeds); returns the divergence status."""
    m = z.shape[0]
    for c in range(m):
        acc[c] = g1[c] - om[c] * om[c] * z[c]
    speed = rec.speed
    for s in range(alpha.shape[0]):
        o = 0.0
        for c in range(m):
            o += alpha[s, c] * v[c]
        speed[j, s] = o
    rec.time[j] = t
    return _record_projected(j, Po, z, v, acc, rec)


@njit(cache=_CACHE, inline="always")
def _envelope_forces(row, first, qs, vs, meshes, env, held):
    """:func:`_envelope`'s forces for the exponential scheme, whose steps are cut into pieces
    at the located contact changes: the normal force at a piece's start (qs, vs) enters the
    least and largest of interval ``row`` (``first`` starts it), and each mesh's contact state
    there goes to ``held`` (its time is added by :func:`_envelope_time` once the piece's
    length is known). Inlined: the caller's compile flags apply."""
    for k in range(env.shape[1]):
        Fd, Fb, _, _, _, state, _ = mesh_eval(k, qs, vs, meshes)
        _envelope_force(row, k, Fd - Fb, first, env)
        held[k] = state


@njit(cache=_CACHE, inline="always")
def _held_states(Gs, held):
    """Each mesh's contact state just after a located crossing, from the gaps
    :func:`_first_event` left in ``Gs`` (the crossing line on the side it crosses to; the
    state evaluated at the crossing itself is round-off)."""
    for k in range(held.shape[0]):
        drive = Gs[k, 0] > 0.0
        back = Gs[k, 2] > 0.0
        held[k] = (2 if back else 1) if drive else (-1 if back else 0)


@njit(cache=_CACHE, fastmath=_FAST_ETD)
def etd_modal(t0, dt, n_steps, e, de, save_every, row0, rec, P, W, K1, X):
    """Exponential RK4 on the reduced modal system with the contact changes located.

    ``X`` (:class:`ContactOperators`) holds one linear operator per combination of the meshes'
    contact states: diag(Λ) with each mesh's stiffness Kg w wᵀ on the lines that touch (none
    while the teeth are apart), its eigenvectors ``Ys`` (orthonormal, η = Y ζ) and frequencies
    ``oms``, the step's ETD weights ``coefs``, and the modal system in its coordinates;
    ``pat``/``stride`` map the contact states to an operator. Each step runs in the
    coordinates of the operator of the contact state at its start, whose oscillators it
    integrates exactly (:func:`_etd_substep`). When a gap function changes sign within the step
    in a way that changes the operator (cubic Hermite through its values and rates at both
    ends) the step is redone up to the crossing and continued from there with the new
    operator, so each piece of a step sees one smooth law. Records Φ_out η every
    ``save_every`` steps as :func:`rk4_modal`, and the meshes' envelope of each recording
    interval at the start of every step and of every piece of a step cut at a contact change
    (:func:`_envelope_forces`, the pieces' times in their contact states); (e, de) in and out
    are modal coordinates η. Returns (status, steps done, substeps added by contact changes)."""
    Ys, oms, coefs, pat, stride, op_of = X.Ys, X.oms, X.coefs, X.pat, X.stride, X.op_of
    n_probe, max_sub, Phis = X.n_probe, X.max_sub, X.Phis
    Phi_outs, alphas = X.Phi_outs, X.alphas
    m = e.shape[0]
    L = (
        K1.k1q,
        K1.k1v,
        K1.k2q,
        K1.k2v,
        K1.k3q,
        K1.k3v,
        K1.k4q,
        K1.k4v,
        K1.qt,
        np.zeros((12, m)),
    )
    none = np.zeros((0, m))
    meshes = P.forces.meshes
    qs, vs = W.qs, W.vs
    nm = meshes.dofs.shape[0]
    G0 = np.zeros((nm, 4))
    acc = np.zeros(m)  # η̈ of a recorded step
    G1 = np.zeros((nm, 4))
    Gs = np.zeros((nm, 4))
    z = np.zeros(m)
    v = np.zeros(m)
    z1 = np.zeros(m)
    v1 = np.zeros(m)
    extra = 0
    code = 0
    # start in the coordinates of the initial contact state's operator
    _gaps_of(e, de, P.Phi_sel, qs, vs, meshes, G0)
    new = op_of[_op_code(G0, pat, stride)]
    for i in range(m):
        z[i] = 0.0
        v[i] = 0.0
        for j in range(m):
            z[i] += Ys[new, j, i] * e[j]
            v[i] += Ys[new, j, i] * de[j]
    cur = new
    Pc = _op_system(P, X, cur)
    j = row0
    status = STATUS_OK
    done = n_steps
    env = rec.env
    held = np.zeros(nm, np.int64)  # each mesh's contact state over the current piece
    for step in range(n_steps):
        t = t0 + step * dt
        left = dt
        forced = -1
        saved = step % save_every == 0
        row = j if saved else j - 1
        if n_probe > 0:
            _gaps_of(z, v, Phis[cur], qs, vs, meshes, G0)
        for sub in range(max_sub):
            if n_probe > 0:
                code = forced if forced >= 0 else _op_code(G0, pat, stride)
                new = op_of[code]
                if new != cur:
                    _rotate(Ys[cur], Ys[new], z, v, z1, v1)
                    cur = new
                    Pc = _op_system(P, X, cur)
            else:
                _matvec2(Phis[cur], z, v, qs, vs)
            # the envelope at the piece's start (qs, vs: its state on the force DOFs); its
            # time goes to the contact state held over the piece, added when its length is
            # known (after a located change: the state the crossing leads to, from Gs)
            _envelope_forces(row, saved and sub == 0, qs, vs, meshes, env, held)
            if forced >= 0:
                _held_states(Gs, held)
            om = oms[cur]
            _etd_substep(t, left, z, v, om, coefs[cur] if sub == 0 else none, Pc, W, L, z1, v1)
            if sub == 0 and saved:
                # the step's start: η̈ = N − μζ from the first stage (no extra evaluation)
                status = _record_etd(j, t, z, v, L[3], om, Phi_outs[cur], alphas[cur], rec, acc)
                j += 1
                if status != STATUS_OK:
                    done = step
                    break
            if sub == max_sub - 1 or n_probe == 0:
                _envelope_time(row, left, held, env)
                break
            _gaps_of(z1, v1, Phis[cur], qs, vs, meshes, G1)
            frac, code = _first_event(G0, G1, left, n_probe, pat, stride, code, Gs)
            if frac > 1.0:
                _envelope_time(row, left, held, env)
                break
            # redo up to the crossing, then continue with the new state's operator
            tau = frac * left
            _envelope_time(row, tau, held, env)
            _etd_substep(t, tau, z, v, om, none, Pc, W, L, z1, v1)
            for i in range(m):
                z[i] = z1[i]
                v[i] = v1[i]
            t += tau
            left -= tau
            extra += 1
            _gaps_of(z, v, Phis[cur], qs, vs, meshes, G0)
            # the state the crossing leads to, whatever round-off says at the crossing itself
            forced = code
        if status != STATUS_OK:
            break
        for i in range(m):
            z[i] = z1[i]
            v[i] = v1[i]
    # back to modal coordinates η = Y ζ
    Y = Ys[cur]
    for i in range(m):
        a = 0.0
        b = 0.0
        for c in range(m):
            a += Y[i, c] * z[c]
            b += Y[i, c] * v[c]
        e[i] = a
        de[i] = b
    return status, done, extra
