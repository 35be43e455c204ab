"""The report's driver: :func:`make_report` checks the request, runs the sections of
:data:`~.sections.SECTIONS` (:mod:`.base`) and writes the directory atomically."""

from __future__ import annotations

import json
import math
import shutil
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import ModelError
from ...files import (
    check_output,
    make_temporary_directory,
    replace_directory,
    write_json,
    write_text,
)
from ...progress import Progress, part, report
from ...threads import managed, processes
from .base import Context, Later
from .blocks import RPM
from .helper import Helper
from .page import _page
from .sections import SECTIONS

__all__ = ["ANALYSES", "Report", "make_report", "parse_analyses"]

#: The analyses the report runs when none are named (``--analyses`` default).
ANALYSES = tuple(s.analysis for s in SECTIONS if s.default)


@dataclass(frozen=True)
class Report:
    """What :func:`make_report` wrote and computed.

        ``directory`` holds ``html`` (the report), ``figures`` (PNG files) and ``json``;
        ``summary`` is the content of ``report.json``. The analysis results are kept for callers
        that want more than the report shows (``None`` when not requested); ``results`` holds every
    section's result by analysis name.
    """

    directory: Path
    html: Path
    json: Path
    figures: tuple[Path, ...]
    summary: dict = field(repr=False)
    modal: object | None = field(default=None, repr=False)
    campbell: object | None = field(default=None, repr=False)
    unbalance: object | None = field(default=None, repr=False)
    transient: object | None = field(default=None, repr=False)
    results: dict = field(default_factory=dict, repr=False)


