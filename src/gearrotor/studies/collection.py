"""Collecting a study: one ``xarray.Dataset`` with a ``case`` dimension, the parameters as
coordinates along it, and the summary metrics of every case (NaN for cases that failed or have
not run).

Coordinates along ``case``: ``case`` (row index), ``label``, ``key``, ``status`` (``done``,
``failed``, ``pending``), ``error`` (text, empty when none) and one coordinate per study
parameter (the values as written in the study file; ``units`` attribute when the parameter has a
unit). Metric variables: see :mod:`gearrotor.studies.metrics`; also ``wall_time`` (s) of each
run and, for transient runs, ``solver_dt`` (s), ``solver_steps``, ``solver_n_modes`` and
``solver_harmonic_error`` (when the integrator reports them).

Every case file is checked when it is read (:func:`read_case`), as saved transient results are
(:func:`gearrotor.analyses.transient.results.check_result`): a study folder is a place anyone can
write to, and a damaged, truncated or foreign file is an input error (:class:`ModelError`, exit
2 at the command line) naming the file and what is wrong, not a traceback.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import ModelError
from ..files import write_netcdf
from .cases import PlannedCase, case_path, plan, study_status
from .metrics import MODAL_METRICS, TRANSIENT_METRICS
from .spec import Study, TransientSettings

__all__ = ["check_case", "collect", "load_case", "open_results", "read_case"]

_CASE = "a case file written by 'gearrotor study run' (delete it to run the case again)"
#: the variables of a transient case that the collection and the report read, besides the
#: metrics and the histories :func:`check_result` checks
_TRANSIENT_VARS = ("probe_shaft", "mesh_shaft", "mesh_teeth")
_READ_ERRORS = (OSError, ValueError, KeyError, TypeError, RecursionError, AttributeError)


def _read_netcdf(path: Path, expected: str) -> xr.Dataset:
    """Open ``path`` and load it into memory; :class:`ModelError` naming the file otherwise."""
    if not path.exists():
        raise ModelError("file not found", file=str(path), expected=expected)
    if path.is_dir():
        raise ModelError("a directory, not a file", file=str(path), expected=expected)
    from ..analyses.transient.results import check_sizes

    check_sizes(path)  # a decompression bomb is refused from the header, before any read
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            return ds.load()
    except _READ_ERRORS as exc:
        text = str(exc).splitlines()[0][:120] if str(exc) else ""
        raise ModelError(
            f"cannot read the file as NetCDF ({type(exc).__name__}{': ' + text if text else ''})",
            file=str(path),
            expected=expected,
        ) from None


def read_case(study: Study, p: PlannedCase) -> xr.Dataset:
    """The stored dataset of the finished case ``p``, loaded into memory and checked
    (:func:`check_case`)."""
    path = case_path(study, p.key)
    ds = _read_netcdf(path, _CASE)
    check_case(ds, str(path), key=p.key, transient=isinstance(study.analysis, TransientSettings))
    return ds


def _json_attr(ds: xr.Dataset, name: str, file: str, kind: type, default=None):
    text = ds.attrs.get(name, default)
    try:
        value = json.loads(text) if isinstance(text, str) and len(text) < 1_000_000 else text
    except (ValueError, RecursionError):
        raise ModelError("not valid JSON", field=name, file=file, expected=_CASE) from None
    if not isinstance(value, kind):
        raise ModelError(
            f"not a JSON {kind.__name__}",
            field=name,
            file=file,
            value=str(text)[:80],
            expected=_CASE,
        )
    return value


def check_case(ds: xr.Dataset, file: str, *, key: str, transient: bool) -> None:
    """Check a case file before anything reads it: it is the file of case ``key`` (a file copied
    from another case or another study is foreign), its ``metrics`` attribute lists metric
    variables it holds (numbers that are finite or NaN for a metric that is undefined; text for
    the modal mode types), ``solver_stats`` is JSON, and for a transient case the stored
    histories pass the check of saved transient results (variables, time axis, finite values,
    the embedded model) and the probes and meshes name shafts of the file. Raises
    :class:`ModelError` naming the file and what is wrong."""
    got = ds.attrs.get("case_key")
    if got != key:
        raise ModelError(
            "the file is not this case's result (foreign or copied from another case)",
            field="case_key",
            file=file,
            value=got,
            expected=f"{key}, the key in the file's name",
        )
    names = _json_attr(ds, "metrics", file, list)
    allowed = TRANSIENT_METRICS if transient else MODAL_METRICS
    bad = [n for n in names if n not in allowed]
    missing = [n for n in allowed if n not in names or n not in ds.data_vars]
    if bad or missing:
        raise ModelError(
            "the metrics of the file are not those of a "
            + ("transient" if transient else "modal")
            + " study",
            field="metrics",
            file=file,
            value=f"unknown {bad}" if bad else f"missing {missing}",
            expected=_CASE,
        )
    for n in names:
        vals = np.asarray(ds[n].values)
        text = n in ("mode_type", "whirl")
        if text != (vals.dtype.kind in "UO"):
            raise ModelError(
                "text expected" if text else "not numeric", field=n, file=file, expected=_CASE
            )
        if not text and np.isinf(vals).any():
            raise ModelError(
                "an infinite value", field=n, file=file, expected="finite numbers or NaN"
            )
    _json_attr(ds, "solver_stats", file, dict, "{}")
    if not transient:
        return
    missing = [v for v in _TRANSIENT_VARS if v not in ds.data_vars]
    if missing:
        raise ModelError(
            "not a transient case", file=file, value=f"missing {', '.join(missing)}", expected=_CASE
        )
    if ds.sizes.get("time", 0):  # histories stored (outputs.histories = window | full)
        from ..analyses.transient.results import check_result

        check_result(ds.drop_vars(names), file)
    n_shaft = ds.sizes.get("shaft", 0)
    for v in ("probe_shaft", "mesh_shaft"):
        idx = np.asarray(ds[v].values)
        if idx.dtype.kind not in "iu" or ((idx < 0) | (idx >= n_shaft)).any():
            raise ModelError(
                "not shaft indices of the file",
                field=v,
                file=file,
                value=idx.tolist()[:8],
                expected=f"integers 0 .. {n_shaft - 1}",
            )


def load_case(
    study: Study, index: int, *, planned: tuple[PlannedCase, ...] | None = None
) -> xr.Dataset:
    """The stored dataset of case ``index`` (histories and metrics), loaded into memory.
    Raises KeyError when the case has not finished, :class:`ModelError` when its file is
    damaged or foreign (:func:`check_case`)."""
    planned = plan(study) if planned is None else planned
    path = case_path(study, planned[index].key)
    if not path.exists():
        raise KeyError(f"case {index} has no result in {study.folder}")
    return read_case(study, planned[index])


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
        ds = read_case(study, p)
        names = json.loads(ds.attrs["metrics"])
        part = ds[names]
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
    return _read_netcdf(path, "the results.nc of a study (gearrotor study run)")
