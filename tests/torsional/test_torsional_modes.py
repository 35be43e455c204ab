"""Torsional modes against closed forms and against the full 6-DOF model.

Closed forms of lumped torsional systems (e.g. Thomson & Dahleh, *Theory of Vibration with
Applications*, 5th ed. 1998, §5.3 torsional systems; W. T. Thomson's geared-system rule, also in
Wachel & Szenasi 1993 and API RP 684 2nd ed. 2005: a geared train is equivalent to a single-
speed train with every inertia and stiffness on the other side of a gear pair multiplied by the
speed ratio squared, n = Ω_other / Ω_ref):

* two inertias J1, J2 on a shaft of stiffness k, free: ω² = k (J1 + J2) / (J1 J2);
  grounded at J1: ω² = k / J2;
* three inertias J1 -k1- J2 -k2- J3, free: J1J2J3 ω⁴ − [k1 J3 (J1+J2) + k2 J1 (J2+J3)] ω²
  + k1 k2 (J1+J2+J3) = 0; grounded at J1: J2J3 ω⁴ − [J3 (k1+k2) + J2 k2] ω² + k1 k2 = 0.

The test shafts are "massless" (tests/torsional_helpers.py: rod inertia ~1e-9 of the disks), so
the lumped closed forms hold to ~1e-9; tolerances of 1e-7 leave room for that and the
eigensolver.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from gearrotor.analyses import modal
from gearrotor.analyses.torsional import torsional_model, torsional_modes
from gearrotor.io.model_file import model_from_dict
from torsional_helpers import disk, geared_train, shaft, stiffness_of

J1, JG, JP, J2, J3 = 2.0, 0.3, 0.05, 5.0, 1.5
K1, K2 = 1.0e5, 4.0e4
NA, NB, RA = 40, 16, 0.2  # bull 40 teeth, pinion 16: the pinion turns n = 2.5x faster
N = NA / NB
RB = RA / N


def two_inertia_geared(mesh_k=1e14, **extra):
    """J1 -k1- bull gear (JG) | mesh | pinion (JP) carrying J2 at the gear node."""
    return geared_train(
        [
            shaft("a", K1, [disk(0, J1), disk(1, JG)]),
            shaft("b", None, [disk(0, JP + J2)], start=0.5),
        ],
        [{"gear": ("a", 1, NA, RA), "mate": ("b", 0, NB, RB), "k": mesh_k}],
        **extra,
    )


def three_inertia_geared(mesh_k=1e14):
    """J1 -k1- bull gear (JG) | mesh | pinion (JP + J2) -k2- J3."""
    return geared_train(
        [
            shaft("a", K1, [disk(0, J1), disk(1, JG)]),
            shaft("b", K2, [disk(0, JP + J2), disk(1, J3)], start=0.5),
        ],
        [{"gear": ("a", 1, NA, RA), "mate": ("b", 0, NB, RB), "k": mesh_k}],
    )


def _elastic(res):
    return res.natural_frequency[~res.rigid_body]


def test_two_inertias_free_with_gear_ratio():
    """ω² = k (J1 + J2') / (J1 J2') with J2' = JG + (JP + J2) n² (rigid mesh: exact; a stiff
    flexible mesh converges to it)."""
    je = JG + (JP + J2) * N**2
    w = np.sqrt(K1 * (J1 + je) / (J1 * je))
    res = torsional_modes(two_inertia_geared(), mesh="rigid")
    assert res.rigid_body[0] and res.natural_frequency[0] == 0.0
    assert _elastic(res)[0] == pytest.approx(w, rel=1e-7)
    flex = torsional_modes(two_inertia_geared(mesh_k=1e12), mesh="flexible")
    # series mesh spring k r_b² ≈ 3.5e10 N·m/rad ≫ k1: relative shift ~ k1 / (k r_b²) ~ 3e-6
    assert _elastic(flex)[0] == pytest.approx(w, rel=1e-5)


def test_rigid_mesh_reflects_inertia_and_stiffness_by_ratio_squared():
    """The rigid model keeps the pinion-side node b1 as its own coordinate (at pinion speed);
    referring it to the bull gear's speed, θ_b1 = −n θ'_b1, turns the reduced matrices into the
    equivalent single-speed chain diag(J1, JG + (JP + J2) n², J3 n²) with k2 n²."""
    tm = torsional_model(three_inertia_geared(), mesh="rigid")
    assert tm.n == 3
    assert tm.factor[tm.dof(1, 0)] == pytest.approx(-N)  # the pinion turns the other way
    order = [int(tm.master[tm.dof(s, n)]) for s, n in ((0, 0), (0, 1), (1, 1))]
    S = np.zeros((3, 3))
    S[order, [0, 1, 2]] = [1.0, 1.0, -N]
    Me, Ke = S.T @ tm.M @ S, S.T @ tm.K @ S
    np.testing.assert_allclose(
        Me, np.diag([J1, JG + (JP + J2) * N**2, J3 * N**2]), rtol=1e-9, atol=1e-8
    )  # the rods' ~1e-9 kg·m²
    k2 = K2 * N**2
    np.testing.assert_allclose(
        Ke, [[K1, -K1, 0], [-K1, K1 + k2, -k2], [0, -k2, k2]], rtol=1e-9, atol=1e-9 * K1
    )


def test_two_inertias_grounded_with_gear_ratio():
    """J1 held: ω² = k / J2'."""
    je = JG + (JP + J2) * N**2
    res = torsional_modes(
        torsional_model(two_inertia_geared(), mesh="rigid", fixed=[{"shaft": "a", "node": 0}])
    )
    assert not res.rigid_body.any()
    assert res.natural_frequency[0] == pytest.approx(np.sqrt(K1 / je), rel=1e-7)


