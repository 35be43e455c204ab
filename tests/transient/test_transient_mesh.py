"""Gear mesh law in time (SPEC 2.4): Fourier rectangular wave, backlash, damping from a ratio."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la

from gearrotor.analyses.transient import (
    ModalRK4,
    Save,
    backlash_h,
    build_system,
    fourier_coefficients,
    mesh_damping_from_ratio,
    stiffness,
    transient,
)
from gearrotor.errors import ModelError


def test_integer_contact_ratio_gives_constant_stiffness():
    for c in (1.0, 2.0, 3.0):
        a, b = fourier_coefficients(c, 0.3, 20)
        assert np.allclose(a, 0, atol=1e-14) and np.allclose(b, 0, atol=1e-14)


def test_series_is_a_rectangular_wave_as_printed_in_spec():
    """Oracle: the Fourier series of a rectangular wave. SPEC 2.4's series, as printed, sums
    (per unit Ka) to a zero-mean two-level wave with levels 2 apart. Note: its upper level lasts
    2 − c of a mesh cycle (1 < c < 2), i.e. the printed signs give the *negative* of the
    tooth-pair-count wave (two pairs for c − 1 of the cycle); implemented as printed, flagged
    in docs/transient.md."""
    c = 1.592
    a, b = fourier_coefficients(c, 0.0, 400)
    phi = np.linspace(0, 2 * np.pi, 4001)[:-1]
    kv = sum(
        2 * (a[s] * np.sin((s + 1) * phi) + b[s] * np.cos((s + 1) * phi)) for s in range(len(a))
    )
    assert abs(kv.mean()) < 1e-3
    upper = kv > 0
    assert abs(upper.mean() - (2 - c)) < 0.01
    hi = np.median(kv[upper])
    lo = np.median(kv[~upper])
    assert hi - lo == pytest.approx(2.0, rel=0.02)
    assert hi == pytest.approx(2 * (c - 1), rel=0.02)


def test_backlash_law_signs():
    b = 1e-5
    d = np.array([-3e-5, -1e-5, 0.0, 5e-6, 1e-5, 4e-5])
    np.testing.assert_allclose(backlash_h(d, b), [-2e-5, 0, 0, 0, 0, 3e-5])


def test_stiffness_law_and_table(make_gearbox):
    train = make_gearbox({"meshes[0].variation.ka_ratio": "0.2", "meshes[0].variation.terms": "5"})
    law = build_system(train).meshes[0]
    phi = np.linspace(0, 2 * np.pi, 1001)
    k = stiffness(law, phi)
    assert k.mean() == pytest.approx(3e7, rel=1e-3)
    assert np.ptp(k) > 0.2 * 3e7
    table = (np.array([0.0, np.pi, 1.5 * np.pi]), np.array([2e7, 4e7, 3e7]))
    law_t = build_system(train, stiffness_tables={0: table}).meshes[0]
    assert stiffness(law_t, 2 * np.pi + np.pi / 2) == pytest.approx(3e7)
    assert stiffness(law_t, 1.75 * np.pi) == pytest.approx(2.5e7)  # wraps to k(0)
    with pytest.raises(ModelError, match="increase"):
        build_system(train, stiffness_tables={0: (np.array([1.0, 0.5]), np.array([1e7, 1e7]))})


def test_stiffness_table_matches_series_in_time(make_gearbox):
    """A table sampled from the series gives the same transient as the series itself."""
    train = make_gearbox(
        {"meshes[0].variation.ka_ratio": "0.2", "meshes[0].variation.terms": "5"}, elements=4
    )
    law = build_system(train).meshes[0]
    phi = np.linspace(0, 2 * np.pi, 2001)[:-1]
    kw = dict(t_end=0.02, integrator=ModalRK4(dt=2e-5), save=Save(dt=1e-4))
    a = transient(train, **kw)
    b = transient(train, stiffness_tables={0: (phi, stiffness(law, phi))}, **kw)
    np.testing.assert_allclose(b.mesh_stiffness, a.mesh_stiffness, rtol=1e-4)
    np.testing.assert_allclose(b.node_x, a.node_x, rtol=1e-3, atol=1e-9)


def test_transmission_error_shifts_the_mesh_deflection(make_gearbox):
    """A static-like TE e(φ_m) = e0 cos φ_m appears in the dynamic transmission error:
    δ_e = δ − e, and the mesh force responds at the mesh frequency."""
    train = make_gearbox(elements=4)
    te = np.array([[2e-6, 0.0]])
    r = transient(
        train, t_end=0.05, integrator=ModalRK4(), transmission_error={0: te}, save=Save(dt=2e-5)
    )
    f, amp = r.spectrum(r.mesh_force[:, 0], start=0.02)
    mesh_cpm = 30 * 6500
    k = np.argmin(np.abs(f - mesh_cpm))
    assert amp[k - 3 : k + 4].max() > 10.0  # N


def test_mesh_damping_from_ratio(make_gearbox):
    """c = 2ζω_i/(w·φ_i)² gives the mesh mode (largest mesh strain energy) exactly ζ when
    projected on that mode."""
    train = make_gearbox({"meshes[0].damping_ratio": "0.02"})
    system = build_system(train)
    c, om = mesh_damping_from_ratio(system, 0, 0.02)
    assert system.meshes[0].damping == pytest.approx(c)
    M, K, _ = system.linear_matrices()
    w2, V = la.eigh(K, M)
    i = np.argmin(np.abs(np.sqrt(np.abs(w2)) - om))
    d = system.mesh_dofs[0]
    wphi = V[d, i] @ system.meshes[0].w
    assert c * wphi**2 / (2 * om) == pytest.approx(0.02)
    assert 900 < om / 2 / np.pi < 1100  # the 1012 Hz lateral-torsional mesh mode
    with pytest.raises(ModelError, match="not both"):
        build_system(make_gearbox({"meshes[0].damping_ratio": "0.02", "meshes[0].damping": "100"}))


@pytest.mark.parametrize("back_flank", ["same", "mirrored"])
def test_back_flank_line_of_action(make_gearbox, back_flank):
    """Reversing the transmitted torque loads the back flank. Along the mirrored line of action
    (pressure angle reflected about the line of centres, SPEC 2.4) the separating force keeps
    pushing the gears apart (gear 1 moves away from gear 2, −x); along the same line
    (SPEC's default law) it would pull them together. The tooth force magnitude is T/(r cos αn)
    either way (torque balance), and the static start stays static in time."""
    from gearrotor.analyses.transient import RK4
    from gearrotor.analyses.transient.equations import static_state
    from gearrotor.io.model_file import model_from_dict

    xs = []
    for torque in (500.0, -500.0):
        train = make_gearbox({f"unbalances[{i}].amount": "0" for i in range(2)})
        data = train.model_dump()
        data["torques"] = [
            {"shaft": "shaft1", "node": 0, "value": torque},
            {"shaft": "shaft2", "node": 20, "value": torque},
        ]
        data["meshes"][0]["backlash"] = {"value": 1e-5, "convention": "one_side"}
        train = model_from_dict(data)
        system = build_system(train, back_flank=back_flank)
        q, alpha = static_state(system)
        g1 = system.index(system.assembly.node_offset[0][10])
        xs.append(q[g1])
        res = transient(
            train,
            t_end=0.005,
            integrator=RK4(dt=8e-6),
            initial="static",
            back_flank=back_flank,
            save=Save(dt=1e-4),
        )
        F = np.abs(res.mesh_force[:, 0])
        assert np.allclose(F, 500.0 / (0.11 * np.cos(0.349)), rtol=1e-6)
        assert len(np.unique(res.contact[:, 0])) == 1
    if back_flank == "mirrored":
        assert xs[0] < 0 and xs[1] < 0
        assert xs[0] == pytest.approx(xs[1], rel=1e-9)
    else:
        assert xs[0] * xs[1] < 0


def test_model_file_table_and_transmission_error(make_gearbox):
    """`stiffness_table` and `transmission_error` in the model file drive the same laws as the
    API arguments."""
    phi = [0.0, 1.0, 3.0, 5.0]
    k = [2e7, 4e7, 3e7, 3.5e7]
    train = make_gearbox(
        {
            "meshes[0].stiffness_table": {"angle": phi, "stiffness": k},
            "meshes[0].transmission_error": {"cos": ["2 um", "0.5 um"], "sin": ["0 um", "1 um"]},
        },
        elements=4,
    )
    law_file = build_system(train).meshes[0]
    plain = make_gearbox(elements=4)
    law_api = build_system(
        plain,
        stiffness_tables={0: (np.array(phi), np.array(k))},
        transmission_error={0: np.array([[2e-6, 0.0], [0.5e-6, 1e-6]])},
    ).meshes[0]
    x = np.linspace(0, 4 * np.pi, 77)
    np.testing.assert_allclose(stiffness(law_file, x), stiffness(law_api, x))
    np.testing.assert_allclose(law_file.te, law_api.te)
