"""Benchmark: 20 s synchronous-motor start-up of examples/motor_gearbox_compressor.toml.

Run: ``python3 benchmarks/torsional.py``. Prints a table; goal (issue 12): the 20 s start-up
with the torsional model in ≤ 5 s on a 2-core machine. The accuracy check halves the step and
compares the peak shaft torque of every element and the energy balance; the run is timed after
a short warm-up run (numba compiles the kernels once and caches them).

Beside it, the same start-up through the coupled 6-DOF transient (``gearrotor.analyses.transient``,
modal RK4, ``initial="rest"``: the model's drives and loads through the same compiled laws) is
timed over its first ``SIX_DOF_INTERVAL`` s and its cost extrapolated to 20 s (it resolves every
kept lateral mode: steps of ~1e-5 s); the speeds of the two at the end of that interval are
compared.
"""

from __future__ import annotations

import os
import platform
import time
from pathlib import Path

import numpy as np

from gearrotor.analyses.torsional import torsional_model, torsional_modes, torsional_transient
from gearrotor.io import load_model

MODEL = Path(__file__).resolve().parents[1] / "examples" / "motor_gearbox_compressor.toml"
T_END = 20.0


def timed(fn):
    """((wall s, CPU s of this process), fn()): on a loaded machine the CPU time is the
    steadier measure."""
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return (time.perf_counter() - t0, time.process_time() - c0), out


SIX_DOF_INTERVAL = 0.1


def six_dof_cost(train, tors_run, interval: float = SIX_DOF_INTERVAL):
    """Seconds of wall time per simulated second of the 6-DOF start-up (modal RK4, the model's
    drives and loads, from rest), its step and steps, and the largest speed difference from the
    torsional start-up ``tors_run`` over the interval (rpm)."""
    from gearrotor.analyses.transient import ModalRK4, Save, transient

    def run(t):
        return transient(train, t_end=t, integrator=ModalRK4(), initial="rest", save=Save(dt=1e-3))

    run(interval / 20)  # compile
    wall, res = timed(lambda: run(interval))
    speed_t = np.array(
        [np.interp(res.time, tors_run.time, tors_run.speed[:, s]) for s in range(4)]
    ).T
    dev = float(np.max(np.abs(np.abs(res.shaft_speed) - speed_t))) * 30 / np.pi
    return (wall[0] / interval, wall[1] / interval), float(res.stats.dt), int(res.stats.steps), dev


def main() -> None:
    print(
        f"machine: {platform.machine()} {platform.processor() or ''} cores={os.cpu_count()} "
        f"python={platform.python_version()} numpy={np.__version__}"
    )
    t_load, train = timed(lambda: load_model(MODEL))
    t_model, tm = timed(lambda: torsional_model(train))
    t_modes, modes = timed(lambda: torsional_modes(tm))
    torsional_transient(tm, t_end=0.05)  # warm-up (compiled kernels are cached)
    t_run, res = timed(lambda: torsional_transient(tm, t_end=T_END))
    t_half, half = timed(lambda: torsional_transient(tm, t_end=T_END, dt=res.dt / 2))
    peak, peak2 = res.peak_element_torque, half.peak_element_torque
    rated = np.abs(res.rated_element_torque)
    path = rated > 1e-6 * rated.max()  # elements that carry the load
    rel = np.abs(peak - peak2) / peak2
    dev = float(rel[path].max())
    worst = int(np.argmax(peak2))
    off = np.flatnonzero(~path & (peak2 > 0.05 * peak2.max()))
    off_dev = float(rel[off].max()) if len(off) else 0.0
    off_el = tm.element_labels()[off[np.argmax(rel[off])]] if len(off) else "-"
    rows = [
        ("load + validate model", t_load, ""),
        (f"torsional model ({tm.n} DOF)", t_model, ""),
        ("torsional modes", t_modes, f"{len(modes)} modes, first {modes.frequency_hz[1]:.2f} Hz"),
        (
            f"start-up {T_END:g} s, dt {res.dt:.3g} s",
            t_run,
            f"goal <= 5 s; {res.steps} steps, {res.iterations / res.steps:.2f} iterations/step, "
            f"pull-in {res.pull_in_time[0]:.2f} s",
        ),
        (
            f"same, dt {half.dt:.3g} s",
            t_half,
            f"peak torque of the load path: max rel. change {dev:.2e} "
            f"({tm.element_labels()[worst]}: {peak[worst]:.5g} -> {peak2[worst]:.5g} N*m)",
        ),
        (
            "  off the load path",
            (0.0, 0.0),
            f"max rel. change {off_dev:.2e} ({off_el}; loaded only by backlash impacts, "
            "higher modes)",
        ),
        (
            "energy residual / work",
            (0.0, 0.0),
            f"{res.energy_error:.2e} (dt), {half.energy_error:.2e} (dt/2)",
        ),
    ]
    try:
        per_s, dt6, steps6, dev6 = six_dof_cost(train, res)
        rows.append(
            (
                "6-DOF start-up, per simulated s",
                per_s,
                f"modal RK4, dt {dt6:.3g} s ({steps6} steps in {SIX_DOF_INTERVAL:g} s); "
                f"{T_END:g} s would take ~{per_s[0] * T_END:.0f} s wall, "
                f"{per_s[1] * T_END / t_run[1]:.0f}x the torsional run's CPU time; speeds "
                f"within {dev6:.3g} rpm of the torsional run (backlash rattle)",
            )
        )
    except Exception as exc:  # report, do not hide, a failure of the comparison run
        rows.append(("6-DOF comparison", (float("nan"),) * 2, f"failed: {exc}"))
    print(f"{'step':<36} {'wall s':>8} {'CPU s':>8}  notes")
    print("-" * 100)
    for name, t, note in rows:
        print(f"{name:<36} {t[0]:>8.3f} {t[1]:>8.3f}  {note}")
    print()
    print(res.table())


if __name__ == "__main__":
    main()