def test_three_inertias_free_and_grounded_with_gear_ratio():
    a, b, c = J1, JG + (JP + J2) * N**2, J3 * N**2
    k1, k2 = K1, K2 * N**2
    free = np.sort(
        np.sqrt(
            np.roots(
                [a * b * c, -(k1 * c * (a + b) + k2 * a * (b + c)), k1 * k2 * (a + b + c)]
            ).real
        )
    )
    res = torsional_modes(three_inertia_geared(), mesh="rigid", n_modes=3)
    np.testing.assert_allclose(_elastic(res)[:2], free, rtol=1e-7)
    grounded = np.sort(np.sqrt(np.roots([b * c, -(c * (k1 + k2) + b * k2), k1 * k2]).real))
    tm = torsional_model(three_inertia_geared(), mesh="rigid", fixed=[{"shaft": "a", "node": 0}])
    np.testing.assert_allclose(torsional_modes(tm).natural_frequency[:2], grounded, rtol=1e-7)


def test_flexible_mesh_is_a_spring_along_the_line_of_action():
    """With a soft mesh the pair J_G | k_m r_a², r_b² | J_P is a spring k_m (r_a r_b)... in the
    equivalent system: four inertias J1 -k1- JG -k_m r_a²- (JP+J2) n² (referred to shaft a,
    torque arm r cos αn). Checked against the eigenvalues of that lumped chain."""
    km = 2e8
    arm_a = RA * np.cos(np.deg2rad(20))
    kmt = km * arm_a**2  # mesh torsional stiffness referred to the bull gear
    Mr = np.diag([J1, JG, (JP + J2) * N**2])
    Kr = np.array([[K1, -K1, 0], [-K1, K1 + kmt, -kmt], [0, -kmt, kmt]])
    w_ref = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(Mr, Kr)).real)[1:])
    res = torsional_modes(two_inertia_geared(mesh_k=km), mesh="flexible", n_modes=3)
    np.testing.assert_allclose(_elastic(res), w_ref, rtol=1e-7)


def test_damping_ratio_of_a_coupling_damper():
    """Two inertias joined by a coupling (ktz, ctz): the free system's elastic mode is the
    oscillator of the reduced inertia J = J1J2/(J1+J2): ζ = c / (2 √(k J))."""
    k, c = 3e5, 150.0
    t = geared_train(
        [shaft("a", None, [disk(1, J1)]), shaft("b", None, [disk(0, J2)], start=0.6)],
        couplings=[
            {
                "node_i": {"shaft": "a", "node": 1},
                "node_j": {"shaft": "b", "node": 0},
                "ktz": k,
                "ctz": c,
            }
        ],
    )
    res = torsional_modes(t, n_modes=2)
    je = J1 * J2 / (J1 + J2)
    zeta = c / (2 * np.sqrt(k * je))
    assert res.natural_frequency[1] == pytest.approx(np.sqrt(k / je), rel=1e-7)
    assert res.damping_ratio[1] == pytest.approx(zeta, rel=1e-7)
    assert res.damped_frequency[1] == pytest.approx(
        np.sqrt(k / je) * np.sqrt(1 - zeta**2), rel=1e-7
    )


def test_largest_stress_element_and_scf():
    """Two sections of one shaft between two disks carry the same modal torque; the thinner
    one has the larger τ = 16 T / (π d³), unless a stress concentration factor on the other
    section outweighs the ratio of the d³."""
    d1, d2 = 0.10, 0.08  # τ ratio (d1/d2)³ = 1.95
    base = {
        "name": "s",
        "material": "light",
        "sections": [{"length": 0.5, "outer_diameter": d1}, {"length": 0.5, "outer_diameter": d2}],
        "disks": [disk(0, J1), disk(2, J2)],
    }
    t = geared_train([base])
    res = torsional_modes(t, n_modes=2)
    assert res.max_stress_element[1] == 1
    T = res.element_torque[1]
    assert T[0] == pytest.approx(T[1], rel=1e-7)  # massless shaft: one torque along it
    assert res.element_stress[1, 1] == pytest.approx(16 * T[1] / (np.pi * d2**3), rel=1e-12)
    data = t.model_dump()
    data["torsional"] = {"stress_concentrations": [{"shaft": "s", "section": 0, "factor": 2.5}]}
    res2 = torsional_modes(model_from_dict(data), n_modes=2)
    assert res2.max_stress_element[1] == 0
    assert res2.element_stress[1, 0] == pytest.approx(2.5 * 16 * T[0] / (np.pi * d1**3), rel=1e-7)


