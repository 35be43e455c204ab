"""Steam-turbine – generator gearbox (SPEC 6.2): the pinion stability study.

Reproduces the figures and numbers of ``docs/examples/steam_turbine_gearbox.md``:

1. damped modes at 10,800 rpm, redesign and original bearings (mode-shape figures);
2. log dec and whirl ratio of the pinion's critical (conical) mode against the cross-coupled
   stiffness q at the high-speed coupling hub, 0 … 1e8 N/m, both bearing designs, light load
   (load case 1): the onset q (log dec = 0) and the whirl ratio there;
3. the critical mode per generator load case, both designs, q = 5.68e7 N/m (and q = 0);
4. API 617 unbalance response with the redesign (Bode; peaks at the probes vs 4 µm);
5. a Campbell diagram of the redesign (no destabiliser);
6. checks: the q patch equals a re-assembly; sensitivity to the loaded gear flank.

Run from the repository root::

    python examples/scripts/steam_turbine_stability.py            # figures + summary JSON
    python examples/scripts/steam_turbine_stability.py --tables   # also re-tabulate the
                                                                  # bull-gear bearings first

Outputs: ``docs/examples/figures/steam_turbine_*.png`` and ``--json`` (default
``out/steam_turbine_stability.json``). About 1 minute on a 2-core machine.

Definitions used throughout:

* *critical mode*: among the damped modes at 10,800 rpm that whirl forward on the pinion, hold
  at least half of their kinetic energy in pinion lateral motion and lie between 0.3x and 1.4x
  of the pinion speed, the one with the lowest log decrement. For this machine it is always a
  conical (pitching) mode of the pinion, hub end and far bearing out of phase; the doc shows it.
* *whirl ratio*: its damped frequency divided by the pinion speed.
"""

from __future__ import annotations

import os

# Small dense eigenproblems: multithreaded BLAS only adds contention on a shared machine.
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import copy  # noqa: E402
import dataclasses  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
import tomllib  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

from gearrotor.analyses import campbell, modal, unbalance_response  # noqa: E402
from gearrotor.analyses.lateral.unbalance import api617_unbalance, shaft_masses  # noqa: E402
from gearrotor.assembly import Assembly, assemble  # noqa: E402
from gearrotor.bearings import Grid, SolverOptions, axial_groove, coefficients_table, save_table  # noqa: E402
from gearrotor.elements import MeshGeometry  # noqa: E402
from gearrotor.io import load_model, model_from_dict  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "examples" / "steam_turbine_gearbox.toml"
BULL_TABLE = ROOT / "examples" / "bearings" / "tables" / "steam_turbine_bull_gear_bearing.csv"
FIGURES = ROOT / "docs" / "examples" / "figures"

RPM = math.pi / 30
SPEED_RPM = 10800.0
Q_FIELD = 5.68e7  # N/m, SPEC 6.2
DESIGNS = {
    "original": "bearings/pinion_offset_halves.toml",
    "redesign": "bearings/pinion_3lobe_dam.toml",
}
LABEL = {"original": "original 2-lobe offset halves", "redesign": "3-lobe pressure dam (redesign)"}
LOAD_CASES = [
    (2, -826),
    (100, -588),
    (995, 1605),
    (1991, 4043),
    (4978, 11352),
    (8959, 21098),
    (12940, 30848),
    (16921, 40594),
    (20902, 50341),
    (24883, 60087),
]
HUB_NODE = 1  # pinion node of the high-speed coupling hub (the destabiliser)
BEARING_NODES = (4, 15)  # pinion bearing nodes


# --------------------------------------------------------------------------------------------
# model variants
def overrides(design: str = "redesign", load_case: int = 0, speeds=None, q=None) -> dict:
    """--set style overrides: pinion bearing design and load case (0-based) for both journals."""
    ov: dict = {}
    for b in (0, 1):
        ov[f"bearings[{b}].fluid_film.file"] = DESIGNS[design]
        ov[f"bearings[{b}].fluid_film.load_case"] = load_case
        if speeds is not None:
            ov[f"bearings[{b}].fluid_film.speeds"] = [f"{s} rpm" for s in speeds]
    if q is not None:
        ov["cross_couplings[0].q"] = f"{q} N/m"
    return ov


