"""Benchmark: how the cost of each analysis grows with the model (issue 16).

Trains of 2, 4, 8 and 16 shafts in a row, each meshing with the next at mid-span (the SPEC 6.1
shaft, gear and bearings, unity ratio, alternating spin), with 20 to 160 elements per shaft.
For each train it times

* ``modal dense``: every damped eigenvalue by dense QR (``modal(method="dense")``);
* ``modal sparse``: the modes below 80,000 cpm by shift-invert Arnoldi;
* ``campbell``: 10 speeds 0–12,000 rpm, modes below 80,000 cpm (the default method);
* ``unbalance``: a 50-speed unbalance sweep (sparse LU per speed);
* ``transient``: 0.2 s of the modal transient (``ModalRK4()`` defaults, setup included, the
  kernels compiled beforehand),

prints time against DOF, the exponent p of a least-squares fit ``t ∝ DOF^p`` per analysis over
the models it ran on and per number of shafts (a fixed number of wanted modes: every shaft adds
its modes below 80,000 cpm, so over all the models the wanted modes grow with the DOFs), and
the dense/sparse crossover (the DOF above which the sparse
eigensolver is faster, interpolated in log-log). Analyses whose cost would exceed a few minutes
are skipped above a DOF cap (printed).

    python benchmarks/scaling.py [--quick] [--json FILE]

``--quick``: 2, 4 and 8 shafts, 20 and 40 elements, capped lower (about a minute idle).
``--busy``: every timing next to one busy process (``python -c "while True: pass"``). Runs in
the environment it is started in (gearrotor's default: one BLAS thread at these sizes, more
only for dense solves from order 1000 on free cores; docs/performance.md).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
from _machine import busy_neighbour, cpu_name, environment

from gearrotor.analyses import campbell, modal
from gearrotor.analyses.lateral.modal import SPARSE_FROM, auto_method
from gearrotor.analyses.lateral.unbalance import unbalance_response
from gearrotor.analyses.transient import ModalRK4, transient
from gearrotor.assembly import assemble
from gearrotor.io.model_file import model_from_dict

# the trains (shared with tests/transient/test_transient_large.py)
sys.path.append(str(Path(__file__).resolve().parents[1] / "tests"))
from helpers import chain  # noqa: E402

RPM = np.pi / 30
FMAX = 80000 * RPM
TASKS = ("modal dense", "modal sparse", "campbell", "unbalance", "transient")


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def fit_exponent(dofs, times) -> float:
    """Least-squares slope of log t against log DOF (nan with fewer than 2 distinct DOF)."""
    x, y = np.log(np.asarray(dofs, float)), np.log(np.asarray(times, float))
    if len(np.unique(x)) < 2:
        return float("nan")
    return float(np.polyfit(x, y, 1)[0])


def crossover(dofs, dense, sparse) -> float | None:
    """DOF at which sparse becomes faster than dense (log-log interpolation between the two
    measured models that bracket it), None when it does not within the measured range."""
    pts = sorted(
        (d, a, b)
        for d, a, b in zip(dofs, dense, sparse, strict=True)
        if np.isfinite(a) and np.isfinite(b)
    )
    for (d0, a0, b0), (d1, a1, b1) in zip(pts, pts[1:], strict=False):
        r0, r1 = np.log(a0 / b0), np.log(a1 / b1)
        if r0 < 0 <= r1:
            f = -r0 / (r1 - r0)
            return float(np.exp(np.log(d0) + f * (np.log(d1) - np.log(d0))))
    if pts and pts[0][1] >= pts[0][2]:
        return float(pts[0][0])  # sparse already faster on the smallest model
    return None


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer, smaller models (~1 min)")
    ap.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    ap.add_argument("--busy", action="store_true", help="next to one busy process")
    args = ap.parse_args()
    shafts = (2, 4, 8) if args.quick else (2, 4, 8, 16)
    elements = (20, 40) if args.quick else (20, 40, 80, 160)
    # DOF above which an analysis is skipped (dense eigen is O(n³) in memory-bound LAPACK:
    # 58 s at 1968 DOF, over a minute above 2000; the modal transient does a dense generalised
    # eigen solve of the whole model in setup)
    cap = {
        "modal dense": 1000 if args.quick else 2000,
        "modal sparse": 20000,
        "campbell": 4000 if args.quick else 8000,
        "unbalance": 20000,
        "transient": 2000 if args.quick else 4000,
    }
    print(
        f"machine: {platform.machine()} {cpu_name()}, {os.cpu_count()} cores, python "
        f"{platform.python_version()}, numpy {np.__version__}; {environment()}; load average "
        f"{os.getloadavg()[0]:.2f}" + ("; next to one busy process" if args.busy else "")
    )
    # compile the transient kernels outside the timings
    transient(
        model_from_dict(chain(2, 4, unbalance_every_shaft=True)), t_end=1e-3, integrator=ModalRK4()
    )
    rows = []
    print(
        "skipped above: "
        + ", ".join(f"{t} {c} DOF" for t, c in cap.items())
        + " (the dense eigen solve takes over a minute above 2000 DOF)"
    )
    head = (
        f"{'shafts':>6} {'elem':>5} {'DOF':>6}"
        + "".join(f"{t:>14}" for t in TASKS)
        + f"{'auto':>8}{'load':>6}"
    )
    print(head)
    print("-" * len(head))
    with busy_neighbour(args.busy):
        _rows(shafts, elements, cap, rows)
    _summary(rows, cap, args)


def _rows(shafts, elements, cap, rows) -> None:
    for ns in shafts:
        for ne in elements:
            train = model_from_dict(chain(ns, ne, unbalance_every_shaft=True))
            asm = assemble(train)
            n = asm.n_dof
            speeds = np.linspace(0, 12000, 10) * RPM
            jobs = {
                "modal dense": lambda asm=asm: modal(asm, method="dense"),
                "modal sparse": lambda asm=asm: modal(asm, method="sparse", max_frequency=FMAX),
                "campbell": lambda asm=asm, s=speeds: campbell(asm, speeds=s, max_frequency=FMAX),
                "unbalance": lambda asm=asm: unbalance_response(
                    asm, speeds=np.linspace(500, 12000, 50) * RPM
                ),
                "transient": lambda train=train: transient(train, t_end=0.2),
            }
            row = {"shafts": ns, "elements": ne, "dof": n}
            for task in TASKS:
                row[task] = _timed(jobs[task]) if n <= cap[task] else float("nan")
            rows.append(row)
            print(
                f"{ns:>6} {ne:>5} {n:>6}"
                + "".join(
                    f"{row[t]:>14.3f}" if np.isfinite(row[t]) else f"{'(skipped)':>14}"
                    for t in TASKS
                )
                + f"{auto_method(n, FMAX):>8}{os.getloadavg()[0]:>6.1f}",
                flush=True,
            )


def _summary(rows, cap, args) -> None:
    print()
    print("fitted exponent p of t ∝ DOF^p (models the analysis ran on):")
    fits = {}
    for task in TASKS:
        ok = [r for r in rows if np.isfinite(r[task])]
        fits[task] = fit_exponent([r["dof"] for r in ok], [r[task] for r in ok])
        print(
            f"  {task:<14} p = {fits[task]:.2f}  ({len(ok)} models, up to "
            f"{max((r['dof'] for r in ok), default=0)} DOF; cap {cap[task]} DOF)"
        )
    # at a fixed number of shafts the modes below FMAX (the wanted ones, the transient's basis)
    # stay the same while the elements multiply the DOFs: the cost of the solvers themselves
    print(
        "at a fixed number of wanted modes (each train refined: 20 -> "
        f"{max(r['elements'] for r in rows)} elements per shaft), p per shaft count:"
    )
    along = {}
    for task in TASKS:
        parts = []
        for ns in sorted({r["shafts"] for r in rows}):
            ok = [r for r in rows if r["shafts"] == ns and np.isfinite(r[task])]
            if len(ok) >= 2:
                p = fit_exponent([r["dof"] for r in ok], [r[task] for r in ok])
                along.setdefault(task, {})[ns] = p
                parts.append(f"{ns} shafts {p:.2f}")
        print(f"  {task:<14} " + (", ".join(parts) or "(too few models)"))
    fits["at_fixed_modes"] = along
    x = crossover(
        [r["dof"] for r in rows],
        [r["modal dense"] for r in rows],
        [r["modal sparse"] for r in rows],
    )
    print(
        "dense/sparse crossover: "
        + (
            "sparse not faster within the measured range"
            if x is None
            else f"sparse faster from the smallest model on ({x:.0f} DOF)"
            if x == min(r["dof"] for r in rows)
            else f"sparse faster above ~{x:.0f} DOF"
        )
        + f"; modal(method='auto', max_frequency=...) goes sparse from {SPARSE_FROM} DOF"
    )
    if args.json:
        args.json.write_text(
            json.dumps({"rows": rows, "exponents": fits, "crossover": x}, indent=1)
        )


if __name__ == "__main__":
    main()
