"""Physics oracles of the transient equations (SPEC 2.5): harmonic steady state at frozen speed,
energy and generalized momentum conservation, implicit θ̈ terms."""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor import assemble
from gearrotor.analyses.transient import RK4, ModalRK4, Save, build_system, transient
from gearrotor.analyses.transient.results import amplitude_at


def _harmonic_reference(train):
    """Solve (K − ω²M + iω(C+G)) X = F on the non-torsional DOFs (θz held at rigid rotation)
    for the unbalance forces F_x = m e ω² e^{iσφ}, F_y = −iσ m e ω² e^{iσφ} (x = Re X e^{iωt})."""
    asm = assemble(train)
    M, C, G, K = (a.toarray() for a in asm.matrices(train.speed))
    keep = asm.dof_kind() != 2
    speeds = asm.shaft_speeds(train.speed)
    w = abs(speeds[0])
    assert np.allclose(np.abs(speeds), w)
    F = np.zeros(asm.n_dof, complex)
    for k, u in enumerate(train.unbalances):
        si, node = train.node_index(u, f"unbalances[{k}]")
        g = asm.node_offset[si][node]
        sig = np.sign(speeds[si])
        F[g] += u.amount * w**2 * np.exp(1j * sig * u.phase)
        F[g + 1] += -1j * sig * u.amount * w**2 * np.exp(1j * sig * u.phase)
    A = K - w**2 * M + 1j * w * (C + G)
    X = np.zeros(asm.n_dof, complex)
    X[keep] = np.linalg.solve(A[np.ix_(keep, keep)], F[keep])
    return asm, X, w


def test_frozen_speed_steady_state_equals_harmonic_response(make_gearbox):
    """Constant mesh, constant speed: the transient settles on the harmonic unbalance response
    of the linear model (oracle: direct complex solve from the assembly), within 1 %."""
    train = make_gearbox()
    asm, X, w = _harmonic_reference(train)
    res = transient(
        train, t_end=0.3, integrator=RK4(dt=8e-6), frozen_speed=True, save=Save(dt=4e-5)
    )
    sl = res.time >= res.time[-1] - 0.05
    t = res.time[sl]
    worst = 0.0
    for m in asm.meshes:
        for g in (m.dofs[0], m.dofs[6]):
            for d in (0, 1):
                x = res.channel(g + d)[sl]
                A = np.column_stack([np.cos(w * t), np.sin(w * t)])
                (a, b), *_ = np.linalg.lstsq(A, x, rcond=None)
                Xt = a - 1j * b
                worst = max(worst, abs(Xt - X[g + d]) / abs(X[g + d]))
    assert worst < 0.01, worst
    # the speed state really is frozen
    assert np.allclose(res.shaft_speed, asm.shaft_speeds(train.speed)[None, :], rtol=1e-12)


def _energy(system, q, v):
    """Lagrangian energy h = T + V of the transient equations (no damping, constant mesh)."""
    M, K, _ = system.linear_matrices()
    G = [g.toarray() for g in system.G]
    e = 0.5 * v @ M @ v + 0.5 * q @ K @ q
    for s, g in enumerate(G):
        e += 0.5 * (system.a_weights[s] @ v) * (v @ g @ q)
    for u in range(len(system.unbalance_me)):
        ix, iy, it = system.unbalance_dofs[u]
        th = q[it] + system.unbalance_phase[u]
        e += system.unbalance_me[u] * v[it] * (-np.sin(th) * v[ix] + np.cos(th) * v[iy])
    return e


