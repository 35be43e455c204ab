"""Benchmark: BLAS/LAPACK threads against problem size, idle and next to one busy process.

Run: ``python3 benchmarks/threads.py`` (``--quick``: fewer sizes and repeats). For each dense
operation the analyses use (the non-symmetric eigen solve of the state matrix, an LU factor
and solve, a matrix product), the time per call with 1 and with every available thread, first
on the machine as it is, then with one busy neighbour (``python -c "while True: pass"``,
started and stopped by this script). Prints a table, the machine and its load, and the size
from which more threads pay (the crossover that :mod:`gearrotor.threads` uses, documented in
docs/performance.md).

Threads are set with threadpoolctl on every BLAS library loaded (numpy's and SciPy's OpenBLAS
are separate libraries in the wheels), the way :func:`gearrotor.threads.limit` does.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import scipy.linalg as la
from _machine import busy_neighbour, cpu_name
from threadpoolctl import ThreadpoolController


def _time(fn, repeat: int) -> float:
    fn()  # warm-up (threads started, pages touched)
    best = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best.append(time.perf_counter() - t0)
    return float(np.median(best))


def _ops(n: int, rng):
    a = rng.standard_normal((n, n))
    b = rng.standard_normal((n, n))
    spd = a @ a.T + n * np.eye(n)
    return {
        "eig": lambda: la.eig(a, check_finite=False),
        "lu+solve": lambda: la.lu_solve(la.lu_factor(a, check_finite=False), b[:, :10]),
        "cholesky": lambda: la.cho_factor(spd, check_finite=False),
        "matmul": lambda: a @ b,
    }


def _measure(sizes, threads, repeat, ctl) -> dict:
    rng = np.random.default_rng(0)
    out = {}
    for n in sizes:
        ops = _ops(n, rng)
        for name, fn in ops.items():
            if name == "eig" and n > 2000:
                continue
            for t in threads:
                with ctl.limit(limits=t):
                    r = repeat if n <= 800 else max(2, repeat // 2)
                    out[(name, n, t)] = _time(fn, r)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    sizes = [200, 400, 800, 1600] if args.quick else [100, 200, 400, 600, 800, 1200, 1600, 2400]
    repeat = 3 if args.quick else 5
    cores = len(os.sched_getaffinity(0))
    threads = sorted({1, cores})
    ctl = ThreadpoolController()
    libs = ", ".join(
        f"{lib['internal_api']} {lib['version']} ({lib['threading_layer']})"
        for lib in ctl.info()
        if lib["user_api"] == "blas"
    )
    print(f"machine: {cpu_name()}, {cores} cores available; BLAS: {libs}")
    print(f"load before: {os.getloadavg()[0]:.2f}")
    idle = _measure(sizes, threads, repeat, ctl)
    load_idle = os.getloadavg()[0]
    with busy_neighbour():
        busy = _measure(sizes, threads, repeat, ctl)
    load_busy = os.getloadavg()[0]
    print(f"load after the idle rows: {load_idle:.2f}; after the busy rows: {load_busy:.2f}")
    print()
    hdr = " | ".join(f"{t} thr" for t in threads)
    print(f"| op | n | idle: {hdr} | idle speed-up | busy neighbour: {hdr} | busy speed-up |")
    print("|---|---|" + "---|" * (2 * len(threads) + 2))
    for name in ("eig", "lu+solve", "cholesky", "matmul"):
        for n in sizes:
            if (name, n, 1) not in idle:
                continue
            ti = [idle[(name, n, t)] for t in threads]
            tb = [busy[(name, n, t)] for t in threads]
            print(
                f"| {name} | {n} | "
                + " | ".join(f"{x:.4f}" for x in ti)
                + f" | {ti[0] / ti[-1]:.2f} | "
                + " | ".join(f"{x:.4f}" for x in tb)
                + f" | {tb[0] / tb[-1]:.2f} |"
            )
    print()
    top = threads[-1]
    for name in ("eig", "lu+solve", "cholesky", "matmul"):
        ns = [n for n in sizes if (name, n, 1) in idle]
        pays = [n for n in ns if idle[(name, n, 1)] > 1.1 * idle[(name, n, top)]]
        print(
            f"{name}: {top} threads > 10 % faster than 1 (idle) from n = "
            f"{pays[0] if pays else 'never'}; speed-up next to a busy process: "
            + ", ".join(f"{busy[(name, n, 1)] / busy[(name, n, top)]:.2f}x" for n in ns)
        )


if __name__ == "__main__":
    main()
