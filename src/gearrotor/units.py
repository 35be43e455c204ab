"""Units at the boundary: values may be plain numbers (SI) or strings with units ("0.06 m",
"6500 rpm", "720 g*mm"). Inside the package everything is SI (angles in rad, speeds in rad/s).
"""

from __future__ import annotations

import ast
import math
import os
import re
from functools import cache, lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

from pydantic import BeforeValidator

if TYPE_CHECKING:  # pragma: no cover
    import pint

__all__ = [
    "registry",
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
    "Pressure",
    "Temperature",
    "MolarMass",
    "rpm_to_rad_s",
    "rad_s_to_rpm",
]


@cache
def registry() -> pint.UnitRegistry:
    """The unit registry, built on first use (importing pint costs ~0.2 s, which a model of plain
    SI numbers, or ``gearrotor --help``, does not pay). pint keeps its parsed definition files
    in ``<user cache dir>/gearrotor/pint`` (as numba keeps the compiled kernels there): building
    the registry from them takes ~0.03 s instead of ~0.5 s of parsing in every process. The
    cache never stops a run: when it cannot be written or read (a damaged or half-written
    entry) the registry is built without it and a damaged folder is removed."""
    import pint

    folder = _registry_cache()
    if folder is not None:
        try:
            return pint.UnitRegistry(cache_folder=folder)
        except Exception:  # noqa: BLE001 - pint/flexcache/pickle raise several types
            import shutil

            shutil.rmtree(folder, ignore_errors=True)  # rebuilt by the next process
    return pint.UnitRegistry()


def _registry_cache() -> Path | None:
    """The folder of pint's cache, created if needed; None when it cannot be."""
    import platformdirs

    folder = Path(platformdirs.user_cache_dir("gearrotor", appauthor=False)) / "pint"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    return folder if os.access(folder, os.W_OK) else None


def __getattr__(name: str):
    # ``gearrotor.units.ureg``, the former module-level registry, now built lazily
    if name == "ureg":
        return registry()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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
    "kinematic_viscosity": ("m^2/s", "a kinematic viscosity", "32 mm^2/s"),
    "specific_heat": ("J/(kg*K)", "a specific heat capacity", "1950 J/(kg*K)"),
    "heat_transfer": ("W/(m^2*K)", "a heat transfer coefficient", "500 W/(m^2*K)"),
    "thermal_conductivity": ("W/(m*K)", "a thermal conductivity", "0.13 W/(m*K)"),
    "dimensionless": ("", "a plain number", "0.3"),
    "voltage": ("V", "a voltage", "13.8 kV"),
    "resistance": ("ohm", "a resistance or reactance", "0.64 ohm"),
    "stress": ("Pa", "a stress", "120 MPa"),
    "acceleration": ("m/s^2", "an acceleration", "9.80665 m/s^2"),
    "pressure": ("Pa", "a pressure", "3.08 bar"),
    "temperature": ("K", "an absolute temperature", "283.15 K"),
    # plain numbers of a molar mass are kg/kmol (= g/mol), as gas tables give them
    "molar_mass": ("kg/kmol", "a molar mass", "28.97 kg/kmol"),
}


@cache
def _dim(unit: str):
    return registry().Quantity(1.0, unit).dimensionality


# A unit expression is at most this long, holds at most this many operators, and raises to
# powers only a plain number of at most this magnitude: pint evaluates expressions with Python
# numbers, so "10**10**10" would otherwise compute a ten-billion-digit integer (hours, gigabytes).
MAX_EXPRESSION_LENGTH = 200
MAX_OPERATORS = 40
MAX_EXPONENT = 64
_SUPERSCRIPT = "⁰¹²³⁴⁵⁶⁷⁸⁹⁻"
_SUPER_DIGITS = str.maketrans(_SUPERSCRIPT, "0123456789-")
_NAME_CHAR = rf"(?:(?![{_SUPERSCRIPT}])[\w°%Ω])"
_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d[\d,]*\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<op>\*\*|[-+*/^()·⋅])"
    rf"|(?P<sup>[{_SUPERSCRIPT}]+)"
    rf"|(?P<name>(?:(?![{_SUPERSCRIPT}])[^\W\d]|[°%Ω]){_NAME_CHAR}*))"
)


