"""Benchmark: the CPU time of drawing and saving each kind of figure the commands write.

    python3 benchmarks/figures.py [--repeat N] [--only NAME ...]

Each kind is built anew ``N`` times (default 5; a command builds each figure once), as the
command that writes it builds it, and saved as that command saves it (``gearrotor.files.
figure_bytes``: dpi, ``bbox_inches``). Printed per kind, the minimum over the repeats of the
process CPU time (``time.process_time``: the other sessions on a shared machine slow the wall
clock more than the CPU time) of:

- build: making the figure (axes, curves, labels; the study spectra figure reuses one figure
  as ``study report`` does),
- save: ``figure_bytes`` (layout, draw, PNG encoding),
- matplotlib's save: ``fig.savefig`` with the same arguments on a figure built the same way
  (its draw-disabled layout pass before the draw: what ``figure_bytes`` did before issue 28's
  eighth round), and whether its PNG is the same, byte for byte.

The data: the flagship model (``examples/unity_gearbox.toml``) and the steam turbine for the
model views, the flagship's modes at 6500 rpm, a 13-speed Campbell, a 9-speed unbalance
response, a 0.3-s modal transient (the standard transient figures), and for the study report
seven synthetic cases (1x, 2x and mesh tones, the seed study's label lengths) and synthetic
study results along three parameters (the trend figures).
"""

from __future__ import annotations

import argparse
import io
import os
import statistics
import sys
import time
from pathlib import Path

from _machine import cpu_name

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
os.environ.setdefault("GEARROTOR_CACHE", "off")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from gearrotor.files import figure_bytes  # noqa: E402

RPM = 30.0 / np.pi
LABEL = "unbalance=720 g*mm, ka_ratio=0.2, contact_ratio=1.592, backlash=0 mm, terms=5"


def _case(k: int) -> xr.Dataset:
    """0.5 s at 1e-4 s of a shaft at 6450 rpm, two probes: 1x + 2x + a 30-tooth mesh tone."""
    t = np.arange(5000) * 1e-4
    w = 6450 / RPM * (1 + 0.001 * k)
    probe = 1e-4 * np.sin(w * t) + 1e-6 * np.sin(2 * w * t) + 1e-8 * np.sin(30 * w * t)
    speed = w + 0.1 * np.sin(30 * w * t)
    return xr.Dataset(
        {
            "probe_signal": (("time", "probe"), np.column_stack([probe, 0.7 * probe])),
            "probe_shaft": ("probe", [0, 0]),
            "shaft_speed": (("time", "shaft"), speed[:, None]),
            "mesh_frequency": ("mesh", [30 * w * RPM]),
        },
        coords={"time": t, "probe": ["gear1_x", "gear1_y"], "shaft": ["s1"], "mesh": ["m"]},
    )


def _results() -> xr.Dataset:
    """27 cases on a 3 x 3 x 3 grid of parameters, the seed study's six metrics."""
    grid = np.array(np.meshgrid([360.0, 720.0, 1080.0], [0.0, 0.1, 0.2], [0.0, 0.01, 0.02]))
    unb, ka, bl = (g.ravel() for g in grid)
    rng = np.random.default_rng(1)
    n = unb.size
    amp = (unb[:, None] * 1e-9) * (1 + ka[:, None]) * rng.uniform(0.9, 1.1, (n, 4))

    def per(dim: str, k: int, scale: float):
        return (("case", dim), scale * rng.uniform(0.5, 1.5, (n, k)))

    return xr.Dataset(
        {
            "amp_1x": (("case", "probe"), amp),
            "amp_2x": (("case", "probe"), amp / 10),
            "speed_fluctuation": per("shaft", 2, 5.0),
            "peak_mesh_force": per("mesh", 1, 2000.0),
            "contact_loss_fraction": per("mesh", 1, 0.01),
            "dominant_frequency": per("probe", 4, 6450.0),
        },
        coords={
            "case": np.arange(n),
            "unbalance": ("case", unb, {"units": "g*mm"}),
            "ka_ratio": ("case", ka),
            "backlash": ("case", bl, {"units": "mm"}),
            "probe": ["gear1_x", "gear1_y", "gear2_x", "gear2_y"],
            "shaft": ["shaft1", "shaft2"],
            "mesh": ["mesh"],
        },
        attrs={"title": "SPEC 6.1 transient test matrix"},
    )


