"""Fast torsional-only transient: start-ups, short circuits, trips, with mesh backlash.

State: the absolute angle θ and speed θ̇ of every DOF of the torsional model (speed is a
state: a start-up from rest to full speed is one run). Equations

    M θ̈ + C θ̇ + K θ = Σ_j σ_j s_j T_j(t, σθ, σθ̇) e_j − Σ_k F_k w_k,

with the drive and load laws T_j of :mod:`.drive_laws` (σ the shaft's sense of rotation, s = +1
for drives, −1 for loads) and, for flexible meshes with backlash b, the contact force along the
line of action ``F = k (δ − b) + c δ̇`` (δ > b, drive flank), ``k (δ + b) + c δ̇`` (δ < −b, back
flank), 0 in between (δ = w·θ; SPEC 2.4's law restricted to torsion, where the mirrored back
flank has the same torque arms). Meshes without backlash are linear springs; rigid meshes are
constraints (no backlash; their force is the constraint reaction).

Integrator: the trapezoidal rule (Newmark average acceleration, β = 1/4, γ = 1/2), fixed step,
compiled with numba. Why: the rod elements of a train have torsional frequencies of tens of kHz
that carry no information about a start-up, and an explicit method (RK4) would need a step
below ~2.8/ω_max ≈ 1e-5 s for 20 s runs; the trapezoidal rule is unconditionally stable, so the
step only has to resolve the modes of interest, it conserves the energy of the linear part
exactly (so the energy balance is a real check of the run, see ``energy``), and its nonlinear
terms are few: per step the contact state of the backlash meshes is found by an active-set
iteration (a state is re-solved until δ at the end of the step agrees with it; each contact
state's effective matrix ``K_s + 2C_s/h + 4M/h²`` is inverted once up front) and the drive
torques, which depend on the end-of-step angle and speed, by fixed-point iteration to 1e-10 of
the rated torques. scipy's stiff solvers (BDF, Radau) would do the same with adaptive steps,
but with a Python right-hand side and Jacobian they take minutes for a 20 s start-up.

Step: by default 20 steps per period of the highest torsional natural frequency below
``max_frequency`` (1 kHz): that mode's frequency is then resolved to (ωh)²/12 ≈ 0.8 % (the
rule's period elongation), lower modes better; modes above are integrated stably but not
resolved. With backlash, the contact mode of each mesh (the mode with the largest share of its
strain energy in the mesh: the duration of a tooth impact) is resolved too, whatever its
frequency: an impact integrated across one coarse step loses the energy identity. Accuracy
check: halve the step (``dt``) and compare the peaks (tests/torsional show the peak shaft torque
of a synchronous-motor start-up converging at the rule's second order). Events (pull-in, a
contact change) take effect at the end of the step in which they occur: first order in the
step, a delay of at most one step.

Outputs (saved every ``save_dt``): speeds per shaft, shaft torque and shear stress per element,
coupling torques, mesh force and contact state, drive and load torques; per element the exact
extreme torques over every step; the energy balance: work of each drive and load, dissipation,
kinetic and potential energy, and its residual.
"""

from __future__ import annotations

import json
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numba import njit
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components

from ...assembly import Assembly
from ...errors import ModelError, SolverError
from ...model import Train
from ...threads import managed
from ..csr import Csr, csr, row_dot
from ..jit import configure_cache
from ..limits import MAX_STEPS, check_run_size
from .drive_laws import (
    P_RATED,
    Drives,
    TorqueLaws,
    advance_states,
    check_load_paths,
    check_transient_supports,
    drive_torques,
    law_torque,
    pack_laws,
)
from .model import TorsionalModel, torsional_model

configure_cache()  # before the first @njit(cache=True): numba's cache outside the package

__all__ = ["TorsionalTransient", "torsional_transient", "MAX_BACKLASH_MESHES"]

RPM = 30 / np.pi
#: contact states are enumerated: 2^n effective matrices for n meshes with backlash
MAX_BACKLASH_MESHES = 8