def parse_analyses(text: str | tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """Analyses from ``"modal,campbell,unbalance"`` (any order, each at most once).

    ``"transient"`` is not run by the report: it is accepted only to state that a transient
    result file must be given (see :func:`make_report`).
    """
    items = text.split(",") if isinstance(text, str) else list(text)
    names = [s.strip().lower() for s in items if s.strip()]
    allowed = tuple(s.analysis for s in SECTIONS if s.analysis)
    bad = [n for n in names if n not in allowed]
    if bad or not names:
        raise ModelError(
            "unknown analysis" if bad else "no analysis requested",
            field="--analyses",
            value=",".join(bad) if bad else text,
            expected="a comma-separated subset of " + ", ".join(allowed),
        )
    out: list[str] = []
    for n in names:
        if n not in out:
            out.append(n)
    return tuple(out)


def _default_max_frequency(asm, top: float, given: float | None) -> tuple[float, str]:
    """(rad/s, why): the given value, or the frequency range an excitation can reach
    (:func:`~gearrotor.analyses.model_summary.excitation_frequency_range`: the flagship's
    lightly damped torsional mode at 215,670 cpm, 10.6 % above its mesh frequency, is in)."""
    if given is not None:
        return float(given), "as given"
    from ...analyses.model_summary import excitation_frequency_range

    return excitation_frequency_range(asm, top)


@managed
def make_report(
    model,
    output: str | Path,
    *,
    analyses: tuple[str, ...] | str = ANALYSES,
    speed: float | None = None,
    max_frequency: float | None = None,
    transient: str | Path | None = None,
    api: bool = False,
    edition: str | None = None,
    n_campbell: int = 40,
    n_unbalance: int = 400,
    source: str | None = None,
    command: str | None = None,
    operating_point: str | None = None,
    operating_points: tuple[str, ...] | list[str] | None = None,
    progress: Progress | None = None,
) -> Report:
    """Run the analyses and write the report directory ``output``.

    Parameters
    ----------
    model : a :class:`~gearrotor.model.Train` (or its :class:`~gearrotor.assembly.Assembly`)
    output : directory to write: created, or an earlier report's (or an empty) folder, which
        is replaced as a whole (:func:`~gearrotor.files.replace_directory`: a reader or a
        killed run sees the old report or the new one, never a mix); a symbolic link to a
        folder is followed (the folder it points to is replaced, the link stays)
    analyses : subset of ``("modal", "campbell", "unbalance")``; ``"transient"`` requires
        ``transient`` (the report reads a saved result, it does not run the solver)
    speed : rad/s, magnitude of the reference-shaft operating speed (default: the model's); the
        modal analysis runs at it, the Campbell sweep covers 0..1.25× and the unbalance sweep
        0.02..1.5× of it (of the MCS when higher); the API checks use the model's operating
        range and maximum continuous speed when the model states them and no speed is given,
        else this speed
    max_frequency : rad/s, highest damped frequency of the modes and the Campbell diagram
        (default: every mode an excitation can reach within its separation margin over the
        operating range, with headroom: 1.1 × (1 + 26 %) × the highest excitation frequency
        (1x, 2x of every shaft, every mesh frequency) at the top operating speed, at least
        5 × that speed; see :func:`_default_max_frequency`); the report states the range and
        why
    transient : path of a transient result (NetCDF written by ``TransientResult.save``)
    api : the unbalance section uses the API 617 unbalance, 4 × 6350 W/N g·mm per plane of the
        model's unbalances (W the plane's share of its shaft's mass, kg; N its shaft's speed at
        the operating speed, rpm; phases as in the model) instead of the model's amounts
        (:func:`gearrotor.analyses.audit.api_unbalance.api617_unbalances`); with the 9th
        edition 2 × 6350 W/N g·mm at the antinodes of the reference shaft's first forward mode
        (:func:`gearrotor.analyses.audit.api_unbalance.mode_unbalances`) and the
        close-clearance check (:func:`gearrotor.analyses.audit.api_unbalance.clearance_check`)
        at the model's close clearances
        (:func:`gearrotor.analyses.audit.api_unbalance.close_clearances`)
    edition : API 617 edition of ``api`` and the audit section, ``"8th"`` or ``"9th"``
        (default: the model's ``[api_audit] edition``, else the 8th); the sections say which
    n_campbell, n_unbalance : number of speeds of the Campbell and unbalance sweeps
    source, command : the model file and the command line, quoted in the report
    operating_point : run the analyses at this operating point of the model: fluid-film
        bearings at the coefficients of its static loads (held over the sweeps), meshes on the
        loaded flank, speed default the point's
        (:func:`~gearrotor.analyses.static.at_operating_point`)
    operating_points : add the operating-points section for these points (bearing-load and
        eccentricity loci, least-stable log dec against power); the ``"operating_points"``
        analysis
    progress : a :data:`gearrotor.progress.Progress` callback (the operating point, the
        sections' analyses, then their figures and the page)

    Raises
    ------
    ModelError : an invalid request (unknown analysis, non-positive speed, transient requested
        without a file, unreadable result file, unbalance report without unbalance or probes,
        output path that is a file) or an invalid model.
    """
    from ...assembly import Assembly, assemble

    analyses = parse_analyses(analyses)
    if "transient" in analyses and transient is None:
        raise ModelError(
            "the transient section needs a saved transient result",
            field="--transient",
            value=None,
            expected="a NetCDF file written by the transient analysis (the report does not run "
            "the transient solver)",
        )
    if transient is not None and "transient" not in analyses:
        analyses = (*analyses, "transient")
    if edition is not None:
        from ...analyses.audit.stability import edition as pick_edition

        edition = pick_edition(edition, "--edition").key
        if not api and "audit" not in analyses:
            raise ModelError(
                "the edition chooses the API 617 unbalance and audit: give --api or the audit "
                "section too",
                field="--edition",
                value=edition,
                expected="--api, or 'audit' in --analyses",
            )
    # also removes the temporary folders of a report whose process was killed (SIGKILL)
    output = check_output(output, "directory", field="--output")
    _check_replaceable(output)
    base_train = model.train if isinstance(model, Assembly) else model
    if operating_points:
        operating_points = tuple(operating_points)
        if "operating_points" not in analyses:
            analyses = (*analyses, "operating_points")
    elif operating_point is not None and "operating_points" in analyses:
        operating_points = (operating_point,)
    elif "operating_points" in analyses:
        operating_points = tuple(p.name for p in base_train.operating_points)
    speed_given = speed is not None  # the API checks use the model's range unless a speed is
    op_note = None
    if operating_point is not None:
        from ...analyses.static import at_operating_point

        try:
            op = base_train.operating_point(operating_point)
        except ModelError as exc:
            raise ModelError(
                exc.message,
                field="--operating-point",
                value=operating_point,
                expected=exc.expected,
            ) from None
        if speed is None:
            speed = abs(op.reference_speed(base_train.speed))
        model = at_operating_point(
            base_train, op, progress=part(progress, 0.0, 0.1, "operating point")
        )
        op_note = (
            f"Operating point {op.name}: fluid-film bearings at the coefficients of its static "
            f"loads at {op.reference_speed(base_train.speed) * RPM:.0f} rpm (held over the "
            "sweeps), meshes loaded on the flank its torque loads."
        )
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    nominal = abs(float(train.speed))
    w = nominal if speed is None else float(speed)
    if not (np.isfinite(w) and w > 0):
        raise ModelError(
            "the report needs a positive operating speed",
            field="--speed",
            value=None if speed is None else f"{w * RPM:.6g} rpm",
            expected="a speed > 0 rpm (the direction of rotation follows the model)",
        )
    from ...model.speed_range import model_operating_range

    operating_range = None if speed_given else model_operating_range(train)
    top = max(w, operating_range[1]) if operating_range is not None else w
    fmax, fmax_basis = _default_max_frequency(asm, top, max_frequency)
    if not (np.isfinite(fmax) and fmax > 0):
        raise ModelError(
            "the maximum frequency must be positive",
            field="--max-frequency",
            value=f"{fmax * RPM:.6g} rpm",
            expected="a frequency > 0 rpm",
        )
    if n_campbell < 2 or n_unbalance < 3:
        raise ModelError(
            "too few sweep speeds",
            value=(n_campbell, n_unbalance),
            expected="n_campbell >= 2 and n_unbalance >= 3",
        )
    ctx = Context(
        asm,
        analyses,
        w,
        fmax,
        operating_range=operating_range,
        api=api,
        transient_file=None if transient is None else Path(transient),
        n_campbell=n_campbell,
        n_unbalance=n_unbalance,
        operating_points=tuple(operating_points or ()),
        base_train=base_train,
        edition=edition,
    )
    ctx.notes.append(
        f"Modes and Campbell diagram up to {fmax * RPM:,.0f} cpm ({fmax_basis}; "
        "--max-frequency sets another range)."
    )
    if op_note:
        ctx.notes.append(op_note)
    requested = [s for s in SECTIONS if s.analysis in analyses]
    for section in requested:
        section.check(ctx)

    output.parent.mkdir(parents=True, exist_ok=True)
    tmp = make_temporary_directory(output, field="--output")  # .NAME.tmp-PID-TOKEN
    # a second process for the independent work when a second core is free (.helper)
    ctx.helper = Helper(processes() > 1)
    try:
        ctx.directory = tmp
        for i, section in enumerate(requested):
            report(progress, 0.1 + 0.6 * i / len(requested), f"running {section.analysis}")
            section.run(ctx)
        if ctx.helper.enabled:
            # while the helper runs an analysis: the figures that need none
            for section in SECTIONS:
                section.early(ctx)
        for key, value in list(ctx.results.items()):
            if isinstance(value, Later):
                ctx.results[key] = ctx.helper.result(value.key)
        summary = ctx.summary
        summary.update({"train": train.name, "gearrotor_report": 1})
        parts = []
        for i, section in enumerate(SECTIONS):
            what = section.analysis or type(section).__name__
            report(progress, 0.7 + 0.3 * i / len(SECTIONS), f"writing {what}")
            parts.extend(section.write(ctx))
        summary["verdicts"] = ctx.verdicts
        summary["inputs"] = {
            "model": source,
            "command": command,
            "analyses": list(analyses),
            "speed_rpm": w * RPM,
            "operating_range_rpm": [v * RPM for v in ctx.api_range],
            "max_frequency_rpm": fmax * RPM,
            "max_frequency_basis": fmax_basis,
            "transient": None if transient is None else str(transient),
            "unbalance": "api617" if api else "model",
            "api617_edition": ctx.api_edition.name if api or "audit" in analyses else None,
            "operating_point": operating_point,
        }
        ctx.helper.finish()  # the PNG files
        write_json(tmp / "report.json", _clean(summary))
        page = _page(train, parts, summary, ctx.figures, ctx.notes, source=source, command=command)
        write_text(tmp / "report.html", page)
        replace_directory(tmp, output)
        report(progress, 1.0)
    except BaseException as exc:
        ctx.helper.close()
        shutil.rmtree(tmp, ignore_errors=True)
        if isinstance(exc, ModelError) and str(tmp) in str(exc):  # a write error: name the
            raise ModelError(str(exc).replace(str(tmp), str(output))) from None  # report's file
        raise
    return Report(
        directory=output,
        html=output / "report.html",
        json=output / "report.json",
        figures=tuple(output / p.name for p in ctx.figures),
        summary=summary,
        modal=ctx.results.get("modal"),
        campbell=ctx.results.get("campbell"),
        unbalance=ctx.results.get("unbalance"),
        transient=ctx.results.get("transient"),
        results=dict(ctx.results),
    )


def _check_replaceable(output: Path) -> None:
    """The report replaces its folder as a whole: refuse, before anything runs, a folder that
    holds anything but an earlier report (its ``report.json`` says so), so that no file of
    the user's goes with it."""
    if not output.is_dir():
        return
    content = [p.name for p in output.iterdir()]
    if not content:
        return
    try:
        earlier = json.loads((output / "report.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        earlier = None
    if not (isinstance(earlier, dict) and "gearrotor_report" in earlier):
        raise ModelError(
            f"the folder holds files that are not a gearrotor report ({sorted(content)[0]!r}"
            f"{' ...' if len(content) > 1 else ''}), and a report replaces its folder as a whole",
            field="--output",
            value=str(output),
            expected="a new or empty folder, or the folder of an earlier report",
        )


def _clean(x):
    """JSON-safe copy: non-finite floats become None, numpy scalars Python numbers."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_clean(v) for v in x]
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x
