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

Where the damping comes from: per mode the modal damping ``φᵀ C_s φ`` of each source s (each
coupling's ``ctz``, each mesh damper ``c w wᵀ``, each torsional support's ``c``, and the shafts'
material damping and torsional dashpots together) as the damping ratio it alone would give,
``ζ_s = φᵀ C_s φ / (2 ω φᵀ M φ)`` (``damping_sources``; for light damping they add up to ζ). A
mesh's ``damping_ratio`` is defined on its *mesh mode* (the mode with the largest share of its
strain energy in the mesh, :func:`.model._with_mesh_damping_ratios`): that mode's
``damping_sources`` give the mesh exactly the ratio asked for, and :attr:`TorsionalModes.mesh_modes`
says which mode that is, whether or not it is among the modes kept.

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

__all__ = ["TorsionalModes", "damping_source_matrices", "torsional_modes"]

RPM = 30 / np.pi


@dataclass(frozen=True)
class TorsionalModes:
    """Torsional modes sorted by natural frequency (rigid-body modes first, at 0).

    natural_frequency, damped_frequency : (m,) rad/s; damping_ratio : (m,);
    rigid_body : (m,) bool; shapes : (m, n_full) node angles (rad, max |θ| = 1);
    element_torque : (m, ne) N·m, element_stress : (m, ne) Pa (per the normalisation);
    max_stress_element : (m,) element index (−1 for rigid-body modes);
    source_names, damping_sources : (m, n_sources) the damping ratio each damping source alone
    gives each mode (module docstring); mesh_modes : per mesh with a ``damping_ratio``, the
    mode the ratio refers to (``mesh``, ``damping_ratio``, ``damping_N_s_per_m``,
    ``frequency_hz``, ``index`` among all the model's modes, ``listed``,
    ``mesh_strain_energy_fraction``, ``mesh_damping_ratio_of_mode``).
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
    source_names: tuple[str, ...] = ()
    damping_sources: NDArray | None = None  # (m, n_sources) ζ each source alone gives
    mesh_modes: tuple[dict, ...] = ()  # per mesh with a damping_ratio: the mode it refers to

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
            d["damping_sources"] = self.sources(i)
            if shapes:
                d["shape"] = self.shaft_twist(i)
            modes.append(d)
        return {
            "mesh_model": self.model.mesh,
            "n_dof": int(self.model.n),
            "n_rigid_body_modes": int(np.sum(self.rigid_body)),
            "modes": modes,
            "mesh_damping": [dict(m) for m in self.mesh_modes],
        }

    def sources(self, i: int) -> dict[str, float]:
        """{source: ζ it alone gives mode i}, largest first, sources below 1e-6 left out."""
        if self.damping_sources is None or self.rigid_body[i]:
            return {}
        z = self.damping_sources[i]
        order = np.argsort(-z)
        return {self.source_names[k]: float(z[k]) for k in order if z[k] > 1e-6}

    def mesh_mode_notes(self) -> list[str]:
        """One line per mesh ``damping_ratio``: the mode it refers to and what it gives there."""
        out = []
        for m in self.mesh_modes:
            where = "" if m["listed"] else f"; not listed: --n-modes {m['index'] + 1}"
            out.append(
                f"mesh {m['mesh']!r}: damping_ratio {m['damping_ratio']:g} is the mesh damper's ζ "
                f"on its mesh mode, mode {m['index']} at {m['frequency_hz']:.4g} Hz "
                f"({m['mesh_strain_energy_fraction']:.0%} of its strain energy in the mesh"
                f"{where}): "
                f"c = {m['damping_N_s_per_m']:.4g} N·s/m, ζ from the mesh there "
                f"{m['mesh_damping_ratio_of_mode']:.4f}; other modes get c (w·φ)² in proportion"
            )
        return out

    def table(self) -> str:
        head = (
            f"{'#':>3} {'freq Hz':>10} {'freq cpm':>11} {'zeta':>8}  {'damped mostly by':<24}"
            f"{'largest stress (element, MPa per rad)':<40}"
        )
        rows = [head, "-" * len(head)]
        labels = self.model.element_labels()
        for i in range(len(self)):
            src = self.sources(i)
            by = next(iter(src), "-") if src else "-"
            if self.rigid_body[i]:
                note = "rigid-body rotation"
            else:
                e = int(self.max_stress_element[i])
                note = f"{labels[e]}  {self.element_stress[i, e] / 1e6:.4g}"
            rows.append(
                f"{i:>3} {self.frequency_hz[i]:>10.3f} {self.frequency_rpm[i]:>11.1f} "
                f"{self.damping_ratio[i]:>8.4f}  {by[:23]:<24}{note}"
            )
        rows.extend(self.mesh_mode_notes())
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


def damping_source_matrices(tm: TorsionalModel) -> tuple[tuple[str, ...], list[NDArray]]:
    """(names, reduced damping matrices (n, n)) of every damping source of the model: each
    coupling with ``ctz``, each mesh damper, each torsional support with ``c``, and the rest of
    C (the shafts' material damping and torsional dashpots) as ``"shaft damping"``."""
    T = tm.T
    names: list[str] = []
    mats: list[NDArray] = []
    rest = tm.C.copy()

    def add(name: str, dofs, vec, c: float) -> None:
        nonlocal rest
        v = np.zeros(tm.n_full)
        np.add.at(v, np.asarray(dofs), np.asarray(vec, float))
        r = T.T @ v
        Cs = c * np.outer(r, r)
        names.append(name)
        mats.append(Cs)
        rest = rest - Cs

    for k, n in enumerate(tm.cp_names):
        if tm.cp_damping[k] != 0:
            add(f"coupling {n}", tm.cp_dofs[k], (-1.0, 1.0), tm.cp_damping[k])
    for k, n in enumerate(tm.mesh_names):
        if tm.mesh == "flexible" and tm.mesh_damping[k] != 0:
            add(f"mesh {n}", tm.mesh_dofs[k], tm.mesh_w[k], tm.mesh_damping[k])
    for k, n in enumerate(tm.gs_names):
        if tm.gs_damping[k] != 0:
            add(f"support {n}", [tm.gs_dofs[k]], (1.0,), tm.gs_damping[k])
    scale = np.abs(tm.C).max() if tm.C.size else 0.0
    if np.abs(rest).max(initial=0.0) > 1e-12 * scale:
        names.append("shaft damping")
        mats.append(rest)
    return tuple(names), mats


def _sources(tm: TorsionalModel, w: NDArray, V: NDArray, rigid: NDArray):
    names, mats = damping_source_matrices(tm)
    out = np.zeros((len(w), len(names)))
    m = np.einsum("ij,ij->j", V, tm.M @ V)
    for s, Cs in enumerate(mats):
        q = np.einsum("ij,ij->j", V, Cs @ V)
        out[:, s] = np.where(rigid, 0.0, q / (2 * np.where(rigid, 1.0, w) * m))
    return names, out


def _mesh_modes(tm: TorsionalModel, w_all: NDArray, kept: NDArray, zeta_src, names) -> tuple:
    out = []
    for k, n in enumerate(tm.mesh_names):
        if np.isnan(tm.mesh_mode_frequency[k]):
            continue
        i = int(np.argmin(np.abs(w_all - tm.mesh_mode_frequency[k])))
        listed = bool(kept[i])
        out.append(
            {
                "mesh": n,
                "damping_ratio": float(tm.mesh_damping_ratio[k]),
                "damping_N_s_per_m": float(tm.mesh_damping[k]),
                "frequency_hz": float(tm.mesh_mode_frequency[k] / (2 * np.pi)),
                "index": i,
                "listed": listed,
                "mesh_strain_energy_fraction": float(tm.mesh_mode_fraction[k]),
                "mesh_damping_ratio_of_mode": float(zeta_src[i, names.index(f"mesh {n}")]),
            }
        )
    return tuple(out)


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
    names, zeta_src = _sources(tm, w, V, rigid)
    mesh_modes = _mesh_modes(tm, w, keep, zeta_src, names)
    w, V, rigid, zeta_src = w[keep], V[:, keep], rigid[keep], zeta_src[keep]
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
        source_names=names,
        damping_sources=zeta_src,
        mesh_modes=mesh_modes,
    )
