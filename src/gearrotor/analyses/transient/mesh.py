"""Gear mesh in time (SPEC 2.4): time-varying stiffness, backlash, contact damping, TE.

Mesh angle ``φ_m = N_i θz_i`` (teeth of gear i times the absolute angle of its node, rad).
Stiffness along the line of action ``k(φ_m) = Kg + Kv(φ_m)`` with the rectangular-wave Fourier
series of the tooth-pair count

    Kv = 2 Ka Σ_{s=1..S} [a_s sin(s φ_m) + b_s cos(s φ_m)],
    a_s = −(2/(sπ)) sin(sπ(c − 2p)) sin(sπc),   b_s = −(2/(sπ)) cos(sπ(c − 2p)) sin(sπc),

(``Ka = ka_ratio · Kg``, contact ratio c, mesh phase p), or a user table k(φ_m) over one mesh
cycle (φ_m in [0, 2π), periodic, linear interpolation) that replaces the series.

Backlash: ``b`` is the **one-side** clearance (``Mesh.backlash.half``; a model may give the total
clearance 2b with ``convention = "total"``). With the effective approach ``δ_e = δ − e(φ_m)``
(transmission error e, a Fourier series in φ_m: ``e = Σ_s [e_cs cos(sφ_m) + e_ss sin(sφ_m)]``),

    h(δ_e) = δ_e − b (δ_e > b, drive-side contact, state +1),
             0       (|δ_e| ≤ b, separated, state 0),
             δ_e + b (δ_e < −b, back-side contact, state −1),

and the normal force is ``F = k h + c δ̇_e`` in contact, 0 when separated. The generalised
force on the 12 gear DOFs is ``−F w`` (δ > 0 is approach of the tooth surfaces along n), so the
torque on gear i's θz is ``−F w[5] = F r_i cos β cos αn``. Back-side contact acts along the same
line of action (SPEC 2.4), or with ``back_flank="mirrored"`` along the mirrored line of action
``n_b = −cx t + cy e − cz z`` (pressure angle reflected about the line of centres; the gap
``δ_b = w_b·q`` closes at ``δ_b > b``, force ``F_b = k (δ_b − b) + c δ̇_b`` along ``−w_b``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ...assembly import Assembly
from ...errors import ModelError
from ...model import Train

__all__ = ["MeshLaw", "mesh_laws", "fourier_coefficients", "stiffness", "backlash_h"]


@dataclass(frozen=True)
class MeshLaw:
    """Everything the time integration needs about one mesh (SI units).

    w : (12,) kinematic vector; kg : N/m; ka : N/m (Ka = ka_ratio·Kg); coef_a, coef_b : (S,)
    series coefficients; backlash : m, one-side b; damping : N·s/m in contact; teeth : N_i of gear
    i; table_phi, table_k : optional k(φ_m) table (rad, N/m); te : (S_e, 2) transmission-error
    cos/sin amplitudes (m) per mesh harmonic; w_back : (12,) kinematic vector of the back flank.
    """

    name: str
    w: NDArray
    kg: float
    ka: float
    coef_a: NDArray
    coef_b: NDArray
    backlash: float
    damping: float
    damping_ratio: float | None
    teeth: int
    table_phi: NDArray
    table_k: NDArray
    te: NDArray
    w_back: NDArray  # (12,) back-flank line: −w (SPEC 2.4) or the mirrored line of action

    @property
    def has_table(self) -> bool:
        return len(self.table_phi) > 0


def fourier_coefficients(contact_ratio: float, phase: float, terms: int) -> tuple[NDArray, NDArray]:
    """(a_s, b_s), s = 1..terms, of the rectangular-wave series (SPEC 2.4)."""
    s = np.arange(1, terms + 1, dtype=float)
    c, p = contact_ratio, phase
    a = -(2 / (s * np.pi)) * np.sin(s * np.pi * (c - 2 * p)) * np.sin(s * np.pi * c)
    b = -(2 / (s * np.pi)) * np.cos(s * np.pi * (c - 2 * p)) * np.sin(s * np.pi * c)
    return a, b


def stiffness(law: MeshLaw, phi: NDArray | float) -> NDArray:
    """k(φ_m) in N/m (vectorised reference implementation of the kernels' law)."""
    phi = np.asarray(phi, float)
    if law.has_table:
        return np.interp(np.mod(phi, 2 * np.pi), law.table_phi, law.table_k)
    k = np.full(phi.shape, law.kg)
    for s in range(len(law.coef_a)):
        k = k + 2 * law.ka * (
            law.coef_a[s] * np.sin((s + 1) * phi) + law.coef_b[s] * np.cos((s + 1) * phi)
        )
    return k


def backlash_h(delta: NDArray | float, b: float) -> NDArray:
    """h(δ) of the backlash law (m)."""
    d = np.asarray(delta, float)
    return np.where(d > b, d - b, np.where(d < -b, d + b, 0.0))


def mesh_laws(
    train: Train,
    asm: Assembly,
    *,
    stiffness_tables: dict[int, tuple[NDArray, NDArray]] | None = None,
    transmission_error: dict[int, NDArray] | None = None,
    back_flank: str = "same",
) -> tuple[MeshLaw, ...]:
    """Mesh laws from the model; ``stiffness_tables[k] = (φ_m, k)`` over one mesh cycle (rad,
    N/m) replaces mesh k's Fourier series; ``transmission_error[k]`` is an (S_e, 2) array of
    cos/sin amplitudes (m) of e(φ_m); ``back_flank`` = ``"same"`` (SPEC 2.4: back-flank contact
    along the drive line, δ < −b) or ``"mirrored"`` (along the line of action mirrored about the
    line of centres: tangential and axial direction cosines reversed, the radial one kept;
    contact when w_b·q > b)."""
    if back_flank not in ("same", "mirrored"):
        raise ModelError(
            "unknown back-flank law",
            field="back_flank",
            value=back_flank,
            expected="'same' or 'mirrored'",
        )
    stiffness_tables = stiffness_tables or {}
    transmission_error = transmission_error or {}
    out = []
    for m in asm.meshes:
        spec = train.meshes[m.spec_index]
        v = spec.variation
        terms = v.terms if v.ka_ratio > 0 else 0
        a, b = fourier_coefficients(v.contact_ratio, v.phase, terms)
        field = f"meshes[{m.spec_index}]"
        phi_t, k_t = np.zeros(0), np.zeros(0)
        if m.spec_index in stiffness_tables:
            phi_t, k_t = (np.asarray(x, float) for x in stiffness_tables[m.spec_index])
            if phi_t.ndim != 1 or phi_t.shape != k_t.shape or len(phi_t) < 2:
                raise ModelError(
                    "a mesh stiffness table needs matching 1-D angle and stiffness arrays",
                    field=f"{field}.stiffness_table",
                )
            if np.any(np.diff(phi_t) <= 0) or phi_t[0] < 0 or phi_t[-1] > 2 * np.pi + 1e-12:
                raise ModelError(
                    "mesh angles of the stiffness table must increase within one "
                    "mesh cycle [0, 2π] rad",
                    field=f"{field}.stiffness_table",
                )
            if np.any(k_t < 0):
                raise ModelError(
                    "mesh stiffness table has negative values",
                    field=f"{field}.stiffness_table",
                    expected="k ≥ 0 N/m",
                )
            # close the period so interpolation wraps
            if phi_t[-1] < 2 * np.pi:
                phi_t = np.append(phi_t, 2 * np.pi)
                k_t = np.append(k_t, k_t[0])
            if phi_t[0] > 0:
                phi_t = np.insert(phi_t, 0, 0.0)
                k_t = np.insert(k_t, 0, k_t[-1])
        te = np.asarray(transmission_error.get(m.spec_index, np.zeros((0, 2))), float)
        if te.ndim != 2 or te.shape[1] != 2:
            raise ModelError(
                "transmission error must be an (S, 2) array of cos/sin amplitudes",
                field=f"{field}.transmission_error",
                value=te.shape,
            )
        if spec.damping_ratio is not None and spec.damping > 0:
            raise ModelError(
                "give either mesh 'damping' or 'damping_ratio', not both",
                field=f"{field}.damping_ratio",
                value=spec.damping_ratio,
            )
        out.append(
            MeshLaw(
                name=m.name,
                w=np.asarray(m.w, float),
                kg=float(m.stiffness),
                ka=float(v.ka_ratio * m.stiffness),
                coef_a=a,
                coef_b=b,
                backlash=float(spec.backlash.half),
                damping=float(m.damping),  # the assembly resolves damping_ratio
                damping_ratio=spec.damping_ratio,
                teeth=int(m.teeth[0]),
                table_phi=phi_t,
                table_k=k_t,
                te=te,
                w_back=(
                    -np.asarray(m.w, float)
                    if back_flank == "same"
                    else replace(m.geometry, helix_angle=m.geometry.helix_angle + np.pi).w()
                ),
            )
        )
    return tuple(out)