def with_q(asm: Assembly, q: float) -> Assembly:
    """The same assembly with the destabiliser set to q (N/m), without re-solving the bearings.

    WORKAROUND: the library re-solves every fluid-film bearing on each ``assemble``; a sweep of
    q only changes two entries of K (kxy = -kyx = q at the hub node), so patch K0 instead.
    """
    q0 = asm.train.cross_couplings[0].q
    d = asm.dof(0, HUB_NODE, 0)
    dK = sp.coo_array(([q - q0, -(q - q0)], ([d, d + 1], [d + 1, d])), shape=(asm.n_dof,) * 2)
    return dataclasses.replace(asm, K0=(asm.K0 + dK.tocsr()).tocsr())


def drive_flank(asm: Assembly) -> Assembly:
    """The same assembly with every mesh acting along the mirrored line of action.

    The library's mesh element loads the flank that puts a +z torque on both gears; in this
    reducer (pinion turning +z and driving) the loaded flank is the mirror image about the line
    of centres, i.e. the element with the pressure angle negated. Used as a sensitivity check.
    """
    rows, cols, vals = [], [], []
    for m in asm.meshes:
        g = m.geometry
        g2 = MeshGeometry(g.radius_i, g.radius_j, -g.pressure_angle, g.helix_angle, g.orientation)
        dK = g2.K(m.stiffness) - g.K(m.stiffness)
        r, c = np.meshgrid(m.dofs, m.dofs, indexing="ij")
        rows.append(r.ravel())
        cols.append(c.ravel())
        vals.append(dK.ravel())
    D = sp.coo_array(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(asm.n_dof,) * 2,
    )
    return dataclasses.replace(asm, K0=(asm.K0 + D.tocsr()).tocsr())


# --------------------------------------------------------------------------------------------
# the critical mode
def pinion_energy(res, i: int) -> float:
    asm = res.assembly
    phi = res.mode_shapes[i]
    mask = np.zeros(asm.n_dof)
    for d in (0, 1, 3, 4):
        mask[asm.node_offset[0] + d] = 1.0
    total = np.real(phi.conj() @ (asm.M @ phi))
    pm = phi * mask
    return float(np.real(pm.conj() @ (asm.M @ pm)) / total)


def conical_index(res, speed: float = SPEED_RPM * RPM) -> int | None:
    """Index of the critical mode (see the module docstring), or None."""
    best = None
    for i in range(len(res)):
        if res.overdamped[i] or res.whirl_per_shaft[i][0] != "F":
            continue
        if not 0.3 < res.damped_frequency[i] / speed < 1.4:
            continue
        if pinion_energy(res, i) < 0.5:
            continue
        if best is None or res.log_dec[i] < res.log_dec[best]:
            best = i
    return best


def bearing_phase_correlation(res, i: int) -> float:
    """Re<a, b>/|a||b| of the (x, y) amplitudes at the hub and at the far bearing: about -1
    for a conical mode pivoting between them, +1 for a cylindrical one."""
    asm = res.assembly
    a = res.mode_shapes[i][asm.dof(0, HUB_NODE, 0) + np.arange(2)]
    b = res.mode_shapes[i][asm.dof(0, BEARING_NODES[1], 0) + np.arange(2)]
    return float(np.real(np.vdot(a, b)) / (np.linalg.norm(a) * np.linalg.norm(b)))


def critical(asm: Assembly, q: float | None = None) -> dict:
    a = asm if q is None else with_q(asm, q)
    res = modal(a, max_frequency=30000 * RPM)
    i = conical_index(res)
    out = {"stable": bool(res.stable), "min_log_dec": float(np.min(res.log_dec))}
    if i is None:
        return out | {"frequency_rpm": float("nan"), "log_dec": float("nan"), "index": None}
    return out | {
        "index": int(i),
        "frequency_rpm": float(res.frequency_rpm[i]),
        "whirl_ratio": float(res.frequency_rpm[i] / SPEED_RPM),
        "log_dec": float(res.log_dec[i]),
        "type": res.mode_type[i],
        "hub_far_bearing_correlation": bearing_phase_correlation(res, i),
    }


