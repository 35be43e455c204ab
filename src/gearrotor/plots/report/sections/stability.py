"""Stability section: the log decrement of every mode against the acceptance threshold
(:data:`~..blocks.LOG_DEC_THRESHOLD`, API 617 Level II) at the operating speed (modes section)
and over the Campbell sweep (Campbell section); the first verdicts of the summary."""

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

__all__ = ["StabilitySection"]


class StabilitySection(Section):
    """Shown when the modal analysis or the Campbell diagram ran."""

    def write(self, ctx: Context) -> list[Part]:
        res, camp = ctx.results.get("modal"), ctx.results.get("campbell")
        if res is None and camp is None:
            ctx.summary["stability"] = {"threshold_log_dec": LOG_DEC_THRESHOLD}
            return []
        undamped = model_undamped_kinds(ctx.assembly, ctx.sign * ctx.speed)
        stab = _stability(res, camp, undamped)
        ctx.summary["stability"] = stab
        _verdicts(ctx, stab)
        return [("stability", "Stability margins", _stability_html(stab))]


def _lateral(mode_type: str) -> bool:
    """The API 617 log dec criterion judges modes with lateral motion (type with ``L``)."""
    return "L" in str(mode_type).split("-")


def modal_statuses(res, undamped_kinds: frozenset[str]) -> list[str]:
    """The status (:func:`~..verdicts.mode_status`) of every mode of a modal result."""
    return [
        mode_status(
            res.mode_type[i],
            float(res.log_dec[i]),
            overdamped=bool(res.overdamped[i]),
            undamped_kinds=undamped_kinds,
        )
        for i in range(len(res))
    ]


def _mode_entry(res, i: int, status: str) -> dict:
    return {
        "mode": int(i),
        "frequency_rpm": float(res.frequency_rpm[i]),
        "log_dec": float(res.log_dec[i]),
        "type": res.mode_type[i],
        "whirl": "/".join(res.whirl_per_shaft[i]),
        "status": status,
    }


def _stability(res, camp, undamped_kinds: frozenset[str]) -> dict:
    out: dict = {
        "threshold_log_dec": LOG_DEC_THRESHOLD,
        "undamped_dofs": sorted(undamped_kinds),
    }
    if res is not None:
        status = modal_statuses(res, undamped_kinds)
        el = [i for i in range(len(res)) if not res.overdamped[i]]
        lat = [i for i in el if _lateral(res.mode_type[i])]
        d = {
            "speed_rpm": float(abs(res.speed) * RPM),
            "stable": bool(res.stable),
            "unstable_modes": [int(i) for i in np.flatnonzero(res.unstable)],
            # positive real eigenvalues (not rigid-body): static divergence, e.g. a negative
            # stiffness; they make the train unstable without an oscillating unstable mode
            "divergent_eigenvalues": int(np.sum(res.real_eigenvalues[~res.rigid_body] > 0)),
            "low_damping_modes": [int(i) for i in el if status[i] == "low damping"],
            # modes the lateral criterion does not judge: below the threshold without lateral
            # motion (their status says why)
            "not_judged_modes": [
                _mode_entry(res, i, status[i]) for i in el if judged(status[i]) is None
            ],
        }
        if lat:
            k = min(lat, key=lambda i: res.log_dec[i])
            d["lowest_log_dec"] = _mode_entry(res, k, status[k])
        d["ok"] = bool(res.stable) and not d["low_damping_modes"]
        out["modal"] = d
    if camp is not None:
        ld = np.where(camp.overdamped, np.inf, camp.log_dec)
        rows = track_rows(res, camp)
        per_mode = []
        for j in range(ld.shape[1]):
            k = int(np.argmin(ld[:, j]))
            lateral = bool(any(_lateral(t) for t in camp.mode_type[:, j]))
            # a track is judged as lateral when it has lateral motion anywhere in the sweep
            ty = "L" if lateral else str(camp.mode_type[k, j])
            st = mode_status(
                ty,
                float(camp.log_dec[k, j]),
                overdamped=bool(np.all(camp.overdamped[:, j])),
                undamped_kinds=undamped_kinds,
            )
            per_mode.append(
                {
                    "mode": rows[j],
                    "track": j,
                    "lateral": lateral,
                    "type": str(camp.mode_type[k, j]),
                    "min_log_dec": float(camp.log_dec[k, j]),
                    "at_speed_rpm": float(camp.speeds[k] * RPM),
                    "frequency_rpm": float(camp.damped_frequency[k, j] * RPM),
                    "status": st,
                    "result": result_of(judged(st)),
                }
            )
        judged_modes = [d for d in per_mode if d["lateral"]]
        lowest = min(judged_modes, key=lambda d: d["min_log_dec"]) if judged_modes else None
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


