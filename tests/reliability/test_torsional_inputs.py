"""Reliability corpus, torsional drives and transients (issue 23): meaningless magnitudes,
name collisions and runs too large for memory are refused with exit 2 and one line naming the
field and the value, within seconds, before anything runs.

The bounds (gearrotor/model/drives.py, each with its reason): |torque| ≤ 1e9 N·m, rated power
≤ 1e10 W, line frequency ≤ 2 kHz, voltage factor ≤ 2 p.u., motor torques ≤ 10 p.u. of rated
(tables, pull-out, an equivalent circuit's breakdown torque), short-circuit amplitudes ≤ 20 p.u.;
coupling stiffness and damping ≥ 0, and a drive's torque passes couplings with stiffness; drive
and load names unique (they label the histories), no drive and load on one node. The run size:
the 6-DOF transient's bounds (gearrotor/analyses/limits.py: 2 GiB of record, 2e10 steps).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .conftest import check_refused, files_in, run

#: A motor (synchronous, 4 poles, 60 Hz) driving a load through a coupling: two shafts, 4 DOF.
TORSIONAL = """\
name = "motor and load"
speed = "1800 rpm"

[materials.steel]
E = "206 GPa"
poisson = 0.3
density = "7850 kg/m^3"

[[shafts]]
name = "m"
material = "steel"
sections = [{ length = "0.5 m", outer_diameter = "0.1 m" }]
disks = [{ node = 0, mass = "100 kg", polar = "20 kg*m^2", transverse = "10 kg*m^2" }]

[[shafts]]
name = "l"
material = "steel"
start = "0.6 m"
sections = [{ length = "0.5 m", outer_diameter = "0.08 m" }]
disks = [{ node = 1, mass = "50 kg", polar = "5 kg*m^2", transverse = "2.5 kg*m^2" }]

[[bearings]]
shaft = "m"
node = 0
k = "1e9 N/m"

[[bearings]]
shaft = "m"
node = 1
k = "1e9 N/m"

[[bearings]]
shaft = "l"
node = 0
k = "1e9 N/m"

[[bearings]]
shaft = "l"
node = 1
k = "1e9 N/m"

[[couplings]]
name = "C"
node_i = { shaft = "m", node = 1 }
node_j = { shaft = "l", node = 0 }
kx = "1e8 N/m"
ky = "1e8 N/m"
ktz = "2e5 N*m/rad"
ctz = "50 N*m*s/rad"

[[torsional.drives]]
type = "synchronous_motor"
name = "motor"
shaft = "m"
node = 0
rated_power = "200 kW"
poles = 4
line_frequency = "60 Hz"
pull_out_torque = 2.0
voltage = { time = ["0 s", "1 s"], factor = [0.9, 1.0] }
start = { slip = [1.0, 0.5, 0.05, 0.0], average = [1.0, 0.9, 1.2, 0.0], pulsating = [0.5, 0.4, \
0.25, 0.2] }

[[torsional.loads]]
type = "quadratic"
name = "load"
shaft = "l"
node = 1
torque = "800 N*m"
speed = "1800 rpm"
"""


@pytest.fixture
def model(tmp_path: Path) -> Path:
    path = tmp_path / "torsional.toml"
    path.write_text(TORSIONAL)
    return path


D = "torsional.drives[0]"
SC = f"{D}.short_circuit={{type='two_phase', time='0.1 s', a1=1e6, tau1='0.1 s'}}"

# (id, --set overrides, substrings of the one-line message)
CASES = [
    ("torque-1e12", ["torsional.loads[0].torque=1e12 N*m"], ["torsional.loads[0]", "1e+12"]),
    ("power-1e15", [f"{D}.rated_power=1e15 W"], [D, "rated_power", "1e+15"]),
    ("line-1e9-Hz", [f"{D}.line_frequency=1e9 Hz"], [D, "line_frequency", "1e+09 Hz"]),
    ("voltage-x100", [f"{D}.voltage.factor=[90, 100]"], [f"{D}", "voltage", "factor[0] = 90"]),
    ("pull-out-50", [f"{D}.pull_out_torque=50"], [f"{D}", "pull_out_torque", "50"]),
    ("short-circuit-1e6", [SC], [f"{D}", "short_circuit", "a1 = 1e+06"]),
    ("coupling-ktz-neg", ["couplings[0].ktz=-1e6"], ["couplings[0].ktz", "-1000000"]),
    ("coupling-ctz-neg", ["couplings[0].ctz=-10"], ["couplings[0].ctz", "-10"]),
    ("coupling-ktz-0", ["couplings[0].ktz=0"], ["couplings[0].ktz", "no torsional stiffness"]),
    ("same-name", ["torsional.loads[0].name=motor"], ["torsional.loads[0].name", "'motor'"]),
    (
        "drive-and-load-one-node",
        ["torsional.loads[0].shaft=m", "torsional.loads[0].node=0"],
        ["torsional.loads[0]", "same node"],
    ),
    ("t-end-1e6", ["--t-end=1e6"], ["t_end", "too long", "GB"]),
    ("dt-1e-12", ["--t-end=1", "--dt=1e-12"], ["dt", "too long", "1e+12 steps"]),
]


@pytest.mark.parametrize(
    ("overrides", "needles"), [c[1:] for c in CASES], ids=[c[0] for c in CASES]
)
def test_torsional_transient_refuses(model, tmp_path, overrides, needles):
    out = tmp_path / "out"
    out.mkdir()
    args = [o if o.startswith("--") else f"--set={o}" for o in overrides]
    before = files_in(tmp_path)
    r, seconds = run(
        "torsional", "transient", model, "--t-end=0.05", *args, "--output", out / "x.nc"
    )
    check_refused(r, seconds, *needles)
    assert files_in(tmp_path) == before


def test_induction_circuit_beyond_its_rating(model, tmp_path):
    """An equivalent circuit whose breakdown torque is 100 × the rated torque (the voltage
    ×100 of a 460 V motor's circuit, or a rating 100 × too small) is refused."""
    text = TORSIONAL.replace('type = "synchronous_motor"', 'type = "induction_motor"').replace(
        "pull_out_torque = 2.0\n",
        'circuit = { r1 = "0.641 ohm", x1 = "1.106 ohm", r2 = "0.332 ohm", x2 = "0.464 ohm", '
        'xm = "26.3 ohm", voltage = "46000 V" }\n',
    )
    text = "\n".join(
        ln for ln in text.splitlines() if not ln.startswith(("start =", "voltage ="))
    ).replace('rated_power = "200 kW"', 'rated_power = "18.65 kW"')
    path = tmp_path / "induction.toml"
    path.write_text(text)
    r, seconds = run("torsional", "modes", path)
    check_refused(r, seconds, "breakdown torque", "× the rated torque")
    ok = tmp_path / "ok.toml"
    ok.write_text(text.replace("46000 V", "460 V"))
    r, _ = run("torsional", "modes", ok)
    assert r.exit_code == 0, r.output


def test_both_transients_share_the_run_bounds(model, small):
    """The 6-DOF transient refuses with the same bounds and the same words (one check,
    gearrotor/analyses/limits.py)."""
    r6, s6 = run("transient", small, "--method", "rk4", "--dt", "1e-12", "--t-end", "1")
    check_refused(r6, s6, "too long", "1e+12 steps")
    rt, st = run("torsional", "transient", model, "--dt", "1e-12", "--t-end", "1")
    check_refused(rt, st, "too long", "1e+12 steps")
    tail = "expected a record of at most 2.15 GB and at most 2e+10 steps"
    assert tail in r6.stderr and tail in rt.stderr