def track_q(asm: Assembly, qs) -> list[dict]:
    """The critical mode at q = qs[0], followed through the q sweep by the MAC of the pinion's
    lateral mode shape among the modes that keep at least 40 % of their energy in pinion lateral
    motion (the least-damped candidate can change identity where a forward and a backward pinion
    mode veer; tracking keeps one physical mode, and the energy filter keeps it off the pinion's
    axial mode near 7,850 rpm, which the helical meshes couple to it)."""
    lat = np.concatenate([asm.node_offset[0] + d for d in (0, 1, 3, 4)])
    rows, prev = [], None
    for q in qs:
        res = modal(with_q(asm, q), max_frequency=30000 * RPM)
        if prev is None:
            i = conical_index(res)
        else:
            cand = [
                k
                for k in range(len(res))
                if not res.overdamped[k]
                and 0.3 < res.damped_frequency[k] / (SPEED_RPM * RPM) < 1.4
                and pinion_energy(res, k) >= 0.4
            ]
            macs = []
            for k in cand:
                v = res.mode_shapes[k][lat]
                macs.append(
                    abs(np.vdot(prev, v)) ** 2 / (np.vdot(prev, prev).real * np.vdot(v, v).real)
                )
            i = cand[int(np.argmax(macs))]
        prev = res.mode_shapes[i][lat]
        rows.append(
            {
                "frequency_rpm": float(res.frequency_rpm[i]),
                "log_dec": float(res.log_dec[i]),
                "whirl": "/".join(res.whirl_per_shaft[i]),
                "min_log_dec_all_modes": float(np.min(res.log_dec)),
            }
        )
    return rows


def onset(qs, log_dec, freq):
    """First zero crossing of log dec(q), linear interpolation; (q, whirl ratio) or None."""
    for k in range(len(qs) - 1):
        if log_dec[k] > 0 >= log_dec[k + 1]:
            t = log_dec[k] / (log_dec[k] - log_dec[k + 1])
            return (
                float(qs[k] + t * (qs[k + 1] - qs[k])),
                float((freq[k] + t * (freq[k + 1] - freq[k])) / SPEED_RPM),
            )
    return None


# --------------------------------------------------------------------------------------------
# bull-gear bearing table (representative)
def bull_gear_table(path: Path = BULL_TABLE) -> dict:
    """Tabulate the representative bull-gear bearings at the rated-load reaction."""
    data = tomllib.loads(MODEL.read_text())
    d = copy.deepcopy(data)
    d["bearings"] = [
        {"shaft": b["shaft"], "node": b["node"], "k": 1e9} for b in data["bearings"]
    ]  # mass only: any bearing will do
    train = model_from_dict(d)
    m_bull = float(shaft_masses(assemble(train))[1])
    # tooth reaction at rated load (load case 10 on each pinion bearing, gravity removed),
    # opposite on the bull gear, plus half the bull-gear weight, per bearing
    fx, fy = LOAD_CASES[-1]
    load = (-float(fx), -(float(fy) + 826.0) - m_bull * 9.81 / 2)
    brg = axial_groove(
        0.250,
        0.200,
        190e-6,
        0.0152,
        n_grooves=2,
        groove_arc=math.radians(20.0),
        first_groove=0.0,
        name="bull gear 2-axial-groove 250x200 mm c 190 um (representative)",
    )
    speeds = [-250.0, -500.0, -1000.0, -1500.0, -2000.0, -2250.0]  # the bull gear turns clockwise
    table = coefficients_table(brg, load, speeds, options=SolverOptions(grid=Grid(36, 8)))
    save_table(table, path)
    return {
        "bull_gear_mass_kg": m_bull,
        "load_N": list(load),
        "eccentricity_ratio": table.eccentricity_ratio.tolist(),
    }


