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

import hashlib
import io
import json
import os
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
#: the integrator's statistics a transient case records (``solver_<name>``), with their units
_SOLVER_STATS = {"dt": "s", "steps": "1", "n_modes": "1", "harmonic_error": "1"}


def _read_netcdf(path: Path, expected: str) -> xr.Dataset:
    """Open ``path`` and load it into memory; :class:`ModelError` naming the file otherwise."""
    return _read_bytes(path, expected)[0]


def _read_bytes(path: Path, expected: str) -> tuple[xr.Dataset, str]:
    """The dataset of ``path`` loaded into memory and the SHA-256 of the bytes it was read from
    (the file is read once: the digest is that of what was checked)."""
    if not path.exists():
        raise ModelError("file not found", file=str(path), expected=expected)
    if path.is_dir():
        raise ModelError("a directory, not a file", file=str(path), expected=expected)
    from ..analyses.transient.results import check_sizes

    arrays = check_sizes(path)  # a decompression bomb is refused from the header, before any read
    try:
        size = path.stat().st_size
        # into memory only a file of at most its arrays' bytes (and some): not one that is not
        # HDF5 at all (its reader says what is wrong from the header), nor one of gigabytes
        # around small arrays
        whole = arrays is not None and size <= arrays + _SLACK
        data = path.read_bytes() if whole else None
    except OSError as exc:
        raise ModelError(
            f"cannot read the file ({type(exc).__name__})", file=str(path), expected=expected
        ) from None
    if data is None:
        digest = file_sha256(path) or ""
        source = path
    else:
        digest = hashlib.sha256(data).hexdigest()
        ds = _plain_netcdf(data)
        if ds is not None:
            return ds, digest
        source = io.BytesIO(data)
    try:
        with xr.open_dataset(source, engine="h5netcdf") as ds:
            return ds.load(), digest
    except _READ_ERRORS as exc:
        text = str(exc).splitlines()[0][:120] if str(exc) else ""
        raise ModelError(
            f"cannot read the file as NetCDF ({type(exc).__name__}{': ' + text if text else ''})",
            file=str(path),
            expected=expected,
        ) from None


_SLACK = 64 * 1024**2  # bytes of a NetCDF file besides its arrays (header, attributes, model)

#: attributes of the NetCDF-4 layout (dimension scales), not of the variables
_LAYOUT_ATTRS = frozenset(
    ("CLASS", "NAME", "REFERENCE_LIST", "DIMENSION_LIST", "_Netcdf4Coordinates", "_Netcdf4Dimid")
)
_TIME_UNITS = frozenset(
    ("days", "hours", "minutes", "seconds", "milliseconds", "microseconds", "nanoseconds")
)
_PHONY = b"This is a netCDF dimension but not a netCDF variable"


def _plain_netcdf(data: bytes) -> xr.Dataset | None:
    """The NetCDF-4 file image ``data`` as xarray reads it (``open_dataset(engine="h5netcdf")``
    with its default decoding), read with h5py directly: 13x faster than xarray and h5netcdf for
    a case file (8 against 107 ms), whose time goes to resolving the dimension scales' references
    variable by variable. Only the layout that xarray writes and that decodes to the plain values
    is taken (numbers and UTF-8 text in the root group, dimensions named by the NetCDF-4
    dimension ids, NaN fill values, no scale/offset, no time units, scalar or text attributes);
    anything else returns None and is read by xarray. The equivalence is tested on the files
    ``study run`` writes (tests/studies/test_study_report.py)."""
    import h5py

    try:
        with h5py.File(io.BytesIO(data), "r") as f:
            return _plain_file(f, h5py)
    except (OSError, ValueError, KeyError, TypeError, RecursionError, AttributeError):
        return None


def _attr_value(value):
    """An attribute as h5netcdf returns it: text, or a number (stored as a 1-element array)."""
    if isinstance(value, str):
        return value
    if isinstance(value, np.ndarray) and value.shape == (1,) and value.dtype.kind in "fiu":
        return value[0]
    raise TypeError("not a plain attribute")


