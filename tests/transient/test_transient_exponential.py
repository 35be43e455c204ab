"""The exponential modal scheme (``ModalRK4(exact_linear=...)``, issue 16): the oscillators
exact, the rest by ETDRK4 (Cox & Matthews 2002, J. Comput. Phys. 176, 430–455), one linear
operator per contact state, contact changes located within the step.

Oracles: the closed-form response of an oscillator to a constant force (which ETDRK4 integrates
exactly, whatever the step); the observed order under step halving (4 for ETDRK4 on a smooth
problem; kept across the contact changes when they are located); the linear stability of the
scheme's one-step matrix; RK4 on the full model (the reference integrator).
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.transient import RK4, ModalRK4, Save, transient
from gearrotor.analyses.transient.kernels import etd_coefficients
from gearrotor.errors import SolverError

VARIATION = {
    "meshes[0].variation.ka_ratio": "0.2",
    "meshes[0].variation.terms": "5",
    "meshes[0].variation.contact_ratio": "1.592",
}
BACKLASH = {"meshes[0].backlash.value": "0.0254 mm"}


@pytest.mark.parametrize("w", [0.0, 1e-3, 0.7, 3.0, 40.0])
def test_etd_step_exact_for_constant_force(w):
    """ζ̈ + ω²ζ = g with g constant: ζ(τ) = ζ0 cos ωτ + v0 sin ωτ/ω + g (1 − cos ωτ)/ω²,
    v(τ) = −ω ζ0 sin ωτ + v0 cos ωτ + g sin ωτ/ω (ω = 0: ζ0 + v0 τ + g τ²/2). With all four
    stages equal to g the step is E(τ)x + (τf1 + 4τf2 + τf3)(0, g), which must reproduce it
    to round-off for ωτ from 0 (series branch of the φ-functions) to 40 (closed form)."""
    tau, z0, v0, g = 1.0, 0.3, -0.7, 2.5
    C = np.zeros((12, 1))
    etd_coefficients(np.array([w]), tau, C)
    z = C[4, 0] * z0 + C[5, 0] * v0 + (C[7, 0] + 4 * C[9, 0] + C[11, 0]) * g
    v = C[4, 0] * v0 - w**2 * C[5, 0] * z0 + (C[6, 0] + 4 * C[8, 0] + C[10, 0]) * g
    if w == 0.0:
        ze, ve = z0 + v0 * tau + 0.5 * g * tau**2, v0 + g * tau
    else:
        c, s = np.cos(w * tau), np.sin(w * tau)
        ze = z0 * c + v0 * s / w + g * 2 * np.sin(0.5 * w * tau) ** 2 / w**2  # 1 - cos ωτ
        ve = -w * z0 * s + v0 * c + g * s / w
    assert z == pytest.approx(ze, rel=1e-12, abs=1e-13)
    assert v == pytest.approx(ve, rel=1e-12, abs=1e-13)


def _observed_order(train, make, dts, t_end=0.01):
    finals, runs = [], []
    for dt in dts:
        res = transient(train, t_end=t_end, integrator=make(dt))
        finals.append(np.concatenate([res.final_q, res.final_qdot]))
        runs.append(res)
    err = [np.linalg.norm(finals[k] - finals[k + 1]) for k in range(len(finals) - 1)]
    return [np.log2(err[k] / err[k + 1]) for k in range(len(err) - 1)], err, runs


def test_exponential_step_halving_order_4(make_gearbox):
    """Coarse gearbox with mesh-stiffness variation, no backlash: order ≈ 4 (measured 4.03,
    4.11) at steps twice the classical modal RK4's (test_transient_integrators)."""
    train = make_gearbox(VARIATION, elements=4)
    orders, _, _ = _observed_order(
        train, lambda dt: ModalRK4(dt=dt, exact_linear=True), [8e-5, 4e-5, 2e-5, 1e-5]
    )
    assert 3.6 < orders[-1] < 4.4, orders


def test_exponential_order_4_across_located_contact_changes(make_gearbox):
    """Coarse gearbox with 2b = 0.0508 mm: the teeth separate (~78 % of the time); 11
    contact changes are located in 0.01 s. With the contact changes located the observed order stays
    ≈ 4 (measured 3.97 between 2e-5, 1e-5 and 5e-6 s); classical modal RK4, which steps across
    the kink of the backlash law, shows 2.3–3.3 and a ~300× larger error at 1e-5 s."""
    train = make_gearbox({**VARIATION, **BACKLASH}, elements=4)
    orders, err, runs = _observed_order(train, lambda dt: ModalRK4(dt=dt), [2e-5, 1e-5, 5e-6])
    assert all(r.stats.scheme == "exponential" for r in runs)  # the default with backlash
    assert runs[-1].stats.contact_events >= 8  # 11 located in 0.01 s
    assert 0.5 < runs[-1].contact_loss_fraction[0] < 0.95
    assert 3.6 < orders[-1] < 4.4, orders
    _, err_rk4, _ = _observed_order(
        train, lambda dt: ModalRK4(dt=dt, exact_linear=False), [1e-5, 5e-6]
    )
    assert err_rk4[0] > 30 * err[1]


