"""Benchmark: 20 s synchronous-motor start-up of examples/motor_gearbox_compressor.toml.

Run: ``python3 benchmarks/torsional.py``. Prints a table; goal (issue 12): the 20 s start-up
with the torsional model in ≤ 5 s on a 2-core machine. The accuracy check halves the step and
compares the peak shaft torque of every element and the energy balance; the run is timed after
a short warm-up run (numba compiles the kernels once and caches them).

Beside it, the coupled 6-DOF transient (``gearrotor.analyses.transient``, modal RK4) of the same
train is timed over a short interval with the motor's rated torque and the load as constant
external torques, and its cost is extrapolated to 20 s: the drive laws reach the 6-DOF model in
phase 2 of issue 12, so the same start-up cannot yet run there.
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
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def six_dof_cost(train, interval: float = 0.02) -> tuple[float, float, int]:
    """Seconds of wall time per simulated second of the coupled 6-DOF transient (modal RK4),
    with the motor's rated torque and the rated load as constant external torques."""
    from gearrotor.analyses.transient import ModalRK4, Save, transient
    from gearrotor.io.model_file import model_from_dict

    drive = train.torsional.drives[0]
    load = train.torsional.loads[0]
    data = train.model_dump()
    data.pop("torsional")
    data["torques"] = [
        {"shaft": drive.shaft, "node": drive.node, "value": drive.rated_torque},
        {"shaft": load.shaft, "node": load.node, "value": -load.torque},  # turns about −z
    ]
    six = model_from_dict(data)
    run = lambda t: transient(six, t_end=t, integrator=ModalRK4(), save=Save(dt=1e-3))  # noqa: E731
    run(interval / 10)  # compile
    wall, res = timed(lambda: run(interval))
    return wall / interval, float(res.stats.dt), int(res.stats.steps)


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
            0.0,
            f"max rel. change {off_dev:.2e} ({off_el}; loaded only by backlash impacts, "
            "higher modes)",
        ),
        (
            "energy residual / work",
            0.0,
            f"{res.energy_error:.2e} (dt), {half.energy_error:.2e} (dt/2)",
        ),
    ]
    try:
        per_s, dt6, steps6 = six_dof_cost(train)
        rows.append(
            (
                "6-DOF modal RK4, per simulated s",
                per_s,
                f"dt {dt6:.3g} s ({steps6} steps in 0.02 s); {T_END:g} s would take "
                f"~{per_s * T_END:.0f} s (constant torques; drive laws in phase 2)",
            )
        )
    except Exception as exc:  # report, do not hide, a failure of the comparison run
        rows.append(("6-DOF comparison", float("nan"), f"failed: {exc}"))
    print(f"{'step':<36} {'s':>8}  notes")
    print("-" * 100)
    for name, t, note in rows:
        print(f"{name:<36} {t:>8.3f}  {note}")
    print()
    print(res.table())


if __name__ == "__main__":
    main()
