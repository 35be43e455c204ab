"""The API 617 stability audit of a train as one call: Level I from the model's ``[api_audit]``
table (:mod:`gearrotor.model.api_audit`) or from arguments that override it, and Level II with every
destabiliser the model holds at the operating speeds, with one verdict.

Level II runs whatever Level I says (the audit reports both); the audit passes when Level I
passes, or when Level I asks for Level II and Level II passes. Level II speeds: the minimum and
maximum operating speeds and the maximum continuous speed of the model (distinct values), the
MCS alone when the model states no operating range.

The edition (API 617 8th or 9th, :func:`~gearrotor.analyses.audit.stability.edition`) comes from the
``edition`` argument, else the model's ``[api_audit] edition``, else the 8th.

One verdict line per check (:meth:`StabilityAudit.checks`), in one vocabulary
(:data:`~gearrotor.analyses.audit.stability.VERDICTS`): Level I says ``"pass"`` or
``"level II required"`` (not a failure: the standard's next step), Level II ``"pass"`` or
``"fail"``, and the audit's conclusion is the Level II line's when Level I sent the machine
there.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...assembly import Assembly
from ...errors import ModelError
from ...model import Train
from ...model.speed_range import model_max_continuous_speed
from ...progress import Progress, part, report
from ...threads import managed
from .stability import (
    RPM,
    Level1Result,
    Level2Result,
    Site,
    Stage,
    _Verdict,
    level1,
    level2,
    mid_span,
)
from .stability import edition as _edition

__all__ = ["StabilityAudit", "level1_inputs", "level2_speeds", "stability_audit"]


@dataclass(frozen=True)
class StabilityAudit(_Verdict):
    """Level I and Level II of a train and the audit's verdict (``"pass"`` or ``"fail"``,
    ``decided_by`` ``"Level I"`` or ``"Level II"``)."""

    level1: Level1Result
    level2: Level2Result
    verdict: str
    decided_by: str

    def to_dict(self) -> dict:
        """The Level I headline numbers at the top (``threshold_q_N_per_m`` = Q_0,
        ``qa_N_per_m``, ``ratio_q0_qa``, ``threshold_mode``, ``level1_verdict``), the edition,
        the audit's ``verdict``, and both results in full."""
        l1, l2 = self.level1.to_dict(), self.level2.to_dict()
        return {
            "edition": self.level1.edition,
            "edition_key": self.level1.edition_key,
            "verdict": self.verdict,
            "decided_by": self.decided_by,
            "mcs_rpm": abs(self.level1.speed) * RPM,
            "qa_N_per_m": l1["qa_N_per_m"],
            "threshold_q_N_per_m": l1["threshold_q_N_per_m"],
            "ratio_q0_qa": l1["ratio_q0_qa"],
            "log_dec_at_qa": l1["log_dec_at_qa"],
            "least_forward_log_dec_at_qa": l1["least_forward_log_dec_at_qa"],
            "followed_mode": l1["followed_mode"],
            "threshold_mode": l1["threshold_mode"],
            "level1_verdict": l1["verdict"],
            "level2_verdict": l2["verdict"],
            "level2_min_forward_log_dec": self.min_level2_log_dec,
            "checks": self.checks(),
            "level1": l1,
            "level2": l2,
        }

    @property
    def min_level2_log_dec(self) -> float | None:
        """The least log dec of the forward lateral modes over the Level II speeds."""
        d = [e.min_forward_log_dec for e in self.level2.evaluations]
        d = [v for v in d if v is not None]
        return min(d) if d else None

    def checks(self) -> list[dict]:
        """One verdict line per check: ``check`` (its name), ``status`` (``"pass"``,
        ``"level II required"``, ``"fail"``), ``ok`` (True: pass, False: fail, None: Level II
        required, which is neither), ``decides`` (whether this check decides the audit) and
        ``detail`` (the numbers behind it)."""
        l1, l2 = self.level1, self.level2
        ratio = "> search limit" if l1.ratio is None else f"{l1.ratio:.3f}"
        low = self.min_level2_log_dec
        l1_status = "pass" if l1.passed else "level II required"
        unmet = [c.name for c in l1.criteria if c.ok is False]
        detail1 = f"Q_0/Q_A = {ratio}, log dec at Q_A {l1.log_dec_at_qa:.3f} ({l1.edition})" + (
            f"; not met: {', '.join(unmet)}" if unmet else ""
        )
        speeds = ", ".join(f"{abs(e.speed) * RPM:.0f}" for e in l2.evaluations)
        detail2 = (
            f"least forward log dec {'-' if low is None else f'{low:.3f}'} (>= "
            f"{l2.criterion_log_dec:g}) at {speeds} rpm"
            + ("" if l1.passed else "; decides the audit")
            + ("; not required: Level I passed" if l1.passed else "")
        )
        return [
            {
                "check": "API 617 Level I stability",
                "status": l1_status,
                "ok": True if l1.passed else None,
                "decides": l1.passed,
                "detail": detail1,
            },
            {
                "check": "API 617 Level II stability",
                "status": l2.verdict,
                "ok": l2.passed,
                "decides": not l1.passed,
                "detail": detail2,
            },
        ]

    def table(self) -> str:
        lines = [f"  {c['check']}: {c['status']} ({c['detail']})" for c in self.checks()]
        return "\n".join(
            [
                self.level1.table(),
                "",
                self.level2.table(),
                "",
                f"{self.level1.edition} stability audit, one line per check:",
                *lines,
                f"  audit: {self.verdict} (decided by {self.decided_by})",
            ]
        )


