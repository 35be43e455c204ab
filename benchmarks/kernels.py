"""Time of the compiled transient kernels: each integrator's first call (numba compiles it, or
loads it from its cache) and a second call of the same run (the compiled speed).

    python benchmarks/kernels.py            # numba's cache as configured (warm after one run)
    python benchmarks/kernels.py --cold     # a fresh, empty numba cache: the compile times
    python benchmarks/kernels.py --only flagship_rk4 torsional_startup

Cases: the SPEC 6.1 flagship by RK4 on the full model and by the classical modal RK4, its
backlash case 15 by the exponential modal scheme (contact changes located), the synchronous
motor start-up of examples/motor_gearbox_compressor.toml through the coupled 6-DOF transient
(drive laws) and through the torsional transient. Prints a table (seconds) with the machine.
To compare two trees, run the script once with each on PYTHONPATH (the numbers of one machine
at one time: quote ratios, the machine may be shared).
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

from _machine import cpu_name
from kernel_results import BACKLASH  # SPEC 6.1 case 15 with backlash

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"


def _cases():
    from gearrotor import load_model
    from gearrotor.analyses.torsional import torsional_transient
    from gearrotor.analyses.transient import RK4, ModalRK4, transient

    flagship = load_model(EX / "unity_gearbox.toml")
    backlash = load_model(EX / "unity_gearbox.toml", BACKLASH)
    motor = load_model(EX / "motor_gearbox_compressor.toml")
    return {
        "flagship_rk4": lambda: transient(flagship, t_end=0.02, integrator=RK4(dt=8.8e-6)),
        "flagship_modal": lambda: transient(flagship, t_end=0.5, integrator=ModalRK4()),
        "backlash_exp": lambda: transient(backlash, t_end=0.2, integrator=ModalRK4()),
        "startup_six_dof": lambda: transient(
            motor, t_end=0.2, integrator=ModalRK4(), initial="rest"
        ),
        "torsional_startup": lambda: torsional_transient(motor, t_end=20.0),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cold", action="store_true", help="a fresh, empty numba cache")
    ap.add_argument("--only", nargs="*", help="these cases only")
    args = ap.parse_args()
    if args.cold:  # before gearrotor is imported: its modules point numba's cache here
        os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="numba-cold-")
    import numba

    cases = _cases()
    names = args.only or list(cases)
    print(
        f"{cpu_name()} · "
        f"{os.cpu_count()} CPUs · Python {platform.python_version()} · numba {numba.__version__}"
        f" · cache {'cold' if args.cold else 'as configured'}"
    )
    print(f"{'case':<20} {'first call':>11} {'second call':>12}")
    for name in names:
        times = []
        for _ in range(2):
            t0 = time.perf_counter()
            cases[name]()
            times.append(time.perf_counter() - t0)
        print(f"{name:<20} {times[0]:>11.3f} {times[1]:>12.3f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
