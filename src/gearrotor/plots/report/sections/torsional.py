"""Torsional section (``--analyses torsional``, not run by default): the torsional audit of
:mod:`gearrotor.analyses.torsional` — modes along the train, the interference diagram with its
separation margins (a verdict), a forced response and, when the model has ``[torsional]``
drives and loads, their start-up (or short-circuit) transient with peak torques and fatigue.

What the report chooses for the user (stated on the page; the ``gearrotor torsional`` commands
take every choice as an option):

* operating range: the model's ``operating_speed_range``, else the report's speed; margin 10 %;
* forced response: a representative excitation of 1 % of each drive's rated torque at 1x and
  at 2x of its shaft (no drive: of the largest static shaft torque; no torque at all: skipped),
  over 0.5..1.2 × the operating speed;
* transient: from rest (``TRANSIENT_MIN`` s, or 2 s past the model's last event: load step,
  voltage change, trip, fault clearing); fatigue against a representative S-N curve of shaft
  steel in shear (``SN_CURVE``), which the page names — not a material property of the model.
"""

from __future__ import annotations

import numpy as np

from ..base import Context, Part, Section
from ..blocks import RPM, _badge, _e, _fmt

__all__ = ["TorsionalSection", "SN_CURVE", "TRANSIENT_MIN", "transient_duration"]

#: Representative S-N curve (Basquin, shear stress amplitude): m, stress, cycles, endurance.
SN_CURVE = {"m": 8.0, "stress": "200 MPa", "cycles": 1e4, "endurance_limit": "60 MPa"}
#: Shortest transient the report runs, s.
TRANSIENT_MIN = 20.0
HZ = 2 * np.pi


def transient_duration(train) -> float:
    """``TRANSIENT_MIN`` s, or 2 s past the model's last drive or load event."""
    tors = train.torsional
    events = [0.0]
    for d in tors.drives if tors else []:
        volt = getattr(d, "voltage", None)
        if volt is not None:
            events.extend(volt.time)
        sc = getattr(d, "short_circuit", None)
        if sc is not None:
            events.append(sc.clear_time if sc.clear_time is not None else sc.time + 1.0)
        if d.trip_time is not None:
            events.append(d.trip_time)
    for ld in tors.loads if tors else []:
        events.extend(s.time for s in ld.steps)
    return max(TRANSIENT_MIN, max(events) + 2.0)


class TorsionalSection(Section):
    analysis = "torsional"
    default = False

    def run(self, ctx: Context) -> None:
        from ....analyses.torsional import (
            SNCurve,
            fatigue,
            interference,
            torsional_model,
            torsional_modes,
            torsional_response,
            torsional_transient,
        )

        train = ctx.train
        tm = torsional_model(train)
        modes = torsional_modes(tm)
        rng = train.operating_speed_range
        lo, hi = (abs(rng[0]), abs(rng[1])) if rng is not None else (ctx.speed, ctx.speed)
        out = {"model": tm, "modes": modes, "range": (lo, hi)}
        out["interference"] = interference(modes, speed_range=(lo, hi))
        exc, basis = _excitations(tm)
        if exc:
            speeds = np.linspace(0.5 * ctx.speed, 1.2 * ctx.speed, 200)
            out["response"] = torsional_response(tm, excitations=exc, speeds=speeds)
            out["response_basis"] = basis
        tors = train.torsional
        if tors is not None and tors.drives and tors.loads:
            t_end = transient_duration(train)
            tr = torsional_transient(tm, t_end=t_end)
            out["transient"] = tr
            out["fatigue"] = fatigue(tr, SNCurve.from_point(**SN_CURVE))
        ctx.results["torsional"] = out

    def write(self, ctx: Context) -> list[Part]:
        res = ctx.results.get("torsional")
        if res is None:  # (before the imports: they load the torsional analyses)
            return []
        from ...torsional import (
            plot_fatigue_damage,
            plot_interference,
            plot_torsional_modes,
            plot_torsional_response,
            plot_torsional_transient,
        )

        modes, inter = res["modes"], res["interference"]
        summary = {
            "modes": modes.to_dict()["modes"],
            "interference": inter.to_dict(),
        }
        n_fail = len(inter.failures)
        ctx.verdict(
            "torsional_separation_margins",
            "API 617 torsional separation margins",
            inter.passes,
            f"{len(inter.crossings)} crossings, {n_fail} below the "
            f"{inter.required_margin:.0%} margin",
        )
        ctx.png(plot_torsional_modes, "torsional_modes.png", modes)
        ctx.png(plot_interference, "torsional_interference.png", inter)
        body = _modes_html(modes) + _img(ctx, "torsional_modes.png", "torsional mode shapes")
        body += _interference_html(inter)
        body += _img(ctx, "torsional_interference.png", "torsional interference diagram")
        resp = res.get("response")
        if resp is not None:
            summary["response"] = {**resp.to_dict(), "excitation": res["response_basis"]}
            ctx.png(plot_torsional_response, "torsional_response.png", resp)
            body += _response_html(resp, res["response_basis"])
            body += _img(ctx, "torsional_response.png", "torsional forced response")
        tr = res.get("transient")
        if tr is not None:
            fat = res["fatigue"]
            summary["transient"] = tr.to_dict()
            summary["fatigue"] = fat.to_dict()
            ctx.png(plot_torsional_transient, "torsional_transient.png", tr)
            ctx.png(plot_fatigue_damage, "torsional_fatigue.png", fat)
            body += _transient_html(tr, fat)
            body += _img(ctx, "torsional_transient.png", "torsional transient")
            body += _img(ctx, "torsional_fatigue.png", "fatigue damage per element")
        ctx.summary["torsional"] = summary
        return [("torsional", "Torsional analysis", body)]


