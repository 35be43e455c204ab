"""Stability section: the log decrement of every mode against the acceptance threshold
(:data:`~..blocks.LOG_DEC_THRESHOLD`, API 617 Level II) at the operating speed (modes section)
and over the Campbell sweep (Campbell section); the first verdicts of the summary.

The modes judged are API 617 Level II's, by the one definition the stability audit uses
(:func:`gearrotor.analyses.audit.stability.criterion_class`): forward whirl, at least half of the
kinetic energy in lateral motion, damped frequency up to 3× the fastest shaft speed at that
speed; any growing mode fails (:func:`gearrotor.analyses.audit.stability.is_unstable`). A Campbell
track is judged at each speed by its mode's class there: the diagram keeps every tracked
mode's kinetic-energy fractions (``CampbellResult.energy_fractions``) and whirl per speed. The
other modes below the threshold are shown with the reason they are not judged
(:mod:`..verdicts`)."""

from __future__ import annotations

import numpy as np

from ..base import Context, Part, Section
from ..blocks import LOG_DEC_THRESHOLD, RPM, _e
from ..verdicts import (
    NOT_JUDGED,
    judged,
    mode_status,
    model_undamped_kinds,
    result_badge,
    result_of,
    status_row_class,
    track_rows,
)

__all__ = [
    "MIN_LATERAL",
    "StabilitySection",
    "campbell_statuses",
    "modal_criteria",
    "modal_statuses",
    "stability_summary",
    "summary_mode_names",
]

#: the lateral kinetic-energy share from which a mode is judged: Level II's default
#: (:func:`gearrotor.analyses.audit.stability.level2`, the audit section's)
MIN_LATERAL = 0.5


class StabilitySection(Section):
    """Shown when the modal analysis or the Campbell diagram ran."""

    def write(self, ctx: Context) -> list[Part]:
        stab = stability_summary(ctx)
        if stab is None:
            ctx.summary["stability"] = {"threshold_log_dec": LOG_DEC_THRESHOLD}
            return []
        ctx.summary["stability"] = stab
        _verdicts(ctx, stab)
        return [("stability", "Stability margins", _stability_html(stab))]


def stability_summary(ctx: Context) -> dict | None:
    """The section's numbers (``report.json``'s ``stability``) from the modal result and the
    Campbell diagram of ``ctx``; None when neither ran. No solve: the modes section calls it
    too, to draw every mode the summary names."""
    res, camp = ctx.results.get("modal"), ctx.results.get("campbell")
    if res is None and camp is None:
        return None
    return _stability(res, camp, model_undamped_kinds(ctx.assembly, ctx.sign * ctx.speed))


def summary_mode_names(ctx: Context) -> set[int]:
    """The rows of the modal table the summary's stability lines name (mode numbers)."""
    stab = stability_summary(ctx)
    names: set[int] = set()
    if stab is not None:
        for line in _verdict_lines(stab, ctx.max_frequency):
            names |= line[-1]
    return names


def _window(speed_ratio, speed: float) -> float:
    from ....analyses.audit.stability import stability_window

    return stability_window(speed_ratio, speed)


def modal_criteria(res) -> np.ndarray:
    """Per mode of a modal result, its class for the stability criteria
    (:func:`gearrotor.analyses.audit.stability.criterion_class` with Level II's window at the
    result's speed)."""
    from ....analyses.audit.stability import criterion_class

    return criterion_class(
        frequency=res.damped_frequency,
        energy_lateral=res.energy_fractions[:, 0],
        whirl=res.whirl,
        overdamped=res.overdamped,
        mode_type=res.mode_type,
        window=_window(res.assembly.speed_ratio, res.speed),
        min_lateral=MIN_LATERAL,
    )


