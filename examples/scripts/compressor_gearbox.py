"""Power turbine – compressor gearbox (SPEC 6.3): the 10x study.

Reproduces the figures and numbers of ``docs/examples/compressor_gearbox.md``:

1. damped modes at 5,700 rpm (pinion speed) and the pinion's lateral-torsional mode near 10x
   (57,000 cpm), its mode shape and a Campbell diagram with the 1x, 10x and 42x (mesh) lines;
2. the seed's transient: unbalance 7,200 g·mm at the pinion blind end, Ka/Kg = 0, 0.25, 0.5,
   0.75, 5 Fourier terms, no backlash, 0–0.5 s, the fast modal integrator, with its accuracy
   checked against classical RK4 at the seed's Δt = 1e-6 s;
3. the same at rated load (36.8 MW: turbine torque on the bull gear, compressor load ∝ Ω² on
   the pinion, starting from the static deflection), RK4 at Δt = 1e-6 s;
4. the same without mesh damping: the time-varying mesh stiffness makes the train
   parametrically unstable (growth rate and frequency);
5. Floquet exponents (which mode pairs the mesh pumps), with and without mesh damping;
6. whirl-promoting power by component;
7. the located pinion: the thrust bearing moved from the bull gear to the pinion, without
   mesh damping (the seed's assumption) - the 10x component grows with Ka/Kg while 1x stays.

Run from the repository root::

    python examples/scripts/compressor_gearbox.py                 # figures + summary JSON
    python examples/scripts/compressor_gearbox.py --t-end 0.15    # quick look (tests)

Outputs: ``docs/examples/figures/compressor_*.png`` (``--figures``) and ``--json`` (default
``out/compressor_gearbox.json``). About 4 minutes on a 2-core machine (two processes).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
from concurrent.futures import ProcessPoolExecutor  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from gearrotor.analyses import campbell, modal  # noqa: E402
from gearrotor.analyses.transient import RK4, ModalRK4, transient  # noqa: E402
from gearrotor.analyses.transient.results import amplitude_at, spectrum  # noqa: E402
from gearrotor.io import load_model  # noqa: E402
from gearrotor.model import Train  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "examples" / "compressor_gearbox.toml"
FIGURES = ROOT / "docs" / "examples" / "figures"

RPM = math.pi / 30
SPEED_RPM = 5700.0  # pinion
KAS = (0.0, 0.25, 0.5, 0.75)
PROBE = "pinion[0]"  # the blind end (unbalance plane)
POWER_W = 36.8e6
#: rated torques (N·m): the power turbine drives the bull gear (which turns about -z), the
#: compressor loads the pinion (turning about +z) in proportion to the square of its speed
T_PINION = -POWER_W / (SPEED_RPM * RPM)
T_BULL = -POWER_W / (SPEED_RPM * 42 / 71 * RPM)


#: section 7: the thrust bearing on the pinion (at its blind-end journal) instead of the bull gear
LOCATED_PINION = {
    "thrust_bearings[0].name": "pinion thrust",
    "thrust_bearings[0].shaft": "pinion",
    "thrust_bearings[0].node": "2",
}


def overrides(ka: float = 0.0, damping_ratio: float | None = None, located: bool = False) -> dict:
    ov = dict(LOCATED_PINION) if located else {}
    for m in (0, 1):
        ov[f"meshes[{m}].variation.ka_ratio"] = str(ka)
        if damping_ratio is not None:
            ov[f"meshes[{m}].damping_ratio"] = str(damping_ratio)
    return ov


def model(
    ka: float = 0.0,
    damping_ratio: float | None = None,
    loaded: bool = False,
    located: bool = False,
) -> Train:
    train = load_model(MODEL, overrides(ka, damping_ratio, located))
    if not loaded:
        return train
    data = train.model_dump()
    data["torques"] = [
        {
            "name": "compressor load",
            "shaft": "pinion",
            "node": 14,
            "value": T_PINION,
            "speed_exponent": 2.0,
            "reference_speed": SPEED_RPM * RPM,
        },
        {"name": "power turbine", "shaft": "bull_gear", "node": 0, "value": T_BULL},
    ]
    return Train.model_validate(data)


# ---- 1. modes ------------------------------------------------------------------------------
def mode_energies(res, i: int) -> dict:
    """Kinetic-energy fractions of mode i per shaft and DOF group (pL, pT, bL, ...)."""
    asm = res.assembly
    M = asm.M
    phi = res.mode_shapes[i]
    e = np.real(np.conj(phi) * (M @ phi))
    e = e / e.sum()
    kind = asm.dof_kind()
    out = {}
    for s, offs in enumerate(asm.node_offset):
        sel = np.zeros(asm.n_dof, bool)
        for o in offs:
            sel[o : o + 6] = True
        for k, g in enumerate("LAT"):
            out["pb"[s] + g] = float(e[sel & (kind == k)].sum())
    return out


def ten_x_mode(res) -> int:
    """The pinion mode nearest 10x among the modes with most of their energy on the pinion."""
    best, idx = None, None
    for i in range(len(res)):
        if res.overdamped[i]:
            continue
        e = mode_energies(res, i)
        if e["pL"] + e["pT"] + e["pA"] < 0.8:
            continue
        d = abs(res.frequency_rpm[i] / SPEED_RPM - 10.0)
        if best is None or d < best:
            best, idx = d, i
    return idx


def mode_rows(res) -> list[dict]:
    rows = []
    for i in range(len(res)):
        e = mode_energies(res, i)
        rows.append(
            {
                "frequency_rpm": float(res.frequency_rpm[i]),
                "order": float(res.frequency_rpm[i] / SPEED_RPM),
                "log_dec": float(res.log_dec[i]),
                "whirl": "/".join(res.whirl_per_shaft[i]),
                "type": res.mode_type[i],
                "energy": {k: round(v, 3) for k, v in e.items() if v >= 0.03},
            }
        )
    return rows


def modes_study(figures: Path | None) -> dict:
    train = load_model(MODEL)
    res = modal(train, speed=SPEED_RPM * RPM, max_frequency=100_000 * RPM)
    rows = mode_rows(res)
    i10 = ten_x_mode(res)
    out = {"modes": rows, "ten_x_index": i10, "ten_x": rows[i10]}
    located = modal(model(located=True), speed=SPEED_RPM * RPM, max_frequency=100_000 * RPM)
    located_rows = mode_rows(located)
    out["located_pinion"] = {
        "ten_x": located_rows[ten_x_mode(located)],
        "axial": [r for r in located_rows if r["type"] == "A"],
    }
    if figures is not None:
        from gearrotor.plots import plot_campbell, plot_mode_shapes

        near = [i for i in range(len(res)) if 8.5 <= res.frequency_rpm[i] / SPEED_RPM <= 12.5]
        near = [i for i in near if not res.overdamped[i]]
        fig = plot_mode_shapes(res, modes=near)
        fig.savefig(figures / "compressor_modes_10x.png", dpi=110)
        cres = campbell(
            train,
            speeds=np.linspace(3000, 7000, 17) * RPM,
            max_frequency=80_000 * RPM,
            extra_orders=(10.0,),
        )
        fig = plot_campbell(cres, max_frequency=80_000 * RPM)
        fig.savefig(figures / "compressor_campbell.png", dpi=110)
        out["campbell_crossings"] = _crossings(cres)
    return out


def _crossings(cres) -> list:
    return cres.to_dict()["crossings"]


# ---- 2.-4. transients ----------------------------------------------------------------------
def probe_spectra(r, window: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Hann spectra (cpm, m 0-pk) of the pinion blind-end x over the whole run (the seed's
    0–0.5 s FFT, ``"run"``) and over the last ``window`` s (``"last"``)."""
    x = r.node_x[:, list(r.node_labels).index(PROBE)]
    last = r.time >= r.time[-1] - window
    dt = float(np.median(np.diff(r.time)))
    return {"run": spectrum(x, dt), "last": spectrum(x[last], dt)}


