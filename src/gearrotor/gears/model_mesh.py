"""A model's gear mesh from its tooth geometry: the loaded mesh of ``[[meshes]] geometry`` and
the law it gives the rotor model.

The gear pair ``[pinion, gear]`` is matched to the mesh's ``gear`` (i) and ``mate`` (j) by the
tooth counts (equal counts: the pinion is ``gear``). The pair's kinematics must agree with the
mesh's: the same tooth counts, helix angle magnitude, normal pressure angle (the reference
one, or the working one of a profile-shifted pair) and radii (the reference or the working
pitch radius, or the base radius for ``radius_type = "base"``; within 1 %: the rotor model only
needs the lever arms). E and ν default to the mesh sides' ``E`` or the shafts' materials.

The law: the mesh angle φ_m = N_i θ_i advances at N_i Ω_i; the mesh cycle τ runs with the
motion, ``τ = sgn(N_i Ω_i) φ_m / 2π + p`` (p: ``variation.phase``, the mesh phase of a
multi-mesh train, in cycles). The stiffness is the TVMS's Fourier series truncated at the
pair's ``harmonics``, sampled over φ_m for the rotor model's stiffness table; the
transmission error e = STE − F/k (:meth:`MeshCurves.excitation`) is given as its cos/sin
harmonics in φ_m (its mean, a constant offset of the relative rotation, is left out).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from ..model import Train
from ..model.gear_pair import GearPair
from .geometry import pair_geometry
from .io import merge_gear_pair
from .loaded import MeshCurves, mesh_curves

__all__ = ["ModelMesh", "model_mesh", "mesh_law_arrays"]

_RADIUS_TOL = 0.01
_ANGLE_TOL = 1e-4  # rad


@dataclass(frozen=True)
class ModelMesh:
    """The loaded mesh of a model's gear mesh: ``curves``, and whether the pinion is the
    mesh's ``gear`` (i) side."""

    curves: MeshCurves
    pinion_is_gear: bool
    spec: GearPair


@functools.lru_cache(maxsize=64)
def _curves(spec: GearPair, E: tuple, nu: tuple) -> MeshCurves:
    return mesh_curves(spec, E=E, poisson=nu)


def _modulus(train: Train, side, field: str) -> tuple[float, float]:
    si = train.shaft_index(side.shaft, f"{field}.shaft")
    mat = train.materials[train.shafts[si].material]
    E = side.E if side.E is not None else mat.E
    nu = mat.poisson if mat.poisson is not None else mat.E / (2 * mat.G) - 1
    return float(E), float(nu)


