"""Benchmark: SPEC 6.1 case 15 (Ka/Kg 0.2, c 1.592, 5 terms, backlash 0.0254 mm), 0–3 s.

RK4 at 4.4e-6 s (the reference) and 8.8e-6 s against ModalRK4's default with backlash (the
exponential scheme: oscillators exact, contact changes located, 4 steps per mesh period) and
the classical modal RK4 (``exact_linear=False``: the default until issue 16's second round,
step 0.9/ω_max = 9.3e-6 s), and, for the ratio the issue asks for, the same case without
backlash (ModalRK4's default there, classical RK4 at 0.9/ω_max, and the exponential scheme).
Prints, per run, the step, the steps, the contact changes located, the largest deviation from
the backlash reference of the 1x amplitudes at the gear nodes and of the speed fluctuation
(both over the last 0.5 s, the result's ``amplitude_1x`` and ``speed_fluctuation``), the
contact-loss fraction over the run, the largest |mesh force| over the last 0.5 s against the
reference's, the wall time of the integration and its ratio to the no-backlash default run,
and the default run again next to one busy process (``python -c "while True: pass"``); ends
with one JSON line. Runs in the environment it is started in (gearrotor's default: one BLAS
thread for these sizes, docs/performance.md).

    python benchmarks/backlash.py [--t-end 3.0] [--no-rk4]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from _machine import busy_neighbour, environment

from gearrotor import load_model
from gearrotor.analyses.transient import RK4, ModalRK4, transient

MODEL = Path(__file__).resolve().parents[1] / "examples" / "unity_gearbox.toml"
CASE = {
    "meshes[0].variation.ka_ratio": "0.2",
    "meshes[0].variation.contact_ratio": "1.592",
    "meshes[0].variation.terms": "5",
    "meshes[0].backlash.value": "0.0254 mm",
}
PLAIN = {"meshes[0].backlash.value": "0 mm"}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=3.0)
    ap.add_argument("--no-rk4", action="store_true", help="skip RK4 8.8e-6 (reference kept)")
    args = ap.parse_args()
    train = load_model(MODEL, CASE)
    plain = load_model(MODEL, {**CASE, **PLAIN})
    window = min(0.5, args.t_end / 2)
    runs = [("RK4 4.4e-6 (reference)", train, RK4(dt=4.4e-6))]
    if not args.no_rk4:
        runs.append(("RK4 8.8e-6", train, RK4(dt=8.8e-6)))
    runs += [
        ("ModalRK4 default (exponential)", train, ModalRK4()),
        ("classical modal RK4", train, ModalRK4(exact_linear=False)),
        ("no backlash: default (classical)", plain, ModalRK4()),
        ("no backlash: exponential", plain, ModalRK4(exact_linear=True)),
    ]
    for _, tr, integ in runs[-4:]:
        transient(tr, t_end=1e-3, integrator=integ)  # compile the kernels
    runs.append(("ModalRK4 default, one busy process", train, ModalRK4()))
    print(environment())
    rows = []
    for name, tr, integ in runs:
        with busy_neighbour("busy" in name):
            r = transient(tr, t_end=args.t_end, integrator=integ)
        a = r.amplitude_1x(window)
        last = r.time >= r.time[-1] - window
        rows.append(
            {
                "run": name,
                "dt": r.stats.dt,
                "steps": r.stats.steps,
                "events": r.stats.contact_events or 0,
                "x1": [a[n][d] for n in a for d in ("x", "y")],
                "sf": r.speed_fluctuation(window).tolist(),
                "loss": float(r.contact_loss_fraction[0]),
                "peak": float(np.abs(r.mesh_force[last]).max()),
                "wall": r.stats.wall_time_s,
            }
        )
    ref = rows[0]
    base = next(row for row in rows if row["run"].startswith("no backlash: default"))
    print(
        f"{'run':<34}{'dt s':>10}{'steps':>8}{'events':>8}{'1x':>8}{'speed fl.':>11}"
        f"{'loss':>8}{'peak F':>9}{'wall s':>8}{'ratio':>7}"
    )
    for row in rows:
        d1 = np.max(np.abs(np.array(row["x1"]) / np.array(ref["x1"]) - 1))
        ds = np.max(np.abs(np.array(row["sf"]) / np.array(ref["sf"]) - 1))
        dp = row["peak"] / ref["peak"] - 1
        print(
            f"{row['run']:<34}{row['dt']:>10.3g}{row['steps']:>8}{row['events']:>8}"
            f"{100 * d1:>7.2f}%{100 * ds:>10.2f}%{100 * row['loss']:>7.1f}%{100 * dp:>+8.1f}%"
            f"{row['wall']:>8.2f}{row['wall'] / base['wall']:>7.2f}"
        )
    print(json.dumps(rows))


if __name__ == "__main__":
    main()
