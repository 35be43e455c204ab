"""Small model builders shared by the tests."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from gearrotor.model import Train


def single_shaft(
    *,
    length=1.0,
    diameter=0.05,
    elements=20,
    E=211e9,
    density=7850.0,
    poisson=0.3,
    bearings=(),
    disks=(),
    speed=0.0,
    **extra,
) -> Train:
    data = {
        "name": "test",
        "speed": speed,
        "materials": {"steel": {"E": E, "density": density, "poisson": poisson}},
        "shafts": [
            {
                "name": "s",
                "material": "steel",
                "sections": [{"length": length, "outer_diameter": diameter, "elements": elements}],
                "disks": list(disks),
            }
        ],
        "bearings": [dict(b, shaft="s") for b in bearings],
    }
    data.update(extra)
    return Train.model_validate(data)


def rotor_toml(
    *, speed: float = 6000, length: float = 0.8, elements: int = 6, disk_node: int | None = 3
) -> str:
    """A model file's rotor without bearings (they follow): a steel shaft ``rotor`` of 100 mm,
    ``length`` m in ``elements`` elements, with a 60 kg disk at ``disk_node`` (None: none), at
    ``speed`` rpm; the rotor of the tilting-pad tests (``tests/pads/pad_models.py``), of the
    whirl-table input tests and of the fluid-film rotor test."""
    disk = (
        ""
        if disk_node is None
        else f'disks = [{{ node = {disk_node}, mass = "60 kg", polar = "1.2 kg*m^2", '
        'transverse = "0.7 kg*m^2" }]\n'
    )
    return f"""
speed = "{speed} rpm"
[materials.steel]
E = "206 GPa"
poisson = 0.3
density = "7850 kg/m^3"
[[shafts]]
name = "rotor"
material = "steel"
sections = [{{ length = "{length} m", outer_diameter = "0.1 m", elements = {elements} }}]
{disk}"""


def chain(n_shafts: int, elements: int, *, unbalance_every_shaft: bool = False) -> dict:
    """A model (as a dict for :func:`gearrotor.io.model_from_dict`) of ``n_shafts`` SPEC 6.1
    shafts in a row (1.02 m, 60 mm, ``elements`` elements, a bearing of 1e7 N/m and
    1.75e4 N·s/m at each end), shaft k meshing with shaft k+1 at mid-span (30 teeth of 0.11 m
    pitch radius, 20°, 3e7 N/m: unity ratio, the shafts spinning ±6500 rpm in turn); an
    unbalance of 720 g·mm at mid-span of the first shaft (of every shaft with
    ``unbalance_every_shaft``) and a probe there. The trains of ``benchmarks/scaling.py`` and
    of ``tests/transient/test_transient_large.py``."""
    mid = elements // 2
    shafts, bearings, meshes, unbalances = [], [], [], []
    for k in range(n_shafts):
        name = f"s{k}"
        shafts.append(
            {
                "name": name,
                "material": "steel",
                "speed": f"{6500 * (-1) ** k} rpm",
                "sections": [
                    {"length": "1.02 m", "outer_diameter": "0.06 m", "elements": elements}
                ],
                **({"position": ["0 m", "0 m"]} if k == 0 else {}),
            }
        )
        bearings += [
            {"name": f"{name}-b{n}", "shaft": name, "node": n, "k": "1e7 N/m", "c": "1.75e4 N*s/m"}
            for n in (0, elements)
        ]
        if k == 0 or unbalance_every_shaft:
            unbalances.append({"shaft": name, "node": mid, "amount": "720 g*mm", "phase": "0 deg"})
        if k + 1 < n_shafts:
            meshes.append(
                {
                    "name": f"m{k}",
                    "gear": {"shaft": name, "node": mid, "teeth": 30, "radius": "0.11 m"},
                    "mate": {"shaft": f"s{k + 1}", "node": mid, "teeth": 30, "radius": "0.11 m"},
                    "radius_type": "pitch",
                    "pressure_angle": "0.349 rad",
                    "stiffness": "3.0e7 N/m",
                }
            )
    return {
        "name": f"chain {n_shafts}x{elements}",
        "reference_shaft": "s0",
        "speed": "6500 rpm",
        "materials": {"steel": {"E": "211 GPa", "poisson": 0.3, "density": "7890 kg/m^3"}},
        "shafts": shafts,
        "bearings": bearings,
        "meshes": meshes,
        "unbalances": unbalances,
        "probes": [{"name": "p0", "shaft": "s0", "node": mid, "angle": "0 deg"}],
    }


def start_view(folder: Path, examples: Path) -> tuple[Path, subprocess.Popen, str]:
    """``gearrotor view`` started as a user starts it, on a copy of the flagship in ``folder``:
    (the model file, the process, the first line it printed on stderr: "serving ... at
    http://127.0.0.1:PORT/ (Ctrl-C to stop)")."""
    model = folder / "model.toml"
    shutil.copy(examples / "unity_gearbox.toml", model)
    proc = subprocess.Popen(
        [sys.executable, "-m", "gearrotor", "view", str(model)],
        stderr=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    return model, proc, proc.stderr.readline()
