"""Torsional natural frequencies and mode shapes of a train.

Frequencies: the undamped eigenproblem ``K φ = ω² M φ`` of the torsional model (the torsional
natural frequencies that API 617 / API RP 684 compare with the excitations). Damping: the
complex eigenvalues of the damped model ``λ² M + λ C + K`` (couplings' ``ctz``, mesh damping,
shaft material damping), each matched to its undamped mode by the modal assurance criterion
(optimal one-to-one assignment), giving the damped frequency and damping ratio
ζ = −Re λ / |λ| of that mode (over-damped modes: ζ = 1, damped frequency 0).

Rigid-body modes (a free train turns as a whole; one per torsionally free part, found from the
model's connectivity, :meth:`TorsionalModel.rigid_modes`) are the lowest eigenpairs; they are
listed with frequency 0 and ``rigid_body`` set.

Mode shapes are the angles of every node, normalised to a largest |θ| of 1 rad (positive).
Per mode the shaft torques GJ/L Δθ and surface shear stresses τ = T r / J_p · SCF follow for
that normalisation (N·m and Pa per rad of the largest twist angle), and the element with the
largest stress is named: where a resonance of that mode would crack the shaft first.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from ...assembly import Assembly
from ...model import Train
from ...threads import managed
from .model import TorsionalModel, torsional_model

__all__ = ["TorsionalModes", "torsional_modes"]

RPM = 30 / np.pi


@dataclass(frozen=True)
class TorsionalModes:
    """Torsional modes sorted by natural frequency (rigid-body modes first, at 0).

    natural_frequency, damped_frequency : (m,) rad/s; damping_ratio : (m,);
    rigid_body : (m,) bool; shapes : (m, n_full) node angles (rad, max |θ| = 1);
    element_torque : (m, ne) N·m, element_stress : (m, ne) Pa (per the normalisation);
    max_stress_element : (m,) element index (−1 for rigid-body modes).
    """

    model: TorsionalModel = field(repr=False)
    natural_frequency: NDArray
    damped_frequency: NDArray
    damping_ratio: NDArray
    rigid_body: NDArray
    shapes: NDArray
    element_torque: NDArray
    element_stress: NDArray
    max_stress_element: NDArray

    def __len__(self) -> int:
        return len(self.natural_frequency)

    @property
    def frequency_hz(self) -> NDArray:
        return self.natural_frequency / (2 * np.pi)

    @property
    def frequency_rpm(self) -> NDArray:
        """Natural frequency in cycles per minute."""
        return self.natural_frequency * RPM

    @property
    def elastic(self) -> NDArray:
        """Indices of the elastic (not rigid-body) modes."""
        return np.flatnonzero(~self.rigid_body)

    def shaft_twist(self, i: int) -> dict[str, dict[str, list[float]]]:
        """Mode i along every shaft: node positions ``z_m`` and angles ``theta_rad``."""
        tm = self.model
        out = {}
        for s, name in enumerate(tm.shaft_names):
            idx = np.flatnonzero(tm.node_shaft == s)
            out[name] = {
                "z_m": tm.node_z[idx].tolist(),
                "theta_rad": self.shapes[i, idx].tolist(),
            }
        return out

    def _stress_entry(self, i: int) -> dict | None:
        e = int(self.max_stress_element[i])
        if e < 0:
            return None
        tm = self.model
        return {
            "shaft": tm.shaft_names[tm.el_shaft[e]],
            "element": int(tm.el_number[e]),
            "section": int(tm.el_section[e]),
            "z_m": [float(tm.node_z[d]) for d in tm.el_dofs[e]],
            "stress_Pa_per_rad": float(self.element_stress[i, e]),
            "torque_Nm_per_rad": float(self.element_torque[i, e]),
            "scf": float(tm.el_scf[e]),
        }

    def to_dict(self, shapes: bool = False) -> dict:
        """JSON-ready: ``modes`` sorted by frequency with index, frequency_hz, frequency_rpm,
        damped_frequency_hz, damping_ratio, rigid_body and max_stress_element; ``shapes=True``
        adds each mode's twist along every shaft."""
        modes = []
        for i in range(len(self)):
            d = {
                "index": i,
                "frequency_hz": float(self.frequency_hz[i]),
                "frequency_rpm": float(self.frequency_rpm[i]),
                "damped_frequency_hz": float(self.damped_frequency[i] / (2 * np.pi)),
                "damping_ratio": float(self.damping_ratio[i]),
                "rigid_body": bool(self.rigid_body[i]),
                "max_stress_element": self._stress_entry(i),
            }
            if shapes:
                d["shape"] = self.shaft_twist(i)
            modes.append(d)
        return {
            "mesh_model": self.model.mesh,
            "n_dof": int(self.model.n),
            "n_rigid_body_modes": int(np.sum(self.rigid_body)),
            "modes": modes,
        }

    def table(self) -> str:
        head = (
            f"{'#':>3} {'freq Hz':>10} {'freq cpm':>11} {'zeta':>8}  "
            f"{'largest stress (element, MPa per rad)':<40}"
        )
        rows = [head, "-" * len(head)]
        labels = self.model.element_labels()
        for i in range(len(self)):
            if self.rigid_body[i]:
                note = "rigid-body rotation"
            else:
                e = int(self.max_stress_element[i])
                note = f"{labels[e]}  {self.element_stress[i, e] / 1e6:.4g}"
            rows.append(
                f"{i:>3} {self.frequency_hz[i]:>10.3f} {self.frequency_rpm[i]:>11.1f} "
                f"{self.damping_ratio[i]:>8.4f}  {note}"
            )
        return "\n".join(rows)


