"""Running a study: execute the planned cases (:mod:`.cases`) on local processes or Dask, store.

Each case's model is resolved in the calling process (:func:`gearrotor.io.load_model` with the
case's overrides); a case whose overrides are invalid is recorded as failed with the error and
the others run. A case is keyed by the SHA-256 of its resolved model (JSON), the analysis
settings and the stored outputs, so a study that is interrupted or re-run skips the finished
cases, and identical rows run once. The study folder holds::

    study.json             the case table: index, parameter values, label, key
    cases/<key>.nc         one finished case (histories + metrics), written atomically
    cases/<key>.error.json a failed case: error text and traceback
    results.nc             the combined dataset (:func:`gearrotor.studies.collect`)

Workers run one case at a time with one BLAS/numba thread each (GEARROTOR_THREADS,
OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, MKL_NUM_THREADS and NUMBA_NUM_THREADS = 1): local workers
are forked from a fork server that imported what a case needs once, or spawned where there is
none (Windows; :func:`gearrotor.studies.workers.worker_processes`); a Dask ``LocalCluster`` gets
the same environment. Each case also runs
in a one-thread :func:`gearrotor.threads.scope` (threadpoolctl), so that the workers of a
remote Dask cluster started without these variables use one BLAS thread too; every worker must
be able to import gearrotor. Results come
back to the calling process, which writes the files, so the study folder need not be shared.
"""

from __future__ import annotations

import contextlib
import json
import os
import sys
import time
import traceback
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass, field
from typing import TextIO

from ..errors import ModelError
from ..files import check_output, remove_stale_temporaries, write_json, write_netcdf
from ..threads import processes
from .cases import (
    CaseStatus,
    PlannedCase,
    _canonical,
    case_error,
    case_path,
    plan,
    study_status,
)
from .spec import Study
from .workers import (
    children_without_sigint,
    init_worker,
    signals_deferred,
    stop_local_cluster,
    stop_pool,
    worker_processes,
)

__all__ = [
    "THREAD_ENV",
    "CaseStatus",
    "PlannedCase",
    "RunSummary",
    "case_path",
    "plan",
    "run_case",
    "run_study",
    "study_status",
]

THREAD_ENV = {
    "GEARROTOR_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "NUMBA_NUM_THREADS": "1",
}


@dataclass(frozen=True)
class RunSummary:
    """Outcome of :func:`run_study`: cases in the table, distinct runs, runs skipped (already
    finished), runs executed now, failed cases (index → error) and wall time (s)."""

    n_cases: int
    n_runs: int
    skipped: int
    executed: int
    failed: dict[int, str] = field(default_factory=dict)
    wall_time_s: float = 0.0
    backend: str = "local"
    workers: int = 1

    @property
    def ok(self) -> bool:
        return not self.failed


# ---- the worker ------------------------------------------------------------------------------
def _payload(study: Study, p: PlannedCase) -> dict:
    return {
        "key": p.key,
        "index": p.case.index,
        "model_json": p.model_json,
        "analysis": study.analysis.model_dump(),
        "window": study.window,
        "histories": study.outputs.histories,
        "values": p.case.values,
        "study": study.name,
    }


def run_case(payload: dict) -> dict:
    """Run one case (in a worker). Never raises: returns ``{"key", "index", "status": "ok",
    "dataset"}`` or ``{..., "status": "failed", "error", "traceback"}``, with ``wall_time_s``
    and the worker's thread settings ``env`` as the worker process was started with."""
    t0 = time.perf_counter()
    base = {
        "key": payload["key"],
        "index": payload["index"],
        "env": {k: os.environ.get(k) for k in THREAD_ENV},
        "pid": os.getpid(),
    }
    try:
        from .. import threads
        from ..model import Train

        train = Train.model_validate_json(payload["model_json"])
        settings = payload["analysis"]
        # one BLAS thread per worker, also on a Dask worker started without THREAD_ENV
        with threads.using(1), threads.scope():
            if settings["type"] == "transient":
                ds = _run_transient(
                    train, settings, window=payload["window"], histories=payload["histories"]
                )
            else:
                ds = _run_modal(train, settings)
        wall = time.perf_counter() - t0
        ds.attrs.update(
            {
                "gearrotor_study": payload["study"],
                "case_key": payload["key"],
                "case_index": int(payload["index"]),
                "case_values": _canonical(payload["values"]),
                "analysis": _canonical(settings),
                "case_wall_time_s": wall,
                "worker_env": _canonical(base["env"]),
            }
        )
        return {**base, "status": "ok", "dataset": ds, "wall_time_s": wall}
    except Exception as exc:  # a failing case is recorded, it must not stop the study
        return {
            **base,
            "status": "failed",
            "error": f"{type(exc).__name__}: {exc}",
            "traceback": traceback.format_exc(),
            "wall_time_s": time.perf_counter() - t0,
        }


