"""ROSS 3.1 reference for speed × whirl tables (issue 24): run with ROSS (Python 3.13), from the
repository root:

    python3.13 -m venv /tmp/ross && /tmp/ross/bin/pip install ross-rotordynamics==3.1.0
    /tmp/ross/bin/python tests/data/ross/whirl_reference.py

A shaft with a disk on two bearings, each on a pedestal (a PointMass held to ground by a second
bearing), built twice in ROSS: with the pedestals (``whirl_pedestal.toml``, the exact model) and
with each bearing given as the 2-D (speed, frequency) table of its pedestal-condensed impedance
``Z = Z_b − Z_b (Z_b + Z_s − ω² m)⁻¹ Z_b`` (``whirl_table.toml``). Writes both rotors as
``Rotor.save`` does and ``whirl_modal.json``: ROSS's ``run_modal`` at SPEED of the pedestal
rotor, and of the table rotor at synchronous whirl and with ``matched_whirl=True`` (each mode's
coefficients at its own damped frequency, iterated).
"""

import json
from pathlib import Path

import numpy as np
import ross as rs

HERE = Path(__file__).resolve().parent
SPEED = 600.0  # rad/s
KB = dict(kxx=2.0e7, kxy=4.0e6, kyx=-3.0e6, kyy=3.0e7, cxx=2.0e4, cxy=1.0e3, cyx=1.0e3, cyy=3.0e4)
PED = dict(m=40.0, kxx=5.0e7, kyy=8.0e7, cxx=6.0e3, cyy=9.0e3)
FREQ = np.linspace(0.0, 4000.0, 17)  # rad/s
SPEEDS = [300.0, 600.0, 900.0]


def condensed(w: float) -> np.ndarray:
    zb = np.array([[KB["kxx"], KB["kxy"]], [KB["kyx"], KB["kyy"]]]) + 1j * w * np.array(
        [[KB["cxx"], KB["cxy"]], [KB["cyx"], KB["cyy"]]]
    )
    zs = np.diag([PED["kxx"], PED["kyy"]]) + 1j * w * np.diag([PED["cxx"], PED["cyy"]])
    return zb - zb @ np.linalg.solve(zb + zs - w * w * PED["m"] * np.eye(2), zb)


steel = rs.Material(name="steel_whirl", rho=7850.0, E=206e9, G_s=79.2e9)
shaft = [rs.ShaftElement(L=0.8 / 6, idl=0.0, odl=0.1, material=steel) for _ in range(6)]
disk = [rs.DiskElement(n=3, m=60.0, Id=0.7, Ip=1.2)]

# the pedestal rotor: bearing to a link node, a point mass there, a bearing to ground
ped_brg, points = [], []
for n, link in ((0, 7), (6, 8)):
    ped_brg.append(rs.BearingElement(n=n, n_link=link, **KB, tag=f"bearing {n}"))
    points.append(rs.PointMass(n=link, m=PED["m"], tag=f"pedestal {n}"))
    ped_brg.append(
        rs.BearingElement(
            n=link, kxx=PED["kxx"], kyy=PED["kyy"], cxx=PED["cxx"], cyy=PED["cyy"],
            tag=f"support {n}",
        )
    )
pedestal = rs.Rotor(shaft, disk, ped_brg, point_mass_elements=points)

# the table rotor: the condensed impedance at every (speed, frequency), the same at each speed
z = np.array([condensed(max(w, 1e-9)) for w in FREQ])
coef = {}
for i, name in enumerate(("xx", "xy", "yx", "yy")):
    k = z.reshape(-1, 4)[:, i].real
    c = z.reshape(-1, 4)[:, i].imag / np.maximum(FREQ, 1e-9)
    coef["k" + name] = np.tile(k, (len(SPEEDS), 1)).tolist()
    coef["c" + name] = np.tile(c, (len(SPEEDS), 1)).tolist()
tab_brg = [
    rs.BearingElement(n=n, speed=SPEEDS, frequency=FREQ.tolist(), tag=f"bearing {n}", **coef)
    for n in (0, 6)
]
table = rs.Rotor(shaft, disk, tab_brg)

pedestal.save(HERE / "whirl_pedestal.toml")
table.save(HERE / "whirl_table.toml")


def run(m):
    return {
        "wd_rad_s": [float(x) for x in m.wd],
        "log_dec": [float(x) for x in m.log_dec],
    }


out = {
    "ross_version": rs.__version__,
    "speed_rad_s": SPEED,
    "pedestal": run(pedestal.run_modal(speed=SPEED, num_modes=24)),
    "table_synchronous": run(table.run_modal(speed=SPEED, num_modes=24)),
    "table_matched_whirl": run(table.run_modal(speed=SPEED, num_modes=24, matched_whirl=True)),
}
(HERE / "whirl_modal.json").write_text(json.dumps(out, indent=1) + "\n")
print(json.dumps(out, indent=1))
