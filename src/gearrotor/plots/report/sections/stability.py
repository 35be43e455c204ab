"""Stability section: the log decrement of every mode against the acceptance threshold
(:data:`~..blocks.LOG_DEC_THRESHOLD`, API 617 Level II) at the operating speed (modes section)
and over the Campbell sweep (Campbell section); the first verdicts of the summary."""

from __future__ import annotations

import numpy as np

from ..base import Context, Part, Section
from ..blocks import LOG_DEC_THRESHOLD, RPM, _badge, _e

__all__ = ["StabilitySection"]


class StabilitySection(Section):
    """Shown when the modal analysis or the Campbell diagram ran."""

    def write(self, ctx: Context) -> list[Part]:
        res, camp = ctx.results.get("modal"), ctx.results.get("campbell")
        stab = _stability(res, camp)
        ctx.summary["stability"] = stab
        ctx.verdicts += _verdicts(stab)
        if res is None and camp is None:
            return []
        return [("stability", "Stability margins", _stability_html(stab))]


def _lateral(mode_type: str) -> bool:
    """The API 617 log dec criterion judges modes with lateral motion (type with ``L``)."""
    return "L" in str(mode_type)


def _stability(res, camp) -> dict:
    out: dict = {"threshold_log_dec": LOG_DEC_THRESHOLD}
    if res is not None:
        el = [i for i in range(len(res)) if not res.overdamped[i]]
        lat = [i for i in el if _lateral(res.mode_type[i])]
        d = {
            "speed_rpm": float(res.speed * RPM),
            "stable": bool(res.stable),
            "unstable_modes": [int(i) for i in np.flatnonzero(res.unstable)],
            # positive real eigenvalues (not rigid-body): static divergence, e.g. a negative
            # stiffness; they make the train unstable without an oscillating unstable mode
            "divergent_eigenvalues": int(np.sum(res.real_eigenvalues[~res.rigid_body] > 0)),
            "low_damping_modes": [
                int(i)
                for i in lat
                if 0 <= res.log_dec[i] < LOG_DEC_THRESHOLD and not res.unstable[i]
            ],
            "undamped_non_lateral_modes": [
                int(i) for i in el if i not in lat and res.mode_class[i] == "undamped"
            ],
        }
        if lat:
            k = min(lat, key=lambda i: res.log_dec[i])
            d["lowest_log_dec"] = {
                "mode": int(k),
                "frequency_rpm": float(res.frequency_rpm[k]),
                "log_dec": float(res.log_dec[k]),
                "type": res.mode_type[k],
                "whirl": "/".join(res.whirl_per_shaft[k]),
            }
        d["ok"] = bool(res.stable) and not d["low_damping_modes"]
        out["modal"] = d
    if camp is not None:
        ld = np.where(camp.overdamped, np.inf, camp.log_dec)
        names = _modal_rows(res, camp)
        per_mode = []
        for j in range(ld.shape[1]):
            k = int(np.argmin(ld[:, j]))
            per_mode.append(
                {
                    "mode": names[j],
                    "track": j,
                    "lateral": bool(any(_lateral(t) for t in camp.mode_type[:, j])),
                    "min_log_dec": float(camp.log_dec[k, j]),
                    "at_speed_rpm": float(camp.speeds[k] * RPM),
                    "frequency_rpm": float(camp.damped_frequency[k, j] * RPM),
                }
            )
        judged = [d for d in per_mode if d["lateral"]]
        lowest = min(judged, key=lambda d: d["min_log_dec"]) if judged else None
        out["campbell"] = {
            "speed_range_rpm": [float(camp.speeds[0] * RPM), float(camp.speeds[-1] * RPM)],
            "modes": per_mode,
            "lowest": lowest,
            "ok": lowest is None or lowest["min_log_dec"] >= LOG_DEC_THRESHOLD,
        }
    return out


def _modal_rows(res, camp) -> list[int | None]:
    """Per Campbell track, the row of the modal table (at the operating speed) it is, so that
    every check names a mode by one numbering: a one-to-one assignment by frequency at the
    operating speed (a sweep point); None for a track without a row within 1 %."""
    from scipy.optimize import linear_sum_assignment

    n = camp.damped_frequency.shape[1]
    if res is None:
        return [None] * n
    k = int(np.argmin(np.abs(camp.speeds - res.speed)))
    rows = [i for i in range(len(res)) if not res.overdamped[i]]
    if not rows or abs(camp.speeds[k] - res.speed) > 1e-6 * max(abs(res.speed), 1.0):
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


