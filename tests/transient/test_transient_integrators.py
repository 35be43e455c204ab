"""Integrators: observed order under step halving (diffrax-style order test), agreement of the
modal method with RK4, stability check, divergence, backlash contact events resolved."""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.transient import RK4, ModalRK4, Save, transient
from gearrotor.analyses.transient.step_limits import _rk4_step_limit
from gearrotor.errors import SolverError
from gearrotor.model import Train

VARIATION = {
    "meshes[0].variation.ka_ratio": "0.2",
    "meshes[0].variation.terms": "5",
    "meshes[0].variation.contact_ratio": "1.592",
}


def _observed_order(train, make, dts, t_end=0.01):
    finals = []
    for dt in dts:
        res = transient(train, t_end=t_end, integrator=make(dt))
        finals.append(np.concatenate([res.final_q, res.final_qdot]))
    err = [np.linalg.norm(finals[k] - finals[k + 1]) for k in range(len(finals) - 1)]
    return [np.log2(err[k] / err[k + 1]) for k in range(len(err) - 1)]


def test_rk4_step_halving_order_4(make_gearbox):
    """Coarse gearbox (highest mode 10.8 kHz) with mesh-stiffness variation: successive
    differences under step halving shrink by ≈ 2⁴ (observed order ≈ 4)."""
    train = make_gearbox(VARIATION, elements=4)
    orders = _observed_order(train, lambda dt: RK4(dt=dt), [2e-5, 1e-5, 5e-6, 2.5e-6])
    assert 3.6 < orders[-1] < 4.4, orders


def test_modal_step_halving_order_4(make_gearbox):
    train = make_gearbox(VARIATION, elements=4)
    orders = _observed_order(train, lambda dt: ModalRK4(dt=dt), [4e-5, 2e-5, 1e-5, 5e-6])
    assert 3.6 < orders[-1] < 4.4, orders


def test_modal_agrees_with_rk4(make_gearbox):
    """Full gearbox, Ka/Kg = 0.2, c = 1.592, 5 terms: the default modal method (cut-off 1.25×
    mesh frequency, ω·dt = 0.9) reproduces RK4's 1x amplitudes within 1 % and the speed
    fluctuation within 2 % over 0.15 s (the full 3 s comparison is benchmarks/transient_app2.py)."""
    train = make_gearbox(VARIATION)
    save = Save(dt=4e-5)
    ref = transient(train, t_end=0.15, integrator=RK4(dt=8e-6), save=save)
    fast = transient(train, t_end=0.15, integrator=ModalRK4(), save=save)
    assert fast.stats.steps * 4 < ref.stats.steps
    a_ref, a_fast = ref.amplitude_1x(0.1), fast.amplitude_1x(0.1)
    for node, amp in a_ref.items():
        for d in ("x", "y"):
            assert abs(a_fast[node][d] / amp[d] - 1) < 0.01
    for s in range(2):
        f_ref = np.ptp(ref.shaft_speed[ref.time > 0.05, s])
        f_fast = np.ptp(fast.shaft_speed[fast.time > 0.05, s])
        assert abs(f_fast / f_ref - 1) < 0.02


def test_rk4_step_outside_stability_region_is_refused(make_gearbox):
    """The dissertation's Δt = 9e-6 s is outside RK4's stability region for this 20-element
    Timoshenko model (highest lateral mode ≈ 50.4 kHz, ω·Δt = 2.85 > 2√2)."""
    train = make_gearbox()
    with pytest.raises(SolverError, match=r"dt ≤ 8\.\d+e-06"):
        transient(train, t_end=1e-3, integrator=RK4(dt=9e-6))


def test_rk4_step_limit_closed_form():
    """RK4's region |1 + z + z²/2 + z³/6 + z⁴/24| ≤ 1: an undamped oscillator (λ = ±iω) is
    stable up to ω·Δt = 2√2, a damper (λ = −c/m) up to |λ|·Δt = 2.7853 (the real root of
    z³ + 4z² + 12z + 24 = 0); a damped pair at the edge has |R| = 1."""
    h, lam = _rk4_step_limit(np.array([[2.0]]), np.array([[8.0]]), np.zeros((1, 1)))
    assert h == pytest.approx(2 * np.sqrt(2) / 2.0, rel=1e-9) and abs(lam) == pytest.approx(2.0)
    root = np.roots([1.0, 4.0, 12.0, 24.0])
    edge = -float(root[np.abs(root.imag) < 1e-12].real[0])
    h, lam = _rk4_step_limit(np.eye(1), np.zeros((1, 1)), np.array([[5.0e3]]))
    assert h == pytest.approx(edge / 5.0e3, rel=1e-9) and lam == pytest.approx(-5.0e3)
    h, lam = _rk4_step_limit(np.eye(1), np.array([[1.0e6]]), np.array([[1.2e3]]))  # ζ = 0.6
    z = h * lam
    assert abs(1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) == pytest.approx(1.0, abs=1e-9)
    assert 2.6 < abs(z) < 2.8


