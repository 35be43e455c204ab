"""Units at the boundary: values may be plain numbers (SI) or strings with units ("0.06 m",
"6500 rpm", "720 g*mm"). Inside the package everything is SI (angles in rad, speeds in rad/s).
"""

from __future__ import annotations

import re
from functools import cache
from typing import Annotated, Any

import pint
from pydantic import BeforeValidator

__all__ = [
    "ureg",
    "to_si",
    "Length",
    "Mass",
    "Inertia",
    "Stiffness",
    "Damping",
    "RotStiffness",
    "RotDamping",
    "Modulus",
    "Density",
    "Angle",
    "AngularSpeed",
    "UnbalanceAmount",
    "Force",
    "Torque",
    "Power",
    "Time",
    "Rate",
    "Frequency",
    "Dimensionless",
    "Voltage",
    "Resistance",
    "Stress",
    "Acceleration",
    "rpm_to_rad_s",
    "rad_s_to_rpm",
]

ureg = pint.UnitRegistry()
# In rotordynamics a "mil" is a thousandth of an inch (pint's default "mil" is the angular mil).
_MIL = re.compile(r"\bmils?\b")

# kind -> (SI unit, human name, example)
KINDS: dict[str, tuple[str, str, str]] = {
    "length": ("m", "a length", "0.06 m"),
    "mass": ("kg", "a mass", "12 kg"),
    "inertia": ("kg*m^2", "a mass moment of inertia", "0.5 kg*m^2"),
    "stiffness": ("N/m", "a stiffness", "1e7 N/m"),
    "damping": ("N*s/m", "a damping coefficient", "1.75e4 N*s/m"),
    "rot_stiffness": ("N*m/rad", "a rotational stiffness", "1e5 N*m/rad"),
    "rot_damping": ("N*m*s/rad", "a rotational damping", "10 N*m*s/rad"),
    "modulus": ("Pa", "a modulus or pressure", "211 GPa"),
    "density": ("kg/m^3", "a density", "7890 kg/m^3"),
    "angle": ("rad", "an angle", "20 deg"),
    "angular_speed": ("rad/s", "a rotational speed", "6500 rpm"),
    "unbalance": ("kg*m", "an unbalance amount", "720 g*mm"),
    "force": ("N", "a force", "1000 N"),
    "torque": ("N*m", "a torque", "500 N*m"),
    "power": ("W", "a power", "1.5 MW"),
    "time": ("s", "a time", "3 s"),
    "rate": ("1/s", "a rate (per second)", "0.5 1/s"),
    "frequency": ("rad/s", "a frequency", "100 Hz"),
    "viscosity": ("Pa*s", "a dynamic viscosity", "0.02 Pa*s"),
    "dimensionless": ("", "a plain number", "0.3"),
    "voltage": ("V", "a voltage", "13.8 kV"),
    "resistance": ("ohm", "a resistance or reactance", "0.64 ohm"),
    "stress": ("Pa", "a stress", "120 MPa"),
    "acceleration": ("m/s^2", "an acceleration", "9.80665 m/s^2"),
}


@cache
def _dim(unit: str):
    return ureg.Quantity(1.0, unit).dimensionality


def to_si(value: Any, kind: str) -> float:
    """Convert a number (taken as SI) or a string with units to the SI value of ``kind``.

    Raises ValueError with the expected kind and an example when the value does not fit.
    """
    unit, name, example = KINDS[kind]
    if isinstance(value, bool):
        raise ValueError(f"expected {name} (e.g. '{example}'), got a boolean")
    if isinstance(value, int | float):
        return float(value)
    if not isinstance(value, str):
        raise ValueError(f"expected {name} as a number or a string such as '{example}'")
    try:
        q = ureg.Quantity(_MIL.sub("thou", value.strip()))
    except Exception as exc:  # pint raises several unrelated types
        raise ValueError(f"cannot read {value!r} as {name} (e.g. '{example}'): {exc}") from None
    if not isinstance(q, pint.Quantity):
        return float(q)
    if kind in ("angular_speed", "frequency") and "hertz" in str(q.units):
        # Hz on a rotational speed or a frequency means cycles per second, not rad/s
        q = q.to("Hz").magnitude * ureg("revolution/second")
    if unit == "":
        if not q.dimensionless:
            raise ValueError(f"expected {name}, got {value!r} with units {q.units:~}")
        return float(q.to("").magnitude)
    if q.dimensionless and q.units == ureg.dimensionless:
        return float(q.magnitude)
    if q.dimensionality != _dim(unit):
        raise ValueError(
            f"expected {name} such as '{example}', got {value!r} (units {q.units:~} "
            f"are not convertible to {unit})"
        )
    return float(q.to(unit).magnitude)


def _quantity(kind: str):
    return Annotated[float, BeforeValidator(lambda v: to_si(v, kind))]


Length = _quantity("length")
Mass = _quantity("mass")
Inertia = _quantity("inertia")
Stiffness = _quantity("stiffness")
Damping = _quantity("damping")
RotStiffness = _quantity("rot_stiffness")
RotDamping = _quantity("rot_damping")
Modulus = _quantity("modulus")
Density = _quantity("density")
Angle = _quantity("angle")
AngularSpeed = _quantity("angular_speed")
UnbalanceAmount = _quantity("unbalance")
Force = _quantity("force")
Torque = _quantity("torque")
Power = _quantity("power")
Time = _quantity("time")
Rate = _quantity("rate")
Frequency = _quantity("frequency")
Viscosity = _quantity("viscosity")
Dimensionless = _quantity("dimensionless")
Voltage = _quantity("voltage")
Resistance = _quantity("resistance")
Stress = _quantity("stress")
Acceleration = _quantity("acceleration")


def rpm_to_rad_s(rpm: float) -> float:
    return rpm * 3.141592653589793 / 30.0


def rad_s_to_rpm(w: float) -> float:
    return w * 30.0 / 3.141592653589793