def _run_transient(train, s: dict, *, window: float, histories: str):
    import numpy as np

    from ..analyses.transient import RK4, ModalRK4, Save, transient
    from .metrics import transient_metrics

    cls = RK4 if s["integrator"] == "rk4" else ModalRK4
    integ = cls(dt=s["dt"], **s["integrator_options"])
    res = transient(
        train,
        t_end=s["t_end"],
        integrator=integ,
        save=Save(dt=s["save_dt"]),
        reactions=s["reactions"],
        blowup=s["blowup"],
    )
    ds = res.to_xarray().drop_vars(["q", "qdot", "global_dof", "dof"], errors="ignore")
    probe_shaft = np.array(
        [train.node_index(p, f"probes[{k}]")[0] for k, p in enumerate(train.probes)], dtype=np.int64
    )
    mesh_shaft = np.array(
        [
            train.shaft_index(m.gear.shaft, f"meshes[{k}].gear.shaft")
            for k, m in enumerate(train.meshes)
        ],
        dtype=np.int64,
    )
    mesh_teeth = np.array([m.gear.teeth for m in train.meshes], dtype=np.int64)
    met = transient_metrics(
        ds, window=window, probe_shaft=probe_shaft, mesh_teeth=mesh_teeth, mesh_shaft=mesh_shaft
    )
    if histories == "window":
        t = ds["time"].values
        ds = ds.isel(time=np.flatnonzero(t >= t[-1] - window - 1e-12))
    elif histories == "none":
        ds = ds.isel(time=slice(0, 0))
    ds = ds.assign(
        probe_shaft=("probe", probe_shaft),
        mesh_shaft=("mesh", mesh_shaft),
        mesh_teeth=("mesh", mesh_teeth),
    )
    ds = _merge(ds, met)
    ds.attrs["metrics"] = json.dumps(list(met.data_vars))
    ds.attrs["metric_window_s"] = float(window)
    return ds


def _merge(a, b):
    """Merge the metric variables ``b`` into ``a`` (same coordinates)."""
    for name, var in b.data_vars.items():
        a[name] = var
    return a


def _run_modal(train, s: dict):
    import numpy as np
    import xarray as xr

    from ..analyses import modal

    res = modal(train, speed=s["speed"], max_frequency=s["max_frequency"])
    keep = np.flatnonzero(~np.asarray(res.overdamped, bool))[: s["n_modes"]]
    n = s["n_modes"]
    fr = np.full(n, np.nan)
    ld = np.full(n, np.nan)
    mt = np.array([""] * n, dtype=object)
    wh = np.array([""] * n, dtype=object)
    fr[: len(keep)] = np.asarray(res.frequency_rpm)[keep]
    ld[: len(keep)] = np.asarray(res.log_dec)[keep]
    mt[: len(keep)] = [res.mode_type[i] for i in keep]
    wh[: len(keep)] = [res.whirl[i] for i in keep]
    ds = xr.Dataset(
        {
            "damped_frequency": ("mode", fr, {"units": "rpm"}),
            "log_dec": ("mode", ld, {"units": "1"}),
            "mode_type": ("mode", mt.astype(str)),
            "whirl": ("mode", wh.astype(str)),
        },
        coords={"mode": np.arange(n)},
        attrs={"title": "gearrotor modal", "speed_rad_s": float(res.speed)},
    )
    ds.attrs["metrics"] = json.dumps(["damped_frequency", "log_dec", "mode_type", "whirl"])
    return ds


