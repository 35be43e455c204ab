"""One vocabulary for the report's judgements: the status of a mode (the modes table, the
stability tables, ``report.json``, the mode-shape figures and the summary use these words and
no others) and the result of a check (the summary's lines, ``report.json``'s ``verdicts`` and
the command line's output).

Mode status (:func:`mode_status`), against the acceptance threshold
:data:`~.blocks.LOG_DEC_THRESHOLD` (API 617 Level II). The modes judged are Level II's
(:func:`gearrotor.analyses.audit.stability.criterion_class`, the one definition both use): forward
whirl, at least half of the kinetic energy in lateral motion, damped frequency up to 3× the
fastest shaft speed. So a mode is

* ``stable``: log dec at or above the threshold (pass);
* ``low damping``: a judged mode below the threshold (FAIL);
* ``UNSTABLE``: a growing mode, whatever it is (FAIL; damping ratio below −1e-7, modal's
  round-off level: :func:`gearrotor.analyses.audit.stability.is_unstable`);
* ``over-damped``: ζ ≥ 0.999, no oscillation (pass);

and, below the threshold but not judged (:data:`NOT_JUDGED`), shown with the reason:

* ``no torsional damping in the model`` (``axial``, ``torsional or axial``): less than half
  lateral (e.g. a coupled lateral–torsional mode that is mostly torsional), in a model whose
  damping matrix has no entry on its other DOFs (no mesh, coupling or material damping, no
  torsional damper). Its log dec is then zero or only the share of the bearings' damping its
  lateral part carries: a statement about the model, not about the machine;
* ``low damping, not lateral``: less than half lateral (or a tilting pad's mode, type ``P``)
  in a model that damps its other DOFs;
* ``low damping, backward``: a lateral mode whirling backward;
* ``low damping, above 3× speed``: a forward lateral mode above the criteria's window.

Check results (:func:`verdict`): ``pass``, ``FAIL``, ``not judged`` (a statement, e.g. the
modes the model cannot damp), ``Level II required`` (API 617 Level I: not a failure, Level II
decides), ``not required`` (Level II when Level I passes), ``n/a``.
"""

from __future__ import annotations

import numpy as np

from .blocks import LOG_DEC_THRESHOLD, _e

__all__ = [
    "LEVEL2_REQUIRED",
    "NOT_JUDGED",
    "RESULTS",
    "judged",
    "mode_status",
    "model_undamped_kinds",
    "status_row_class",
    "track_rows",
    "verdict",
]

NOT_JUDGED = "not judged"
LEVEL2_REQUIRED = "Level II required"
#: Every check result a verdict can have, and its css class on the page.
RESULTS = {
    "pass": "ok",
    "FAIL": "fail",
    NOT_JUDGED: "na",
    LEVEL2_REQUIRED: "na",
    "not required": "na",
    "n/a": "na",
}
_KIND = {1: "axial", 2: "torsional"}  # Assembly.dof_kind() codes of the non-lateral DOFs


def model_undamped_kinds(asm, speed: float) -> frozenset[str]:
    """The DOF groups (``"torsional"``, ``"axial"``) on which the damping matrix C at
    reference-shaft ``speed`` (rad/s) has no entry: a mode of only those DOFs can be damped
    only through its coupling to the lateral DOFs. A gear-mesh damper ``c w wᵀ`` puts entries
    on the torsional block, material damping on every block."""
    _, C, _, _ = asm.matrices(speed)
    C = C.tocoo()
    kind = asm.dof_kind()
    scale = float(np.max(np.abs(C.data), initial=0.0))
    out = set()
    for k, name in _KIND.items():
        sel = (kind[C.row] == k) & (kind[C.col] == k)
        if not np.any(np.abs(C.data[sel]) > 1e-12 * scale):
            out.add(name)
    return frozenset(out)


def _kinds(mode_type: str) -> set[str]:
    parts = set(str(mode_type).split("-"))
    return {n for k, n in (("T", "torsional"), ("A", "axial")) if k in parts}


#: the status of a mode below the threshold that the criteria do not judge, by the reason
#: :func:`gearrotor.analyses.audit.stability.criterion_class` gives (``"not lateral"``: see
#: :func:`mode_status`)
_NOT_JUDGED_STATUS = {
    "backward": "low damping, backward",
    "above window": "low damping, above 3× speed",
    "not lateral": "low damping, not lateral",
}