@dataclass(frozen=True)
class TorsionalTransient:
    """Result of :func:`torsional_transient` (SI units; arrays over the saved times).

    speed : (ns, n_shafts) rad/s along each shaft's rotation (polar-inertia weighted mean);
    element_torque, element_stress : (ns, ne); coupling_torque : (ns, nc); mesh_force : (ns, nm)
    N (normal, compression positive), mesh_state : (ns, nm) +1 drive flank, −1 back flank, 0
    separated; law_torque : (ns, nl) torque of each drive (motoring +) and load (braking +);
    element_torque_max/min : (ne,) extremes over every step; rated_element_torque : (ne,) the
    static torque at the nominal operating point (None without drives and loads).
    """

    model: TorsionalModel = field(repr=False)
    laws: TorqueLaws = field(repr=False)
    time: NDArray
    speed: NDArray
    element_torque: NDArray
    element_stress: NDArray
    coupling_torque: NDArray
    mesh_force: NDArray
    mesh_state: NDArray
    law_torque: NDArray
    element_torque_max: NDArray
    element_torque_min: NDArray
    coupling_torque_max: NDArray
    coupling_torque_min: NDArray
    mesh_force_max: NDArray
    mesh_force_min: NDArray
    rated_element_torque: NDArray | None
    law_work: NDArray  # (nl,) J, work done on the train (loads negative)
    dissipated: float  # J
    kinetic: tuple[float, float]  # (initial, final) J
    potential: tuple[float, float]
    dt: float
    steps: int
    iterations: int  # total iterations (≥ steps)
    unsettled_steps: int  # steps whose contact state / torques did not settle
    pull_in_time: NDArray  # (nl,) s, NaN if the law did not pull in (synchronous motors)
    wall_time: float
    notes: tuple[str, ...] = ()

    @property
    def energy_residual(self) -> float:
        """Work in − (ΔKE + ΔPE + dissipation), J."""
        return float(
            self.law_work.sum()
            - (self.kinetic[1] - self.kinetic[0])
            - (self.potential[1] - self.potential[0])
            - self.dissipated
        )

    @property
    def energy_error(self) -> float:
        """|energy residual| relative to the drives' work."""
        w = np.abs(self.law_work).sum()
        return abs(self.energy_residual) / w if w > 0 else 0.0

    @property
    def peak_element_torque(self) -> NDArray:
        """(ne,) largest |shaft torque| over every step, N·m."""
        return np.maximum(np.abs(self.element_torque_max), np.abs(self.element_torque_min))

    @property
    def peak_element_stress(self) -> NDArray:
        return self.model.shear_stress(self.peak_element_torque)

    def section_table(self) -> list[dict]:
        """Per shaft section: peak |torque|, rated torque (largest static torque of its
        elements at the nominal point; None outside the load path) and their ratio; peak
        shear stress."""
        tm = self.model
        out = []
        rated_all = self.rated_element_torque
        floor = 1e-6 * np.abs(rated_all).max() if rated_all is not None else 0.0
        for s, name in enumerate(tm.shaft_names):
            for sec in np.unique(tm.el_section[tm.el_shaft == s]):
                idx = np.flatnonzero((tm.el_shaft == s) & (tm.el_section == sec))
                k = idx[np.argmax(self.peak_element_torque[idx])]
                rated = float(np.max(np.abs(rated_all[idx]))) if rated_all is not None else None
                if rated is not None and rated <= floor:
                    rated = None  # outside the load path (beyond the load, a free end)
                peak = float(self.peak_element_torque[k])
                out.append(
                    {
                        "shaft": name,
                        "section": int(sec),
                        "element": int(tm.el_number[k]),
                        "peak_torque_Nm": peak,
                        "rated_torque_Nm": rated,
                        "peak_over_rated": peak / rated if rated else None,
                        "peak_shear_stress_Pa": float(self.peak_element_stress[k]),
                        "scf": float(tm.el_scf[k]),
                    }
                )
        return out

    def to_dict(self) -> dict:
        tm = self.model
        return {
            "mesh_model": tm.mesh,
            "t_end_s": float(self.time[-1]),
            "dt_s": self.dt,
            "steps": self.steps,
            "iterations": self.iterations,
            "unsettled_steps": self.unsettled_steps,
            "wall_time_s": self.wall_time,
            "final_speeds_rpm": dict(
                zip(tm.shaft_names, (self.speed[-1] * RPM).tolist(), strict=True)
            ),
            "sections": self.section_table(),
            "couplings": [
                {
                    "name": n,
                    "max_torque_Nm": float(self.coupling_torque_max[k]),
                    "min_torque_Nm": float(self.coupling_torque_min[k]),
                }
                for k, n in enumerate(tm.cp_names)
            ],
            "meshes": [
                {
                    "name": n,
                    "max_force_N": float(self.mesh_force_max[k]),
                    "min_force_N": float(self.mesh_force_min[k]),
                    "separated_fraction": float(np.mean(self.mesh_state[:, k] == 0)),
                    "back_flank_fraction": float(np.mean(self.mesh_state[:, k] == -1)),
                }
                for k, n in enumerate(tm.mesh_names)
            ],
            "laws": [
                {
                    "name": n,
                    "drive": bool(self.laws.is_drive[j]),
                    "work_J": float(self.law_work[j]),
                    "max_torque_Nm": float(self.law_torque[:, j].max()),
                    "pull_in_time_s": None
                    if np.isnan(self.pull_in_time[j])
                    else float(self.pull_in_time[j]),
                }
                for j, n in enumerate(self.laws.names)
            ],
            "energy": {
                "work_J": float(self.law_work.sum()),
                "kinetic_J": float(self.kinetic[1] - self.kinetic[0]),
                "potential_J": float(self.potential[1] - self.potential[0]),
                "dissipated_J": self.dissipated,
                "residual_J": self.energy_residual,
                "relative_error": self.energy_error,
            },
            "notes": list(self.notes),
        }

    def to_xarray(self, fatigue=None):
        """An ``xarray.Dataset`` of the histories (units attributes, the model embedded as
        JSON, the summary of :meth:`to_dict` and of ``fatigue`` as JSON attributes)."""
        import xarray as xr

        tm = self.model
        data = {
            "speed": (("time", "shaft"), self.speed, {"units": "rad/s"}),
            "element_torque": (("time", "element"), self.element_torque, {"units": "N m"}),
            "element_stress": (
                ("time", "element"),
                self.element_stress,
                {"units": "Pa", "long_name": "surface shear stress x SCF"},
            ),
            "coupling_torque": (("time", "coupling"), self.coupling_torque, {"units": "N m"}),
            "mesh_force": (("time", "mesh"), self.mesh_force, {"units": "N"}),
            "mesh_state": (
                ("time", "mesh"),
                self.mesh_state.astype(np.int8),
                {"long_name": "+1 drive flank, 0 separated, -1 back flank"},
            ),
            "law_torque": (
                ("time", "law"),
                self.law_torque,
                {"units": "N m", "long_name": "drive (motoring +) and load (braking +) torque"},
            ),
            "peak_element_torque": (("element",), self.peak_element_torque, {"units": "N m"}),
        }
        if self.rated_element_torque is not None:
            data["rated_element_torque"] = (
                ("element",),
                self.rated_element_torque,
                {"units": "N m"},
            )
        attrs = {
            "title": "gearrotor torsional transient",
            "model_json": tm.train.model_dump_json(),
            "summary_json": json.dumps(self.to_dict()),
        }
        if fatigue is not None:
            attrs["fatigue_json"] = json.dumps(fatigue.to_dict())
        return xr.Dataset(
            data,
            coords={
                "time": ("time", self.time, {"units": "s"}),
                "shaft": list(tm.shaft_names),
                "element": tm.element_labels(),
                "coupling": list(tm.cp_names),
                "mesh": list(tm.mesh_names),
                "law": list(self.laws.names),
            },
            attrs=attrs,
        )

    def save(self, path: str | Path, fatigue=None) -> Path:
        """Write the result atomically (temporary file in the same directory, then
        ``os.replace``): ``.nc`` NetCDF (:meth:`to_xarray`, h5netcdf engine) or ``.json``
        (:meth:`to_dict`, the fatigue summary, and the histories of time, speed, drive and
        load torques, shaft, coupling torques and mesh forces)."""
        from ...files import write_json, write_netcdf

        path = Path(path)
        if path.suffix.lower() == ".json":
            out = self.to_dict()
            if fatigue is not None:
                out["fatigue"] = fatigue.to_dict()
            tm = self.model
            out["histories"] = {
                "time_s": self.time.tolist(),
                "speed_rad_s": dict(zip(tm.shaft_names, self.speed.T.tolist(), strict=True)),
                "law_torque_Nm": dict(
                    zip(self.laws.names, self.law_torque.T.tolist(), strict=True)
                ),
                "element_torque_Nm": dict(
                    zip(tm.element_labels(), self.element_torque.T.tolist(), strict=True)
                ),
                "coupling_torque_Nm": dict(
                    zip(tm.cp_names, self.coupling_torque.T.tolist(), strict=True)
                ),
                "mesh_force_N": dict(zip(tm.mesh_names, self.mesh_force.T.tolist(), strict=True)),
            }
            write_json(path, out, indent=None, allow_nan=False)
        else:
            write_netcdf(path, self.to_xarray(fatigue))
        return path

    def table(self) -> str:
        rows = [
            f"{'shaft':<14} {'sec':>3} {'peak N·m':>12} {'rated N·m':>12} {'peak/rated':>10} "
            f"{'peak MPa':>9}"
        ]
        rows.append("-" * len(rows[0]))
        for r in self.section_table():
            rated = "-" if r["rated_torque_Nm"] is None else f"{r['rated_torque_Nm']:.4g}"
            ratio = "-" if r["peak_over_rated"] is None else f"{r['peak_over_rated']:.3g}"
            rows.append(
                f"{r['shaft']:<14} {r['section']:>3} {r['peak_torque_Nm']:>12.4g} {rated:>12} "
                f"{ratio:>10} {r['peak_shear_stress_Pa'] / 1e6:>9.4g}"
            )
        tm = self.model
        for k, n in enumerate(tm.cp_names):
            rows.append(
                f"coupling {n}: torque {self.coupling_torque_min[k]:.4g} .. "
                f"{self.coupling_torque_max[k]:.4g} N·m"
            )
        for k, n in enumerate(tm.mesh_names):
            sep = np.mean(self.mesh_state[:, k] != 1)
            rows.append(
                f"mesh {n}: force {self.mesh_force_min[k]:.4g} .. {self.mesh_force_max[k]:.4g} N, "
                f"off the drive flank {sep:.1%} of the time"
            )
        rows.append(
            f"dt {self.dt:.3g} s, {self.steps} steps, {self.iterations} iterations, "
            f"{self.unsettled_steps} unsettled; energy residual {self.energy_error:.2e} of the "
            f"work; {self.wall_time:.2f} s"
        )
        rows.extend(self.notes)
        return "\n".join(rows)