def _excitations(tm):
    """1 % of each drive's rated torque at 1x and 2x of its shaft (module docstring)."""
    from ....analyses.torsional import HarmonicTorque, pack_laws

    laws = pack_laws(tm.train)
    out, basis = [], []
    for j in np.flatnonzero(laws.is_drive):
        s, node = (int(x) for x in laws.nodes[j])
        amp = 0.01 * float(laws.rated_torque[j])
        shaft = tm.train.shafts[s].name
        for order in (1.0, 2.0):
            out.append(HarmonicTorque(shaft=shaft, node=node, amplitude=amp, order=order))
        basis.append(f"{amp:.4g} N·m (1 % of {laws.names[j]}'s rated torque) at 1x and 2x")
    if not out and len(tm.el_stiffness):
        f0 = tm.nominal_torques() if tm.train.torsional else None
        if f0 is not None and np.any(f0):
            th, _ = tm.static_twist(f0)
            amp = 0.01 * float(np.abs(tm.element_torque(th)).max())
            s = int(tm.node_shaft[int(np.argmax(np.abs(f0)))])
            node = int(np.argmax(np.abs(f0))) - int(np.flatnonzero(tm.node_shaft == s)[0])
            name = tm.shaft_names[s]
            for order in (1.0, 2.0):
                out.append(HarmonicTorque(shaft=name, node=node, amplitude=amp, order=order))
            basis.append(f"{amp:.4g} N·m (1 % of the largest static shaft torque) at 1x and 2x")
    return out, "; ".join(basis)


def _img(ctx: Context, name: str, alt: str) -> str:
    """The PNG just written, inline (data URI: the page stays self-contained)."""

    data = ctx.png_data(name)
    return (
        f'<p><img src="data:image/png;base64,{data}" alt="{_e(alt)}" '
        f'title="{_e(name)}" style="max-width:100%"></p>'
    )


def _modes_html(modes) -> str:
    labels = modes.model.element_labels()
    rows = [
        f"<p>Torsional model: {modes.model.n} DOF, {modes.model.mesh} meshes; modes hold at "
        "every speed (no speed-dependent term acts in torsion).</p>",
        "<h3>Torsional modes</h3><table><tr><th>#</th><th>frequency (Hz)</th>"
        "<th>frequency (cpm)</th><th>damping ratio</th><th class='l'>damped mostly by</th>"
        "<th class='l'>largest stress</th></tr>",
    ]
    for i in range(min(len(modes), 10)):
        if modes.rigid_body[i]:
            note = "rigid-body rotation"
        else:
            note = labels[int(modes.max_stress_element[i])]
        by = next(iter(modes.sources(i)), "–")
        rows.append(
            f"<tr><td>{i}</td><td>{modes.frequency_hz[i]:.2f}</td>"
            f"<td>{modes.frequency_rpm[i]:.0f}</td><td>{modes.damping_ratio[i]:.4f}</td>"
            f"<td class='l'>{_e(by)}</td><td class='l'>{_e(note)}</td></tr>"
        )
    rows.append("</table>")
    rows.extend(f"<p>{_e(line)}</p>" for line in modes.mesh_mode_notes())
    return "\n".join(rows)


