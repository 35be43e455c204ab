"""Reference runs of the compiled transient kernels, saved and compared byte for byte.

A change to the kernels' plumbing (how their arrays are grouped and passed) must leave every
number they produce unchanged to the last bit. This script runs short transients that between
them take every path of the kernels: the SPEC 6.1 flagship at its nominal point (RK4 on the
full model, frozen speed, classical modal RK4, the exponential modal scheme, a stiffness table
and a transmission error, external torques: constant, time table, speed law), the SPEC 6.1
backlash case 15 (exponential scheme with contact changes located, both back-flank laws,
classical modal RK4, RK4), the compressor (speed-dependent fluid-film bearing tables), an
operating point of the steam turbine (constant loads), a geometry-based mesh
(examples/gears/spur_rig.toml: tabulated stiffness and transmission error), the compressor
with seals (speed × whirl tables), tilting pads with their DOFs (the model of tests/pads),
and the synchronous-motor start-up of
examples/motor_gearbox_compressor.toml (torsional transient, and its first 0.4 s through the
coupled 6-DOF transient with the same drive laws, and 0.05 s of it at speed).

    python benchmarks/kernel_results.py save DIR [--only CASE ...]  # DIR/<case>.<name>.npy
    python benchmarks/kernel_results.py compare A B    # the same files, the same bytes?

Run ``save`` once with the tree before a change on ``PYTHONPATH`` and once with the tree after
it, then ``compare``: it prints one line per case and exits 1 if any array differs (wall times
are not saved).
"""

from __future__ import annotations

import argparse
import hashlib
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
CASE15 = {
    "meshes[0].variation.ka_ratio": "0.2",
    "meshes[0].variation.contact_ratio": "1.592",
    "meshes[0].variation.terms": "5",
}
BACKLASH = {**CASE15, "meshes[0].backlash.value": "0.0254 mm"}


def _with_torques(train):
    from gearrotor.io.model_file import model_from_dict

    data = train.model_dump()
    data["torques"] = [
        {"shaft": "shaft1", "node": 0, "value": 40.0},
        {"shaft": "shaft2", "node": 0, "time": [0.0, 0.01, 0.02], "values": [0.0, -30.0, -30.0]},
        {"shaft": "shaft2", "node": 1, "value": -10.0, "speed_exponent": 2.0,
         "reference_speed": 600.0},
    ]  # fmt: skip
    return model_from_dict(data)


def _lateral_cases():
    from gearrotor import load_model
    from gearrotor.analyses.transient import RK4, ModalRK4, Save, build_system, transient
    from gearrotor.analyses.transient.mesh import stiffness

    flagship = load_model(EX / "unity_gearbox.toml")
    varying = load_model(EX / "unity_gearbox.toml", CASE15)
    backlash = load_model(EX / "unity_gearbox.toml", BACKLASH)
    law = build_system(varying).meshes[0]
    phi = np.linspace(0, 2 * np.pi, 401)[:-1]
    te = np.array([[2e-6, 0.0], [0.0, 5e-7]])
    save = Save(dt=1e-4)
    yield "flagship_rk4", lambda: transient(flagship, t_end=0.01, integrator=RK4(dt=8.8e-6))
    yield (
        "flagship_rk4_frozen",
        lambda: transient(
            flagship, t_end=0.005, integrator=RK4(dt=8.8e-6), frozen_speed=True, reactions=False
        ),
    )
    yield "flagship_modal", lambda: transient(flagship, t_end=0.1, integrator=ModalRK4())
    yield (
        "flagship_modal_exp",
        lambda: transient(flagship, t_end=0.1, integrator=ModalRK4(exact_linear=True)),
    )
    yield "case15_table_te", lambda: transient(
        varying, t_end=0.05, integrator=ModalRK4(), save=save,
        stiffness_tables={0: (phi, stiffness(law, phi))}, transmission_error={0: te},
    )  # fmt: skip
    yield (
        "flagship_torques_rk4",
        lambda: transient(
            _with_torques(flagship), t_end=0.01, integrator=RK4(dt=8.8e-6), save=save
        ),
    )
    yield (
        "flagship_torques_modal",
        lambda: transient(_with_torques(flagship), t_end=0.03, integrator=ModalRK4(), save=save),
    )
    yield "backlash_exp", lambda: transient(backlash, t_end=0.1, integrator=ModalRK4())
    yield (
        "backlash_exp_mirrored",
        lambda: transient(
            backlash, t_end=0.05, integrator=ModalRK4(), back_flank="mirrored", save=save
        ),
    )
    yield (
        "backlash_modal_rk4",
        lambda: transient(backlash, t_end=0.03, integrator=ModalRK4(exact_linear=False), save=save),
    )
    yield (
        "backlash_rk4",
        lambda: transient(backlash, t_end=0.01, integrator=RK4(dt=4.4e-6), save=save),
    )
    compressor = load_model(EX / "compressor_gearbox.toml")
    yield "compressor_modal", lambda: transient(compressor, t_end=0.05, save=save)
    yield (
        "compressor_rk4",
        lambda: transient(compressor, t_end=0.002, integrator=RK4(dt=2e-7), save=Save(dt=2e-5)),
    )
    steam = load_model(EX / "steam_turbine_gearbox.toml")
    point = steam.operating_points[0].name
    yield (
        "steam_operating_point",
        lambda: transient(steam, t_end=0.02, operating_point=point, save=save),
    )
    # a mesh from its tooth geometry (loaded TVMS and transmission error tables, issue 27)
    spur = load_model(EX / "gears" / "spur_rig.toml")
    yield "spur_geometry_modal", lambda: transient(spur, t_end=0.02, save=save)
    yield (
        "spur_geometry_rk4",
        lambda: transient(spur, t_end=0.002, integrator=RK4(dt=2e-6), save=save),
    )
    # seals as speed x whirl tables (the transient reads their synchronous coefficients)
    seals = load_model(EX / "seals" / "compressor_with_seals.toml")
    yield "seals_modal", lambda: transient(seals, t_end=0.02, save=save)
    # tilting pads with their own DOFs (the model of tests/pads)
    sys.path[:0] = [str(ROOT / "tests" / "pads"), str(ROOT / "tests")]
    from pad_models import write

    pads = write(Path(tempfile.mkdtemp()))
    yield "pads_rk4", lambda: transient(pads, t_end=0.01, integrator=RK4(dt=5e-6), save=save)
    yield "pads_modal", lambda: transient(pads, t_end=0.05, save=save)
    motor = load_model(EX / "motor_gearbox_compressor.toml")
    yield (
        "startup_six_dof",
        lambda: transient(
            motor, t_end=0.4, integrator=ModalRK4(), initial="rest", save=Save(dt=1e-3)
        ),
    )
    # at speed: the synchronous motor pulls into step at the first evaluation
    yield (
        "motor_at_speed_six_dof",
        lambda: transient(motor, t_end=0.05, integrator=ModalRK4(), save=Save(dt=1e-4)),
    )


