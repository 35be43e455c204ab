"""Benchmark: the SPEC 6.1 27-row transient matrix (examples/unity_gearbox_study.toml) as a study.

Runs the study into fresh folders on local processes and/or a Dask LocalCluster (the same code
path: :func:`gearrotor.studies.run_study`), prints the machine, a table of the runs (wall time,
step, modes, 1x at the gear probe, speed fluctuation, contact loss) and the totals, checks that
both back-ends give identical metrics, and ends with one JSON line. Each run uses the modal
integrator (ModalRK4 defaults), which matches RK4 at 8.8e-6 s within 0.5 % in the 1x amplitudes
and the speed fluctuation (benchmarks/transient_app2.py); RK4 at the dissertation's 9e-6 s is
unstable for this model. Goal: the 27 rows in ≤ 2 minutes on a 2-core machine.

    python benchmarks/study.py [--t-end 3.0] [--backend local|dask|both] [--workers N]
                               [--folder DIR [--reuse]] [--report]

The wall time includes starting the workers and loading the compiled kernels (numba's on-disk
cache; the first run on a machine also compiles them: run twice for the steady figure).

``--report`` then times ``study report`` on the finished study (the first back-end's folder):
its parts in this process (the collection anew and from an up-to-date ``results.nc``, one case
file read and checked, a trend figure, a spectra figure of 7 cases) and the whole command as a
user runs it, the full report and a group report (``--cases 1,4-6 --probes gear1_y
--per-figure 8``), with the trend figures drawn (an empty results cache) and found in the cache.
With ``--folder DIR --reuse`` of a finished study (``DIR/local``) the run only finds every
case done.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import shutil
import subprocess
import sys
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
        "folder": study.folder.name,
    }, collect(study, write=False)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=3.0, help="s, end time of every run")
    ap.add_argument("--backend", choices=["local", "dask", "both"], default="both")
    ap.add_argument("--workers", type=int, default=None, help="default: all cores")
    ap.add_argument("--folder", type=Path, default=None, help="default: a temporary folder")
    ap.add_argument("--report", action="store_true", help="then time 'study report'")
    ap.add_argument(
        "--reuse", action="store_true", help="keep the finished cases found in --folder"
    )
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
        if not args.reuse:
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
    report = _report_times(base, root / rows[0]["folder"], root) if args.report else None
    print(json.dumps({"rows": rows, "folder": str(root), "report": report}))


def _best(fn, repeat: int = 3) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def _report_times(base, folder: Path, root: Path) -> dict:
    """Seconds of the parts of ``study report`` on the finished study in ``folder`` (best of 3,
    in this process) and of the whole command (one run each, a new process); prints a table."""
    from gearrotor.files import save_figure
    from gearrotor.studies import collect, plan
    from gearrotor.studies.collection import read_case
    from gearrotor.studies.plots import _pyplot, overlay_spectra, trend_figure

    text = STUDY.read_text()  # the study file of this folder, for the command
    text = text.replace('model = "unity_gearbox.toml"', f'model = "{base.model.as_posix()}"')
    text = text.replace('output = "unity_gearbox_study.study"', f'output = "{folder.as_posix()}"')
    text = text.replace('t_end = "3.0 s"', f't_end = "{base.analysis.t_end} s"')
    text = text.replace('window = "0.5 s"', f'window = "{base.window} s"')
    (root / "study.toml").write_text(text)
    st = load_study(root / "study.toml")
    plt = _pyplot()
    planned = plan(st)
    results = st.folder / "results.nc"

    def anew():
        results.unlink(missing_ok=True)
        collect(st, planned=planned)

    parts = {"collect, results.nc absent (27 case files read)": _best(anew)}
    parts["collect, results.nc up to date"] = _best(lambda: collect(st, planned=planned))
    ds = collect(st, planned=planned)
    parts["one case file read and checked"] = _best(lambda: read_case(st, planned[0]))
    params = list(st.parameters)

    def figure(make):
        fig = make()
        save_figure(fig, root / "bench.png", dpi=110)
        plt.close(fig)

    parts["one trend figure (drawn)"] = _best(
        lambda: figure(lambda: trend_figure(ds, params[0], params))
    )
    data = {str(i): read_case(st, planned[i]) for i in range(7)}
    parts["one spectra figure, 7 cases"] = _best(
        lambda: figure(lambda: overlay_spectra(data, channel="probe", name="gear1_x"))
    )
    cache = root / "report-cache"
    shutil.rmtree(cache, ignore_errors=True)
    env = {**os.environ, "GEARROTOR_CACHE_DIR": str(cache)}
    group = ["--cases", "1,4-6", "--probes", "gear1_y", "--per-figure", "8"]
    for name, extra in (
        ("study report (full), trend figures drawn", []),
        ("study report (full), trend figures in the cache", []),
        ("study report (group), trend figures in the cache", group),
    ):
        cmd = [sys.executable, "-m", "gearrotor", "study", "report", str(st.file)]
        cmd += ["--output", str(root / "report"), *extra]
        t0 = time.perf_counter()
        subprocess.run(cmd, env=env, check=True, capture_output=True)
        parts[name] = time.perf_counter() - t0
    print()
    print(f"{'study report: part':<52}{'s':>8}")
    for name, t in parts.items():
        print(f"{name:<52}{t:>8.2f}")
    return parts


if __name__ == "__main__":
    main()