def metrics(r, window: float, spectra: dict) -> dict:
    """Pinion blind-end amplitudes (µm, 0-pk): 1x and 42x by least squares over the last
    ``window`` s; the 10x (9.5x–10.5x), 7.5x–9.5x and 32x (31x–33x) bands from the
    :func:`probe_spectra` of the same window."""
    t = r.time
    k = list(r.node_labels).index(PROBE)
    x, y = r.node_x[:, k], r.node_y[:, k]
    last = t >= t[-1] - window
    om = float(np.mean(np.abs(r.shaft_speed[last, 0])))
    out = {
        "x_1x_um": amplitude_at(t[last], x[last], om) * 1e6,
        "y_1x_um": amplitude_at(t[last], y[last], om) * 1e6,
        "x_42x_um": amplitude_at(t[last], x[last], 42 * om) * 1e6,
        "y_42x_um": amplitude_at(t[last], y[last], 42 * om) * 1e6,
    }
    for tag, (f, a) in spectra.items():
        order = f / (om / RPM)
        for band, lo, hi in (("10x", 9.5, 10.5), ("8x", 7.5, 9.5), ("32x", 31.0, 33.0)):
            m = (order >= lo) & (order <= hi)
            j = int(np.argmax(a[m]))
            out[f"x_{band}_{tag}_um"] = float(a[m][j] * 1e6)
            out[f"x_{band}_{tag}_cpm"] = float(f[m][j])
    f, a = spectra["last"]
    m = (f > 2000) & (f < 300_000)
    fm, am = f[m], a[m]
    loc = np.flatnonzero((am[1:-1] > am[:-2]) & (am[1:-1] >= am[2:])) + 1
    top = loc[np.argsort(am[loc])[::-1][:5]]
    out["peaks_last"] = [[float(fm[j]), float(am[j] * 1e6)] for j in sorted(top)]
    # the force range over every integration step (the result's step envelope), and that of
    # the recorded samples, which depends on where the samples fall in the mesh cycle
    ext = r.mesh_extremes()
    out["mesh_force_N"] = [float(ext.least[0]), float(ext.largest[0])]
    out["mesh_force_samples_N"] = [
        float(r.mesh_force[:, 0].min()),
        float(r.mesh_force[:, 0].max()),
    ]
    out["pinion_speed_rpm"] = [
        float(r.shaft_speed_rpm[:, 0].min()),
        float(r.shaft_speed_rpm[:, 0].max()),
    ]
    out["whirl_power_W"] = {
        str(n): float(np.mean(r.whirl_power[last, c])) for c, n in enumerate(r.whirl_names)
    }
    return out