def modal_statuses(res, undamped_kinds: frozenset[str]) -> list[str]:
    """The status (:func:`~..verdicts.mode_status`) of every mode of a modal result."""
    crit = modal_criteria(res)
    return [
        mode_status(
            res.mode_type[i],
            float(res.log_dec[i]),
            overdamped=bool(res.overdamped[i]),
            undamped_kinds=undamped_kinds,
            criterion=str(crit[i]),
        )
        for i in range(len(res))
    ]


def campbell_statuses(camp, undamped_kinds: frozenset[str]) -> tuple[np.ndarray, np.ndarray]:
    """(criterion class, status) of every tracked mode at every speed of a Campbell diagram,
    arrays (n_speeds, n_modes): each speed judged as a modal result there (its whirl, lateral
    kinetic-energy share and Level II's window at that speed)."""
    from ....analyses.audit.stability import criterion_class

    if camp.energy_fractions is None:
        raise ValueError("the Campbell result has no energy fractions (made before they were kept)")
    n_s, n_m = camp.damped_frequency.shape
    crit = np.empty((n_s, n_m), dtype=object)
    status = np.empty((n_s, n_m), dtype=object)
    for k in range(n_s):
        crit[k] = criterion_class(
            frequency=camp.damped_frequency[k],
            energy_lateral=camp.energy_fractions[k, :, 0],
            whirl=camp.whirl[k],
            overdamped=camp.overdamped[k],
            mode_type=camp.mode_type[k],
            window=_window(camp.speed_ratio, camp.speeds[k]),
            min_lateral=MIN_LATERAL,
        )
        for j in range(n_m):
            status[k, j] = mode_status(
                str(camp.mode_type[k, j]),
                float(camp.log_dec[k, j]),
                overdamped=bool(camp.overdamped[k, j]),
                undamped_kinds=undamped_kinds,
                criterion=str(crit[k, j]),
            )
    return crit, status


def _mode_entry(res, i: int, status: str) -> dict:
    return {
        "mode": int(i),
        "frequency_rpm": float(res.frequency_rpm[i]),
        "log_dec": float(res.log_dec[i]),
        "type": res.mode_type[i],
        "whirl": "/".join(res.whirl_per_shaft[i]),
        "energy_lateral": float(res.energy_fractions[i, 0]),
        "status": status,
    }


# the order in which a track's speeds speak for it: its worst status over the sweep
_RANK = {"UNSTABLE": 0, "low damping": 1, "stable": 3, "over-damped": 4}


def _rank(status: str) -> int:
    return _RANK.get(status, 2)  # 2: below the threshold, not judged


