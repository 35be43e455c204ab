"""Equations of motion of the nonlinear transient (SPEC 2.5), resolved to arrays.

State: the global DOF vector q (``x, y, z, θx, θy, θz`` per node, θz the *absolute* angle) and
q̇. The equations are the Lagrange equations of

    T = ½ q̇ᵀ M q̇ + Σ_s ½ Ω_s q̇ᵀ G_s q + Σ_u m e_u (c_uᵀq̇)(s_uᵀq̇),   V = ½ qᵀ K q + V_mesh,

which give

    (M + U(q)) q̈ + (C + Σ_s Ω_s G_s) q̇ + K q = f_mesh + f_brg + f_unb + T_ext,
    U(q) = Σ_s (a_s g_sᵀ + g_s a_sᵀ) + Σ_u m e_u (c_u s_uᵀ + s_u c_uᵀ),   g_s = ½ G_s q,

where

* ``Ω_s = a_sᵀ q̇`` is the spin speed of shaft s: the polar-inertia weighted mean of its nodes'
  θ̇z (its angular momentum about the axis over its polar inertia). The gyroscopic matrix of the
  shaft (per unit speed, from the assembly) is scaled by this instantaneous speed. Twist makes
  node speeds differ by far less than 0.1 %, so per-element speeds would change nothing
  measurable, while the per-shaft choice keeps the angular-acceleration terms rank 2 per shaft
  (exact low-rank solve) and the reduced gyroscopic matrix a sum Σ Ω_s G_sʳ.
* ``G̃(θ̈z) q = ½ Ω̇_s G_s q`` is the angular-acceleration term of disks and shaft elements: the
  symmetric split ``T = ½ Ω q̇ᵀ G q`` of the spin–tilt coupling (for a disk
  ``½ Ip Ω (θ̇x θy − θ̇y θx)``). Its reaction ``½ q̈ᵀ G_s q`` appears in the torsional rows.
* unbalance u at node angle θ = θz + φ: ``c_u`` selects θz, ``s_u = −sin θ e_x + cos θ e_y`` and
  ``r_u = cos θ e_x + sin θ e_y``; the force is ``m e (θ̇² r_u − θ̈ s_u)``, i.e.
  ``F_x = m e (θ̇² cos θ + θ̈ sin θ)``, ``F_y = m e (θ̇² sin θ − θ̈ cos θ)`` (SPEC 2.5), and the
  reaction torque on the node is ``m e (ẍ sin θ − ÿ cos θ)``.

With ``reactions=False`` the reaction rows are dropped (the dissertation's form: the lateral
equations only carry the θ̈ terms). The θ̈ (and, with reactions, ẍ, ÿ) terms are implicit; they
are solved exactly at every evaluation by the Woodbury identity on the low-rank U (rank
2·(shafts + unbalances)), never by fixed-point iteration.

The gear mesh is *not* in K: its force is ``−F w`` on the 12 DOFs of the two gear nodes with
``F = k(φ_m) h(δ − e(φ_m)) + c (δ̇ − ė)`` (damping only in contact), see :mod:`.mesh`.
Speed-dependent bearings (coefficient tables) are applied as forces with the coefficients at the
shaft's instantaneous speed; constant bearings, couplings, thrust bearings and cross-coupling
stay in K and C. Tilting-pad bearings with pad dynamics (:class:`~gearrotor.elements.PadBearing`)
are linearised at the operating point: their full film matrices at the nominal shaft speed are in
K and C over the journal, the housing and the pad DOFs, and the pads' inertia is in M, so the pad
equations are integrated with the rotor (the nonlinear film, and coefficients that follow the
instantaneous speed, are a later step).

The shafts' material damping is in C. The circulatory stiffness of rotating (internal) material
damping, Σ_s Ω_s Kc_s, is in K at the *nominal* shaft speeds (not at the instantaneous Ω_s(t),
which would need a term Ω_s(t) Kc_s q in the kernels): exact with ``frozen_speed``, and off by
the relative speed deviation ΔΩ/Ω of that term otherwise (small in steady operation; a run-up
from rest is not represented correctly).

Active DOFs: groups of DOFs that no element couples to anything forced and that start at rest
(e.g. the axial DOFs of a spur-gear train without thrust load) stay exactly zero and are
removed; this is exact, and it removes the stiff axial rods from the explicit step limit.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components

from ...assembly import Assembly, _Triplets, assemble
from ...errors import ModelError
from ...model import Train
from ..torsional.drive_laws import check_transient_supports
from .mesh import MeshLaw, mesh_laws

__all__ = ["TransientSystem", "build_system", "mesh_damping_from_ratio"]


@dataclass(frozen=True)
class TransientSystem:
    """The transient equations of a train as arrays over the active DOFs (SI units).

    ``active`` (n,) maps active index → global DOF. Matrices are (n, n) CSR over active DOFs.
    """

    assembly: Assembly = field(repr=False)
    active: NDArray
    M: sp.csr_array
    K: sp.csr_array  # without the gear meshes and speed-dependent bearings; Σ Ω_s Kc_s included
    C: sp.csr_array  # without the gear meshes and speed-dependent bearings
    G: tuple[sp.csr_array, ...]  # per shaft, per unit speed
    Kc: tuple[sp.csr_array, ...]  # per shaft, per unit speed (in K at the nominal speeds)
    shaft_of_row: NDArray  # (n,) shaft of each active DOF (−1: pedestal)
    torsion: NDArray  # (n,) bool: θz DOFs
    a_weights: tuple[NDArray, ...]  # per shaft: (n,) weights, Ω_s = a_s · q̇
    nominal_speeds: NDArray  # (n_shafts,) rad/s
    meshes: tuple[MeshLaw, ...]
    mesh_dofs: NDArray  # (n_mesh, 12) active indices (−1: inactive DOF, w entry is 0)
    unbalance_dofs: NDArray  # (n_unb, 3) active indices of x, y, θz
    unbalance_me: NDArray  # (n_unb,) kg·m
    unbalance_phase: NDArray  # (n_unb,) rad
    torque_dof: NDArray  # (n_torque,) active θz index
    bearing_dofs: NDArray  # (n_brg, 4): journal x, y, pedestal x, y (−1 for ground)
    bearing_shaft: NDArray  # (n_brg,)
    bearing_dynamic: NDArray  # (n_brg,) bool: speed-dependent (applied as a force)
    reactions: bool = True
    # constant loads (n,) over active DOFs (an operating point's weight, static forces and the
    # fluid-film journals' static load), or None; applied like constant torques
    constant_force: NDArray | None = None
    # (n_brg, 2) constant part of each journal's force, N on the journal (an operating point's
    # linearised film force about its static equilibrium), or None
    bearing_preload: NDArray | None = None

    @property
    def n(self) -> int:
        return len(self.active)

    @property
    def train(self) -> Train:
        return self.assembly.train

    def index(self, global_dof: int) -> int:
        """Active index of a global DOF (−1 when the DOF is inactive)."""
        pos = np.searchsorted(self.active, global_dof)
        if pos < len(self.active) and self.active[pos] == global_dof:
            return int(pos)
        return -1

    def initial_state(self) -> tuple[NDArray, NDArray]:
        """Zero displacement, every node of a shaft at the shaft's nominal speed."""
        q0 = np.zeros(self.n)
        v0 = np.zeros(self.n)
        for s, a in enumerate(self.a_weights):
            v0[a != 0] = self.nominal_speeds[s]
        return q0, v0

    def linear_matrices(self, meshes: bool = True) -> tuple[NDArray, NDArray, NDArray]:
        """Dense (M, K, C) of the constant-speed linear model at the nominal speeds: the meshes
        at their average stiffness Kg (no damping; left out with ``meshes=False``), bearings at
        the nominal speeds."""
        K = self.K.toarray()
        C = self.C.toarray()
        for law, d in zip(self.meshes if meshes else (), self.mesh_dofs, strict=False):
            ok = d >= 0
            K[np.ix_(d[ok], d[ok])] += law.kg * np.outer(law.w[ok], law.w[ok])
        for b, d in enumerate(self.bearing_dofs):
            if not self.bearing_dynamic[b]:
                continue
            el = self.assembly.bearings[b].element
            sp_ = self.nominal_speeds[self.bearing_shaft[b]]
            k, c = el.K(sp_), el.C(sp_)
            idx = d[:2] if d[2] < 0 else d
            if d[2] >= 0:
                k = np.block([[k, -k], [-k, k]])
                c = np.block([[c, -c], [-c, c]])
            K[np.ix_(idx, idx)] += k
            C[np.ix_(idx, idx)] += c
        return self.M.toarray(), K, C

    def at_speed(self, speed: float) -> TransientSystem:
        """The system at reference-shaft speed ``speed`` (rad/s): the nominal shaft speeds and
        the circulatory stiffness of rotating damping in K re-evaluated there."""
        speeds = self.assembly.shaft_speeds(speed)
        K = self.K
        for new, old, kc in zip(speeds, self.nominal_speeds, self.Kc, strict=True):
            if kc.nnz and new != old:
                K = K + (new - old) * kc
        return replace(self, nominal_speeds=np.asarray(speeds, float), K=sp.csr_array(K))

    def mesh_rates(self) -> NDArray:
        """(n_mesh,) rad/s, signed: the rate of each mesh angle φ_m = N_i θ_i at the nominal
        speeds (its absolute value is the mesh frequency)."""
        return np.array(
            [
                law.teeth * self.nominal_speeds[self.assembly.meshes[k].shafts[0]]
                for k, law in enumerate(self.meshes)
            ],
            float,
        )

    def gyroscopic(self, speeds: NDArray | None = None) -> NDArray:
        """Dense Σ_s Ω_s G_s at the given (default nominal) shaft speeds."""
        speeds = self.nominal_speeds if speeds is None else speeds
        out = np.zeros((self.n, self.n))
        for s, g in zip(speeds, self.G, strict=True):
            out += s * g.toarray()
        return out


