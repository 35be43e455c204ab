"""Tilting pads with their dynamics in the train (issue 24): the full coefficients over speed,
the pad inertia and pivot overrides of a model file, and speed × whirl tables of the reduced
coefficients.

* :func:`pad_table` — a :class:`~gearrotor.elements.PadTable`: the full film stiffness and
  damping over [x, y, pad DOFs] (pivot springs included) at one load over several speeds, and
  the pads' mass matrix; the train carries it as pad DOFs
  (:class:`~gearrotor.elements.PadBearing`).
* :func:`with_pad_properties` — a tilting-pad bearing with the pad inertia, pad mass and pivot
  stiffness a model file gives (``[[bearings]] fluid_film.pad_inertia`` …), checked.
* :func:`whirl_table` — the reduced coefficients on a speed × whirl grid (``K_r(Ω, ω)``,
  ``C_r(Ω, ω)``, Lund's pad assembly at each whirl frequency), the frequency-dependent input of
  a bearing given by a table (:func:`save_whirl_table`, ``docs/bearings.md``).

Every function computes the full matrices once per (speed, load) with
:func:`~gearrotor.bearings.coefficients`; the reduced coefficients at any whirl frequency follow
from them by condensation (:func:`gearrotor.elements.pad_bearing.condense`), so the pad-DOF
model, the synchronous table and the whirl table are one set of numbers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..elements.pad_bearing import PadTable
from ..errors import ModelError
from ..files import atomic_file
from .coefficients import COEFFICIENT_NAMES, coefficients
from .equilibrium import Equilibrium, equilibrium
from .film import SolverOptions, _lever_scale
from .geometry import Bearing, TiltingPadBearing

__all__ = [
    "pad_table",
    "pad_table_from_equilibria",
    "with_pad_properties",
    "WhirlTable",
    "whirl_table",
    "save_whirl_table",
]


def with_pad_properties(
    bearing: Bearing,
    *,
    inertia: float | None = None,
    mass: float | None = None,
    pivot_stiffness: float | None = None,
    field: str = "fluid_film",
    source: str | None = None,
) -> TiltingPadBearing:
    """``bearing`` with every pad's inertia (kg·m² about the pivot), mass (kg) and pivot
    stiffness (N/m) replaced where given, checked for pad dynamics: a tilting-pad bearing,
    inertia > 0 on every pad, and mass > 0 where the pivot is flexible (a pad DOF without
    inertia makes the train's mass matrix singular). Errors name ``field`` (and ``source``)."""
    if not isinstance(bearing, TiltingPadBearing):
        raise ModelError(
            "pad dynamics needs a tilting-pad bearing",
            field=f"{field}.pad_dynamics",
            value=f"a {type(bearing).__name__} ({bearing.name or 'unnamed'})",
            expected="a bearing file of type = 'tilting_pad', or pad_dynamics = false",
            file=source,
        )
    pads = []
    for p in bearing.pads:
        p = replace(
            p,
            inertia=p.inertia if inertia is None else inertia,
            mass=p.mass if mass is None else mass,
            pivot_stiffness=p.pivot_stiffness if pivot_stiffness is None else pivot_stiffness,
        )
        pads.append(p)
    out = replace(bearing, pads=tuple(pads))
    for k, p in enumerate(out.pads):
        if not p.inertia > 0:
            raise ModelError(
                "pad dynamics needs the pads' inertia about the pivot",
                field=f"{field}.pad_inertia",
                value=f"{p.inertia:g} kg*m^2 (pad {k + 1})",
                expected="pad_inertia > 0 in the bearing file or here (kg*m^2)",
                file=source,
            )
        if p.pivot_stiffness is not None and not p.mass > 0:
            raise ModelError(
                "a flexible pivot needs the pad's mass (the radial pad DOF carries it)",
                field=f"{field}.pad_mass",
                value=f"{p.mass:g} kg (pad {k + 1})",
                expected="pad_mass > 0 in the bearing file or here (kg)",
                file=source,
            )
    return out


def _table_from(
    bearing: TiltingPadBearing, cos: Sequence, extrapolate: str
) -> tuple[PadTable, NDArray]:
    speed = np.array([abs(co.speed) for co in cos])
    order = np.argsort(speed)
    if np.any(np.diff(speed[order]) <= 0):
        raise ModelError(
            "the pad-dynamics speeds must differ",
            field="speeds",
            value=(speed * 30 / math.pi).tolist(),
            expected="distinct speeds",
        )
    co0 = cos[0]
    tab = PadTable(
        speed=speed[order],
        K=np.array([cos[i].K_full for i in order]),
        C=np.array([cos[i].C_full for i in order]),
        M=co0.M_full.copy(),
        dofs=tuple(co0.dofs),
        lever=_lever_scale(bearing),
        extrapolate=extrapolate,
    )
    return tab, order


def pad_table(
    bearing: TiltingPadBearing,
    load: Sequence[float],
    speeds: ArrayLike,
    *,
    options: SolverOptions | None = None,
    extrapolate: str = "error",
) -> PadTable:
    """Full coefficients of a tilting-pad bearing at one load (Fx, Fy in N) over ``speeds``
    (rad/s, signed: the journal's sense of rotation), as a :class:`PadTable` over |speed|."""
    cos, prev = [], None
    for w in np.atleast_1d(np.asarray(speeds, float)):
        eq = equilibrium(
            bearing,
            tuple(load),
            float(w),
            options=options,
            start=prev if prev is not None and prev.speed * w > 0 else None,
        )
        cos.append(coefficients(bearing, eq, options=options))
        prev = eq
    return _table_from(bearing, cos, extrapolate)[0]


def pad_table_from_equilibria(
    bearing: TiltingPadBearing,
    equilibria: Sequence[Equilibrium],
    *,
    options: SolverOptions | None = None,
    extrapolate: str = "error",
) -> PadTable:
    """Full coefficients at already solved equilibria (one per speed; an operating point's
    static loads, which may change with speed)."""
    cos = [coefficients(bearing, eq, options=options) for eq in equilibria]
    return _table_from(bearing, cos, extrapolate)[0]


@dataclass(frozen=True)
class WhirlTable:
    """Reduced coefficients on a speed × whirl grid.

    speed_rpm : (n_s,) shaft speeds (rpm, as solved: signed); whirl_rpm : (n_w,) whirl
    frequencies (rpm, ≥ 0); values : (n_s, n_w, 8) kxx kxy kyx kyy (N/m) cxx cxy cyx cyy (N·s/m);
    load : the static load (N); name : the bearing's name.
    """

    speed_rpm: NDArray
    whirl_rpm: NDArray
    values: NDArray
    load: tuple[float, float] = (0.0, 0.0)
    name: str = ""


def whirl_table(
    bearing: Bearing,
    load: Sequence[float],
    speeds: ArrayLike,
    whirls: ArrayLike,
    *,
    options: SolverOptions | None = None,
) -> WhirlTable:
    """The reduced coefficients at ``speeds`` (rpm, signed) × ``whirls`` (rpm, ≥ 0): at each
    speed the full matrices once, condensed at every whirl frequency. A fixed-geometry bearing's
    coefficients do not depend on the whirl (no fluid inertia here): its rows repeat."""
    from ..elements.pad_bearing import condense

    rpm = np.atleast_1d(np.asarray(speeds, float))
    wr = np.atleast_1d(np.asarray(whirls, float))
    if np.any(wr < 0) or np.any(np.diff(wr) <= 0):
        raise ModelError(
            "whirl frequencies must be >= 0 and increasing",
            field="whirls",
            value=wr.tolist(),
            expected="an increasing list of whirl frequencies >= 0 rpm",
        )
    vals = np.zeros((len(rpm), len(wr), 8))
    prev = None
    for i, n in enumerate(rpm):
        w = n * math.pi / 30
        eq = equilibrium(
            bearing,
            tuple(load),
            w,
            options=options,
            start=prev if prev is not None and prev.speed * w > 0 else None,
        )
        co = coefficients(bearing, eq, options=options)
        prev = eq
        for j, om in enumerate(wr * math.pi / 30):
            om = max(om, 1e-9 * max(abs(w), 1.0))
            z = condense(co.K_full, co.C_full, co.M_full, 1j * om)
            vals[i, j] = [*z.real.ravel(), *(z.imag / om).ravel()]
    return WhirlTable(rpm, wr, vals, (float(load[0]), float(load[1])), bearing.name)


_UNITS = ["rpm", "rpm"] + ["N/m"] * 4 + ["N*s/m"] * 4


def save_whirl_table(table: WhirlTable, path: str | Path) -> Path:
    """Write a speed × whirl table as CSV: header ``speed_rpm,whirl_rpm,kxx,…,cyy``, a ``#``
    units line, one row per (speed, whirl), whirl fastest (the format a model's ``table_file``
    reads, ``docs/bearings.md``)."""
    import csv

    path = Path(path)
    if path.suffix.lower() != ".csv":
        raise ModelError(
            "a whirl table is written as CSV", field="path", value=str(path), expected="a .csv file"
        )
    with atomic_file(path, "w", encoding="utf-8", newline="") as fh:
        fh.write(
            f"# bearing: {table.name}; load Fx,Fy = {table.load[0]!r},{table.load[1]!r} N; "
            "reduced coefficients at whirl_rpm\n"
        )
        w = csv.writer(fh)
        w.writerow(["speed_rpm", "whirl_rpm", *COEFFICIENT_NAMES])
        fh.write("# " + ",".join(_UNITS) + "\n")
        for i, s in enumerate(table.speed_rpm):
            for j, om in enumerate(table.whirl_rpm):
                w.writerow([repr(float(v)) for v in (s, om, *table.values[i, j])])
    return path
