"""Benchmark: Floquet exponents of the compressor gearbox (SPEC 6.3) at Ka/Kg = 0.75.

Times the two transition-matrix schemes of :mod:`gearrotor.analyses.lateral.floquet` on the same
reduced model (102 modes, 204 states): the Lawson RK4 in the mean system's eigen-coordinates
(the default) and 4th-order Magnus steps with a matrix exponential per step (the fallback), at
the step count the default converges to, and prints the largest multiplier difference.

    python benchmarks/floquet.py [--repeat 3]

Runs in the environment it is started in (gearrotor's default: one BLAS thread at these sizes).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from gearrotor.analyses.lateral.floquet import floquet  # noqa: E402
from gearrotor.analyses.transient import build_system  # noqa: E402
from gearrotor.io import load_model  # noqa: E402

MODEL = Path(__file__).resolve().parents[1] / "examples" / "compressor_gearbox.toml"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeat", type=int, default=3)
    a = p.parse_args()
    ov = {f"meshes[{k}].variation.ka_ratio": "0.75" for k in (0, 1)}
    t0 = time.perf_counter()
    system = build_system(load_model(MODEL, ov))
    t_build = time.perf_counter() - t0
    best = np.inf
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        res = floquet(system)
        best = min(best, time.perf_counter() - t0)
    tm = np.inf
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        mag = floquet(system, method="magnus")
        tm = min(tm, time.perf_counter() - t0)
    d = np.abs(res.multipliers[:, None] - mag.multipliers[None, :]).min(axis=1).max()
    print(f"compressor gearbox, Ka/Kg = 0.75, {res.n_modes} modes, {res.slices} steps per period")
    print(f"{'step':<36}{'time (s)':>10}")
    print(f"{'build transient system (+bearings)':<36}{t_build:>10.3f}")
    print(f"{'Floquet, Lawson RK4 (default)':<36}{best:>10.3f}")
    print(f"{'Floquet, Magnus + expm (fallback)':<36}{tm:>10.3f}")
    print(f"ratio Magnus / Lawson: {tm / best:.1f}; largest multiplier difference {d:.1e}")
    print(f"least stable: {res.growth[0]:.3f} 1/s at {res.frequency_cpm[0]:,.0f} cpm")


if __name__ == "__main__":
    main()