# ---- storing ---------------------------------------------------------------------------------
def _write_case(study: Study, out: dict) -> None:
    key = out["key"]
    err = case_path(study, key, error=True)
    if out["status"] == "ok":
        path = case_path(study, key)
        write_netcdf(path, out["dataset"])
        err.unlink(missing_ok=True)
    else:
        write_json(
            err, {k: out.get(k) for k in ("key", "index", "error", "traceback", "wall_time_s")}
        )


def _write_manifest(study: Study, planned: tuple[PlannedCase, ...]) -> None:
    (study.folder / "cases").mkdir(parents=True, exist_ok=True)
    doc = {
        "name": study.name,
        "study_file": str(study.file),
        "model": str(study.model),
        "parameters": {
            k: {"paths": list(v.targets), "unit": v.unit} for k, v in study.parameters.items()
        },
        "analysis": study.analysis.model_dump(),
        "outputs": study.outputs.model_dump(),
        "window_s": study.window,
        "cases": [
            {
                "index": p.case.index,
                "values": p.case.values,
                "label": p.case.label,
                "key": p.key,
                "input_error": p.error,
            }
            for p in planned
        ],
    }
    path = study.folder / "study.json"
    write_json(path, doc, default=str)


# ---- progress ----------------------------------------------------------------------------------
class _Progress:
    """A text progress bar on ``stream`` (redrawn in place on a terminal, one line per case
    otherwise)."""

    def __init__(
        self,
        total: int,
        *,
        enabled: bool,
        stream: TextIO | None = None,
        total_weight: float | None = None,
    ) -> None:
        self.total, self.enabled = total, enabled
        self.stream = stream or sys.stderr
        self.done = self.failed = 0
        self.weight_total = float(total if total_weight is None else total_weight)
        self.weight_done = 0.0
        self.t0 = time.perf_counter()
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def update(self, text: str, *, failed: bool = False, weight: float = 1.0) -> None:
        self.done += 1
        self.failed += failed
        self.weight_done += weight
        if not self.enabled:
            return
        el = time.perf_counter() - self.t0
        # time per unit of estimated work so far × the work left (cases weigh unequally:
        # see _case_weight), not time per case × cases left
        left = max(self.weight_total - self.weight_done, 0.0)
        eta = el / max(self.weight_done, 1e-9) * left
        n = 30
        fill = int(n * self.done / max(self.total, 1))
        bar = f"[{'#' * fill}{'.' * (n - fill)}] {self.done}/{self.total}"
        tail = f"{self.failed} failed, {el:.0f} s, ~{eta:.0f} s left"
        if self.tty:
            self.stream.write(f"\r{bar} {tail} ")
            if self.done == self.total:
                self.stream.write("\n")
        else:
            self.stream.write(f"{bar} {text}; {tail}\n")
        self.stream.flush()


@contextlib.contextmanager
def _thread_env() -> Iterator[None]:
    """Set the one-thread variables in this process's environment while workers are spawned
    (they inherit it); restore the previous values afterwards."""
    old = {k: os.environ.get(k) for k in THREAD_ENV}
    os.environ.update(THREAD_ENV)
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


# a case with backlash runs ~1.2–2x longer than one without (issue 16's exponential modal scheme:
# the seed study's backlash rows 3.7–5.8 s against 2–3 s; 5x before it)
BACKLASH_COST = 1.5


def _case_weight(p: PlannedCase) -> float:
    """Relative run time of a case, known before it runs: 1, or ``BACKLASH_COST`` for a model
    with a mesh backlash (the seed study's backlash rows take ~1.2–2x as long as the others)."""
    try:
        model = json.loads(p.model_json or "{}")
    except ValueError:
        return 1.0
    weight = 1.0
    for m in model.get("meshes") or []:
        b = (m or {}).get("backlash") or {}
        if isinstance(b, dict) and float(b.get("value") or 0.0) > 0:
            weight = BACKLASH_COST
    return weight


