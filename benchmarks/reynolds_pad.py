"""Benchmark and bit-identity check of the fluid-film pad solve (``reynolds.solve_pad``).

A fixed, deterministic set of pad solves: every pad of every example bearing file
(examples/bearings/*.toml: fixed multilobe pads with pressure-dam pockets, tilting pads,
thermal bearings) plus a periodic 360° plain bearing and a tilting-pad bearing with flexible
pivots; each pad at several journal/pad states and velocities (cold and warm-started active
sets), under the three cavitation models, isoviscous and with a nodal viscosity field.

    python benchmarks/reynolds_pad.py --save out.npz      # every output array of every solve
    python benchmarks/reynolds_pad.py --compare a.npz b.npz   # bit for bit (np.array_equal)
    python benchmarks/reynolds_pad.py --time [--repeat 5]      # time the solve loop

Run ``--save`` with PYTHONPATH pointing at each tree to compare two versions of the solver.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if not os.environ.get("PYTHONPATH"):  # PYTHONPATH=<tree>/src picks the tree to measure
    sys.path.insert(0, str(ROOT / "src"))

from gearrotor.bearings import load_bearing  # noqa: E402
from gearrotor.bearings.geometry import plain, tilting_pad  # noqa: E402
from gearrotor.bearings.reynolds import FilmContact, Grid, pad_mesh, solve_pad  # noqa: E402

DEG = math.pi / 180.0
CAVITATION = ("swift_stieber", "half_sommerfeld", "none")


def bearings() -> list[tuple[str, object, Grid, float]]:
    """(name, bearing, grid, speed rad/s) of every case."""
    out = []
    for path in sorted((ROOT / "examples" / "bearings").glob("*.toml")):
        case = load_bearing(path)
        speed = case.speed if case.speed is not None else 1000.0
        out.append((path.stem, case.bearing, case.options.grid, speed))
    out.append(("plain_periodic", plain(0.1, 0.05, 100e-6, 0.02), Grid(24, 6), 800.0))
    tp = tilting_pad(
        0.1,
        0.07,
        78.44e-6,
        0.0277,
        [45 * DEG, 135 * DEG, 225 * DEG, 315 * DEG],
        75 * DEG,
        0.47,
        0.5,
        inertia=2e-4,
        mass=0.5,
        thickness=0.02,
        pivot_stiffness=5e8,
    )
    out.append(("tilting_flexible_pivot", tp, Grid(24, 8), 420.0))
    return out


def cases():
    """Yield (label, mesh, q, qdot, omega, viscosity, radius, clearance, cavitation, warm)."""
    rng = np.random.default_rng(20261128)
    for name, b, grid, speed in bearings():
        r, c = b.radius, b.clearance
        for k, pad in enumerate(b.pads):
            mesh = pad_mesh(pad, r, b.length, c, grid)
            shape = (len(mesh.theta), len(mesh.zeta))
            tt, zz = np.meshgrid(mesh.theta, mesh.zeta, indexing="ij")
            field = b.viscosity * (1.0 + 0.3 * np.sin(tt) * np.cos(3 * zz / max(zz.max(), 1e-9)))
            assert field.shape == shape
            for s in range(4):
                q = rng.uniform(-0.45, 0.45, 4)
                if not hasattr(pad, "pivot"):
                    q[2:] = 0.0
                qdot = rng.uniform(-1, 1, 4) * 0.02 * abs(speed) * (s % 2)
                omega = speed if s != 3 else -speed
                for cav in CAVITATION:
                    for visc in (b.viscosity, field):
                        label = f"{name}/pad{k}/s{s}/{cav}/{'field' if np.ndim(visc) else 'iso'}"
                        yield label, mesh, q, qdot, omega, visc, r, c, cav


def run_all(collect: bool = True) -> tuple[dict, int]:
    out: dict[str, np.ndarray] = {}
    n = 0
    for label, mesh, q, qdot, omega, visc, r, c, cav in cases():
        kw = dict(viscosity=visc, radius=r, clearance=c, cavitation=cav)
        try:
            cold = solve_pad(mesh, q, qdot, omega, **kw)
            # warm start from the cold set at a nearby state (as the Jacobians and Newton do)
            warm = solve_pad(mesh, q * 0.97, qdot, omega, active=cold.active, **kw)
        except FilmContact as exc:
            if collect:
                out[label + "/contact"] = np.array(str(exc))
            continue
        n += 2
        if collect:
            for tag, f in (("cold", cold), ("warm", warm)):
                for attr in ("theta", "z", "pressure", "film", "forces", "active"):
                    out[f"{label}/{tag}/{attr}"] = np.asarray(getattr(f, attr))
                for attr in ("side_flow", "friction_power", "iterations"):
                    out[f"{label}/{tag}/{attr}"] = np.array(getattr(f, attr))
    return out, n


def compare(a: str, b: str) -> int:
    da, db = np.load(a), np.load(b)
    ka, kb = set(da.files), set(db.files)
    bad = sorted(ka ^ kb)
    for k in sorted(ka & kb):
        x, y = da[k], db[k]
        if x.dtype != y.dtype or x.shape != y.shape or not np.array_equal(x, y):
            bad.append(k)
    n_solves = len({k.rsplit("/", 1)[0] for k in ka if not k.endswith("/contact")})
    print(f"{len(ka & kb)} arrays of {n_solves} pad solves compared bit for bit: {len(bad)} differ")
    for k in bad[:20]:
        print("  differs:", k)
    return 1 if bad else 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--save", metavar="NPZ")
    ap.add_argument("--compare", nargs=2, metavar="NPZ")
    ap.add_argument("--time", action="store_true")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    if args.compare:
        return compare(*args.compare)
    if args.save:
        out, n = run_all()
        np.savez(args.save, **out)
        print(f"{n} pad solves, {len(out)} arrays written to {args.save}")
    if args.time:
        run_all(collect=False)  # meshes built and cached
        best = math.inf
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            _, n = run_all(collect=False)
            best = min(best, time.perf_counter() - t0)
        print(f"{'pad solves':>12} {'best s':>8} {'ms/solve':>9}")
        print(f"{n:>12d} {best:>8.3f} {1e3 * best / n:>9.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
