"""Small models for the speed × whirl table tests (issue 24)."""

from __future__ import annotations

import numpy as np

from gearrotor.model import Train

RPM = np.pi / 30

#: a 0.8 m shaft with a 60 kg disk on two bearings (anisotropic, cross-coupled), each on a
#: 40 kg pedestal: the pedestal is an exactly rational journal impedance
BEARING = dict(
    kxx=2.0e7, kxy=4.0e6, kyx=-3.0e6, kyy=3.0e7, cxx=2.0e4, cxy=1.0e3, cyx=1.0e3, cyy=3.0e4
)
SUPPORT = dict(mass=40.0, kxx=5.0e7, kyy=8.0e7, cxx=6.0e3, cyy=9.0e3)


def base(speed_rpm: float = 6000.0) -> dict:
    return {
        "speed": f"{speed_rpm} rpm",
        "materials": {"steel": {"E": "206 GPa", "poisson": 0.3, "density": "7850 kg/m^3"}},
        "shafts": [
            {
                "name": "rotor",
                "material": "steel",
                "sections": [{"length": "0.8 m", "outer_diameter": "0.1 m", "elements": 6}],
                "disks": [
                    {"node": 3, "mass": "60 kg", "polar": "1.2 kg*m^2", "transverse": "0.7 kg*m^2"}
                ],
            }
        ],
        "unbalances": [{"shaft": "rotor", "node": 3, "amount": "500 g*mm"}],
        "probes": [{"name": "disk", "shaft": "rotor", "node": 3, "angle": "0 deg"}],
    }


def pedestal_model(speed_rpm: float = 6000.0) -> Train:
    """The rotor with its bearings on pedestals (the reference)."""
    data = base(speed_rpm)
    data["bearings"] = [
        {"name": n, "shaft": "rotor", "node": node, **BEARING, "support": SUPPORT}
        for n, node in (("left", 0), ("right", 6))
    ]
    return Train.model_validate(data)


def pedestal_impedance(whirl: float) -> np.ndarray:
    """The journal impedance of bearing + pedestal at s = i·whirl (2, 2): Z_b − Z_b (Z_b + Z_s −
    ω² m)⁻¹ Z_b, Z_b = K + iωC of the bearing, Z_s of the pedestal's springs and dampers."""
    b, s = BEARING, SUPPORT
    w = whirl
    zb = np.array([[b["kxx"], b["kxy"]], [b["kyx"], b["kyy"]]]) + 1j * w * np.array(
        [[b["cxx"], b["cxy"]], [b["cyx"], b["cyy"]]]
    )
    zs = np.diag([s["kxx"], s["kyy"]]) + 1j * w * np.diag([s["cxx"], s["cyy"]])
    return zb - zb @ np.linalg.solve(zb + zs - w * w * s["mass"] * np.eye(2), zb)


def table_of(impedance, speeds_rpm, whirls_rpm) -> dict:
    """A model's speed × whirl ``table`` of an impedance function of the whirl (rad/s), the
    same at every speed."""
    cols = {k: [] for k in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")}
    for _ in speeds_rpm:
        rows = {k: [] for k in cols}
        for wr in whirls_rpm:
            w = max(wr * RPM, 1e-9)
            z = impedance(w)
            for i, n in enumerate(("xx", "xy", "yx", "yy")):
                rows["k" + n].append(float(z.ravel()[i].real))
                rows["c" + n].append(float(z.ravel()[i].imag / w))
        for k in cols:
            cols[k].append(rows[k])
    return {
        "speed": [f"{s} rpm" for s in speeds_rpm],
        "whirl": [f"{w} rpm" for w in whirls_rpm],
        **cols,
    }


def table_model(table: dict, speed_rpm: float = 6000.0, fit_tolerance=None) -> Train:
    """The rotor with both bearings given by ``table`` (no pedestals)."""
    data = base(speed_rpm)
    extra = {} if fit_tolerance is None else {"fit_tolerance": fit_tolerance}
    data["bearings"] = [
        {"name": n, "shaft": "rotor", "node": node, "table": table, **extra}
        for n, node in (("left", 0), ("right", 6))
    ]
    return Train.model_validate(data)
