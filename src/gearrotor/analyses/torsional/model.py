"""The torsional model of a train: the θz partition of its assembly, meshes flexible or rigid.

:func:`torsional_model` derives the model from the same :func:`~gearrotor.assembly.assemble`
path as every other analysis, keeping only the torsional DOF θz of every node:

* shaft elements: the torsional rod of :class:`~gearrotor.elements.ShaftElement` (consistent
  mass ρJ L/6 [[2, 1], [1, 2]], stiffness GJ/L, material damping α M + β K with the assembly's
  correction that keeps the mass-proportional part from braking the spin);
* disks: their polar inertia; couplings: ``ktz``, ``ctz``; torsional supports (springs and
  dampers to ground); sections whose rod is given directly (``torsional_stiffness``,
  ``polar_inertia``, ``torsional_damping``);
* gear meshes, ``mesh="flexible"``: the mesh element ``k w wᵀ`` (and ``c w wᵀ``) restricted to
  the two gears' θz, i.e. a torsional spring ``k (r_i cos β cos αn)²`` per side with the sign
  pattern of the kinematic vector w (:class:`~gearrotor.elements.MeshGeometry`), the base-circle
  torque arm of the normal stiffness; ``mesh="rigid"``: the kinematic constraint
  ``w_θi θ_i + w_θj θ_j = 0`` (gears rolling at the ratio r_i/r_j), eliminating the mate's angle,
  which reflects the inertia and stiffness on the mate's side by the ratio squared.

Dropping the lateral and axial DOFs is exact when they are held (stiff bearings at the gears)
and is the usual isolated-torsion model otherwise; :mod:`tests.torsional` compares it with the
torsional modes of the full 6-DOF model.

The model keeps every node's angle as a physical coordinate: reduced coordinates p are the
angles of *master* nodes and every node's angle is ``θ = factor · p[master]`` (factor 1 on its
own, the gear ratio through rigid meshes, 0 for ``fixed`` nodes), so results are reported per
node and element whichever mesh model is chosen.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components

from ...assembly import Assembly, _shaft_elements, assemble
from ...errors import ModelError
from ...model import NodeRef, Train

__all__ = ["TorsionalModel", "torsional_model", "MESH_MODELS"]

MESH_MODELS = ("flexible", "rigid")


@dataclass(frozen=True)
class TorsionalModel:
    """Torsional matrices of a train in reduced coordinates, with the maps back to every node.

    Full coordinates: the θz of every node, shaft by shaft (``n_full``); reduced coordinates:
    ``n`` master angles; ``theta_full = factor * p[master]`` (master −1: fixed, θ = 0).
    Matrices are dense (n, n), SI (kg·m², N·m/rad, N·m·s/rad).

    Element tables (arrays over the shaft elements, couplings and meshes) give what the
    result objects need: torques, shear stresses (τ = T r / J_p · SCF), mesh forces.
    """

    train: Train = field(repr=False)
    assembly: Assembly = field(repr=False)
    mesh: str
    M: NDArray
    K: NDArray
    C: NDArray
    M_full: NDArray = field(repr=False)  # (n_full, n_full), rigid meshes left out
    K_full: NDArray = field(repr=False)
    C_full: NDArray = field(repr=False)
    master: NDArray  # (n_full,) int
    factor: NDArray  # (n_full,)
    roots: NDArray  # (n,) full index of the node whose angle each reduced coordinate is
    node_shaft: NDArray  # (n_full,) shaft index of each full DOF
    node_index: NDArray  # (n_full,) node index on its shaft
    node_z: NDArray  # (n_full,) m
    shaft_names: tuple[str, ...]
    speed_ratio: NDArray  # (n_shafts,) Ω_s / Ω_ref, signed (tooth counts)
    rotation: NDArray  # (n_shafts,) ±1, sense of rotation of each shaft
    kinematic: NDArray  # (n_full,) rotation of each node per unit rotation of the reference
    # shaft when the train turns as a whole through its connections (meshes: their radii)
    # shaft elements
    el_shaft: NDArray
    el_number: NDArray  # element index along its shaft
    el_section: NDArray
    el_dofs: NDArray  # (ne, 2) full DOFs of the element's nodes
    el_stiffness: NDArray  # GJ/L, N·m/rad
    el_radius: NDArray  # outer radius, m
    el_polar: NDArray  # polar second moment J_p, m⁴
    el_scf: NDArray  # stress concentration factor
    # couplings (only those joining two nodes in torsion)
    cp_names: tuple[str, ...]
    cp_dofs: NDArray  # (nc, 2)
    cp_stiffness: NDArray
    cp_damping: NDArray
    # torsional supports: springs / dampers from a node to ground
    gs_names: tuple[str, ...]
    gs_dofs: NDArray  # (ng,) full DOF
    gs_stiffness: NDArray  # N·m/rad
    gs_damping: NDArray  # N·m·s/rad
    # meshes
    mesh_names: tuple[str, ...]
    mesh_dofs: NDArray  # (nm, 2) full DOFs of gear i and gear j
    mesh_w: NDArray  # (nm, 2) θz entries of the kinematic vector (m): δ = w · θ
    mesh_stiffness: NDArray  # Kg, N/m
    mesh_damping: NDArray  # N·s/m (resolved from damping_ratio for flexible meshes)
    mesh_backlash: NDArray  # one-side b, m
    mesh_teeth: NDArray  # (nm, 2)
    mesh_shafts: NDArray  # (nm, 2)
    # a mesh's damping_ratio and the mode it refers to (NaN where the mesh gives none)
    mesh_damping_ratio: NDArray  # (nm,)
    mesh_mode_frequency: NDArray  # (nm,) rad/s, undamped natural frequency of the mesh mode
    mesh_mode_fraction: NDArray  # (nm,) share of that mode's strain energy in the mesh

    # ---- sizes and maps --------------------------------------------------------------------
    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def n_full(self) -> int:
        return len(self.master)

    @property
    def T(self) -> NDArray:
        """(n_full, n) map from reduced to full coordinates."""
        T = np.zeros((self.n_full, self.n))
        ok = self.master >= 0
        T[np.flatnonzero(ok), self.master[ok]] = self.factor[ok]
        return T

    def expand(self, p: NDArray) -> NDArray:
        """Full angles (…, n_full) from reduced coordinates (…, n)."""
        p = np.asarray(p)
        out = p[..., np.maximum(self.master, 0)] * self.factor
        return np.where(self.master >= 0, out, 0.0)

    def reduce_force(self, f: NDArray) -> NDArray:
        """Generalised forces Tᵀ f (…, n) of full nodal torques f (…, n_full)."""
        f = np.asarray(f)
        out = np.zeros(f.shape[:-1] + (self.n,), dtype=f.dtype)
        ok = np.flatnonzero(self.master >= 0)
        np.add.at(out.T, self.master[ok], (f[..., ok] * self.factor[ok]).T)
        return out

    def dof(self, shaft: int, node: int) -> int:
        """Full index of node ``node`` of shaft ``shaft``."""
        idx = np.flatnonzero((self.node_shaft == shaft) & (self.node_index == node))
        return int(idx[0])

    def node_dof(self, ref: NodeRef, field: str) -> int:
        """Full index of a node reference of the model (checked)."""
        return self.dof(*self.train.node_index(ref, field))

    # ---- element quantities ----------------------------------------------------------------
    def element_labels(self) -> list[str]:
        return [
            f"{self.shaft_names[s]}[{e}]"
            for s, e in zip(self.el_shaft, self.el_number, strict=True)
        ]

    def element_torque(self, theta: NDArray) -> NDArray:
        """Shaft torque (…, ne) N·m from full angles (…, n_full): GJ/L (θ_b − θ_a), positive
        when the node further along +z is turned further about +z."""
        theta = np.asarray(theta)
        d = theta[..., self.el_dofs[:, 1]] - theta[..., self.el_dofs[:, 0]]
        return d * self.el_stiffness

    def shear_stress(self, torque: NDArray) -> NDArray:
        """Surface shear stress (…, ne) Pa of element torques: τ = T r / J_p × SCF."""
        return np.asarray(torque) * (self.el_radius / self.el_polar * self.el_scf)

    def coupling_torque(self, theta: NDArray, theta_dot: NDArray | None = None) -> NDArray:
        """Coupling torque (…, nc) N·m: ktz (θ_j − θ_i) + ctz (θ̇_j − θ̇_i)."""
        theta = np.asarray(theta)
        out = (theta[..., self.cp_dofs[:, 1]] - theta[..., self.cp_dofs[:, 0]]) * self.cp_stiffness
        if theta_dot is not None:
            theta_dot = np.asarray(theta_dot)
            dv = theta_dot[..., self.cp_dofs[:, 1]] - theta_dot[..., self.cp_dofs[:, 0]]
            out = out + dv * self.cp_damping
        return out

    def mesh_deflection(self, theta: NDArray) -> NDArray:
        """Approach of the tooth surfaces along the line of action (…, nm) m: δ = w · θ."""
        theta = np.asarray(theta)
        return (
            theta[..., self.mesh_dofs[:, 0]] * self.mesh_w[:, 0]
            + theta[..., self.mesh_dofs[:, 1]] * self.mesh_w[:, 1]
        )

    def mesh_force(
        self, theta: NDArray, theta_dot: NDArray | None = None, *, residual: NDArray | None = None
    ) -> NDArray:
        """Normal mesh force (…, nm) N, positive in compression along the line of action.

        Flexible meshes: ``k δ + c δ̇``. Rigid meshes: the constraint force, from the residual
        ``r = M θ̈ + C θ̇ + K θ − f`` of the full equations without the meshes (the meshes put
        ``−F w`` on the gears, so ``r = −Σ F_k w_k``; least squares over the meshes) — give
        ``residual`` (…, n_full); complex amplitudes work for both."""
        if self.mesh == "flexible":
            out = self.mesh_deflection(theta) * self.mesh_stiffness
            if theta_dot is not None:
                out = out + self.mesh_deflection(theta_dot) * self.mesh_damping
            return out
        if residual is None:
            raise ValueError("rigid meshes: the mesh force needs the equations' residual")
        W = np.zeros((self.n_full, len(self.mesh_names)))
        for k in range(len(self.mesh_names)):
            W[self.mesh_dofs[k], k] = self.mesh_w[k]
        r = np.asarray(residual)
        sol = np.linalg.lstsq(W, -r.reshape(-1, self.n_full).T, rcond=None)[0]
        return sol.T.reshape(r.shape[:-1] + (len(self.mesh_names),))

    def nominal_torques(self, speed: float | None = None) -> NDArray:
        """Nodal torques (n_full,) N·m about +z at a steady reference-shaft speed (default the
        nominal one): every load of ``[torsional]`` at its shaft's speed, against the rotation,
        balanced by the drives in proportion to their rated power (Σ T Ω = 0)."""
        train = self.train
        tors = train.torsional
        if tors is None or not tors.drives or not tors.loads:
            raise ModelError(
                "the rated torques need drives and loads",
                field="torsional",
                expected="[[torsional.drives]] and [[torsional.loads]] (or give the torques)",
            )
        w = abs(train.speed if speed is None else speed)
        f = np.zeros(self.n_full)
        power = 0.0
        ratio = np.abs(self.kinematic_ratio)  # the speeds at which the torques balance exactly
        for k, ld in enumerate(tors.loads):
            i = self.node_dof(ld, f"torsional.loads[{k}]")
            s = self.node_shaft[i]
            ws = ratio[s] * w
            tq = ld.torque_at(ws)
            f[i] -= self.rotation[s] * tq
            power += tq * ws
        rated = sum(d.rated_power for d in tors.drives)
        for k, d in enumerate(tors.drives):
            i = self.node_dof(d, f"torsional.drives[{k}]")
            s = self.node_shaft[i]
            ws = ratio[s] * w
            f[i] += self.rotation[s] * power * d.rated_power / rated / ws
        return f

    @property
    def kinematic_ratio(self) -> NDArray:
        """(n_shafts,) rotation of each shaft per unit rotation of the reference shaft when the
        train turns as a whole, from the mesh kinematics (the radii the meshes use: δ = w·θ = 0)
        rather than the tooth counts; equal to :attr:`speed_ratio` when the pitch radii are in
        the tooth ratio. A shaft not connected to the reference shaft keeps its tooth ratio."""
        first = np.array(
            [np.flatnonzero(self.node_shaft == s)[0] for s in range(len(self.shaft_names))]
        )
        return self.kinematic[first]

    @property
    def torque_arm(self) -> NDArray:
        """(nm, 2) m: torque on gear i / j per unit normal mesh force, |w_θ|."""
        return np.abs(self.mesh_w)

    # ---- static torque flow ----------------------------------------------------------------
    def rigid_modes(self) -> NDArray:
        """(n, r) M-orthonormal rigid-body rotations of the reduced model, one per torsionally
        free part of the train (parts joined by stiffness): every node of a part turning as
        the mesh kinematics make it turn (:attr:`kinematic`: the radii the meshes use, so a
        rigid rotation strains no mesh whatever the tooth counts say); a part held by a fixed
        node or a spring to ground, or whose rotation strains something (a loop of meshes
        whose ratios do not close), has none. Built from the connectivity rather than picked
        from the eigenvalues, whose zeros round-off can lift well above any fixed threshold in
        a stiff, light model."""
        pattern = sp.csr_array(np.abs(self.K) > 0)
        n_parts, part = connected_components(pattern, directed=False)
        r_all = self.kinematic[self.roots]
        scale = np.abs(self.K).max() if self.K.size else 1.0
        modes = []
        for c in range(n_parts):
            r = np.where(part == c, r_all, 0.0)
            if np.linalg.norm(self.K @ r) <= 1e-9 * scale * np.linalg.norm(r):
                modes.append(r / np.sqrt(r @ self.M @ r))
        return np.array(modes).T.reshape(self.n, len(modes))

    def static_twist(self, f_full: NDArray, *, balanced: bool = True) -> tuple[NDArray, NDArray]:
        """Static angles (n_full,) under nodal torques f (n_full,) N·m, with the rigid-body
        accelerations (r,) of the free parts (d'Alembert: ``K θ + M R α = f``, ``Rᵀ M θ = 0``).

        ``balanced=True`` requires the torques to balance (no rigid acceleration, relative
        to the largest torque): :class:`ModelError` otherwise."""
        p, alpha = self.static_reduced(f_full, balanced=balanced)
        return self.expand(p), alpha

    def _split_by_coupling(self, R: NDArray) -> None:
        _split_coupling_error(self, R)

    def static_reduced(self, f_full: NDArray, *, balanced: bool = True) -> tuple[NDArray, NDArray]:
        """:meth:`static_twist` in reduced coordinates (n,)."""
        f = self.reduce_force(np.asarray(f_full, float))
        R = self.rigid_modes()
        MR = self.M @ R
        nr = R.shape[1]
        A = np.block([[self.K, MR], [MR.T, np.zeros((nr, nr))]])
        sol = la.solve(A, np.concatenate([f, np.zeros(nr)]))
        alpha = sol[self.n :]
        if balanced and nr:
            net = R.T @ f
            scale = np.abs(R).T @ np.abs(f) + 1e-300
            if np.any(np.abs(net) > 1e-6 * scale) and nr > 1:
                self._split_by_coupling(R)
            if np.any(np.abs(net) > 1e-6 * scale):
                raise ModelError(
                    "the torques do not balance: they would accelerate the train",
                    field="torques",
                    value=f"net torque on the rigid rotation {net.tolist()}",
                    expected="drive and load torques in power balance (Σ T_k Ω_k = 0)",
                )
        return sol[: self.n], alpha


def _split_coupling_error(tm: TorsionalModel, R: NDArray) -> None:
    """Raise a :class:`ModelError` naming a coupling without torsional stiffness that separates
    two torsionally free parts (``R``: their rigid rotations), if there is one."""
    part = np.argmax(np.abs(tm.T @ R), axis=1)
    for k in np.flatnonzero(tm.cp_stiffness == 0):
        a, b = tm.cp_dofs[k]
        if part[a] != part[b]:
            raise ModelError(
                f"the train is torsionally split into {R.shape[1]} free parts at a coupling "
                "without torsional stiffness: no steady torque passes it",
                field=f"couplings[{k}].ktz",
                value=0.0,
                expected="a positive torsional stiffness (N*m/rad) for a coupling that carries "
                "torque",
            )


def _union_find(n: int):
    parent = np.arange(n)
    fac = np.ones(n)

    def find(i: int) -> tuple[int, float]:
        f = 1.0
        root = i
        while parent[root] != root:
            f *= fac[root]
            root = parent[root]
        # compress
        j, fj = i, f
        while parent[j] != j:
            nxt, fn = parent[j], fj / fac[j]
            parent[j], fac[j] = root, fj
            j, fj = nxt, fn
        return root, f

    return parent, fac, find


def torsional_model(
    model: Train | Assembly,
    *,
    mesh: str = "flexible",
    fixed: Sequence[NodeRef | dict] = (),
) -> TorsionalModel:
    """The torsional model of a train (module docstring).

    Parameters
    ----------
    model : the :class:`Train` (or its :class:`Assembly`)
    mesh : ``"flexible"`` (each mesh a spring along its line of action) or ``"rigid"``
        (kinematic constraint at the gear ratio)
    fixed : nodes held at θ = 0 (``{"shaft": ..., "node": ...}`` or :class:`NodeRef`): a
        torsionally grounded train (e.g. a locked rotor) for modes and forced response
    """
    if mesh not in MESH_MODELS:
        raise ModelError(
            "unknown mesh model", field="mesh", value=mesh, expected="'flexible' or 'rigid'"
        )
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    layout = train.layout()
    tz = np.concatenate([offs + 5 for offs in asm.node_offset])
    n_full = len(tz)
    pos = -np.ones(asm.n_dof, int)
    pos[tz] = np.arange(n_full)
    node_shaft = np.concatenate([np.full(sl.n_nodes, i) for i, sl in enumerate(layout.shafts)])
    node_index = np.concatenate([np.arange(sl.n_nodes) for sl in layout.shafts])
    node_z = np.concatenate([sl.z for sl in layout.shafts])
    Mf = asm.M[tz][:, tz].toarray()
    Kf = asm.K0[tz][:, tz].toarray()
    Cf = asm.C0[tz][:, tz].toarray()

    # ---- meshes ----------------------------------------------------------------------------
    nm = len(asm.meshes)
    mesh_dofs = np.array([pos[m.dofs[[5, 11]]] for m in asm.meshes], int).reshape(nm, 2)
    mesh_w = np.array([m.w[[5, 11]] for m in asm.meshes], float).reshape(nm, 2)
    kg = np.array([m.stiffness for m in asm.meshes], float)
    cm = np.array([m.damping for m in asm.meshes], float)
    backlash = np.array([train.meshes[m.spec_index].backlash.half for m in asm.meshes], float)

    parent, fac, find = _union_find(n_full)
    if mesh == "rigid":
        for k in range(nm):
            d = mesh_dofs[k]
            ww = np.outer(mesh_w[k], mesh_w[k])
            Kf[np.ix_(d, d)] -= kg[k] * ww
            Cf[np.ix_(d, d)] -= cm[k] * ww
            c = -mesh_w[k, 0] / mesh_w[k, 1]  # θ_j = c θ_i
            (ri, fi), (rj, fj) = find(int(d[0])), find(int(d[1]))
            if ri != rj:
                parent[rj] = ri
                fac[rj] = c * fi / fj
            elif abs(fj - c * fi) > 1e-9 * abs(c * fi):
                raise ModelError(
                    "rigid meshes close a loop at inconsistent ratios",
                    field=f"meshes[{asm.meshes[k].spec_index}]",
                    value=f"ratio {c:.9g} vs {fj / fi:.9g} through the other meshes",
                    expected="pitch radii that close the loop (or mesh = 'flexible')",
                )
    fixed_dofs = set()
    for k, ref in enumerate(fixed):
        ref = ref if isinstance(ref, NodeRef) else NodeRef.model_validate(ref)
        si, node = train.node_index(ref, f"fixed[{k}]")
        fixed_dofs.add(find(int(np.flatnonzero((node_shaft == si) & (node_index == node))[0]))[0])
    roots = []
    factor = np.ones(n_full)
    root_of = np.zeros(n_full, int)
    for i in range(n_full):
        r, f = find(i)
        root_of[i], factor[i] = r, f
        if r == i and r not in fixed_dofs:
            roots.append(r)
    col = -np.ones(n_full, int)
    col[roots] = np.arange(len(roots))
    master = col[root_of]
    factor = np.where(master >= 0, factor, 0.0)

    T = np.zeros((n_full, len(roots)))
    ok = np.flatnonzero(master >= 0)
    T[ok, master[ok]] = factor[ok]
    M, K, C = (T.T @ A @ T for A in (Mf, Kf, Cf))
    if np.any(np.diag(M) <= 0):
        raise ModelError(
            "a torsional degree of freedom has no polar inertia",
            field="shafts / disks",
            expected="density and polar inertia on every shaft",
        )

    # ---- shaft elements --------------------------------------------------------------------
    scf = {}
    if train.torsional is not None:
        for sc in train.torsional.stress_concentrations:
            scf[(train.shaft_index(sc.shaft, "stress_concentrations.shaft"), sc.section)] = (
                sc.factor
            )
    el = {k: [] for k in ("shaft", "num", "sec", "dofs", "k", "r", "J", "scf")}
    for si in range(len(layout.shafts)):
        elements = _shaft_elements(train, si)
        sections = np.repeat(
            np.arange(len(train.shafts[si].sections)),
            [sec.elements for sec in train.shafts[si].sections],
        )
        base = int(pos[asm.node_offset[si][0] + 5])
        for e, (element, sec) in enumerate(zip(elements, sections, strict=True)):
            jp = 2 * element.inertia
            el["shaft"].append(si)
            el["num"].append(e)
            el["sec"].append(sec)
            el["dofs"].append((base + e, base + e + 1))
            el["k"].append(element.rod_stiffness)
            el["r"].append(element.outer_diameter / 2)
            el["J"].append(jp)
            el["scf"].append(scf.get((si, int(sec)), 1.0))

    # ---- couplings -------------------------------------------------------------------------
    cp = {k: [] for k in ("name", "dofs", "k", "c")}
    for k, c in enumerate(train.couplings):
        si, ni = train.node_index(c.node_i, f"couplings[{k}].node_i")
        sj, nj = train.node_index(c.node_j, f"couplings[{k}].node_j")
        cp["name"].append(c.name or f"couplings[{k}]")
        cp["dofs"].append((pos[asm.node_offset[si][ni] + 5], pos[asm.node_offset[sj][nj] + 5]))
        cp["k"].append(c.ktz)
        cp["c"].append(c.ctz)

    # ---- torsional supports (springs / dampers to ground) -----------------------------------
    gs = {k: [] for k in ("name", "dof", "k", "c")}
    for k, t in enumerate(train.torsional_supports):
        si, ni = train.node_index(t, f"torsional_supports[{k}]")
        gs["name"].append(t.name or f"torsional_supports[{k}]")
        gs["dof"].append(pos[asm.node_offset[si][ni] + 5])
        gs["k"].append(t.k)
        gs["c"].append(t.c)

    ratios = np.array([sl.speed_ratio for sl in layout.shafts])
    sense = np.sign(ratios * train.speed) if train.speed != 0 else np.sign(ratios)
    links = [(int(a), int(b), 1.0) for a, b in el["dofs"]]
    links += [(int(a), int(b), 1.0) for a, b in cp["dofs"]]
    links += [
        (int(mesh_dofs[k, 0]), int(mesh_dofs[k, 1]), -mesh_w[k, 0] / mesh_w[k, 1])
        for k in range(nm)
    ]
    ref = train.shaft_index(train.reference, "reference_shaft")
    kinematic = _kinematic_rotation(n_full, links, node_shaft, ratios, ref)
    out = TorsionalModel(
        train=train,
        assembly=asm,
        mesh=mesh,
        M=M,
        K=K,
        C=C,
        M_full=Mf,
        K_full=Kf,
        C_full=Cf,
        master=master,
        factor=factor,
        roots=np.array(roots, int),
        node_shaft=node_shaft,
        node_index=node_index,
        node_z=node_z,
        shaft_names=tuple(s.name for s in train.shafts),
        speed_ratio=ratios,
        rotation=sense,
        kinematic=kinematic,
        el_shaft=np.array(el["shaft"], int),
        el_number=np.array(el["num"], int),
        el_section=np.array(el["sec"], int),
        el_dofs=np.array(el["dofs"], int).reshape(-1, 2),
        el_stiffness=np.array(el["k"], float),
        el_radius=np.array(el["r"], float),
        el_polar=np.array(el["J"], float),
        el_scf=np.array(el["scf"], float),
        cp_names=tuple(cp["name"]),
        cp_dofs=np.array(cp["dofs"], int).reshape(-1, 2),
        cp_stiffness=np.array(cp["k"], float),
        cp_damping=np.array(cp["c"], float),
        gs_names=tuple(gs["name"]),
        gs_dofs=np.array(gs["dof"], int),
        gs_stiffness=np.array(gs["k"], float),
        gs_damping=np.array(gs["c"], float),
        mesh_names=tuple(m.name for m in asm.meshes),
        mesh_dofs=mesh_dofs,
        mesh_w=mesh_w,
        mesh_stiffness=kg,
        mesh_damping=cm,
        mesh_backlash=backlash,
        mesh_teeth=np.array([m.teeth for m in asm.meshes], int).reshape(nm, 2),
        mesh_shafts=np.array([m.shafts for m in asm.meshes], int).reshape(nm, 2),
        mesh_damping_ratio=np.full(nm, np.nan),
        mesh_mode_frequency=np.full(nm, np.nan),
        mesh_mode_fraction=np.full(nm, np.nan),
    )
    return _with_mesh_damping_ratios(out)


def _kinematic_rotation(
    n_full: int, links: list, node_shaft: NDArray, ratios: NDArray, ref: int
) -> NDArray:
    """(n_full,) rotation of every node when the train turns as a whole: propagated along the
    links ``(i, j, c)``, θ_j = c θ_i (shaft elements and couplings c = 1, meshes
    c = −w_i / w_j from the kinematic vector), from the reference shaft at 1; a part not joined
    to it starts from its first shaft's tooth ratio. Where a loop's ratios do not close the
    first path wins (such a part has no rigid rotation: :meth:`TorsionalModel.rigid_modes`
    checks K r = 0)."""
    adj: list[list[tuple[int, float]]] = [[] for _ in range(n_full)]
    for i, j, c in links:
        adj[i].append((j, c))
        adj[j].append((i, 1.0 / c))
    out = np.full(n_full, np.nan)
    starts = np.concatenate([np.flatnonzero(node_shaft == ref), np.arange(n_full)])
    for s0 in starts:
        if not np.isnan(out[s0]):
            continue
        out[s0] = ratios[node_shaft[s0]]
        stack = [int(s0)]
        while stack:
            i = stack.pop()
            for j, c in adj[i]:
                if np.isnan(out[j]):
                    out[j] = c * out[i]
                    stack.append(j)
    return out


def _with_mesh_damping_ratios(tm: TorsionalModel) -> TorsionalModel:
    """Resolve ``Mesh.damping_ratio`` on the torsional model: the mesh damper ``c w wᵀ`` that
    gives the mode with the largest mesh strain-energy fraction (the *mesh mode*,
    ``Kg (w·φ)² / ω²``) the damping ratio ζ, ``c = 2 ζ ω / (w·φ)²`` (φ mass-normalised): the
    damper alone adds ``2 ζ ω`` to that mode's modal damping, and ``c (w·φ_j)²`` to every
    other mode's. The 6-DOF analyses resolve the same ratio on their own (lateral–torsional)
    mesh mode (:func:`gearrotor.assembly.assemble`), so the coefficient differs between the
    two models; give ``damping`` for one coefficient in both. Rigid meshes carry no damping
    (their deflection is zero). The mesh mode's frequency and strain-energy share are kept
    (``mesh_mode_frequency``, ``mesh_mode_fraction``) for the reports."""
    train = tm.train
    specs = [train.meshes[m.spec_index] for m in tm.assembly.meshes]
    if tm.mesh == "rigid" or all(s.damping_ratio is None for s in specs):
        return tm
    for k, s in enumerate(specs):
        if s.damping_ratio is not None and s.damping > 0:
            raise ModelError(
                "give either mesh 'damping' or 'damping_ratio', not both",
                field=f"meshes[{tm.assembly.meshes[k].spec_index}].damping_ratio",
                value=s.damping_ratio,
            )
    w2, V = la.eigh(tm.K, tm.M)
    elastic = np.arange(len(w2)) >= tm.rigid_modes().shape[1]
    C = tm.C.copy()
    Cf = tm.C_full.copy()
    damping = tm.mesh_damping.copy()
    zeta, freq, share = (tm.mesh_damping_ratio.copy() for _ in range(3))
    T = tm.T
    for k, s in enumerate(specs):
        if s.damping_ratio is None:
            continue
        wf = np.zeros(tm.n_full)
        wf[tm.mesh_dofs[k]] = tm.mesh_w[k]
        wr = T.T @ wf
        wphi = V.T @ wr
        frac = np.where(elastic, tm.mesh_stiffness[k] * wphi**2 / np.where(elastic, w2, 1.0), 0.0)
        i = int(np.argmax(frac))
        c = 2.0 * s.damping_ratio * np.sqrt(w2[i]) / wphi[i] ** 2
        zeta[k], freq[k], share[k] = s.damping_ratio, np.sqrt(w2[i]), frac[i]
        dc = c - damping[k]  # C and C_full hold the assembly's (6-DOF model's) mesh damper
        damping[k] = c
        C += dc * np.outer(wr, wr)
        Cf[np.ix_(tm.mesh_dofs[k], tm.mesh_dofs[k])] += dc * np.outer(tm.mesh_w[k], tm.mesh_w[k])
    return replace(
        tm,
        C=C,
        C_full=Cf,
        mesh_damping=damping,
        mesh_damping_ratio=zeta,
        mesh_mode_frequency=freq,
        mesh_mode_fraction=share,
    )
