"""Seals shared by the seal tests (SI units)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

from gearrotor.seals import AnnularSeal, Friction, IdealGas, LabyrinthSeal, Liquid

HERE = Path(__file__).resolve().parent
RPM = 3.141592653589793 / 30

#: ROSS 3.1's numbers on the same inputs (regenerate with ross_reference.py).
ROSS = json.loads((HERE / "ross_reference.json").read_text())

#: Air as ROSS's seal tests give it (molar mass, γ; the viscosity of its Sutherland fit at the
#: inlet temperature, which gearrotor holds constant).
AIR = IdealGas(28.96807, 1.41, 1.7746561138374613e-05, 283.15)

#: ROSS's labyrinth test seal (ross/tests/test_seals_golden.py): 16 interlocking teeth.
LAB = LabyrinthSeal(
    shaft_diameter=0.145,
    radial_clearance=0.3e-3,
    n_teeth=16,
    pitch=3.175e-3,
    tooth_height=3.175e-3,
    tooth_width=0.1524e-3,
    teeth_on="interlocking",
    inlet_pressure=308000.0,
    outlet_pressure=94300.0,
    inlet_temperature=283.15,
    preswirl=0.98,
    fluid=AIR,
)
LAB_CASES = {
    "inter": LAB,
    "rotor": replace(LAB, teeth_on="rotor", preswirl=0.3, radial_clearance=0.25e-3),
    "stator": replace(LAB, teeth_on="stator"),
    "choked": replace(LAB, inlet_pressure=1.0e6, n_teeth=3),
}

#: ROSS's hole-pattern test seal (ross/tests/test_holepattern.py) at 13 bar outlet; the
#: viscosity of its Sutherland law at 300 K; Moody friction with roughness e = 0.00198 H.
HP_AIR = IdealGas(29.0, 1.4, 1.458e-6 * 300.0**1.5 / (110.4 + 300.0), 300.0)
_E = 0.00198 * 0.4e-3
HOLE_PATTERN = AnnularSeal(
    "hole_pattern",
    shaft_diameter=0.1502,
    radial_clearance=0.4e-3,
    length=0.0254,
    inlet_pressure=1.83e6,
    outlet_pressure=1.3e6,
    preswirl=1.0,
    fluid=HP_AIR,
    entrance_loss=0.1,
    stator=Friction("moody", roughness=_E),
    rotor=Friction("moody", roughness=_E),
    cell_depth=2.29e-3,
    hole_area_ratio=1.0,
    inlet_temperature=300.0,
)
HP_CASES = {
    "short_swirl": HOLE_PATTERN,
    "short_no_swirl": replace(HOLE_PATTERN, preswirl=0.0),
    "long_swirl": replace(HOLE_PATTERN, length=0.0508),
}


def kanki_long() -> AnnularSeal:
    """Kanki & Kawakami (1984) long water seal: R 100 mm, L 200 mm, C 0.5 mm, 2000 rpm, 1.47 ->
    0.49 MPa, no inlet swirl, entrance loss 0.2, Blasius friction."""
    return AnnularSeal(
        "liquid_annular",
        shaft_diameter=0.2,
        radial_clearance=0.5e-3,
        length=0.2,
        inlet_pressure=1.47e6,
        outlet_pressure=0.49e6,
        preswirl=0.0,
        fluid=Liquid(996.89, 8.78e-4),
        entrance_loss=0.2,
        stator=Friction("hirs", 0.079, -0.25),
        rotor=Friction("hirs", 0.079, -0.25),
    )


def kanki_short() -> AnnularSeal:
    """Kanki & Kawakami (1984) short water seal: L 40 mm, water at 25.6 °C, inlet swirl 400 rpm
    of 2000 (0.2), entrance loss 0.6, Blasius friction (rotor n = 0.07)."""
    return AnnularSeal(
        "liquid_annular",
        shaft_diameter=0.2,
        radial_clearance=0.5e-3,
        length=0.04,
        inlet_pressure=1.47e6,
        outlet_pressure=0.49e6,
        preswirl=0.2,
        fluid=Liquid(995.5, 7.888e-4),
        entrance_loss=0.6,
        stator=Friction("hirs", 0.079, -0.25),
        rotor=Friction("hirs", 0.07, -0.25),
    )