def _list(v: list) -> str:
    return ", ".join(str(x) for x in v) if v else "–"


def _mode_name(d: dict) -> str:
    """'mode 7' (the modal table's numbering) or 'track 3' when the track has no row there."""
    return f"mode {d['mode']}" if d.get("mode") is not None else f"Campbell track {d['track']}"


def _stability_html(stab: dict) -> str:
    parts = [
        f"<p>Acceptance threshold: log dec ≥ {LOG_DEC_THRESHOLD} for every mode with lateral "
        "motion (type with L) that is not over-damped (API 617 Level II criterion); a negative "
        "log dec is an unstable mode. Modes are numbered as in the modal table at the "
        "operating speed.</p>"
    ]
    m = stab.get("modal")
    if m is not None:
        low = m.get("lowest_log_dec")
        parts.append("<table><tr><th class='l'>at operating speed</th><th>value</th></tr>")
        parts.append(f"<tr><td class='l'>speed (rpm)</td><td>{m['speed_rpm']:.0f}</td></tr>")
        parts.append(f"<tr><td class='l'>all modes stable</td><td>{_badge(m['stable'])}</td></tr>")
        if low:
            parts.append(
                f"<tr><td class='l'>lowest log dec</td><td>{low['log_dec']:.4g} (mode "
                f"{low['mode']}, {low['frequency_rpm']:.0f} cpm, {_e(low['type'])}, "
                f"{_e(low['whirl'])})</td></tr>"
            )
            parts.append(
                f"<tr><td class='l'>margin to threshold</td>"
                f"<td>{low['log_dec'] - LOG_DEC_THRESHOLD:+.4g}</td></tr>"
            )
        parts.append(
            f"<tr><td class='l'>unstable modes</td><td>{_list(m['unstable_modes'])}"
            f"</td></tr><tr><td class='l'>low-damping modes</td>"
            f"<td>{_list(m['low_damping_modes'])}</td></tr>"
            "<tr><td class='l'>undamped modes without lateral motion (not judged: the model "
            f"has no damping on them)</td><td>{_list(m['undamped_non_lateral_modes'])}</td></tr>"
            "</table>"
        )
    c = stab.get("campbell")
    if c is not None:
        lo, hi = c["speed_range_rpm"]
        parts.append(
            f"<p>Over the Campbell sweep {lo:.0f}..{hi:.0f} rpm, lowest log dec of each "
            "tracked mode:</p><table><tr><th>mode</th><th>min log dec</th>"
            "<th>at speed (rpm)</th><th>frequency there (cpm)</th><th>check</th></tr>"
        )
        for d in c["modes"]:
            cls = (
                "bad"
                if d["min_log_dec"] < 0
                else ("warn" if d["min_log_dec"] < LOG_DEC_THRESHOLD else "")
            )
            parts.append(
                f"<tr class='{cls}'><td>{_mode_name(d)}</td><td>{d['min_log_dec']:.4g}</td>"
                f"<td>{d['at_speed_rpm']:.0f}</td><td>{d['frequency_rpm']:.0f}</td>"
                f"<td>{_badge(d['min_log_dec'] >= LOG_DEC_THRESHOLD)}</td></tr>"
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


def _verdicts(stab: dict) -> list[dict]:
    out = []
    m = stab.get("modal")
    if m is not None:
        low = m.get("lowest_log_dec")
        txt = (
            f"lowest log dec {low['log_dec']:.3g} (mode {low['mode']}, "
            f"{low['frequency_rpm']:.0f} cpm)"
            if low
            else "no lightly damped mode"
        )
        out.append(
            {
                "check": f"stability at {m['speed_rpm']:.0f} rpm",
                "ok": m["ok"],
                "detail": ("stable; " if m["stable"] else f"UNSTABLE: {_why_unstable(m)}; ") + txt,
            }
        )
    c = stab.get("campbell")
    if c is not None and c["lowest"] is not None:
        lo = c["lowest"]
        out.append(
            {
                "check": "stability over the Campbell speed range",
                "ok": c["ok"],
                "detail": f"lowest log dec {lo['min_log_dec']:.3g} ({_mode_name(lo)} at "
                f"{lo['at_speed_rpm']:.0f} rpm)",
            }
        )
    return out