@pytest.mark.parametrize("method", ["rk4", "modal"])
def test_energy_conserved_free_speed_no_damping(make_gearbox, method):
    """Free speed, no damping, no torque, with unbalance and an initial lateral/torsional
    perturbation: the equations are Lagrangian, so the energy h = T + V is conserved; the
    integrator's drift falls at least at RK4's order (measured ≈ 2⁵ per halving here)."""
    ov = {f"bearings[{i}].c": "0" for i in range(4)}
    train = make_gearbox(ov, elements=4)
    asm = assemble(train)
    q0 = np.zeros(asm.n_dof)
    q0[asm.node_offset[0][2]] = 5e-5
    q0[asm.node_offset[0][0] + 5] = 2e-3
    system = build_system(train, initial_q=q0)
    drifts = []
    for dt in (5e-6, 2.5e-6) if method == "rk4" else (1e-5, 5e-6):
        integ = RK4(dt=dt) if method == "rk4" else ModalRK4(dt=dt, cutoff=8000)
        res = transient(
            train, t_end=0.05, integrator=integ, initial_q=q0, save=Save(dt=1e-3, full_state=True)
        )
        E = np.array([_energy(system, q, v) for q, v in zip(res.q, res.qdot, strict=True)])
        E_end = _energy(system, res.final_q, res.final_qdot)
        drifts.append(max(np.abs(E - E[0]).max(), abs(E_end - E[0])))
    assert drifts[1] < 2e-6 * E[0]
    assert drifts[0] / drifts[1] > 12.0, drifts
    # the lateral motion is not trivial: the energy exchanged with it is many times the drift
    lateral = ~system.torsion
    kin_lat = 0.5 * np.einsum(
        "ti,ij,tj->t",
        res.qdot[:, lateral],
        system.M.toarray()[np.ix_(lateral, lateral)],
        res.qdot[:, lateral],
    )
    assert kin_lat.max() > 100 * drifts[1]


def test_generalized_momentum_conserved(make_gearbox):
    """Without unbalance, torque and mesh variation the Lagrangian is invariant under the rigid
    rotation r of the train (θz_s = ratio_s α): p = rᵀM q̇ + Σ_s ½ ratio_s q̇ᵀG_s q is conserved,
    with bearing damping too (it acts on lateral DOFs only). Total Σ J_i Ω_i weighted by the
    speed ratios is its rigid part."""
    ov = {f"unbalances[{i}].amount": "0" for i in range(2)}
    train = make_gearbox(ov, elements=4)
    asm = assemble(train)
    q0 = np.zeros(asm.n_dof)
    q0[asm.node_offset[0][2]] = 5e-5  # gear 1 x
    q0[asm.node_offset[1][2] + 1] = -3e-5  # gear 2 y
    q0[asm.node_offset[0][0] + 5] = 2e-3  # twist of shaft 1
    system = build_system(train, initial_q=q0)
    res = transient(
        train,
        t_end=0.05,
        integrator=RK4(dt=1e-5),
        initial_q=q0,
        save=Save(dt=1e-3, full_state=True),
    )
    r = np.zeros(system.n)
    ratio = asm.speed_ratio
    for s, a in enumerate(system.a_weights):
        r[a != 0] = ratio[s]
    M = system.M.toarray()
    G = [g.toarray() for g in system.G]
    p = np.array(
        [
            r @ M @ v + sum(0.5 * ratio[s] * (v @ G[s] @ q) for s in range(len(G)))
            for q, v in zip(res.q, res.qdot, strict=True)
        ]
    )
    lateral = np.ptp(res.q[:, ~system.torsion], axis=0).max()
    assert lateral > 1e-5  # something moved
    assert np.ptp(p) < 1e-10 * abs(p[0]), (np.ptp(p), p[0])
    # the speeds did fluctuate
    assert np.ptp(res.shaft_speed[:, 0]) > 1e-3


def test_reactions_change_only_the_torsion(make_gearbox):
    """The dissertation form (reactions=False) keeps the unbalance torque out of the torsional
    equations; the 1x lateral response is the same within 1 %, the mean speed is not (with
    reactions the spin feeds the bearing damping and the free train slows down)."""
    train = make_gearbox(elements=4)
    kw = dict(t_end=0.3, integrator=ModalRK4(), save=Save(dt=2e-4))
    a = transient(train, reactions=True, **kw)
    b = transient(train, reactions=False, **kw)
    sl = a.time > 0.2
    w = abs(a.shaft_speed[sl, 0].mean())
    xa = amplitude_at(a.time[sl], a.node_x[sl, 0], w)
    xb = amplitude_at(b.time[sl], b.node_x[sl, 0], w)
    assert abs(xa / xb - 1) < 0.01
    slow_a = a.shaft_speed[-1, 0] - a.shaft_speed[0, 0]
    slow_b = b.shaft_speed[-1, 0] - b.shaft_speed[0, 0]
    assert slow_a < -0.1  # rad/s: coasting down on bearing damping
    assert abs(slow_b) < abs(slow_a)
