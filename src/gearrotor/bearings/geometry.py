"""Bearing geometry: pads, pockets, fixed-geometry and tilting-pad journal bearings.

Conventions (used throughout :mod:`gearrotor.bearings`)
--------------------------------------------------------
* Global lateral axes x, y; the shaft spins about +z. The circumferential angle θ is measured
  from +x towards +y (counter-clockwise seen from +z). A positive speed turns the journal
  counter-clockwise, i.e. in the direction of increasing θ.
* The journal centre sits at (x, y) relative to the bearing centre. The film thickness of a pad is

      h(θ, z) = c_p − (c_p − c) cos(θ − θ_p) − x cos θ − y sin θ + pocket(θ, z)
                [ − δ (R + t) sin(θ − θ_p) + ξ cos(θ − θ_p) ]   (tilting pads only)

  with c the assembled (bearing) radial clearance, c_p = c / (1 − m) the pad (machined)
  clearance, m the preload, θ_p = θ_start + offset · arc the pad's reference (pivot) angle,
  δ the pad tilt (rad) and ξ the outward radial pivot displacement (m).
* All pockets are centred axially (symmetric about the bearing mid-plane).

Everything is SI: lengths in m, angles in rad, viscosity in Pa·s, speeds in rad/s.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ..errors import ModelError

__all__ = [
    "Pocket",
    "Pad",
    "FixedBearing",
    "TiltingPad",
    "TiltingPadBearing",
    "Bearing",
    "plain",
    "axial_groove",
    "offset_halves",
    "elliptical",
    "multilobe",
    "tilting_pad",
]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class Pocket:
    """A recessed step pocket (pressure dam) on a pad.

    Attributes
    ----------
    start
        Angle of the pocket start from the pad start (rad, ≥ 0). The pocket spans
        ``[pad.start + start, pad.start + start + arc]``; with a positive speed the step (dam) is
        at its end.
    arc
        Angular extent of the pocket (rad).
    width
        Axial width (m), centred on the bearing mid-plane.
    depth
        Depth of the recess (m), added to the film thickness.
    """

    start: float
    arc: float
    width: float
    depth: float

    def __post_init__(self) -> None:
        _positive("pocket.arc", self.arc)
        _positive("pocket.width", self.width)
        _positive("pocket.depth", self.depth)
        if self.start < 0:
            raise ModelError(
                "pocket start must be ≥ 0",
                field="pocket.start",
                value=self.start,
                expected="an angle from the pad start, ≥ 0",
            )


@dataclass(frozen=True)
class Pad:
    """One fixed pad (lobe or arc) of a journal bearing.

    Attributes
    ----------
    start
        Angle of the pad start (rad, from +x, counter-clockwise).
    arc
        Angular extent (rad), 0 < arc ≤ 2π. A 2π pad with ``periodic`` is a full plain bearing.
    preload
        Preload m = 1 − c/c_p (dimensionless, 0 ≤ m < 1).
    offset
        Position of the reference (minimum-clearance) angle in the pad, θ_p = start + offset·arc.
    pocket
        Optional pressure-dam pocket.
    periodic
        True only for a full 360° film without a groove (plain cylindrical bearing).
    """

    start: float
    arc: float
    preload: float = 0.0
    offset: float = 0.5
    pocket: Pocket | None = None
    periodic: bool = False

    def __post_init__(self) -> None:
        if not 0.0 < self.arc <= TWO_PI + 1e-12:
            raise ModelError(
                "pad arc out of range",
                field="pad.arc",
                value=self.arc,
                expected="0 < arc ≤ 360 deg",
            )
        if not 0.0 <= self.preload < 1.0:
            raise ModelError(
                "preload out of range",
                field="pad.preload",
                value=self.preload,
                expected="0 ≤ preload < 1",
            )
        if self.periodic and abs(self.arc - TWO_PI) > 1e-9:
            raise ModelError(
                "only a 360° pad can be periodic",
                field="pad.periodic",
                value=self.arc,
                expected="arc = 360 deg",
            )
        if self.pocket is not None and self.pocket.start + self.pocket.arc > self.arc + 1e-12:
            raise ModelError(
                "pocket extends beyond the pad",
                field="pad.pocket",
                value=f"{math.degrees(self.pocket.start + self.pocket.arc):.4g} deg",
                expected=f"start + arc ≤ pad arc ({math.degrees(self.arc):.4g} deg)",
            )

    @property
    def reference_angle(self) -> float:
        """θ_p (rad): the pad's minimum-clearance (pivot) angle."""
        return self.start + self.offset * self.arc