# ---- execution ---------------------------------------------------------------------------------
@contextlib.contextmanager
def _local_pool(workers: int, method: str | None = None) -> Iterator[ProcessPoolExecutor]:
    """The pool of local workers: forked from a fork server that imported what a case needs,
    or spawned where there is none (:func:`~gearrotor.studies.workers.worker_processes`), with
    the one-thread environment; ``method`` forces the start method (tests)."""
    with _thread_env(), worker_processes(method) as (context, parent):
        env = dict(os.environ)
        with ProcessPoolExecutor(
            max_workers=workers,
            mp_context=context,
            initializer=init_worker,
            initargs=(parent, env),
        ) as pool:
            yield pool


def _execute_local(payloads: list[dict], workers: int, on_done: Callable[[dict], None]) -> None:
    with _local_pool(workers) as pool:
        futs = {}
        try:
            # submitting starts the workers: whole, so that a signal meanwhile (answered at the
            # end of the block) finds each started worker in the pool, to be killed; a worker
            # forked after the run had stopped would find the pool's queues gone, with a
            # traceback (the first one waits for the fork server's imports, ~2 s)
            with signals_deferred(), children_without_sigint():
                for p in payloads:
                    futs[pool.submit(run_case, p)] = p
            pending = set(futs)
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for f in done:
                    p = futs[f]
                    try:
                        out = f.result()
                    except Exception as exc:  # worker died (killed, out of memory)
                        out = {
                            "key": p["key"],
                            "index": p["index"],
                            "status": "failed",
                            "error": f"worker failed: {type(exc).__name__}: {exc}",
                        }
                    on_done(out)
        except BaseException:  # interrupted: stop the workers, keep what is stored
            stop_pool(pool)
            raise


def _execute_dask(
    payloads: list[dict], scheduler: str, workers: int | None, on_done: Callable[[dict], None]
) -> int:
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise ModelError(
            "a Dask scheduler needs dask.distributed",
            field="--scheduler",
            value=scheduler,
            expected="pip install 'gearrotor[dask]'",
        ) from None
    with contextlib.ExitStack() as stack:
        cluster = None
        if scheduler == "local":
            n = workers or processes()
            # started whole (a Ctrl-C meanwhile is answered once it is up), its workers
            # without SIGINT (the parent answers it)
            with signals_deferred(), children_without_sigint():
                cluster = stack.enter_context(
                    LocalCluster(
                        n_workers=n,
                        threads_per_worker=1,
                        processes=True,
                        # no dashboard; the scheduler's HTTP server (health and metrics
                        # routes, always started) on a free port of this host: on its
                        # default 8787 a second cluster on the machine (another study, a
                        # notebook's) printed "Port 8787 is already in use" into the run
                        dashboard_address="127.0.0.1:0",
                        scheduler_kwargs={"dashboard": False},
                        env=dict(THREAD_ENV),
                    )
                )
                client = stack.enter_context(Client(cluster))
        else:
            try:
                client = stack.enter_context(Client(scheduler, timeout="30s"))
            except (OSError, TimeoutError, ValueError) as exc:
                raise ModelError(
                    f"cannot connect to the Dask scheduler: {exc}",
                    field="--scheduler",
                    value=scheduler,
                    expected="an address such as tcp://host:8786, or 'local'",
                ) from None
            n = len(client.scheduler_info().get("workers", {}))
        futs = {}
        try:
            for p in payloads:
                futs[client.submit(run_case, p, key=f"gearrotor-case-{p['key']}", pure=False)] = p
            for f in as_completed(list(futs)):
                p = futs[f]
                try:
                    out = f.result()
                except Exception as exc:  # worker lost
                    out = {
                        "key": p["key"],
                        "index": p["index"],
                        "status": "failed",
                        "error": f"worker failed: {type(exc).__name__}: {exc}",
                    }
                on_done(out)
        except BaseException:  # interrupted
            client.cancel(list(futs))
            if cluster is not None:  # ours: stop it now, quietly
                stop_local_cluster(cluster, stack.close)
            raise
    return n


def _require(*modules: str) -> None:
    """Fail early, with the install command, when an optional dependency is missing."""
    import importlib.util

    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if missing:
        raise ModelError(
            f"parametric studies need {', '.join(missing)}",
            expected="pip install 'gearrotor[results]' (add [dask] for --scheduler, [plot] "
            "for study report)",
        )