def _plain_file(f, h5py) -> xr.Dataset | None:
    attrs = {}
    for name in f.attrs:
        if name == "_NCProperties":
            continue
        if name.startswith("_") or name == "coordinates":
            return None
        attrs[name] = _attr_value(f.attrs[name])
    dsets = {}
    for name in f:  # creation order (xarray writes it tracked), as xarray lists them
        obj = f.get(name, getclass=True)
        if obj is not h5py.Dataset:
            return None
        dsets[name] = f[name]
    dim_names: dict[int, str] = {}
    scales: set[str] = set()
    for name, d in dsets.items():
        if d.attrs.get("CLASS") == b"DIMENSION_SCALE":
            dim_names[int(d.attrs["_Netcdf4Dimid"])] = name
            scales.add(name)
    variables: dict[str, xr.Variable] = {}
    coord_names: set[str] = set()
    for name, d in dsets.items():
        keys = set(d.attrs.keys())
        if name in scales and bytes(d.attrs.get("NAME", b"")).startswith(_PHONY):
            continue  # a dimension without a variable
        if d.ndim == 0:
            dims: tuple[str, ...] = ()
        elif "_Netcdf4Coordinates" in keys:
            dims = tuple(dim_names[int(i)] for i in np.atleast_1d(d.attrs["_Netcdf4Coordinates"]))
        elif name in scales and d.ndim == 1:
            dims = (name,)
        else:
            return None
        if len(dims) != d.ndim:
            return None
        vattrs, encoding = {}, {}
        for key in keys - _LAYOUT_ATTRS:
            value = d.attrs[key]
            if key == "_FillValue":
                fill = np.asarray(value)
                if d.dtype.kind != "f" or fill.size != 1 or not np.isnan(fill).all():
                    return None
                encoding["_FillValue"] = d.dtype.type(np.nan)
            elif key == "coordinates":
                coord_names.update(str(_attr_value(value)).split())
            elif key.startswith("_") or key in (
                "scale_factor",
                "add_offset",
                "missing_value",
                "calendar",
                "dtype",
            ):
                return None
            else:
                vattrs[key] = _attr_value(value)
        units = vattrs.get("units")
        if isinstance(units, str) and (" since " in units or units.strip() in _TIME_UNITS):
            return None
        text = h5py.check_string_dtype(d.dtype)
        if text is not None:
            if text.length is not None or text.encoding != "utf-8":
                return None
            values = np.asarray(d.asstr()[()], dtype=object).astype(str)
        elif d.dtype.kind in "fiu" and d.dtype.fields is None:
            values = d[()]
        else:
            return None
        encoding["dtype"] = values.dtype
        variables[name] = xr.Variable(dims, values, vattrs, encoding=encoding)
    coords = {n: v for n, v in variables.items() if n in scales or n in coord_names}
    data_vars = {n: v for n, v in variables.items() if n not in coords}
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def read_case(study: Study, p: PlannedCase) -> xr.Dataset:
    """The stored dataset of the finished case ``p``, loaded into memory and checked
    (:func:`check_case`)."""
    return _read_case(study, p)[0]


