"""Gear forces of the static solution against Ft = T/r, Fr = Ft tan αt, Fa = Ft tan β
(tan αt = tan αn / cos β; SPEC 7 and e.g. Shigley's Mechanical Engineering Design, ch. 13),
torque ratio = tooth ratio, double-helical axial cancellation, the flank set by the operating
point, and bad input. The static solution gets the mesh forces from the train's stiffness, not
from these formulas; the tolerance 1e-8 allows for round-off only (equilibrium is exact)."""

import math

import numpy as np
import pytest

from gearrotor.analyses.static import static, static_sweep, tooth_forces
from gearrotor.errors import ModelError
from gearrotor.model import OperatingPoint, Train

ALPHA = math.radians(20.0)
REL = 1e-8


def gear_pair(helix=0.0, double=False, thrust=True, ktz=None, teeth=(20, 60), radius=0.05):
    """Pinion 'p' (node 4 of 8, the gear mid-span) meshing with wheel 'g'; spans 0.4 m."""
    zp, zg = teeth
    rp, rg = radius, radius * zg / zp
    mesh = {
        "gear": {"shaft": "p", "node": 4, "teeth": zp, "radius": rp},
        "mate": {"shaft": "g", "node": 4, "teeth": zg, "radius": rg},
        "pressure_angle": ALPHA,
        "helix_angle": helix,
        "orientation": 0.0,
        "face_width": 0.04,
        "stiffness": 1e9,
    }
    meshes = [dict(mesh, name="m")]
    if double:
        meshes = [
            dict(mesh, name="A", gear=dict(mesh["gear"], node=3), mate=dict(mesh["mate"], node=3)),
            dict(
                mesh,
                name="B",
                helix_angle=-helix,
                gear=dict(mesh["gear"], node=5),
                mate=dict(mesh["mate"], node=5),
            ),
        ]
    shaft = {
        "material": "steel",
        "sections": [{"length": 0.4, "outer_diameter": 0.06, "elements": 8}],
    }
    data = {
        "speed": 300.0,
        "materials": {"steel": {"E": 211e9, "density": 7850.0, "poisson": 0.3}},
        "shafts": [dict(shaft, name="p"), dict(shaft, name="g")],
        "bearings": [{"shaft": s, "node": n, "k": 5e8} for s in ("p", "g") for n in (0, 8)],
        "meshes": meshes,
    }
    if thrust:
        data["thrust_bearings"] = [{"shaft": "g", "node": 0, "kzz": 1e9}]
        if not double:
            data["thrust_bearings"].append({"shaft": "p", "node": 0, "kzz": 1e9})
    if ktz is not None:  # a third shaft coupled to the wheel
        data["shafts"].append(dict(shaft, name="c"))
        data["bearings"] += [{"shaft": "c", "node": n, "k": 5e8} for n in (0, 8)]
        data["couplings"] = [
            {
                "node_i": {"shaft": "g", "node": 8},
                "node_j": {"shaft": "c", "node": 0},
                "kx": 1e8,
                "ky": 1e8,
                "kz": 1e8,
                "ktz": ktz,
            }
        ]
    return Train.model_validate(data)


def op(torque=100.0, load_shaft="g", load_node=8, **kw):
    return OperatingPoint(
        name="T",
        torque=torque,
        gravity=False,
        drive={"shaft": "p", "node": 0},
        load={"shaft": load_shaft, "node": load_node},
        **kw,
    )


@pytest.mark.parametrize("helix", [0.0, math.radians(15.0), math.radians(-25.0)])
def test_tooth_forces_and_torque_ratio(helix):
    t = gear_pair(helix)
    res = static(t, op(100.0))
    closed = tooth_forces(100.0, 0.05, ALPHA, helix)
    m = res.mesh("m")
    assert m.tangential == pytest.approx(closed.tangential, rel=REL)
    assert m.separating == pytest.approx(closed.separating, rel=REL)
    assert abs(m.axial) == pytest.approx(abs(closed.axial), rel=REL, abs=1e-9)
    assert m.normal == pytest.approx(closed.normal, rel=REL)
    # torque ratio through the mesh = tooth ratio (SPEC 2.3): the shafts counter-rotate, so
    # the load torque about +z has the drive torque's sign, T_load / T_drive = N_g/N_p
    assert res.load_torque / res.drive_torque == pytest.approx(60 / 20, rel=REL)
    assert m.torque_mate / m.torque_gear == pytest.approx(60 / 20, rel=REL)
    # the pinion's bearings carry the tooth force, half each (gear at mid-span)
    fp = sum(b.force for b in res.bearings if b.shaft == "p")
    assert np.hypot(fp[0], fp[1]) == pytest.approx(
        math.hypot(closed.tangential, closed.separating), rel=REL
    )
    # the axial force goes to the thrust bearings (equal and opposite on the two shafts)
    thrust = {b.shaft: b.force[2] for b in res.bearings if b.kind == "thrust"}
    assert abs(thrust["p"]) == pytest.approx(abs(closed.axial), rel=REL, abs=1e-9)
    assert thrust["p"] == pytest.approx(-thrust["g"], rel=REL, abs=1e-9)
    assert np.abs(res.residual).max() < 1e-9 * closed.normal


