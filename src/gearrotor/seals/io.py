"""Seal input files (TOML).

Values may carry units ("145 mm", "3.08 bar", "10 degC", "1.8e-5 Pa*s"); plain numbers are SI
(m, Pa, K, Pa·s, kg/m³) except the molar mass, in kg/kmol (= g/mol) as gas tables give it.
Unknown keys are rejected; every error names the file, the field, the value and what was
expected. The format is in ``docs/seals.md``; examples are in ``examples/seals/``::

    type = "labyrinth"
    shaft_diameter = "145 mm"
    radial_clearance = "0.3 mm"
    n_teeth = 16
    pitch = "3.175 mm"
    tooth_height = "3.175 mm"
    tooth_width = "0.1524 mm"
    teeth_on = "interlocking"         # "stator" | "rotor" | "interlocking"
    inlet_pressure = "308 kPa"
    outlet_pressure = "94.3 kPa"
    inlet_temperature = "283.15 K"
    preswirl = 0.98                   # inlet swirl velocity / rotor surface speed

    [gas]                             # ideal gas ...
    molar_mass = 28.97                # kg/kmol
    gamma = 1.4
    viscosity = "1.8e-5 Pa*s"
    # ... or a real gas through CoolProp: composition = {Nitrogen = 0.79, Oxygen = 0.21}
"""

from __future__ import annotations

import difflib
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, Strict, ValidationError, model_validator

from ..errors import ModelError
from ..inputs import read_toml
from ..units import Density, Dimensionless, Length, MolarMass, Pressure, Temperature, Viscosity
from .annular import AnnularSeal, Friction
from .fluids import IdealGas, Liquid, RealGas
from .labyrinth import LabyrinthSeal, vermes_carry_over

__all__ = ["load_seal", "parse_seal", "SEAL_TYPES"]

SEAL_TYPES = ("labyrinth", "liquid_annular", "hole_pattern", "honeycomb")
Int = Annotated[int, Strict()]
_MAX_TEETH = 200
_MAX_POINTS = 2000


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class _Gas(_Strict):
    molar_mass: MolarMass | None = Field(default=None, gt=0)
    gamma: Dimensionless | None = Field(default=None, gt=1.0, le=5.0 / 3.0 + 1e-9)
    viscosity: Viscosity | None = Field(default=None, gt=0)
    composition: dict[str, Annotated[float, Field(gt=0)]] | None = Field(default=None, min_length=1)

    @model_validator(mode="after")
    def _one_form(self) -> _Gas:
        ideal = [self.molar_mass, self.gamma]
        if self.composition is not None:
            if any(v is not None for v in ideal):
                raise ValueError(
                    "give either 'composition' (a real gas through CoolProp) or 'molar_mass' "
                    "and 'gamma' (an ideal gas), not both"
                )
            return self
        missing = [n for n in ("molar_mass", "gamma", "viscosity") if getattr(self, n) is None]
        if missing:
            raise ValueError(
                f"an ideal gas needs molar_mass (kg/kmol), gamma and viscosity; missing "
                f"{', '.join(missing)} (or give a 'composition' for CoolProp)"
            )
        return self


class _Liquid(_Strict):
    density: Density = Field(gt=0)
    viscosity: Viscosity = Field(gt=0)


class _Friction(_Strict):
    law: Literal["hirs", "blasius", "moody"] = "hirs"
    n: Dimensionless | None = Field(default=None, gt=0)
    m: Dimensionless | None = Field(default=None, gt=-1, lt=0)
    roughness: Length = Field(default=0.0, ge=0)

    def build(self) -> Friction:
        if self.law == "moody":
            return Friction("moody", roughness=self.roughness)
        if self.law == "blasius":
            return Friction("hirs", 0.079, -0.25)
        return Friction(
            "hirs", 0.079 if self.n is None else self.n, -0.25 if self.m is None else self.m
        )


class _Common(_Strict):
    name: str = ""
    shaft_diameter: Length = Field(gt=0)
    radial_clearance: Length = Field(gt=0)
    inlet_pressure: Pressure = Field(gt=0)
    outlet_pressure: Pressure = Field(gt=0)
    preswirl: Dimensionless = Field(default=0.0, ge=-2.0, le=2.0)
    notes: str = ""


