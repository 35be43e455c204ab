"""The nonlinear transient at an operating point (issue 11 item 3): the point's speed and
torque, fluid-film journals at the coefficients of its static loads carrying the static load
(their film force linearised about the static equilibrium), the weight kept as a constant
load, and the run started from the point's static state.

With no unbalance and constant balanced torques the static state is an equilibrium of the
transient, so the run must stay there: the displacements at every saved time equal the static
analysis's deflection and the journal forces its bearing loads. The tolerance 1e-7 (relative)
is far above round-off (1e-12 in practice) and far below any physical effect: leaving out the
weight, the journals' static load or the torque moves the shaft by its whole static deflection.
The transmitted tooth force is checked against the closed form Ft = T / r_p."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor.analyses.static import static
from gearrotor.analyses.transient import transient
from gearrotor.assembly import assemble
from gearrotor.cli import app
from gearrotor.io import load_model

TORQUE = 200.0  # N·m at the pinion's drive node
R_PINION = 0.05  # m

MODEL = """
name = "gear pair on plain journals"
speed = 300.0

[materials.steel]
E = 211e9
density = 7850.0
poisson = 0.3

[[shafts]]
name = "p"
material = "steel"
sections = [{{ length = 0.4, outer_diameter = 0.06, elements = 8 }}]

[[shafts]]
name = "g"
material = "steel"
sections = [{{ length = 0.4, outer_diameter = 0.06, elements = 8 }}]

[[bearings]]
shaft = "p"
node = 0
fluid_film = {{ file = "{film}", speeds = ["2000 rpm", "3000 rpm", "4000 rpm"] }}

[[bearings]]
shaft = "p"
node = 8
fluid_film = {{ file = "{film}", speeds = ["2000 rpm", "3000 rpm", "4000 rpm"] }}

[[bearings]]
shaft = "g"
node = 0
k = 5e8

[[bearings]]
shaft = "g"
node = 8
k = 5e8

[[thrust_bearings]]
shaft = "p"
node = 0
kzz = 1e9

[[thrust_bearings]]
shaft = "g"
node = 0
kzz = 1e9

[[meshes]]
name = "m"
gear = {{ shaft = "p", node = 4, teeth = 20, radius = {rp} }}
mate = {{ shaft = "g", node = 4, teeth = 60, radius = {rg} }}
pressure_angle = 0.3490658503988659
helix_angle = 0.0
face_width = 0.04
stiffness = 1e9

[[operating_points]]
name = "P"
torque = {torque}
drive = {{ shaft = "p", node = 0 }}
load = {{ shaft = "g", node = 8 }}
"""


@pytest.fixture(scope="module")
def model_file(examples, tmp_path_factory):
    path = tmp_path_factory.mktemp("optr") / "pair.toml"
    film = (examples / "bearings" / "plain_ld1.toml").as_posix()
    path.write_text(
        MODEL.format(film=film, rp=R_PINION, rg=3 * R_PINION, torque=TORQUE), encoding="utf-8"
    )
    return path


def test_transient_at_operating_point_stays_at_static_state(model_file):
    train = load_model(model_file)
    st = static(train, "P")
    res = transient(train, t_end=0.05, operating_point="P")
    act = res.active_dofs
    lateral = assemble(train).dof_kind()[act] == 0
    q_static = st.q[act]
    scale = np.max(np.abs(q_static[lateral]))
    # the journals carry weight and tooth force: a real static deflection to hold
    assert scale > 1e-5
    journals = [b for b in st.bearings if b.kind == "fluid-film"]
    assert len(journals) == 2 and all(b.eccentricity_ratio > 0.05 for b in journals)
    # at t_end: the static deflection
    assert np.max(np.abs(res.final_q[lateral] - q_static[lateral])) < 1e-7 * scale
    # and at every saved time (the recorded DOFs)
    rec = [int(np.flatnonzero(act == g)[0]) for g in res.recorded_dofs]
    rec_lat = lateral[rec]
    dev = np.abs(res.q[:, rec_lat] - q_static[rec][rec_lat][None, :])
    assert dev.max() < 1e-7 * scale
    # the journals' forces are the static analysis's bearing loads (N on the journal = minus
    # the load on the bearing) throughout the run
    for k, b in enumerate(st.bearings[:4]):
        np.testing.assert_allclose(
            res.bearing_force[:, k, :],
            np.broadcast_to(-b.force[:2], res.bearing_force[:, k, :].shape),
            rtol=0,
            atol=1e-7 * np.linalg.norm(b.force[:2]),
        )
    # the train runs at the point's load: tooth force from Ft = T / r_p, steady speeds
    ft = TORQUE / R_PINION
    assert st.meshes[0].tangential == pytest.approx(ft, rel=1e-9)
    assert np.abs(res.mesh_force[:, 0]) == pytest.approx(st.meshes[0].normal, rel=1e-7)
    assert res.shaft_speed[:, 0] == pytest.approx(train.speed, rel=1e-9)


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_cli_transient_operating_point(model_file):
    r = invoke(
        "transient", model_file, "--operating-point", "P", "--t-end", "0.01",
        "--format", "json", "--no-progress",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert json.loads(r.stdout)
    bad = invoke("transient", model_file, "--operating-point", "NOPE", "--t-end", "0.01")
    assert bad.exit_code == 2
    assert len(bad.stderr.strip().splitlines()) == 1, bad.stderr
    assert "--operating-point" in bad.stderr and "NOPE" in bad.stderr


def test_cli_ucs_operating_point_bearing_curves(model_file, examples):
    """``gearrotor ucs --operating-point``: each journal's Kxx/Kyy at each of its speeds are
    those of the standalone bearing solver under the static load the train puts on it at that
    speed (the torque held); to 1e-6, the journal equilibrium's tolerance (1e-9 in force)
    amplified by the coefficients' sensitivity to the eccentricity."""
    from gearrotor.bearings import coefficients, equilibrium, load_bearing

    # the bearing curves do not depend on the stiffness sweep: the smallest one keeps it quick
    r = invoke(
        "ucs", model_file, "--operating-point", "P", "--format", "json",
        "--n-points", "2", "--n-modes", "1",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    curves = json.loads(r.stdout)["bearings"]
    train = load_model(model_file)
    case = load_bearing(examples / "bearings" / "plain_ld1.toml")
    for k in (0, 1):
        c = curves[k]
        assert len(c["speeds_rpm"]) == 3
        for rpm, kxx, kyy in zip(c["speeds_rpm"], c["kxx_N_per_m"], c["kyy_N_per_m"], strict=True):
            w = rpm * np.pi / 30
            load = static(train, "P", speed=w).bearings[k].force[:2]
            eq = equilibrium(case.bearing, tuple(load), w, options=case.options)
            co = coefficients(case.bearing, eq, options=case.options)
            assert kxx == pytest.approx(co.K[0, 0], rel=1e-6)
            assert kyy == pytest.approx(co.K[1, 1], rel=1e-6)
    bad = invoke("ucs", model_file, "--operating-point", "NOPE")
    assert bad.exit_code == 2
    assert len(bad.stderr.strip().splitlines()) == 1, bad.stderr
