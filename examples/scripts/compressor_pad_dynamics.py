"""Power turbine – compressor gearbox (SPEC 6.3) with its tilting pads as pad DOFs (issue 24,
item 4): what changes against the synchronously reduced coefficients.

Four bearing models of the same machine (``examples/compressor_gearbox.toml``):

* ``sync``: the shipped model, synchronously reduced coefficients, rigid pivots;
* ``pads``: the pads' tilt DOFs in the train (``fluid_film.pad_dynamics = true``), rigid pivots;
* ``sync_flex``: synchronously reduced coefficients with flexible pivots (``PIVOTS``);
* ``pads_flex``: the pads' tilt and radial DOFs with flexible pivots.

Computed: the damped modes at 5,700 rpm (the pinion's 10x mode), the 10x mode against the
pivot stiffness, the Floquet exponents of the 10x + 32x pair, and the seed's transients
(Ka/Kg = 0 and 0.75, unbalance only; and the located pinion without mesh damping, section 7
of the example) with the pinion blind-end probe's 1x and 10x lines.

Run from the repository root (about 6 minutes on 2 cores)::

    python examples/scripts/compressor_pad_dynamics.py

Outputs: ``docs/examples/figures/compressor_pads_*.png`` and ``out/compressor_pads.json``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from concurrent.futures import ProcessPoolExecutor  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import compressor_gearbox as cg  # noqa: E402

from gearrotor.analyses import modal  # noqa: E402
from gearrotor.analyses.lateral.floquet import floquet  # noqa: E402
from gearrotor.analyses.transient import ModalRK4, transient  # noqa: E402
from gearrotor.analyses.transient.equations import build_system  # noqa: E402
from gearrotor.io import load_model  # noqa: E402

RPM = math.pi / 30
FIGURES = cg.FIGURES
#: representative pivot flexibility (rocker-back line contacts of the pads' width) and pad
#: masses (steel pads of the files' thickness and arc): pinion, bull gear
PIVOTS = {"pinion": (3.0e9, 9.0), "bull_gear": (3.5e9, 12.5)}
CONFIGS = ("sync", "pads", "sync_flex", "pads_flex")
LABELS = {
    "sync": "synchronous coefficients, rigid pivots (shipped)",
    "pads": "pad DOFs, rigid pivots",
    "sync_flex": "synchronous coefficients, flexible pivots",
    "pads_flex": "pad DOFs, flexible pivots",
}


def overrides(config: str, kp: dict | None = None, speeds_only: bool = False) -> dict:
    """--set overrides of one bearing model (``kp``: pivot stiffness per shaft instead of
    ``PIVOTS``; ``speeds_only``: each bearing tabulated at its shaft's running speed only)."""
    ov = {}
    kp = kp or {s: v[0] for s, v in PIVOTS.items()}
    for k, shaft in enumerate(("pinion", "pinion", "bull_gear", "bull_gear")):
        ff = f"bearings[{k}].fluid_film"
        if config.startswith("pads"):
            ov[f"{ff}.pad_dynamics"] = "true"
        if config.endswith("flex") and kp[shaft] is not None:
            ov[f"{ff}.pivot_stiffness"] = f"{kp[shaft]} N/m"
            ov[f"{ff}.pad_mass"] = f"{PIVOTS[shaft][1]} kg"
        if speeds_only:
            ov[f"{ff}.speeds"] = '["5700 rpm"]' if shaft == "pinion" else '["3371.83 rpm"]'
            ov[f"bearings[{k}].extrapolate"] = "hold"
    return ov


def train_of(config: str, ka: float = 0.0, zeta=None, located=False, **kw):
    ov = cg.overrides(ka, zeta, located)
    ov.update(overrides(config, **kw))
    return load_model(cg.MODEL, ov)


def ten_x(res) -> dict:
    i = cg.ten_x_mode(res)
    return {
        "cpm": float(res.frequency_rpm[i]),
        "log_dec": float(res.log_dec[i]),
        "whirl": "/".join(res.whirl_per_shaft[i]),
        "type": res.mode_type[i],
    }


def modes_study() -> dict:
    out = {}
    for c in CONFIGS:
        res = modal(train_of(c), speed=cg.SPEED_RPM * RPM, max_frequency=100_000 * RPM)
        rows = [
            {
                "cpm": float(res.frequency_rpm[i]),
                "log_dec": float(res.log_dec[i]),
                "type": res.mode_type[i],
                "whirl": "/".join(res.whirl_per_shaft[i]),
                "class": res.mode_class[i],
            }
            for i in range(len(res))
        ]
        out[c] = {"ten_x": ten_x(res), "modes": rows, "n_dof": int(res.assembly.n_dof)}
        print(c, out[c]["ten_x"], flush=True)
    return out


def pivot_sweep() -> dict:
    """The 10x mode against the pivot stiffness (both shafts' pivots scaled together)."""
    scale = [None, 30.0, 10.0, 3.0, 1.0, 0.5, 0.3]
    out = {"scale": [], "pads": [], "sync": []}
    for s in scale:
        kp = {sh: (None if s is None else s * v[0] / 3.0) for sh, v in PIVOTS.items()}
        out["scale"].append(None if s is None else kp["pinion"])
        for c, key in (("pads_flex", "pads"), ("sync_flex", "sync")):
            res = modal(
                train_of(c, kp=kp, speeds_only=True),
                speed=cg.SPEED_RPM * RPM,
                max_frequency=100_000 * RPM,
            )
            out[key].append(ten_x(res))
        print("kp", kp, out["pads"][-1], out["sync"][-1], flush=True)
    return out


def floquet_study() -> dict:
    out = {}
    for c in CONFIGS:
        out[c] = {}
        for zeta, located, tag in ((None, False, "shipped"), (0.0, True, "located_undamped")):
            system = build_system(train_of(c, zeta=zeta, located=located, speeds_only=True))
            rows = []
            for ka in (0.0, 0.25, 0.5, 0.75):
                r = floquet(system, ka_ratio=ka)
                # the exponent at the 32x/10x pair: the largest growth near 32x
                near = np.abs(r.frequency / (cg.SPEED_RPM * RPM) - 32.0) < 0.6
                g32 = float(np.max(r.growth[near])) if near.any() else float("nan")
                rows.append({"ka": ka, "pair_32x_10x": g32, "least_stable": float(r.growth[0])})
            out[c][tag] = rows
            print(c, tag, rows, flush=True)
    return out


def run_case(args) -> dict:
    config, ka, zeta, located, t_end = args
    train = train_of(config, ka, zeta, located)
    t0 = time.perf_counter()
    try:
        r = transient(train, t_end=t_end, integrator=ModalRK4(static_correction=False))
    except Exception as exc:  # noqa: BLE001 - a diverging run is a result here
        return {"config": config, "ka": ka, "zeta": zeta, "located": located, "error": str(exc)}
    window = min(0.25, 0.5 * t_end)
    spectra = cg.probe_spectra(r, window)
    m = cg.metrics(r, window, spectra)
    f, a = spectra["last"]
    keep = f <= 120_000
    return {
        "config": config,
        "ka": ka,
        "zeta": zeta,
        "located": located,
        "wall_s": time.perf_counter() - t0,
        "dt_s": r.stats.dt,
        "n_modes": r.stats.n_modes,
        "metrics": {k: v for k, v in m.items() if k != "whirl_power_W"},
        "spectrum_last": [f[keep].tolist(), a[keep].tolist()],
    }


def transient_study(t_end: float, workers: int) -> list:
    cases = []
    for c in ("sync", "pads_flex", "pads"):
        for ka in (0.0, 0.75):
            cases.append((c, ka, None, False, t_end))
        cases.append((c, 0.75, 0.0, True, t_end))
    with ProcessPoolExecutor(workers) as ex:
        runs = list(ex.map(run_case, cases))
    for r in runs:
        m = r.get("metrics", {})
        print(
            r["config"],
            r["ka"],
            r["located"],
            r.get("error") or (m["x_1x_um"], m["y_1x_um"], m["x_10x_last_um"], m["x_10x_last_cpm"]),
            flush=True,
        )
    return runs


# ---- figures ---------------------------------------------------------------------------------
def reduced_figure(path: Path) -> None:
    """The pinion bearing's reduced coefficients against whirl frequency (pad assembly at
    every frequency), rigid and flexible pivots, with the synchronous values and 10x."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gearrotor.assembly import assemble

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    w = cg.SPEED_RPM * RPM
    ratios = np.linspace(0.05, 45, 400)
    for c, style in (("pads", "-"), ("pads_flex", "--")):
        asm = assemble(train_of(c, speeds_only=True))
        pads = asm.bearings[0].element.pads
        K = np.array([pads.reduced(w, r * w)[0] for r in ratios])
        C = np.array([pads.reduced(w, r * w)[1] for r in ratios])
        tag = "rigid pivots" if c == "pads" else "flexible pivots"
        ax[0].plot(ratios, K[:, 0, 0] / 1e9, "C0" + style, label=f"Kxx, {tag}")
        ax[0].plot(ratios, K[:, 1, 1] / 1e9, "C1" + style, label=f"Kyy, {tag}")
        ax[1].plot(ratios, C[:, 0, 0] / 1e6, "C0" + style, label=f"Cxx, {tag}")
        ax[1].plot(ratios, C[:, 1, 1] / 1e6, "C1" + style, label=f"Cyy, {tag}")
    for a in ax:
        a.axvline(1.0, color="k", lw=0.8)
        a.axvline(10.0, color="C3", lw=0.8, ls=":")
        a.text(1.2, 0.95, "1x", transform=a.get_xaxis_transform())
        a.text(10.4, 0.95, "10x", transform=a.get_xaxis_transform(), color="C3")
        a.set_xlabel("whirl frequency / running speed")
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    ax[0].set_ylabel("reduced stiffness (GN/m)")
    ax[1].set_ylabel("reduced damping (MN·s/m)")
    fig.suptitle("Pinion bearing at rated load, 5,700 rpm: Lund's pad assembly at every whirl")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def sweep_figure(sweep: dict, modes: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    k = [v if v is not None else 1e12 for v in sweep["scale"]]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for key, lab, st in (("pads", "pad DOFs", "o-"), ("sync", "synchronous coefficients", "s--")):
        ax[0].semilogx(k, [r["cpm"] for r in sweep[key]], st, label=lab)
        ax[1].semilogx(k, [r["log_dec"] for r in sweep[key]], st, label=lab)
    for a in ax:
        a.axvline(PIVOTS["pinion"][0], color="C3", lw=0.8, ls=":")
        a.set_xlabel("pinion pivot stiffness (N/m; bull gear ×7/6; 1e12: rigid)")
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    ax[0].axhline(57_000, color="k", lw=0.6)
    ax[0].set_ylabel("pinion 10x mode (cpm)")
    ax[1].set_ylabel("its log dec")
    fig.suptitle("The pinion's 10x lateral-torsional mode at 5,700 rpm against pivot stiffness")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def spectra_figure(runs: list, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(12, 4.2), sharey=True)
    panels = (
        (False, None, "seed's case, Ka/Kg = 0.75, 2 % mesh damping"),
        (True, 0.0, "located pinion, no mesh damping, Ka/Kg = 0.75"),
    )
    for a, (located, _zeta, title) in zip(ax, panels, strict=True):
        for r in runs:
            if r.get("error") or r["located"] != located or r["ka"] != 0.75:
                continue
            f, amp = (np.asarray(v) for v in r["spectrum_last"])
            a.semilogy(f, np.maximum(amp * 1e6, 1e-9), lw=0.9, label=LABELS[r["config"]])
        a.axvline(57_000, color="C3", lw=0.8, ls=":")
        a.set_xlim(0, 120_000)
        a.set_title(title, fontsize=10)
        a.set_xlabel("frequency (cpm)")
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    ax[0].set_ylabel("pinion blind end x (µm 0-pk, last 0.25 s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=0.5)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--figures", type=Path, default=FIGURES)
    ap.add_argument("--json", type=Path, default=cg.ROOT / "out" / "compressor_pads.json")
    args = ap.parse_args()
    t0 = time.perf_counter()
    out = {"pivots": PIVOTS, "modes": modes_study()}
    out["pivot_sweep"] = pivot_sweep()
    out["floquet"] = floquet_study()
    out["transients"] = transient_study(args.t_end, args.workers)
    args.figures.mkdir(parents=True, exist_ok=True)
    reduced_figure(args.figures / "compressor_pads_reduced.png")
    sweep_figure(out["pivot_sweep"], out["modes"], args.figures / "compressor_pads_pivot.png")
    spectra_figure(out["transients"], args.figures / "compressor_pads_spectra.png")
    out["wall_s"] = time.perf_counter() - t0
    args.json.parent.mkdir(parents=True, exist_ok=True)
    runs = out["transients"]
    for r in runs:
        r.pop("spectrum_last", None)
    args.json.write_text(json.dumps(out, indent=1))
    print(f"done in {out['wall_s']:.0f} s")


if __name__ == "__main__":
    main()
