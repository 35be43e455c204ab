"""A gear pair's tooth geometry and micro-geometry: the content of a gear-pair file, or the
inline ``geometry`` of a ``[[meshes]]`` entry (issue 27).

The tooth stiffness, the load sharing and the loaded transmission error computed from it live in
:mod:`gearrotor.gears`; this module only holds the validated input. Values accept units
(``"3 mm"``, ``"20 deg"``, ``"206 GPa"``, ``"500 N*m"``); plain numbers are SI. Per-gear values
are ``[pinion, gear]`` pairs (the pinion is the first gear, usually the one with fewer teeth).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, Strict, model_serializer, model_validator

from ..units import Angle, Dimensionless, Length, Modulus, Torque

__all__ = [
    "ToothRelief",
    "FlankModifications",
    "GearModifications",
    "GearPair",
    "GEAR_PAIR_REQUIRED",
]

#: The keys a complete gear pair needs (a gear-pair file, or an inline geometry without
#: ``file``); the others have defaults. ``E`` and ``poisson`` may also come from the shaft
#: material when the pair is a mesh of a model.
GEAR_PAIR_REQUIRED = ("module", "teeth", "pressure_angle", "face_width")

Int = Annotated[int, Strict()]


class Spec(BaseModel):
    """Frozen, unknown keys rejected (as :class:`gearrotor.model.components.Spec`, which
    imports this module)."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class ToothRelief(Spec):
    """A profile relief: material removed towards the tip (``tip_relief``) or the root
    (``root_relief``) of a flank. ``amount`` (m) is the deviation at the end of the active
    profile (the tip, or the start of active profile), measured along the line of action in
    the transverse plane (as a profile chart shows it); ``length`` (m) is the roll length
    over which it grows from zero, along the line of action; ``shape`` ``"linear"`` or
    ``"parabolic"``."""

    amount: Length = Field(ge=0)
    length: Length = Field(gt=0)
    shape: Literal["linear", "parabolic"] = "linear"


class FlankModifications(Spec):
    """Micro-geometry of one gear's loaded flank: profile reliefs, ``crowning`` (m, the
    material removed at each face end by a parabolic lead crowning) and ``lead_slope``
    (m, signed: the lead deviation across the face width, linear, zero at the start of the
    face, ``lead_slope`` at its end; the slopes of the two gears add)."""

    tip_relief: ToothRelief | None = None
    root_relief: ToothRelief | None = None
    crowning: Length = Field(default=0.0, ge=0)
    lead_slope: Length = 0.0

    @property
    def any(self) -> bool:
        return bool(self.tip_relief or self.root_relief or self.crowning or self.lead_slope)


class GearModifications(Spec):
    """Micro-geometry of the pair: ``pinion`` and ``gear`` flank modifications."""

    pinion: FlankModifications = FlankModifications()
    gear: FlankModifications = FlankModifications()


class GearPair(Spec):
    """An external spur or helical gear pair (transverse involute, rack-generated root).

    ``module`` normal module (m); ``teeth`` [pinion, gear]; ``pressure_angle`` normal αn;
    ``helix_angle`` β (0 for spur; the sign is the hand and plays no part in the stiffness);
    ``face_width`` (m, the common face width); ``addendum_coefficient`` h_a* (1),
    ``dedendum_coefficient`` h_f* (1.25: the rack's addendum, which cuts the root),
    ``root_radius_coefficient`` ρ_f* (0.38, ISO 53 profile A: the rack tip radius over the
    module); ``profile_shift`` [x1, x2]; ``bore_diameter`` [d1, d2] (m; the gear body's inner
    diameter for the fillet-foundation term; default: a solid body, see docs/gears.md);
    ``E`` (Pa) and ``poisson``, one value or [pinion, gear]; ``torque`` (N·m) the pinion
    torque transmitted (the operating load; ``gearrotor mesh --torque`` overrides it);
    ``driver`` which gear drives; ``modifications`` the micro-geometry; ``harmonics`` the mesh
    harmonics kept when the curves act in a model; ``slices`` across the face (default: 1 for
    a spur pair without lead modifications, else 41); ``positions`` per mesh cycle.

    In a model, ``file`` names a gear-pair file (relative to the model file) whose keys the
    other keys given here override (typically ``torque``).
    """

    file: str | None = None
    module: Length | None = Field(default=None, gt=0)
    teeth: tuple[Int, Int] | None = None
    pressure_angle: Angle | None = Field(default=None, gt=0, lt=1.2)
    helix_angle: Angle = Field(default=0.0, gt=-1.2, lt=1.2)
    face_width: Length | None = Field(default=None, gt=0)
    addendum_coefficient: Dimensionless = Field(default=1.0, gt=0, le=3)
    dedendum_coefficient: Dimensionless = Field(default=1.25, gt=0, le=4)
    root_radius_coefficient: Dimensionless = Field(default=0.38, ge=0, le=1)
    profile_shift: tuple[Dimensionless, Dimensionless] = (0.0, 0.0)
    bore_diameter: tuple[Length, Length] | None = None
    E: Modulus | tuple[Modulus, Modulus] | None = None
    poisson: Dimensionless | tuple[Dimensionless, Dimensionless] | None = None
    torque: Torque | None = Field(default=None, ge=0)
    driver: Literal["pinion", "gear"] = "pinion"
    modifications: GearModifications = GearModifications()
    harmonics: Int = Field(default=20, ge=1, le=200)
    slices: Int | None = Field(default=None, ge=1, le=400)
    positions: Int = Field(default=128, ge=16, le=4096)

    @model_validator(mode="after")
    def _values(self) -> GearPair:
        if self.teeth is not None and min(self.teeth) < 3:
            raise ValueError(f"expected at least 3 teeth on each gear, got {list(self.teeth)}")
        if self.teeth is not None and max(self.teeth) > 10_000:
            raise ValueError(f"expected at most 10000 teeth, got {list(self.teeth)}")
        if self.bore_diameter is not None and min(self.bore_diameter) <= 0:
            raise ValueError(
                f"expected positive bore diameters, got {list(self.bore_diameter)} m "
                "(leave 'bore_diameter' out for solid gear bodies)"
            )
        for name in ("E", "poisson"):
            v = getattr(self, name)
            vals = v if isinstance(v, tuple) else (v,)
            if any(x is not None and not x > 0 for x in vals):
                raise ValueError(f"expected positive '{name}', got {v}")
            if name == "poisson" and any(x is not None and not x < 0.5 for x in vals):
                raise ValueError(f"expected 'poisson' below 0.5, got {v}")
        return self

    @model_serializer(mode="wrap")
    def _compact(self, handler):
        # absent optional keys stay out (model JSON: study case keys, checkpoint fingerprints)
        out = handler(self)
        for key in ("file", "bore_diameter", "E", "poisson", "torque", "slices"):
            if getattr(self, key) is None:
                out.pop(key, None)
        return out

    def missing(self) -> list[str]:
        """The required keys not given (:data:`GEAR_PAIR_REQUIRED`)."""
        return [k for k in GEAR_PAIR_REQUIRED if getattr(self, k) is None]

    def per_gear(self, name: str) -> tuple[float, float] | None:
        """A per-gear value as (pinion, gear): ``E``, ``poisson``."""
        v = getattr(self, name)
        if v is None or isinstance(v, tuple):
            return v
        return (v, v)