def _stability(res, camp, undamped_kinds: frozenset[str]) -> dict:
    from ....analyses.audit.stability import UNSTABLE_LOG_DEC, WINDOW_MULTIPLE, is_unstable

    out: dict = {
        "threshold_log_dec": LOG_DEC_THRESHOLD,
        "undamped_dofs": sorted(undamped_kinds),
        # the modes judged (analyses.audit.stability.criterion_class): Level II's
        "criterion": {
            "min_lateral": MIN_LATERAL,
            "window_speed_multiple": WINDOW_MULTIPLE,
            "whirl": "forward",
            "unstable_below_log_dec": UNSTABLE_LOG_DEC,
        },
    }
    if res is not None:
        status = modal_statuses(res, undamped_kinds)
        crit = modal_criteria(res)
        el = [i for i in range(len(res)) if not res.overdamped[i]]
        growing = [int(i) for i in el if is_unstable(res.log_dec[i])]
        judged_modes = [i for i in el if crit[i] == "judged" or i in growing]
        d = {
            "speed_rpm": float(abs(res.speed) * RPM),
            "window_rpm": float(_window(res.assembly.speed_ratio, res.speed) * RPM),
            "stable": bool(res.stable),
            "unstable_modes": growing,
            # positive real eigenvalues (not rigid-body): static divergence, e.g. a negative
            # stiffness; they make the train unstable without an oscillating unstable mode
            "divergent_eigenvalues": int(np.sum(res.real_eigenvalues[~res.rigid_body] > 0)),
            "judged_modes": [int(i) for i in el if crit[i] == "judged"],
            "low_damping_modes": [int(i) for i in el if status[i] == "low damping"],
            # below the threshold and not judged by the criterion: their status says why
            "not_judged_modes": [
                _mode_entry(res, i, status[i]) for i in el if judged(status[i]) is None
            ],
        }
        if judged_modes:
            k = min(judged_modes, key=lambda i: res.log_dec[i])
            d["lowest_log_dec"] = _mode_entry(res, k, status[k])
        d["ok"] = bool(res.stable) and not d["low_damping_modes"]
        out["modal"] = d
    if camp is not None:
        crit, status = campbell_statuses(camp, undamped_kinds)
        ld = np.where(camp.overdamped, np.inf, camp.log_dec)
        rows = track_rows(res, camp)
        per_mode = []
        low_pts = []  # (log dec, track, speed index): the judged and the growing points
        for j in range(ld.shape[1]):
            rank = np.array([_rank(s) for s in status[:, j]])
            pts = np.flatnonzero(rank == rank.min())
            k = int(pts[np.argmin(ld[pts, j])])
            st = str(status[k, j])
            jd = np.flatnonzero((crit[:, j] == "judged") | (status[:, j] == "UNSTABLE"))
            if len(jd):
                kj = int(jd[np.argmin(ld[jd, j])])
                low_pts.append((float(camp.log_dec[kj, j]), j, kj))
            ef = camp.energy_fractions[k, j, 0]
            per_mode.append(
                {
                    "mode": rows[j],
                    "track": j,
                    # judged by the criterion at some speed of the sweep
                    "judged": bool(np.any(crit[:, j] == "judged")),
                    "type": str(camp.mode_type[k, j]),
                    "whirl": str(camp.whirl[k, j]),
                    "energy_lateral": float(ef) if np.isfinite(ef) else None,
                    "min_log_dec": float(camp.log_dec[k, j]),
                    "at_speed_rpm": float(camp.speeds[k] * RPM),
                    "frequency_rpm": float(camp.damped_frequency[k, j] * RPM),
                    "status": st,
                    "result": result_of(judged(st)),
                }
            )
        lowest = None
        if low_pts:
            v, j, k = min(low_pts)
            lowest = {
                "mode": rows[j],
                "track": j,
                "type": str(camp.mode_type[k, j]),
                "min_log_dec": v,
                "at_speed_rpm": float(camp.speeds[k] * RPM),
                "frequency_rpm": float(camp.damped_frequency[k, j] * RPM),
            }
        nj = [d for d in per_mode if d["result"] == NOT_JUDGED]
        out["campbell"] = {
            "speed_range_rpm": [float(camp.speeds[0] * RPM), float(camp.speeds[-1] * RPM)],
            "modes": per_mode,
            "lowest": lowest,
            "lowest_not_judged": min(nj, key=lambda d: d["min_log_dec"]) if nj else None,
            # the verdict is the tracks' results: FAIL when one is FAIL
            "ok": not any(d["result"] == "FAIL" for d in per_mode),
        }
    return out


def _list(v: list) -> str:
    return ", ".join(str(x) for x in v) if v else "–"


def _mode_name(d: dict) -> str:
    """'mode 7' (the modal table's numbering) or 'track 3' when the track has no row there."""
    return f"mode {d['mode']}" if d.get("mode") is not None else f"track {d['track']}"


def _undamped_words(stab: dict) -> str:
    kinds = stab.get("undamped_dofs", [])
    return " or ".join(kinds) if kinds else ""


def _criterion_words(stab: dict) -> str:
    c = stab["criterion"]
    return (
        f"forward whirl, at least {c['min_lateral']:.0%} of the kinetic energy in lateral "
        f"motion, damped frequency up to {c['window_speed_multiple']:g}× the fastest shaft "
        "speed"
    )