def _read_case(study: Study, p: PlannedCase) -> tuple[xr.Dataset, str]:
    """:func:`read_case` and the SHA-256 of the bytes the dataset was read from."""
    path = case_path(study, p.key)
    ds, digest = _read_bytes(path, _CASE)
    check_case(ds, str(path), key=p.key, transient=isinstance(study.analysis, TransientSettings))
    return ds, digest


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
    folder (atomically) when ``write``.

    ``results.nc`` records the SHA-256 of every case file it was collected from (attribute
    ``case_files_sha256``). When the study folder's ``results.nc`` is up to date (the same
    cases, states, errors, parameters and settings, and every finished case's file has the
    digest recorded: each was read and checked when it was collected), it is the collection and
    no case file is read (0.05 s against 0.9 s for the 27 cases of the seed study); a case file
    replaced, damaged or added since is read, and checked, by collecting anew."""
    planned = plan(study) if planned is None else planned
    status = study_status(study, planned)
    frame = _frame(study, planned, status)
    done = [p for p, st in zip(planned, status, strict=True) if st.state == "done"]
    digests = {p.key: file_sha256(case_path(study, p.key)) for p in done}
    cached = _up_to_date(study, frame, digests)
    if cached is not None:
        return cached
    parts = []
    read: dict[str, tuple[xr.Dataset, str]] = {}
    for p in done:
        if p.key not in read:  # identical rows share one file
            read[p.key] = _read_case(study, p)
        ds = read[p.key][0]
        names = json.loads(ds.attrs["metrics"])
        part = ds[names]
        part["wall_time"] = (
            (),
            float(ds.attrs.get("case_wall_time_s", np.nan)),
            {"units": "s", "long_name": "wall time of the run"},
        )
        stats = json.loads(ds.attrs.get("solver_stats", "{}"))
        for k, unit in _SOLVER_STATS.items():
            if k in stats:
                v = np.nan if stats[k] is None else float(stats[k])
                part[f"solver_{k}"] = ((), v, {"units": unit})
        part.attrs = {}
        parts.append(part.expand_dims(case=[p.case.index]))
    if parts:
        res = xr.concat(
            parts, dim="case", join="outer", data_vars="all", coords="different", compat="equals"
        )
        res = res.reindex(case=frame["case"].values)
    else:
        res = xr.Dataset(coords={"case": frame["case"].values})
    res = res.assign_coords(frame.coords)
    res.attrs.update(frame.attrs)
    res.attrs[_SOURCES] = _sources({k: d for k, (_, d) in read.items()})
    if write:
        study.folder.mkdir(parents=True, exist_ok=True)
        path = study.folder / "results.nc"
        write_netcdf(path, res)
    return res


#: attribute of results.nc: the SHA-256 of each case file it was collected from (JSON object,
#: case key -> hex digest), with the version of the collection that read them
_SOURCES = "case_files_sha256"
_COLLECTION = 1  # a new version of the collection or its checks: results.nc is collected anew


def _sources(digests: dict[str, str | None]) -> str:
    return json.dumps({"collection": _COLLECTION, "sha256": dict(sorted(digests.items()))})


def file_sha256(path: Path) -> str | None:
    """The SHA-256 of the file (1 ms for a 1.6 MB case file), None when it cannot be read (it
    is then read, and its error reported, by the collection)."""
    from ..analyses.transient.results import MAX_RESULT_BYTES

    try:
        with open(path, "rb") as fh:
            if os.fstat(fh.fileno()).st_size > MAX_RESULT_BYTES:
                return None  # not hashed: the collection refuses it from its header
            return hashlib.file_digest(fh, "sha256").hexdigest()
    except OSError:
        return None


def _frame(study: Study, planned, status) -> xr.Dataset:
    """The collection without its metrics: the coordinates along ``case`` and the attributes."""
    idx = np.array([p.case.index for p in planned], dtype=np.int64)
    coords = {
        "label": ("case", np.array([p.case.label for p in planned], dtype=object).astype(str)),
        "key": ("case", np.array([p.key for p in planned], dtype=object).astype(str)),
        "status": ("case", np.array([s.state for s in status], dtype=object).astype(str)),
        "error": ("case", np.array([s.error or "" for s in status], dtype=object).astype(str)),
    }
    for name in study.parameters:
        coords[name] = _param_coord(study, name, [p.case.values[name] for p in planned])
    attrs = {
        "title": f"gearrotor study: {study.name}",
        "study_file": str(study.file),
        "model_file": str(study.model),
        "analysis": json.dumps(study.analysis.model_dump()),
        "metric_window_s": float(study.window),
        "parameters": json.dumps(list(study.parameters)),
    }
    return xr.Dataset(coords={"case": idx, **coords}, attrs=attrs)


def _up_to_date(study: Study, frame: xr.Dataset, digests: dict[str, str | None]):
    """The study folder's ``results.nc`` when it is the collection of these case files (see
    :func:`collect`), else None (absent, damaged, older, or of other files or settings)."""
    path = study.folder / "results.nc"
    if None in digests.values() or not path.is_file():
        return None
    try:
        ds = _read_netcdf(path, "results.nc")
    except ModelError:
        return None
    if ds.attrs.get(_SOURCES) != _sources(digests):
        return None
    if any(ds.attrs.get(k) != v for k, v in frame.attrs.items()):
        return None
    for name, var in frame.coords.items():
        if name not in ds.coords or not ds[name].variable.identical(var.variable):
            return None
    transient = isinstance(study.analysis, TransientSettings)
    metrics = set(TRANSIENT_METRICS if transient else MODAL_METRICS)
    allowed = metrics | {"wall_time"} | {f"solver_{k}" for k in _SOLVER_STATS}
    if digests and not metrics <= set(ds.data_vars):
        return None
    for name, var in ds.data_vars.items():
        text = name in ("mode_type", "whirl")
        vals = np.asarray(var.values)
        if name not in allowed or var.dims[:1] != ("case",) or text != (vals.dtype.kind == "U"):
            return None
        if not text and (vals.dtype.kind != "f" or np.isinf(vals).any()):
            return None
    return ds


def open_results(study: Study | str | Path) -> xr.Dataset:
    """The combined results of a study (``results.nc`` of its folder, or a path to it)."""
    path = study.folder / "results.nc" if isinstance(study, Study) else Path(study)
    return _read_netcdf(path, "the results.nc of a study (gearrotor study run)")