def _arrays(result) -> dict[str, np.ndarray]:
    """Every array field of a result (and its solver statistics but the wall times)."""
    from dataclasses import fields, is_dataclass

    out = {}
    for f in fields(result):
        v = getattr(result, f.name)
        if isinstance(v, np.ndarray):
            out[f.name] = v
        elif isinstance(v, (int, float)) and "wall" not in f.name:
            out[f.name] = np.array(v)
        elif isinstance(v, tuple) and v and all(isinstance(x, float) for x in v):
            out[f.name] = np.array(v)
        elif is_dataclass(v) and f.name == "stats":
            for g in fields(v):
                x = getattr(v, g.name)
                if isinstance(x, (int, float)) and "time" not in g.name:
                    out[f"stats.{g.name}"] = np.array(x)
    return out


def save(folder: Path, only: list[str] | None = None) -> None:
    from gearrotor import load_model
    from gearrotor.analyses.torsional import torsional_transient

    folder.mkdir(parents=True, exist_ok=True)
    cases = list(_lateral_cases())
    motor = load_model(EX / "motor_gearbox_compressor.toml")
    cases.append(("startup_torsional", lambda: torsional_transient(motor, t_end=20.0)))
    rigid = load_model(EX / "motor_gearbox_compressor.toml", {"meshes[0].backlash.value": "0 mm"})
    cases.append(
        (
            "startup_torsional_at_speed",
            lambda: torsional_transient(motor, t_end=1.0, initial_speed=150.0),
        )
    )
    cases.append(
        (
            "startup_torsional_rigid",
            lambda: torsional_transient(rigid, t_end=2.0, mesh="rigid"),
        )
    )
    for name, run in cases:
        if only and name not in only:
            continue
        arrays = _arrays(run())
        for key, arr in arrays.items():
            np.save(folder / f"{name}.{key}.npy", arr, allow_pickle=False)
        print(f"{name}: {len(arrays)} arrays", flush=True)


def compare(a: Path, b: Path) -> int:
    def digest(p: Path) -> str:
        return hashlib.sha256(p.read_bytes()).hexdigest()

    names_a = {p.name for p in a.glob("*.npy")}
    names_b = {p.name for p in b.glob("*.npy")}
    cases_b = {n.split(".", 1)[0] for n in names_b}
    names_a = {n for n in names_a if n.split(".", 1)[0] in cases_b}  # a subset saved: those
    bad = 0
    for name in sorted(names_a ^ names_b):
        print(f"only in one set: {name}")
        bad += 1
    by_case: dict[str, list[str]] = {}
    for name in sorted(names_a & names_b):
        by_case.setdefault(name.split(".", 1)[0], []).append(name)
    for case, names in by_case.items():
        differ = [n for n in names if digest(a / n) != digest(b / n)]
        print(f"{case:<34} {len(names):>3} arrays, {len(differ)} differ {' '.join(differ)}")
        bad += len(differ)
    print("bit-identical" if bad == 0 else f"{bad} differences")
    return 1 if bad else 0


def main() -> None:
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("save")
    s.add_argument("folder", type=Path)
    s.add_argument("--only", nargs="*", help="these cases only")
    c = sub.add_parser("compare")
    c.add_argument("a", type=Path)
    c.add_argument("b", type=Path)
    args = ap.parse_args()
    if args.cmd == "save":
        save(args.folder, args.only)
    else:
        sys.exit(compare(args.a, args.b))


if __name__ == "__main__":
    main()
