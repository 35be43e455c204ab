"""Gear mesh element (SPEC 2.3): kinematic properties, stiffness formulas, torsional frequency."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearrotor.analyses import modal
from gearrotor.elements import MeshGeometry, buckingham_stiffness, iso6336_stiffness
from gearrotor.model import Train

angles = st.floats(-np.pi, np.pi)
radii = st.floats(0.02, 1.0)


def geometry(ri, rj, alpha, beta, phi):
    return MeshGeometry(ri, rj, alpha, beta, phi)


@settings(max_examples=60, deadline=None)
@given(
    ri=radii,
    rj=radii,
    alpha=st.floats(0.1, 0.6),
    beta=st.floats(-0.6, 0.6),
    phi=angles,
    theta=st.lists(st.floats(-1, 1), min_size=3, max_size=3),
    t=st.lists(st.floats(-1, 1), min_size=3, max_size=3),
    z=st.floats(-2, 2),
)
def test_rigid_body_motions_do_not_strain_the_mesh(ri, rj, alpha, beta, phi, theta, t, z):
    g = geometry(ri, rj, alpha, beta, phi)
    w = g.w()
    assert np.linalg.norm(g.n) == pytest.approx(1.0, rel=1e-12)  # unit normal (SPEC: cz fix)
    # rigid translation of both gears
    q = np.concatenate([t, [0, 0, 0], t, [0, 0, 0]])
    assert abs(w @ q) < 1e-12
    # rigid rotation θ of the pair about an axis through the origin (gear centres c_i, c_j)
    th = np.array(theta)
    ci = np.array([0.3, -0.2, z])
    cj = ci + (ri + rj) * g.e
    q = np.concatenate([np.cross(th, ci), th, np.cross(th, cj), th])
    assert abs(w @ q) < 1e-12 * (1 + np.abs(q).max())


@settings(max_examples=30, deadline=None)
@given(ri=radii, rj=radii, alpha=st.floats(0.1, 0.6), beta=st.floats(-0.6, 0.6), phi=angles)
def test_gear_ratio_torque_ratio_and_psd(ri, rj, alpha, beta, phi):
    g = geometry(ri, rj, alpha, beta, phi)
    w = g.w()
    # gears turning together at the gear ratio (opposite senses): r_i θ_i = −r_j θ_j
    q = np.zeros(12)
    q[5], q[11] = 1.0, -ri / rj
    assert abs(w @ q) < 1e-12
    # static normal force F: generalised forces F w; torque ratio T_j/T_i = r_j/r_i
    assert w[11] / w[5] == pytest.approx(rj / ri, rel=1e-12)
    assert abs(w[5]) == pytest.approx(ri * np.cos(beta) * np.cos(alpha), rel=1e-12)
    K = g.K(3e7)
    assert np.allclose(K, K.T)
    ev = np.linalg.eigvalsh(K)
    assert ev.min() > -1e-6 * ev.max()
    assert np.sum(ev > 1e-9 * ev.max()) == 1  # rank one


def test_spur_mesh_reduces_to_line_of_action_kinematics():
    """ϕ = 0, β = 0: δ = sinα (x_i − x_j) − cosα (y_i − y_j) − cosα (r_i θz_i + r_j θz_j),
    the dissertation's spur element with θz of the two gears positive in opposite senses."""
    a, ri, rj = 0.349, 0.11, 0.2
    w = geometry(ri, rj, a, 0.0, 0.0).w()
    expect = np.zeros(12)
    expect[[0, 1, 5]] = np.sin(a), -np.cos(a), -ri * np.cos(a)
    expect[[6, 7, 11]] = -np.sin(a), np.cos(a), -rj * np.cos(a)
    np.testing.assert_allclose(w, expect, atol=1e-15)


def test_helical_mesh_has_axial_and_tilt_terms():
    a, b, ri, rj = 0.349, 0.471, 0.0909, 0.6532
    w = geometry(ri, rj, a, b, 0.0).w()
    assert w[2] == pytest.approx(np.sin(b) * np.cos(a))  # axial
    assert abs(w[3]) + abs(w[4]) > 0.01 * ri  # tilt coupling through the axial force arm
    # opposite hand flips the axial component
    w2 = geometry(ri, rj, a, -b, 0.0).w()
    assert w2[2] == pytest.approx(-w[2])