def test_modal_keeps_cross_coupled_stiffness(make_gearbox):
    """A destabilising cross-coupling kxy = −kyx = 5e5 N/m at each gear (the skew part of K)
    raises the coarse gearbox's 1x response at gear 1 from 289 to 426 µm (x); the modal method
    (modes of the symmetric part, the skew part applied as a force) reproduces RK4 within 1 %
    (its 1x tolerance, 0.5 %, plus the start transient; measured 0.3 %). Built on one
    triangle of K, it gave 185 µm."""
    data = make_gearbox(elements=4).model_dump()
    data["cross_couplings"] = [{"shaft": s, "node": 2, "q": 5e5} for s in ("shaft1", "shaft2")]
    train = Train.model_validate(data)
    save = Save(dt=4e-5)
    ref = transient(train, t_end=0.15, integrator=RK4(dt=1e-5), save=save).amplitude_1x(0.1)
    fast = transient(train, t_end=0.15, integrator=ModalRK4(), save=save).amplitude_1x(0.1)
    assert ref["shaft1[2]"]["x"] > 3e-4
    for node, amp in ref.items():
        for d in ("x", "y"):
            assert fast[node][d] == pytest.approx(amp[d], rel=0.01), (node, d)


def test_modal_default_step_respects_damping(make_gearbox):
    """Bearing damping 1e6 N·s/m (57x SPEC 6.1's) makes the reduced system's low modes
    overdamped with |λ| far above the highest kept frequency: the accuracy step (ω_k·Δt = 0.9,
    1.5e-5 s) diverged within 0.2 ms. The default step is 0.95× the reduced system's stability
    limit instead, the accuracy step is refused, and the 1x response agrees with RK4 within
    1 % (measured 0.15 %)."""
    train = make_gearbox({f"bearings[{j}].c": "1e6 N*s/m" for j in range(4)}, elements=4)
    save = Save(dt=1e-4)
    fast = transient(train, t_end=0.05, integrator=ModalRK4(), save=save)
    assert fast.stats.dt < 0.2 * 0.9 / (2 * np.pi * fast.stats.highest_mode_hz)
    with pytest.raises(SolverError, match=r"modal RK4 step dt = 1\.5e-05 s is outside"):
        transient(train, t_end=0.05, integrator=ModalRK4(dt=1.5e-5), save=save)
    ref = transient(train, t_end=0.05, integrator=RK4(dt=1.3e-6), save=save)
    a_ref, a_fast = ref.amplitude_1x(0.03), fast.amplitude_1x(0.03)
    for node, amp in a_ref.items():
        for d in ("x", "y"):
            assert a_fast[node][d] == pytest.approx(amp[d], rel=0.01), (node, d)


def test_divergence_names_the_time(make_gearbox):
    train = make_gearbox(elements=4)
    with pytest.raises(SolverError, match=r"diverged at t = [0-9.e-]+ s"):
        transient(
            train, t_end=0.05, integrator=RK4(dt=1e-4, check_stability=False), save=Save(dt=1e-4)
        )


def test_backlash_contact_loss_resolved(make_gearbox):
    """Backlash 2b = 2 µm: the teeth separate and re-engage on both flanks every 1x cycle. The
    contact-state history is the same at Δt and Δt/2 (transitions within one recording
    interval), each contact episode spans many steps, and the 1x amplitude agrees."""
    train = make_gearbox({"meshes[0].backlash.value": "0.001 mm"}, elements=20)
    save = Save(dt=1.6e-5)
    runs = [transient(train, t_end=0.04, integrator=RK4(dt=dt), save=save) for dt in (8e-6, 4e-6)]
    c0, c1 = (r.contact[:, 0] for r in runs)
    assert set(np.unique(c0)) == {-1, 0, 1}
    switches = np.flatnonzero(np.diff(c0) != 0)
    assert len(switches) > 10
    assert np.mean(c0 != c1) < 0.02
    steps_per_episode = runs[1].time[-1] / len(switches) / 4e-6
    assert steps_per_episode > 20
    a0, a1 = (r.amplitude_1x(0.02)["shaft1[10]"]["x"] for r in runs)
    assert abs(a0 / a1 - 1) < 0.01
    # no force while separated, compression/tension on the drive/back flank
    F = runs[1].mesh_force[:, 0]
    assert np.all(F[c1 == 0] == 0)
    assert np.all(F[c1 == 1] >= 0) and np.all(F[c1 == -1] <= 0)


def test_modal_backlash_uses_separated_modes(make_gearbox):
    """With backlash the modal basis also spans the separated shafts: contact-loss fraction
    and 1x amplitude close to RK4 (impacts make the detailed history sensitive)."""
    train = make_gearbox({"meshes[0].backlash.value": "0.0254 mm"})
    ref = transient(train, t_end=0.1, integrator=RK4(dt=8e-6), save=Save(dt=1e-5))
    fast = transient(train, t_end=0.1, integrator=ModalRK4(dt=1e-5), save=Save(dt=1e-5))
    assert abs(fast.contact_loss_fraction[0] - ref.contact_loss_fraction[0]) < 0.05
    a_ref = ref.amplitude_1x(0.05)["shaft1[10]"]["x"]
    a_fast = fast.amplitude_1x(0.05)["shaft1[10]"]["x"]
    assert abs(a_fast / a_ref - 1) < 0.01


def test_modal_accuracy_unreachable_is_an_error(make_gearbox):
    """When even the full basis misses the requested 1x accuracy the run is refused, not
    silently run inaccurate (a zero tolerance cannot be met: round-off alone exceeds it)."""
    train = make_gearbox()
    with pytest.raises(SolverError, match="cannot reach the requested 1x accuracy"):
        transient(train, t_end=1e-3, integrator=ModalRK4(tolerance=0.0))
