"""The DOF sets of a run and the nonlinear forces' parameters for the compiled kernels.

:func:`_output_dofs` — the active DOFs a run records; :func:`_force_dofs` — the DOFs the
nonlinear forces act on; :func:`_pack_forces` — the parameter arrays of
:func:`.kernels.nl_forces` (meshes, unbalances, torques, speed-dependent bearings) with indices
into a DOF selection. The integrators and the result (mesh forces recomputed from the recorded
states, :func:`.results.build_result`) use the same packing.

The ``[torsional]`` drives and loads of the model (:mod:`gearrotor.model.drives`) act through
the same compiled laws as in the torsional-only transient (:mod:`..torsional.drive_laws`, one
implementation for both): :func:`_drive_laws` finds their θz DOFs, and the last group of the
pack carries them to :func:`.kernels.nl_forces`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..torsional.drive_laws import P_SIGN, TorqueLaws, pack_laws
from .equations import TransientSystem


def _drive_laws(system: TransientSystem) -> tuple[TorqueLaws, NDArray, NDArray]:
    """The model's drive and load laws, the active θz index of each law's node and its shaft's
    sense of rotation σ (the laws see θ and Ω along the rotation; the torque about +z is
    ``σ · sign · T``)."""
    laws = pack_laws(system.train)
    asm = system.assembly
    dof = np.array(
        [system.index(int(asm.node_offset[s][nd] + 5)) for s, nd in laws.nodes], np.int64
    )
    sense = np.array([1.0 if system.nominal_speeds[s] >= 0 else -1.0 for s, _ in laws.nodes], float)
    return laws, dof, sense


def _output_dofs(system: TransientSystem, full_state: bool) -> NDArray:
    """Active indices recorded: gear nodes, probes, unbalances, bearings, couplings, torques."""
    if full_state:
        return np.arange(system.n, dtype=np.int64)
    asm, train = system.assembly, system.train
    glob = []
    for m in asm.meshes:
        glob.extend(m.dofs)
    for b in asm.bearings:  # journal, pedestal and pad DOFs
        glob.extend(b.local()[0])
    for group, prefix in (
        (train.unbalances, "unbalances"),
        (train.probes, "probes"),
        (train.torques, "torques"),
        (train.torsional.drives if train.torsional else [], "torsional.drives"),
        (train.torsional.loads if train.torsional else [], "torsional.loads"),
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


def _force_dofs(system: TransientSystem) -> NDArray:
    idx = set(system.mesh_dofs[system.mesh_dofs >= 0].tolist())
    idx |= set(system.unbalance_dofs.ravel().tolist())
    idx |= set(system.torque_dof.tolist())
    if system.constant_force is not None:
        idx |= set(np.flatnonzero(system.constant_force).tolist())
    idx |= set(_drive_laws(system)[1].tolist())
    for j in range(len(system.bearing_dofs)):
        if system.bearing_dynamic[j]:
            idx |= set(system.bearing_dofs[j][system.bearing_dofs[j] >= 0].tolist())
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
            [law.kg, law.ka, law.backlash, law.damping, law.teeth]
            + [law.kg if modal else 0.0, 0.0, 0.0]
            for law in laws
        ],
        float,
    ).reshape(nm, 8)
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
    t_dof = system.torque_dof
    if system.constant_force is not None:  # constant loads: constant "torques" on their DOFs
        c_dof = np.flatnonzero(system.constant_force)
        for d in c_dof:
            t_par.append([system.constant_force[d], 0.0, 1.0])
            t_ptr.append(len(t_time))
        t_dof = np.concatenate([np.asarray(t_dof, np.int64), c_dof])
    torq = (
        at(t_dof).astype(np.int64),
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
    laws, l_dof, l_sense = _drive_laws(system)
    drv = (
        (
            at(l_dof).astype(np.int64),
            l_sense,
            laws.par[:, P_SIGN].copy(),  # +1 drive, −1 load
            laws.new_state(),  # mutable: synchronous motors' pull-in state
            *laws.arrays(),
        ),
    )
    return mesh + unb + torq + brg + drv
