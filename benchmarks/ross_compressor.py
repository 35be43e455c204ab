"""Benchmark: one damped eigen solve of ROSS's own compressor example (issue 28).

ROSS 3.1's ``compressor_example()`` (Timbó & Ritto 2019: 91 shaft elements on 55 stations, 36
of them concentric mass sleeves of negligible stiffness, 7 disks, two tabulated journal
bearings and 12 tabulated seals), rebuilt as a gearrotor model
(``benchmarks/data/ross_compressor.toml``: the same geometry, materials, disks and coefficient
tables; the sleeves as ``mass_outer_diameter``). Times ``modal(train, speed=...)`` for the 12
lowest modes at 10,000 rpm, warm, at distinct speeds (each call assembles the speed-dependent
tables), split into assembly, solve and classification, against ROSS's 0.075 s (issue 28,
ROSS 3.1 ``rotor.run_modal(speed, num_modes=12)`` warm on this machine).

    python3 benchmarks/ross_compressor.py [--repeat 10]
    python3 benchmarks/ross_compressor.py --convert ROSS_TOML   # regenerate the model file

``--convert`` reads ROSS's saved rotor (``ross/tests/data/compressor_example.toml`` of the
ROSS repository) and writes the gearrotor model: the numbers are ROSS's data, the conversion is
this script's.
"""

from __future__ import annotations

import argparse
import collections
import time
import tomllib
from pathlib import Path

import numpy as np
from _machine import busy_neighbour, cpu_name, environment

MODEL = Path(__file__).resolve().parent / "data" / "ross_compressor.toml"
RPM = np.pi / 30
ROSS_S = 0.075  # issue 28: ROSS 3.1, one warm run_modal at a new speed, this machine


def convert(ross_toml: Path) -> str:
    """The gearrotor model file of a ROSS single-shaft rotor file (stations, sleeves, disks,
    bearing and seal tables)."""
    d = tomllib.loads(ross_toml.read_text())
    shaft = collections.defaultdict(list)
    mats = {}
    for k, v in d.items():
        if k.startswith("ShaftElement"):
            shaft[v["n"]].append(v)
            m = v["material"]
            mats[m["name"]] = m
    lines = [
        'name = "ROSS compressor example (Timbó & Ritto 2019), rebuilt from ROSS 3.1"',
        'speed = "10000 rpm"',
        'shear_method = "cowper"',
        "",
    ]
    for name, m in mats.items():
        if m["E"] < 1e6:  # the sleeves' placeholder material: mass only
            continue
        lines += [
            f"[materials.{name}]",
            f"E = {m['E']!r}",
            f"shear_modulus = {m['G_s']!r}",
            f"density = {m['rho']!r}",
            "",
        ]
    sections = []
    for n in sorted(shaft):
        core = [e for e in shaft[n] if e["material"]["E"] >= 1e6]
        sleeve = [e for e in shaft[n] if e["material"]["E"] < 1e6]
        (c,) = core
        assert c["idl"] == c["idr"] and c["odl"] == c["odr"], "tapered elements"
        parts = [
            f"length = {c['L']!r}",
            f"outer_diameter = {c['odl']!r}",
            "elements = 1",
            f'material = "{c["material"]["name"]}"',
        ]
        if c["idl"] > 0:
            parts.append(f"inner_diameter = {c['idl']!r}")
        if sleeve:
            (s,) = sleeve
            assert abs(s["idl"] - c["odl"]) < 1e-12 and s["material"]["rho"] == c["material"]["rho"]
            parts.append(f"mass_outer_diameter = {s['odl']!r}")
        sections.append("  { " + ", ".join(parts) + " },")
    disks = [
        f"  {{ node = {v['n']}, mass = {v['m']!r}, polar = {v['Ip']!r}, "
        f"transverse = {v['Id']!r} }},"
        for k, v in d.items()
        if k.startswith("DiskElement")
    ]
    lines += ["[[shafts]]", 'name = "rotor"', 'material = "shaft_mat_1"', "sections = ["]
    lines += sections + ["]", "disks = ["] + disks + ["]", ""]
    for k, v in d.items():
        kind = (
            "bearings"
            if k.startswith("BearingElement")
            else "seals"
            if k.startswith("Seal")
            else None
        )
        if kind is None:
            continue
        assert not any(np.any(v[m]) for m in ("mxx", "mxy", "myx", "myy", "kzz", "czz"))
        lines += [f"[[{kind}]]", f'name = "{v["tag"]}"', 'shaft = "rotor"', f"node = {v['n']}"]
        table = [f"speed = {list(map(float, v['frequency']))!r}"]
        table += [
            f"{c} = {list(map(float, v[c]))!r}"
            for c in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
        ]
        lines += ["table = { " + ", ".join(table) + " }", ""]
    return "\n".join(lines)