# ------------------------------------------------------------------------------------------
# kernel: the packs it reads, then the trapezoidal steps
# ------------------------------------------------------------------------------------------
class Linear(NamedTuple):
    """The linear part of the reduced model: M, and K, C without the flexible meshes (each
    :class:`~..csr.Csr`); ``Kinv`` (2^nb, n, n) the inverse of the effective matrix
    ``K_s + 2 C_s / h + 4 M / h²`` of every contact state s of the nb backlash meshes."""

    M: Csr
    K: Csr
    C: Csr
    Kinv: NDArray


class Meshes(NamedTuple):
    """Flexible meshes on their line of action, δ = wi θ_i + wj θ_j (reduced coordinates
    i, j): stiffness k, damping c, backlash b (F = k (δ − s b) + c δ̇ on flank s); ``bit``
    the mesh's bit in the contact-state combination (−1: no backlash, always engaged);
    ``state`` (mutable) its contact state +1 drive flank, 0 separated, −1 back flank."""

    i: NDArray
    j: NDArray
    wi: NDArray
    wj: NDArray
    k: NDArray
    c: NDArray
    b: NDArray
    bit: NDArray
    state: NDArray


class Elements(NamedTuple):
    """Shaft elements: torque ``k (fj θ_j − fi θ_i)`` between reduced coordinates i and j
    (fi, fj: the nodes' factors on their masters)."""

    i: NDArray
    j: NDArray
    fi: NDArray
    fj: NDArray
    k: NDArray


class Couplings(NamedTuple):
    """Couplings: torque ``k (fj θ_j − fi θ_i) + c (fj θ̇_j − fi θ̇_i)``."""

    i: NDArray
    j: NDArray
    fi: NDArray
    fj: NDArray
    k: NDArray
    c: NDArray


class Samples(NamedTuple):
    """The saved samples (filled by the kernel): time, reduced angles p and speeds v, the
    laws' torques, the meshes' contact state and force."""

    time: NDArray
    p: NDArray
    v: NDArray
    torque: NDArray
    mesh_state: NDArray
    mesh_force: NDArray


class Extremes(NamedTuple):
    """Extremes over every step (updated by the kernel): element and coupling torques, mesh
    forces."""

    element_max: NDArray
    element_min: NDArray
    coupling_max: NDArray
    coupling_min: NDArray
    mesh_max: NDArray
    mesh_min: NDArray


class Tally(NamedTuple):
    """Accumulated by the kernel: each law's work, the dissipated energy (1,), each law's
    pull-in time (NaN: none) and the statistics (iterations, unsettled steps, diverged)."""

    work: NDArray
    dissipated: NDArray
    pull_in: NDArray
    stats: NDArray


@njit(cache=True)
def _mv(A, x, out):
    """out = A x (``A`` a :class:`~..csr.Csr`)."""
    indptr, indices, data = A
    for i in range(indptr.shape[0] - 1):
        out[i] = row_dot(indptr, indices, data, i, x)