class _Labyrinth(_Common):
    type: Literal["labyrinth"]
    n_teeth: Int = Field(ge=1, le=_MAX_TEETH)
    pitch: Length = Field(gt=0)
    tooth_height: Length = Field(gt=0)
    tooth_width: Length = Field(ge=0)
    teeth_on: Literal["stator", "rotor", "interlocking"]
    inlet_temperature: Temperature = Field(gt=0)
    gas: _Gas


class _Annular(_Common):
    length: Length = Field(gt=0)
    entrance_loss: Dimensionless = Field(default=0.1, ge=0, le=10)
    stator_friction: _Friction = _Friction()
    rotor_friction: _Friction = _Friction()
    n_points: Int = Field(default=40, ge=4, le=_MAX_POINTS)


class _LiquidAnnular(_Annular):
    type: Literal["liquid_annular"]
    liquid: _Liquid


class _Damper(_Annular):
    type: Literal["hole_pattern", "honeycomb"]
    cell_depth: Length = Field(ge=0)
    hole_area_ratio: Dimensionless = Field(ge=0, le=1)
    inlet_temperature: Temperature = Field(gt=0)
    gas: _Gas


_Input = Annotated[_Labyrinth | _LiquidAnnular | _Damper, Field(discriminator="type")]


class _File(_Strict):
    seal: _Input


def _known_keys() -> set[str]:
    keys: set[str] = set()
    for cls in (_Labyrinth, _LiquidAnnular, _Damper, _Gas, _Liquid, _Friction):
        keys |= set(cls.model_fields)
    return keys


def _loc(loc: tuple) -> str:
    out = ""
    for part in loc[1:]:  # drop the wrapper's "seal"
        if isinstance(part, int):
            out += f"[{part}]"
        elif part in SEAL_TYPES or str(part).startswith("function-"):
            continue
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


def _lookup(doc, loc: tuple):
    cur = doc
    for part in loc:
        if isinstance(cur, dict) and part in cur:
            cur = cur[part]
        elif isinstance(cur, list) and isinstance(part, int) and part < len(cur):
            cur = cur[part]
        elif part in SEAL_TYPES:
            continue
        else:
            return None
    return cur


def _gas(g: _Gas, temperature: float, p_lo: float, p_hi: float, field: str):
    if g.composition is not None:
        comp = tuple(sorted(g.composition.items()))
        try:
            return RealGas(comp, temperature, 0.5 * p_lo, p_hi, mu=g.viscosity)
        except ModelError as exc:
            f = exc.field.replace("gas.", f"{field}.", 1) if exc.field else field
            raise ModelError(exc.message, field=f, value=exc.value, expected=exc.expected) from None
    return IdealGas(g.molar_mass, g.gamma, g.viscosity, temperature)


def _check(inp) -> None:
    """Cross-field checks: pressures, and a labyrinth's carry-over geometry."""
    if inp.outlet_pressure >= inp.inlet_pressure:
        raise ModelError(
            "the outlet pressure is not below the inlet pressure",
            field="outlet_pressure",
            value=f"{inp.outlet_pressure:.6g} Pa (inlet {inp.inlet_pressure:.6g} Pa)",
            expected="outlet_pressure < inlet_pressure (the seal leaks from inlet to outlet)",
        )
    if inp.type == "labyrinth":
        if inp.tooth_width >= inp.pitch:
            raise ModelError(
                "the tooth is wider than the pitch",
                field="tooth_width",
                value=f"{inp.tooth_width:.6g} m (pitch {inp.pitch:.6g} m)",
                expected="tooth_width < pitch",
            )
        a = vermes_carry_over(inp.pitch, inp.tooth_width, inp.radial_clearance)
        if inp.teeth_on != "interlocking" and a >= 1.0:
            raise ModelError(
                f"Vermes' carry-over factor is {a:.4g} >= 1 (the cavities are too short for "
                "the clearance)",
                field="radial_clearance",
                value=f"{inp.radial_clearance:.6g} m",
                expected="(pitch - tooth_width)/radial_clearance > 1.29",
            )