def _stability_html(stab: dict) -> str:
    parts = [
        f"<p>Acceptance threshold: log dec ≥ {LOG_DEC_THRESHOLD} for every mode with lateral "
        "motion (type with L) that is not over-damped (API 617 Level II criterion); a negative "
        "log dec is an unstable mode. Modes without lateral motion below the threshold are "
        "shown, not judged"
        + (
            f"; this model has no {_undamped_words(stab)} damping (its damping matrix has no "
            f"entry on those DOFs), so their log dec is zero or only the share of the bearing "
            "damping their small lateral part carries: a statement about the model (status "
            f"“no {_undamped_words(stab)} damping in the model”)"
            if stab.get("undamped_dofs")
            else ""
        )
        + ". Modes are numbered as in the modal table at the operating speed.</p>"
    ]
    m = stab.get("modal")
    if m is not None:
        low = m.get("lowest_log_dec")
        parts.append("<table><tr><th class='l'>at operating speed</th><th>value</th></tr>")
        parts.append(f"<tr><td class='l'>speed (rpm)</td><td>{m['speed_rpm']:.0f}</td></tr>")
        parts.append(
            "<tr><td class='l'>all modes stable</td>"
            f"<td>{result_badge(result_of(m['stable']))}</td></tr>"
        )
        if low:
            parts.append(
                f"<tr><td class='l'>lowest log dec of a lateral mode</td><td>"
                f"{low['log_dec']:.4g} (mode {low['mode']}, {low['frequency_rpm']:.0f} cpm, "
                f"{_e(low['type'])}, {_e(low['whirl'])})</td></tr>"
            )
            parts.append(
                f"<tr><td class='l'>margin to threshold</td>"
                f"<td>{low['log_dec'] - LOG_DEC_THRESHOLD:+.4g}</td></tr>"
            )
        nj = ", ".join(
            f"{d['mode']} ({d['frequency_rpm']:.0f} cpm, {_e(d['type'])}, log dec "
            f"{d['log_dec']:.3g}: {_e(d['status'])})"
            for d in m["not_judged_modes"]
        )
        parts.append(
            f"<tr><td class='l'>unstable modes</td><td>{_list(m['unstable_modes'])}"
            f"</td></tr><tr><td class='l'>low-damping lateral modes (FAIL)</td>"
            f"<td>{_list(m['low_damping_modes'])}</td></tr>"
            "<tr><td class='l'>modes without lateral motion below the threshold (not judged)"
            f"</td><td>{nj or '–'}</td></tr></table>"
        )
    c = stab.get("campbell")
    if c is not None:
        lo, hi = c["speed_range_rpm"]
        parts.append(
            f"<p>Over the Campbell sweep {lo:.0f}..{hi:.0f} rpm, lowest log dec of each "
            "tracked mode:</p><table><tr><th>mode</th><th>type</th><th>min log dec</th>"
            "<th>at speed (rpm)</th><th>frequency there (cpm)</th><th class='l'>status</th>"
            "<th>check</th></tr>"
        )
        for d in c["modes"]:
            parts.append(
                f"<tr class='{status_row_class(d['status'])}'><td>{_mode_name(d)}</td>"
                f"<td>{_e(d['type'])}</td><td>{d['min_log_dec']:.4g}</td>"
                f"<td>{d['at_speed_rpm']:.0f}</td><td>{d['frequency_rpm']:.0f}</td>"
                f"<td class='l'>{_e(d['status'])}</td><td>{result_badge(d['result'])}</td></tr>"
            )
        parts.append("</table>")
    return "\n".join(parts)


