"""Regenerates the ROSS reference numbers of tests/audit/test_stability.py::
test_level1_against_ross (not run by the test suite; needs ROSS, ``pip install
ross-rotordynamics`` (2.3.0 used, with plotly < 6) in a separate environment):

    python tests/audit/data/ross_level1_reference.py

The rotor is ROSS's ``rotor_example`` with damped anisotropic bearings: 6 steel elements of
0.25 m, Ø 50 mm (E 211 GPa, G 81.2 GPa, ρ 7810 kg/m³, Cowper shear), disks from geometry
(Ø 280/50 mm, 70 mm wide) at nodes 2 and 4, bearings at nodes 0 and 6 (kxx 1e6, kyy 0.8e6 N/m,
cxx = cyy = 500 N·s/m), 4000 rpm, Q at node 3. ROSS's ``run_level1`` returns, per Q, the log dec
of the first mode that is not backward (its "first forward mode"); Q_0 is found here by Brent's
method on that same function."""

import numpy as np
import ross as rs
from scipy.optimize import brentq

steel = rs.Material(name="steel_ref", rho=7810, E=211e9, G_s=81.2e9)
shaft = [rs.ShaftElement(0.25, 0.0, 0.05, material=steel) for _ in range(6)]
disks = [
    rs.DiskElement.from_geometry(n=n, material=steel, width=0.07, i_d=0.05, o_d=0.28)
    for n in (2, 4)
]
bearings = [rs.BearingElement(n, kxx=1e6, kyy=0.8e6, cxx=500.0, cyy=500.0) for n in (0, 6)]
speed = 4000 * np.pi / 30
rotor = rs.Rotor(shaft, disks, bearings, rated_w=speed)


def first_forward_log_dec(q: float) -> float:
    res = rotor.run_level1(n=3, stiffness_range=(q, q), num=1)
    return float(res.log_dec[0])


qs = [0.0, 2e4, 5e4, 1e5]
print("disk", [(d.m, d.Ip, d.Id) for d in disks])
print("log_dec", [repr(first_forward_log_dec(q)) for q in qs])
print("q0", repr(brentq(first_forward_log_dec, 0.0, 5e4, xtol=1e-6, rtol=1e-12)))