def parse_seal(doc: dict, source: str = "") -> LabyrinthSeal | AnnularSeal:
    """Validate a parsed seal file (its top-level keys) into a seal model."""
    try:
        inp = _File.model_validate({"seal": doc}).seal
    except ValidationError as exc:
        errors = sorted(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
        first = errors[0]
        more = f" (and {len(errors) - 1} more error(s))" if len(errors) > 1 else ""
        msg = first["msg"].removeprefix("Value error, ")
        kind = first["type"]
        where = _loc(first["loc"])
        value = first.get("input")
        if kind == "extra_forbidden":
            key = first["loc"][-1]
            close = difflib.get_close_matches(str(key), sorted(_known_keys()), n=1, cutoff=0.7)
            message = f"unknown key {key!r}" + (f" (did you mean {close[0]!r}?)" if close else "")
            expected, value = "a key listed in docs/seals.md", None
        elif kind == "missing":
            message, expected, value = "missing required field", "this field to be given", None
        elif kind in ("union_tag_invalid", "union_tag_not_found"):
            message, where = "unknown seal type", "type"
            value = doc.get("type") if isinstance(doc, dict) else None
            expected = " | ".join(SEAL_TYPES)
        elif kind == "value_error":
            message, expected = msg, None
        else:
            message, expected = "invalid value", msg[:1].lower() + msg[1:]
        raw = _lookup(doc, first["loc"][1:]) if len(first["loc"]) > 1 else None
        if raw is not None and kind not in ("extra_forbidden", "missing"):
            value = raw  # as written in the file ("-0.3 mm"), not converted
        if isinstance(value, dict):
            value = None
        raise ModelError(
            message + more, field=where, value=value, expected=expected, file=source or None
        ) from None
    try:
        _check(inp)
        name = inp.name or Path(source).stem or inp.type
        if inp.type == "labyrinth":
            gas = _gas(
                inp.gas, inp.inlet_temperature, inp.outlet_pressure, inp.inlet_pressure, "gas"
            )
            return LabyrinthSeal(
                inp.shaft_diameter,
                inp.radial_clearance,
                inp.n_teeth,
                inp.pitch,
                inp.tooth_height,
                inp.tooth_width,
                inp.teeth_on,
                inp.inlet_pressure,
                inp.outlet_pressure,
                inp.inlet_temperature,
                inp.preswirl,
                gas,
                name,
            )
        if inp.type == "liquid_annular":
            fluid = Liquid(inp.liquid.density, inp.liquid.viscosity)
            extra = {}
        else:
            fluid = _gas(
                inp.gas, inp.inlet_temperature, inp.outlet_pressure, inp.inlet_pressure, "gas"
            )
            extra = dict(
                cell_depth=inp.cell_depth,
                hole_area_ratio=inp.hole_area_ratio,
                inlet_temperature=inp.inlet_temperature,
            )
        return AnnularSeal(
            inp.type,
            inp.shaft_diameter,
            inp.radial_clearance,
            inp.length,
            inp.inlet_pressure,
            inp.outlet_pressure,
            inp.preswirl,
            fluid,
            entrance_loss=inp.entrance_loss,
            stator=inp.stator_friction.build(),
            rotor=inp.rotor_friction.build(),
            n_points=inp.n_points,
            name=name,
            **extra,
        )
    except ModelError as err:
        raise (err.with_file(source) if source else err) from None


def load_seal(path: str | Path) -> LabyrinthSeal | AnnularSeal:
    """Read a seal TOML file (see the module docstring and ``docs/seals.md``)."""
    path = Path(path)
    doc = read_toml(path, "seal")
    if "shafts" in doc or "bearing" in doc:
        raise ModelError(
            "this is a " + ("rotor model" if "shafts" in doc else "bearing") + " file, not a "
            "seal file",
            file=str(path),
            expected="a seal file with type = " + " | ".join(repr(t) for t in SEAL_TYPES),
        )
    return parse_seal(doc, str(path))