@njit(cache=True)
def _law_forces(t, p, v, drives, g):
    """Generalised law forces g (overwritten); the laws' torques into ``drives.torque``."""
    for i in range(g.shape[0]):
        g[i] = 0.0
    drive_torques(t, p, v, drives, False, g)


@njit(cache=True)
def _state_of(delta, b):
    if delta > b:
        return 1
    if delta < -b:
        return -1
    return 0


@njit(cache=True, inline="always")
def _deflection(k, x, mi, mj, wi, wj):
    """δ (or δ̇) of mesh k for the angles (or speeds) x (the :class:`Meshes` arrays)."""
    return wi[k] * x[mi[k]] + wj[k] * x[mj[k]]


@njit(cache=True)
def _run(
    h, n_steps, save_every, t0, p, v, a, lin, meshes, drives, elements, couplings, samples, ext,
    tally, tol, max_iter,
):  # fmt: skip
    """The trapezoidal steps from (p, v, a) at t0 (module docstring): per step the contact
    state of the backlash meshes by an active-set iteration and the law torques at the end of
    the step by fixed-point iteration; the law events after each accepted step. Returns the
    number of samples saved."""
    n = p.shape[0]
    mi, mj, wi, wj, mk, mc, mb, bit, mstate = meshes
    dof, gain, sign, state, _, laws = drives
    ei, ej, efi, efj, ek = elements
    ci, cj, cfi, cfj, ck, cc = couplings
    e_max, e_min, c_max, c_min, f_max, f_min = ext
    o_t, o_p, o_v, o_tq, o_ms, o_mf = samples
    M, K, C, Kinv = lin
    work, diss, pull_in, stats = tally
    nm = mi.shape[0]
    nl = dof.shape[0]
    par = laws.par
    # work vectors of the state's length: law forces at both ends, M, K, C terms, ...
    wn = np.zeros((12, n))
    g0, g1, Mterm, Kp_n, Cv_n, tmp, rhs, dp, p1, v1, a1, vb = (
        wn[0], wn[1], wn[2], wn[3], wn[4], wn[5], wn[6], wn[7], wn[8], wn[9], wn[10], wn[11]
    )  # fmt: skip
    # per law: torques at the step start, the previous iterate; angle and speed
    wl = np.zeros((4, nl))
    tq0, tq_old, th, om = wl[0], wl[1], wl[2], wl[3]
    tq1 = drives.torque  # the torques of the last evaluation: the end of the step
    s_try = np.zeros(nm, np.int64)
    s_new = np.zeros(nm, np.int64)
    t = t0
    _law_forces(t, p, v, drives, g0)
    for j in range(nl):
        tq0[j] = tq1[j]
    isave = 0
    iters = 0
    unsettled = 0
    for step in range(n_steps + 1):
        save = step % save_every == 0 or step == n_steps
        # ---- the extremes of the current state, and (save) its sample --------------------
        # (inline: a call with the packs would count a reference to each of their arrays)
        for e in range(ei.shape[0]):
            T = ek[e] * (efj[e] * p[ej[e]] - efi[e] * p[ei[e]])
            if T > e_max[e]:
                e_max[e] = T
            if T < e_min[e]:
                e_min[e] = T
        for c in range(ci.shape[0]):
            T = ck[c] * (cfj[c] * p[cj[c]] - cfi[c] * p[ci[c]]) + cc[c] * (
                cfj[c] * v[cj[c]] - cfi[c] * v[ci[c]]
            )
            if T > c_max[c]:
                c_max[c] = T
            if T < c_min[c]:
                c_min[c] = T
        for k in range(nm):
            dl = _deflection(k, p, mi, mj, wi, wj)
            dv = _deflection(k, v, mi, mj, wi, wj)
            s = mstate[k]
            F = 0.0
            if s != 0 or bit[k] < 0:
                F = mk[k] * (dl - s * mb[k]) + mc[k] * dv
            if F > f_max[k]:
                f_max[k] = F
            if F < f_min[k]:
                f_min[k] = F
            if save:
                o_mf[isave, k] = F
                o_ms[isave, k] = s if bit[k] >= 0 else (1 if dl >= 0 else -1)
        if save:
            o_t[isave] = t
            for i in range(n):
                o_p[isave, i] = p[i]
                o_v[isave, i] = v[i]
            for j in range(nl):
                o_tq[isave, j] = tq0[j]
            isave += 1
        if step == n_steps:
            break
        # ---- one trapezoidal step -----------------------------------------------------------
        t1 = t + h
        _mv(K, p, Kp_n)
        _mv(C, v, Cv_n)
        for i in range(n):
            tmp[i] = 4.0 / h * v[i] + a[i]
        _mv(M, tmp, Mterm)
        # predictor for the law torques, contact state from the last step
        for i in range(n):
            p1[i] = p[i] + h * v[i] + 0.5 * h * h * a[i]
            v1[i] = v[i] + h * a[i]
        _law_forces(t1, p1, v1, drives, g1)
        for k in range(nm):
            s_try[k] = mstate[k]
        settled = False
        for it in range(max_iter):
            iters += 1
            comb = 0
            for i in range(n):
                rhs[i] = g1[i] + Mterm[i] - Kp_n[i] + Cv_n[i]
            for k in range(nm):
                if bit[k] >= 0 and s_try[k] == 0:
                    continue
                if bit[k] >= 0:
                    comb += 1 << bit[k]
                dl = _deflection(k, p, mi, mj, wi, wj)
                dv = _deflection(k, v, mi, mj, wi, wj)
                f = -mk[k] * (dl - s_try[k] * mb[k]) + mc[k] * dv
                if bit[k] < 0:
                    f = -mk[k] * dl + mc[k] * dv
                rhs[mi[k]] += f * wi[k]
                rhs[mj[k]] += f * wj[k]
            for i in range(n):
                acc = 0.0
                for j in range(n):
                    acc += Kinv[comb, i, j] * rhs[j]
                dp[i] = acc
            for i in range(n):
                p1[i] = p[i] + dp[i]
                v1[i] = 2.0 / h * dp[i] - v[i]
            change = False
            for k in range(nm):
                if bit[k] >= 0:
                    s_new[k] = _state_of(_deflection(k, p1, mi, mj, wi, wj), mb[k])
                    if s_new[k] != s_try[k]:
                        change = True
            err = 0.0
            scale = 0.0
            for j in range(nl):
                tq_old[j] = tq1[j]
            _law_forces(t1, p1, v1, drives, g1)
            for j in range(nl):
                err = max(err, abs(tq1[j] - tq_old[j]))
                scale = max(scale, abs(par[j, P_RATED]))
            if not change and err <= tol * max(scale, 1.0):
                settled = True
                break
            if change and it >= 4:
                # chattering at a flank: keep the contact (stiff) state of the previous try
                for k in range(nm):
                    if s_try[k] != 0:
                        s_new[k] = s_try[k]
            for k in range(nm):
                s_try[k] = s_new[k]
        if not settled:
            unsettled += 1
        for k in range(nm):
            mstate[k] = s_try[k]
        # accelerations, energy, advance
        for i in range(n):
            a1[i] = 4.0 / (h * h) * dp[i] - 4.0 / h * v[i] - a[i]
            vb[i] = v[i] + v1[i]
        _mv(C, vb, tmp)
        dd = 0.0
        for i in range(n):
            dd += vb[i] * tmp[i]
        for k in range(nm):
            if bit[k] < 0 or mstate[k] != 0:
                dvb = _deflection(k, vb, mi, mj, wi, wj)
                dd += mc[k] * dvb * dvb
        diss[0] += 0.25 * h * dd
        for j in range(nl):
            d = dof[j]
            fj = gain[j] * sign[j]
            work[j] += 0.5 * (tq0[j] + tq1[j]) * fj * (p1[d] - p[d])
        for i in range(n):
            p[i] = p1[i]
            v[i] = v1[i]
            a[i] = a1[i]
        for j in range(nl):
            tq0[j] = tq1[j]
        t = t1
        for j in range(nl):
            f = gain[j]
            th[j] = f * p[dof[j]]
            om[j] = f * v[dof[j]]
        if advance_states(t, th, om, state, par):
            for j in range(nl):
                if state[j, 0] != 0.0 and np.isnan(pull_in[j]):
                    pull_in[j] = t
            # the synchronous torque starts from zero: the step's end torques are unchanged
        for i in range(n):
            if not np.isfinite(p[i]):
                stats[0] = iters
                stats[1] = unsettled
                stats[2] = 1
                return isave
    stats[0] = iters
    stats[1] = unsettled
    stats[2] = 0
    return isave


