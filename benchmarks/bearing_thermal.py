"""Benchmark: thermal bearings, cost per load point (isoviscous, effective temperature, THD).

The 5-pad tilting-pad THD example (``examples/bearings/tilting_5pad_thd.toml``, the inputs of
ROSS 3.1's adiabatic tilting-pad example) at three load points, the Fillon et al. (1992) 4-pad
rig with heat to the pads and the journal (``tilting_4pad_thd.toml``; its effective-model row
adiabatic) at 1000 and 4000 rpm, and the other example bearings
with an ISO VG 32 oil supplied at 40 °C; equilibrium and the 8 coefficients per point, best of
``--repeat`` runs. Goal (issue 24): a THD tilting pad ≤ 2 s per load point on 2 cores (the
solver is single-threaded).

    python benchmarks/bearing_thermal.py [--repeat 3] [--grids 20x8,36x8]

The ratio column is the point's time over the isoviscous solve of the same bearing, grid and
load, measured in the same run (absolute times vary with the machine's load).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from _machine import cpu_name  # noqa: E402

from gearrotor.bearings import Grid, coefficients, load_bearing  # noqa: E402
from gearrotor.bearings.lubricant import CELSIUS, iso_vg  # noqa: E402
from gearrotor.bearings.thermal import ThermalModel  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "bearings"


def _grid(text: str) -> Grid:
    a, b = text.lower().split("x")
    return Grid(int(a), int(b))


def _time(case, opts, load, speed, repeat):
    best, co = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        co = coefficients(case.bearing, load, speed, options=opts)
        best = min(best, time.perf_counter() - t0)
    return best, co


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats (best is reported)")
    ap.add_argument("--grids", default="20x8,36x8", help="grids per pad, comma separated")
    args = ap.parse_args(argv)
    print(
        f"machine : {platform.node()} | {cpu_name()} | {os.cpu_count()} cpus | "
        f"{platform.system()} {platform.release()}"
    )
    print(f"python  : {platform.python_version()} | numpy {np.__version__}")
    tp = load_bearing(EXAMPLES / "tilting_5pad_thd.toml")
    points = [
        ("tilting 5-pad", tp, (884.05, -2670.4), 3000.0, tp.options.thermal),
        ("tilting 5-pad", tp, (884.05, -2670.4), 6000.0, tp.options.thermal),
        ("tilting 5-pad", tp, (0.0, -6000.0), 3000.0, tp.options.thermal),
    ]
    rig = load_bearing(EXAMPLES / "tilting_4pad_thd.toml")  # heat to pads and journal
    points += [
        ("tilting 4-pad Fillon rig", rig, rig.loads[0], rpm, rig.options.thermal)
        for rpm in (1000.0, 4000.0)
    ]
    oil = ThermalModel("thd", iso_vg(32), CELSIUS + 40.0)
    for name in ("tilting_4pad.toml", "pinion_3lobe_dam.toml", "plain_ld1.toml"):
        case = load_bearing(EXAMPLES / name)
        points.append((case.bearing.name, case, case.loads[0], case.speed * 30 / math.pi, oil))
    print()
    print(
        f"{'bearing':<28} {'grid':>6} {'rpm':>6} {'load N':>7} {'model':>10} {'s':>7} "
        f"{'ratio':>6} {'solves':>6} {'iter':>4} {'ecc':>6} {'T_max C':>7}"
    )
    worst_thd_tilting = 0.0
    for grid_text in args.grids.split(","):
        grid = _grid(grid_text)
        for name, case, load, rpm, thermal in points:
            speed = rpm * math.pi / 30
            base = replace(case.options, grid=grid, thermal=None)
            t_iso, _ = _time(case, base, load, speed, args.repeat)
            for model in ("isoviscous", "effective", "thd"):
                if model == "isoviscous":
                    t, co = t_iso, None
                    co = coefficients(case.bearing, load, speed, options=base)
                else:
                    walls = {}
                    if model == "effective":  # no wall heat paths in the effective model
                        walls = dict(pad_heat_transfer=0.0, journal_heat_transfer=0.0)
                    th_model = replace(thermal, model=model, **walls)
                    opts = replace(base, thermal=th_model)
                    t, co = _time(case, opts, load, speed, args.repeat)
                eq = co.equilibrium
                th = eq.thermal
                if model == "thd" and "tilting" in name:
                    worst_thd_tilting = max(worst_thd_tilting, t)
                print(
                    f"{name[:28]:<28} {grid_text:>6} {rpm:>6.0f} {math.hypot(*load):>7.0f} "
                    f"{model:>10} {t:>7.3f} {t / t_iso:>6.2f} {eq.film_solves:>6d} "
                    f"{th.iterations if th else 0:>4d} {eq.eccentricity_ratio:>6.3f} "
                    f"{(th.max_temperature - CELSIUS) if th else float('nan'):>7.2f}"
                )
    print(
        f"slowest THD tilting-pad load point: {worst_thd_tilting:.3f} s (best of {args.repeat}; "
        "goal <= 2 s)"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
