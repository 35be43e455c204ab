"""The cases of a study in its folder: :func:`plan` resolves every case's model and keys it,
:func:`case_path` names its files, :func:`study_status` reads its state from them.

A case is keyed by the SHA-256 of its resolved model (JSON), the analysis settings and the
stored outputs (:mod:`.execute` runs the cases, :mod:`.collection` gathers their results).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ModelError
from .spec import Case, Study

__all__ = ["CaseStatus", "PlannedCase", "case_path", "case_error", "plan", "study_status"]

FORMAT_VERSION = 1
_MAX_ERROR_FILE = 4 * 1024 * 1024  # bytes read of a failed case's file (a longer one is damaged)


@dataclass(frozen=True)
class PlannedCase:
    """A case with its key and resolved model (``model_json``), or the input error that
    prevented resolving it (``error``)."""

    case: Case
    key: str
    model_json: str | None
    error: str | None = None


@dataclass(frozen=True)
class CaseStatus:
    """State of one case in the study folder: ``"done"``, ``"failed"`` (error text in
    ``error``) or ``"pending"``."""

    index: int
    key: str
    label: str
    state: str
    error: str | None = None


def _canonical(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)


def _settings(study: Study) -> dict:
    return {
        "format": FORMAT_VERSION,
        "analysis": study.analysis.model_dump(),
        "outputs": study.outputs.model_dump(),
        "window": study.window,
    }


def plan(study: Study) -> tuple[PlannedCase, ...]:
    """Resolve every case's model and compute its key (cheap: no analysis runs)."""
    from ..io import load_model

    settings = _settings(study)
    out = []
    for case in study.cases:
        try:
            train = load_model(study.model, case.overrides)
        except ModelError as exc:
            h = hashlib.sha256(_canonical({"invalid": case.overrides, **settings}).encode())
            out.append(PlannedCase(case, h.hexdigest()[:20], None, str(exc)))
            continue
        mj = train.model_dump_json()
        h = hashlib.sha256(_canonical({"model": json.loads(mj), **settings}).encode())
        out.append(PlannedCase(case, h.hexdigest()[:20], mj))
    return tuple(out)


def case_path(study: Study, key: str, *, error: bool = False) -> Path:
    """File of a finished (``<key>.nc``) or failed (``<key>.error.json``) case."""
    return study.folder / "cases" / (f"{key}.error.json" if error else f"{key}.nc")


def case_error(path: Path) -> str:
    """The error text of a failed case's file (``<key>.error.json``); :class:`ModelError`
    naming the file when it is not one (damaged, truncated, foreign)."""
    expected = "a failed case's file written by 'gearrotor study run' (delete it to run again)"
    try:
        with open(path, "rb") as fh:  # an error text with its traceback: kilobytes
            doc = json.loads(fh.read(_MAX_ERROR_FILE).decode("utf-8"))
    except (OSError, ValueError, RecursionError) as exc:
        raise ModelError(
            f"cannot read the file as JSON ({type(exc).__name__})",
            file=str(path),
            expected=expected,
        ) from None
    if not isinstance(doc, dict) or not isinstance(doc.get("error"), str):
        raise ModelError(
            "no error text in the file", field="error", file=str(path), expected=expected
        )
    return doc["error"]


def study_status(
    study: Study, planned: tuple[PlannedCase, ...] | None = None
) -> tuple[CaseStatus, ...]:
    """State of every case of the study from the files in its folder."""
    planned = plan(study) if planned is None else planned
    out = []
    for p in planned:
        state, err = "pending", p.error
        if p.error is not None:
            state = "failed"
        elif case_path(study, p.key).exists():
            state = "done"
        elif case_path(study, p.key, error=True).exists():
            state = "failed"
            err = case_error(case_path(study, p.key, error=True))
        out.append(CaseStatus(p.case.index, p.key, p.case.label, state, err))
    return tuple(out)