def mode_status(
    mode_type: str,
    log_dec: float,
    *,
    overdamped: bool,
    undamped_kinds: frozenset[str],
    criterion: str = "judged",
) -> str:
    """The status of a mode (module docstring): ``mode_type`` as ``modal`` names it (``L``,
    ``L-T``, ``T``, ``P``, ...), ``log_dec`` its log decrement, ``undamped_kinds`` from
    :func:`model_undamped_kinds`, ``criterion`` its class for the stability criteria
    (:func:`gearrotor.analyses.audit.stability.criterion_class`: ``"judged"``, ``"backward"``,
    ``"not lateral"``, ``"above window"``, ``"over-damped"``)."""
    from ...analyses.audit.stability import is_unstable

    if overdamped or criterion == "over-damped":
        return "over-damped"
    if not np.isfinite(log_dec) or is_unstable(log_dec):
        return "UNSTABLE"
    if log_dec >= LOG_DEC_THRESHOLD:
        return "stable"
    if criterion == "judged":
        return "low damping"
    if criterion == "not lateral":
        kinds = _kinds(mode_type)
        if kinds and kinds <= undamped_kinds:
            which = " or ".join(n for n in ("torsional", "axial") if n in kinds)
            return f"no {which} damping in the model"
    return _NOT_JUDGED_STATUS[criterion]


def judged(status: str) -> bool | None:
    """pass (True), FAIL (False) or not judged (None) for a mode of this status."""
    if status in ("stable", "over-damped"):
        return True
    if status in ("low damping", "UNSTABLE"):
        return False
    return None


def status_row_class(status: str) -> str:
    """css class of a table row of a mode with this status."""
    return {"UNSTABLE": "bad", "low damping": "bad", "over-damped": "od"}.get(
        status, "" if judged(status) else "warn"
    )


def result_of(ok: bool | None) -> str:
    return {True: "pass", False: "FAIL", None: NOT_JUDGED}[ok]


def result_badge(result: str) -> str:
    """The coloured word of a check result (:data:`RESULTS`)."""
    return f'<span class="{RESULTS[result]}">{_e(result)}</span>'


def verdict(key: str, check: str, ok: bool | None, detail: str, result: str | None = None):
    """A line of the summary: ``key`` names the check (one line per key), ``check`` says what
    is checked, ``ok`` True (pass), False (FAIL) or None (not a pass/fail result), ``result``
    the word shown (default from ``ok``: ``pass``, ``FAIL``, ``not judged``)."""
    result = result_of(ok) if result is None else result
    if result not in RESULTS:
        raise ValueError(f"unknown check result {result!r}")
    return {"key": key, "check": check, "ok": ok, "result": result, "detail": detail}


def track_rows(res, camp) -> list[int | None]:
    """Per Campbell track, the row of the modal table (at the operating speed) it is, so that
    the crossing and stability tables and the figures name a mode by one numbering: a
    one-to-one assignment by frequency at the operating speed (a sweep point); None for a track
    without a row within 1 % (then it is named ``track j``)."""
    from scipy.optimize import linear_sum_assignment

    n = camp.damped_frequency.shape[1]
    if res is None:
        return [None] * n
    k = int(np.argmin(np.abs(camp.speeds - abs(res.speed))))
    rows = [i for i in range(len(res)) if not res.overdamped[i]]
    if not rows or abs(camp.speeds[k] - abs(res.speed)) > 1e-6 * max(abs(res.speed), 1.0):
        return [None] * n
    f = camp.damped_frequency[k]
    fr = res.damped_frequency[rows]
    cost = np.abs(f[:, None] - fr[None, :]) / np.maximum(np.abs(f[:, None]), 1e-9)
    cost = np.where(np.isfinite(cost), cost, 1e9)
    out: list[int | None] = [None] * n
    for j, c in zip(*linear_sum_assignment(cost), strict=True):
        if cost[j, c] <= 0.01:
            out[j] = int(rows[c])
    return out


def track_name(rows: list[int | None], j: int) -> str:
    """``mode 7`` (the modal table's row) or ``track 3`` (a Campbell track without one)."""
    return f"mode {rows[j]}" if rows[j] is not None else f"track {j}"


def _range_words(lo: float, hi: float) -> str:
    """'operating range 10,800–11,340 rpm' or 'operating speed 6,500 rpm' (rpm in)."""
    if abs(hi - lo) <= 1e-9 * max(abs(hi), 1.0):
        return f"operating speed {hi:,.0f} rpm"
    return f"operating range {lo:,.0f}–{hi:,.0f} rpm"