@dataclass(frozen=True)
class FixedBearing:
    """A fixed-geometry journal bearing: a set of pads on one journal.

    Attributes
    ----------
    diameter
        Journal diameter D (m).
    length
        Axial length L (m).
    clearance
        Assembled radial clearance c (m) (the minimum clearance of a preloaded lobe).
    viscosity
        Dynamic viscosity μ (Pa·s), isoviscous.
    pads
        The pads.
    name
        Free text.
    """

    diameter: float
    length: float
    clearance: float
    viscosity: float
    pads: tuple[Pad, ...]
    name: str = ""

    def __post_init__(self) -> None:
        _positive("diameter", self.diameter)
        _positive("length", self.length)
        _positive("clearance", self.clearance)
        _positive("viscosity", self.viscosity)
        if self.clearance > 0.05 * self.diameter:
            raise ModelError(
                "radial clearance is not small compared with the radius",
                field="clearance",
                value=self.clearance,
                expected=f"c ≪ R (typically 1e-3 D = {1e-3 * self.diameter:.3g} m)",
            )
        if not self.pads:
            raise ModelError(
                "a bearing needs at least one pad",
                field="pads",
                value=[],
                expected="one or more pads",
            )
        object.__setattr__(self, "pads", tuple(self.pads))
        for k, pad in enumerate(self.pads):
            if pad.pocket is not None and pad.pocket.width > self.length + 1e-12:
                raise ModelError(
                    "pocket wider than the bearing",
                    field=f"pads[{k}].pocket.width",
                    value=pad.pocket.width,
                    expected=f"≤ length ({self.length} m)",
                )

    @property
    def radius(self) -> float:
        """Journal radius R (m)."""
        return 0.5 * self.diameter


@dataclass(frozen=True)
class TiltingPad:
    """One tilting pad.

    Attributes
    ----------
    pivot
        Pivot angle θ_p (rad).
    arc
        Pad arc (rad).
    offset
        Pivot offset (fraction of the arc from the pad's leading edge for a positive speed).
    preload
        Preload m = 1 − c/c_p.
    inertia
        Pad mass moment of inertia about the pivot (kg·m²).
    mass
        Pad mass (kg), used with a flexible pivot.
    thickness
        Pad thickness t (m): the lever of the tilt is R + t.
    pivot_stiffness
        Radial pivot stiffness (N/m); ``None`` = rigid pivot (no radial pad DOF).
    """

    pivot: float
    arc: float
    offset: float = 0.5
    preload: float = 0.0
    inertia: float = 0.0
    mass: float = 0.0
    thickness: float = 0.0
    pivot_stiffness: float | None = None

    def __post_init__(self) -> None:
        if not 0.0 < self.arc < math.pi:
            raise ModelError(
                "tilting-pad arc out of range",
                field="pad.arc",
                value=self.arc,
                expected="0 < arc < 180 deg",
            )
        if not 0.0 <= self.preload < 1.0:
            raise ModelError(
                "preload out of range",
                field="pad.preload",
                value=self.preload,
                expected="0 ≤ preload < 1",
            )
        for name in ("inertia", "mass", "thickness"):
            if getattr(self, name) < 0:
                raise ModelError(
                    f"{name} must be ≥ 0",
                    field=f"pad.{name}",
                    value=getattr(self, name),
                    expected="a value ≥ 0",
                )
        if self.pivot_stiffness is not None and self.pivot_stiffness <= 0:
            raise ModelError(
                "pivot stiffness must be > 0",
                field="pad.pivot_stiffness",
                value=self.pivot_stiffness,
                expected="> 0 N/m, or omit for rigid",
            )

    @property
    def start(self) -> float:
        """Pad start angle (rad)."""
        return self.pivot - self.offset * self.arc

    def as_pad(self) -> Pad:
        """The pad's film geometry at zero tilt (a fixed pad with the same profile)."""
        return Pad(self.start, self.arc, self.preload, self.offset)


@dataclass(frozen=True)
class TiltingPadBearing:
    """A tilting-pad journal bearing. Same fields as :class:`FixedBearing` with tilting pads."""

    diameter: float
    length: float
    clearance: float
    viscosity: float
    pads: tuple[TiltingPad, ...]
    name: str = ""

    def __post_init__(self) -> None:
        _positive("diameter", self.diameter)
        _positive("length", self.length)
        _positive("clearance", self.clearance)
        _positive("viscosity", self.viscosity)
        if not self.pads:
            raise ModelError(
                "a bearing needs at least one pad",
                field="pads",
                value=[],
                expected="one or more pads",
            )
        object.__setattr__(self, "pads", tuple(self.pads))

    @property
    def radius(self) -> float:
        """Journal radius R (m)."""
        return 0.5 * self.diameter

    @property
    def n_pad_dofs(self) -> int:
        """Number of pad DOFs: one tilt per pad plus one radial DOF per flexible pivot."""
        return len(self.pads) + sum(p.pivot_stiffness is not None for p in self.pads)


Bearing = FixedBearing | TiltingPadBearing