def test_double_helical_halves_cancel_axially():
    t = gear_pair(math.radians(30.0), double=True)
    res = static(t, op(200.0))
    a, b = res.mesh("A"), res.mesh("B")
    closed = tooth_forces(100.0, 0.05, ALPHA, math.radians(30.0))  # each half carries half
    assert a.tangential == pytest.approx(closed.tangential, rel=1e-6)
    assert a.axial == pytest.approx(-b.axial, rel=1e-6)
    assert abs(a.axial) == pytest.approx(closed.axial, rel=1e-6)
    thrust = [bb for bb in res.bearings if bb.kind == "thrust"][0]
    assert abs(thrust.force[2]) < 1e-6 * closed.axial


def test_power_gives_torque_and_flank_follows_the_driver():
    t = gear_pair()
    w = 300.0  # rad/s of the pinion
    res = static(
        t,
        OperatingPoint(
            name="P",
            power=3000.0,
            gravity=False,
            drive={"shaft": "p", "node": 0},
            load={"shaft": "g", "node": 8},
        ),
    )
    assert res.drive_torque == pytest.approx(3000.0 / w, rel=1e-12)
    assert res.power == pytest.approx(3000.0, rel=1e-12)
    forward = res.mesh("m")
    back = static(
        t,
        OperatingPoint(
            name="P",
            power=3000.0,
            gravity=False,
            drive={"shaft": "g", "node": 8},
            load={"shaft": "p", "node": 0},
        ),
    )
    # the other shaft drives: the other flank carries the load, same tooth force magnitude
    assert back.mesh("m").flank == -forward.flank
    assert back.mesh("m").tangential == pytest.approx(forward.tangential, rel=1e-9)
    # the separating force pushes the shafts apart either way (+x on the wheel side)
    fp = [sum(b.force for b in r.bearings if b.shaft == "p") for r in (res, back)]
    assert fp[0][0] < 0 and fp[1][0] < 0
    assert fp[0][1] == pytest.approx(-fp[1][1], rel=1e-9)


def test_torque_through_a_coupling():
    t = gear_pair(ktz=1e5)
    res = static(t, op(100.0, load_shaft="c", load_node=8))
    assert res.load_torque / res.drive_torque == pytest.approx(3.0, rel=REL)
    tq = res.shaft("c").torque
    assert np.abs(tq).max() == pytest.approx(300.0, rel=REL)


def test_sweep_and_json_keys():
    t = gear_pair().model_copy(
        update={"operating_points": [op(50.0), op(100.0).model_copy(update={"name": "T2"})]}
    )
    sw = static_sweep(t)
    assert [r.operating_point for r in sw] == ["T", "T2"]
    d = sw[1].to_dict()
    assert {"operating_point", "bearings", "meshes", "shafts"} <= set(d)
    assert {
        "name",
        "shaft",
        "node",
        "force_N",
        "eccentricity_ratio",
        "attitude_deg",
        "min_film_um",
    } <= set(d["bearings"][0])
    assert {"name", "tangential_N", "separating_N", "axial_N", "misalignment_um"} <= set(
        d["meshes"][0]
    )
    assert sw[1].mesh("m").tangential == pytest.approx(2 * sw[0].mesh("m").tangential)


# --- bad input -------------------------------------------------------------------------------
def test_unknown_shaft():
    t = gear_pair()
    with pytest.raises(ModelError) as e:
        static(t, op(load_shaft="nope"))
    assert e.value.field == "operating_point.load.shaft" and e.value.value == "nope"


def test_unknown_operating_point_and_model_check():
    t = gear_pair()
    with pytest.raises(ModelError, match="unknown operating point"):
        static(t, "LC9")
    data = t.model_dump()
    data["operating_points"] = [
        {
            "name": "x",
            "torque": 5,
            "drive": {"shaft": "q", "node": 0},
            "load": {"shaft": "g", "node": 0},
        }
    ]
    with pytest.raises(ModelError) as e:
        Train.model_validate(data).layout()
    assert e.value.field == "operating_points[0].drive.shaft"


def test_power_at_zero_speed():
    t = gear_pair()
    with pytest.raises(ModelError) as e:
        static(
            t,
            OperatingPoint(
                name="z",
                speed=0.0,
                power=1000.0,
                drive={"shaft": "p", "node": 0},
                load={"shaft": "g", "node": 8},
            ),
        )
    assert e.value.field == "operating_point.power"


def test_torque_nothing_reacts():
    with pytest.raises(ValueError, match="'load' node"):
        OperatingPoint(name="n", torque=10.0, drive={"shaft": "p", "node": 0})
    t = gear_pair(ktz=0.0)  # the coupling carries no torque
    with pytest.raises(ModelError, match="nothing reacts the torque") as e:
        static(t, op(100.0, load_shaft="c", load_node=8))
    assert e.value.field == "operating_point.load"


def test_axial_load_nothing_reacts():
    t = gear_pair(math.radians(20.0), thrust=False)
    with pytest.raises(ModelError, match="axial") as e:
        static(t, op(100.0))
    assert e.value.field == "thrust_bearings"
