"""Benchmark: build + damped eigenvalues of the geared flagship (252 DOF) and a 60-speed Campbell.

Run: ``python3 benchmarks/modal.py``. Prints a table; goals (issue 2): eigen solve ≤ 0.3 s,
Campbell ≤ 10 s on a 2-core machine, with no loss of accuracy (the sparse shift-invert
eigenvalues are compared against the dense ones).
"""

from __future__ import annotations

import os
import platform
import time
from pathlib import Path

import numpy as np

from gearrotor.analyses import campbell, modal
from gearrotor.assembly import assemble
from gearrotor.io import load_model

RPM = np.pi / 30
MODEL = Path(__file__).resolve().parents[1] / "examples" / "unity_gearbox.toml"


def best_of(fn, n=5):
    times = []
    out = None
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), float(np.median(times)), out


def main() -> None:
    print(f"machine: {platform.machine()} {platform.processor() or ''} cores={os.cpu_count()} "
          f"python={platform.python_version()} numpy={np.__version__}")
    t_build, _, train = best_of(lambda: load_model(MODEL))
    t_asm, _, asm = best_of(lambda: assemble(train))
    t_dense, med_dense, rd = best_of(lambda: modal(asm, method="dense"))
    fmax = 80000 * RPM
    t_sparse, med_sparse, rs = best_of(lambda: modal(asm, method="sparse", max_frequency=fmax))
    rd_low = modal(asm, method="dense", max_frequency=fmax)
    err = float(np.max(np.abs(rs.eigenvalues - rd_low.eigenvalues) / np.abs(rd_low.eigenvalues)))
    speeds = np.linspace(0, 12000, 60) * RPM
    t_camp, _, cres = best_of(lambda: campbell(asm, speeds=speeds, max_frequency=fmax), n=2)
    t_camp_d, _, cres_d = best_of(
        lambda: campbell(asm, speeds=speeds, max_frequency=fmax, method="dense"), n=1)
    cerr = float(np.max(np.abs(np.sort(cres.damped_frequency, axis=1)
                               - np.sort(cres_d.damped_frequency, axis=1))
                        / np.sort(cres_d.damped_frequency, axis=1)))
    rows = [
        ("load + validate model file", t_build, ""),
        ("assemble (252 DOF)", t_asm, ""),
        ("damped eigen, dense (all 504)", t_dense, f"median {med_dense:.3f} s"),
        ("damped eigen, sparse (<80k cpm)", t_sparse,
         f"median {med_sparse:.3f} s, max rel dev vs dense {err:.1e}"),
        ("build + dense eigen", t_build + t_asm + t_dense, "goal <= 0.3 s"),
        ("Campbell 60 speeds, sparse", t_camp,
         f"goal <= 10 s, {cres.damped_frequency.shape[1]} modes, {len(cres.crossings)} crossings"),
        ("Campbell 60 speeds, dense", t_camp_d, f"max rel dev sparse vs dense {cerr:.1e}"),
    ]
    print(f"{'step':<34} {'best s':>8}  notes")
    print("-" * 80)
    for name, t, note in rows:
        print(f"{name:<34} {t:>8.3f}  {note}")


if __name__ == "__main__":
    main()