def _stability_html(stab: dict) -> str:
    m = stab.get("modal")
    window = f" ({m['window_rpm']:,.0f} cpm at {m['speed_rpm']:,.0f} rpm)" if m is not None else ""
    parts = [
        f"<p>Acceptance threshold: log dec ≥ {LOG_DEC_THRESHOLD} for every mode API 617 Level "
        f"II judges ({_criterion_words(stab)}{window}: the modes of the stability audit, one "
        "definition); a growing mode (log dec below "
        f"{stab['criterion']['unstable_below_log_dec']:.2g}, the eigensolvers' round-off "
        "level) fails whatever it is. The other modes below the threshold are shown, not "
        "judged, with the reason: backward whirl, above 3× speed, or not lateral (less than "
        "half lateral, e.g. a coupled lateral–torsional mode that is mostly torsional, or a "
        "tilting pad's mode, type P)"
        + (
            f"; this model has no {_undamped_words(stab)} damping (its damping matrix has no "
            f"entry on those DOFs), so the log dec of a mode that is mostly "
            f"{_undamped_words(stab)} is zero or only the share of the bearing damping its "
            "lateral part carries: a statement about the model (status "
            f"“no {_undamped_words(stab)} damping in the model”)"
            if stab.get("undamped_dofs")
            else ""
        )
        + ". Modes are numbered as in the modal table at the operating speed.</p>"
    ]
    if m is not None:
        low = m.get("lowest_log_dec")
        parts.append("<table><tr><th class='l'>at operating speed</th><th>value</th></tr>")
        parts.append(f"<tr><td class='l'>speed (rpm)</td><td>{m['speed_rpm']:.0f}</td></tr>")
        parts.append(
            "<tr><td class='l'>all modes stable</td>"
            f"<td>{result_badge(result_of(m['stable']))}</td></tr>"
        )
        parts.append(
            f"<tr><td class='l'>modes judged (forward lateral up to {m['window_rpm']:,.0f} cpm)"
            f"</td><td>{_list(m['judged_modes'])}</td></tr>"
        )
        if low:
            parts.append(
                f"<tr><td class='l'>lowest log dec of a judged mode</td><td>"
                f"{low['log_dec']:.4g} (mode {low['mode']}, {low['frequency_rpm']:.0f} cpm, "
                f"{_e(low['type'])}, {_e(low['whirl'])})</td></tr>"
            )
            parts.append(
                f"<tr><td class='l'>margin to threshold</td>"
                f"<td>{low['log_dec'] - LOG_DEC_THRESHOLD:+.4g}</td></tr>"
            )
        nj = ", ".join(
            f"{d['mode']} ({d['frequency_rpm']:.0f} cpm, {_e(d['type'])}, "
            f"{d['energy_lateral']:.0%} lateral, log dec {d['log_dec']:.3g}: {_e(d['status'])})"
            for d in m["not_judged_modes"]
        )
        parts.append(
            f"<tr><td class='l'>unstable modes</td><td>{_list(m['unstable_modes'])}"
            f"</td></tr><tr><td class='l'>low-damping judged modes (FAIL)</td>"
            f"<td>{_list(m['low_damping_modes'])}</td></tr>"
            "<tr><td class='l'>modes below the threshold, not judged</td>"
            f"<td>{nj or '–'}</td></tr></table>"
        )
    c = stab.get("campbell")
    if c is not None:
        lo, hi = c["speed_range_rpm"]
        parts.append(
            f"<p>Over the Campbell sweep {lo:.0f}..{hi:.0f} rpm, each tracked mode at the speed "
            "of its worst status (unstable, then low damping, then not judged, then stable; "
            "the lowest log dec among those speeds):</p><table><tr><th>mode</th><th>type</th>"
            "<th>whirl</th><th>lateral share</th><th>log dec</th><th>at speed (rpm)</th>"
            "<th>frequency there (cpm)</th><th class='l'>status</th><th>check</th></tr>"
        )
        for d in c["modes"]:
            share = "–" if d["energy_lateral"] is None else f"{d['energy_lateral']:.0%}"
            parts.append(
                f"<tr class='{status_row_class(d['status'])}'><td>{_mode_name(d)}</td>"
                f"<td>{_e(d['type'])}</td><td>{_e(d['whirl'])}</td><td>{share}</td>"
                f"<td>{d['min_log_dec']:.4g}</td>"
                f"<td>{d['at_speed_rpm']:.0f}</td><td>{d['frequency_rpm']:.0f}</td>"
                f"<td class='l'>{_e(d['status'])}</td><td>{result_badge(d['result'])}</td></tr>"
            )
        parts.append("</table>")
    return "\n".join(parts)


