"""The compressor gearbox (examples/compressor_gearbox.toml, SPEC 6.3) in the transient: two
helical meshes (double helical), a pinion that floats axially on them, and tabulated tilting-pad
bearings whose cross-coupled stiffness is not symmetric (kxy ≠ kyx) and whose journals are
heavily damped (cyy ≈ 5e6 N·s/m).

* ModalRK4 with static-correction shapes agrees with RK4 at the seed's Δt = 1e-6 s, unbalance
  only and at rated load (36.8 MW, Ka/Kg = 0.5). It used to re-diagonalise its extended basis
  with one triangle of the non-symmetric reduced stiffness, which gave the rigid rotation a
  6 Hz frequency: 27x the 1x amplitude, half the mean mesh force.
* RK4's stability limit is set by the journals' overdamped eigenvalue (λ ≈ −1.98e5 1/s,
  |λ|·Δt ≤ 2.785), not by the highest natural frequency (ω·Δt ≤ 2√2 gave 1.58e-5 s): the
  CLI's former default, 1.5e-5 s, diverges within 3 ms and is now refused; the default runs.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import typer
from typer.testing import CliRunner

from gearrotor.analyses.transient import (
    RK4,
    ModalRK4,
    Save,
    amplitude_at,
    build_system,
    rk4_max_step,
    transient,
)
from gearrotor.cli.transient import plot_command, transient_command
from gearrotor.errors import SolverError
from gearrotor.io import load_model
from gearrotor.model import Train

MODEL = Path(__file__).resolve().parents[2] / "examples" / "compressor_gearbox.toml"
RPM = np.pi / 30
PROBE = "pinion[0]"  # blind end, the unbalance plane


def compressor(loaded: bool = False, ka: float = 0.0) -> Train:
    """The example; ``loaded`` adds the rated torques as examples/scripts/compressor_gearbox.py
    does (36.8 MW: turbine on the bull-gear hub, compressor ∝ Ω² on the pinion hub)."""
    overrides = {f"meshes[{m}].variation.ka_ratio": str(ka) for m in (0, 1)}
    train = load_model(MODEL, overrides)
    if not loaded:
        return train
    data = train.model_dump()
    data["torques"] = [
        {
            "shaft": "pinion",
            "node": 14,
            "value": -36.8e6 / (5700 * RPM),
            "speed_exponent": 2.0,
            "reference_speed": 5700 * RPM,
        },
        {"shaft": "bull_gear", "node": 0, "value": -36.8e6 / (5700 * 42 / 71 * RPM)},
    ]
    return Train.model_validate(data)


def _metrics(res, window: float = 0.02) -> dict:
    t = res.time
    last = t >= t[-1] - window
    om = float(np.mean(np.abs(res.shaft_speed[last, 0])))
    k = list(res.node_labels).index(PROBE)
    F = res.mesh_force[last]
    return {
        "x_1x": amplitude_at(t[last], res.node_x[last, k], om),
        "y_1x": amplitude_at(t[last], res.node_y[last, k], om),
        "F_mean": F.mean(axis=0),
        "F_1x": np.array([amplitude_at(t[last], F[:, j], om) for j in range(2)]),
        "F_mesh": np.array([amplitude_at(t[last], F[:, j], 42 * om) for j in range(2)]),
    }


@pytest.mark.parametrize("loaded", [False, True], ids=["unbalance", "rated_load"])
def test_modal_static_correction_agrees_with_rk4(loaded):
    """0.03 s from rest (unbalance only) or from the static deflection (rated load, Ka/Kg =
    0.5), compared over the last 0.02 s, recorded every 1e-5 s (25 samples per mesh period:
    the default 4 would alias the mesh harmonics). 1x at the blind end within 0.5 %, the
    tolerance the modal basis is built to (its linear 1x error, ``stats.harmonic_error``;
    measured 0.02–0.04 %); mean mesh force per helix within 0.1 % (173.7 kN at rated load:
    measured 0.04 %) and its 1x (unbalance only, ≈ 370 N) or mesh-frequency (rated load,
    ≈ 88 kN) amplitude within 1 % (measured 0.01 %). Before the fix: 27x the 1x amplitude,
    the helix forces in antiphase."""
    train = compressor(loaded, ka=0.5 if loaded else 0.0)
    kw = {"t_end": 0.03, "save": Save(dt=1e-5), "initial": "static" if loaded else "zero"}
    ref = _metrics(transient(train, integrator=RK4(dt=1e-6), **kw))
    fast_res = transient(train, integrator=ModalRK4(static_correction=True), **kw)
    fast = _metrics(fast_res)
    assert fast_res.stats.harmonic_error < 0.005
    assert fast["x_1x"] == pytest.approx(ref["x_1x"], rel=0.005)
    assert fast["y_1x"] == pytest.approx(ref["y_1x"], rel=0.005)
    assert 1.5e-6 < ref["x_1x"] < 2.5e-6
    if loaded:
        assert ref["F_mean"] == pytest.approx([173.7e3, 173.7e3], rel=0.002)
        assert fast["F_mean"] == pytest.approx(ref["F_mean"], rel=0.001)
        assert fast["F_mesh"] == pytest.approx(ref["F_mesh"], rel=0.01)
    else:
        assert np.all(np.abs(fast["F_mean"]) < 0.2 * ref["F_1x"])
        assert fast["F_1x"] == pytest.approx(ref["F_1x"], rel=0.01)


def test_modal_default_basis_at_rated_load_uses_static_correction():
    """With torques in the model the static correction is the default: the mean mesh force
    per helix carries the rated load from the first revolution (0.02 s run)."""
    res = transient(compressor(loaded=True), t_end=0.02, save=Save(dt=1e-5), initial="static")
    F = res.mesh_force[res.time >= 0.01]
    assert F.mean(axis=0) == pytest.approx([173.7e3, 173.7e3], rel=0.002)
    assert np.ptp(F, axis=0).max() < 0.01 * 173.7e3


def test_rk4_step_limit_set_by_tilting_pad_damping():
    """The limit is 2.785/|λ| of the journals' overdamped eigenvalue: 1.40e-5 s (the undamped
    estimate was 2√2/ω_max = 1.58e-5 s). The old default (1.5e-5 s) is refused before the run
    and diverges without the check; 0.95× the limit runs 5 ms."""
    train = compressor()
    limit = rk4_max_step(build_system(train))
    assert 1.38e-5 < limit < 1.42e-5
    with pytest.raises(SolverError, match=r"λ = -1\.98\d*e\+05 ± 0i .* dt ≤ 1\.39\d*e-05 s"):
        transient(train, t_end=0.005, integrator=RK4(dt=1.5e-5))
    with pytest.raises(SolverError, match=r"diverged at t = 0\.00[0-3]"):
        transient(train, t_end=0.005, integrator=RK4(dt=1.5e-5, check_stability=False))
    res = transient(train, t_end=0.005, integrator=RK4(dt=0.95 * limit))
    k = list(res.node_labels).index(PROBE)
    assert np.abs(res.node_x[:, k]).max() < 5e-6


def test_cli_default_rk4_step_is_stable(tmp_path):
    """``--method rk4`` without ``--dt``: 0.95× the limit rounded down to two digits."""
    app = typer.Typer()
    app.command("transient")(transient_command)
    app.command("transient-plot")(plot_command)
    res = CliRunner().invoke(
        app,
        [
            "transient",
            str(MODEL),
            "--t-end",
            "0.005",
            "--method",
            "rk4",
            "--format",
            "json",
            "--no-progress",
        ],
    )
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout.strip().splitlines()[-1])
    assert s["dt_s"] == 1.3e-5
    for m in s["meshes"].values():  # unbalance only: ±0.7 kN
        assert -1e3 < m["force_min_N"] < m["force_max_N"] < 1e3