def run_study(
    study: Study,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    cases: list[int] | None = None,
    retry_failed: bool = True,
    progress: bool = True,
    collect_results: bool = True,
    stream: TextIO | None = None,
) -> RunSummary:
    """Run the cases of ``study`` that are not finished and store each as it completes.

    scheduler : None (local processes), ``"local"`` (a Dask LocalCluster) or a Dask scheduler
        address (``tcp://host:8786``)
    workers : processes (local) or Dask workers (LocalCluster); default: the cores not busy
        with other processes (:func:`gearrotor.threads.processes`: ``--threads N`` sets N)
    cases : run only these case indices (the others are left as they are)
    retry_failed : run previously failed cases again (default); False skips them
    progress : a progress bar on ``stream`` (default stderr)
    collect_results : write ``results.nc`` (:func:`collect`) at the end
    """
    t0 = time.perf_counter()
    _require("xarray", "h5netcdf")
    check_output(study.folder, "directory", field="output")
    for d in (study.folder, study.folder / "cases"):  # left by a run that was killed
        remove_stale_temporaries(d)
    if workers is not None and workers < 1:
        raise ModelError(
            "the number of workers must be positive",
            field="--workers",
            value=workers,
            expected="an integer >= 1",
        )
    planned = plan(study)
    if cases is not None:
        bad = [i for i in cases if not 0 <= i < len(planned)]
        if bad:
            raise ModelError(
                "case index out of range",
                field="cases",
                value=bad,
                expected=f"0 .. {len(planned) - 1}",
            )
        planned_sel = tuple(planned[i] for i in sorted(set(cases)))
    else:
        planned_sel = planned
    _write_manifest(study, planned)
    failed: dict[int, str] = {}
    todo: dict[str, PlannedCase] = {}
    skipped = 0
    seen = set()
    for p in planned_sel:
        if p.error is not None:
            failed[p.case.index] = p.error
            continue
        if p.key in seen:
            continue
        seen.add(p.key)
        if case_path(study, p.key).exists():
            skipped += 1
        elif not retry_failed and case_path(study, p.key, error=True).exists():
            skipped += 1
        else:
            todo[p.key] = p
    by_key: dict[str, list[int]] = {}
    for p in planned_sel:
        by_key.setdefault(p.key, []).append(p.case.index)
    for p in planned_sel:  # previously failed and not retried
        ep = case_path(study, p.key, error=True)
        if (
            p.error is None
            and p.key not in todo
            and ep.exists()
            and not case_path(study, p.key).exists()
        ):
            failed[p.case.index] = case_error(ep)
    bar = _Progress(len(todo), enabled=progress, stream=stream)

    def on_done(out: dict) -> None:
        _write_case(study, out)
        idx = by_key[out["key"]]
        ok = out["status"] == "ok"
        if not ok:
            for i in idx:
                failed[i] = out["error"]
        text = (
            f"case {','.join(map(str, idx))} "
            f"{'ok' if ok else 'FAILED: ' + out['error'][:200]}"
            f" ({out.get('wall_time_s', 0.0):.1f} s)"
        )
        bar.update(text, failed=not ok, weight=weights.get(out["key"], 1.0))

    # the longest cases first (a worker does not idle at the end on one backlash case), and
    # the remaining time estimated from their weights
    order = sorted(todo.values(), key=_case_weight, reverse=True)
    weights = {p.key: _case_weight(p) for p in order}
    bar.weight_total = sum(weights.values())
    payloads = [_payload(study, p) for p in order]
    n_workers = workers or processes()
    backend = "local"
    if payloads:
        if scheduler is None:
            n_workers = min(n_workers, len(payloads))
            _execute_local(payloads, n_workers, on_done)
        else:
            backend = "dask-local" if scheduler == "local" else f"dask:{scheduler}"
            n_workers = _execute_dask(payloads, scheduler, workers, on_done)
    if collect_results:
        from .collection import collect

        collect(study, planned=planned)
    return RunSummary(
        n_cases=len(planned_sel),
        n_runs=len(seen),
        skipped=skipped,
        executed=len(payloads),
        failed=dict(sorted(failed.items())),
        wall_time_s=time.perf_counter() - t0,
        backend=backend,
        workers=n_workers,
    )
