"""API 617 9th edition (2022): the unbalance placed from the mode shape (6.8.2.7) and the
close-clearance check (6.8.2.10-6.8.2.11), as ROSS 3.1 implements that edition (petrobras/ross
pull request #1377 and its tests: the same rotor, placements and loads are checked here, with
numbers of our own model). Tolerances: exact identities (rel 1e-9) where the quantity is a
closed form of the model's own masses; the masses against hand-computed geometry to 1e-12."""

import json

import numpy as np
import pytest

from gearrotor.analyses import unbalance_response
from gearrotor.analyses.audit.api_unbalance import (
    CloseClearance,
    clearance_check,
    mode_unbalances,
    nodal_masses,
    residual_unbalance,
)
from gearrotor.assembly import assemble
from gearrotor.errors import ModelError
from helpers import single_shaft

RPM = np.pi / 30
RHO, D, LE = 7810.0, 0.05, 0.25  # ROSS's rotor_example: 6 steel elements of 0.25 m, Ø 50 mm
DISK = {"outer_diameter": 0.28, "inner_diameter": 0.05, "width": 0.07}  # disks at nodes 2, 4
SHAFT_M = RHO * np.pi * D**2 / 4 * LE  # per element
DISK_M = RHO * np.pi * (0.28**2 - 0.05**2) / 4 * 0.07


def rotor(bearing_nodes=(0, 6), disks=(2, 4), mcs_rpm=9000.0):
    return single_shaft(
        length=6 * LE,
        diameter=D,
        elements=6,
        density=RHO,
        bearings=[{"node": n, "k": 1e6, "c": 1e3} for n in bearing_nodes],
        disks=[dict(DISK, node=n) for n in disks],
        speed=mcs_rpm * RPM,
        max_continuous_speed=mcs_rpm * RPM,
        operating_speed_range=[f"{0.78 * mcs_rpm} rpm", f"{mcs_rpm} rpm"],
        probes=[
            {"name": "DE-45", "shaft": "s", "node": 0, "angle": np.pi / 4},
            {"name": "NDE-45", "shaft": "s", "node": 6, "angle": -np.pi / 4},
        ],
    )


def u_r(w_kg, n_rpm):
    """U_r = 6350 W/N g·mm (N at most 25,000 rpm), as kg·m."""
    return 6350 * w_kg / min(n_rpm, 25000) * 1e-6


def test_nodal_masses_add_up_to_the_rotor():
    m = nodal_masses(assemble(rotor()), 0)
    assert m.sum() == pytest.approx(6 * SHAFT_M + 2 * DISK_M, rel=1e-12)
    assert m[0] == pytest.approx(SHAFT_M / 2, rel=1e-12)  # half of the end element
    assert m[2] == pytest.approx(SHAFT_M + DISK_M, rel=1e-12)


def test_first_mode_one_antinode_sum_of_journal_loads():
    """The first forward mode (cylindrical/first bending) has one antinode, at mid-span: one
    unbalance of 2 U_r with W = the sum of the journal static loads (the rotor's weight)."""
    u = mode_unbalances(rotor(), mode=0)
    total = 6 * SHAFT_M + 2 * DISK_M
    assert u.nodes == (3,) and u.phases == (0.0,)
    assert u.static_loads == pytest.approx((total,), rel=1e-12)
    assert u.amounts == pytest.approx((2 * u_r(total, 9000),), rel=1e-12)
    assert "9th edition" in u.edition
    d = json.loads(json.dumps(u.to_dict()))
    assert d["unbalances"][0]["amount_g_mm"] == pytest.approx(2 * 6350 * total / 9000)


def test_conical_mode_two_antinodes_180_degrees_apart():
    """The second forward mode (conical) of the symmetric rotor: two antinodes either side of
    mid-span, 180° apart, each with the static load of its nearest journal (half the weight)."""
    u = mode_unbalances(rotor(), mode=1)
    total = 6 * SHAFT_M + 2 * DISK_M
    assert len(u.nodes) == 2 and u.nodes[0] < 3 < u.nodes[1]
    assert abs(u.phases[1] - u.phases[0]) == pytest.approx(np.pi)
    assert u.static_loads == pytest.approx((total / 2, total / 2), rel=1e-9)
    assert u.amounts == pytest.approx((2 * u_r(total / 2, 9000),) * 2, rel=1e-9)


def test_overhung_mode_mass_outboard_of_the_bearing():
    """Bearings at nodes 0 and 2, a disk at the free end (node 6): the first forward mode's
    antinode is the overhung disk; W = the mass outboard of the bearing (disk + 4 elements)."""
    u = mode_unbalances(rotor(bearing_nodes=(0, 2), disks=(6,), mcs_rpm=6000.0), mode=0)
    assert u.nodes == (6,)
    assert u.static_loads == pytest.approx((DISK_M + 4 * SHAFT_M,), rel=1e-12)
    assert u.amounts == pytest.approx((2 * u_r(DISK_M + 4 * SHAFT_M, 6000),), rel=1e-12)


