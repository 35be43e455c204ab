"""Reference numbers from ROSS 3.1 (ross-rotordynamics 3.1.0) on the inputs of the seal tests.

Not a test: the regeneration script of ``ross_reference.json``. ROSS is never a dependency of
gearrotor; run this in a separate environment that has it (Python 3.13)::

    python -m venv /tmp/ross && /tmp/ross/bin/pip install ross-rotordynamics==3.1.0
    /tmp/ross/bin/python tests/seals/ross_reference.py tests/seals/ross_reference.json

(ccp, imported by ROSS, prints to stdout at import: the JSON goes to the named file.)

The labyrinth inputs are ROSS's own seal test cases (ross/tests/test_seals_golden.py) with an
ideal gas; gearrotor takes a constant viscosity (ROSS's Sutherland fit at the inlet
temperature, 1.7747e-5 Pa s).
"""

import json
import sys
import warnings

import numpy as np

warnings.filterwarnings("ignore")

from ross.seals.holepattern_seal import HolePatternSeal  # noqa: E402
from ross.seals.labyrinth_seal import LabyrinthSeal  # noqa: E402
from ross.units import Q_  # noqa: E402

LAB = {
    "n": 0,
    "inlet_pressure": 308000,
    "outlet_pressure": 94300,
    "inlet_temperature": 283.15,
    "preswirl": 0.98,
    "n_teeth": 16,
    "shaft_diameter": Q_(145, "mm"),
    "radial_clearance": Q_(0.3, "mm"),
    "pitch": Q_(3.175, "mm"),
    "tooth_height": Q_(3.175, "mm"),
    "tooth_width": Q_(0.1524, "mm"),
    "seal_type": "inter",
    "molar_mass": 28.96807,
    "gamma": 1.41,
    "reference_temperatures": [283.15, 282.60903080958565],
    "reference_viscosities": [1.7746561138374613e-05, 1.7687886306966975e-05],
}
CASES = {
    "inter": ({}, [5000, 8000, 11000]),
    "rotor": (
        {"seal_type": "rotor", "preswirl": 0.3, "radial_clearance": Q_(0.25, "mm")},
        [6000, 9000],
    ),
    "stator": ({"seal_type": "stator"}, [8000]),
    "choked": ({"inlet_pressure": 1.0e6, "n_teeth": 3}, [8000]),
    "zero_swirl": ({"preswirl": 0.0}, [1]),
}
#: A real gas (CoolProp through ccp) at high pressure: methane 70 bar -> 35 bar, 14 teeth on
#: the stator.
REAL = {
    "inlet_pressure": 7.0e6,
    "outlet_pressure": 3.5e6,
    "inlet_temperature": 310.0,
    "seal_type": "stator",
    "n_teeth": 14,
    "gas_composition": {"Methane": 1.0},
    "gas_model": "real",
}
HP = dict(
    n=0,
    axial_length=0.0254,
    shaft_diameter=0.1502,
    radial_clearance=0.0004,
    relative_roughness=0.00198,
    cell_length=0.001,
    cell_width=0.001,
    cell_depth=0.00229,
    inlet_pressure=1830000.0,
    outlet_pressure=823500.0,
    inlet_temperature=300.0,
    preswirl=1.0,
    entrance_loss_coefficient=0.1,
    exit_loss_coefficient=0.5,
    sutherland_b=1.458e-6,
    sutherland_s=110.4,
    molar_mass=29.0,
    gamma=1.4,
)
HP_CASES = {
    "short_swirl": ({"outlet_pressure": 1.3e6}, 5000),
    "short_no_swirl": ({"outlet_pressure": 1.3e6, "preswirl": 0.0}, 5000),
    "long_swirl": ({"axial_length": 0.0508, "outlet_pressure": 1.3e6}, 5000),
}


def _lab(params, rpm, frequency_hz=None):
    kw = {**LAB, **params, "speed": Q_(rpm, "RPM")}
    if frequency_hz is not None:
        kw["frequency"] = Q_(frequency_hz, "Hz")
    s = LabyrinthSeal(**kw)
    return {c: _first(getattr(s, c)) for c in ("kxx", "kxy", "cxx", "cxy")} | {
        "leakage": _first(s.seal_leakage)
    }


def _lab_kw(kw, rpm):
    s = LabyrinthSeal(**{**kw, "speed": Q_(rpm, "RPM")})
    return {c: _first(getattr(s, c)) for c in ("kxx", "kxy", "cxx", "cxy")} | {
        "leakage": _first(s.seal_leakage)
    }


def _first(x):
    return float(np.ravel(np.asarray(x, float))[0])


def main():
    out = {"ross_version": "3.1.0", "labyrinth": {}, "labyrinth_whirl": {}, "hole_pattern": {}}
    for name, (params, speeds) in CASES.items():
        out["labyrinth"][name] = {str(rpm): _lab(params, [rpm]) for rpm in speeds}
    kw = {k: v for k, v in LAB.items() if k not in ("molar_mass", "gamma")}
    kw = {**kw, **REAL}
    kw.pop("reference_temperatures")
    kw.pop("reference_viscosities")
    out["labyrinth_real_gas"] = {"methane_10000rpm": _lab_kw(kw, [10000])}
    out["labyrinth_whirl"]["inter_8000rpm"] = {
        str(f): _lab({}, [8000], [f]) for f in (50.0, 133.33333333333334, 250.0)
    }
    for name, (params, rpm) in HP_CASES.items():
        s = HolePatternSeal(**{**HP, **params, "speed": Q_([rpm], "RPM")})
        out["hole_pattern"][name] = {
            "rpm": rpm,
            **{c: _first(getattr(s, c)) for c in ("kxx", "kxy", "cxx", "cxy", "mxx")},
            "leakage": _first(s.seal_leakage),
        }
    with open(sys.argv[1], "w") as fh:
        json.dump(out, fh, indent=1)
        fh.write("\n")


if __name__ == "__main__":
    main()
