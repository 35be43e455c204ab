"""Collecting a study: one ``xarray.Dataset`` with a ``case`` dimension, the parameters as
coordinates along it, and the summary metrics of every case (NaN for cases that failed or have
not run).

Coordinates along ``case``: ``case`` (row index), ``label``, ``key``, ``status`` (``done``,
``failed``, ``pending``), ``error`` (text, empty when none) and one coordinate per study
parameter (the values as written in the study file; ``units`` attribute when the parameter has a
unit). Metric variables: see :mod:`gearrotor.studies.metrics`; also ``wall_time`` (s) of each
run and, for transient runs, ``solver_dt`` (s), ``solver_steps``, ``solver_n_modes`` and
``solver_harmonic_error`` (when the integrator reports them).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from ..files import write_netcdf
from .cases import PlannedCase, case_path, plan, study_status
from .spec import Study

__all__ = ["collect", "load_case", "open_results"]


def load_case(
    study: Study, index: int, *, planned: tuple[PlannedCase, ...] | None = None
) -> xr.Dataset:
    """The stored dataset of case ``index`` (histories and metrics), loaded into memory.
    Raises KeyError when the case has not finished."""
    planned = plan(study) if planned is None else planned
    path = case_path(study, planned[index].key)
    if not path.exists():
        raise KeyError(f"case {index} has no result in {study.folder}")
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


def _param_coord(study: Study, name: str, values: list) -> xr.Variable:
    par = study.parameters[name]
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
        arr = np.asarray(values, float)
    else:
        arr = np.asarray([str(v) for v in values], dtype=object).astype(str)
    attrs = {"units": par.unit} if par.unit else {}
    attrs["model_paths"] = ", ".join(par.targets)
    return xr.Variable("case", arr, attrs)


def collect(
    study: Study, *, planned: tuple[PlannedCase, ...] | None = None, write: bool = True
) -> xr.Dataset:
    """Gather the metrics of every case into one Dataset; write ``results.nc`` in the study
    folder (atomically) when ``write``."""
    planned = plan(study) if planned is None else planned
    status = study_status(study, planned)
    parts = []
    for p, st in zip(planned, status, strict=True):
        if st.state != "done":
            continue
        with xr.open_dataset(case_path(study, p.key), engine="h5netcdf") as ds:
            names = json.loads(ds.attrs["metrics"])
            part = ds[names].load()
            part["wall_time"] = (
                (),
                float(ds.attrs.get("case_wall_time_s", np.nan)),
                {"units": "s", "long_name": "wall time of the run"},
            )
            stats = json.loads(ds.attrs.get("solver_stats", "{}"))
            for k, unit in (("dt", "s"), ("steps", "1"), ("n_modes", "1"), ("harmonic_error", "1")):
                if k in stats:
                    v = np.nan if stats[k] is None else float(stats[k])
                    part[f"solver_{k}"] = ((), v, {"units": unit})
        part.attrs = {}
        parts.append(part.expand_dims(case=[p.case.index]))
    idx = np.array([p.case.index for p in planned], dtype=np.int64)
    if parts:
        res = xr.concat(
            parts, dim="case", join="outer", data_vars="all", coords="different", compat="equals"
        )
        res = res.reindex(case=idx)
    else:
        res = xr.Dataset(coords={"case": idx})
    coords = {
        "label": ("case", np.array([p.case.label for p in planned], dtype=object).astype(str)),
        "key": ("case", np.array([p.key for p in planned], dtype=object).astype(str)),
        "status": ("case", np.array([s.state for s in status], dtype=object).astype(str)),
        "error": ("case", np.array([s.error or "" for s in status], dtype=object).astype(str)),
    }
    for name in study.parameters:
        coords[name] = _param_coord(study, name, [p.case.values[name] for p in planned])
    res = res.assign_coords(coords)
    res.attrs.update(
        {
            "title": f"gearrotor study: {study.name}",
            "study_file": str(study.file),
            "model_file": str(study.model),
            "analysis": json.dumps(study.analysis.model_dump()),
            "metric_window_s": float(study.window),
            "parameters": json.dumps(list(study.parameters)),
        }
    )
    if write:
        study.folder.mkdir(parents=True, exist_ok=True)
        path = study.folder / "results.nc"
        write_netcdf(path, res)
    return res


def open_results(study: Study | str | Path) -> xr.Dataset:
    """The combined results of a study (``results.nc`` of its folder, or a path to it)."""
    path = study.folder / "results.nc" if isinstance(study, Study) else Path(study)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()
