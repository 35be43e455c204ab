"""The arrays the compiled kernels take for a run, per method: the full model for :class:`RK4`
(sparse matrices, the block Cholesky factor of M, the θ̈ coupling terms) and the modal
reduction for :class:`ModalRK4` (:mod:`.reduction`); both check the step against RK4's
stability region (:mod:`.step_limits`)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components

from ...errors import ModelError, SolverError
from ...threads import limit as thread_limit
from ..csr import Csr, csr
from ..torsional.drive_laws import P_WLINE
from .equations import TransientSystem
from .forces import _drive_laws, _force_dofs, pack_forces
from .kernels import (
    ContactOperators,
    ImplicitTerms,
    MassFactor,
    MeshLaws,
    ModalModel,
    ModalWork,
    PhysicalModel,
    PhysicalWork,
    Stages,
    Woodbury,
    etd_coefficients,
)
from .options import RK4, ModalRK4, excitation_frequency
from .reduction import (
    ModalBases,
    _dense,
    _gyroscopic,
    _harmonic_error,
    _harmonic_shapes,
    _static_shapes,
    basis_stiffness,
    full_model,
    linear_damping,
    reduced_gyroscopic,
    skew_block,
)
from .step_limits import _etd_unstable, _linearised, _rk4_step_limit, _unstable_step


@dataclass
class _Prepared:
    kind: str
    dt: float
    n_state: int
    model: PhysicalModel | ModalModel
    work: PhysicalWork | ModalWork
    stages: Stages
    out: NDArray  # active output DOFs
    Phi_out: NDArray | None
    info: dict
    # the exact-linear modal scheme's operators per contact state (kernels.etd_modal)
    operators: ContactOperators | None = None

    @property
    def drive_state(self) -> NDArray:
        """The drives' event state inside the model (synchronous motors' pull-in), saved
        with checkpoints."""
        return self.model.forces.drives.state


def _woodbury(rows: int, n: int, r: int) -> Woodbury:
    """The :class:`~.kernels.Woodbury` work of rank r: Z (rows, n)."""
    return Woodbury(np.zeros((rows, n)), np.zeros((r, r)), np.zeros(r), np.zeros(r, np.int64))


def _mass_factor(M: sp.csr_array) -> tuple[MassFactor, NDArray]:
    """Sparse Cholesky factor of M, block by block (M's connected components, each banded in
    node order): returns the :class:`~.kernels.MassFactor` (perm, L: diagonal last in each
    row, U = Lᵀ: diagonal first, with ``M[perm][:, perm] = L Lᵀ``), and the component label of
    every DOF."""
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
    return MassFactor(perm.astype(np.int64), csr(L), csr(L.T)), labels


def _prepare_physical(system: TransientSystem, integ: RK4, out: NDArray, frozen: bool) -> _Prepared:
    n = system.n
    sel = _force_dofs(system)
    G = sum((g for g in system.G), sp.csr_array((n, n)))
    mass, comp = _mass_factor(system.M)
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
    speed_rows = Csr(np.array(a_ptr, np.int64), np.array(a_idx, np.int64), np.array(a_w, float))
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
    forces = pack_forces(system, sel, modal=False, bearing_ref=False)
    model = PhysicalModel(
        K=csr(system.K),
        C=csr(system.C),
        G=csr(G),
        row_shaft=system.shaft_of_row.astype(np.int64),
        mass=mass,
        speed_rows=speed_rows,
        torsion=np.flatnonzero(system.torsion).astype(np.int64),
        frozen=bool(frozen),
        reactions=bool(system.reactions),
        sel=sel,
        forces=forces,
        implicit=ImplicitTerms(
            Minv_a,
            *Minv_u,
            system.unbalance_dofs.astype(np.int64).reshape(-1, 3),
            z_ptr,
            z_idx,
            g_ptr,
            g_idx,
        ),
    )
    r = 2 * (ns + len(ud))
    nsel = len(sel)
    work = PhysicalWork(
        F=np.zeros(n),
        gq=np.zeros(n),
        zq=np.zeros(n),
        qs=np.zeros(nsel),
        vs=np.zeros(nsel),
        fs=np.zeros(nsel),
        Om=np.zeros(ns),
        wb=_woodbury(max(r, 1), n, r),
        y=np.zeros(n),
    )
    stages = Stages(*(np.zeros(n) for _ in range(10)))
    return _Prepared("physical", integ.dt, n, model, work, stages, out, None, {"n_dof": n})


def _linear_growth(Phi: NDArray, K: NDArray, CG: NDArray, M: NDArray | None = None) -> float:
    """Largest growth rate (1/s) of the linear model projected on Φ (M-orthonormal; ``M``
    given: the full model, Φ = I) beyond round-off (1e-7 of the largest |λ|), else 0."""
    Kr, Cr = Phi.T @ K @ Phi, Phi.T @ CG @ Phi
    m = Kr.shape[0]
    if M is not None:
        Kr, Cr = la.solve(M, Kr), la.solve(M, Cr)
    A = np.block([[np.zeros((m, m)), np.eye(m)], [-Kr, -Cr]])
    with thread_limit(2 * m, "eig"):
        lam = la.eigvals(A)
    g = float(lam.real.max())
    return g if g > 1e-7 * float(np.abs(lam).max()) else 0.0


def _pad_shapes(system: TransientSystem) -> NDArray:
    """Unit vectors (n, k) on the active pad DOFs and the journals of the bearings with pad
    dynamics (none without them)."""
    cols = []
    for b in system.assembly.bearings:
        if b.pad_dofs is None:
            continue
        for g in b.local()[0]:
            i = system.index(int(g))
            if i >= 0:
                e = np.zeros(system.n)
                e[i] = 1.0
                cols.append(e)
    return np.array(cols).T.reshape(system.n, -1)


def _prepare_modal(
    system: TransientSystem, integ: ModalRK4, out: NDArray, save_dt: float | None = None
) -> _Prepared:
    M, K, C = system.linear_matrices()
    # modes of the symmetric part of K; its skew part (cross-coupled bearings and seals) acts
    # as a force on its few DOFs (kernel: k_idx, k_skew)
    Ks = basis_stiffness(system, K)  # 0.5 (K + Kᵀ), pad blocks made semidefinite
    Ka = K - Ks
    # sparse on a large model (reduction.SPARSE_FROM), where the modes below the cut-off in use
    # are solved by shift-invert Lanczos instead of all of them densely (reduction.Spectrum)
    M, K, C, Ks, Ka = full_model(system, M, K, C, Ks, Ka)
    wcut = (
        2 * np.pi * integ.cutoff
        if integ.cutoff is not None
        else (integ.cutoff_factor * excitation_frequency(system))
    )
    backlash = any(law.backlash > 0 for law in system.meshes)
    separated = integ.separated_modes
    if separated is None:
        separated = "torsional" if backlash else False
    bases = ModalBases(system, M, Ks, separated)
    static = integ.static_correction
    l_dof = _drive_laws(system)[1]
    if static is None:
        # torques load the mesh through its compliance; with backlash the mesh force drops to
        # zero in separation, a rank-one change along w whose response the modes plus the
        # static shape under w span (see ModalRK4)
        static = (
            len(system.torque_dof) + len(l_dof) > 0 or backlash or system.constant_force is not None
        )
    # drives and loads get static correction shapes as the external torques do
    torqued = replace(system, torque_dof=np.concatenate([system.torque_dof, l_dof]))
    shapes = _static_shapes(torqued, M, K) if static else np.zeros((system.n, 0))
    pad_shapes = _pad_shapes(system)
    if pad_shapes.shape[1]:
        # tilting pads with pad dynamics: every pad coordinate in the basis (a few DOFs per
        # bearing), so that the pads' film coupling, much of it one-sided (K − Ks), is carried
        # whole and not through truncated modes
        shapes = np.hstack([shapes, pad_shapes])
    Phi, w2r = bases.basis(wcut, shapes)
    check = _harmonic_error(system, M, K, C, Phi, w2r, out, Ka)
    if integ.cutoff is None and check > integ.tolerance:
        # the modes above the cut-off carry part of the 1x response (their quasi-static
        # compliance, heavily damped bearings): add the full model's 1x response shapes
        # before raising the cut-off (issue 16: 173 → 65 modes for the compressor example)
        shapes = np.hstack([shapes, _harmonic_shapes(system, M, K, C)])
        Phi, w2r = bases.basis(wcut, shapes)
        check = _harmonic_error(system, M, K, C, Phi, w2r, out, Ka)
    while integ.cutoff is None and check > integ.tolerance and wcut < bases.omega_max:
        wcut *= 1.25
        Phi, w2r = bases.basis(wcut, shapes)
        check = _harmonic_error(system, M, K, C, Phi, w2r, out, Ka)
    if integ.cutoff is None and check > integ.tolerance:
        raise SolverError(
            f"the modal reduction cannot reach the requested 1x accuracy: with every mode "
            f"kept the reduced model's linear unbalance response is {check:.3g} off the full "
            f"model's (tolerance {integ.tolerance:g}); use the RK4 method"
        )
    if pad_shapes.shape[1]:
        # with pad dynamics much of the stiffness is one-sided (K − Ks): a truncated basis may
        # turn it into a growing mode the full model does not have; raise the cut-off until
        # the reduced linear model is as stable as the full one
        full = None
        CG = C + _gyroscopic(system, C)
        while (grow := _linear_growth(Phi, K, CG)) > 0.0:
            if full is None:
                full = _linear_growth(np.eye(system.n), *map(_dense, (K, CG, M)))
            if full > 0.0 or integ.cutoff is not None or wcut >= bases.omega_max:
                break
            wcut *= 1.25
            Phi, w2r = bases.basis(wcut, shapes)
        else:
            grow = 0.0
        check = _harmonic_error(system, M, K, C, Phi, w2r, out, Ka)
    lam = np.clip(w2r, 0.0, None)
    om = np.sqrt(lam)
    lam[om < 1e-6 * max(om.max(), 1.0)] = 0.0  # rigid-body modes exactly
    m = Phi.shape[1]
    C_lin = linear_damping(system, C)
    limit, lam_lim = _rk4_step_limit(
        np.eye(m), np.diag(lam) + Phi.T @ Ka @ Phi, Phi.T @ C_lin @ Phi
    )
    exact = integ.exact_linear if integ.exact_linear is not None else backlash
    dt = integ.dt
    # the drives' fastest torque: 2 f_line (synchronous start-up pulsation at standstill,
    # two-phase short circuit), resolved like the highest kept mode
    w_drive = 2.0 * float(np.max(_drive_laws(system)[0].par[:, P_WLINE], initial=0.0))
    if dt is None and exact:
        # the oscillators are exact: the step resolves the excitation (4 steps per period
        # of the highest mesh frequency, ω·dt = π/2) and the drives
        dt = min(0.5 * np.pi / excitation_frequency(system), integ.accuracy / max(w_drive, 1e-9))
        if save_dt is not None:
            # records are taken at step starts: a whole number of steps per save interval
            dt = save_dt / np.ceil(save_dt / dt * (1 - 1e-9))
    elif dt is None:
        dt = min(integ.accuracy / max(float(om.max()), w_drive, 1e-9), 0.95 * limit)
    if dt >= 0.995 * limit and not exact:
        raise _unstable_step("modal RK4", dt, limit, lam_lim, " or lower the cut-off")
    k_dofs, Ka_k = skew_block(Ka)
    sel = np.union1d(_force_dofs(system), k_dofs).astype(np.int64)
    Cr = Phi.T @ C @ Phi
    Gr = reduced_gyroscopic(system, Phi)
    alpha = np.array([Phi.T @ a for a in system.a_weights])  # Ω_s = a_sᵀ Φ η̇
    ns = len(system.a_weights)
    nu = len(system.unbalance_dofs)
    r = 2 * (ns + nu)
    forces = pack_forces(system, sel, modal=True, bearing_ref=True)
    model = ModalModel(
        lam=lam,
        Cr=np.ascontiguousarray(Cr),
        Gr=np.ascontiguousarray(Gr),
        alpha=np.ascontiguousarray(alpha),
        Phi_sel=np.ascontiguousarray(Phi[sel]),
        PhiT_sel=np.ascontiguousarray(Phi[sel].T),
        reactions=bool(system.reactions),
        k_idx=np.searchsorted(sel, k_dofs).astype(np.int64),
        k_skew=np.ascontiguousarray(Ka_k),
        forces=forces,
    )
    nsel = len(sel)
    work = ModalWork(
        qs=np.zeros(nsel),
        vs=np.zeros(nsel),
        fs=np.zeros(nsel),
        Om=np.zeros(ns),
        wb=_woodbury(2 * max(r, 1), m, r),
        gq=np.zeros((ns, m)),
    )
    stages = Stages(*(np.zeros(m) for _ in range(10)))
    operators = None
    if exact:
        operators = _contact_operators(system, model, Phi, out, dt)
        Bk = -Phi.T @ Ka @ Phi
        Bc = -Phi.T @ C_lin @ Phi
        while (
            grow := max(
                _etd_unstable(om_j, C_j, Y.T @ Bk @ Y, Y.T @ Bc @ Y, dt)
                for Y, om_j, C_j in zip(operators.Ys, operators.oms, operators.coefs, strict=True)
            )
        ) > 1.0 + 1e-6:
            if integ.dt is not None:
                raise SolverError(
                    f"modal exponential RK4 step dt = {dt:.4g} s amplifies the damped modes of "
                    f"the reduced model (growth {grow:.6g} per step beyond the model's own); "
                    "use a smaller dt (the default is reduced until it is stable)"
                )
            dt *= 0.8
            if save_dt is not None:
                dt = save_dt / np.ceil(save_dt / dt * (1 - 1e-9))
            operators = _contact_operators(system, model, Phi, out, dt)
    info = {
        "n_modes": m,
        "cutoff_hz": wcut / 2 / np.pi,
        "harmonic_error": check,
        "highest_mode_hz": float(om.max() / 2 / np.pi),
        "Phi": Phi,
        "M": M,
    }
    return _Prepared(
        "modal",
        dt,
        m,
        model,
        work,
        stages,
        out,
        np.ascontiguousarray(Phi[out]),
        info,
        operators=operators,
    )


def _contact_operators(
    system: TransientSystem, model: ModalModel, Phi: NDArray, out: NDArray, dt: float
) -> ContactOperators:
    """The linear operators of the exact-linear modal scheme (:func:`.kernels.etd_modal`),
    one per combination of the meshes' contact states: diag(Λ) (every mesh engaged at Kg on
    its drive line, as the modal basis is built) with Kg w wᵀ removed from the meshes whose
    teeth are apart (and, for the mirrored back flank, Kg w_b w_bᵀ added while it touches);
    its eigenvectors Y (orthonormal: η = Y ζ), frequencies ω (rad/s), the ETD weights of the
    step and the reduced system in its coordinates (the mesh stiffness it holds not subtracted
    again)."""
    meshes: MeshLaws = model.forces.meshes
    m_sel, m_w = meshes.dofs, meshes.lines
    lam0, Cr, Gr, alpha, Phi_sel = model.lam, model.Cr, model.Gr, model.alpha, model.Phi_sel
    m = len(lam0)
    nm = len(system.meshes)
    pats = np.zeros((nm, 4), np.int64)
    radix = []
    for k in range(nm):
        same = np.allclose(m_w[k, 1], -m_w[k, 0])
        # state index s = drive touching + 2·back touching → pattern (bit 0 drive, 1 back)
        pats[k] = [0, 1, 1, 1] if same else [0, 1, 2, 3]
        radix.append(2 if same else 4)
    stride = np.concatenate([[1], np.cumprod(radix)[:-1]]).astype(np.int64)
    n_ops = int(np.prod(radix))
    if n_ops > 64:
        raise ModelError(
            f"the exact-linear modal scheme needs one operator per combination of contact "
            f"states, {n_ops} for these meshes",
            field="exact_linear",
            value=True,
            expected="at most 64 combinations (fewer meshes, or exact_linear=False)",
        )
    u = np.zeros((nm, 2, m))
    for k in range(nm):
        for j in range(12):
            if m_sel[k, j] >= 0:
                u[k, 0] += m_w[k, 0, j] * Phi_sel[m_sel[k, j]]
                u[k, 1] += m_w[k, 1, j] * Phi_sel[m_sel[k, j]]
    Ys = np.zeros((n_ops, m, m))
    oms = np.zeros((n_ops, m))
    kg_linear = np.zeros((n_ops, nm))
    kg_back_linear = np.zeros((n_ops, nm))
    for code in range(n_ops):
        Kc = np.diag(lam0).astype(float)
        changed = False
        for k, law in enumerate(system.meshes):
            p = (code // stride[k]) % radix[k]
            drive, back = (p, 0) if radix[k] == 2 else (p & 1, (p >> 1) & 1)
            kg_linear[code, k] = law.kg * drive
            kg_back_linear[code, k] = law.kg * back
            if not drive:
                Kc -= law.kg * np.outer(u[k, 0], u[k, 0])
                changed = True
            if back:
                Kc += law.kg * np.outer(u[k, 1], u[k, 1])
                changed = True
        if not changed:
            Ys[code] = np.eye(m)
            oms[code] = np.sqrt(lam0)
            continue
        mu, Y = la.eigh(0.5 * (Kc + Kc.T))
        mu = np.clip(mu, 0.0, None)
        mu[mu < 1e-12 * max(mu.max(), 1.0)] = 0.0
        Ys[code] = Y
        oms[code] = np.sqrt(mu)
    op_of = np.arange(n_ops, dtype=np.int64)
    coefs = np.zeros((n_ops, 12, m))
    for code in range(n_ops):
        etd_coefficients(oms[code], dt, coefs[code])
    rot = np.ascontiguousarray
    Phis = np.array([rot(Phi_sel @ Y) for Y in Ys])
    return ContactOperators(
        Ys=Ys,
        oms=oms,
        coefs=coefs,
        pat=pats,
        stride=stride,
        op_of=op_of,
        # contact changes change the operator only with backlash or a mirrored back flank
        n_probe=8 if any(law.backlash > 0 for law in system.meshes) or 4 in radix else 0,
        max_sub=16,
        lams=oms**2,
        Crs=np.array([Y.T @ Cr @ Y for Y in Ys]),
        Grs=np.array([[Y.T @ g @ Y for g in Gr] for Y in Ys]).reshape(n_ops, *Gr.shape),
        alphas=np.array([alpha @ Y for Y in Ys]).reshape(n_ops, *alpha.shape),
        Phis=Phis,
        PhiTs=np.array([rot(p.T) for p in Phis]),
        kg_linear=kg_linear,
        kg_back_linear=kg_back_linear,
        Phi_outs=np.array([rot(Phi[out] @ Y) for Y in Ys]),
    )