def model_mesh(train: Train, k: int) -> ModelMesh:
    """The loaded mesh of ``train.meshes[k]`` (which has a ``geometry``); errors name the
    mesh's fields."""
    m = train.meshes[k]
    field = f"meshes[{k}].geometry"
    try:
        spec = merge_gear_pair(m.geometry, field)
    except ModelError as exc:
        if exc.file is not None or (exc.field or "").startswith(field):
            raise
        raise ModelError(
            exc.message, field=f"{field}.{exc.field}", value=exc.value, expected=exc.expected
        ) from None
    zi, zj = m.gear.teeth, m.mate.teeth
    if tuple(spec.teeth) == (zi, zj):
        pinion_is_gear = True
    elif tuple(spec.teeth) == (zj, zi):
        pinion_is_gear = False
    else:
        raise ModelError(
            "the gear pair's tooth counts are not the mesh's",
            field=f"{field}.teeth",
            value=list(spec.teeth),
            expected=f"[{zi}, {zj}] (gear, mate) or [{zj}, {zi}]",
        )
    if abs(abs(spec.helix_angle) - abs(m.helix_angle)) > _ANGLE_TOL:
        raise ModelError(
            "the gear pair's helix angle is not the mesh's",
            field=f"{field}.helix_angle",
            value=f"{np.rad2deg(spec.helix_angle):.6g} deg",
            expected=f"±{np.rad2deg(abs(m.helix_angle)):.6g} deg (meshes[{k}].helix_angle)",
        )
    g = pair_geometry(
        spec.teeth,
        spec.module,
        spec.pressure_angle,
        spec.face_width,
        helix_angle=spec.helix_angle,
        profile_shift=spec.profile_shift,
        addendum=spec.addendum_coefficient,
        dedendum=spec.dedendum_coefficient,
        tip_radius_coefficient=spec.root_radius_coefficient,
    )
    beta = abs(spec.helix_angle)
    alpha_wn = float(np.arctan(np.tan(g.alpha_wt) * np.cos(beta)))
    if min(abs(m.pressure_angle - spec.pressure_angle), abs(m.pressure_angle - alpha_wn)) > (
        _ANGLE_TOL
    ):
        raise ModelError(
            "the gear pair's pressure angle is not the mesh's",
            field=f"meshes[{k}].pressure_angle",
            value=f"{np.rad2deg(m.pressure_angle):.6g} deg",
            expected=f"{np.rad2deg(spec.pressure_angle):.6g} deg (the pair's normal pressure "
            f"angle) or {np.rad2deg(alpha_wn):.6g} deg (its working one)",
        )
    sides = (g.pinion, g.gear) if pinion_is_gear else (g.gear, g.pinion)
    for side, t, name in ((m.gear, sides[0], "gear"), (m.mate, sides[1], "mate")):
        if m.radius_type == "base":
            targets = {"base": t.r_b}
        else:
            targets = {"reference": t.r, "working": t.r_b / np.cos(g.alpha_wt)}
        if min(abs(side.radius / r - 1) for r in targets.values()) > _RADIUS_TOL:
            shown = ", ".join(f"{n} {r * 1e3:.6g} mm" for n, r in targets.items())
            raise ModelError(
                "the mesh's radius does not match the gear pair's",
                field=f"meshes[{k}].{name}.radius",
                value=f"{side.radius * 1e3:.6g} mm",
                expected=f"within 1 % of the gear pair's {m.radius_type} radius ({shown})",
            )
    if spec.torque is None:
        raise ModelError(
            "the mesh's gear geometry needs the operating torque",
            field=f"{field}.torque",
            expected="the pinion torque, e.g. torque = '5000 N*m' (in the gear-pair file or "
            "inline)",
        )
    if m.driver is not None:
        driver = "pinion" if (m.driver == "gear") == pinion_is_gear else "gear"
        if "driver" in spec.model_fields_set and spec.driver != driver:
            raise ModelError(
                "the gear pair's driver is not the mesh's",
                field=f"{field}.driver",
                value=spec.driver,
                expected=f"{driver!r} (meshes[{k}].driver = {m.driver!r})",
            )
        spec = spec.model_copy(update={"driver": driver})
    Ei, nui = _modulus(train, m.gear, f"meshes[{k}].gear")
    Ej, nuj = _modulus(train, m.mate, f"meshes[{k}].mate")
    E = (Ei, Ej) if pinion_is_gear else (Ej, Ei)
    nu = (nui, nuj) if pinion_is_gear else (nuj, nui)
    try:
        curves = _curves(spec, E, nu)
    except ModelError as exc:
        if exc.file is not None:
            raise
        raise ModelError(
            exc.message, field=f"{field}.{exc.field}", value=exc.value, expected=exc.expected
        ) from None
    return ModelMesh(curves, pinion_is_gear, spec)


def mesh_law_arrays(
    curves: MeshCurves, direction: float, phase: float = 0.0, harmonics: int | None = None
) -> tuple[NDArray, NDArray, NDArray]:
    """The rotor model's law of a loaded mesh: (φ_m, k(φ_m)) over one mesh cycle (rad, N/m;
    the TVMS series truncated at ``harmonics``) and the transmission error's (S, 2) cos/sin
    amplitudes in φ_m (m). ``direction``: the sign of the mesh rate N_i Ω_i."""
    H = curves.harmonics if harmonics is None else harmonics
    kc, ec, _ = curves.excitation(H)
    sgn = 1.0 if direction >= 0 else -1.0
    h = np.arange(H + 1)
    rot = np.exp(2j * np.pi * h * phase)
    kc, ec = kc * rot, ec * rot
    n = max(256, 16 * H)
    phi = np.arange(n) * 2 * np.pi / n
    k = np.real(np.exp(1j * sgn * np.outer(phi, h)) @ kc)
    te = np.column_stack([ec.real[1:], -sgn * ec.imag[1:]])
    if np.any(k <= 0):
        raise ModelError(
            "the truncated mesh stiffness series goes negative",
            field="geometry.harmonics",
            value=H,
            expected="more harmonics",
        )
    return phi, k, te