_ROSS_SCRIPT = """
import sys, time, numpy as np, ross as rs
rotor = rs.compressor_example()
speeds = (10000 + 0.5 * np.arange(int(sys.argv[1]) + 1)) * np.pi / 30
rotor.run_modal(speed=speeds[0], num_modes=12)
out = []
for w in speeds[1:]:
    t0 = time.perf_counter()
    m = rotor.run_modal(speed=w, num_modes=12)
    out.append(time.perf_counter() - t0)
print(float(np.median(out)))
print(" ".join(f"{f:.3f}" for f in np.sort(m.wd)[:12] / (2 * np.pi)))
"""


def _ross(python: Path, repeat: int, pinned: bool = False) -> tuple[float, str] | None:
    """ROSS's warm ``run_modal`` at distinct speeds, in its own interpreter (a separate
    environment: ROSS is no dependency of gearrotor)."""
    import os
    import subprocess

    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    if pinned:
        env.update(OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    p = subprocess.run(
        [str(python), "-c", _ROSS_SCRIPT, str(repeat)], capture_output=True, text=True, env=env
    )
    if p.returncode != 0:
        print("ROSS failed: " + (p.stderr.strip().splitlines() or ["?"])[-1])
        return None
    t, freqs = p.stdout.strip().splitlines()[-2:]
    return float(t), freqs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=10)
    ap.add_argument("--convert", type=Path, help="write the model from ROSS's rotor file")
    ap.add_argument("--ross-python", type=Path, help="a Python with ROSS installed: time it too")
    args = ap.parse_args()
    if args.convert:
        MODEL.parent.mkdir(exist_ok=True)
        MODEL.write_text(convert(args.convert))
        print(f"written {MODEL}")
        return
    import importlib

    from gearrotor.assembly import assemble
    from gearrotor.io import load_model

    mm = importlib.import_module("gearrotor.analyses.lateral.modal")
    train = load_model(MODEL)
    asm = assemble(train)
    print(f"machine: {cpu_name()}; {environment()}")
    print(f"model: {MODEL.name}, {asm.n_dof} DOF")
    speeds = (10000 + 0.5 * np.arange(args.repeat + 1)) * RPM  # distinct speeds, ~10,000 rpm
    mm.modal(asm, speed=speeds[0], n_modes=12)  # warm: imports, first factorisations

    def timed(fn):
        out = []
        for w in speeds[1:]:
            t0 = time.perf_counter()
            fn(w)
            out.append(time.perf_counter() - t0)
        return float(np.median(out))

    fmax = 2 * np.pi * 1000  # 1000 Hz: the 12 lowest modes (160-891 Hz)
    rows = {
        "assembly asm.matrices(w) (tables)": timed(lambda w: asm.matrices(w)),
        "modal(train, max_frequency=1000 Hz)": timed(
            lambda w: mm.modal(train, speed=w, max_frequency=fmax)
        ),
        "modal(asm, max_frequency=1000 Hz)": timed(
            lambda w: mm.modal(asm, speed=w, max_frequency=fmax)
        ),
        "modal(train, n_modes=12, method=sparse)": timed(
            lambda w: mm.modal(train, speed=w, n_modes=12, method="sparse")
        ),
        "modal(train, method=dense)": timed(lambda w: mm.modal(train, speed=w, method="dense")),
    }
    with busy_neighbour():
        rows["modal(train, max_frequency), busy"] = timed(
            lambda w: mm.modal(train, speed=w, max_frequency=fmax)
        )
    ross = _ross(args.ross_python, args.repeat) if args.ross_python else None
    ross1 = _ross(args.ross_python, args.repeat, pinned=True) if args.ross_python else None
    ref = ross[0] if ross else ROSS_S
    where = "ROSS in this run" if ross else "ROSS 0.075 s (issue 28)"
    r = mm.modal(train, speed=10000 * RPM, max_frequency=fmax)
    print(f"{'step':<42}{'median s':>10}{where + ' / it':>28}")
    for k, t in rows.items():
        print(f"{k:<42}{t:>10.4f}{ref / t:>28.2f}")
    if ross:
        print(f"{'ROSS 3.1 run_modal(speed, num_modes=12)':<42}{ross[0]:>10.4f}")
    if ross1:
        print(f"{'ROSS 3.1, BLAS pinned to 1 thread':<42}{ross1[0]:>10.4f}")
    print(f"gearrotor: method {r.method}; 12 lowest modes at 10,000 rpm (Hz, log dec):")
    for f, ld in zip(r.damped_frequency / (2 * np.pi), r.log_dec, strict=True):
        print(f"  {f:10.3f} {ld:9.4f}")
    if ross:
        print(f"ROSS damped frequencies (Hz): {ross[1]}")


if __name__ == "__main__":
    main()
