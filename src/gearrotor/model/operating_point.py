"""Operating points: the speed, the transmitted power or torque and the static loads at which a
train runs (issue 11).

An operating point names the reference-shaft ``speed``, the ``power`` or ``torque`` that enters
the train at the ``drive`` node and leaves it at the ``load`` node, gravity (on by default,
−y at 9.80665 m/s²) and optional static ``forces`` (forces and moments at nodes). The static
analysis (:func:`gearrotor.analyses.static.static`) turns it into bearing loads; with fluid-film
bearings the coefficients of every analysis then follow those loads.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field, field_validator, model_validator

from ..units import Acceleration, AngularSpeed, Force, Power, Torque
from .components import Flag, NodeRef, Spec

__all__ = [
    "MAX_ACCELERATION",
    "MAX_FORCE",
    "MAX_POWER",
    "MAX_TORQUE",
    "OperatingPoint",
    "StaticForce",
    "STANDARD_GRAVITY",
]

#: standard acceleration of gravity (m/s², CGPM 1901)
STANDARD_GRAVITY = 9.80665

# Bounds of the magnitudes an operating point may state (issue 23): each far above any machine
# (so no real input is refused) and far below where the numbers stop meaning anything.
#: Largest steady acceleration (100 g): machinery on ships and vehicles is designed for shock
#: loads of tens of g, and a steady acceleration beyond 100 g is no operating point of a train.
MAX_ACCELERATION = 100 * STANDARD_GRAVITY
#: Largest static force (N) and moment (N·m): 1e9 N is the weight of 100,000 t; the heaviest
#: turbine-generator trains weigh a few hundred tonnes and their tooth forces are meganewtons.
MAX_FORCE = 1e9
#: Largest transmitted torque (N·m): a 100 MW ship's shaft at 90 rpm carries 1.1e7 N·m.
MAX_TORQUE = 1e9
#: Largest transmitted power (W): the largest turbine-generator sets are below 2 GW.
MAX_POWER = 1e11


def _bounded(limit: float, unit: str, why: str):
    def check(v):
        values = v if isinstance(v, tuple) else (v,)
        for x in values:
            if x is not None and abs(x) > limit:
                raise ValueError(
                    f"no machine runs at {abs(x):.6g} {unit}: the bound {limit:.6g} {unit} is "
                    f"{why}; expected |value| <= {limit:.6g} {unit}"
                )
        return v

    return check


class StaticForce(NodeRef):
    """A static force (N) and moment (N·m) at a node, in the global x, y, z axes."""

    name: str | None = None
    force: tuple[Force, Force, Force] = (0.0, 0.0, 0.0)
    moment: tuple[Torque, Torque, Torque] = (0.0, 0.0, 0.0)

    _force = field_validator("force")(
        _bounded(MAX_FORCE, "N", "the weight of 100,000 t (rotor trains weigh a few hundred)")
    )
    _moment = field_validator("moment")(
        _bounded(MAX_FORCE, "N*m", "a hundred times the largest shaft torques (1e7 N*m)")
    )


class OperatingPoint(Spec):
    """One operating point of a train.

    ``speed``: reference-shaft speed (default: the model's ``speed``; same sense as the model).
    ``power`` (W) or ``torque`` (N·m, at the drive node, positive in its sense of rotation)
    enters at ``drive`` and leaves at ``load`` (the reaction torque there balances the power:
    ``T_load Ω_load = −T_drive Ω_drive``). ``hold``: what a speed sweep keeps constant
    (default: the one given). ``gravity``: weight of shafts, disks, gears and pedestals along
    ``gravity_direction`` (unit vector, default −y) times ``gravity_acceleration``.
    """

    name: str = Field(min_length=1)
    speed: AngularSpeed | None = None
    power: Power | None = None
    torque: Torque | None = None
    hold: Literal["power", "torque"] | None = None
    drive: NodeRef | None = None
    load: NodeRef | None = None
    gravity: Flag = True
    gravity_direction: tuple[float, float, float] = (0.0, -1.0, 0.0)
    gravity_acceleration: Acceleration = Field(default=STANDARD_GRAVITY, ge=0)
    forces: list[StaticForce] = Field(default_factory=list)

    _power = field_validator("power")(
        _bounded(MAX_POWER, "W", "fifty times the largest turbine-generator sets (2 GW)")
    )
    _torque = field_validator("torque")(
        _bounded(MAX_TORQUE, "N*m", "a hundred times a 100 MW ship's shaft at 90 rpm (1.1e7 N*m)")
    )
    _gravity = field_validator("gravity_acceleration")(
        _bounded(
            MAX_ACCELERATION,
            "m/s^2",
            "100 g (machinery on ships and vehicles is designed for shock loads of tens of g)",
        )
    )

    @field_validator("gravity_direction")
    @classmethod
    def _unit(cls, v):
        n = float(np.linalg.norm(v))
        if not n > 0:
            raise ValueError(f"expected a non-zero direction vector, got {list(v)}")
        return tuple(float(x) / n for x in v)

    @model_validator(mode="after")
    def _consistent(self) -> OperatingPoint:
        if self.power is not None and self.torque is not None:
            raise ValueError("give 'power' or 'torque', not both")
        if self.hold == "power" and self.power is None:
            raise ValueError("hold = 'power' needs 'power'")
        if self.hold == "torque" and self.power is None and self.torque is None:
            raise ValueError("hold = 'torque' needs 'torque' or 'power'")
        transmitted = bool(self.power) or bool(self.torque)
        if transmitted and self.drive is None:
            raise ValueError("a power or torque needs the 'drive' node where it enters")
        if transmitted and self.load is None:
            raise ValueError(
                "a power or torque needs the 'load' node that reacts it (nothing else reacts "
                "the torque on the drive shaft)"
            )
        return self

    @property
    def held(self) -> str:
        """What a speed sweep keeps constant: ``"power"`` or ``"torque"``."""
        if self.hold is not None:
            return self.hold
        return "power" if self.power is not None else "torque"

    def reference_speed(self, train_speed: float) -> float:
        """The reference-shaft speed of the point (rad/s)."""
        return float(train_speed if self.speed is None else self.speed)

    def drive_torque(self, drive_speed: float, nominal_drive_speed: float) -> float:
        """Torque (N·m, about +z) at the drive node when the drive shaft turns at
        ``drive_speed`` (rad/s, signed); ``nominal_drive_speed`` is its speed at the point
        itself (a held torque is the point's torque). Positive power drives: the torque has the
        sign of the rotation."""
        if not (self.power or self.torque):
            return 0.0
        sense = np.sign(drive_speed) or np.sign(nominal_drive_speed) or 1.0
        if self.torque is not None:
            return float(sense * self.torque)
        w = drive_speed if self.held == "power" else nominal_drive_speed
        return float(sense * self.power / abs(w))
