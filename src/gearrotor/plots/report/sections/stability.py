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


def _stability(res, camp) -> dict:
    out: dict = {"threshold_log_dec": LOG_DEC_THRESHOLD}
    if res is not None:
        el = [i for i in range(len(res)) if not res.overdamped[i]]
        d = {
            "speed_rpm": float(res.speed * RPM),
            "stable": bool(res.stable),
            "unstable_modes": [int(i) for i in np.flatnonzero(res.unstable)],
            # positive real eigenvalues (not rigid-body): static divergence, e.g. a negative
            # stiffness; they make the train unstable without an oscillating unstable mode
            "divergent_eigenvalues": int(np.sum(res.real_eigenvalues[~res.rigid_body] > 0)),
            "low_damping_modes": [
                int(i)
                for i in el
                if 0 <= res.log_dec[i] < LOG_DEC_THRESHOLD and not res.unstable[i]
            ],
        }
        if el:
            k = min(el, key=lambda i: res.log_dec[i])
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
        per_mode = []
        for j in range(ld.shape[1]):
            k = int(np.argmin(ld[:, j]))
            per_mode.append(
                {
                    "mode": j,
                    "min_log_dec": float(camp.log_dec[k, j]),
                    "at_speed_rpm": float(camp.speeds[k] * RPM),
                    "frequency_rpm": float(camp.damped_frequency[k, j] * RPM),
                }
            )
        lowest = min(per_mode, key=lambda d: d["min_log_dec"]) if per_mode else None
        out["campbell"] = {
            "speed_range_rpm": [float(camp.speeds[0] * RPM), float(camp.speeds[-1] * RPM)],
            "modes": per_mode,
            "lowest": lowest,
            "ok": lowest is None or lowest["min_log_dec"] >= LOG_DEC_THRESHOLD,
        }
    return out


def _stability_html(stab: dict) -> str:
    parts = [
        f"<p>Acceptance threshold: log dec ≥ {LOG_DEC_THRESHOLD} for every mode that is not "
        "over-damped (API 617 Level II criterion); a negative log dec is an unstable "
        "mode.</p>"
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
            f"<tr><td class='l'>unstable modes</td><td>{m['unstable_modes'] or '–'}"
            f"</td></tr><tr><td class='l'>low-damping modes</td>"
            f"<td>{m['low_damping_modes'] or '–'}</td></tr></table>"
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
                f"<tr class='{cls}'><td>{d['mode']}</td><td>{d['min_log_dec']:.4g}</td>"
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
                "detail": f"lowest log dec {lo['min_log_dec']:.3g} (mode {lo['mode']} at "
                f"{lo['at_speed_rpm']:.0f} rpm)",
            }
        )
    return out