def _check_expression(text: str) -> None:
    """Refuse unit expressions whose evaluation could take unbounded time or memory.

    The text is rewritten as a Python expression (every unit name a placeholder, implicit
    multiplication made explicit, ``^`` as ``**``) and its syntax tree checked: every exponent
    is a plain number of magnitude at most :data:`MAX_EXPONENT`, no power is raised to a power,
    and the expression has at most :data:`MAX_OPERATORS` operators. Raises ``ValueError``.
    """
    if len(text) > MAX_EXPRESSION_LENGTH:
        raise ValueError(
            f"the value is {len(text)} characters long; expected a number with units of at "
            f"most {MAX_EXPRESSION_LENGTH} characters such as '1e7 N/m'"
        )
    parts: list[str] = []
    pos, prev_operand = 0, False
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            if text[pos:].strip() == "":
                break
            bad = text[pos:].lstrip()[:1]
            raise ValueError(f"cannot read {text!r}: unexpected character {bad!r}")
        pos = m.end()
        if m.group("sup") is not None:  # "m²": a power written in superscript digits
            exp = m.group("sup").translate(_SUPER_DIGITS)
            parts += ["**", f"({exp})"]
            prev_operand = True
            continue
        if m.group("op") is not None:
            op = {"^": "**", "·": "*", "⋅": "*"}.get(m.group("op"), m.group("op"))
            if op == "(" and prev_operand:
                parts.append("*")
            parts.append(op)
            prev_operand = op == ")"
            continue
        if prev_operand:  # "6500 rpm", "kg m": implicit multiplication
            parts.append("*")
        parts.append(m.group("num").replace(",", "") if m.group("num") is not None else "x")
        prev_operand = True
    try:
        tree = ast.parse(" ".join(parts), mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise ValueError(f"cannot read {text!r} as a number with units") from None
    n_ops = 0
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp | ast.UnaryOp):
            n_ops += 1
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            exp = node.right
            if isinstance(exp, ast.UnaryOp) and isinstance(exp.op, ast.USub | ast.UAdd):
                exp = exp.operand
            plain = isinstance(exp, ast.Constant) and isinstance(exp.value, int | float)
            nested = any(
                isinstance(n, ast.BinOp) and isinstance(n.op, ast.Pow) for n in ast.walk(node.left)
            )
            if not plain or nested or abs(exp.value) > MAX_EXPONENT:
                raise ValueError(
                    f"cannot read {text!r}: exponents must be plain numbers of magnitude at "
                    f"most {MAX_EXPONENT}, and a power cannot be raised to a power "
                    "(e.g. '2.1e11 Pa', 'kg*m^2')"
                )
    if n_ops > MAX_OPERATORS:
        raise ValueError(
            f"cannot read {text!r}: more than {MAX_OPERATORS} operators in a unit expression"
        )


def _short(value: Any) -> str:
    text = repr(value) if not isinstance(value, int) or abs(value) < 10**30 else "a huge integer"
    return text if len(text) <= 60 else text[:57] + "..."


def _finite(x: float, value: Any, name: str, example: str) -> float:
    if not math.isfinite(x):
        raise ValueError(
            f"expected {name} as a finite number (e.g. '{example}'), got {_short(value)}, which is "
            "not finite (nan, inf, or beyond the range of a float)"
        )
    return x


def to_si(value: Any, kind: str) -> float:
    """Convert a number (taken as SI) or a string with units to the SI value of ``kind``.

    Raises ValueError with the expected kind and an example when the value does not fit,
    including values that are not finite (nan, inf, "1e999 Pa") and unit expressions whose
    evaluation would not be bounded (see :func:`_check_expression`).
    """
    unit, name, example = KINDS[kind]
    if isinstance(value, bool):
        raise ValueError(f"expected {name} (e.g. '{example}'), got a boolean")
    if isinstance(value, int | float):
        try:
            x = float(value)
        except OverflowError:
            x = math.inf
        return _finite(x, value, name, example)
    if not isinstance(value, str):
        raise ValueError(f"expected {name} as a number or a string such as '{example}'")
    return _string_to_si(value, kind)


@lru_cache(maxsize=4096)
def _string_to_si(value: str, kind: str) -> float:
    """:func:`to_si` of a string (remembered: a study's cases and a model's elements repeat the
    same few texts thousands of times, and pint takes ~0.25 ms to read one)."""
    unit, name, example = KINDS[kind]
    text = _MIL.sub("thou", value.strip())
    if kind in _PER_DEGREE:  # "J/(kg*degC)": a temperature difference, not a temperature
        text = _DEGREE.sub(lambda m: "delta_deg" + m.group(1)[-1], text)
    _check_expression(text)
    ureg = registry()
    try:
        q = _temperature(text) if kind == "temperature" else ureg.Quantity(text)
    except Exception as exc:  # pint raises several unrelated types
        msg = str(exc).splitlines()[0][:120] if str(exc) else type(exc).__name__
        raise ValueError(f"cannot read {value!r} as {name} (e.g. '{example}'): {msg}") from None
    try:
        x = _convert(q, value, kind)
    except OverflowError:
        x = math.inf
    return _finite(x, value, name, example)


# kinds whose units divide by a temperature difference, and the offset units pint would refuse
_PER_DEGREE = {"specific_heat", "heat_transfer", "thermal_conductivity"}
_DEGREE = re.compile(r"(?<![\w°])(degC|degF|°C|°F)(?!\w)")

_NUMBER_UNIT = re.compile(r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*)")


def _temperature(text: str):
    """A temperature such as "10 degC", "283.15 K" or "50 degF": a number and one unit (pint
    cannot multiply a number by an offset unit such as degC inside an expression)."""
    m = _NUMBER_UNIT.fullmatch(text)
    if m is None:
        return registry().Quantity(text)
    return registry().Quantity(float(m.group(1)), m.group(2) or "kelvin")


def _convert(q: Any, value: Any, kind: str) -> float:
    unit, name, example = KINDS[kind]
    ureg = registry()
    if not isinstance(q, ureg.Quantity):
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
Pressure = _quantity("pressure")
Temperature = _quantity("temperature")
MolarMass = _quantity("molar_mass")


def rpm_to_rad_s(rpm: float) -> float:
    return rpm * 3.141592653589793 / 30.0


def rad_s_to_rpm(w: float) -> float:
    return w * 30.0 / 3.141592653589793