def _why_unstable(m: dict, named: set[int]) -> str:
    """What makes an unstable train unstable, in words (never an empty list)."""
    parts = []
    if m["unstable_modes"]:
        parts.append(f"growing modes {', '.join(str(i) for i in m['unstable_modes'])}")
        named.update(m["unstable_modes"])
    n = m.get("divergent_eigenvalues", 0)
    if n:
        parts.append(
            f"{n} positive real eigenvalue{'s' if n > 1 else ''} (static divergence: a "
            "negative stiffness)"
        )
    return ", ".join(parts) or "see the modes table"


def _names(ds: list[dict], named: set[int], most: int = 8) -> str:
    """'modes 2, 6, 11' ('mode 2'; 'modes 2, 6, ... and 12 more', the rest in the tables);
    the mode numbers written go into ``named``."""
    shown = ds[:most]
    named.update(d["mode"] for d in shown if d.get("mode") is not None)
    names = [_mode_name(d).removeprefix("mode ") for d in shown]
    more = f" and {len(ds) - most} more" if len(ds) > most else ""
    return f"{'mode' if len(ds) == 1 else 'modes'} {', '.join(names)}{more}"


def _point(d: dict, v: float, named: set[int], speed_key: str | None) -> str:
    """'mode 33 (215,670 cpm, T) log dec 0.0099[ at 2,000 rpm]'."""
    if d.get("mode") is not None:
        named.add(d["mode"])
    where = f" at {d[speed_key]:,.0f} rpm" if speed_key else ""
    return f"{_mode_name(d)} ({d['frequency_rpm']:,.0f} cpm, {d['type']}) log dec {v:.2g}{where}"


def _not_judged_detail(
    modes: list[dict], named: set[int], speed_key: str | None = None, most: int = 3
) -> str:
    """'no torsional damping in the model: modes 20, 21, 32 undamped (log dec 0), mode 33
    (215,670 cpm, T) log dec 0.0099; ...': grouped by status, the undamped modes by number,
    the ``most`` least damped others with frequency and (lowest) log dec."""
    by: dict[str, list[dict]] = {}
    for d in modes:
        by.setdefault(d["status"], []).append(d)
    out = []
    for st, ds in by.items():
        ld = [d.get("log_dec", d.get("min_log_dec")) for d in ds]
        zero = [d for d, v in zip(ds, ld, strict=True) if v == 0]
        zero.sort(key=lambda d: (d.get("mode") is None, d.get("mode") or 0, d.get("track", 0)))
        damped = sorted(((d, v) for d, v in zip(ds, ld, strict=True) if v != 0), key=lambda x: x[1])
        items = [f"{_names(zero, named)} undamped (log dec 0)"] if zero else []
        items += [_point(d, v, named, speed_key) for d, v in damped[:most]]
        if len(damped) > most:
            items.append(f"{len(damped) - most} more above")
        out.append(f"{st}: {', '.join(items)}")
    return "; ".join(out)


