"""Steady-state torsional forced response to harmonic torques over a speed sweep.

Each excitation is a harmonic torque ``T_a cos(ω t + φ)`` about +z at a node, at a fixed
frequency or at an ``order`` of a shaft's speed (ω = order × |Ω_shaft|). At every
reference-shaft speed the complex amplitudes solve

    (K + iω C − ω² M) Θ = F

in the reduced torsional model; excitations at the same frequency (the same order × speed
ratio, or the same fixed frequency) add with their phases, excitations at different
frequencies are combined as the sum of their amplitudes — the peak their sum reaches when
the phases line up, which incommensurate frequencies eventually do.

Outputs per speed (zero-to-peak amplitudes): alternating shaft torque GJ/L ΔΘ and surface
shear stress τ = T r / J_p · SCF of every shaft element, coupling torque (ktz + iω ctz) ΔΘ,
dynamic normal mesh force (flexible: (k + iω c) w·Θ; rigid: the constraint force) and mesh
torque on each gear. Given the mean transmitted load (the rated torques, an input here), a
mesh whose dynamic force amplitude exceeds the mean normal force unloads the teeth once per
cycle: tooth separation and backlash rattle — flagged per speed.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
from numpy.typing import NDArray
from pydantic import Field, model_validator

from ...assembly import Assembly
from ...errors import ModelError
from ...model import ExternalTorque, NodeRef, Train
from ...threads import managed
from ...units import Angle, Dimensionless, Frequency, Torque
from .model import TorsionalModel, torsional_model

__all__ = ["HarmonicTorque", "TorsionalResponse", "torsional_response"]

RPM = 30 / np.pi


class HarmonicTorque(NodeRef):
    """A harmonic torque ``amplitude · cos(ω t + phase)`` (N·m, 0-pk) about +z at a node:
    ``order`` × the speed of ``order_shaft`` (default: the node's shaft), or a fixed
    ``frequency`` (rad/s, or e.g. ``"120 Hz"``)."""

    name: str | None = None
    amplitude: Torque = Field(ge=0)
    order: Dimensionless | None = Field(default=None, gt=0)
    frequency: Frequency | None = Field(default=None, gt=0)
    order_shaft: str | None = None
    phase: Angle = 0.0

    @model_validator(mode="after")
    def _one(self) -> HarmonicTorque:
        if (self.order is None) == (self.frequency is None):
            raise ValueError("give exactly one of 'order' or 'frequency'")
        if self.order_shaft is not None and self.order is None:
            raise ValueError("'order_shaft' goes with 'order'")
        return self


@dataclass(frozen=True)
class TorsionalResponse:
    """Zero-to-peak amplitudes over the reference-shaft ``speeds`` (rad/s).

    element_torque, element_stress : (ns, ne) N·m, Pa; coupling_torque : (ns, nc) N·m;
    mesh_force : (ns, nm) N (normal, dynamic); mean_mesh_force : (nm,) N or None;
    contact_loss : (ns, nm) bool (dynamic > mean) or None.
    """

    model: TorsionalModel = field(repr=False)
    speeds: NDArray
    excitations: tuple[HarmonicTorque, ...]
    element_torque: NDArray
    element_stress: NDArray
    coupling_torque: NDArray
    mesh_force: NDArray
    mean_mesh_force: NDArray | None
    contact_loss: NDArray | None

    @property
    def mesh_torque(self) -> NDArray:
        """(ns, nm, 2) N·m: dynamic torque amplitude on gear i and gear j."""
        return self.mesh_force[..., None] * self.model.torque_arm[None]

    def peak_stress(self) -> tuple[int, int]:
        """(speed index, element) of the largest alternating shear stress."""
        k = int(np.argmax(self.element_stress))
        return divmod(k, self.element_stress.shape[1])

    def contact_loss_speeds(self, mesh: int) -> NDArray:
        """Reference speeds (rad/s) at which mesh ``mesh`` loses contact (empty if none)."""
        if self.contact_loss is None:
            return np.zeros(0)
        return self.speeds[self.contact_loss[:, mesh]]

    def excitation_frequencies(self) -> NDArray:
        """(n_excitations, ns) rad/s: each excitation's frequency at each reference speed."""
        tm = self.model
        out = np.zeros((len(self.excitations), len(self.speeds)))
        for k, e in enumerate(self.excitations):
            if e.order is None:
                out[k] = e.frequency
                continue
            s = (
                tm.node_shaft[tm.node_dof(e, f"excitations[{k}]")]
                if e.order_shaft is None
                else tm.train.shaft_index(e.order_shaft, f"excitations[{k}].order_shaft")
            )
            out[k] = e.order * abs(tm.speed_ratio[s]) * np.abs(self.speeds)
        return out

    def curves(self) -> dict:
        """The response curves over the speeds (JSON-ready, zero-to-peak amplitudes): every
        element's torque and stress, every coupling's torque, every mesh's dynamic force, and
        each excitation's frequency."""
        tm = self.model
        labels = tm.element_labels()
        freq = self.excitation_frequencies() / (2 * np.pi)
        return {
            "speeds_rpm": (self.speeds * RPM).tolist(),
            "excitation_frequency_hz": {
                self._label(k): freq[k].tolist() for k in range(len(self.excitations))
            },
            "element_torque_Nm": {
                labels[k]: self.element_torque[:, k].tolist() for k in range(len(labels))
            },
            "element_stress_Pa": {
                labels[k]: self.element_stress[:, k].tolist() for k in range(len(labels))
            },
            "coupling_torque_Nm": {
                n: self.coupling_torque[:, k].tolist() for k, n in enumerate(tm.cp_names)
            },
            "mesh_force_N": {
                n: self.mesh_force[:, k].tolist() for k, n in enumerate(tm.mesh_names)
            },
        }

    def _label(self, k: int) -> str:
        e = self.excitations[k]
        if e.name:
            return e.name
        law = f"{e.order:g}x" if e.order is not None else f"{e.frequency / (2 * np.pi):g} Hz"
        return f"excitations[{k}] ({e.shaft}[{e.node if e.node is not None else e.at}], {law})"

    def to_dict(self) -> dict:
        tm = self.model
        labels = tm.element_labels()
        i, e = self.peak_stress() if self.element_stress.size else (0, -1)
        out = {
            "mesh_model": tm.mesh,
            "speeds_rpm": (self.speeds * RPM).tolist(),
            "curves": self.curves(),
            "peak": None
            if e < 0
            else {
                "element": labels[e],
                "speed_rpm": float(self.speeds[i] * RPM),
                "shear_stress_Pa": float(self.element_stress[i, e]),
                "torque_Nm": float(self.element_torque[i, e]),
            },
            "elements": [
                {
                    "element": labels[k],
                    "max_torque_Nm": float(self.element_torque[:, k].max()),
                    "max_shear_stress_Pa": float(self.element_stress[:, k].max()),
                    "scf": float(tm.el_scf[k]),
                }
                for k in range(len(labels))
            ],
            "couplings": [
                {"name": n, "max_torque_Nm": float(self.coupling_torque[:, k].max())}
                for k, n in enumerate(tm.cp_names)
            ],
            "meshes": [],
        }
        for k, n in enumerate(tm.mesh_names):
            d = {
                "name": n,
                "max_dynamic_force_N": float(self.mesh_force[:, k].max()),
                "mean_force_N": None
                if self.mean_mesh_force is None
                else float(abs(self.mean_mesh_force[k])),
                "contact_loss_speeds_rpm": None
                if self.contact_loss is None
                else (self.contact_loss_speeds(k) * RPM).tolist(),
            }
            out["meshes"].append(d)
        return out

    def table(self) -> str:
        tm = self.model
        labels = tm.element_labels()
        rows = [f"{'element':<18} {'max torque N·m':>15} {'max stress MPa':>15} {'at rpm':>9}"]
        rows.append("-" * len(rows[0]))
        order = np.argsort(-self.element_stress.max(axis=0))[:10]
        for k in order:
            i = int(np.argmax(self.element_stress[:, k]))
            rows.append(
                f"{labels[k]:<18} {self.element_torque[:, k].max():>15.4g} "
                f"{self.element_stress[i, k] / 1e6:>15.4g} {self.speeds[i] * RPM:>9.0f}"
            )
        for k, n in enumerate(tm.mesh_names):
            note = ""
            if self.contact_loss is not None:
                lost = self.contact_loss_speeds(k)
                note = (
                    f"  CONTACT LOSS at {lost.min() * RPM:.0f}-{lost.max() * RPM:.0f} rpm"
                    if len(lost)
                    else "  no contact loss"
                )
            mean = (
                ""
                if self.mean_mesh_force is None
                else f", mean {abs(self.mean_mesh_force[k]):.4g} N"
            )
            rows.append(
                f"mesh {n}: max dynamic force {self.mesh_force[:, k].max():.4g} N{mean}{note}"
            )
        for k, n in enumerate(tm.cp_names):
            rows.append(f"coupling {n}: max torque {self.coupling_torque[:, k].max():.4g} N·m")
        return "\n".join(rows)


@managed
def torsional_response(
    model: Train | Assembly | TorsionalModel,
    *,
    excitations: Sequence[HarmonicTorque | dict],
    speeds: NDArray,
    mesh: str = "flexible",
    rated_load: Sequence[ExternalTorque | dict] | None = None,
) -> TorsionalResponse:
    """Forced torsional response over reference-shaft ``speeds`` (rad/s) (module docstring).

    rated_load : the mean torques (N·m about +z at nodes, in power balance) that set the mean
        mesh loads; default: the model's ``[torsional]`` loads at the nominal speed balanced by
        its drives (:meth:`TorsionalModel.nominal_torques`); without either, contact loss is
        not evaluated (``contact_loss`` is None).
    """
    tm = model if isinstance(model, TorsionalModel) else torsional_model(model, mesh=mesh)
    train = tm.train
    exc = tuple(
        e if isinstance(e, HarmonicTorque) else HarmonicTorque.model_validate(e)
        for e in excitations
    )
    if not exc:
        raise ModelError(
            "no excitation given", field="excitations", expected="at least one harmonic torque"
        )
    speeds = np.asarray(speeds, float)
    if speeds.ndim != 1 or len(speeds) == 0:
        raise ModelError("speeds must be a non-empty 1-D array", field="speeds")
    # group the excitations by frequency law: (slope on |Ω_ref|, fixed frequency)
    groups: dict[tuple[float, float], NDArray] = {}
    for k, e in enumerate(exc):
        dof = tm.node_dof(e, f"excitations[{k}]")
        if e.order is not None:
            s = (
                tm.node_shaft[dof]
                if e.order_shaft is None
                else train.shaft_index(e.order_shaft, f"excitations[{k}].order_shaft")
            )
            key = (round(e.order * abs(tm.speed_ratio[s]), 12), 0.0)
        else:
            key = (0.0, e.frequency)
        f = groups.setdefault(key, np.zeros(tm.n_full, complex))
        f[dof] += e.amplitude * np.exp(1j * e.phase)
    ns, ne, nc, nm = len(speeds), len(tm.el_stiffness), len(tm.cp_names), len(tm.mesh_names)
    torque = np.zeros((ns, ne))
    coupling = np.zeros((ns, nc))
    meshf = np.zeros((ns, nm))
    T = tm.T
    for (slope, fixed), f in groups.items():
        fr = tm.reduce_force(f)
        for i, w_ref in enumerate(speeds):
            w = slope * abs(w_ref) + fixed
            Z = tm.K + 1j * w * tm.C - w**2 * tm.M
            theta = T @ la.solve(Z, fr)
            torque[i] += np.abs(tm.element_torque(theta))
            coupling[i] += np.abs(tm.coupling_torque(theta, 1j * w * theta))
            if nm:
                res = None
                if tm.mesh == "rigid":
                    res = (tm.K_full + 1j * w * tm.C_full - w**2 * tm.M_full) @ theta - f
                meshf[i] += np.abs(tm.mesh_force(theta, 1j * w * theta, residual=res))
    mean = contact = None
    if nm and (rated_load is not None or _has_drives_and_loads(train)):
        f0 = _load_vector(tm, rated_load) if rated_load is not None else tm.nominal_torques()
        theta0, _ = tm.static_twist(f0)
        res0 = tm.K_full @ theta0 - f0 if tm.mesh == "rigid" else None
        mean = tm.mesh_force(theta0, residual=res0)
        contact = meshf > np.abs(mean)[None, :]
    return TorsionalResponse(
        model=tm,
        speeds=speeds,
        excitations=exc,
        element_torque=torque,
        element_stress=tm.shear_stress(torque),
        coupling_torque=coupling,
        mesh_force=meshf,
        mean_mesh_force=mean,
        contact_loss=contact,
    )


def _has_drives_and_loads(train: Train) -> bool:
    t = train.torsional
    return t is not None and bool(t.drives) and bool(t.loads)


def _load_vector(tm: TorsionalModel, torques) -> NDArray:
    f = np.zeros(tm.n_full)
    for k, t in enumerate(torques):
        t = t if isinstance(t, ExternalTorque) else ExternalTorque.model_validate(t)
        f[tm.node_dof(t, f"rated_load[{k}]")] += t.value
    return f