# --------------------------------------------------------------------------------------------
def study(out_json: Path, figures: Path = FIGURES) -> dict:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gearrotor.plots import plot_bode, plot_campbell, plot_mode_shapes

    figures.mkdir(parents=True, exist_ok=True)
    summary: dict = {}
    t0 = time.time()

    # 1. modes at 10,800 rpm, load case 1, q = 5.68e7 N/m --------------------------------------
    base = {}
    for design in DESIGNS:
        asm = assemble(load_model(MODEL, overrides(design, 0)))
        base[design] = asm
        res = modal(asm, max_frequency=30000 * RPM)
        i = conical_index(res)
        elastic = [k for k in range(len(res)) if not res.overdamped[k]]
        shown = [k for k in elastic if res.frequency_rpm[k] > 3000][:6]
        plot_mode_shapes(res, modes=shown, path=figures / f"steam_turbine_modes_{design}.png")
        summary[f"modes_{design}"] = [
            {
                "frequency_rpm": round(float(res.frequency_rpm[k]), 1),
                "log_dec": round(float(res.log_dec[k]), 3),
                "whirl": "/".join(res.whirl_per_shaft[k]),
                "type": res.mode_type[k],
                "pinion_energy": round(pinion_energy(res, k), 2),
                "critical": k == i,
            }
            for k in elastic
        ]
        summary[f"critical_{design}_lc1_q568"] = critical(asm)
    summary["pinion_mass_kg"] = float(shaft_masses(base["redesign"])[0])
    summary["bull_gear_mass_kg"] = float(shaft_masses(base["redesign"])[1])
    summary["mesh_stiffness_N_per_m"] = [float(m.stiffness) for m in base["redesign"].meshes]

    # check: the q patch equals a re-assembly with the override
    asm0 = assemble(load_model(MODEL, overrides("original", 0, q=0.0)))
    a = critical(asm0)
    b = critical(base["original"], 0.0)
    assert (
        abs(a["log_dec"] - b["log_dec"]) < 1e-9
        and abs(a["frequency_rpm"] - b["frequency_rpm"]) < 1e-6
    )

    # 2. log dec vs q, light load ----------------------------------------------------------------
    qs = np.linspace(0.0, 1.0e8, 41)
    sweep = {}
    for design, asm in base.items():
        rows = track_q(asm, qs)
        ld = np.array([r["log_dec"] for r in rows])
        fr = np.array([r["frequency_rpm"] for r in rows])
        on = onset(qs, ld, fr)
        sweep[design] = (ld, fr, on)
        summary[f"q_sweep_{design}"] = {
            "q_N_per_m": qs.tolist(),
            "log_dec": ld.tolist(),
            "frequency_rpm": fr.tolist(),
            "onset_q_N_per_m": None if on is None else on[0],
            "onset_whirl_ratio": None if on is None else on[1],
            "whirl": [r["whirl"] for r in rows],
        }
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    for k, (design, (ld, fr, on)) in enumerate(sweep.items()):
        a1.plot(qs / 1e7, ld, f"C{k}.-", label=LABEL[design])
        a2.plot(qs / 1e7, fr / SPEED_RPM, f"C{k}.-")
        if on is not None:
            a1.plot(on[0] / 1e7, 0, f"C{k}o", mfc="none", ms=10)
            a1.annotate(
                f"onset {on[0] / 1e7:.2f}e7 N/m\nwhirl {on[1]:.3f}x",
                (on[0] / 1e7, 0),
                textcoords="offset points",
                xytext=(8, 8) if k == 0 else (6, 14),
                fontsize=8,
                color=f"C{k}",
                bbox={"fc": "white", "ec": "none", "alpha": 0.8},
            )
    for ax in (a1, a2):
        ax.axvline(Q_FIELD / 1e7, color="k", ls="--", lw=1)
        ax.grid(alpha=0.3)
    a1.axhline(0, color="r", lw=1)
    a1.text(Q_FIELD / 1e7 + 0.1, a1.get_ylim()[1] * 0.85, "field q = 5.68e7", fontsize=8)
    a1.set_ylabel("log dec of the critical\npinion (conical) mode")
    a1.legend(fontsize=8, loc="lower left")
    a2.set_ylabel("whirl ratio (freq / 10,800 rpm)")
    a2.set_xlabel("cross-coupled stiffness q at the HS coupling hub (1e7 N/m)")
    a1.set_title("Pinion stability vs destabiliser, load case 1 (2, -826 N), 10,800 rpm")
    fig.tight_layout()
    fig.savefig(figures / "steam_turbine_logdec_vs_q.png", dpi=130)
    plt.close(fig)

    # 3. per load case, both designs -----------------------------------------------------------
    per_case: dict = {d: {"q0": [], "q568": []} for d in DESIGNS}
    for design in DESIGNS:
        for lc in range(len(LOAD_CASES)):
            asm = assemble(load_model(MODEL, overrides(design, lc, speeds=[SPEED_RPM])))
            per_case[design]["q0"].append(critical(asm, 0.0))
            per_case[design]["q568"].append(critical(asm, Q_FIELD))
    summary["load_cases"] = per_case
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    x = np.arange(1, len(LOAD_CASES) + 1)
    for k, design in enumerate(DESIGNS):
        for key, ls, lab in (("q568", "-", "q = 5.68e7 N/m"), ("q0", ":", "q = 0")):
            ld = [r["log_dec"] for r in per_case[design][key]]
            fr = [r["frequency_rpm"] for r in per_case[design][key]]
            a1.plot(
                x,
                ld,
                f"C{k}o{ls}",
                label=f"{LABEL[design]}, {lab}",
                mfc="none" if key == "q0" else None,
            )
            a2.plot(x, fr, f"C{k}o{ls}", mfc="none" if key == "q0" else None)
    a1.axhline(0, color="r", lw=1)
    a1.set_ylabel("log dec of the critical mode")
    a1.legend(fontsize=7)
    a2.set_ylabel("its frequency (rpm)")
    a2.axhline(SPEED_RPM, color="0.5", lw=0.8, ls="--")
    a2.set_xlabel("generator load case (SPEC 6.2; 1 = gravity only, 10 = about 12 MW)")
    a2.set_xticks(x)
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    a1.set_title("Critical pinion mode per load case, 10,800 rpm")
    fig.tight_layout()
    fig.savefig(figures / "steam_turbine_load_cases.png", dpi=130)
    plt.close(fig)

    # 4. API 617 unbalance response, redesign: light and rated load without the destabiliser
    #    (the API 617 response analysis), and light load with it (the field condition)
    mcs = 1.05 * SPEED_RPM
    unb = {}
    for lc, q, in_phase in ((0, 0.0, False), (9, 0.0, False), (0, Q_FIELD, False), (0, 0.0, True)):
        ov = overrides("redesign", lc, q=q)
        if in_phase:  # both pinion planes in phase: the cylindrical mode's distribution
            ov["unbalances[1].phase"] = "0 deg"
        asm = assemble(load_model(MODEL, ov))
        tag = f"lc{lc + 1}" + ("_q568" if q else "") + ("_inphase" if in_phase else "")
        train = asm.train
        masses = shaft_masses(asm)
        counts = {s.name: sum(u.shaft == s.name for u in train.unbalances) for s in train.shafts}
        new = []
        for u in train.unbalances:
            si = train.shaft_index(u.shaft, "unbalances.shaft")
            amount = api617_unbalance(
                masses[si] / counts[u.shaft], abs(asm.speed_ratio[si]) * mcs * RPM
            )
            new.append(u.model_copy(update={"amount": amount}))
        speeds = np.linspace(2000.0, 16000.0, 281) * RPM
        res = unbalance_response(
            asm, speeds=speeds, unbalances=new, operating_range=(SPEED_RPM * RPM, mcs * RPM)
        )
        d = res.to_dict()
        op_mask = (res.speeds >= SPEED_RPM * RPM - 1e-9) & (res.speeds <= mcs * RPM + 1e-9)
        unb[tag] = {
            "unbalance_g_mm": {f"{u.shaft}[{u.node}]": u.amount * 1e6 for u in new},
            "peaks": {
                p["name"]: {
                    "peak_um_0pk": p["peak_amplitude_um"],
                    "peak_um_pp": p["peak_amplitude_pp_um"],
                    "at_rpm": p["peak_speed_rpm"],
                    "api617_limit_pp_um": p["api617_limit_pp_um"],
                    "max_in_operating_range_um_0pk": float(
                        np.max(np.abs(pr.response[op_mask])) * 1e6
                    ),
                    "criticals": p["critical_speeds"],
                }
                for p, pr in zip(d["probes"], res.probes, strict=True)
            },
        }
        if not in_phase:
            fig = plot_bode(res)
            fig.axes[0].set_title(
                f"API 617 unbalance response, redesign, load case {lc + 1}, "
                f"q = {q:.3g} N/m (0-pk, 4 x U per plane)",
                fontsize=10,
            )
            fig.savefig(figures / f"steam_turbine_bode_{tag}.png", dpi=130, bbox_inches="tight")
            plt.close(fig)
    summary["unbalance"] = unb

    # 5. Campbell diagram, redesign, load case 1, no destabiliser --------------------------------
    asm = assemble(load_model(MODEL, overrides("redesign", 0, q=0.0)))
    camp = campbell(asm, speeds=np.linspace(2000.0, 14000.0, 49) * RPM, max_frequency=30000 * RPM)
    plot_campbell(camp, path=figures / "steam_turbine_campbell.png", max_frequency=30000 * RPM)
    summary["campbell_crossings"] = [
        {
            "order": c.order,
            "speed_rpm": float(c.speed / RPM),
            "frequency_rpm": float(c.frequency / RPM),
            "log_dec": float(c.log_dec),
            "whirl": c.whirl,
            "type": c.mode_type,
        }
        for c in camp.crossings
    ]

    # 6. sensitivity: loaded flank ----------------------------------------------------------------
    summary["drive_flank_check"] = {
        design: critical(drive_flank(base[design])) for design in DESIGNS
    }
    summary["run_time_s"] = time.time() - t0
    out_json.parent.mkdir(parents=True, exist_ok=True)
    out_json.write_text(json.dumps(summary, indent=1))
    return summary