def run_case(args: tuple) -> dict:
    """One transient (in a worker process): returns metrics, the blind-end spectrum and a
    decimated blind-end history."""
    ka, zeta, loaded, method, t_end, *rest = args
    located = bool(rest and rest[0])
    train = model(ka, zeta, loaded, located)
    integ = RK4(dt=1e-6) if method == "rk4" else ModalRK4(static_correction=False)
    t0 = time.perf_counter()
    try:
        r = transient(train, t_end=t_end, integrator=integ, initial="static" if loaded else "zero")
    except Exception as exc:  # noqa: BLE001 - a diverging run is a result here
        return {
            "ka": ka,
            "zeta": zeta,
            "loaded": loaded,
            "located": located,
            "method": method,
            "error": str(exc),
        }
    wall = time.perf_counter() - t0
    k = list(r.node_labels).index(PROBE)
    window = min(0.25, 0.5 * t_end)
    spectra = probe_spectra(r, window)
    (f, a), (fl, al) = spectra["run"], spectra["last"]
    keep = f <= 300_000
    step = max(1, len(r.time) // 4000)
    return {
        "ka": ka,
        "zeta": zeta,
        "loaded": loaded,
        "located": located,
        "method": method,
        "wall_s": wall,
        "dt_s": r.stats.dt,
        "steps": r.stats.steps,
        "n_modes": r.stats.n_modes,
        "metrics": metrics(r, window, spectra),
        "spectrum": [f[keep].tolist(), a[keep].tolist()],
        "spectrum_last": [fl[fl <= 300_000].tolist(), al[fl <= 300_000].tolist()],
        "history": [r.time[::step].tolist(), r.node_x[::step, k].tolist()],
        "whirl": [r.time[::step].tolist(), r.whirl_power[::step].T.tolist(), list(r.whirl_names)],
    }


def growth(run: dict) -> dict:
    """Exponential growth of the non-synchronous part of the blind-end history (1/s)."""
    t, x = (np.asarray(v) for v in run["history"])
    n = len(t) // 10
    rms = []
    for j in range(10):
        seg = x[j * n : (j + 1) * n]
        tt = t[j * n : (j + 1) * n]
        om = SPEED_RPM * RPM
        A = np.column_stack([np.cos(om * tt), np.sin(om * tt), np.ones_like(tt)])
        c, *_ = np.linalg.lstsq(A, seg, rcond=None)
        rms.append(float(np.std(seg - A @ c)))
    rms = np.asarray(rms)
    tc = np.array([t[j * n : (j + 1) * n].mean() for j in range(10)])
    rate = float(np.polyfit(tc[5:], np.log(rms[5:]), 1)[0])
    return {"rate_per_s": rate, "rms_um": (rms * 1e6).tolist(), "t_s": tc.tolist()}


# ---- figures ---------------------------------------------------------------------------------
def spectra_figure(runs: list[dict], title: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(10, 7.5))
    for r in runs:
        if "error" in r:
            continue
        f, a = (np.asarray(v) for v in r["spectrum"])
        lab = f"Ka/Kg = {r['ka']:.2f}"
        axes[0].semilogy(f / 1000, np.maximum(a * 1e6, 1e-8), lw=0.8, label=lab)
        m = f <= 80_000
        axes[1].semilogy(f[m] / 1000, np.maximum(a[m] * 1e6, 1e-8), lw=0.8, label=lab)
    for ax in axes:
        for order, name in ((1, "1x"), (10, "10x"), (42, "42x mesh")):
            fc = order * SPEED_RPM / 1000
            if fc <= ax.get_xlim()[1] * 1.02:
                ax.axvline(fc, color="k", lw=0.5, ls=":")
                ax.text(
                    fc, 0.97, f" {name}", fontsize=8, va="top", transform=ax.get_xaxis_transform()
                )
        ax.set_ylabel("pinion blind end x, µm 0-pk")
        ax.grid(alpha=0.3, which="both")
    axes[1].set_xlabel("frequency (1000 cpm)")
    axes[0].set_title(title, fontsize=10)
    axes[0].legend(fontsize=8, ncol=4)
    axes[0].set_ylim(1e-8, 10)
    axes[1].set_ylim(1e-8, 10)
    axes[1].set_xlim(0, 80)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def amplitudes_figure(seed: list[dict], loaded: list[dict], path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, runs, title in (
        (axes[0], seed, "seed case: unbalance only (modal integrator)"),
        (axes[1], loaded, "rated load 36.8 MW (RK4, Δt = 1e-6 s)"),
    ):
        ok = [r for r in runs if "error" not in r]
        ka = [r["ka"] for r in ok]
        for key, lab, mk in (
            ("x_1x_um", "1x", "o-"),
            ("x_42x_um", "42x (mesh)", "s-"),
            ("x_10x_run_um", "10x band, 0–t_end FFT", "^-"),
            ("x_10x_last_um", "10x band, last 0.25 s", "v--"),
        ):
            ax.semilogy(ka, [max(r["metrics"][key], 1e-8) for r in ok], mk, label=lab)
        ax.set_xlabel("Ka/Kg")
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("pinion blind end x, µm 0-pk")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def instability_figure(runs: list[dict], path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for r in runs:
        lab = f"Ka/Kg = {r['ka']:.2f}, no mesh damping"
        if "error" in r:
            continue
        g = growth(r)
        axes[0].semilogy(g["t_s"], g["rms_um"], "o-", label=f"{lab}: {g['rate_per_s']:.0f} 1/s")
        f, a = (np.asarray(v) for v in r["spectrum"])
        m = f <= 260_000
        axes[1].semilogy(f[m] / 1000, np.maximum(a[m] * 1e6, 1e-8), lw=0.8, label=lab)
    axes[0].set_xlabel("time (s)")
    axes[0].set_ylabel("non-synchronous rms, µm")
    axes[0].set_title("pinion blind end: growth without mesh damping", fontsize=9)
    axes[1].set_xlabel("frequency (1000 cpm)")
    axes[1].set_ylabel("µm 0-pk")
    axes[1].set_title("spectrum over the run", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def whirl_figure(runs: list[tuple[dict, str]], path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(
        len(runs),
        2,
        figsize=(12, 4.2 * len(runs)),
        gridspec_kw={"width_ratios": [1.6, 1]},
        squeeze=False,
    )
    for row, (run, title) in enumerate(runs):
        t = np.asarray(run["whirl"][0])
        P = np.asarray(run["whirl"][1])
        names = run["whirl"][2]
        mean = run["metrics"]["whirl_power_W"]
        n = max(1, int(round(0.005 / np.median(np.diff(t)))))
        ker = np.ones(n) / n
        ax = axes[row, 0]
        for k, name in enumerate(names):
            p = np.convolve(np.pad(P[k], (n // 2, n - 1 - n // 2), mode="edge"), ker, mode="valid")
            ax.plot(t, p, lw=0.8, label=name)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("W (5 ms average)")
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=6, ncol=2)
        ax.grid(alpha=0.3)
        vals = [mean[n_] for n_ in names]
        ax = axes[row, 1]
        ax.barh(range(len(names)), vals, color=["C3" if v > 0 else "C0" for v in vals])
        ax.set_yticks(range(len(names)), names, fontsize=7)
        ax.axvline(0, color="k", lw=0.5)
        ax.set_xlabel("mean over the last 0.25 s (W); > 0 feeds whirl")
        ax.grid(alpha=0.3)
    fig.suptitle("Whirl-promoting power P = Fx ẋ + Fy ẏ by component, Ka/Kg = 0.75", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---- 5. Floquet: which mode pairs the mesh stiffness variation pumps ----------------------------
#: (mesh damping ratio or None for the model's, located pinion) of the Floquet study
CONFIGS = ((None, False), (0.0, False), (0.0, True))


def _config_label(zeta: float | None, located: bool) -> str:
    return ("2 % mesh damping" if zeta is None else "no mesh damping") + (
        ", located pinion" if located else ""
    )


def floquet_study(figures: Path | None) -> dict:
    """Floquet exponents of the constant-speed train for Ka/Kg = 0 ... 0.75, with the model's
    2 % mesh damping and without, and without it on the located pinion (section 7); the 10x
    mode and its 42x − 10x partner are followed by their undamped frequencies; a speed sweep
    of the largest growth rate at Ka/Kg = 0.75."""
    from gearrotor.analyses.lateral.floquet import floquet
    from gearrotor.analyses.transient import build_system

    out: dict = {"cases": [], "sweep": []}
    mesh_cpm = 42 * SPEED_RPM
    for zeta, located in CONFIGS:
        system = build_system(model(0.0, zeta, located=located))
        for ka in KAS:
            r = floquet(system, ka_ratio=ka)
            mf = r.mode_frequency * 30 / math.pi
            ten = int(np.argmin(np.where((mf > 45_000) & (mf < 70_000), np.abs(mf - 63_850), 1e9)))
            partner = int(np.argmin(np.abs(mf - (mesh_cpm - 57_000))))

            def row(i, r=r, mf=mf):
                return {
                    "growth_1_s": float(r.growth[i]),
                    "frequency_cpm": float(r.frequency_cpm[i]),
                    "mode_cpm": float(mf[r.mode[i]]),
                    "partner_cpm": float(mf[r.partner[i]]) if r.partner[i] >= 0 else None,
                }

            pair = [i for i in range(len(r.growth)) if r.mode[i] in (ten, partner)]
            out["cases"].append(
                {
                    "zeta": zeta,
                    "located": located,
                    "ka": ka,
                    "top": [row(i) for i in range(3)],
                    "ten_x_mode_cpm": float(mf[ten]),
                    "partner_mode_cpm": float(mf[partner]),
                    "pair": [row(i) for i in pair[:2]],
                }
            )
    speeds = np.linspace(5000.0, 6400.0, 57)
    for zeta, located in CONFIGS:
        system = build_system(model(0.0, zeta, located=located))
        g = [float(floquet(system, ka_ratio=0.75, speed=v * RPM).growth[0]) for v in speeds]
        out["sweep"].append(
            {"zeta": zeta, "located": located, "speed_rpm": speeds.tolist(), "growth_1_s": g}
        )
    if figures is not None:
        floquet_figure(out, figures / "compressor_floquet.png")
    return out


def floquet_figure(f: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.6), constrained_layout=True)
    styles = ("-", "--", ":")
    for (zeta, located), style in zip(CONFIGS, styles, strict=True):
        cs = [c for c in f["cases"] if c["zeta"] == zeta and c["located"] == located]
        tag = _config_label(zeta, located)
        ka = [c["ka"] for c in cs]
        a1.plot(
            ka,
            [max(p["growth_1_s"] for p in c["pair"]) for c in cs],
            "o" + style,
            color="C3",
            label=f"10x + 32x pair, {tag}",
        )
        a1.plot(
            ka,
            [c["top"][0]["growth_1_s"] for c in cs],
            "s" + style,
            color="C0",
            label=f"least stable exponent, {tag}",
        )
    a1.axhline(0, color="k", lw=0.8)
    a1.set_yscale("symlog", linthresh=1.0)
    a1.set_xlabel("Ka/Kg")
    a1.set_ylabel("Floquet growth rate (1/s)")
    a1.set_title("5,700 rpm: growth rate against Ka/Kg (positive: unstable)")
    a1.legend(fontsize=7)
    a1.grid(alpha=0.3)
    for sw, style in zip(f["sweep"], styles, strict=True):
        a2.plot(
            sw["speed_rpm"], sw["growth_1_s"], style, label=_config_label(sw["zeta"], sw["located"])
        )
    a2.axhline(0, color="k", lw=0.8)
    a2.axvline(SPEED_RPM, color="0.5", lw=0.8, ls=":")
    a2.set_yscale("symlog", linthresh=1.0)
    a2.set_xlabel("pinion speed (rpm)")
    a2.set_ylabel("largest Floquet growth rate (1/s)")
    a2.set_title("Ka/Kg = 0.75: stability against speed")
    a2.legend(fontsize=8)
    a2.grid(alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def located_figure(runs: list[dict], path: Path) -> None:
    """Section 7: blind-end spectra (last 0.25 s) and the 1x, 10x and 32x lines against Ka."""
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(
        1, 2, figsize=(12, 4.4), gridspec_kw={"width_ratios": [1.6, 1]}, constrained_layout=True
    )
    ok = [r for r in runs if "error" not in r]
    for r in ok:
        f, a = (np.asarray(v) for v in r["spectrum_last"])
        m = f <= 260_000
        a1.semilogy(
            f[m] / 1000, np.maximum(a[m] * 1e6, 1e-7), lw=0.8, label=f"Ka/Kg = {r['ka']:.2f}"
        )
    for order, name in ((1, "1x"), (10, "10x"), (32, "32x"), (42, "42x mesh")):
        fc = order * SPEED_RPM / 1000
        a1.axvline(fc, color="k", lw=0.5, ls=":")
        a1.text(fc, 0.97, f" {name}", fontsize=8, va="top", transform=a1.get_xaxis_transform())
    a1.set_ylim(1e-7, 10)
    a1.set_xlabel("frequency (1000 cpm)")
    a1.set_ylabel("pinion blind end x, µm 0-pk")
    a1.set_title(
        "Located pinion, no mesh damping, unbalance only: spectrum of the last 0.25 s", fontsize=9
    )
    a1.legend(fontsize=8)
    ka = [r["ka"] for r in ok]
    for key, lab, mk in (
        ("x_1x_um", "1x", "o-"),
        ("x_10x_last_um", "10x band (57,000 cpm)", "^-"),
        ("x_32x_last_um", "32x band (182,000 cpm)", "s--"),
    ):
        a2.semilogy(ka, [max(r["metrics"][key], 1e-7) for r in ok], mk, label=lab)
    a2.set_xlabel("Ka/Kg")
    a2.set_title("pinion blind end x, last 0.25 s", fontsize=9)
    a2.legend(fontsize=8)
    for ax in (a1, a2):
        ax.grid(alpha=0.3, which="both")
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---- the study -------------------------------------------------------------------------------
def study(out_json: Path, figures: Path | None, t_end: float = 0.5, workers: int = 2) -> dict:
    s: dict = {"t_end_s": t_end}
    t0 = time.perf_counter()
    s["modal"] = modes_study(figures)
    s["floquet"] = floquet_study(figures)
    jobs = [(ka, None, False, "modal", t_end) for ka in KAS]  # the seed's case, fast
    jobs += [(0.75, None, False, "rk4", t_end)]  # accuracy check of the modal integrator
    jobs += [(ka, None, True, "rk4", t_end) for ka in KAS]  # rated load
    jobs += [(ka, 0.0, False, "modal", t_end) for ka in (0.25, 0.5)]  # no mesh damping
    jobs += [(ka, 0.0, False, "modal", t_end, True) for ka in KAS]  # located pinion
    with ProcessPoolExecutor(workers) as pool:
        res = list(pool.map(run_case, jobs))
    seed = res[:4]
    check = res[4]
    loaded = res[5:9]
    undamped = res[9:11]
    located = res[11:]
    strip = ("spectrum", "spectrum_last", "history", "whirl")
    s["seed_case"] = [{k: v for k, v in r.items() if k not in strip} for r in seed]
    s["rk4_check"] = {k: v for k, v in check.items() if k not in strip}
    m, c = seed[3]["metrics"], check["metrics"]
    s["rk4_check"]["deviation"] = {
        key: (m[key] - c[key]) / c[key] for key in ("x_1x_um", "y_1x_um", "x_42x_um", "y_42x_um")
    }
    s["rated_load"] = [{k: v for k, v in r.items() if k not in strip} for r in loaded]
    s["no_mesh_damping"] = []
    for r in undamped:
        d = {k: v for k, v in r.items() if k not in strip}
        if "error" not in r:
            d["growth"] = growth(r)
        s["no_mesh_damping"].append(d)
    s["located_pinion"] = [{k: v for k, v in r.items() if k not in strip} for r in located]
    if figures is not None:
        located_figure(located, figures / "compressor_located_pinion.png")
        spectra_figure(
            seed,
            "Seed case: 7,200 g·mm at the blind end, no torque, 2 % mesh damping (modal RK4)",
            figures / "compressor_spectra_seed.png",
        )
        spectra_figure(
            loaded,
            "Rated load (36.8 MW), from the static deflection, 2 % mesh damping (RK4, Δt = 1e-6 s)",
            figures / "compressor_spectra_loaded.png",
        )
        amplitudes_figure(seed, loaded, figures / "compressor_amplitudes_vs_ka.png")
        instability_figure(undamped, figures / "compressor_no_mesh_damping.png")
        whirl_figure(
            [
                (seed[3], "seed case (unbalance only)"),
                (loaded[3], "rated load 36.8 MW"),
            ],
            figures / "compressor_whirl_power.png",
        )
    s["wall_s"] = time.perf_counter() - t0
    out_json.parent.mkdir(parents=True, exist_ok=True)
    out_json.write_text(json.dumps(s, indent=1))
    return s


def report(s: dict) -> str:
    lines = []
    t = s["modal"]["ten_x"]
    lines.append(
        f"10x mode: {t['frequency_rpm']:.0f} cpm ({t['order']:.2f}x), log dec {t['log_dec']:.3f}, "
        f"{t['whirl']} {t['type']} {t['energy']}"
    )
    for name in ("seed_case", "rated_load", "located_pinion"):
        lines.append(name)
        for r in s[name]:
            if "error" in r:
                lines.append(f"  Ka {r['ka']:.2f}: {r['error'][:100]}")
                continue
            m = r["metrics"]
            lines.append(
                f"  Ka {r['ka']:.2f}: 1x {m['x_1x_um']:.4f}/{m['y_1x_um']:.4f} um, 42x "
                f"{m['x_42x_um']:.4f} um, 10x run {m['x_10x_run_um']:.2e} last "
                f"{m['x_10x_last_um']:.2e} um, 32x last {m['x_32x_last_um']:.2e} um, 8x last "
                f"{m['x_8x_last_um']:.2e} um "
                f"({r['method']}, {r['wall_s']:.0f} s)"
            )
    lines.append(f"rk4 check: {s['rk4_check'].get('deviation')}")
    for r in s["no_mesh_damping"]:
        if "error" in r:
            lines.append(f"  no mesh damping Ka {r['ka']}: {r['error'][:90]}")
        else:
            g = r["growth"]
            lines.append(
                f"  no mesh damping Ka {r['ka']}: growth {g['rate_per_s']:.1f} 1/s, "
                f"peaks {r['metrics']['peaks_last']}"
            )
    return "\n".join(lines)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--json", type=Path, default=ROOT / "out" / "compressor_gearbox.json")
    p.add_argument("--figures", type=Path, default=FIGURES)
    p.add_argument("--no-figures", action="store_true")
    p.add_argument("--t-end", type=float, default=0.5)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--floquet-only", action="store_true", help="only section 5 (about 1 min)")
    a = p.parse_args()
    figs = None if a.no_figures else a.figures
    if figs is not None:
        import matplotlib

        matplotlib.use("Agg")
        figs.mkdir(parents=True, exist_ok=True)
    if a.floquet_only:
        print(json.dumps(floquet_study(figs)["cases"], indent=1))
        return
    s = study(a.json, figs, a.t_end, a.workers)
    print(report(s))
    print(f"wall {s['wall_s']:.0f} s")


if __name__ == "__main__":
    main()