def _positive(name: str, value: float) -> None:
    if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
        raise ModelError(
            f"{name} must be a positive number",
            field=name,
            value=value,
            expected="a finite value > 0",
        )


def plain(
    diameter: float, length: float, clearance: float, viscosity: float, name: str = "plain"
) -> FixedBearing:
    """Plain cylindrical (360°, ungrooved) journal bearing (all SI)."""
    return FixedBearing(
        diameter, length, clearance, viscosity, (Pad(0.0, TWO_PI, periodic=True),), name
    )


def axial_groove(
    diameter: float,
    length: float,
    clearance: float,
    viscosity: float,
    n_grooves: int = 2,
    groove_arc: float = math.radians(20.0),
    first_groove: float = 0.0,
    name: str = "axial groove",
) -> FixedBearing:
    """Cylindrical bearing with ``n_grooves`` equal axial grooves (ambient pressure).

    Grooves of ``groove_arc`` (rad) are centred at ``first_groove + k·2π/n`` (rad); the pads
    between them are circular arcs (no preload).
    """
    if n_grooves < 1:
        raise ModelError(
            "need at least one groove",
            field="n_grooves",
            value=n_grooves,
            expected="an integer ≥ 1",
        )
    pitch = TWO_PI / n_grooves
    arc = pitch - groove_arc
    pads = tuple(Pad(first_groove + 0.5 * groove_arc + k * pitch, arc) for k in range(n_grooves))
    return FixedBearing(diameter, length, clearance, viscosity, pads, name)


def multilobe(
    diameter: float,
    length: float,
    clearance: float,
    viscosity: float,
    pivots: Sequence[float],
    arc: float,
    preload: float,
    offset: float = 0.5,
    pockets: dict[int, Pocket] | None = None,
    name: str = "multilobe",
) -> FixedBearing:
    """Multi-lobe bearing with lobes whose reference angles are ``pivots`` (rad).

    Each lobe spans ``arc`` (rad) starting at ``pivot − offset·arc``; ``pockets`` maps a lobe
    index (0-based) to a pressure-dam :class:`Pocket`.
    """
    pockets = pockets or {}
    for k in pockets:
        if not 0 <= k < len(pivots):
            raise ModelError(
                "pocket on a pad that does not exist",
                field="pockets",
                value=k,
                expected=f"pad index 0..{len(pivots) - 1}",
            )
    pads = tuple(
        Pad(p - offset * arc, arc, preload, offset, pockets.get(k)) for k, p in enumerate(pivots)
    )
    return FixedBearing(diameter, length, clearance, viscosity, pads, name)


def offset_halves(
    diameter: float,
    length: float,
    clearance: float,
    viscosity: float,
    preload: float = 0.5,
    groove_arc: float = math.radians(20.0),
    name: str = "offset halves",
) -> FixedBearing:
    """Two-lobe offset-halves bearing, split horizontally, for a positive speed.

    The two halves are shifted horizontally in opposite directions so that each lobe converges
    towards the trailing split line: lobe 1 spans the upper half (grooves of ``groove_arc`` at
    the split lines), lobe 2 the lower half, each with its minimum clearance c at the trailing
    end of its arc (offset 1.0) and preload ``preload`` (c_p = c/(1 − m) at the far end).
    """
    arc = math.pi - groove_arc
    start = 0.5 * groove_arc
    pads = (Pad(start, arc, preload, 1.0), Pad(start + math.pi, arc, preload, 1.0))
    return FixedBearing(diameter, length, clearance, viscosity, pads, name)


def elliptical(
    diameter: float,
    length: float,
    clearance: float,
    viscosity: float,
    preload: float = 0.5,
    groove_arc: float = math.radians(20.0),
    name: str = "elliptical",
) -> FixedBearing:
    """Elliptical (lemon-bore) bearing: two lobes centred at 90° and 270°, horizontal split."""
    arc = math.pi - groove_arc
    return multilobe(
        diameter,
        length,
        clearance,
        viscosity,
        (0.5 * math.pi, 1.5 * math.pi),
        arc,
        preload,
        0.5,
        name=name,
    )


def tilting_pad(
    diameter: float,
    length: float,
    clearance: float,
    viscosity: float,
    pivots: Sequence[float],
    arc: float,
    preload: float = 0.0,
    offset: float = 0.5,
    inertia: float = 0.0,
    mass: float = 0.0,
    thickness: float = 0.0,
    pivot_stiffness: float | None = None,
    name: str = "tilting pad",
) -> TiltingPadBearing:
    """Tilting-pad bearing with identical pads at ``pivots`` (rad)."""
    pads = tuple(
        TiltingPad(p, arc, offset, preload, inertia, mass, thickness, pivot_stiffness)
        for p in pivots
    )
    return TiltingPadBearing(diameter, length, clearance, viscosity, pads, name)
