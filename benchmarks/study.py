"""Benchmark: the SPEC 6.1 27-row transient matrix (examples/unity_gearbox_study.toml) as a study.

Runs the study into fresh folders on local processes and/or a Dask LocalCluster (the same code
path: :func:`gearrotor.studies.run_study`), prints the machine, a table of the runs (wall time,
step, modes, 1x at the gear probe, speed fluctuation, contact loss) and the totals, checks that
both back-ends give identical metrics, and ends with one JSON line. Each run uses the modal
integrator (ModalRK4 defaults), which matches RK4 at 8.8e-6 s within 0.5 % in the 1x amplitudes
and the speed fluctuation (benchmarks/transient_app2.py); RK4 at the dissertation's 9e-6 s is
unstable for this model. Goal: the 27 rows in ≤ 2 minutes on a 2-core machine.

    python benchmarks/study.py [--t-end 3.0] [--backend local|dask|both] [--workers N]
                               [--folder DIR]

The wall time includes starting the workers and loading the compiled kernels (numba's on-disk
cache; the first run on a machine also compiles them: run twice for the steady figure).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
from _machine import cpu_name

from gearrotor.studies import collect, load_study, run_study

STUDY = Path(__file__).resolve().parents[1] / "examples" / "unity_gearbox_study.toml"


def _run(study, backend: str, workers: int | None) -> tuple[dict, object]:
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    summary = run_study(
        study, scheduler="local" if backend == "dask" else None, workers=workers, progress=True
    )
    wall = time.perf_counter() - t0
    return {
        "backend": summary.backend,
        "workers": summary.workers,
        "cases": summary.n_cases,
        "runs": summary.executed,
        "failed": len(summary.failed),
        "wall_s": wall,
        "load_before": load0,
    }, collect(study, write=False)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=3.0, help="s, end time of every run")
    ap.add_argument("--backend", choices=["local", "dask", "both"], default="both")
    ap.add_argument("--workers", type=int, default=None, help="default: all cores")
    ap.add_argument("--folder", type=Path, default=None, help="default: a temporary folder")
    args = ap.parse_args()
    base = load_study(STUDY)
    if args.t_end != 3.0:
        analysis = base.analysis.model_copy(update={"t_end": args.t_end})
        outputs = base.outputs.model_copy(update={"window": min(base.window, 0.5 * args.t_end)})
        base = dataclasses.replace(base, analysis=analysis, outputs=outputs)
    root = args.folder or Path(tempfile.mkdtemp(prefix="gearrotor-study-bench-"))
    print(
        f"machine: {platform.machine()} {cpu_name()}, {os.cpu_count()} cores, python "
        f"{platform.python_version()}, numpy {np.__version__}; load average before: "
        f"{os.getloadavg()[0]:.2f}"
    )
    print(
        f"study: {base.name}, {len(base.cases)} rows, t_end = {base.analysis.t_end} s, "
        f"integrator {base.analysis.integrator}"
    )
    rows, results = [], {}
    for backend in ("local", "dask") if args.backend == "both" else (args.backend,):
        folder = root / backend
        shutil.rmtree(folder, ignore_errors=True)
        st = dataclasses.replace(base, folder=folder)
        row, ds = _run(st, backend, args.workers)
        rows.append(row)
        results[backend] = ds
    ds = next(iter(results.values()))
    print()
    print(
        f"{'case':>4} {'wall s':>7} {'1x µm':>8} {'2x µm':>7} {'dfl rpm':>8} {'F N':>8}"
        f" {'loss %':>7}  parameters"
    )
    for i in range(ds.sizes["case"]):
        c = ds.isel(case=i)
        if str(c["status"].values) != "done":
            print(f"{i:>4} {'failed':>7}  {c['label'].values}: {c['error'].values}")
            continue
        wall = float(c["wall_time"])
        print(
            f"{i:>4} {wall:>7.1f} {float(c['amp_1x'].max()) * 1e6:>8.2f}"
            f" {float(c['amp_2x'].max()) * 1e6:>7.3f} {float(c['speed_fluctuation'].max()):>8.2f}"
            f" {float(c['peak_mesh_force'].max()):>8.1f}"
            f" {100 * float(c['contact_loss_fraction'].max()):>7.2f}  {c['label'].values}"
        )
    if "solver_dt" in ds:
        dt = ds["solver_dt"].values
        line = f"modal step: {np.nanmin(dt):.3g} .. {np.nanmax(dt):.3g} s"
        if "solver_harmonic_error" in ds:
            line += (
                f"; harmonic (1x) error of the reduction vs the full model: "
                f"max {np.nanmax(ds['solver_harmonic_error'].values):.2%}"
            )
        print(line)
    print()
    print(f"{'backend':<12}{'workers':>8}{'cases':>7}{'runs':>6}{'failed':>8}{'wall (s)':>10}")
    for r in rows:
        print(
            f"{r['backend']:<12}{r['workers']:>8}{r['cases']:>7}{r['runs']:>6}{r['failed']:>8}"
            f"{r['wall_s']:>10.1f}"
        )
    if len(results) == 2:
        a, b = results["local"], results["dask"]
        differ = [
            v
            for v in a.data_vars
            if v != "wall_time"
            and np.issubdtype(a[v].dtype, np.number)
            and not np.array_equal(a[v].values, b[v].values, equal_nan=True)
        ]
        same = not differ
        print(f"local and Dask metrics identical: {same} {differ or ''}")
    print(json.dumps({"rows": rows, "folder": str(root)}))


if __name__ == "__main__":
    main()
