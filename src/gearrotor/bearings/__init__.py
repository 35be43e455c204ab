"""Fluid-film journal bearings: geometry, Reynolds solver, equilibrium, dynamic coefficients.

Conventions: global lateral axes x, y; the shaft spins about +z; angles θ from +x towards +y;
a positive speed is counter-clockwise seen from +z. Loads are the static force on the journal
(N); film forces are the bearing reaction on the journal; K = −∂F/∂x, C = −∂F/∂ẋ. SI inside.
See ``docs/bearings.md``.

Typical use::

    from gearrotor.bearings import load_bearing, coefficients
    case = load_bearing("examples/bearings/pinion_3lobe_dam.toml")
    co = coefficients(case.bearing, case.loads[0], case.speed, options=case.options)
    co.K, co.C, co.equilibrium.eccentricity_ratio
"""

from .coefficients import (
    COEFFICIENT_NAMES,
    BearingTable,
    Coefficients,
    coefficients,
    coefficients_table,
    load_speed_sweep,
    load_sweep,
    load_table,
    save_table,
    static_stiffness,
)
from .equilibrium import Equilibrium, equilibrium, sommerfeld_number
from .film import BearingFilm, SolverOptions, dof_names, film_state
from .geometry import (
    Bearing,
    FixedBearing,
    Pad,
    Pocket,
    TiltingPad,
    TiltingPadBearing,
    axial_groove,
    elliptical,
    multilobe,
    offset_halves,
    plain,
    tilting_pad,
)
from .io import BearingCase, load_bearing, parse_bearing
from .reynolds import Grid, PadFilm

__all__ = [
    "COEFFICIENT_NAMES",
    "Bearing",
    "BearingCase",
    "BearingFilm",
    "BearingTable",
    "Coefficients",
    "Equilibrium",
    "FixedBearing",
    "Grid",
    "Pad",
    "PadFilm",
    "Pocket",
    "SolverOptions",
    "TiltingPad",
    "TiltingPadBearing",
    "axial_groove",
    "coefficients",
    "coefficients_table",
    "dof_names",
    "elliptical",
    "equilibrium",
    "film_state",
    "load_bearing",
    "load_speed_sweep",
    "load_sweep",
    "load_table",
    "multilobe",
    "offset_halves",
    "parse_bearing",
    "plain",
    "save_table",
    "sommerfeld_number",
    "static_stiffness",
    "tilting_pad",
]