def kinds() -> dict[str, tuple]:
    """name -> (make: () -> list of build callables, savefig keywords, whether the builds
    reuse one figure). A build callable returns a new figure (or the reused one drawn again);
    ``make`` runs the analyses once."""
    from gearrotor.analyses import campbell, modal, unbalance_response
    from gearrotor.analyses.transient import plots as tplots
    from gearrotor.io import load_model
    from gearrotor.plots import figures as pf
    from gearrotor.plots.model_view import plot_model
    from gearrotor.studies import plots as sp

    flagship = ROOT / "examples" / "unity_gearbox.toml"
    steam = ROOT / "examples" / "steam_turbine_gearbox.toml"

    def model_views():
        trains = [load_model(flagship), load_model(steam)]
        return [lambda t=t: plot_model(t) for t in trains]

    def mode_pages():
        res = modal(load_model(flagship), speed=6500 / RPM, max_frequency=100000 / RPM)
        elastic = [i for i in range(len(res)) if not res.overdamped[i]]
        return [lambda: pf.plot_mode_shapes(res, modes=elastic[:8])]

    def campbell_diagram():
        train = load_model(flagship)
        fmax = 80000 / RPM
        res = campbell(train, speeds=np.linspace(0, 12000, 13) / RPM, max_frequency=fmax)
        return [
            lambda: pf.plot_campbell(
                res,
                max_frequency=fmax,
                operating_speed=abs(train.speed),
                max_continuous_speed=train.max_continuous_speed,
            )
        ]

    def bode_orbits():
        train = load_model(flagship)
        res = unbalance_response(train, speeds=np.linspace(5800, 7200, 9) / RPM)
        return [lambda: pf.plot_bode(res), lambda: pf.plot_orbits(res, 4)]

    def transient_figures():
        from gearrotor.analyses.transient import transient

        ds = tplots._ds(transient(load_model(flagship), t_end=0.3))
        fns = (
            tplots.plot_time_histories,
            tplots.plot_spectra,
            tplots.plot_orbits,
            tplots.plot_speeds,
            tplots.plot_mesh,
            tplots.plot_whirl_power,
        )
        return [lambda fn=fn: fn(ds) for fn in fns]

    def spectra():
        cases = {f"{k}: {LABEL}": _case(k) for k in range(7)}
        kept = [None]  # one figure drawn again for each, as study report does

        def build(channel, name):
            kept[0] = sp.overlay_spectra(
                cases, channel=channel, name=name, title="a study", figure=kept[0]
            )
            return kept[0]

        figs = [("probe", "gear1_x"), ("probe", "gear1_y"), ("speed", "s1")]
        return [lambda c=c, n=n: build(c, n) for c, n in figs]

    def trends():
        ds = _results()
        params = ["unbalance", "ka_ratio", "backlash"]
        return [lambda p=p: sp.trend_figure(ds, p, params) for p in params]

    return {
        "model view (show --plot, report)": (
            model_views,
            dict(dpi=130, bbox_inches="tight"),
            False,
        ),
        "mode shapes, 8 modes (modal --plot)": (mode_pages, dict(dpi=130), False),
        "Campbell (campbell --plot)": (campbell_diagram, dict(dpi=130), False),
        "Bode, orbits (unbalance --plot)": (bode_orbits, dict(dpi=130), False),
        "transient figures (transient-plot)": (transient_figures, dict(dpi=110), False),
        "study spectra (study report)": (spectra, dict(dpi=110), True),
        "study trends (study report)": (trends, dict(dpi=110), False),
    }


def _close(fig, keep: bool) -> None:
    if not keep:
        plt.close(fig)


def measure(builds, kw: dict, repeat: int, reused: bool) -> dict:
    """Per figure (summed over the kind's figures): min build, save and matplotlib-save CPU
    seconds over ``repeat`` rounds, and whether the two saves gave the same bytes."""
    build_t, save_t, mpl_t, same = [], [], [], True
    for _ in range(repeat):
        b_sum = s_sum = m_sum = 0.0
        for build in builds:
            for path in ("ours", "matplotlib"):
                t0 = time.process_time()
                fig = build()
                t1 = time.process_time()
                if path == "ours":
                    png = figure_bytes(fig, **kw)
                else:
                    buf = io.BytesIO()
                    fig.savefig(buf, format="png", pil_kwargs={"compress_level": 3}, **kw)
                    same &= buf.getvalue() == png
                t2 = time.process_time()
                _close(fig, reused)
                if path == "ours":
                    b_sum += t1 - t0
                    s_sum += t2 - t1
                else:
                    m_sum += t2 - t1
        build_t.append(b_sum / len(builds))
        save_t.append(s_sum / len(builds))
        mpl_t.append(m_sum / len(builds))
    return {"build": min(build_t), "save": min(save_t), "mpl": min(mpl_t), "same": same}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--only", nargs="*", default=None, help="kinds whose name contains one")
    args = ap.parse_args()
    table = kinds()
    print(f"# figures: {cpu_name()}, matplotlib {matplotlib.__version__}, load {os.getloadavg()}")
    print(f"# CPU seconds per figure, min of {args.repeat}; save = gearrotor.files.figure_bytes")
    print()
    print("| figure kind | figures | build s | save s | matplotlib's save s | ratio | same PNG |")
    print("|---|---|---|---|---|---|---|")
    for name, (make, kw, reused) in table.items():
        if args.only and not any(o.lower() in name.lower() for o in args.only):
            continue
        builds = make()
        builds[0]()  # warm: fonts, tick objects' classes, numba
        plt.close("all")
        r = measure(builds, kw, args.repeat, reused)
        plt.close("all")
        print(
            f"| {name} | {len(builds)} | {r['build']:.3f} | {r['save']:.3f} | {r['mpl']:.3f} "
            f"| {r['mpl'] / r['save']:.2f} | {'yes' if r['same'] else 'NO'} |",
            flush=True,
        )
    print()
    print(f"(median load during the run {statistics.median(os.getloadavg()):.2f})")


if __name__ == "__main__":
    main()
