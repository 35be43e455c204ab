"""Mesh-response section (``--analyses mesh_response``, not run by default): the periodic
steady state over speed under the gear-mesh excitation and unbalance
(:func:`gearrotor.analyses.lateral.mesh_response.mesh_response`): DTE and dynamic factor against
speed with ISO 6336-1's K_v, probe amplitudes and bearing forces at 1x, 1x and 2x mesh frequency,
and the numbers at the operating speed; contact loss in the operating range is a FAIL (the
teeth separate, the linear response does not hold)."""

from __future__ import annotations

import numpy as np

from ....errors import ModelError
from ..base import Context, Part, Section
from ..blocks import RPM, _e, _fmt

__all__ = ["MeshResponseSection"]

#: speeds of the sweep, from 5 % to 125 % of the operating speed
N_SPEEDS = 80


class MeshResponseSection(Section):
    analysis = "mesh_response"
    default = False

    def check(self, ctx: Context) -> None:
        if not ctx.train.meshes:
            raise ModelError(
                "the mesh response needs a gear mesh",
                field="--analyses",
                value="mesh_response",
                expected="a model with [[meshes]]",
            )

    def run(self, ctx: Context) -> None:
        from ....analyses.lateral.mesh_response import mesh_response

        speeds = ctx.sweep(0.05 * ctx.speed, 1.25 * ctx.speed, N_SPEEDS, "mesh response")
        ctx.results["mesh_response"] = mesh_response(ctx.assembly.train, speeds=speeds)

    def write(self, ctx: Context) -> list[Part]:
        res = ctx.results.get("mesh_response")
        if res is None:
            return []
        from ...mesh_response import plot_bearing_forces, plot_mesh_response

        ctx.save(plot_mesh_response(res, title=ctx.train.name), "mesh_response.png")
        ctx.save(plot_bearing_forces(res), "mesh_bearing_forces.png")
        lo, hi = ctx.api_range
        in_range = (res.speed >= lo * (1 - 1e-9)) & (res.speed <= hi * (1 + 1e-9))
        i_op = int(np.argmin(np.abs(res.speed - ctx.speed)))
        summary = res.to_dict()
        summary["operating_speed_rpm"] = float(res.speed[i_op] * RPM)
        ctx.summary["mesh_response"] = summary
        if not in_range.any():  # an operating speed, not a range: the nearest sweep speed
            in_range[i_op] = True
        lost = np.flatnonzero(res.contact_loss.any(axis=1) & in_range)
        ctx.verdict(
            "mesh_contact",
            "gear teeth stay in contact (periodic mesh response, operating range)",
            not len(lost),
            "contact loss at " + ", ".join(f"{res.speed_rpm[i]:.0f}" for i in lost[:6]) + " rpm"
            if len(lost)
            else f"minimum mesh force {res.force_min[in_range].min():.4g} N > 0",
        )
        return [("mesh-response", "Gear mesh response over speed", _html(ctx, res, i_op))]


def _html(ctx: Context, res, i: int) -> str:

    rows = [
        f"<p>Harmonic balance of the linear time-periodic equations at {len(res.speed)} "
        f"speeds ({res.speed_rpm.min():.0f}–{res.speed_rpm.max():.0f} rpm), "
        f"{res.harmonics} mesh harmonics; values at {res.speed_rpm[i]:.0f} rpm. "
        "DTE: the mesh deflection along the line of action about its mean (rms); dynamic "
        "factor: largest over mean mesh force.</p>",
        "<table><tr><th>mesh</th><th>law</th><th>mesh frequency (cpm)</th>"
        "<th>DTE rms (µm)</th><th>max DTE rms (µm) at rpm</th><th>dynamic factor</th>"
        "<th>ISO 6336-1 K_v</th><th>contact loss</th></tr>",
    ]
    for k, name in enumerate(res.meshes):
        j = int(np.nanargmax(res.dte_rms[:, k]))
        iso = res.iso_kv[i, k] if res.iso_kv is not None else np.nan
        rows.append(
            f"<tr><td>{_e(name)}</td><td>{_e(res.laws[k])}</td>"
            f"<td>{res.mesh_frequency[i, k] * RPM:.0f}</td>"
            f"<td>{_fmt(res.dte_rms[i, k] * 1e6, '.4g')}</td>"
            f"<td>{_fmt(res.dte_rms[j, k] * 1e6, '.4g')} at {res.speed_rpm[j]:.0f}</td>"
            f"<td>{_fmt(res.dynamic_factor[i, k], '.4g')}</td>"
            f"<td>{_fmt(iso if np.isfinite(iso) else None, '.4g')}</td>"
            f"<td>{int(res.contact_loss[:, k].sum())} of {len(res.speed)} speeds</td></tr>"
        )
    rows.append("</table>")
    rows.append(
        "<table><tr><th>probe</th><th>1x (µm 0-pk)</th><th>1x mesh (µm)</th>"
        "<th>2x mesh (µm)</th></tr>"
    )
    for p, name in enumerate(res.probes):
        rows.append(
            f"<tr><td>{_e(name)}</td><td>{_fmt(res.probe_1x[i, p] * 1e6, '.4g')}</td>"
            f"<td>{_fmt(res.probe_mesh[i, p, :, 0].max() * 1e6, '.4g')}</td>"
            f"<td>{_fmt(res.probe_mesh[i, p, :, 1].max() * 1e6, '.4g')}</td></tr>"
        )
    rows.append("</table>")
    rows += [f"<p class='note'>{_e(n)}</p>" for n in res.notes]
    for name, alt in (
        ("mesh_response.png", "DTE, dynamic factor and probe amplitudes against speed"),
        ("mesh_bearing_forces.png", "bearing forces against speed"),
    ):
        data = ctx.png_data(name)
        rows.append(
            f'<p><img src="data:image/png;base64,{data}" alt="{_e(alt)}" '
            f'title="{_e(name)}" style="max-width:100%"></p>'
        )
    return "\n".join(rows)
