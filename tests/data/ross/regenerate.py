"""Regenerate the ROSS 3.1 reference files of tests/io/test_ross.py (run with ROSS, which needs
Python 3.13, from the repository root; gearrotor's own Python writes the export scripts):

    python3.13 -m venv /tmp/ross && /tmp/ross/bin/pip install ross-rotordynamics==3.1.0
    GEARROTOR_PYTHON=python3 /tmp/ross/bin/python tests/data/ross/regenerate.py

Writes, next to this script: the rotors of ROSS's own examples as ROSS saves them
(``Rotor.save``); the ROSS scripts ``gearrotor export --to ross-python`` writes for the
flagship (``export_*.py``, with the overrides listed in EXPORTS); and ``ross_modal.json``:
ROSS's ``run_modal`` (default 12 modes) of each rotor at the listed speeds (natural frequencies
wn, damped frequencies wd in rad/s, log decs). The speed × whirl table reference has its own
script, ``whirl_reference.py`` (run the same way).
"""

import json
import os
import runpy
import subprocess
from pathlib import Path

import numpy as np
import ross as rs
from ross.multi_rotor.multi_rotor import two_shaft_rotor_example

HERE = Path(__file__).resolve().parent
RPM = np.pi / 30

rotors = {
    "rotor_example": (rs.rotor_example(), [0.0, 3000.0, 10000.0]),
    "compressor_example": (rs.compressor_example(), [10000.0]),
    "two_shaft_rotor_example": (two_shaft_rotor_example(), [0.0, 3000.0]),
}
ROOT = HERE.parents[2]
#: the flagship exported as it is, with Cowper's shear coefficient (ROSS 3.1's "hutchinson"
#: coefficient is not Hutchinson's, see tests/io/test_ross.py), and with anisotropic bearings
#: and a tilted line of centres (the orientation sign)
ANISO = [f"bearings[{k}].{c}={v}" for k in range(4) for c, v in (("k", 0), ("kxx", 1e7),
                                                                    ("kyy", 3e7))]
EXPORTS = {
    "export_unity_cowper": ["shear_method=cowper"],
    "export_unity_tilted": ["shear_method=cowper", "meshes[0].orientation=0.5", *ANISO],
}
for name, sets in EXPORTS.items():
    cmd = [os.environ.get("GEARROTOR_PYTHON", "python3"), "-m", "gearrotor", "export",
           "examples/unity_gearbox.toml", "--output", str(HERE / f"{name}.py")]
    for s_ in sets:
        cmd += ["--set", s_]
    subprocess.run(cmd, check=True, cwd=ROOT)
    rotor = runpy.run_path(str(HERE / f"{name}.py"))["rotor"]
    rotors[name] = (rotor, [6500.0])
out = {"ross_version": rs.__version__, "exports": EXPORTS, "rotors": {}}
for name, (rotor, speeds) in rotors.items():
    if not name.startswith("export_"):
        rotor.save(HERE / f"{name}.toml")
    runs = []
    for rpm in speeds:
        m = rotor.run_modal(speed=rpm * RPM)
        runs.append(
            {
                "speed_rpm": rpm,
                "wn_rad_s": [float(x) for x in m.wn],
                "wd_rad_s": [float(x) for x in m.wd],
                "log_dec": [float(x) for x in m.log_dec],
            }
        )
    out["rotors"][name] = runs
(HERE / "ross_modal.json").write_text(json.dumps(out, indent=1) + "\n")
print("written", sorted(p.name for p in HERE.iterdir()))