def _damping(tm: TorsionalModel, w: NDArray, V: NDArray, elastic: NDArray):
    """(damped frequency, damping ratio) per undamped mode from the complex eigenvalues."""
    m = len(w)
    wd = np.where(elastic, w, 0.0)
    zeta = np.zeros(m)
    if not np.any(tm.C) or not np.any(elastic):
        return wd, zeta
    n = tm.n
    Minv = la.inv(tm.M)
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -Minv @ tm.K
    A[n:, n:] = -Minv @ tm.C
    lam, X = la.eig(A)
    X = X[:n]
    floor = 1e-6 * w[elastic].min()  # rigid-body eigenvalues sit at round-off below this
    cand = np.flatnonzero((lam.imag >= -1e-9 * np.abs(lam)) & (np.abs(lam) > floor))
    el = np.flatnonzero(elastic)
    phi = V[:, el]
    num = np.abs(phi.T @ tm.M @ X[:, cand]) ** 2
    den = np.outer(
        np.einsum("ij,ij->j", phi, tm.M @ phi),
        np.real(np.einsum("ij,ij->j", X[:, cand].conj(), tm.M @ X[:, cand])),
    )
    mac = num / np.maximum(den, 1e-300)
    jump = np.abs(np.abs(lam[cand])[None, :] - w[el][:, None]) / w[el][:, None]
    rows, cols = linear_sum_assignment(1.0 - mac + 0.1 * jump)
    for r, c in zip(rows, cols, strict=True):
        lj = lam[cand[c]]
        zeta[el[r]] = min(-lj.real / abs(lj), 1.0)
        wd[el[r]] = abs(lj.imag) if abs(lj.imag) > 1e-9 * abs(lj) else 0.0
    return wd, zeta


@managed
def torsional_modes(
    model: Train | Assembly | TorsionalModel,
    *,
    mesh: str = "flexible",
    max_frequency: float | None = None,
    n_modes: int | None = None,
) -> TorsionalModes:
    """Torsional natural frequencies and modes (module docstring).

    Parameters
    ----------
    model : a :class:`Train` / :class:`Assembly` (its torsional model is built with ``mesh``)
        or a :class:`TorsionalModel`
    mesh : ``"flexible"`` or ``"rigid"`` gear meshes (ignored for a TorsionalModel)
    max_frequency : rad/s, keep modes up to this natural frequency
    n_modes : keep at most this many (lowest) modes, rigid-body modes included

    The torsional model has no speed dependence (no gyroscopic or bearing term acts on θz), so
    the modes hold at every speed.
    """
    tm = model if isinstance(model, TorsionalModel) else torsional_model(model, mesh=mesh)
    w2, V = la.eigh(tm.K, tm.M)  # ascending
    R = tm.rigid_modes()
    rigid = np.arange(len(w2)) < R.shape[1]
    if R.shape[1]:  # the exact rigid rotations instead of round-off's mixture of them
        V[:, rigid] = R
    w = np.where(rigid, 0.0, np.sqrt(np.abs(w2)))
    keep = np.ones(len(w), bool)
    if max_frequency is not None:
        keep &= w <= max_frequency
    if n_modes is not None:
        keep &= np.arange(len(w)) < n_modes
    w, V, rigid = w[keep], V[:, keep], rigid[keep]
    wd, zeta = _damping(tm, w, V, ~rigid)
    shapes = tm.expand(V.T)
    k = np.argmax(np.abs(shapes), axis=1)
    shapes = shapes / shapes[np.arange(len(w)), k][:, None]
    torque = tm.element_torque(shapes)
    stress = tm.shear_stress(torque)
    worst = np.where(rigid, -1, np.argmax(np.abs(stress), axis=1) if stress.size else -1)
    return TorsionalModes(
        model=tm,
        natural_frequency=w,
        damped_frequency=wd,
        damping_ratio=zeta,
        rigid_body=rigid,
        shapes=shapes,
        element_torque=torque,
        element_stress=stress,
        max_stress_element=np.asarray(worst, int),
    )
