"""Gear meshes from the tooth geometry and the periodic mesh response: every figure and number
of ``docs/gears.md`` and of section 9 of ``docs/examples/compressor_gearbox.md``.

1. the loaded mesh of ROSS 3.1's GearElementTVMS test pair (62/62 teeth, module 2 mm) and its
   TVMS beside ROSS's (tests/gears/ross_reference.json);
2. tip relief and the transmission error against load (Harris's map);
3. the mesh response of the spur test rig (examples/gears/spur_rig.toml) over speed, with
   ISO 6336-1's K_v;
4. the single-mesh rig after Kahraman & Blankenship (examples/gears/kahraman_rig.toml) with
   backlash: linear and nonlinear (run-up, run-down) harmonic balance over speed, and the
   nonlinear transient at a few speeds;
5. the compressor gearbox (SPEC 6.3) with its mesh from the tooth geometry
   (examples/gears/compressor_helix.toml): the helix's loaded mesh, the periodic response over
   the speed range, and Floquet at 5,700 rpm (shipped and located pinion, with and without
   mesh damping).

Run from the repository root (about 4 minutes on a loaded 2-core machine)::

    python examples/scripts/gears.py            # figures + out/gears.json
    python examples/scripts/gears.py kahraman   # one step (its numbers in out/gears.json)

Outputs: ``docs/figures/gears_*.png``, ``docs/examples/figures/compressor_geometry_*.png`` and
``out/gears.json``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import json  # noqa: E402
import math  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from gearrotor.analyses.lateral.floquet import floquet  # noqa: E402
from gearrotor.analyses.lateral.mesh_response import mesh_response  # noqa: E402
from gearrotor.files import save_figure  # noqa: E402
from gearrotor.gears import load_gear_pair, mesh_curves  # noqa: E402
from gearrotor.gears.plots import plot_mesh_cycle  # noqa: E402
from gearrotor.io import load_model  # noqa: E402
from gearrotor.model.gear_pair import GearPair  # noqa: E402
from gearrotor.plots.mesh_response import plot_mesh_response  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
FIG = ROOT / "docs" / "figures"
EXFIG = ROOT / "docs" / "examples" / "figures"
GEARS = ROOT / "examples" / "gears"
RPM = math.pi / 30


def _save(fig, path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    save_figure(fig, path, dpi=120)


def ross_pair(out: dict) -> None:
    ross = json.loads((ROOT / "tests" / "gears" / "ross_reference.json").read_text())
    c = mesh_curves(load_gear_pair(GEARS / "ross_test_pair.toml"), positions=1000)
    plot_mesh_cycle(c, FIG / "gears_spur_cycle.png")
    kr = np.asarray(ross["tvms_curve_N_per_m"])
    tau_r = np.arange(len(kr)) / len(kr)
    # ROSS's cycle starts where the driving tooth's involute starts, gearrotor's where a pair
    # enters contact: align the two by the start of the double-contact zone (the jump up)
    mine = np.interp(tau_r, c.position, c.stiffness)
    shifts = np.arange(len(kr))
    best = int(np.argmax([np.corrcoef(np.roll(kr, -s), mine)[0, 1] for s in shifts]))
    fig = Figure(figsize=(8.0, 4.2), layout="constrained")
    ax = fig.subplots()
    ax.plot(c.position, c.stiffness / 1e6, label="gearrotor (potential energy, Sainsot, Hertz)")
    ax.plot(tau_r, np.roll(kr, -best) / 1e6, "--", label="ROSS 3.1 GearElementTVMS")
    ax.set_xlabel("mesh cycle (ROSS's curve shifted to the same origin)")
    ax.set_ylabel("mesh stiffness (MN/m)")
    ax.set_title("ROSS 3.1's test pair: 62/62 teeth, m 2 mm, b 20 mm, 35 mm bore", fontsize=10)
    ax.legend(fontsize=8)
    _save(fig, FIG / "gears_ross_tvms.png")
    out["ross_pair"] = {
        "gearrotor_mean_max_min_N_per_m": [c.mean_stiffness, c.max_stiffness, c.min_stiffness],
        "ross_mean_max_min_N_per_m": [
            ross["tvms_mean_N_per_m"],
            ross["tvms_max_N_per_m"],
            ross["tvms_min_N_per_m"],
        ],
        "contact_ratio": c.contact_ratio,
        "ste_peak_to_peak_um": c.ste_peak_to_peak * 1e6,
        "ste_harmonics_um": [float(x) * 1e6 for x in c.ste_harmonics(5)],
    }


def harris(out: dict) -> None:
    spec = load_gear_pair(GEARS / "spur_50_50.toml")
    base = mesh_curves(spec)
    g = base.geometry
    amount = float(base.ste.max())
    length = (g.s_E - g.s_A) - g.base_pitch
    relief = {"tip_relief": {"amount": amount, "length": length}}
    mods = {"modifications": {"pinion": relief, "gear": relief}}
    mod = GearPair.model_validate(spec.model_dump(exclude_unset=True) | mods)
    torques = np.linspace(20.0, 600.0, 30)
    ptp_plain = [mesh_curves(spec, t).ste_peak_to_peak * 1e6 for t in torques]
    ptp_mod = [mesh_curves(mod, t).ste_peak_to_peak * 1e6 for t in torques]
    h1_mod = [mesh_curves(mod, t).ste_harmonics(1)[0] * 1e6 for t in torques]
    fig = Figure(figsize=(8.0, 4.4), layout="constrained")
    ax = fig.subplots()
    ax.plot(torques, ptp_plain, label="unmodified: peak-to-peak")
    ax.plot(torques, ptp_mod, label=f"tip relief {amount * 1e6:.2f} µm, long: peak-to-peak")
    ax.plot(torques, h1_mod, ":", label="tip relief: 1st mesh harmonic")
    ax.axvline(300.0, color="0.5", lw=0.8)
    ax.text(305, max(ptp_plain) * 0.9, "design torque", fontsize=8)
    ax.set_xlabel("pinion torque (N·m)")
    ax.set_ylabel("loaded STE (µm)")
    ax.set_title("50/50 spur pair, m 3 mm, b 20 mm: tip relief against load (Harris map)",
                 fontsize=10)  # fmt: skip
    ax.legend(fontsize=8)
    _save(fig, FIG / "gears_harris_map.png")
    i = int(np.argmin(np.abs(torques - 300.0)))
    out["harris"] = {
        "relief_um": amount * 1e6,
        "relief_length_mm": length * 1e3,
        "ptp_unmodified_um_at_300": ptp_plain[i],
        "ptp_relief_um_at_300": ptp_mod[i],
        "torque_of_min_ptp_N_m": float(torques[int(np.argmin(ptp_mod))]),
    }


def rig(out: dict) -> None:
    train = load_model(GEARS / "spur_rig.toml")
    speeds = np.linspace(400.0, 8000.0, 153) * RPM
    res = mesh_response(train, speeds=speeds)
    plot_mesh_response(res, FIG / "gears_rig_response.png", title=train.name)
    k = int(np.nanargmax(res.dte_rms[:, 0]))
    out["rig"] = {
        "peak_speed_rpm": float(res.speed_rpm[k]),
        "peak_dte_rms_um": float(res.dte_rms[k, 0] * 1e6),
        "iso_resonance_rpm": float(res.iso_resonance_speed[0] / RPM),
        "contact_loss_rpm": [float(x) for x in res.speed_rpm[res.contact_loss[:, 0]]],
        "dte_rms_um_at_3000": float(np.interp(3000, res.speed_rpm, res.dte_rms[:, 0]) * 1e6),
    }


def kahraman(out: dict) -> None:
    from gearrotor.analyses.transient import RK4, Save, transient
    from gearrotor.analyses.transient.equations import build_system, mesh_damping_from_ratio
    from gearrotor.analyses.transient.step_limits import rk4_max_step
    from gearrotor.model import ExternalTorque

    train = load_model(GEARS / "kahraman_rig.toml")
    speeds = np.linspace(1000.0, 6000.0, 101) * RPM
    kw = dict(speeds=speeds, harmonics=20, unbalance=False)
    lin = mesh_response(train, **kw)
    down = mesh_response(train, nonlinear=True, sweep="down", stability=False, **kw)
    up = mesh_response(train, nonlinear=True, sweep="up", stability=False, **kw)
    _, om = mesh_damping_from_ratio(build_system(train), 0, 0.02)
    # the transient with backlash, from the static state, at a few speeds
    tq = [ExternalTorque(shaft="pinion", node=2, value=300.0),
          ExternalTorque(shaft="gear", node=2, value=300.0)]  # fmt: skip
    rows = []
    for rpm in (1300.0, 2000.0, 3000.0, 4000.0, 5000.0):
        w = rpm * RPM
        shafts = [s.model_copy(update={"speed": w * (1 if i == 0 else -1)})
                  for i, s in enumerate(train.shafts)]  # fmt: skip
        tr = train.model_copy(update={"speed": w, "shafts": shafts, "torques": tq})
        system = build_system(tr)
        Tm = 2 * np.pi / (50 * w)
        res = transient(tr, t_end=0.1, integrator=RK4(dt=min(0.8 * rk4_max_step(system), Tm / 64)),
                        initial="static", save=Save(dt=Tm / 64, full_state=True))  # fmt: skip
        sel = res.time >= res.time[-1] - int(0.04 / Tm) * Tm + 1e-12
        law, d = system.meshes[0], system.mesh_dofs[0]
        delta = np.column_stack([res.channel(g) for g in system.active[d]])[sel] @ law.w
        i = int(np.argmin(abs(speeds / RPM - rpm)))
        rows.append({"rpm": rpm, "transient_dte_um": float(np.std(delta) * 1e6),
                     "transient_separated": float(np.mean(res.mesh_force[sel, 0] == 0)),
                     "hb_down_dte_um": float(down.dte_rms[i, 0] * 1e6),
                     "hb_down_separated": float(down.separation_fraction[i, 0]),
                     "hb_up_dte_um": float(up.dte_rms[i, 0] * 1e6),
                     "hb_up_separated": float(up.separation_fraction[i, 0]),
                     "linear_dte_um": float(lin.dte_rms[i, 0] * 1e6)})  # fmt: skip
    fig = Figure(figsize=(8.6, 5.0), layout="constrained")
    ax = fig.subplots()
    x = speeds / RPM
    ax.plot(x, np.where(lin.unstable, np.nan, lin.dte_rms[:, 0]) * 1e6, color="0.5", ls=":",
            label="linear (teeth always in contact)")  # fmt: skip
    ax.plot(x, down.dte_rms[:, 0] * 1e6, color="C3", label="backlash law, run-down")
    ax.plot(x, up.dte_rms[:, 0] * 1e6, color="C0", ls="--", label="backlash law, run-up")
    for r in rows:
        ax.plot(r["rpm"], r["transient_dte_um"], "ko", ms=5,
                label="transient from the static state" if r is rows[0] else None)  # fmt: skip
    ax.axvline(om / 50 / RPM, color="0.3", lw=0.8)
    ax.text(om / 50 / RPM, 0.9, " mesh mode", transform=ax.get_xaxis_transform(), fontsize=8)
    ax.set_xlabel("speed (rpm)")
    ax.set_ylabel("DTE rms (µm)")
    ax.set_ylim(0, 1.3 * np.nanmax(down.dte_rms[:, 0]) * 1e6)
    ax.set_title(train.name + "\nthe linear response runs off the scale at the resonance",
                 fontsize=10)  # fmt: skip
    ax.legend(fontsize=8)
    _save(fig, FIG / "gears_kahraman_rig.png")
    sep = down.separation_fraction[:, 0] > 0
    out["kahraman"] = {
        "mesh_mode_rpm": float(om / 50 / RPM),
        "mesh_mode_Hz": float(om / 2 / np.pi),
        "linear_peak_rpm": float(
            x[int(np.nanargmax(np.where(lin.unstable, np.nan, lin.dte_rms[:, 0])))]
        ),
        "down_jump_rpm": float(x[sep & (x > 2200)].min()),
        "up_jump_rpm": float(x[(up.separation_fraction[:, 0] > 0.2) & (x > 2200)].min()),
        "down_converged": int(down.converged.sum()),
        "up_converged": int(up.converged.sum()),
        "n": len(x),
        "transient": rows,
    }


def compressor(out: dict) -> None:
    pair = GearPair(file=str(GEARS / "compressor_helix.toml"))
    c = mesh_curves(load_gear_pair(GEARS / "compressor_helix.toml"))
    plot_mesh_cycle(c, EXFIG / "compressor_geometry_mesh.png")
    model = ROOT / "examples" / "compressor_gearbox.toml"

    def with_geometry(overrides=None):
        tr = load_model(model, overrides)
        meshes = [m.model_copy(update={"stiffness": None, "geometry": pair}) for m in tr.meshes]
        return tr.model_copy(update={"meshes": meshes})

    tr = with_geometry()
    speeds = np.linspace(3000.0, 7000.0, 81) * RPM
    res = mesh_response(tr, speeds=speeds, harmonics=5)
    plot_mesh_response(
        res,
        EXFIG / "compressor_geometry_response.png",
        title="Compressor gearbox, mesh from the tooth geometry (rated torque per helix)",
    )
    i = int(np.argmin(np.abs(res.speed_rpm - 5700.0)))
    out["compressor"] = {
        "mesh_mean_max_min_N_per_m": [c.mean_stiffness, c.max_stiffness, c.min_stiffness],
        "equivalent_ka_ratio": (c.max_stiffness - c.min_stiffness) / (2 * c.mean_stiffness),
        "contact_ratio": c.contact_ratio,
        "overlap_ratio": c.overlap_ratio,
        "normal_force_N": c.force,
        "ste_harmonics_um": [float(x) * 1e6 for x in c.ste_harmonics(5)],
        "at_5700": {
            "dte_rms_um": [float(x * 1e6) for x in res.dte_rms[i]],
            "dynamic_factor": [float(x) for x in res.dynamic_factor[i]],
            "probe_1x_um": dict(zip(res.probes, (res.probe_1x[i] * 1e6).tolist(), strict=True)),
            "probe_mesh_1x_um": dict(
                zip(res.probes, (res.probe_mesh[i, :, 0, 0] * 1e6).tolist(), strict=True)
            ),
            "probe_mesh_2x_um": dict(
                zip(res.probes, (res.probe_mesh[i, :, 0, 1] * 1e6).tolist(), strict=True)
            ),
        },
        "max_over_range": {
            "dte_rms_um": float(np.nanmax(res.dte_rms) * 1e6),
            "dynamic_factor": float(np.nanmax(res.dynamic_factor)),
            "probe_mesh_1x_um": float(np.nanmax(res.probe_mesh[:, :, :, 0]) * 1e6),
            "contact_loss": bool(res.contact_loss.any()),
        },
    }
    located = {
        "thrust_bearings[0].shaft": "pinion",
        "thrust_bearings[0].node": 2,
        "thrust_bearings[0].name": "pinion thrust",
    }
    rows = []
    for name, ov in (("shipped", {}), ("located pinion", located)):
        for zeta in (0.02, 0.0):
            ovz = ov | {"meshes[0].damping_ratio": zeta, "meshes[1].damping_ratio": zeta}
            r = floquet(with_geometry(ovz))
            top = r.to_dict(1)["exponents"][0]
            rows.append(
                {
                    "case": name,
                    "mesh_damping_ratio": zeta,
                    "least_stable_growth_1_s": top["growth_1_s"],
                    "at_cpm": top["frequency_cpm"],
                    "stable": r.stable,
                }
            )
    out["compressor"]["floquet_5700"] = rows


def main() -> None:
    out: dict = {}
    import sys

    steps = (ross_pair, harris, rig, kahraman, compressor)
    only = set(sys.argv[1:])
    for step in steps:
        if only and step.__name__ not in only:
            continue
        step(out)
        print(step.__name__, "done", flush=True)
    path = ROOT / "out" / "gears.json"
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