def test_exponential_unstable_step_refused_and_default_reduced(make_gearbox):
    """Bearing damping 1e6 N·s/m (57× SPEC 6.1's): low modes overdamped with rates far above
    the mesh frequency, which the explicit part of the scheme must resolve. An explicit step
    that amplifies them is refused; the default (4 steps per mesh period, 7.7e-5 s) is reduced
    until stable, and the 1x response then agrees with RK4 within 1 % (as the classical
    scheme's test_modal_default_step_respects_damping)."""
    train = make_gearbox({f"bearings[{j}].c": "1e6 N*s/m" for j in range(4)}, elements=4)
    with pytest.raises(SolverError, match="amplifies the damped modes"):
        transient(train, t_end=1e-3, integrator=ModalRK4(dt=7.7e-5, exact_linear=True))
    save = Save(dt=1e-4)
    fast = transient(train, t_end=0.05, integrator=ModalRK4(exact_linear=True), save=save)
    assert fast.stats.dt < 0.5 * np.pi / (2 * np.pi * 3250.0)
    ref = transient(train, t_end=0.05, integrator=RK4(dt=1.3e-6), save=save)
    a_ref, a_fast = ref.amplitude_1x(0.03), fast.amplitude_1x(0.03)
    for node, amp in a_ref.items():
        for d in ("x", "y"):
            assert a_fast[node][d] == pytest.approx(amp[d], rel=0.01), (node, d)


def test_exponential_default_step_resolves_the_mesh_not_the_contact_mode(make_gearbox):
    """SPEC 6.1 with 2b = 0.0508 mm: the basis keeps a 15.5 kHz Ritz vector (the gears on the
    mesh spring) that set classical RK4's step to 9.3e-6 s; the exponential scheme integrates
    it exactly and steps at a quarter of the mesh period (3250 Hz: 7.7e-5 s)."""
    res = transient(make_gearbox(BACKLASH), t_end=1e-3)
    assert res.stats.scheme == "exponential"
    assert res.stats.highest_mode_hz > 1.4e4
    assert res.stats.dt == pytest.approx(0.25 / 3250.0, rel=1e-3)
    plain = transient(make_gearbox(), t_end=1e-3)
    assert plain.stats.scheme == "rk4"


def test_exponential_resumed_run_is_bit_identical(make_gearbox, tmp_path, monkeypatch):
    """Checkpoints hold the modal state η; each chunk starts from the operator of the state it
    finds, so a run with backlash killed at 57 % resumes from 55 % and ends bit-identical to an
    uninterrupted run with the same checkpoints (as the classical integrators,
    test_transient_checkpoint.py)."""
    from gearrotor.analyses.transient import Checkpoint, driver

    train = make_gearbox(BACKLASH, elements=4)
    kw = dict(t_end=0.2, save=Save(dt=2e-4))
    reference = transient(train, checkpoint=Checkpoint(tmp_path / "ref.npz"), **kw)
    assert reference.stats.scheme == "exponential" and reference.stats.contact_events > 0
    ck = Checkpoint(tmp_path / "run.npz", every=1e9)
    real = driver.kn.etd_modal

    def dies_at_57_percent(t0, dt, nst, *args):
        if t0 + nst * dt > 0.57 * 0.2:
            raise KeyboardInterrupt
        return real(t0, dt, nst, *args)

    monkeypatch.setattr(driver.kn, "etd_modal", dies_at_57_percent)
    with pytest.raises(KeyboardInterrupt):
        transient(train, checkpoint=ck, **kw)
    monkeypatch.setattr(driver.kn, "etd_modal", real)
    res = transient(train, checkpoint=ck, **kw)
    assert res.stats.contact_events < reference.stats.contact_events  # resumed, not rerun
    # the step envelope too (saved in the checkpoint: test_transient_envelope.py)
    for name in ("final_q", "node_x", "time", "contact", "mesh_force_max"):
        np.testing.assert_array_equal(getattr(res, name), getattr(reference, name), name)
    np.testing.assert_array_equal(res.mesh_contact_loss_time, reference.mesh_contact_loss_time)


_RERUN = """
import hashlib, sys
import numpy as np
if sys.argv[2] == "former":  # every kernel with its Python entry point, as before kernel_only
    import numba
    import gearrotor.analyses.jit as jit
    jit.kernel_only = lambda **options: numba.njit(**options)
from gearrotor import load_model
from gearrotor.analyses.transient import transient
train = load_model(sys.argv[1], {"meshes[0].backlash.value": "0.0254 mm"})
r = transient(train, t_end=0.3)
h = hashlib.sha1()
for a in (r.contact, r.time, r.speed_fluctuation()):
    h.update(np.ascontiguousarray(a).tobytes())
print(r.stats.scheme, h.hexdigest())
"""


@pytest.mark.slow
def test_rerun_reproduces_a_backlash_run_bit_for_bit(tmp_path, examples):
    """The same run in two processes, the first compiling the kernels into an empty numba cache
    and the second loading them from it, gives the same contact history and speeds bit for
    bit. With 'reassoc' among the exponential kernels' fastmath flags the compiled and the
    cached code rounded differently (1e-13 relative without backlash); the impacts amplify
    that to ~1 % in the speed fluctuation (SPEC 6.1 case 15, measured 16.87 against 17.02 rpm
    in two runs of the study), so a rerun did not reproduce a result.

    A third process compiles the kernels the former way, every one with numba's Python entry
    point (``jit.kernel_only`` replaced by plain ``njit``, in an empty cache of its own): the
    kernels called only from kernels are compiled without it since the numba start-up work
    (issue 28), which must leave every number the same to the bit."""
    import os
    import subprocess
    import sys

    script = tmp_path / "rerun.py"
    script.write_text(_RERUN)

    def run(path: str, cache: str) -> list[str]:
        env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / cache)}
        return subprocess.run(
            [sys.executable, str(script), str(examples / "unity_gearbox.toml"), path],
            env=env,
            capture_output=True,
            text=True,
            check=True,
            timeout=600,
        ).stdout.split()

    out = [run("current", "numba"), run("current", "numba"), run("former", "numba-former")]
    assert out[0][0] == "exponential"
    assert out[0] == out[1]  # compiled, then loaded from the cache
    assert out[0] == out[2]  # the former way of compiling
