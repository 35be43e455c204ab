"""Benchmark: the SPEC 6.1 gearbox, Ka/Kg = 0.2, c = 1.592, 5 Fourier terms, 0–3.0 s.

RK4 reference on the full model against the modal method (ModalRK4 defaults: classical RK4
without backlash) and its exponential scheme (``exact_linear=True``: oscillators exact, 4 steps
per mesh period; the default with backlash, benchmarks/backlash.py). Prints the
machine, wall times (JIT compilation excluded by a warm-up), the fast method's deviation from
the reference in the 1x amplitudes of the gear nodes (x and y, last 0.5 s) and in the speed
fluctuation amplitude (half peak-to-peak about the linear trend, last 0.5 s), and ends with one
JSON line, and the modal run again next to one busy process (``python -c "while True:
pass"``). Runs in the environment it is started in (gearrotor's default: one BLAS thread for
these sizes; the kernels are serial).

    python benchmarks/transient_app2.py [--t-end 3.0] [--rk4-dt 8.8e-6]

The dissertation's RK4 step, 9e-6 s, lies outside RK4's stability region for this 20-element
Timoshenko model (highest mode 50.4 kHz: ω·Δt = 2.85 > 2√2); it is tried first and reported.
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

import numpy as np
from _machine import busy_neighbour, cpu_name, environment

from gearrotor import load_model
from gearrotor.analyses.transient import RK4, ModalRK4, transient
from gearrotor.errors import SolverError

MODEL = Path(__file__).resolve().parents[1] / "examples" / "unity_gearbox.toml"
CASE = {
    "meshes[0].variation.ka_ratio": "0.2",
    "meshes[0].variation.contact_ratio": "1.592",
    "meshes[0].variation.terms": "5",
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=3.0)
    ap.add_argument("--rk4-dt", type=float, default=8.8e-6)
    args = ap.parse_args()
    train = load_model(MODEL, CASE)
    print(
        f"machine: {platform.machine()} {cpu_name()}, python {platform.python_version()}, "
        f"numpy {np.__version__}; {environment()}"
    )
    # warm-up: compile the kernels (cached on disk afterwards)
    transient(train, t_end=1e-3, integrator=RK4(dt=args.rk4_dt))
    transient(train, t_end=1e-3, integrator=ModalRK4())
    transient(train, t_end=1e-3, integrator=ModalRK4(exact_linear=True))
    try:
        transient(train, t_end=1e-3, integrator=RK4(dt=9e-6))
    except SolverError as exc:
        print(f"RK4 at 9e-6 s: {exc}")
    t0 = time.perf_counter()
    ref = transient(train, t_end=args.t_end, integrator=RK4(dt=args.rk4_dt))
    t1 = time.perf_counter()
    fast = transient(train, t_end=args.t_end, integrator=ModalRK4())
    t2 = time.perf_counter()
    # the exponential modal scheme (oscillators exact, 4 steps per mesh period; issue 16),
    # opt-in without backlash
    expo = transient(train, t_end=args.t_end, integrator=ModalRK4(exact_linear=True))
    t3 = time.perf_counter()
    with busy_neighbour():
        busy = transient(train, t_end=args.t_end, integrator=ModalRK4())
    t4 = time.perf_counter()
    a_ref, a_fast = ref.amplitude_1x(0.5), fast.amplitude_1x(0.5)
    f_ref, f_fast = ref.speed_fluctuation(0.5), fast.speed_fluctuation(0.5)
    dev_1x = max(abs(a_fast[n][d] / a_ref[n][d] - 1) for n in a_ref for d in ("x", "y"))
    dev_speed = float(np.max(np.abs(f_fast / f_ref - 1)))
    s = fast.stats
    print(
        f"{'method':<12}{'dt (s)':>11}{'steps':>9}{'DOF/modes':>11}{'integrate (s)':>15}"
        f"{'whole call (s)':>16}"
    )
    print(
        f"{'rk4':<12}{ref.stats.dt:>11.3g}{ref.stats.steps:>9}{ref.stats.n_dof:>11}"
        f"{ref.stats.wall_time_s:>15.2f}{t1 - t0:>16.2f}"
    )
    print(
        f"{'modal-rk4':<12}{s.dt:>11.3g}{s.steps:>9}{s.n_modes:>11}{s.wall_time_s:>15.2f}"
        f"{t2 - t1:>16.2f}"
    )
    e = expo.stats
    print(
        f"{'modal-exp':<12}{e.dt:>11.3g}{e.steps:>9}{e.n_modes:>11}{e.wall_time_s:>15.2f}"
        f"{t3 - t2:>16.2f}"
    )
    b = busy.stats
    print(
        f"{'modal, busy':<12}{b.dt:>11.3g}{b.steps:>9}{b.n_modes:>11}{b.wall_time_s:>15.2f}"
        f"{t4 - t3:>16.2f}   (next to one busy process)"
    )
    a_exp, f_exp = expo.amplitude_1x(0.5), expo.speed_fluctuation(0.5)
    dev_1x_exp = max(abs(a_exp[n][d] / a_ref[n][d] - 1) for n in a_ref for d in ("x", "y"))
    dev_speed_exp = float(np.max(np.abs(f_exp / f_ref - 1)))
    print(
        f"modal-exp (exact_linear=True): 1x within {100 * dev_1x_exp:.2f} %, speed fluctuation "
        f"within {100 * dev_speed_exp:.2f} % of rk4"
    )
    print(
        f"modal: cut-off {s.cutoff_hz:.0f} Hz, highest kept mode {s.highest_mode_hz:.0f} Hz, "
        f"1x harmonic check {100 * s.harmonic_error:.2f} %; wall times in the JSON line are "
        "whole calls (setup, integration, outputs)"
    )
    print(f"{'node':<14}{'dir':>4}{'rk4 1x µm':>12}{'modal 1x µm':>13}{'dev %':>8}")
    for n in a_ref:
        for d in ("x", "y"):
            print(
                f"{n:<14}{d:>4}{a_ref[n][d] * 1e6:>12.3f}{a_fast[n][d] * 1e6:>13.3f}"
                f"{100 * (a_fast[n][d] / a_ref[n][d] - 1):>8.3f}"
            )
    for k, name in enumerate(ref.shaft_names):
        print(
            f"{name}: speed fluctuation rk4 {f_ref[k] * 30 / np.pi:.3f} rpm, modal "
            f"{f_fast[k] * 30 / np.pi:.3f} rpm ({100 * (f_fast[k] / f_ref[k] - 1):.3f} %)"
        )
    print(
        json.dumps(
            {
                "fast_wall_s": round(t2 - t1, 3),
                "rk4_wall_s": round(t1 - t0, 3),
                "dev_1x": float(dev_1x),
                "dev_speed": dev_speed,
                "exp_wall_s": round(t3 - t2, 3),
                "exp_dev_1x": float(dev_1x_exp),
                "exp_dev_speed": dev_speed_exp,
                "fast_busy_wall_s": round(t4 - t3, 3),
            }
        )
    )


if __name__ == "__main__":
    main()
