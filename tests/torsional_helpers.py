"""Small torsional trains with closed forms: rigid disks on (nearly) massless shafts.

A shaft element of length L and diameter d has GJ/L = G π d⁴ / (32 L); the "massless" material
has a density of 0.01 kg/m³, so the rod inertia of a 50 mm shaft (ρ J_p L ≈ 3e-9 kg·m²) is
~1e-9 of the disks' and the closed forms of lumped inertias hold to that order. (Lighter still
would not help: a free shaft end then has a torsional frequency √(3G/ρ)/L of ~1e8 rad/s, and the
eigensolver's round-off, ~ε ω_max², would show in the low modes.) Carrier shafts that are not in
the load path (``k=None``) are 50 mm thick.
"""

from __future__ import annotations

import numpy as np

from gearrotor.io import model_from_dict

G = 80e9
E = 2 * G * 1.3
LIGHT = {"E": E, "poisson": 0.3, "density": 1e-2}


def stiffness_of(diameter: float, length: float) -> float:
    """GJ/L (N·m/rad) of a solid shaft of the helpers' material."""
    return G * np.pi * diameter**4 / 32 / length


def diameter_for(k: float, length: float = 0.5) -> float:
    """Solid diameter giving the torsional stiffness k (N·m/rad) over ``length``."""
    return (32 * k * length / (G * np.pi)) ** 0.25


def disk(node: int, polar: float) -> dict:
    return {"node": node, "mass": 10.0, "polar": polar, "transverse": polar / 2}


def shaft(
    name: str,
    k: float | None,
    disks: list[dict],
    *,
    start: float = 0.0,
    length: float = 0.5,
    speed: str | None = None,
    elements: int = 1,
) -> dict:
    """A shaft of one section (torsional stiffness k over ``length``; k None: a 50 mm carrier
    whose stiffness does not matter, nothing passes through it)."""
    d = diameter_for(k, length) if k is not None else 0.05
    out = {
        "name": name,
        "material": "light",
        "start": start,
        "sections": [{"length": length, "outer_diameter": d, "elements": elements}],
        "disks": disks,
    }
    if speed is not None:
        out["speed"] = speed
    return out


def geared_train(
    shafts: list[dict],
    meshes: list[dict] = (),
    couplings: list[dict] = (),
    *,
    speed: str = "1000 rpm",
    bearings: list[dict] | None = None,
    **extra,
):
    """A train of ``shafts`` with spur meshes (``{"gear": (shaft, node, teeth, radius),
    "mate": ..., "k": N/m}``) and couplings, lateral bearings of 1e9 N/m at every shaft end."""
    mesh_specs = []
    for m in meshes:
        g, j = m["gear"], m["mate"]
        spec = {
            "gear": {"shaft": g[0], "node": g[1], "teeth": g[2], "radius": g[3]},
            "mate": {"shaft": j[0], "node": j[1], "teeth": j[2], "radius": j[3]},
            "pressure_angle": "20 deg",
            "stiffness": m.get("k", 1e9),
        }
        for key in ("damping", "damping_ratio", "backlash", "driver", "helix_angle", "name"):
            if key in m:
                spec[key] = m[key]
        mesh_specs.append(spec)
    if bearings is None:
        bearings = []
        for s in shafts:
            n = sum(sec.get("elements", 1) for sec in s["sections"])
            bearings += [
                {"shaft": s["name"], "node": 0, "k": 1e9},
                {"shaft": s["name"], "node": n, "k": 1e9},
            ]
    data = {
        "name": "torsional test train",
        "speed": speed,
        "materials": {"light": LIGHT},
        "shafts": shafts,
        "meshes": mesh_specs,
        "couplings": list(couplings),
        "bearings": bearings,
        **extra,
    }
    return model_from_dict(data)


def driven_gear_pair():
    """A gear (2e5 N·m/rad shaft, 3.0 + 0.6 kg·m²) driving a pinion (50:20) at 1500 rpm with a
    30 kW torque drive on the gear and a quadratic load on the pinion: the small train the
    torsional figure and report tests share (a start-up to ~1500 rpm in a few seconds)."""
    return geared_train(
        [
            shaft("g", 2e5, [disk(0, 3.0), disk(1, 0.6)]),
            shaft("p", 5e4, [disk(0, 0.2), disk(1, 0.4)], start=0.5),
        ],
        [
            {
                "gear": ("g", 1, 50, 0.25),
                "mate": ("p", 0, 20, 0.1),
                "k": 1e9,
                "driver": "gear",
                "damping_ratio": 0.02,
            }
        ],
        speed="1500 rpm",
        torsional={
            "drives": [
                {
                    "type": "torque",
                    "shaft": "g",
                    "node": 0,
                    "rated_power": "30 kW",
                    "rated_speed": "1500 rpm",
                    "value": 250.0,
                }
            ],
            "loads": [
                {"type": "quadratic", "shaft": "p", "node": 1, "torque": 60.0, "speed": "3750 rpm"}
            ],
        },
    )