def test_buckingham_and_iso6336():
    # Buckingham: Kg = c w E1E2/(9(E1+E2)); equal moduli give c w E/18
    assert buckingham_stiffness(1.6, 0.05, 206e9, 206e9) == pytest.approx(1.6 * 0.05 * 206e9 / 18)
    # ISO 6336-1: for very large tooth counts and no shift q' -> C1 = 0.04723 mm·µm/N, so
    # c'th = 21.17 N/(mm·µm) and with CM = 0.8, εα = 1: cγα = 16.94 N/(mm·µm) (spur, steel)
    k = iso6336_stiffness(10**7, 10**7, 0.01, 1.0)
    assert k == pytest.approx(0.8 / 0.04723 * 1e9 * 0.01, rel=1e-5)
    # a 20/40 spur pair lands in ISO's usual 14..20 N/(mm µm) band per unit face width
    c = iso6336_stiffness(20, 40, 1e-3, 1.6) / 1e6
    assert 14 < c < 20


def test_torsional_frequency_of_two_rigid_gears_on_a_mesh_spring():
    """ω² = k cos²α (r1²/J1 + r2²/J2) for rigid gears on a mesh spring (laterally rigid)."""
    k, a, r1, r2, J1, J2 = 2e8, 0.349, 0.1, 0.25, 0.4, 3.1
    stiff = 1e14
    shafts, bearings = [], []
    for name in ("p", "g"):
        shafts.append(
            {
                "name": name,
                "material": "m",
                "sections": [{"length": 0.01, "outer_diameter": 0.05, "elements": 1}],
                "disks": [
                    {"node": 0, "mass": 1.0, "polar": J1 if name == "p" else J2, "transverse": 0.5}
                ],
            }
        )
        for node in (0, 1):
            bearings.append({"shaft": name, "node": node, "k": stiff})
    t = Train.model_validate(
        {
            "materials": {"m": {"E": 2e11, "density": 7800, "poisson": 0.3}},
            "shafts": shafts,
            "bearings": bearings,
            "speed": 0.0,
            "thrust_bearings": [{"shaft": s, "node": 0, "kzz": stiff} for s in ("p", "g")],
            "meshes": [
                {
                    "gear": {"shaft": "p", "node": 0, "teeth": 20, "radius": r1},
                    "mate": {"shaft": "g", "node": 0, "teeth": 50, "radius": r2},
                    "pressure_angle": a,
                    "stiffness": k,
                }
            ],
        }
    )
    res = modal(t)
    rho, Jp = 7800, np.pi * 0.05**4 / 32 * 0.01  # the short shaft adds ρ Jp L of polar inertia
    j1, j2 = J1 + rho * Jp, J2 + rho * Jp
    expect = np.sqrt(k * np.cos(a) ** 2 * (r1**2 / j1 + r2**2 / j2))
    tors = res.damped_frequency[np.array(res.mode_type) == "T"]
    assert tors[0] == pytest.approx(expect, rel=1e-4)  # lateral compliance ~ k/1e14
    assert res.n_rigid_body == 2  # the free rotation of the geared pair (a Jordan pair)


def test_driver_selects_the_loaded_flank(examples):
    """With a driver named, the contact force (compressive δ > 0, generalised force −k δ w)
    opposes the driver's rotation and drives the mate; the other flank mirrors the tangential
    and axial cosines and keeps the separating radial component."""
    from gearrotor.assembly import assemble
    from gearrotor.io import load_model

    for driver, speed in (("gear", 6500), ("gear", -6500), ("mate", 6500), ("mate", -6500)):
        t = load_model(
            examples / "unity_gearbox.toml",
            {
                "meshes[0].driver": driver,
                "speed": f"{speed} rpm",
                "shafts[0].speed": f"{speed} rpm",
                "shafts[1].speed": f"{-speed} rpm",
            },
        )
        asm = assemble(t)
        w = asm.meshes[0].w
        omega = asm.shaft_speeds(t.speed)
        torque = -w[[5, 11]]  # θz generalised forces per unit compressive contact force
        d = 0 if driver == "gear" else 1
        assert torque[d] * omega[d] < 0  # resists the driver
        assert torque[1 - d] * omega[1 - d] > 0  # drives the driven gear
        assert w[0] == pytest.approx(np.sin(0.349))  # radial part unchanged: separating


def test_flank_mirror_geometry():
    g = geometry(0.1, 0.3, 0.349, 0.3, 0.7)
    h = MeshGeometry(0.1, 0.3, 0.349, 0.3, 0.7, flank=-1)
    cx, cy, cz = g.direction_cosines
    assert h.direction_cosines == pytest.approx((-cx, cy, -cz))
    # still a valid mesh: gear ratio and rigid motions give no approach
    q = np.zeros(12)
    q[5], q[11] = 1.0, -0.1 / 0.3
    assert abs(h.w() @ q) < 1e-12