def report(s: dict) -> str:
    lines = []
    lines.append(
        f"pinion {s['pinion_mass_kg']:.1f} kg, bull gear {s['bull_gear_mass_kg']:.0f} kg, "
        f"mesh {s['mesh_stiffness_N_per_m'][0]:.3e} N/m per helix"
    )
    for d in DESIGNS:
        c = s[f"critical_{d}_lc1_q568"]
        lines.append(
            f"{d:9s} LC1 q=5.68e7: critical mode {c['frequency_rpm']:.0f} rpm "
            f"({c['whirl_ratio']:.3f}x) log dec {c['log_dec']:+.3f} type {c['type']} "
            f"corr {c['hub_far_bearing_correlation']:+.2f}; all stable: {c['stable']}"
        )
        sw = s[f"q_sweep_{d}"]
        lines.append(
            f"          onset q = {sw['onset_q_N_per_m']} N/m, "
            f"whirl ratio {sw['onset_whirl_ratio']}; "
            f"log dec at q=0: {sw['log_dec'][0]:.3f} at {sw['frequency_rpm'][0]:.0f} rpm"
        )
    lines.append("load case:   " + " ".join(f"{k:>7d}" for k in range(1, 11)))
    for d in DESIGNS:
        for key in ("q0", "q568"):
            lines.append(
                f"{d[:4]} {key:5s} ld "
                + " ".join(f"{r['log_dec']:7.3f}" for r in s["load_cases"][d][key])
            )
            lines.append(
                f"{d[:4]} {key:5s} f  "
                + " ".join(f"{r['frequency_rpm']:7.0f}" for r in s["load_cases"][d][key])
            )
    for lc, u in s["unbalance"].items():
        lines.append(f"API 617 unbalance, redesign, {lc}: {u['unbalance_g_mm']}")
        for name, p in u["peaks"].items():
            lines.append(
                f"   {name:7s} peak {p['peak_um_0pk']:.2f} um 0-pk ({p['peak_um_pp']:.2f} pk-pk)"
                f" at {p['at_rpm']:.0f} rpm; in 10800-11340 rpm "
                f"{p['max_in_operating_range_um_0pk']:.2f} um 0-pk; "
                f"API 617 limit {p['api617_limit_pp_um']:.1f} um pk-pk"
            )
    for d, c in s["drive_flank_check"].items():
        lines.append(
            f"drive-flank mesh, {d}: {c['frequency_rpm']:.0f} rpm log dec {c['log_dec']:+.3f}"
        )
    lines.append(f"run time {s['run_time_s']:.1f} s")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument(
        "--tables", action="store_true", help="re-tabulate the bull-gear bearings first"
    )
    ap.add_argument("--json", type=Path, default=ROOT / "out" / "steam_turbine_stability.json")
    ap.add_argument("--figures", type=Path, default=FIGURES)
    args = ap.parse_args()
    if args.tables or not BULL_TABLE.exists():
        print("bull-gear bearing table:", bull_gear_table())
    s = study(args.json, args.figures)
    print(report(s))


if __name__ == "__main__":
    main()