def _fail_detail(fails: list[dict], named: set[int]) -> str:
    """'UNSTABLE: mode 2 (5,294 cpm, L-T-A) log dec -0.31 at 2,000 rpm; low damping: modes
    6, 11': the growing tracks each with where, the others by number."""
    out = []
    grow = [d for d in fails if d["status"] == "UNSTABLE"]
    if grow:
        out.append(
            "UNSTABLE: "
            + ", ".join(_point(d, d["min_log_dec"], named, "at_speed_rpm") for d in grow[:3])
            + (f" and {len(grow) - 3} more" if len(grow) > 3 else "")
        )
    low = [d for d in fails if d["status"] != "UNSTABLE"]
    if low:
        out.append(f"low damping: {_names(low, named)}")
    return "; ".join(out)


def _verdict_lines(stab: dict, max_frequency: float) -> list[tuple]:
    """The summary's stability lines: (key, check, ok, detail, the mode numbers named)."""
    thr = f"log dec ≥ {LOG_DEC_THRESHOLD}"
    lines = []
    m = stab.get("modal")
    if m is not None:
        named: set[int] = set()
        low = m.get("lowest_log_dec")
        if low:
            named.add(low["mode"])
            txt = (
                f"lowest log dec of a judged mode {low['log_dec']:.3g} (mode {low['mode']}, "
                f"{low['frequency_rpm']:,.0f} cpm, {low['type']})"
            )
        else:
            txt = "no judged mode"
        if m["low_damping_modes"]:
            low_d = [{"mode": i} for i in m["low_damping_modes"]]
            txt += f"; low damping: {_names(low_d, named)}"
        state = "stable; " if m["stable"] else f"UNSTABLE: {_why_unstable(m, named)}; "
        lines.append(
            (
                "stability_operating_speed",
                f"stability at {m['speed_rpm']:,.0f} rpm: {thr} for every forward lateral "
                f"mode up to {m['window_rpm']:,.0f} cpm (3× the fastest shaft speed: API 617 "
                f"Level II's modes), no mode growing up to {max_frequency * RPM:,.0f} cpm",
                m["ok"],
                state + txt,
                named,
            )
        )
        if m["not_judged_modes"]:
            named = set()
            detail = _not_judged_detail(m["not_judged_modes"], named)
            lines.append(
                (
                    "not_judged_operating_speed",
                    f"modes below the threshold not judged at {m['speed_rpm']:,.0f} rpm",
                    None,
                    detail,
                    named,
                )
            )
    c = stab.get("campbell")
    if c is not None and (c["lowest"] is not None or c["lowest_not_judged"] is not None):
        lo, hi = c["speed_range_rpm"]
        fails = [d for d in c["modes"] if d["result"] == "FAIL"]
        low = c["lowest"]
        named = set()
        if low:
            detail = (
                f"lowest log dec of a judged mode {low['min_log_dec']:.3g} ({_mode_name(low)}, "
                f"{low['type']}, at {low['at_speed_rpm']:,.0f} rpm)"
            )
            if low.get("mode") is not None:
                named.add(low["mode"])
        else:
            detail = "no judged mode"
        if fails:
            detail += f"; FAIL: {_fail_detail(fails, named)}"
        lines.append(
            (
                "stability_campbell_range",
                f"stability over the Campbell speed range {lo:,.0f}–{hi:,.0f} rpm: {thr} for "
                "every forward lateral mode up to 3× the fastest shaft speed at each speed, "
                "no mode growing",
                c["ok"],
                detail,
                named,
            )
        )
        nj = [d for d in c["modes"] if d["result"] == NOT_JUDGED]
        if nj:
            named = set()
            detail = _not_judged_detail(nj, named, "at_speed_rpm")
            lines.append(
                (
                    "not_judged_campbell_range",
                    f"modes below the threshold not judged over {lo:,.0f}–{hi:,.0f} rpm",
                    None,
                    detail,
                    named,
                )
            )
    return lines


def _verdicts(ctx: Context, stab: dict) -> None:
    for key, check, ok, detail, _ in _verdict_lines(stab, ctx.max_frequency):
        ctx.verdict(key, check, ok, detail)