def _pattern(m: sp.sparray, n: int) -> sp.csr_array:
    m = sp.csr_array(m)
    return sp.csr_array((np.ones(m.nnz), m.indices, m.indptr), shape=(n, n))


def build_system(
    model: Train | Assembly,
    *,
    frozen_speed: bool = False,
    reactions: bool = True,
    initial_q: NDArray | None = None,
    stiffness_tables: dict[int, tuple[NDArray, NDArray]] | None = None,
    transmission_error: dict[int, NDArray] | None = None,
    back_flank: str = "same",
    constant_force: NDArray | None = None,
    bearing_preload: NDArray | None = None,
) -> TransientSystem:
    """Resolve a train to the arrays of the transient equations.

    frozen_speed : θz prescribed as nominal rigid rotation (constant speed); the torsional DOFs
        are then still in the state but their accelerations are zero.
    initial_q : (n_dof,) global initial displacement (makes its DOFs active).
    stiffness_tables, transmission_error, back_flank : see :func:`.mesh.mesh_laws`.
    constant_force : (n_dof,) global constant loads (an operating point's static loads), N and
        N·m; bearing_preload : (n_brg, 2) their part that is a journal's film force (reported
        with the bearing forces).
    """
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    check_transient_supports(train)  # no torsional spring to ground on the absolute angle
    n_all = asm.n_dof
    kind = asm.dof_kind()
    speeds = asm.shaft_speeds(train.speed)

    # ---- meshes out of K and C (they become nonlinear forces) -------------------------------
    K = sp.lil_array(asm.K0 + asm.circulatory(speeds))
    C = sp.lil_array(asm.C0)
    for m in asm.meshes:
        ww = np.outer(m.w, m.w)
        K[np.ix_(m.dofs, m.dofs)] = K[np.ix_(m.dofs, m.dofs)].toarray() - m.stiffness * ww
        C[np.ix_(m.dofs, m.dofs)] = C[np.ix_(m.dofs, m.dofs)].toarray() - m.damping * ww
    K = sp.csr_array(K)
    C = sp.csr_array(C)
    # tilting pads with pad dynamics: full matrices at the nominal speed (module docstring)
    Kp, Cp = _Triplets(), _Triplets()
    for b in asm.bearings:
        if b.pad_dofs is not None:
            b.scatter(Kp, Cp, speeds[b.shaft])
    K = K + Kp.csr(n_all)
    C = C + Cp.csr(n_all)
    # round-off of the subtraction: drop entries far below the matrix scale
    for A in (K, C):
        if A.nnz:
            A.data[np.abs(A.data) < 1e-12 * np.abs(A.data).max()] = 0.0
            A.eliminate_zeros()
    for m in asm.meshes:
        ri, rj = m.geometry.radius_i, m.geometry.radius_j
        ni, nj = m.teeth
        if abs(ri / rj - ni / nj) > 1e-9 * ni / nj:
            raise ModelError(
                "transient analysis needs pitch radii exactly in the tooth ratio (the absolute "
                "angles roll at N_i θ_i = −N_j θ_j; any mismatch grows into a mesh deflection)",
                field=f"meshes[{m.spec_index}]",
                value=f"r_i/r_j = {ri / rj:.9g}, N_i/N_j = {ni / nj:.9g}",
                expected="r_i/r_j = N_i/N_j",
            )

    # ---- couplings of the dynamics: which DOFs can move -------------------------------------
    pat = _pattern(asm.M, n_all) + _pattern(K, n_all) + _pattern(C, n_all)
    for g in asm.G_shaft:
        pat = pat + _pattern(g, n_all)
    extra_r, extra_c = [], []

    def link(dofs):
        dofs = np.asarray(dofs)
        r, c = np.meshgrid(dofs, dofs, indexing="ij")
        extra_r.append(r.ravel())
        extra_c.append(c.ravel())

    forced = np.zeros(n_all, bool)
    for m in asm.meshes:
        nz = m.dofs[np.abs(m.w) > 1e-14]
        link(nz)
        forced[nz] = True
    for b in asm.bearings:
        link(b.local()[0])
    unb = []
    for k, u in enumerate(train.unbalances):
        si, node = train.node_index(u, f"unbalances[{k}]")
        d = asm.node_offset[si][node] + np.array([0, 1, 5])
        link(d)
        forced[d] = True
        unb.append((d, u.amount, u.phase))
    tq = []
    for k, t in enumerate(train.torques):
        si, node = train.node_index(t, f"torques[{k}]")
        d = asm.node_offset[si][node] + 5
        forced[d] = True
        tq.append(d)
    forced[kind == 2] = True  # every node spins
    if initial_q is not None:
        initial_q = np.asarray(initial_q, float)
        if initial_q.shape != (n_all,):
            raise ModelError(
                "initial displacement has the wrong length",
                value=initial_q.shape,
                expected=f"({n_all},) global DOFs",
            )
        forced |= initial_q != 0
    if constant_force is not None:
        constant_force = np.asarray(constant_force, float)
        if constant_force.shape != (n_all,):
            raise ValueError(f"constant_force must have shape ({n_all},)")
        forced |= constant_force != 0
    if extra_r:
        r = np.concatenate(extra_r)
        c = np.concatenate(extra_c)
        pat = pat + sp.csr_array((np.ones(len(r)), (r, c)), shape=(n_all, n_all))
    _, labels = connected_components(pat, directed=False)
    active = np.flatnonzero(np.isin(labels, np.unique(labels[forced])))
    pos = -np.ones(n_all, int)
    pos[active] = np.arange(len(active))

    def sub(A):
        return sp.csr_array(sp.csr_array(A)[active][:, active])

    Ma = sub(asm.M)
    n = len(active)
    torsion = kind[active] == 2
    shaft_of_row = -np.ones(n, int)
    a_w = []
    Mdiag_rows = np.asarray(Ma.sum(axis=1)).ravel()
    for s, offs in enumerate(asm.node_offset):
        rows = pos[np.concatenate([offs + j for j in range(6)])]
        shaft_of_row[rows[rows >= 0]] = s
        tz = pos[offs + 5]
        a = np.zeros(n)
        a[tz] = Mdiag_rows[tz]
        if a.sum() <= 0:
            raise ModelError(
                "a shaft without polar inertia cannot spin in a transient", field=f"shafts[{s}]"
            )
        a_w.append(a / a.sum())

    # model-file tables and transmission errors; explicit arguments take precedence
    tables = {
        k: (np.asarray(m.stiffness_table.angle), np.asarray(m.stiffness_table.stiffness))
        for k, m in enumerate(train.meshes)
        if m.stiffness_table is not None
    }
    tables.update(stiffness_tables or {})
    errors = {
        k: np.column_stack([m.transmission_error.cos, m.transmission_error.sin])
        for k, m in enumerate(train.meshes)
        if m.transmission_error is not None and m.transmission_error.cos
    }
    # meshes from their tooth geometry: the loaded TVMS and transmission error (issue 27)
    for m in asm.meshes:
        spec = train.meshes[m.spec_index]
        if spec.excitation_law == "geometry" and m.spec_index not in (stiffness_tables or {}):
            from ...gears.model_mesh import mesh_law_arrays, model_mesh

            direction = m.teeth[0] * speeds[m.shafts[0]] or asm.speed_ratio[m.shafts[0]]
            curves = model_mesh(train, m.spec_index).curves
            phi, k_phi, te = mesh_law_arrays(curves, direction, spec.variation.phase)
            tables[m.spec_index] = (phi, k_phi)
            given = errors.get(m.spec_index)  # the model's own (profile, pitch) errors add
            if given is not None:
                n = max(len(given), len(te))
                te = np.pad(te, ((0, n - len(te)), (0, 0))) + np.pad(
                    np.asarray(given, float), ((0, n - len(given)), (0, 0))
                )
            errors[m.spec_index] = te
    errors.update(transmission_error or {})
    laws = mesh_laws(
        train,
        asm,
        stiffness_tables=tables,
        transmission_error=errors,
        back_flank=back_flank,
    )
    mesh_dofs = np.array([pos[m.dofs] for m in asm.meshes], int).reshape(-1, 12)
    brg = []
    for b in asm.bearings:
        d = list(pos[b.dofs]) + (
            list(pos[b.support_dofs]) if b.support_dofs is not None else [-1, -1]
        )
        brg.append(d)
    system = TransientSystem(
        assembly=asm,
        active=active,
        M=Ma,
        K=sub(K),
        C=sub(C),
        G=tuple(sub(g) for g in asm.G_shaft),
        Kc=tuple(sub(kc) for kc in asm.Kc_shaft),
        shaft_of_row=shaft_of_row,
        torsion=torsion,
        a_weights=tuple(a_w),
        nominal_speeds=np.asarray(speeds, float),
        meshes=laws,
        mesh_dofs=mesh_dofs,
        unbalance_dofs=np.array([pos[d] for d, _, _ in unb], int).reshape(-1, 3),
        unbalance_me=np.array([a for _, a, _ in unb], float),
        unbalance_phase=np.array([p for _, _, p in unb], float),
        torque_dof=np.array([pos[d] for d in tq], int),
        bearing_dofs=np.array(brg, int).reshape(-1, 4),
        bearing_shaft=np.array([b.shaft for b in asm.bearings], int),
        bearing_dynamic=np.array(
            [b.element.speed_dependent and b.pad_dofs is None for b in asm.bearings], bool
        ),
        reactions=reactions,
        constant_force=None if constant_force is None else constant_force[active],
        bearing_preload=None if bearing_preload is None else np.asarray(bearing_preload, float),
    )
    # a mesh damping_ratio is already resolved into MeshInfo.damping by the assembly (the same
    # damper for every analysis)
    return system


