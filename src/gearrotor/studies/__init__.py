"""Parametric studies (SPEC 3.4): a matrix of cases over a base model, run as independent jobs
on local processes or a Dask cluster, resumable, collected into one labelled dataset.

    study = load_study("examples/unity_gearbox_study.toml")
    summary = run_study(study)                 # local processes, all cores
    ds = collect(study)                        # xarray.Dataset, dims (case, probe, ...)
    report(study, "figures/")                  # overlay spectra and trend plots (PNG)

Heavy optional dependencies (xarray, dask.distributed, matplotlib) are imported when used.
"""

from .cases import CaseStatus, PlannedCase, case_path, plan, study_status
from .execute import THREAD_ENV, RunSummary, run_case, run_study
from .spec import (
    Case,
    ModalSettings,
    Outputs,
    Parameter,
    Study,
    TransientSettings,
    load_study,
    study_from_dict,
)

__all__ = [
    "THREAD_ENV",
    "Case",
    "CaseStatus",
    "ModalSettings",
    "Outputs",
    "Parameter",
    "PlannedCase",
    "RunSummary",
    "Study",
    "TransientSettings",
    "case_path",
    "collect",
    "load_case",
    "load_study",
    "open_results",
    "plan",
    "report",
    "run_case",
    "run_study",
    "study_from_dict",
    "study_status",
]


def __getattr__(name: str):
    if name in ("collect", "load_case", "open_results"):
        from . import collection

        return getattr(collection, name)
    if name == "report":
        from .plots import report

        return report
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
