"""Drive and load torques as compiled laws of (t, θ, Ω): the contract with the integrators.

:func:`pack_laws` turns a train's ``[torsional]`` drives and loads (:mod:`gearrotor.model.drives`)
into a :class:`TorqueLaws` pack of arrays; :func:`law_torque` (numba) evaluates law j at time t
from the node's rotation angle θ and speed Ω *along its shaft's sense of rotation* and returns
the torque along that sense (drives positive when motoring, loads positive when braking: the
caller applies ``sign`` and the shaft's sense ``σ``: generalised torque about +z
``σ · sign · T``). :func:`advance_states` updates the event state once per accepted step
(synchronous motors pulling into step).

Both transients act through :class:`Drives` (the laws, the coordinate of each law's node in the
integrator's state and its gain, the event state) and :func:`drive_torques` (numba), which adds
``gain · sign · T`` to the generalised forces: the coupled 6-DOF transient on the θz of the
law's node (gain σ), the torsional transient on its reduced coordinate (gain σ times the
node's factor on its master). Nothing here depends on either model.

Parameter columns of ``par`` (one row per law) are named by the ``P_*`` constants.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ...errors import ModelError
from ...model import InductionMotor, SynchronousMotor, TorqueDrive, Train
from ..jit import configure_cache

configure_cache()  # before the first @njit(cache=True): numba's cache outside the package

__all__ = [
    "TorqueLaws",
    "LawArrays",
    "Drives",
    "pack_laws",
    "law_torque",
    "drive_torques",
    "advance_state",
    "advance_states",
    "evaluate",
    "check_load_paths",
    "check_transient_supports",
]

KIND_CONSTANT, KIND_TABLE, KIND_QUADRATIC, KIND_INDUCTION, KIND_SYNCHRONOUS, KIND_HISTORY = range(6)
(
    P_KIND,
    P_SIGN,
    P_RATED,
    P_SPEED,  # synchronous speed (motors) or reference speed (quadratic load), rad/s
    P_WLINE,  # line angular frequency, rad/s
    P_PP,  # pole pairs
    P_PULLIN,  # pull-in slip
    P_TPO,  # pull-out torque, N·m
    P_VALUE,  # constant torque, N·m
    P_TRIP,  # trip time, s (inf: none)
    P_SC,  # short circuit: 0 none, 1 three-phase, 2 two-phase
    P_SCT,  # fault time
    P_SCC,  # clearing time (inf: not cleared)
    P_A0,
    P_T0,
    P_A1,
    P_T1,
    P_A2,
    P_T2,
    P_QV2,  # phases · V_th² (circuit)
    P_RTH,
    P_XTH,
    P_R2,
    P_X2,
    P_VEXP,  # voltage exponent of a table torque (2 for an induction-motor table)
) = range(25)
N_PAR = 25
N_STATE = 2  # synced flag, δ at pull-in


class LawArrays(NamedTuple):
    """The arrays :func:`law_torque` reads (one compiled argument): ``par`` (nl, N_PAR);
    tables ``t_ptr`` (nl + 1) into ``t_x`` (speed or slip), ``t_y`` (torque or average p.u.),
    ``t_z`` (pulsating p.u.); voltage ``v_ptr`` into ``v_t``, ``v_f``; load steps ``s_ptr``
    into ``s_t``, ``s_f``."""

    par: NDArray
    t_ptr: NDArray
    t_x: NDArray
    t_y: NDArray
    t_z: NDArray
    v_ptr: NDArray
    v_t: NDArray
    v_f: NDArray
    s_ptr: NDArray
    s_t: NDArray
    s_f: NDArray


class Drives(NamedTuple):
    """The drives and loads as an integrator applies them (one compiled argument of
    :func:`drive_torques`).

    dof : (nl,) int64, the coordinate of each law's node in the integrator's state vector;
    gain : (nl,) the node's angle along its shaft's rotation per unit of that coordinate
    (σ, times the node's factor on its master in the torsional model); sign : (nl,) +1 drive,
    −1 load; state : (nl, N_STATE) the event state (synchronous motors' pull-in; mutable,
    saved with checkpoints); torque : (nl,) the torques of the last evaluation (output);
    laws : :class:`LawArrays`."""

    dof: NDArray
    gain: NDArray
    sign: NDArray
    state: NDArray
    torque: NDArray
    laws: LawArrays


@dataclass(frozen=True)
class TorqueLaws:
    """Packed drives (first) and loads (after them) of a train.

    names : labels; nodes : (nl, 2) (shaft, node); is_drive : (nl,) bool; rated_torque :
    (nl,) N·m; arrays : the :class:`LawArrays` :func:`law_torque` reads (``par`` (nl, N_PAR)
    and the tables).
    """

    names: tuple[str, ...]
    nodes: NDArray
    is_drive: NDArray
    rated_torque: NDArray
    arrays: LawArrays

    def __len__(self) -> int:
        return len(self.names)

    @property
    def par(self) -> NDArray:
        """(nl, N_PAR) the laws' parameters, columns named by the ``P_*`` constants."""
        return self.arrays.par

    def new_state(self) -> NDArray:
        return np.zeros((len(self), N_STATE))

    def drives(self, dof: NDArray, gain: NDArray) -> Drives:
        """The :class:`Drives` pack of these laws acting on state coordinates ``dof`` with
        gains ``gain`` (a fresh event state)."""
        return Drives(
            np.asarray(dof, np.int64),
            np.asarray(gain, float),
            self.par[:, P_SIGN].copy(),
            self.new_state(),
            np.zeros(len(self)),
            self.arrays,
        )


def pack_laws(train: Train) -> TorqueLaws:
    """Pack the train's drives and loads (empty pack without ``[torsional]``)."""
    tors = train.torsional
    drives = list(tors.drives) if tors is not None else []
    loads = list(tors.loads) if tors is not None else []
    names, nodes, par = [], [], []
    tabs: list[tuple] = []
    volts: list[tuple] = []
    steps: list[tuple] = []
    for k, d in enumerate(drives):
        field = f"torsional.drives[{k}]"
        nodes.append(train.node_index(d, field))
        names.append(d.name or field)
        p = np.zeros(N_PAR)
        p[P_SIGN] = 1.0
        p[P_RATED] = d.rated_torque
        p[P_TRIP] = d.trip_time if d.trip_time is not None else np.inf
        p[P_SCC] = np.inf
        tab = (np.zeros(0), np.zeros(0), np.zeros(0))
        if isinstance(d, TorqueDrive):
            if d.table is not None:
                p[P_KIND] = KIND_TABLE
                tab = (np.asarray(d.table.speed), np.asarray(d.table.torque), np.zeros(0))
            elif d.history is not None:
                p[P_KIND] = KIND_HISTORY
                tab = (np.asarray(d.history.time), np.asarray(d.history.torque), np.zeros(0))
            else:
                p[P_KIND] = KIND_CONSTANT
                p[P_VALUE] = d.value
        else:
            p[P_SPEED] = d.synchronous_speed
            p[P_WLINE] = d.line_frequency
            p[P_PP] = d.poles / 2
            sc = d.short_circuit
            if sc is not None:
                p[P_SC] = 1 if sc.type == "three_phase" else 2
                p[P_SCT] = sc.time
                p[P_SCC] = sc.clear_time if sc.clear_time is not None else np.inf
                p[[P_A0, P_T0, P_A1, P_T1, P_A2, P_T2]] = (
                    sc.a0,
                    sc.tau0,
                    sc.a1,
                    sc.tau1,
                    sc.a2,
                    sc.tau2,
                )
            if d.voltage is not None:
                volts.append((k, np.asarray(d.voltage.time), np.asarray(d.voltage.factor)))
            if isinstance(d, InductionMotor):
                if d.circuit is not None:
                    p[P_KIND] = KIND_INDUCTION
                    vth, rth, xth = d.circuit.thevenin()
                    p[[P_QV2, P_RTH, P_XTH, P_R2, P_X2]] = (
                        d.circuit.phases * vth**2,
                        rth,
                        xth,
                        d.circuit.r2,
                        d.circuit.x2,
                    )
                else:
                    p[P_KIND] = KIND_TABLE
                    p[P_VEXP] = 2.0
                    tab = (np.asarray(d.table.speed), np.asarray(d.table.torque), np.zeros(0))
            elif isinstance(d, SynchronousMotor):
                p[P_KIND] = KIND_SYNCHRONOUS
                p[P_PULLIN] = d.pull_in_slip
                p[P_TPO] = d.pull_out_torque * d.rated_torque
                tab = d.start.arrays()
        par.append(p)
        tabs.append(tab)
    for k, ld in enumerate(loads):
        field = f"torsional.loads[{k}]"
        nodes.append(train.node_index(ld, field))
        names.append(ld.name or field)
        p = np.zeros(N_PAR)
        p[P_SIGN] = -1.0
        p[P_TRIP] = np.inf
        p[P_SCC] = np.inf
        tab = (np.zeros(0), np.zeros(0), np.zeros(0))
        if ld.type == "constant":
            p[P_KIND] = KIND_CONSTANT
            p[P_VALUE] = ld.torque
            p[P_RATED] = ld.torque
        elif ld.type == "quadratic":
            p[P_KIND] = KIND_QUADRATIC
            p[P_VALUE] = ld.torque
            p[P_SPEED] = ld.speed
            p[P_RATED] = ld.torque
        elif ld.type == "history":
            p[P_KIND] = KIND_HISTORY
            tab = (np.asarray(ld.history.time), np.asarray(ld.history.torque), np.zeros(0))
            p[P_RATED] = float(np.max(np.abs(ld.history.torque)))
        else:
            p[P_KIND] = KIND_TABLE
            tab = (np.asarray(ld.table.speed), np.asarray(ld.table.torque), np.zeros(0))
            p[P_RATED] = float(np.max(np.abs(ld.table.torque)))
        par.append(p)
        tabs.append(tab)
        if ld.steps:
            steps.append(
                (
                    len(drives) + k,
                    np.array([s.time for s in ld.steps]),
                    np.array([s.factor for s in ld.steps]),
                )
            )
    nl = len(names)

    def ragged(items, width):
        ptr = np.zeros(nl + 1, np.int64)
        cols = [[] for _ in range(width)]
        by = {j: arrs for j, *arrs in items}
        for j in range(nl):
            arrs = by.get(j)
            length = len(arrs[0]) if arrs is not None else 0
            for c in range(width):
                if arrs is not None and len(arrs[c]):
                    cols[c].append(np.asarray(arrs[c], float))
                elif length:
                    cols[c].append(np.zeros(length))
            ptr[j + 1] = ptr[j] + length
        return (ptr,) + tuple(np.concatenate(c + [np.zeros(1)]) if c else np.zeros(1) for c in cols)

    t_ptr, t_x, t_y, t_z = ragged([(j, *t) for j, t in enumerate(tabs)], 3)
    v_ptr, v_t, v_f = ragged(volts, 2)
    s_ptr, s_t, s_f = ragged(steps, 2)
    par_arr = np.array(par, float).reshape(nl, N_PAR)
    return TorqueLaws(
        names=tuple(names),
        nodes=np.array(nodes, np.int64).reshape(nl, 2),
        is_drive=np.arange(nl) < len(drives),
        rated_torque=par_arr[:, P_RATED].copy(),
        arrays=LawArrays(par_arr, t_ptr, t_x, t_y, t_z, v_ptr, v_t, v_f, s_ptr, s_t, s_f),
    )


@njit(cache=True)
def law_torque(j, t, th, om, state, laws):
    """Torque (N·m) of law j along its shaft's rotation: motoring for drives, braking for
    loads. th, om: node angle (rad) and speed (rad/s) along the rotation; state: (nl, 2);
    laws: :class:`LawArrays`."""
    par, t_ptr, t_x, t_y, t_z, v_ptr, v_t, v_f, s_ptr, s_t, s_f = laws
    return _law_torque(
        j, t, th, om, state, par, t_ptr, t_x, t_y, t_z, v_ptr, v_t, v_f, s_ptr, s_t, s_f
    )


@njit(cache=True)
def _law_torque(j, t, th, om, state, par, t_ptr, t_x, t_y, t_z, v_ptr, v_t, v_f, s_ptr, s_t, s_f):
    """:func:`law_torque` on the arrays of :class:`LawArrays` (called in the integrators'
    loops: arrays passed are borrowed, while each array read from a pack counts a reference)."""
    if t >= par[j, P_TRIP]:
        return 0.0
    sc = par[j, P_SC]
    if sc > 0.0 and t >= par[j, P_SCT]:
        if t >= par[j, P_SCC]:
            return 0.0
        tau = t - par[j, P_SCT]
        w = par[j, P_WLINE]
        out = par[j, P_A0] * np.exp(-tau / par[j, P_T0])
        out += par[j, P_A1] * np.exp(-tau / par[j, P_T1]) * np.sin(w * tau)
        out -= par[j, P_A2] * np.exp(-tau / par[j, P_T2]) * np.sin(2.0 * w * tau)
        return par[j, P_RATED] * out
    v = 1.0
    lo, hi = v_ptr[j], v_ptr[j + 1]
    if hi > lo:
        v = np.interp(t, v_t[lo:hi], v_f[lo:hi])
    kind = int(par[j, P_KIND])
    lo, hi = t_ptr[j], t_ptr[j + 1]
    if kind == KIND_CONSTANT:
        out = par[j, P_VALUE]
    elif kind == KIND_TABLE:
        out = np.interp(om, t_x[lo:hi], t_y[lo:hi]) * v ** par[j, P_VEXP]
    elif kind == KIND_HISTORY:
        out = np.interp(t, t_x[lo:hi], t_y[lo:hi])
    elif kind == KIND_QUADRATIC:
        out = par[j, P_VALUE] * om * abs(om) / (par[j, P_SPEED] * par[j, P_SPEED])
    elif kind == KIND_INDUCTION:
        s = 1.0 - om / par[j, P_SPEED]
        a = par[j, P_RTH] * s + par[j, P_R2]
        b = s * (par[j, P_XTH] + par[j, P_X2])
        out = v * v * par[j, P_QV2] * par[j, P_R2] * s / (par[j, P_SPEED] * (a * a + b * b))
    else:  # synchronous motor
        s = 1.0 - om / par[j, P_SPEED]
        delta = par[j, P_WLINE] * t - par[j, P_PP] * th
        avg = np.interp(s, t_x[lo:hi], t_y[lo:hi]) * par[j, P_RATED]
        if state[j, 0] == 0.0:
            puls = np.interp(s, t_x[lo:hi], t_z[lo:hi]) * par[j, P_RATED]
            out = v * v * (avg + puls * np.sin(2.0 * delta))
        else:
            out = v * v * avg + v * par[j, P_TPO] * np.sin(delta - state[j, 1])
    factor = 1.0
    for k in range(s_ptr[j], s_ptr[j + 1]):
        if t >= s_t[k]:
            factor = s_f[k]
    return out * factor


@njit(cache=True, inline="always")
def drive_torques(t, q, v, drives, advance, force):
    """Every law's torque at time t from the state (q, v) into ``drives.torque``, and
    ``gain · sign · T`` added to ``force`` at its coordinate. ``advance``: a synchronous motor
    whose slip has reached its pull-in slip pulls into step here, before its torque
    (:func:`advance_state`: the coupled 6-DOF transient, an event located within the step
    being taken); otherwise the caller advances the states after each accepted step
    (:func:`advance_states`: the torsional transient)."""
    # the arrays read once here, the laws' pack passed on (NOTES in ..transient.kernels)
    dof, gain, sign, state, torque = (
        drives.dof,
        drives.gain,
        drives.sign,
        drives.state,
        drives.torque,
    )
    par, t_ptr, t_x, t_y, t_z, v_ptr, v_t, v_f, s_ptr, s_t, s_f = drives.laws
    for j in range(dof.shape[0]):
        d = dof[j]
        g = gain[j]
        th = g * q[d]
        om = g * v[d]
        if advance:
            advance_state(j, t, th, om, state, par)
        T = _law_torque(
            j, t, th, om, state, par, t_ptr, t_x, t_y, t_z, v_ptr, v_t, v_f, s_ptr, s_t, s_f
        )
        torque[j] = T
        force[d] += g * sign[j] * T


@njit(cache=True)
def advance_state(j, t, th, om, state, par):
    """Law j at time t (node angle th, speed om along the rotation): a synchronous motor whose
    slip has fallen to its pull-in slip pulls into step (state[j] = 1, δ_p). Returns whether
    it did."""
    if int(par[j, P_KIND]) != KIND_SYNCHRONOUS or state[j, 0] != 0.0:
        return False
    s = 1.0 - om / par[j, P_SPEED]
    if s <= par[j, P_PULLIN]:
        state[j, 0] = 1.0
        state[j, 1] = par[j, P_WLINE] * t - par[j, P_PP] * th
        return True
    return False


@njit(cache=True)
def advance_states(t, th, om, state, par):
    """After an accepted step at time t (th, om per law along the rotation): every law's
    :func:`advance_state`."""
    changed = False
    for j in range(par.shape[0]):
        if advance_state(j, t, th[j], om[j], state, par):
            changed = True
    return changed


def evaluate(laws: TorqueLaws, j: int, t, theta, omega, state: NDArray | None = None) -> NDArray:
    """Law j's torque (N·m, along the rotation) at arrays of t, θ, Ω (Python helper for tests
    and plots; the same compiled law the integrators call)."""
    t, theta, omega = np.broadcast_arrays(*(np.asarray(x, float) for x in (t, theta, omega)))
    st = laws.new_state() if state is None else state
    out = np.empty(t.shape)
    for k in np.ndindex(t.shape):
        out[k] = law_torque(j, t[k], theta[k], omega[k], st, laws.arrays)
    return out


def check_load_paths(laws: TorqueLaws, component_of: NDArray, node_dof) -> None:
    """Every drive must reach a load through the train's torsional connections:
    ``component_of`` labels the connected part of each DOF, ``node_dof(shaft, node)`` maps a
    law's node to its DOF. Raises :class:`ModelError` naming the drive otherwise."""
    loaded = {
        int(component_of[node_dof(*laws.nodes[j])])
        for j in range(len(laws))
        if not laws.is_drive[j]
    }
    for j in np.flatnonzero(laws.is_drive):
        if int(component_of[node_dof(*laws.nodes[j])]) not in loaded:
            raise ModelError(
                "no load path: the drive's shaft is joined to no load in torsion (a coupling "
                "without ktz, a missing mesh, or no load at all)",
                field=f"torsional.drives[{j}]",
                value=laws.names[j],
                expected="a [[torsional.loads]] entry on a shaft torsionally connected to it",
            )


def check_transient_supports(train: Train) -> None:
    """A transient turns the train (θz is the absolute angle): a torsional spring to ground
    would wind up with it, so it is refused (:class:`ModelError` naming the support); a damper
    to ground is a torque ``−c θ̇`` on the absolute speed, a viscous brake, and is kept."""
    for k, t in enumerate(train.torsional_supports):
        if t.k > 0:
            raise ModelError(
                "a torsional spring to ground holds the shaft, but a transient turns the train "
                "(θz is the absolute angle)",
                field=f"torsional_supports[{k}].k",
                value=f"{t.k:.6g} N·m/rad",
                expected="k = 0 in a transient (a damper c acts on the absolute speed); a held "
                "end belongs to the linear analyses (modes, response)",
            )