def test_residual_unbalance_above_25000_rpm():
    """Above 25,000 rpm U_r = 6350 W / 25,000 = 0.254 W g·mm."""
    assert residual_unbalance(10.0, 30000 * RPM) == pytest.approx(0.254 * 10.0 * 1e-6)
    assert residual_unbalance(10.0, 9000 * RPM) == pytest.approx(6350 * 10 / 9000 * 1e-6)
    u = mode_unbalances(rotor(mcs_rpm=30000.0), mode=0)
    assert u.amounts[0] == pytest.approx(2 * 0.254 * u.static_loads[0] * 1e-6, rel=1e-12)


CLEAR = [("s", 0, 200e-6, "DE"), ("s", 3, 500e-6, "eye"), ("s", 6, 240e-6, "NDE")]
SPEEDS = np.linspace(100, 10000, 51) * RPM


def test_clearance_check_scales_the_response_to_the_vibration_limit():
    """A_vl = 25.4 µm √(12000/N_mc), at most 25.4 µm; A_max the largest pk-pk probe amplitude
    between N_ma and N_mc; S_cc = A_vl / A_max; each location's scaled major-axis pk-pk
    response against 75 % of its diametral clearance. The same linear response computed here
    from unbalance_response gives the same numbers (rel 1e-9)."""
    t = rotor()
    c = clearance_check(t, CLEAR, speeds=SPEEDS)
    assert c.vibration_limit == pytest.approx(25.4e-6)  # N_mc = 9000 < 12000 rpm
    op = (0.78 * 9000 * RPM, 9000 * RPM)
    speeds = np.union1d(SPEEDS, op)
    res = unbalance_response(
        t, speeds=speeds, unbalances=mode_unbalances(t, mode=0).unbalances(), operating_range=op
    )
    inside = (speeds >= op[0] * (1 - 1e-12)) & (speeds <= op[1] * (1 + 1e-12))
    a_max = max(2 * np.max(p.amplitude[inside]) for p in res.probes)
    assert c.max_probe_amplitude == pytest.approx(a_max, rel=1e-9)
    assert c.scale_factor == pytest.approx(min(25.4e-6 / a_max, 6.0), rel=1e-9)
    X, Y = res.node_response(0, 3)
    major = 0.5 * (np.abs(X + 1j * Y) + np.abs(X - 1j * Y))
    eye = c.locations[1]
    assert eye.name == "eye" and eye.limit == pytest.approx(0.75 * 500e-6)
    assert eye.scaled_response == pytest.approx(2 * c.scale_factor * major.max(), rel=1e-9)
    assert c.passed == all(loc.scaled_response < loc.limit for loc in c.locations)
    d = json.loads(json.dumps(c.to_dict()))
    assert d["verdict"] == c.verdict and len(d["locations"]) == 3


def test_clearance_check_is_blind_to_the_unbalance_amount():
    """The response is linear in the unbalance: scaled to A_vl, a 4x larger unbalance gives the
    same scaled clearance response (the scale factor takes 1/4), as long as the cap does not
    act."""
    t = rotor()
    u = mode_unbalances(t, mode=0)
    big = type(u)(**{**u.__dict__, "amounts": tuple(4 * a for a in u.amounts)})
    small = clearance_check(t, CLEAR, speeds=SPEEDS, unbalance=u, scale_factor_cap=None)
    large = clearance_check(t, CLEAR, speeds=SPEEDS, unbalance=big, scale_factor_cap=None)
    assert large.scale_factor == pytest.approx(small.scale_factor / 4, rel=1e-9)
    for a, b in zip(small.locations, large.locations, strict=True):
        assert a.scaled_response == pytest.approx(b.scaled_response, rel=1e-9)


def test_clearance_check_cap_and_failure():
    """API 617 caps S_cc at 6; a tight clearance fails."""
    t = rotor()
    u = mode_unbalances(t, mode=0)
    tiny = type(u)(**{**u.__dict__, "amounts": tuple(1e-3 * a for a in u.amounts)})
    capped = clearance_check(t, CLEAR, speeds=SPEEDS, unbalance=tiny)
    assert capped.scale_factor == 6.0
    tight = clearance_check(t, [CloseClearance("s", 3, 20e-6, "tight eye")], speeds=SPEEDS)
    assert not tight.passed and tight.verdict == "fail"
    assert "fail" in tight.table() and "9th edition" in tight.table()


def test_bad_input():
    t = rotor()
    with pytest.raises(ModelError, match="mode"):
        mode_unbalances(t, mode=20)
    with pytest.raises(ModelError, match=r"clearances\[0\]"):
        clearance_check(t, [("s", 9, 1e-4)], speeds=SPEEDS)
    with pytest.raises(ModelError, match="diametral"):
        clearance_check(t, [("s", 3, -1e-4)], speeds=SPEEDS)
    with pytest.raises(ModelError, match="clearances"):
        clearance_check(t, [], speeds=SPEEDS)