def _default_dt(tm: TorsionalModel, max_frequency: float, contact: NDArray) -> float:
    """20 steps per period of the highest mode below ``max_frequency`` and of the contact mode
    of every mesh with backlash (``contact``, (nm,) bool): the mode with the largest share of
    its strain energy in the mesh, whose period is the duration of a tooth impact."""
    w2, V = la.eigh(tm.K, tm.M)
    n_rigid = tm.rigid_modes().shape[1]
    w = np.sqrt(np.abs(w2[n_rigid:]))
    V = V[:, n_rigid:]
    keep = list(w[w <= max_frequency])
    T = tm.T
    for k in np.flatnonzero(contact):
        wf = np.zeros(tm.n_full)
        wf[tm.mesh_dofs[k]] = tm.mesh_w[k]
        share = tm.mesh_stiffness[k] * (V.T @ (T.T @ wf)) ** 2 / w**2
        keep.append(w[np.argmax(share)])
    if not keep:
        return 2 * np.pi / max_frequency / 20
    return float(2 * np.pi / max(keep) / 20)


@managed
def torsional_transient(
    model: Train | Assembly | TorsionalModel,
    *,
    t_end: float,
    dt: float | None = None,
    mesh: str = "flexible",
    save_dt: float | None = None,
    initial_speed: float = 0.0,
    static_initial: bool | None = None,
    max_frequency: float = 2 * np.pi * 1000.0,
    tol: float = 1e-10,
    max_iter: int = 30,
) -> TorsionalTransient:
    """Integrate the torsional transient of a train with its ``[torsional]`` drives and loads
    (module docstring).

    Parameters
    ----------
    model : a :class:`Train` / :class:`Assembly` (torsional model built with ``mesh``) or a
        :class:`TorsionalModel` (without fixed nodes)
    t_end : s; dt : s (default: 20 steps per period of the highest mode below
        ``max_frequency``, rad/s); save_dt : s between saved samples (default 5e-4 s, at
        least dt)
    initial_speed : rad/s of the reference shaft at t = 0 (every shaft at its ratio; 0: a
        start from rest)
    static_initial : start from the static twist under the torques at t = 0 (default: True
        when the train starts at speed, False from rest); a synchronous motor that starts
        within its pull-in slip starts in step with the load angle that carries its share of
        the load
    tol : relative tolerance of the drive-torque iteration; max_iter : iterations per step
    """
    t_start = _time.perf_counter()
    tm = model if isinstance(model, TorsionalModel) else torsional_model(model, mesh=mesh)
    train = tm.train
    if np.any(tm.master < 0):
        raise ModelError(
            "the transient turns the whole train: fixed nodes are not allowed",
            field="fixed",
            expected="a torsional model without fixed nodes",
        )
    if not (np.isfinite(t_end) and t_end > 0):
        raise ModelError("t_end must be positive", field="t_end", value=t_end)
    check_transient_supports(train)  # dampers to ground act on the absolute speed
    laws = pack_laws(train)
    if len(laws) == 0:
        raise ModelError(
            "a torsional transient needs drives or loads",
            field="torsional",
            expected="[[torsional.drives]] / [[torsional.loads]] in the model",
        )
    notes = []
    nm = len(tm.mesh_names)
    if tm.mesh == "flexible":
        for m in tm.assembly.meshes:
            ri, rj = m.geometry.radius_i, m.geometry.radius_j
            ni, nj = m.teeth
            if abs(ri / rj - ni / nj) > 1e-9 * ni / nj:
                raise ModelError(
                    "the torsional transient needs pitch radii exactly in the tooth ratio (the "
                    "absolute angles roll at N_i θ_i = −N_j θ_j; a mismatch grows into a mesh "
                    "deflection)",
                    field=f"meshes[{m.spec_index}]",
                    value=f"r_i/r_j = {ri / rj:.9g}, N_i/N_j = {ni / nj:.9g}",
                    expected="r_i/r_j = N_i/N_j",
                )
    elif np.any(tm.mesh_backlash > 0):
        raise ModelError(
            "rigid meshes have no backlash: give mesh = 'flexible' for a transient with backlash",
            field="mesh",
            value="rigid",
            expected="'flexible' (or backlash 0)",
        )
    variation = [
        train.meshes[m.spec_index].name or f"meshes[{m.spec_index}]"
        for m in tm.assembly.meshes
        if (
            train.meshes[m.spec_index].variation.ka_ratio > 0
            and train.meshes[m.spec_index].variation.terms > 0
        )
        or train.meshes[m.spec_index].stiffness_table is not None
        or train.meshes[m.spec_index].transmission_error is not None
        or train.meshes[m.spec_index].excitation_law == "geometry"
    ]
    if variation:
        notes.append(
            "mesh stiffness variation / transmission error of "
            f"{', '.join(variation)} not included: the torsional transient uses the average Kg"
        )
    # ---- load paths -------------------------------------------------------------------------
    # torque reaches a load through stiffness: a coupling with ktz = 0 and a damper only would
    # slip without bound (its twist grows with the transmitted torque times time)
    edges = [tm.el_dofs, tm.cp_dofs[tm.cp_stiffness > 0]]
    if nm:
        edges.append(tm.mesh_dofs if tm.mesh == "rigid" else tm.mesh_dofs[tm.mesh_stiffness > 0])
    e = np.concatenate([x.reshape(-1, 2) for x in edges])
    graph = sp.coo_array((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(tm.n_full,) * 2)
    _, component = connected_components(graph, directed=False)
    try:
        check_load_paths(laws, component, tm.dof)
    except ModelError:
        for k in np.flatnonzero((tm.cp_stiffness == 0) & (tm.cp_damping > 0)):
            a, b = tm.cp_dofs[k]
            if component[a] != component[b]:
                raise ModelError(
                    "a coupling in a drive's load path has no torsional stiffness: through "
                    "its damper alone the twist would grow without bound under the torque",
                    field=f"couplings[{k}].ktz",
                    value=0.0,
                    expected="a positive torsional stiffness (N*m/rad) for a coupling that "
                    "carries the drive's torque",
                ) from None
        raise

    # ---- matrices ---------------------------------------------------------------------------
    n = tm.n
    T = tm.T
    W = np.zeros((nm, n))
    for k in range(nm):
        wf = np.zeros(tm.n_full)
        wf[tm.mesh_dofs[k]] = tm.mesh_w[k]
        W[k] = T.T @ wf
    K0, C0 = tm.K.copy(), tm.C.copy()
    if tm.mesh == "flexible":
        for k in range(nm):
            K0 -= tm.mesh_stiffness[k] * np.outer(W[k], W[k])
            C0 -= tm.mesh_damping[k] * np.outer(W[k], W[k])
        # no fixed nodes and no rigid meshes: every gear node is its own reduced coordinate
        m_idx = tm.master[tm.mesh_dofs].astype(np.int64).reshape(nm, 2)
        m_w = (tm.mesh_w * tm.factor[tm.mesh_dofs]).reshape(nm, 2)
        bl = np.flatnonzero(tm.mesh_backlash > 0)
        if len(bl) > MAX_BACKLASH_MESHES:
            raise ModelError(
                "too many meshes with backlash for the torsional transient",
                field="meshes",
                value=len(bl),
                expected=f"at most {MAX_BACKLASH_MESHES}",
            )
        m_bit = -np.ones(nm, np.int64)
        m_bit[bl] = np.arange(len(bl))
        kin = nm
    else:  # rigid meshes live in T
        m_idx = np.zeros((0, 2), np.int64)
        m_w = np.zeros((0, 2))
        m_bit = np.zeros(0, np.int64)
        bl = np.zeros(0, int)
        kin = 0
    kin_k = tm.mesh_stiffness[:kin].astype(float)
    kin_c = tm.mesh_damping[:kin].astype(float)
    kin_b = tm.mesh_backlash[:kin].astype(float)

    given_dt = dt is not None
    if dt is None:
        dt = _default_dt(
            tm, max_frequency, tm.mesh_backlash > 0 if tm.mesh == "flexible" else np.zeros(nm, bool)
        )
    if not (np.isfinite(dt) and dt > 0):
        raise ModelError("the time step must be positive", field="dt", value=dt)
    if save_dt is not None and not (np.isfinite(save_dt) and save_dt > 0):
        raise ModelError("the save interval must be positive", field="save_dt", value=save_dt)
    steps = np.ceil(t_end / dt - 1e-9)  # a float first: 1e12 steps must not be an int loop
    save_dt = 5e-4 if save_dt is None else save_dt
    every = max(1.0, np.round(save_dt / (t_end / steps)))
    per_sample = (
        1
        + 2 * tm.n
        + len(laws)
        + 2 * nm
        + 3 * tm.n_full
        + 2 * len(tm.el_stiffness)
        + len(tm.cp_names)
        + len(tm.shaft_names)
    )  # saved states, torques, mesh records, and the outputs derived from them
    too_many_steps = steps > MAX_STEPS
    check_run_size(
        int(min(steps, 2**62)),
        int(min(steps // every + 2, 2**62)),
        per_sample,
        t_end,
        field="dt" if given_dt and too_many_steps else "t_end",
        value=dt if given_dt and too_many_steps else None,
    )
    n_steps = int(steps)
    h = t_end / n_steps
    save_every = max(1, int(round(save_dt / h)))
    n_save = n_steps // save_every + 1 + (n_steps % save_every != 0)  # the end is saved

    # effective matrices of every contact combination
    ncomb = 1 << len(bl)
    Kinv = np.empty((ncomb, n, n))
    for comb in range(ncomb):
        Ks, Cs = K0.copy(), C0.copy()
        for k in range(kin):
            on = m_bit[k] < 0 or (comb >> m_bit[k]) & 1
            if on:
                Ks += kin_k[k] * np.outer(W[k], W[k])
                Cs += kin_c[k] * np.outer(W[k], W[k])
        Kinv[comb] = la.inv(Ks + 2.0 / h * Cs + 4.0 / h**2 * tm.M)

    # ---- laws: nodes to reduced DOFs ---------------------------------------------------------
    nl = len(laws)
    full = np.array([tm.dof(s, nd) for s, nd in laws.nodes], np.int64)
    l_sense = tm.rotation[tm.node_shaft[full]].astype(float)
    # a law's node angle along the rotation: σ · factor · (its master's reduced coordinate)
    drives = laws.drives(tm.master[full], tm.factor[full].astype(float) * l_sense)
    meshes = Meshes(
        m_idx[:, 0].copy(),
        m_idx[:, 1].copy(),
        m_w[:, 0].copy(),
        m_w[:, 1].copy(),
        kin_k,
        kin_c,
        kin_b,
        m_bit,
        np.zeros(nm if tm.mesh == "flexible" else 0, np.int64),
    )

    # ---- initial state ------------------------------------------------------------------------
    v = tm.speed_ratio[tm.node_shaft[tm.roots]] * initial_speed  # every node at its shaft's speed
    p = np.zeros(n)
    if static_initial is None:
        static_initial = initial_speed != 0.0
    g = np.zeros(n)
    if initial_speed != 0.0:
        _synchronise_at_start(laws, drives, p, v)
    if static_initial:
        _law_forces(0.0, p, v, drives, g)
        f0 = np.zeros(tm.n_full)
        np.add.at(f0, full, drives.torque * laws.par[:, 1] * l_sense)
        p, _ = tm.static_reduced(f0, balanced=False)
        if np.any(kin_b > 0):
            # the loaded flank of each backlash mesh is in contact: F = k (δ − s b), so the
            # twist is the linear one plus the clearance taken up, a prestrain s b along w
            for k in np.flatnonzero(kin_b > 0):
                s_k = np.sign(kin_k[k] * (W[k] @ p))
                f0[tm.mesh_dofs[k]] += kin_k[k] * kin_b[k] * s_k * tm.mesh_w[k]
            p, _ = tm.static_reduced(f0, balanced=False)
        _synchronise_at_start(laws, drives, p, v)
    _law_forces(0.0, p, v, drives, g)
    mstate = meshes.state
    for k in range(len(mstate)):
        dl = m_w[k, 0] * p[m_idx[k, 0]] + m_w[k, 1] * p[m_idx[k, 1]]
        mstate[k] = _state_of(dl, kin_b[k]) if m_bit[k] >= 0 else 1
    force = g - K0 @ p - C0 @ v
    for k in range(kin):
        on = m_bit[k] < 0 or mstate[k] != 0
        if on:
            dl = W[k] @ p
            dv = W[k] @ v
            force -= (
                kin_k[k] * (dl - (mstate[k] * kin_b[k] if m_bit[k] >= 0 else 0.0)) + kin_c[k] * dv
            ) * W[k]
    a = la.solve(tm.M, force)
    ke0 = 0.5 * v @ tm.M @ v
    pe0 = _potential(tm, p, meshes)

    # ---- element maps, records ----------------------------------------------------------------
    def mapped(d):
        d = np.asarray(d, np.int64).reshape(-1, 2)
        return (
            tm.master[d[:, 0]].astype(np.int64),
            tm.master[d[:, 1]].astype(np.int64),
            tm.factor[d[:, 0]].astype(float),
            tm.factor[d[:, 1]].astype(float),
        )

    elements = Elements(*mapped(tm.el_dofs), tm.el_stiffness.astype(float))
    couplings = Couplings(
        *mapped(tm.cp_dofs), tm.cp_stiffness.astype(float), tm.cp_damping.astype(float)
    )
    ne, nc, nk = len(elements.i), len(couplings.i), len(mstate)
    samples = Samples(
        np.zeros(n_save),
        np.zeros((n_save, n)),
        np.zeros((n_save, n)),
        np.zeros((n_save, nl)),
        np.zeros((n_save, nk), np.int64),
        np.zeros((n_save, nk)),
    )
    ext = Extremes(
        *(np.full(ne, -np.inf), np.full(ne, np.inf)),
        *(np.full(nc, -np.inf), np.full(nc, np.inf)),
        *(np.full(nk, -np.inf), np.full(nk, np.inf)),
    )
    tally = Tally(np.zeros(nl), np.zeros(1), np.full(nl, np.nan), np.zeros(3, np.int64))
    tally.pull_in[drives.state[:, 0] != 0] = 0.0
    lin = Linear(
        csr(tm.M, drop_zeros=True), csr(K0, drop_zeros=True), csr(C0, drop_zeros=True), Kinv
    )
    n_saved = _run(
        h, n_steps, save_every, 0.0, p, v, a, lin, meshes, drives, elements, couplings, samples,
        ext, tally, tol, max_iter,
    )  # fmt: skip
    stats = tally.stats
    if stats[2]:
        raise SolverError(
            "the torsional transient diverged (non-finite state) near "
            f"t = {samples.time[n_saved - 1]:.4g} s: the trapezoidal rule is stable at any step "
            "for the linear part, so check what drives it (negative or absurd damping, stiffness "
            f"or torques); a smaller dt (now {h:.3g} s) helps only when the drive torques did not "
            f"settle ({int(stats[1])} unsettled steps)"
        )
    o_t, o_p, o_v = samples.time[:n_saved], samples.p[:n_saved], samples.v[:n_saved]
    o_tq, o_ms, o_mf = (
        samples.torque[:n_saved],
        samples.mesh_state[:n_saved],
        samples.mesh_force[:n_saved],
    )

    # ---- outputs ------------------------------------------------------------------------------
    theta = tm.expand(o_p)
    theta_dot = tm.expand(o_v)
    el_t = tm.element_torque(theta)
    cp_t = tm.coupling_torque(theta, theta_dot)
    f_nodes = np.zeros((n_saved, tm.n_full))
    np.add.at(f_nodes.T, full, (o_tq * (laws.par[:, 1] * l_sense)).T)
    if tm.mesh == "rigid" and nm:
        acc = la.solve(tm.M, (tm.reduce_force(f_nodes) - o_v @ tm.C.T - o_p @ tm.K.T).T).T
        res = tm.expand(acc) @ tm.M_full.T + theta_dot @ tm.C_full.T + theta @ tm.K_full.T
        mf = tm.mesh_force(theta, residual=res - f_nodes)
        ms = np.sign(mf).astype(np.int64)
        fmx, fmn = mf.max(axis=0), mf.min(axis=0)
        notes.append("rigid meshes: mesh force extremes over the saved samples")
    else:
        mf, ms, fmx, fmn = o_mf, o_ms, ext.mesh_max, ext.mesh_min
    row = np.abs(tm.M_full).sum(axis=1)
    speed = np.zeros((n_saved, len(tm.shaft_names)))
    for s in range(len(tm.shaft_names)):
        idx = tm.node_shaft == s
        speed[:, s] = tm.rotation[s] * (theta_dot[:, idx] @ row[idx]) / row[idx].sum()
    rated = None
    tors = train.torsional
    if tors is not None and tors.drives and tors.loads:
        th_r, _ = tm.static_twist(tm.nominal_torques())
        rated = tm.element_torque(th_r)
    ke1 = 0.5 * o_v[-1] @ tm.M @ o_v[-1]
    pe1 = _potential(tm, o_p[-1], meshes)
    return TorsionalTransient(
        model=tm,
        laws=laws,
        time=o_t,
        speed=speed,
        element_torque=el_t,
        element_stress=tm.shear_stress(el_t),
        coupling_torque=cp_t,
        mesh_force=mf,
        mesh_state=ms,
        law_torque=o_tq,
        element_torque_max=ext.element_max,
        element_torque_min=ext.element_min,
        coupling_torque_max=ext.coupling_max,
        coupling_torque_min=ext.coupling_min,
        mesh_force_max=fmx,
        mesh_force_min=fmn,
        rated_element_torque=rated,
        law_work=tally.work,
        dissipated=float(tally.dissipated[0]),
        kinetic=(float(ke0), float(ke1)),
        potential=(float(pe0), float(pe1)),
        dt=float(h),
        steps=int(n_steps),
        iterations=int(stats[0]),
        unsettled_steps=int(stats[1]),
        pull_in_time=tally.pull_in,
        wall_time=_time.perf_counter() - t_start,
        notes=tuple(notes),
    )


def _potential(tm, p, meshes: Meshes) -> float:
    """Strain energy: shaft elements and couplings from their twist, meshes from h(δ)."""
    theta = tm.expand(p)
    el = tm.element_torque(theta)
    pe = 0.5 * np.sum(el**2 / tm.el_stiffness)
    if len(tm.cp_names):
        d = theta[tm.cp_dofs[:, 1]] - theta[tm.cp_dofs[:, 0]]
        pe += 0.5 * np.sum(tm.cp_stiffness * d**2)
    for k in range(len(meshes.k)):
        dl = meshes.wi[k] * p[meshes.i[k]] + meshes.wj[k] * p[meshes.j[k]]
        if meshes.bit[k] < 0:
            pe += 0.5 * meshes.k[k] * dl**2
        elif meshes.state[k] != 0:
            pe += 0.5 * meshes.k[k] * (dl - meshes.state[k] * meshes.b[k]) ** 2
    return float(pe)


def _synchronise_at_start(laws: TorqueLaws, drives: Drives, p: NDArray, v: NDArray) -> None:
    """Synchronous motors starting within their pull-in slip start in step (their state in
    ``drives``), at the load angle whose synchronous torque carries their share (by rated
    power) of the loads at t = 0."""
    from .drive_laws import KIND_SYNCHRONOUS, P_KIND, P_PP, P_PULLIN, P_SPEED

    par = laws.par
    sync = [j for j in range(len(laws)) if laws.is_drive[j] and par[j, P_KIND] == KIND_SYNCHRONOUS]
    if not sync:
        return
    arrs = laws.arrays
    probe = laws.new_state()
    power = 0.0
    for j in np.flatnonzero(~laws.is_drive):
        om = drives.gain[j] * v[drives.dof[j]]
        power += law_torque(j, 0.0, 0.0, om, probe, arrs) * om
    rated = sum(float(par[j, P_RATED] * par[j, P_SPEED]) for j in np.flatnonzero(laws.is_drive))
    for j in sync:
        f = drives.gain[j]
        om = f * v[drives.dof[j]]
        s = 1.0 - om / par[j, P_SPEED]
        if s > par[j, P_PULLIN]:
            continue
        need = power * par[j, P_RATED] * par[j, P_SPEED] / rated / om
        probe[j, 0] = 1.0
        probe[j, 1] = 0.0
        # the torque at δ − δ_p = ±π/2 is v² T_avg ± v T_po: split the two parts
        th = np.pi / 2 / par[j, P_PP]
        t_plus = law_torque(j, 0.0, -th, om, probe, arrs)
        t_minus = law_torque(j, 0.0, th, om, probe, arrs)
        avg, sync = 0.5 * (t_plus + t_minus), 0.5 * (t_plus - t_minus)
        x = (need - avg) / sync
        if abs(x) > 1:
            raise ModelError(
                "the load exceeds the synchronous motor's pull-out torque at the initial speed",
                field=f"torsional.drives[{j}].pull_out_torque",
                value=f"{sync:.6g} N·m (at the initial voltage)",
                expected=f"at least {need - avg:.6g} N·m",
            )
        delta0 = -par[j, P_PP] * f * p[drives.dof[j]]  # δ at t = 0
        drives.state[j, 0] = 1.0
        drives.state[j, 1] = delta0 - np.arcsin(x)