def mesh_damping_from_ratio(
    system: TransientSystem, mesh: int, ratio: float
) -> tuple[float, float]:
    """Mesh damping coefficient c (N·s/m) giving modal damping ratio ``ratio`` to the mesh mode.

    The mesh mode is the undamped mode φ_i (mass-normalised, of the constant-speed linear model
    with the meshes at Kg, without gyroscopics; the symmetric part of its stiffness, as the
    skew part of cross-coupled bearings stores no strain energy) with the largest mesh
    strain-energy fraction ``Kg (w·φ_i)² / ω_i²``. A damper ``c w wᵀ`` adds ``c (w·φ_i)²`` to
    that mode's modal damping ``2 ζ ω_i``, hence ``c = 2 ζ ω_i / (w·φ_i)²``. Returns (c, ω_i in
    rad/s).
    """
    M, K, _ = system.linear_matrices()
    w2, V = la.eigh(0.5 * (K + K.T), M)
    law = system.meshes[mesh]
    d = system.mesh_dofs[mesh]
    ok = d >= 0
    wphi = V[d[ok]].T @ law.w[ok]
    elastic = w2 > 1e-6 * w2.max()
    frac = np.where(elastic, law.kg * wphi**2 / np.where(elastic, w2, 1.0), 0.0)
    i = int(np.argmax(frac))
    om = float(np.sqrt(w2[i]))
    return 2.0 * ratio * om / wphi[i] ** 2, om