ROTOR_TOML = f"""name = "rotor_example"
speed = "9000 rpm"
max_continuous_speed = "9000 rpm"
operating_speed_range = ["7020 rpm", "9000 rpm"]

[materials.steel]
E = 211e9
density = {RHO}
poisson = 0.3

[[shafts]]
name = "s"
material = "steel"
sections = [{{ length = 1.5, outer_diameter = {D}, elements = 6 }}]
disks = [
  {{ node = 2, outer_diameter = 0.28, inner_diameter = 0.05, width = 0.07 }},
  {{ node = 4, outer_diameter = 0.28, inner_diameter = 0.05, width = 0.07 }},
]

[[bearings]]
shaft = "s"
node = 0
k = 1e6
c = 1e3

[[bearings]]
shaft = "s"
node = 6
k = 1e6
c = 1e3

[[unbalances]]
shaft = "s"
node = 2
amount = "10 g*mm"

[[probes]]
name = "DE-45"
shaft = "s"
node = 0
angle = "45 deg"

[[probes]]
name = "NDE-45"
shaft = "s"
node = 6
angle = "-45 deg"
"""


def test_unbalance_command_with_the_9th_edition(tmp_path):
    """``gearrotor unbalance --api --edition 9th``: the unbalance from the mode shape (the
    library's numbers), the close-clearance check with --clearance, the edition in the output;
    --edition without --api and --clearance with the 8th edition are input errors."""
    from typer.testing import CliRunner

    from gearrotor.cli import app

    p = tmp_path / "rotor.toml"
    p.write_text(ROTOR_TOML)
    run = CliRunner().invoke
    args = ["unbalance", str(p), "--min-speed", "100", "--max-speed", "10000", "--n-speeds", "40"]
    r = run(
        app,
        [*args, "--api", "--edition", "9th", "--clearance", "s:3:0.5 mm:eye", "--format", "json"],
    )
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["api617_edition"] == "API 617 9th edition (2022)"
    lib = mode_unbalances(rotor(mcs_rpm=9000.0), mode=0).to_dict()
    assert d["api617_mode_unbalance"]["unbalances"] == lib["unbalances"]
    assert d["unbalances"][0]["amount_g_mm"] == pytest.approx(lib["unbalances"][0]["amount_g_mm"])
    check = d["close_clearance_check"]
    assert check["locations"][0]["name"] == "eye" and check["verdict"] in ("pass", "fail")
    r = run(app, [*args, "--api", "--edition", "9", "--mode", "1"])
    assert r.exit_code == 0, r.output
    assert "API 617 9th edition (2022)" in r.stdout and r.stdout.count("unbalance ") >= 2
    for bad, field in (
        (["--edition", "9th"], "--api"),
        (["--api", "--clearance", "s:3:0.5 mm"], "--clearance"),
        (["--api", "--edition", "9th", "--clearance", "s:3"], "--clearance"),
        (["--api", "--edition", "10th"], "--edition"),
    ):
        r = run(app, [*args, *bad])
        assert r.exit_code == 2 and r.stderr.startswith(f"error: {field}"), (bad, r.output)


AUDIT_TABLE = """
[api_audit]
edition = "9th"
qa = "1e4 N/m"
at = [{ shaft = "s", node = 3 }]
clearances = [
  { shaft = "s", node = 3, diametral = "0.5 mm", name = "eye" },
  { shaft = "s", node = 0, diametral = "200 um", name = "DE" },
]
"""


def test_model_table_gives_the_edition_and_the_clearances(tmp_path):
    """[api_audit] edition = "9th" and clearances: `gearrotor unbalance --api` runs the 9th
    edition's unbalance and close-clearance check from the file; a clearance off its shaft is
    an input error naming the key; a table without clearances serialises as before."""
    from typer.testing import CliRunner

    from gearrotor.cli import app
    from gearrotor.io import load_model

    p = tmp_path / "rotor.toml"
    p.write_text(ROTOR_TOML + AUDIT_TABLE)
    t = load_model(p)
    assert [c.name for c in t.api_audit.clearances] == ["eye", "DE"]
    assert t.api_audit.clearances[1].diametral == pytest.approx(200e-6)
    r = CliRunner().invoke(
        app,
        [
            "unbalance",
            str(p),
            "--api",
            "--n-speeds",
            "30",
            "--max-speed",
            "10000",
            "--format",
            "json",
        ],
    )
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["api617_edition"] == "API 617 9th edition (2022)"
    assert [c["name"] for c in d["close_clearance_check"]["locations"]] == ["eye", "DE"]
    bad = tmp_path / "bad.toml"
    bad.write_text(ROTOR_TOML + AUDIT_TABLE.replace("node = 0, diametral", "node = 9, diametral"))
    with pytest.raises(ModelError, match=r"api_audit.clearances\[1\]"):
        load_model(bad)
    plain = tmp_path / "plain.toml"
    plain.write_text(ROTOR_TOML + AUDIT_TABLE.split("clearances")[0])
    assert "clearances" not in json.loads(load_model(plain).model_dump_json())["api_audit"]
