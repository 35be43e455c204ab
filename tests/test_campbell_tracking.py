"""Campbell mode tracking where a mode becomes over-damped (issue 22 follow-up): its track
ends instead of taking another mode's place.

Oracle: a short, stiff rotor on two identical isotropic bearings whose damping grows with speed,
c(Ω) = c0 + c1 Ω. Its cylindrical (translation) mode is the rigid-body oscillator
m ẍ + 2c ẋ + 2k x = 0 (the bearings at the ends, symmetric), which stops oscillating at
ζ = c / √(2 k m) = 1; the shaft's first free-free bending mode lies 14× higher, so the
flexible rotor's frequency differs from the rigid one's by the order of (ω/ω_b)² ≈ 0.5 %
(measured 1.1 % at 0 rpm; 2 % is the identification's tolerance): the track must exist where
the rigid ζ ≤ 0.95 and be gone where ζ ≥ 1.05. Before the fix the Hungarian assignment had to give
every track a mode, and the ended tracks took the bending modes' places (a 10× frequency jump).
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses import campbell, modal
from gearrotor.assembly import assemble
from helpers import single_shaft

K = 1e7  # N/m, each bearing
C0, C1 = 1e3, 20.0  # N·s/m and N·s/m per rad/s: c(Ω) = C0 + C1 Ω
L, D, RHO = 0.5, 0.1, 7850.0


def _rotor():
    speeds = [0.0, 1000.0, 2000.0]
    c = [C0 + C1 * s for s in speeds]
    table = dict(
        speed=speeds, kxx=[K] * 3, kyy=[K] * 3, kxy=[0.0] * 3, kyx=[0.0] * 3,
        cxx=c, cyy=c, cxy=[0.0] * 3, cyx=[0.0] * 3,
    )  # fmt: skip
    return single_shaft(
        length=L,
        diameter=D,
        elements=4,
        density=RHO,
        bearings=[dict(node=0, table=table), dict(node=4, table=table)],
    )


@pytest.mark.parametrize("reduced", [True, False])
def test_track_of_a_mode_that_becomes_over_damped_ends(reduced):
    asm = assemble(_rotor())
    m = RHO * np.pi * D**2 / 4 * L
    w_cyl = np.sqrt(2 * K / m)
    speeds = np.linspace(0.0, 2000.0, 21)
    res = campbell(asm, speeds=speeds, max_frequency=15000.0, reduced=reduced)
    f = res.damped_frequency
    # the cylindrical pair (x and y): the tracks starting at the rigid rotor's frequency
    zeta0 = C0 / np.sqrt(2 * K * m)
    cyl = np.flatnonzero(np.abs(f[0] / (w_cyl * np.sqrt(1 - zeta0**2)) - 1) < 0.02)
    assert len(cyl) == 2
    zeta = (C0 + C1 * speeds) / np.sqrt(2 * K * m)
    assert np.all(np.isfinite(f[zeta <= 0.95][:, cyl]))
    assert np.all(np.isnan(f[zeta >= 1.05][:, cyl]))
    assert np.all(res.overdamped[zeta >= 1.05][:, cyl])
    # the full solve agrees: no complex pair near the rigid frequency beyond ζ = 1.05
    r = modal(asm, speed=speeds[-1], max_frequency=15000.0)
    assert not np.any(~r.overdamped & (r.damped_frequency < 0.5 * w_cyl))
    # no track jumps up to another mode (the failure: an ended track took the next mode up);
    # the damping only lowers these modes' frequencies (by √(1 − ζ²) near ζ = 1 steeply), the
    # bending modes' by ≤ 3.5 % per step here
    both = np.isfinite(f[1:]) & np.isfinite(f[:-1])
    rise = (f[1:] - f[:-1]) / f[:-1]
    assert np.all(rise[both] < 0.05), np.max(rise[both])
    # the bending modes are tracked at every speed
    bending = np.flatnonzero(f[0] > 5 * w_cyl)
    assert len(bending) >= 2 and np.all(np.isfinite(f[:, bending]))
    # JSON: no NaN (None where the track has no mode)
    d = res.to_dict()
    assert d["modes"][cyl[0]]["frequency_rpm"][-1] is None
