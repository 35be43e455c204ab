"""The DOF sets of a run and the nonlinear forces' packs for the compiled kernels.

:func:`_output_dofs` — the active DOFs a run records; :func:`_force_dofs` — the DOFs the
nonlinear forces act on; :func:`pack_forces` — the :class:`~.kernels.Forces` of
:func:`.kernels.nonlinear_forces`, one pack per law (:class:`~.kernels.MeshLaws`,
:class:`~.kernels.Unbalances`, :class:`~.kernels.Torques`, :class:`~.kernels.BearingTables`,
:class:`~..torsional.drive_laws.Drives`), each built by one function here from the
:class:`~.equations.TransientSystem`, with indices into a DOF selection. The integrators and
the result (mesh forces recomputed from the recorded states, :func:`.results.build_result`) use
the same packing.

The ``[torsional]`` drives and loads of the model (:mod:`gearrotor.model.drives`) act through
the same compiled laws as in the torsional-only transient (:mod:`..torsional.drive_laws`, one
implementation for both): :func:`_drive_laws` finds their θz DOFs, and their
:class:`~..torsional.drive_laws.Drives` pack carries them to the kernel.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..torsional.drive_laws import TorqueLaws, pack_laws
from .equations import TransientSystem
from .kernels import BearingTables, Forces, MeshLaws, Torques, Unbalances


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


def pack_forces(system: TransientSystem, sel: NDArray, *, modal: bool, bearing_ref: bool) -> Forces:
    """The :class:`~.kernels.Forces` of a run with indices into the force DOFs ``sel``:
    ``modal``: the meshes' Kg on the drive line is in the linear part (the modal basis is
    built with it); ``bearing_ref``: the speed-dependent bearings' coefficients at the nominal
    speed are (both subtracted by the kernel)."""
    loc = -np.ones(system.n + 1, np.int64)
    loc[sel] = np.arange(len(sel))

    def at(idx):
        idx = np.asarray(idx, np.int64)
        return np.where(idx >= 0, loc[np.where(idx >= 0, idx, system.n)], -1)

    laws, l_dof, l_sense = _drive_laws(system)
    return Forces(
        _mesh_laws(system, at, modal),
        _unbalances(system, at),
        _torques(system, at),
        _bearing_tables(system, at, bearing_ref),
        laws.drives(at(l_dof), l_sense),  # the θz of the law's node, along the rotation
    )


def _mesh_laws(system: TransientSystem, at, modal: bool) -> MeshLaws:
    laws = system.meshes
    nm = len(laws)
    S = max([len(law.coef_a) for law in laws] + [1])
    Se = max([len(law.te) for law in laws] + [1])
    fourier = np.zeros((nm, S, 2))
    n_fourier = np.zeros(nm, np.int64)
    te = np.zeros((nm, Se, 2))
    n_te = np.zeros(nm, np.int64)
    tptr = [0]
    tphi, tk = [], []
    for k, law in enumerate(laws):
        fourier[k, : len(law.coef_a), 0] = law.coef_a
        fourier[k, : len(law.coef_b), 1] = law.coef_b
        n_fourier[k] = len(law.coef_a)
        te[k, : len(law.te)] = law.te
        n_te[k] = len(law.te)
        tphi.append(law.table_phi)
        tk.append(law.table_k)
        tptr.append(tptr[-1] + len(law.table_phi))

    def column(name):
        return np.array([getattr(law, name) for law in laws], float)

    return MeshLaws(
        dofs=np.array([at(d) for d in system.mesh_dofs], np.int64).reshape(nm, 12),
        lines=np.array([[law.w, law.w_back] for law in laws], float).reshape(nm, 2, 12),
        kg=column("kg"),
        ka=column("ka"),
        backlash=column("backlash"),
        damping=column("damping"),
        teeth=column("teeth"),
        kg_linear=column("kg") if modal else np.zeros(nm),
        kg_back_linear=np.zeros(nm),
        fourier=fourier,
        n_fourier=n_fourier,
        table_ptr=np.array(tptr, np.int64),
        table_phi=np.concatenate(tphi + [np.zeros(1)]),
        table_k=np.concatenate(tk + [np.zeros(1)]),
        te=te,
        n_te=n_te,
        last=np.zeros((nm, 2)),
    )


def _unbalances(system: TransientSystem, at) -> Unbalances:
    return Unbalances(
        np.array([at(d) for d in system.unbalance_dofs], np.int64).reshape(-1, 3),
        system.unbalance_me.astype(float),
        system.unbalance_phase.astype(float),
    )


def _torques(system: TransientSystem, at) -> Torques:
    """The model's torques, and the constant loads as constant "torques" on their DOFs."""
    par, ptr, time, values = [], [0], [], []
    for tq in system.train.torques:
        par.append([tq.value, tq.speed_exponent, tq.reference_speed or 1.0])
        if tq.time is not None:
            time.extend(tq.time)
            values.extend(tq.values)
        ptr.append(len(time))
    dof = system.torque_dof
    if system.constant_force is not None:
        c_dof = np.flatnonzero(system.constant_force)
        for d in c_dof:
            par.append([system.constant_force[d], 0.0, 1.0])
            ptr.append(len(time))
        dof = np.concatenate([np.asarray(dof, np.int64), c_dof])
    par = np.array(par, float).reshape(-1, 3)
    return Torques(
        dof=at(dof).astype(np.int64),
        value=par[:, 0].copy(),
        speed_exponent=par[:, 1].copy(),
        reference_speed=par[:, 2].copy(),
        table_ptr=np.array(ptr, np.int64),
        time=np.array(time + [0.0], float),
        values=np.array(values + [0.0], float),
    )


def _bearing_tables(system: TransientSystem, at, bearing_ref: bool) -> BearingTables:
    dofs, shaft, ptr, speed, coef, ref = [], [], [0], [], [], []
    for j, info in enumerate(system.assembly.bearings):
        if not system.bearing_dynamic[j]:
            continue
        tab = info.element.table
        dofs.append(at(system.bearing_dofs[j]))
        shaft.append(system.bearing_shaft[j])
        speed.extend(tab.speed)
        coef.append(np.asarray(tab.values, float))
        ptr.append(len(speed))
        ref.append(
            info.element.coefficients(system.nominal_speeds[system.bearing_shaft[j]])
            if bearing_ref
            else np.zeros(8)
        )
    return BearingTables(
        dofs=np.array(dofs, np.int64).reshape(-1, 4),
        shaft=np.array(shaft, np.int64),
        ptr=np.array(ptr, np.int64),
        speed=np.array(speed + [0.0], float),
        coef=np.concatenate(coef + [np.zeros((1, 8))]),
        ref=np.array(ref, float).reshape(-1, 8),
    )
