"""Flexible unity-ratio spur gearbox (SPEC 6.1): the worked example's numbers and figures.

Reproduces ``docs/examples/unity_gearbox.md``:

1. damped modes of one shaft and of the gearbox at 6,500 rpm, compared with the dissertation's
   single-shaft table;
2. unbalance response (720 g·mm at both gear nodes, same phase) over 100–10,000 rpm;
3. the nominal transient (720 g·mm, no torque, 0–3.0 s, modal integrator) in the default
   energy-consistent form (``reactions=True``: the undriven train coasts down by its bearing
   dissipation) and in the dissertation's form (``reactions=False``): speeds and 1x;
4. the effect of mesh damping (0, 1, 2, 3, 4 % of critical on the mesh mode) on the
   high-frequency torsional content with a time-varying mesh stiffness (Ka/Kg = 0.2, c = 1.592,
   5 Fourier terms).

Run from the repository root::

    python examples/scripts/unity_gearbox.py            # figures + summary JSON (about 1 min)

Outputs: ``docs/examples/figures/unity_*.png`` (``--figures``) and ``--json`` (default
``out/unity_gearbox.json``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from gearrotor.analyses import modal, unbalance_response  # noqa: E402
from gearrotor.analyses.transient import ModalRK4, transient  # noqa: E402
from gearrotor.analyses.transient.results import spectrum  # noqa: E402
from gearrotor.io import load_model  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "examples" / "unity_gearbox.toml"
SINGLE = ROOT / "examples" / "unity_gearbox_single_shaft.toml"
FIGURES = ROOT / "docs" / "examples" / "figures"
RPM = math.pi / 30
SPEED_RPM = 6500.0

#: SPEC 6.1, the dissertation's single-shaft damped eigenvalues at 6500 rpm:
#: (rpm, log dec, whirl); the first four are over-damped rigid-body modes
SPEC_SINGLE = [
    (5.41, 8902, "B"),
    (6.65, 5980, "B"),
    (836, 1063, "F"),
    (838, 1060, "F"),
    (6243, 0.76, "B"),
    (6261, 0.77, "F"),
    (27478, 1.32, "B"),
    (27571, 1.33, "F"),
    (64614, 1.13, "B"),
    (64862, 1.15, "F"),
]
ZETAS = (0.0, 0.01, 0.02, 0.03, 0.04)
VARIATION = {"meshes[0].variation.ka_ratio": "0.2", "meshes[0].variation.terms": "5"}
HF_BAND = (209_000.0, 222_000.0)  # cpm: the lightly damped T mode at 215,670 cpm


def single_shaft_table() -> list[dict]:
    res = modal(load_model(SINGLE), speed=SPEED_RPM * RPM, max_frequency=70_000 * RPM)
    rows = []
    for k, (f_ref, ld_ref, wh) in enumerate(SPEC_SINGLE):
        f, ld = float(res.frequency_rpm[k]), float(res.log_dec[k])
        rows.append(
            {
                "spec_rpm": f_ref,
                "spec_log_dec": ld_ref,
                "spec_whirl": wh,
                "rpm": f,
                "log_dec": ld,
                "whirl": res.whirl[k],
                "overdamped": bool(res.overdamped[k]),
                "deviation": f / f_ref - 1,
            }
        )
    return rows


def gearbox_modes(figures: Path | None) -> list[dict]:
    res = modal(load_model(MODEL), speed=SPEED_RPM * RPM, max_frequency=260_000 * RPM)
    rows = [
        {
            "rpm": float(res.frequency_rpm[i]),
            "log_dec": float(res.log_dec[i]),
            "whirl": "/".join(res.whirl_per_shaft[i]),
            "type": res.mode_type[i],
            "overdamped": bool(res.overdamped[i]),
        }
        for i in range(len(res))
    ]
    if figures is not None:
        from gearrotor.plots import plot_mode_shapes

        lt = [i for i in range(len(res)) if "T" in res.mode_type[i] and not res.overdamped[i]]
        lt = [i for i in lt if res.frequency_rpm[i] > 1000 and abs(res.log_dec[i]) > 1e-6]
        first = [i for i in range(len(res)) if not res.overdamped[i]][:2]
        fig = plot_mode_shapes(res, modes=first + lt[:3])
        fig.savefig(figures / "unity_modes.png", dpi=110)
    return rows


def unbalance(figures: Path | None) -> dict:
    train = load_model(MODEL)
    speeds = np.linspace(100, 10_000, 397) * RPM
    res = unbalance_response(train, speeds=speeds, operating_range=(SPEED_RPM * RPM,) * 2)
    d = res.to_dict()
    k = int(np.argmin(np.abs(np.asarray(d["speeds_rpm"]) - SPEED_RPM)))
    out = []
    for p in d["probes"]:
        q = {key: v for key, v in p.items() if key not in ("amplitude_um", "phase_deg")}
        q["amplitude_at_6500_um"] = p["amplitude_um"][k]
        out.append(q)
    if figures is not None:
        from gearrotor.plots import plot_bode

        fig = plot_bode(res)
        fig.savefig(figures / "unity_bode.png", dpi=110)
    return {"probes": out}


def nominal(figures: Path | None, t_end: float = 3.0) -> dict:
    train = load_model(MODEL)
    out = {}
    runs = {}
    for tag, reactions in (("reactions", True), ("no_reactions", False)):
        t0 = time.perf_counter()
        r = transient(train, t_end=t_end, integrator=ModalRK4(), reactions=reactions)
        s = r.summary()
        s["wall_s"] = time.perf_counter() - t0
        w = r.shaft_speed_rpm[:, 0]
        s["coast_rate_rpm_per_s"] = float(np.polyfit(r.time, w, 1)[0])
        first = r.time <= 0.1
        s["speed_fluctuation_first_0.1s_rpm"] = float(
            0.5
            * np.ptp(w[first] - np.polyval(np.polyfit(r.time[first], w[first], 1), r.time[first]))
        )
        s["bearing_power_W"] = float(
            -sum(
                r.whirl_power[r.time > t_end - 0.5, c].mean()
                for c, n in enumerate(r.whirl_names)
                if n.startswith("bearing")
            )
        )
        out[tag] = s
        runs[tag] = r
    if figures is not None:
        from gearrotor.analyses.transient.plots import standard_figures

        tmp = figures / "_unity_nominal"
        tmp.mkdir(exist_ok=True)
        made = standard_figures(runs["reactions"], tmp, prefix="unity_nominal")
        for p in made:
            p.replace(figures / p.name)
        tmp.rmdir()
        out["figures"] = [p.name for p in made]
        speeds_figure(runs, figures / "unity_speeds_reactions.png")
    return out


def speeds_figure(runs: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for tag, lab in (("reactions", "reactions=True (default)"), ("no_reactions", "--no-reactions")):
        r = runs[tag]
        axes[0].plot(r.time, r.shaft_speed_rpm[:, 0], lw=0.7, label=lab)
        sl = r.time <= 0.05
        axes[1].plot(r.time[sl] * 1e3, r.shaft_speed_rpm[sl, 0], lw=0.8, label=lab)
    axes[0].set_xlabel("time (s)")
    axes[1].set_xlabel("time (ms)")
    for ax in axes:
        ax.set_ylabel("shaft 1 speed (rpm)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_title("whole run: coast-down by bearing dissipation vs constant mean", fontsize=9)
    axes[1].set_title("first 50 ms: the mesh reaction torques make the speed fluctuate", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def mesh_damping(figures: Path | None, t_end: float = 3.0, zetas=ZETAS) -> list[dict]:
    """Ka/Kg = 0.2 runs with mesh damping ratios ZETAS: torsional (shaft-1 speed) and DTE
    content in HF_BAND (around the lightly damped torsional mode at 215,670 cpm, which the
    30x + 3x mesh sideband at 214,500 cpm excites) over the first and the last 0.5 s."""
    rows, spectra = [], []
    for z in zetas:
        ov = dict(VARIATION)
        if z:
            ov["meshes[0].damping_ratio"] = str(z)
        r = transient(load_model(MODEL, ov), t_end=t_end, integrator=ModalRK4())
        t = r.time
        dt = float(np.median(np.diff(t)))
        row = {"zeta": z, "summary": r.summary()}
        for win, sl in (
            ("early", t <= min(0.5, t[-1] / 2)),
            ("late", t >= t[-1] - min(0.5, t[-1] / 2)),
        ):
            for name, sig, scale in (
                ("speed1_rpm", r.shaft_speed_rpm[:, 0], 1.0),
                ("dte_um", r.dte[:, 0], 1e6),
            ):
                f, a = spectrum(sig[sl], dt)
                band = (f >= HF_BAND[0]) & (f <= HF_BAND[1])
                j = int(np.argmax(a[band]))
                row[f"{name}_{win}"] = {
                    "hf_peak_cpm": float(f[band][j]),
                    "hf_peak": float(a[band][j] * scale),
                }
                if name == "speed1_rpm":
                    spectra.append((z, win, f, a * scale))
        m = r.mesh_force[t >= t[-1] - 0.5, 0]
        row["mesh_force_range_N"] = [float(m.min()), float(m.max())]
        rows.append(row)
    if figures is not None:
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
        for z, win, f, a in spectra:
            ax = axes[0 if win == "early" else 1]
            m = (f >= 150_000) & (f <= 250_000)
            ax.semilogy(f[m] / 1000, np.maximum(a[m], 1e-7), lw=0.8, label=f"mesh ζ = {z:.0%}")
        for ax, title in zip(axes, ("first 0.5 s", "last 0.5 s"), strict=True):
            ax.axvspan(HF_BAND[0] / 1000, HF_BAND[1] / 1000, color="0.9", zorder=0)
            for order, name in ((30, "30x"), (31, "+1x"), (32, "+2x"), (33, "+3x")):
                ax.axvline(order * SPEED_RPM / 1000, color="k", lw=0.5, ls=":")
                ax.text(
                    order * SPEED_RPM / 1000,
                    0.97,
                    f" {name}",
                    fontsize=7,
                    va="top",
                    transform=ax.get_xaxis_transform(),
                )
            ax.axvline(215.67, color="C3", lw=0.8, ls="--")
            ax.set_xlabel("frequency (1000 cpm)")
            ax.set_title(f"shaft-1 speed spectrum, {title} (red: T mode 215,670 cpm)", fontsize=9)
            ax.grid(alpha=0.3, which="both")
        axes[0].set_ylabel("speed fluctuation, rpm 0-pk")
        axes[0].legend(fontsize=8)
        fig.suptitle(
            "Ka/Kg = 0.2, c = 1.592, 5 terms: mesh damping and the high-frequency "
            "torsional content",
            fontsize=10,
        )
        fig.tight_layout()
        fig.savefig(figures / "unity_mesh_damping.png", dpi=110)
        plt.close(fig)
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--json", type=Path, default=ROOT / "out" / "unity_gearbox.json")
    p.add_argument("--figures", type=Path, default=FIGURES)
    p.add_argument("--no-figures", action="store_true")
    p.add_argument("--t-end", type=float, default=3.0)
    a = p.parse_args()
    figs = None if a.no_figures else a.figures
    if figs is not None:
        import matplotlib

        matplotlib.use("Agg")
        figs.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    s = {
        "single_shaft": single_shaft_table(),
        "gearbox_modes": gearbox_modes(figs),
        "nominal": nominal(figs, a.t_end),
        "mesh_damping": mesh_damping(figs, a.t_end),
    }
    s["unbalance"] = unbalance(figs)
    s["wall_s"] = time.perf_counter() - t0
    a.json.parent.mkdir(parents=True, exist_ok=True)
    a.json.write_text(json.dumps(s, indent=1, default=str))
    for r in s["single_shaft"]:
        print(
            f"{r['spec_rpm']:>9} {r['rpm']:10.2f} {100 * r['deviation']:+6.2f} %  "
            f"ld {r['spec_log_dec']:>7} {r['log_dec']:9.3f}  {r['spec_whirl']} {r['whirl']}"
        )
    for tag, n in s["nominal"].items():
        if tag == "figures":
            continue
        print(
            tag,
            n["shafts"]["shaft1"],
            n["nodes"]["shaft1[10]"],
            f"coast {n['coast_rate_rpm_per_s']:.1f} rpm/s, bearings {n['bearing_power_W']:.1f} W,"
            f" first-0.1s fluctuation {n['speed_fluctuation_first_0.1s_rpm']:.2f} rpm",
        )
    for r in s["mesh_damping"]:
        print(
            f"zeta {r['zeta']:.2f}: speed early {r['speed1_rpm_early']} late "
            f"{r['speed1_rpm_late']}, dte early {r['dte_um_early']} late {r['dte_um_late']}, "
            f"force {r['mesh_force_range_N']}, "
            f"1x {r['summary']['nodes']['shaft1[10]']['x_1x_um']:.2f}"
        )
    print(f"wall {s['wall_s']:.0f} s")


if __name__ == "__main__":
    main()