def static_state(system: TransientSystem) -> tuple[NDArray, float]:
    """Static deflection under the external torques at t = 0 (the users' usual initial state),
    and the constant loads of an operating point (weight, static forces, journal loads).

    Solves ``K q + M r α = f``, ``rᵀ M q = 0``: the deflection in a frame that follows the rigid
    rotation r of the train (θz_s = ratio_s·α) with its uniform angular acceleration α (rad/s²,
    of the reference shaft) when the torques do not balance (d'Alembert). The meshes carry their
    stiffness at φ_m = 0, backlash and transmission error; the contact flank is found by
    iteration. Unbalance is left out (its load rotates). Returns (q over active DOFs, α).
    """
    from ..static.solver import Contact, solve_static
    from .mesh import stiffness as mesh_k

    train = system.train
    f = np.zeros(system.n)
    for j, tq in enumerate(train.torques):
        dof = system.torque_dof[j]
        sh = system.shaft_of_row[dof]
        val = tq.value if tq.time is None else float(np.interp(0.0, tq.time, tq.values))
        if tq.speed_exponent:
            val *= (abs(system.nominal_speeds[sh]) / tq.reference_speed) ** tq.speed_exponent
        f[dof] += val
    if system.constant_force is not None:
        f += system.constant_force
    if not f.any():
        return np.zeros(system.n), 0.0
    M, K, _ = system.linear_matrices(meshes=False)
    M = system.M.toarray()
    ratio = system.assembly.speed_ratio
    r = np.zeros(system.n)
    for s, a in enumerate(system.a_weights):
        r[a != 0] = ratio[s]
    laws = system.meshes
    contacts = []
    for k, law in enumerate(laws):
        d = system.mesh_dofs[k]
        ok = d >= 0
        contacts.append(
            Contact(
                d[ok],
                law.w[ok],
                law.w_back[ok],
                float(mesh_k(law, 0.0)),
                law.backlash,
                float(law.te[:, 0].sum()) if len(law.te) else 0.0,
            )
        )
    # the package's one static solver (analyses/static/solver.py)
    try:
        sol = solve_static(K, f, M=M, rigid=r[:, None], contacts=contacts, field="torques")
    except la.LinAlgError:
        raise ModelError(
            "no static initial state: with the teeth separated the torques spin the shafts apart",
            field="torques",
            expected="torques that load the meshes",
        ) from None
    return sol.q, float(sol.acceleration[0])