def level2_speeds(train: Train) -> list[float]:
    """Reference-shaft speeds (rad/s) of Level II: min and max operating speed and MCS."""
    mcs = model_max_continuous_speed(train, "the stability audit")
    speeds = [mcs]
    if train.operating_speed_range is not None:
        speeds += list(train.operating_speed_range)
    out: list[float] = []
    for w in sorted(speeds):
        if not out or abs(w - out[-1]) > 1e-9 * w:
            out.append(float(w))
    return out


def level1_inputs(
    train: Train,
    *,
    qa: float | None = None,
    stages: Sequence[Stage] | None = None,
    at: Sequence[Site | tuple] | None = None,
    operating_speed: float | None = None,
    average_density: float | None = None,
    exclude_bearings: Sequence[str] | None = None,
    edition: str | None = None,
) -> dict:
    """Keyword arguments of :func:`~.stability.level1`: the model's ``[api_audit]`` table with
    the given arguments in place of its values (``qa`` or ``stages`` replace both of the
    table's Q_A sources, and then the table's sites are not used either; a site's node
    ``"mid_span"`` becomes the middle of its shaft's span).
    """
    table = train.api_audit
    if qa is not None and stages:
        raise ModelError(
            "give the anticipated cross-coupling once: Q_A or the stages of its formula",
            field="qa / stages",
            expected="one of the two",
        )
    from_table = qa is None and not stages
    if from_table:
        if table is None:
            raise ModelError(
                "the stability audit needs the anticipated cross-coupling Q_A",
                field="api_audit",
                expected="an [api_audit] table in the model, or Q_A (--qa) or the formula's "
                "inputs (--power ...)",
            )
        qa = table.qa
        stages = [
            Stage(s.shaft, s.node, s.power, s.diameter, s.height, s.density_ratio, s.kind)
            for s in table.stages
        ]
    sites = at
    if not sites and from_table:  # the table's sites go with the table's Q_A
        sites = [(s.shaft, s.node, s.weight) for s in table.at]
    resolved = []
    for k, s in enumerate(sites or ()):
        site = s if isinstance(s, Site) else Site(*s)
        if site.node == "mid_span":
            site = mid_span(train, site.shaft, site.weight)
        elif not isinstance(site.node, int | np.integer):
            raise ModelError(
                "a site's node is an index or 'mid_span'", field=f"at[{k}].node", value=site.node
            )
        resolved.append(site)
    if operating_speed is None and table is not None:
        operating_speed = table.operating_speed
    if average_density is None and table is not None:
        average_density = table.density
    if exclude_bearings is None:
        exclude_bearings = table.exclude_bearings if table is not None else ()
    if edition is None and table is not None:
        edition = table.edition
    return {
        "edition": _edition(edition).key,
        "qa": qa,
        "stages": tuple(stages or ()),
        "at": tuple(resolved),
        "operating_speed": operating_speed,
        "average_density": average_density,
        "exclude_bearings": tuple(exclude_bearings),
    }


@managed
def stability_audit(
    model: Train | Assembly,
    *,
    speeds: Sequence[float] | None = None,
    n_curve: int = 11,
    rtol: float = 1e-4,
    operating_point=None,
    progress: Progress | None = None,
    **level1_args,
) -> StabilityAudit:
    """Level I (at the model's MCS, inputs from :func:`level1_inputs` with ``level1_args``)
    and Level II at ``speeds`` (rad/s, default :func:`level2_speeds`).

    ``edition`` (in ``level1_args``): ``"8th"`` or ``"9th"``, default the model's
    ``[api_audit] edition`` (else the 8th).

    ``operating_point`` (name or :class:`~gearrotor.model.OperatingPoint`): fluid-film bearings
    at the coefficients of the point's static loads, evaluated at the MCS and the Level II
    speeds, meshes on the loaded flank (:func:`~gearrotor.analyses.static.at_operating_point`).

    ``progress``: a :data:`gearrotor.progress.Progress` callback (the operating point's static
    solves, Level I, Level II).
    """
    train = model.train if isinstance(model, Assembly) else model
    mcs = model_max_continuous_speed(train, "the stability audit (Level I runs at the MCS)")
    ws = list(speeds) if speeds is not None else level2_speeds(train)
    if operating_point is not None:
        from ..static.operating_point import model_at_operating_point

        at = sorted({float(abs(w)) for w in [mcs, *ws]})
        op = part(progress, 0.0, 0.6, "operating point")
        train = model_at_operating_point(train, operating_point, at, op)[0]
    start = 0.6 if operating_point is not None else 0.0
    kw = level1_inputs(train, **level1_args)
    report(progress, start, "Level I")
    r1 = level1(train, n_curve=n_curve, rtol=rtol, **kw)
    report(progress, start + 0.8 * (1 - start), "Level II")
    r2 = level2(train, speeds=ws, edition=kw["edition"])
    report(progress, 1.0)
    if r1.passed:
        verdict, by = "pass", "Level I"
    else:
        verdict, by = r2.verdict, "Level II"
    return StabilityAudit(r1, r2, verdict, by)
