"""External torques (constant, time table, speed law) and speed-dependent bearings in time."""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor import assemble
from gearrotor.analyses.transient import RK4, ModalRK4, Save, build_system, transient

NO_UNB = {f"unbalances[{i}].amount": "0" for i in range(2)}


def _momentum(system, res):
    """Generalized momentum of the rigid rotation r (θz_s = ratio_s α)."""
    ratio = system.assembly.speed_ratio
    r = np.zeros(system.n)
    for s, a in enumerate(system.a_weights):
        r[a != 0] = ratio[s]
    M = system.M.toarray()
    G = [g.toarray() for g in system.G]
    return np.array(
        [
            r @ M @ v + sum(0.5 * ratio[s] * (v @ G[s] @ q) for s in range(len(G)))
            for q, v in zip(res.q, res.qdot, strict=True)
        ]
    )


@pytest.mark.parametrize(
    "torque",
    [
        {"value": "50 N*m"},
        {"time": [0.0, 0.02, 0.04], "values": [0.0, 80.0, 80.0]},
        {"value": "60 N*m", "speed_exponent": 2.0, "reference_speed": "6500 rpm"},
    ],
)
def test_torque_changes_the_momentum_by_its_impulse(make_gearbox, torque):
    """dp/dt = ratio_s · T(t, Ω) on the rigid rotation: p(t) − p(0) = ∫ ratio T dt."""
    from gearrotor.io.model_file import model_from_dict

    train = make_gearbox(NO_UNB, elements=4)
    data = train.model_dump()
    data["torques"] = [{"shaft": "shaft2", "node": 0, **torque}]
    train = model_from_dict(data)
    system = build_system(train)
    res = transient(train, t_end=0.05, integrator=RK4(dt=1e-5), save=Save(dt=1e-4, full_state=True))
    p = _momentum(system, res)
    t = res.time
    ratio = system.assembly.speed_ratio[1]
    tq = train.torques[0]
    if tq.time is not None:
        T = np.interp(t, tq.time, tq.values)
    else:
        T = np.full_like(t, tq.value)
    if tq.speed_exponent:  # at the node's own speed (sampled: trapezoid error ~1e-3)
        i = np.flatnonzero(res.recorded_dofs == system.assembly.node_offset[1][0] + 5)[0]
        T = T * (np.abs(res.qdot[:, i]) / tq.reference_speed) ** tq.speed_exponent
    impulse = np.concatenate([[0.0], np.cumsum(0.5 * (T[1:] + T[:-1]) * np.diff(t))]) * ratio
    np.testing.assert_allclose(p - p[0], impulse, atol=5e-3 * abs(impulse).max())
    assert abs((p[-1] - p[0]) / impulse[-1] - 1) < 1e-3
    # a positive torque accelerates shaft 2 about +z (it spins at −6500 rpm: slows it down)
    assert res.shaft_speed[-1, 1] > res.shaft_speed[0, 1]


def _with_table(train, kxx_at):
    from gearrotor.io.model_file import model_from_dict

    data = train.model_dump()
    sp = [500.0, 680.678, 900.0]
    for b in data["bearings"]:
        k, c = b.pop("k"), b.pop("c")
        b["table"] = {
            "speed": sp,
            "kxx": [kxx_at(s, k) for s in sp],
            "kxy": [0.0] * 3,
            "kyx": [0.0] * 3,
            "kyy": [k] * 3,
            "cxx": [c] * 3,
            "cxy": [0.0] * 3,
            "cyx": [0.0] * 3,
            "cyy": [c] * 3,
        }
    return model_from_dict(data)