def _why_unstable(m: dict) -> str:
    """What makes an unstable train unstable, in words (never an empty list)."""
    parts = []
    if m["unstable_modes"]:
        parts.append(f"growing modes {', '.join(str(i) for i in m['unstable_modes'])}")
    n = m.get("divergent_eigenvalues", 0)
    if n:
        parts.append(
            f"{n} positive real eigenvalue{'s' if n > 1 else ''} (static divergence: a "
            "negative stiffness)"
        )
    return ", ".join(parts) or "see the modes table"


def _names(ds: list[dict], most: int = 8) -> str:
    """'modes 2, 6, 11' ('mode 2'; 'modes 2, 6, ... and 12 more', the rest in the tables)."""
    names = [_mode_name(d).removeprefix("mode ") for d in ds]
    more = f" and {len(names) - most} more" if len(names) > most else ""
    return f"{'mode' if len(names) == 1 else 'modes'} {', '.join(names[:most])}{more}"


def _not_judged_detail(modes: list[dict], speed_key: str | None = None, most: int = 3) -> str:
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
        damped = sorted(((d, v) for d, v in zip(ds, ld, strict=True) if v != 0), key=lambda x: x[1])
        items = [f"{_names(zero)} undamped (log dec 0)"] if zero else []
        for d, v in damped[:most]:
            where = f" at {d[speed_key]:,.0f} rpm" if speed_key else ""
            items.append(
                f"{_mode_name(d)} ({d['frequency_rpm']:,.0f} cpm, {d['type']}) log dec "
                f"{v:.2g}{where}"
            )
        if len(damped) > most:
            items.append(f"{len(damped) - most} more above")
        out.append(f"{st}: {', '.join(items)}")
    return "; ".join(out)


def _verdicts(ctx: Context, stab: dict) -> None:
    thr = f"log dec ≥ {LOG_DEC_THRESHOLD}"
    m = stab.get("modal")
    if m is not None:
        low = m.get("lowest_log_dec")
        txt = (
            f"lowest log dec of a lateral mode {low['log_dec']:.3g} (mode {low['mode']}, "
            f"{low['frequency_rpm']:,.0f} cpm, {low['type']})"
            if low
            else "no lateral mode"
        )
        if m["low_damping_modes"]:
            low_d = [{"mode": i} for i in m["low_damping_modes"]]
            txt += f"; low damping: {_names(low_d)}"
        ctx.verdict(
            "stability_operating_speed",
            f"stability at {m['speed_rpm']:,.0f} rpm: every lateral mode up to "
            f"{ctx.max_frequency * RPM:,.0f} cpm, {thr}",
            m["ok"],
            ("stable; " if m["stable"] else f"UNSTABLE: {_why_unstable(m)}; ") + txt,
        )
        if m["not_judged_modes"]:
            ctx.verdict(
                "not_lateral_operating_speed",
                f"modes without lateral motion at {m['speed_rpm']:,.0f} rpm",
                None,
                _not_judged_detail(m["not_judged_modes"]),
            )
    c = stab.get("campbell")
    if c is not None and (c["lowest"] is not None or c["lowest_not_judged"] is not None):
        lo, hi = c["speed_range_rpm"]
        fails = [d for d in c["modes"] if d["result"] == "FAIL"]
        low = c["lowest"]
        detail = (
            f"lowest log dec of a lateral mode {low['min_log_dec']:.3g} ({_mode_name(low)}, "
            f"{low['type']}, at {low['at_speed_rpm']:,.0f} rpm)"
            if low
            else "no lateral mode"
        )
        if fails:
            detail += f"; FAIL: {_names(fails)}"
        ctx.verdict(
            "stability_campbell_range",
            f"stability over the Campbell speed range {lo:,.0f}–{hi:,.0f} rpm: every lateral "
            f"mode, {thr}",
            c["ok"],
            detail,
        )
        nj = [d for d in c["modes"] if d["result"] == NOT_JUDGED]
        if nj:
            ctx.verdict(
                "not_lateral_campbell_range",
                f"modes without lateral motion over {lo:,.0f}–{hi:,.0f} rpm",
                None,
                _not_judged_detail(nj, "at_speed_rpm"),
            )