def _interference_html(inter) -> str:
    label = inter.range_label
    rows = [
        f"<h3>Interference diagram</h3><p>{label[0].upper() + label[1:]} (reference "
        f"shaft), required separation {inter.required_margin:.0%} (API 617 / API RP 684); modes "
        f"up to {inter.max_frequency / HZ:.0f} Hz checked.</p>",
        "<table><tr><th>mode</th><th>frequency (Hz)</th><th class='l'>excitation</th>"
        "<th>speed (rpm)</th><th>margin</th><th>result</th><th class='l'>where</th></tr>",
    ]
    for c in inter.crossings:
        sp = "–" if c.speed is None else f"{c.speed * RPM:.0f}"
        rows.append(
            f"<tr><td>{c.mode}</td><td>{c.natural_frequency / HZ:.2f}</td>"
            f"<td class='l'>{_e(c.line)}</td><td>{sp}</td><td>{c.margin:.1%}</td>"
            f"<td>{_badge(c.passes)}</td><td class='l'>{_e(c.location)}</td></tr>"
        )
    rows.append("</table>")
    return "\n".join(rows)


def _response_html(resp, basis: str) -> str:
    d = resp.to_dict()
    pk = d["peak"]
    text = (
        f"<h3>Forced response</h3><p>Representative excitation: {_e(basis)}, "
        f"{d['speeds_rpm'][0]:.0f}–{d['speeds_rpm'][-1]:.0f} rpm. "
    )
    if pk is not None:
        text += (
            f"Largest alternating shear stress {pk['shear_stress_Pa'] / 1e6:.3g} MPa in "
            f"{_e(pk['element'])} at {pk['speed_rpm']:.0f} rpm. "
        )
    for m in d["meshes"]:
        lost = m["contact_loss_speeds_rpm"]
        if lost is None:
            continue
        text += (
            f"Mesh {_e(m['name'])}: "
            + (
                f"<b>load reversal (tooth separation)</b> at {min(lost):.0f}–{max(lost):.0f} rpm"
                if lost
                else "no load reversal"
            )
            + ". "
        )
    return text + "</p>"


def _transient_html(tr, fat) -> str:
    d = tr.to_dict()
    t_end = d["t_end_s"]
    pull = [
        f"{_e(x['name'])} pulls in at {x['pull_in_time_s']:.2f} s"
        for x in d["laws"]
        if x["pull_in_time_s"] is not None
    ]
    rows = [
        f"<h3>Transient of the model's drives and loads</h3><p>0–{t_end:g} s from rest "
        f"(trapezoidal rule, dt {tr.dt:.3g} s; energy residual {tr.energy_error:.1e} of the "
        f"drives' work){'; ' + '; '.join(pull) if pull else ''}.</p>",
        "<table><tr><th class='l'>shaft</th><th>section</th><th>peak torque (N·m)</th>"
        "<th>rated (N·m)</th><th>peak / rated</th><th>peak stress (MPa)</th></tr>",
    ]
    for r in tr.section_table():
        rows.append(
            f"<tr><td class='l'>{_e(r['shaft'])}</td><td>{r['section']}</td>"
            f"<td>{r['peak_torque_Nm']:.4g}</td><td>{_fmt(r['rated_torque_Nm'], '.4g')}</td>"
            f"<td>{_fmt(r['peak_over_rated'])}</td>"
            f"<td>{r['peak_shear_stress_Pa'] / 1e6:.3g}</td></tr>"
        )
    rows.append("</table>")
    n = fat.allowable_starts
    sn = SN_CURVE
    rows.append(
        f"<p>Fatigue (rainflow, ASTM E1049; Miner's rule) against a representative S-N curve of "
        f"shaft steel in shear, m = {sn['m']:g}, {sn['stress']} at {sn['cycles']:g} cycles, "
        f"endurance limit {sn['endurance_limit']} (not from the model: use <code>gearrotor "
        f"torsional transient --sn-...</code> for the material): governing element "
        f"{_e(fat.to_dict()['governing_element'])}, damage per event "
        f"{fat.damage.max():.3g}, allowable events "
        f"{'unlimited' if np.isinf(n) else f'{n:.3g}'}.</p>"
    )
    return "\n".join(rows)