@pytest.mark.parametrize("integrator", [RK4(dt=1e-5), ModalRK4()])
def test_speed_table_with_constant_values_equals_constant_bearings(make_gearbox, integrator):
    train = make_gearbox(elements=4)
    tabled = _with_table(train, lambda s, k: k)
    kw = dict(t_end=0.05, integrator=integrator, save=Save(dt=1e-4))
    a = transient(train, **kw)
    b = transient(tabled, **kw)
    np.testing.assert_allclose(b.node_x, a.node_x, rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(b.bearing_force, a.bearing_force, rtol=1e-6, atol=1e-6)


def test_speed_dependent_bearing_frozen_speed_harmonic(make_gearbox):
    """kxx varying with speed: at frozen speed the steady state is the harmonic response with
    the coefficients at the running speed (oracle: complex solve with Assembly.matrices)."""
    train = _with_table(make_gearbox(elements=4), lambda s, k: k * (0.5 + s / 680.678))
    asm = assemble(train)
    M, C, G, K = (x.toarray() for x in asm.matrices(train.speed))
    keep = asm.dof_kind() != 2
    w = abs(train.speed)
    F = np.zeros(asm.n_dof, complex)
    for k, u in enumerate(train.unbalances):
        si, node = train.node_index(u, f"unbalances[{k}]")
        g = asm.node_offset[si][node]
        sig = np.sign(asm.shaft_speeds(train.speed)[si])
        F[g] += u.amount * w**2
        F[g + 1] += -1j * sig * u.amount * w**2
    A = K - w**2 * M + 1j * w * (C + G)
    X = np.zeros(asm.n_dof, complex)
    X[keep] = np.linalg.solve(A[np.ix_(keep, keep)], F[keep])
    res = transient(
        train, t_end=0.3, integrator=RK4(dt=1e-5), frozen_speed=True, save=Save(dt=5e-5)
    )
    sl = res.time > 0.25
    t = res.time[sl]
    g = asm.node_offset[0][2]
    x = res.channel(g)[sl]
    (a, b), *_ = np.linalg.lstsq(np.column_stack([np.cos(w * t), np.sin(w * t)]), x, rcond=None)
    assert abs((a - 1j * b) - X[g]) < 0.01 * abs(X[g])


def _loaded(make_gearbox, torque=500.0):
    from gearrotor.io.model_file import model_from_dict

    train = make_gearbox(NO_UNB)
    data = train.model_dump()
    data["torques"] = [
        {"shaft": "shaft1", "node": 0, "value": torque},
        {"shaft": "shaft2", "node": 20, "value": torque},
    ]
    return model_from_dict(data)


@pytest.mark.parametrize("integrator", [RK4(dt=8e-6), ModalRK4()])
def test_static_initial_state_under_torque(make_gearbox, integrator):
    """Balanced drive/load torques of 500 N·m: starting from the static deflection, nothing
    moves and the mesh carries exactly T/(r cos αn) (oracle: static equilibrium); starting
    from zero, the torque step rings the torsional modes (±100 % of the mean force). The modal
    method includes static correction shapes when the model has torques."""
    train = _loaded(make_gearbox)
    F_exact = 500.0 / (0.11 * np.cos(0.349))
    st = transient(train, t_end=0.02, integrator=integrator, initial="static", save=Save(dt=2e-5))
    F = st.mesh_force[:, 0]
    assert np.allclose(np.abs(F), F_exact, rtol=1e-6)
    z = transient(train, t_end=0.02, integrator=integrator, save=Save(dt=2e-5))
    assert abs(np.abs(z.mesh_force[1:, 0]).mean() / F_exact - 1) < 0.02
    assert np.ptp(z.mesh_force[:, 0]) > F_exact
    if isinstance(integrator, ModalRK4):
        assert z.stats.n_modes > 34  # static shapes added


def test_static_initial_state_with_backlash_and_unbalanced_torque(make_gearbox):
    """Backlash is taken up on the loaded flank; an unbalanced torque gives the rigid angular
    acceleration α = rᵀf / rᵀMr of the whole train (d'Alembert)."""
    from gearrotor.analyses.transient.equations import static_state
    from gearrotor.io.model_file import model_from_dict

    train = _loaded(make_gearbox)
    data = train.model_dump()
    data["meshes"][0]["backlash"] = {"value": 2e-5, "convention": "one_side"}
    data["torques"][1]["value"] = 300.0
    train = model_from_dict(data)
    system = build_system(train)
    q, alpha = static_state(system)
    r = np.zeros(system.n)
    for s, a in enumerate(system.a_weights):
        r[a != 0] = system.assembly.speed_ratio[s]
    M = system.M.toarray()
    assert alpha == pytest.approx((500.0 - 300.0) / (r @ M @ r), rel=1e-9)
    law = system.meshes[0]
    d = system.mesh_dofs[0]
    delta = law.w[d >= 0] @ q[d[d >= 0]]
    assert abs(delta) > law.backlash
    res = transient(
        train, t_end=0.01, integrator=RK4(dt=8e-6), initial="static", save=Save(dt=2e-5)
    )
    assert np.all(res.contact[:, 0] == np.sign(delta))
    acc = np.polyfit(res.time, res.shaft_speed[:, 0], 1)[0]
    assert acc == pytest.approx(alpha, rel=1e-3)