def test_json_lists_modes_sorted_with_the_rigid_body_mode_flagged():
    res = torsional_modes(three_inertia_geared(), mesh="flexible")
    d = json.loads(json.dumps(res.to_dict(shapes=True)))
    modes = d["modes"]
    f = [m["frequency_hz"] for m in modes]
    assert f == sorted(f)
    assert modes[0]["rigid_body"] and modes[0]["frequency_hz"] == 0.0
    assert modes[0]["max_stress_element"] is None
    assert not any(m["rigid_body"] for m in modes[1:])
    m1 = modes[1]
    assert {"index", "frequency_hz", "frequency_rpm", "damping_ratio"} <= set(m1)
    assert m1["frequency_rpm"] == pytest.approx(60 * m1["frequency_hz"])
    assert set(m1["shape"]) == {"a", "b"}
    assert "rigid-body" in res.table()


def _stiff_geared_pair(k_brg: float):
    """Two spur-geared shafts with real (not massless) steel, bearings of k_brg beside the
    gears: torsion couples to lateral motion only through the bearings' compliance."""
    steel = {"E": 208e9, "poisson": 0.3, "density": 7850.0}
    shafts = [
        {
            "name": "a",
            "material": "steel",
            "sections": [{"length": 0.6, "outer_diameter": 0.08, "elements": 6}],
            "disks": [disk(0, 1.0), disk(3, 0.4)],
        },
        {
            "name": "b",
            "material": "steel",
            "start": 0.0,
            "sections": [{"length": 0.6, "outer_diameter": 0.06, "elements": 6}],
            "disks": [disk(3, 0.1), disk(6, 0.3)],
        },
    ]
    bearings = [{"shaft": s, "node": n, "k": k_brg} for s in ("a", "b") for n in (2, 3, 4)]
    data = {
        "name": "pair",
        "speed": "3000 rpm",
        "materials": {"steel": steel},
        "shafts": shafts,
        "meshes": [
            {
                "gear": {"shaft": "a", "node": 3, "teeth": 60, "radius": 0.15},
                "mate": {"shaft": "b", "node": 3, "teeth": 30, "radius": 0.075},
                "pressure_angle": "20 deg",
                "stiffness": 5e8,
            }
        ],
        "thrust_bearings": [{"shaft": s, "node": 3, "kzz": 1e9} for s in ("a", "b")],
        "bearings": bearings,
    }
    return model_from_dict(data)


def _torsional_from_full(train, n):
    full = modal(train, speed=0.0)
    sel = [i for i in range(len(full)) if full.energy_fractions[i, 2] > 0.5]
    return full.natural_frequency[sel][:n], full.energy_fractions[sel][:n, 2]


def test_reduced_model_matches_the_full_6dof_torsional_modes():
    """The full model's torsional modes (modal's kinetic-energy classification, torsional
    fraction > 0.99) against the reduced model of the same train. They differ by the lateral
    compliance the mesh force meets at the bearings (bearings at and beside the gears), so the
    gap must fall in proportion to the bearing compliance: ~10x per decade of bearing stiffness,
    down to < 1e-4 at 1e13 N/m (the mesh mode, most coupled, sets the gap)."""
    gaps = []
    for k_brg in (1e11, 1e12, 1e13):
        train = _stiff_geared_pair(k_brg)
        red = torsional_modes(train, n_modes=4).natural_frequency[1:4]
        wf, frac = _torsional_from_full(train, 3)
        assert np.all(frac > 0.99)
        gaps.append(np.max(np.abs(wf - red) / red))
    assert gaps[-1] < 1e-4
    for a, b in zip(gaps, gaps[1:], strict=False):
        assert 7 < a / b < 13


def test_coupled_train_without_mesh_matches_the_full_model_exactly():
    """Without meshes torsion is uncoupled from everything else in the 6-DOF model: same
    frequencies to round-off (speed 0: no gyroscopic terms; modal's dense solver)."""
    t = geared_train(
        [
            shaft("a", 2e5, [disk(0, J1), disk(1, 0.2)]),
            shaft("b", 5e4, [disk(0, 0.2), disk(1, J2)], start=0.6),
        ],
        couplings=[
            {
                "node_i": {"shaft": "a", "node": 1},
                "node_j": {"shaft": "b", "node": 0},
                "ktz": 1e6,
                "kx": 1e8,
                "ky": 1e8,
            }
        ],
        speed="0 rpm",
    )
    red = torsional_modes(t, n_modes=4)
    full = modal(t)
    tors = np.sort(full.natural_frequency[full.energy_fractions[:, 2] > 0.999])[:3]
    np.testing.assert_allclose(tors, red.natural_frequency[1:4], rtol=1e-9)


def test_stiffness_helper_is_gj_over_l():
    t = geared_train([shaft("a", K1, [disk(0, J1), disk(1, J2)])])
    tm = torsional_model(t)
    assert tm.el_stiffness[0] == pytest.approx(K1, rel=1e-12)
    assert stiffness_of(0.1, 1.0) == pytest.approx(80e9 * np.pi * 1e-4 / 32)
