"""Bearing input files (TOML).

Values may carry units as strings parsed by pint ("140 mm", "0.0152 Pa*s", "10800 rpm",
"97 deg", "5.5 mil"); plain numbers are SI (m, Pa·s, rad/s, rad, N). Unknown keys are rejected.
Every error names the file, the field, the value and what was expected
(:class:`~gearrotor.errors.ModelError`). See ``docs/bearings.md`` for the format; examples are
in ``examples/bearings/``.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    Strict,
    ValidationError,
)

from ..errors import ModelError
from ..inputs import read_toml
from ..units import to_si
from .film import SolverOptions
from .geometry import (
    Bearing,
    Pad,
    Pocket,
    axial_groove,
    elliptical,
    multilobe,
    offset_halves,
    plain,
    tilting_pad,
)
from .lubricant import CELSIUS, Lubricant, iso_vg
from .reynolds import Grid

__all__ = ["BearingCase", "load_bearing", "parse_bearing"]


def _q(kind: str):
    return Annotated[float, BeforeValidator(lambda v: to_si(v, kind))]


Length = _q("length")
Angle = _q("angle")
Viscosity = _q("viscosity")
Speed = _q("angular_speed")
Force = _q("force")
Stiffness = _q("stiffness")
Mass = _q("mass")
Inertia = _q("inertia")
Fraction = _q("dimensionless")
Temperature = Annotated[float, BeforeValidator(lambda v: to_si(v, "temperature")), Field(gt=0)]
KinematicViscosity = Annotated[
    float, BeforeValidator(lambda v: to_si(v, "kinematic_viscosity")), Field(gt=0)
]
SpecificHeat = Annotated[float, BeforeValidator(lambda v: to_si(v, "specific_heat")), Field(gt=0)]
Conductivity = Annotated[
    float, BeforeValidator(lambda v: to_si(v, "thermal_conductivity")), Field(gt=0)
]
HeatTransfer = Annotated[
    float,
    BeforeValidator(
        lambda v: math.inf if v == math.inf or v == "inf" else to_si(v, "heat_transfer")
    ),
    Field(ge=0),
]
Density = Annotated[float, BeforeValidator(lambda v: to_si(v, "density")), Field(gt=0)]
Int = Annotated[int, Strict()]
#: pivot (or reference-angle) position as a fraction of the pad arc
Offset = Annotated[float, BeforeValidator(lambda v: to_si(v, "dimensionless")), Field(ge=0, le=1)]
#: Largest Reynolds grid (nodes over all pads): the solver's sparse factorisation takes very
#: roughly ``BYTES_PER_NODE`` bytes per node, so this bounds a solve to about 0.5 GB.
MAX_GRID_NODES = 500_000
BYTES_PER_NODE = 1000
Preload = Annotated[
    float,
    BeforeValidator(lambda v: to_si(v, "dimensionless")),
    Field(ge=0.0, lt=1.0, description="preload m = 1 − c/c_p"),
]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


def _arc_check(v: float) -> float:
    if not 0.0 < v <= 2 * math.pi + 1e-9:
        raise ValueError(
            f"expected an angle between 0 and 360 deg (plain numbers are radians; write e.g. "
            f"'{math.degrees(v) if v < 10 else v:.4g} deg')"
        )
    return v


Arc = Annotated[float, BeforeValidator(lambda v: to_si(v, "angle")), AfterValidator(_arc_check)]


class _GridIn(_Strict):
    n_theta: Int = Field(36, ge=4, le=10_000, description="intervals per pad arc")
    n_z: Int = Field(8, ge=2, le=10_000, description="intervals from the edge to the mid-plane")


class _LoadIn(_Strict):
    fx: Force
    fy: Force
    name: str = ""


class _PocketIn(_Strict):
    pads: list[Int] = Field(min_length=1, description="1-based pad numbers")
    start: Angle = 0.0
    arc: Arc
    width: Length
    depth: Length


class _PadIn(_Strict):
    start: Angle
    arc: Arc
    preload: Preload = 0.0
    offset: Offset = 0.5


class _LubricantIn(_Strict):
    """``[bearing.lubricant]``: one of ``grade``, ``nu40`` + ``nu100``, ``viscosity_points``."""

    name: str = ""
    grade: str | None = None
    viscosity_index: Fraction = 100.0
    nu40: KinematicViscosity | None = None
    nu100: KinematicViscosity | None = None
    viscosity_points: list[tuple[Temperature, Viscosity]] | None = Field(
        default=None, min_length=2, max_length=3
    )
    law: Literal["walther", "vogel", "exponential"] | None = None
    density: Density = 870.0
    specific_heat: SpecificHeat | None = None
    thermal_conductivity: Conductivity = 0.13
    pour_point: Temperature = CELSIUS - 6.0
    max_temperature: Temperature = CELSIUS + 150.0


class _ThermalIn(_Strict):
    """``[bearing.thermal]``."""

    model: Literal["isoviscous", "effective", "thd"]
    supply_temperature: Temperature
    temperature: Temperature | None = None
    carry_over: Fraction = 0.8
    effective_factor: Fraction = 0.5
    pad_heat_transfer: HeatTransfer = 0.0
    journal_heat_transfer: HeatTransfer = 0.0
    journal_temperature: Temperature | None = None
    # layers across the film: 8 are within 0.1 K of 32 on the examples; 64 bounds the cost
    cross_film_layers: Int = Field(8, ge=1, le=64)
    tolerance: float = Field(0.1, gt=0, le=10, description="K")
    max_iterations: Int = Field(100, ge=1, le=10_000)
    relaxation: float = Field(0.7, gt=0, le=1)


class _Common(_Strict):
    name: str = ""
    diameter: Length
    length: Length
    clearance: Length
    viscosity: Viscosity | None = None
    lubricant: _LubricantIn | None = None
    thermal: _ThermalIn | None = None
    speed: Speed | None = None
    cavitation: Literal["swift_stieber", "half_sommerfeld", "none"] = "swift_stieber"
    grid: _GridIn = _GridIn()
    loads: list[_LoadIn] = []
    notes: str = ""


class _PlainIn(_Common):
    type: Literal["plain"]


class _AxialGrooveIn(_Common):
    type: Literal["axial_groove"]
    grooves: Int = Field(2, ge=1, le=64)
    groove_arc: Angle = math.radians(20.0)
    first_groove: Angle = 0.0
    pockets: list[_PocketIn] = []


class _OffsetHalvesIn(_Common):
    type: Literal["offset_halves"]
    preload: Preload = 0.5
    groove_arc: Angle = math.radians(20.0)
    pockets: list[_PocketIn] = []


class _EllipticalIn(_Common):
    type: Literal["elliptical"]
    preload: Preload = 0.5
    groove_arc: Angle = math.radians(20.0)
    pockets: list[_PocketIn] = []


class _MultilobeIn(_Common):
    type: Literal["multilobe"]
    pivots: list[Angle] = Field(min_length=1)
    arc: Arc
    preload: Preload = 0.0
    offset: Offset = 0.5
    pockets: list[_PocketIn] = []


class _PadsIn(_Common):
    type: Literal["pads"]
    pads: list[_PadIn] = Field(min_length=1)
    pockets: list[_PocketIn] = []


class _TiltingIn(_Common):
    type: Literal["tilting_pad"]
    pivots: list[Angle] = Field(min_length=1)
    arc: Arc
    preload: Preload = 0.0
    offset: Offset = 0.5
    pad_inertia: Inertia = 0.0
    pad_mass: Mass = 0.0
    pad_thickness: Length = 0.0
    pivot_stiffness: Stiffness | None = None


_Input = Annotated[
    _PlainIn
    | _AxialGrooveIn
    | _OffsetHalvesIn
    | _EllipticalIn
    | _MultilobeIn
    | _PadsIn
    | _TiltingIn,
    Field(discriminator="type"),
]


class _File(_Strict):
    bearing: _Input


@dataclass(frozen=True)
class BearingCase:
    """A bearing read from a file with its operating data.

    Attributes
    ----------
    bearing
        The geometry.
    speed
        Speed (rad/s, signed) or None when the file gives none.
    loads
        Load cases (Fx, Fy) in N.
    load_names
        Names of the load cases ("" when not given).
    options
        Solver options (grid, cavitation, thermal model) from the file.
    source
        The file it came from.
    notes
        Free text from the file.
    lubricant
        The ``[bearing.lubricant]``, if given.
    temperature
        ``thermal.model = "isoviscous"``: the film temperature (K) the viscosity is taken at.
    """

    bearing: Bearing
    speed: float | None
    loads: tuple[tuple[float, float], ...]
    load_names: tuple[str, ...] = ()
    options: SolverOptions = field(default_factory=SolverOptions)
    source: str = ""
    notes: str = ""
    lubricant: Lubricant | None = None
    temperature: float | None = None


def _known_keys() -> set[str]:
    keys: set[str] = set()
    for cls in (
        _File,
        _PlainIn,
        _AxialGrooveIn,
        _OffsetHalvesIn,
        _EllipticalIn,
        _MultilobeIn,
        _PadsIn,
        _TiltingIn,
        _PadIn,
        _PocketIn,
        _LoadIn,
        _GridIn,
        _LubricantIn,
        _ThermalIn,
    ):
        keys |= set(cls.model_fields)
    return keys


def _did_you_mean(key: object) -> str:
    close = difflib.get_close_matches(str(key), sorted(_known_keys()), n=1, cutoff=0.7)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _check_size(bearing: Bearing, grid: _GridIn) -> None:
    """Total pad arc at most 360°, and a Reynolds grid that fits in memory."""
    total = sum(p.arc for p in bearing.pads)
    if total > 2 * math.pi * (1 + 1e-9):
        raise ModelError(
            "the pads' arcs add up to more than a full circle",
            field="bearing.arc",
            value=f"{len(bearing.pads)} pads, {math.degrees(total):.6g} deg in total",
            expected="pad arcs (and grooves between them) within 360 deg",
        )
    nodes = len(bearing.pads) * (grid.n_theta + 1) * (grid.n_z + 1)
    if nodes > MAX_GRID_NODES:
        raise ModelError(
            f"the Reynolds grid is too large: {nodes} nodes over {len(bearing.pads)} pads would "
            f"need about {nodes * BYTES_PER_NODE / 1e9:.3g} GB",
            field="bearing.grid",
            value=f"n_theta = {grid.n_theta}, n_z = {grid.n_z}",
            expected=f"at most {MAX_GRID_NODES} nodes (pads x (n_theta + 1) x (n_z + 1))",
        )


def _with_pockets(pockets: list[_PocketIn], n_pads: int) -> dict[int, Pocket]:
    out: dict[int, Pocket] = {}
    for k, p in enumerate(pockets):
        for num in p.pads:
            if not 1 <= num <= n_pads:
                raise ModelError(
                    "pocket on a pad that does not exist",
                    field=f"bearing.pockets[{k}].pads",
                    value=num,
                    expected=f"pad numbers 1..{n_pads}",
                )
            if num - 1 in out:
                raise ModelError(
                    "two pockets on one pad",
                    field=f"bearing.pockets[{k}].pads",
                    value=num,
                    expected="at most one pocket per pad",
                )
            out[num - 1] = Pocket(p.start, p.arc, p.width, p.depth)
    return out


def _build(inp: Any, viscosity: float) -> Bearing:
    common = dict(
        diameter=inp.diameter, length=inp.length, clearance=inp.clearance, viscosity=viscosity
    )
    name = inp.name
    t = inp.type
    if t == "plain":
        return plain(**common, name=name or "plain")
    if t == "tilting_pad":
        return tilting_pad(
            **common,
            pivots=inp.pivots,
            arc=inp.arc,
            preload=inp.preload,
            offset=inp.offset,
            inertia=inp.pad_inertia,
            mass=inp.pad_mass,
            thickness=inp.pad_thickness,
            pivot_stiffness=inp.pivot_stiffness,
            name=name or "tilting pad",
        )
    if t == "axial_groove":
        base = axial_groove(
            **common,
            n_grooves=inp.grooves,
            groove_arc=inp.groove_arc,
            first_groove=inp.first_groove,
            name=name or "axial groove",
        )
    elif t == "offset_halves":
        base = offset_halves(
            **common, preload=inp.preload, groove_arc=inp.groove_arc, name=name or "offset halves"
        )
    elif t == "elliptical":
        base = elliptical(
            **common, preload=inp.preload, groove_arc=inp.groove_arc, name=name or "elliptical"
        )
    elif t == "multilobe":
        base = multilobe(
            **common,
            pivots=inp.pivots,
            arc=inp.arc,
            preload=inp.preload,
            offset=inp.offset,
            name=name or "multilobe",
        )
    else:  # pads
        from .geometry import FixedBearing

        base = FixedBearing(
            **common,
            pads=tuple(Pad(p.start, p.arc, p.preload, p.offset) for p in inp.pads),
            name=name or "pads",
        )
    pockets = _with_pockets(inp.pockets, len(base.pads))
    if not pockets:
        return base
    from dataclasses import replace

    pads = tuple(
        replace(p, pocket=pockets.get(k)) if k in pockets else p for k, p in enumerate(base.pads)
    )
    return replace(base, pads=pads)


def _loc(loc: tuple) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif part in (
            "plain",
            "axial_groove",
            "offset_halves",
            "elliptical",
            "multilobe",
            "pads",
            "tilting_pad",
            "function-after",
            "function-before",
        ):
            continue
        else:
            out += ("." if out else "") + str(part)
    return out


def parse_bearing(doc: dict, source: str = "") -> BearingCase:
    """Validate a parsed TOML document (``{"bearing": {...}}``) into a :class:`BearingCase`."""
    try:
        data = _File.model_validate(doc)
    except ValidationError as exc:
        # a misspelt key also makes its field "missing": name the misspelling first
        errors = sorted(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
        first = errors[0]
        more = f" (and {len(errors) - 1} more error(s))" if len(errors) > 1 else ""
        msg = first["msg"].removeprefix("Value error, ")
        kind = first["type"]
        message, expected = {
            "value_error": (msg, None),
            "extra_forbidden": ("unknown key", "a key listed in docs/bearings.md (check spelling)"),
            "missing": ("missing required field", "this field to be given"),
            "union_tag_invalid": (
                "unknown bearing type",
                "plain | axial_groove | offset_halves | elliptical | multilobe | pads | "
                "tilting_pad",
            ),
        }.get(kind, ("invalid value", msg[:1].lower() + msg[1:]))
        value = first.get("input")
        where = _loc(first["loc"])
        if kind == "extra_forbidden" and first["loc"]:
            message = f"unknown key {first['loc'][-1]!r}{_did_you_mean(first['loc'][-1])}"
            value = None
        if kind == "missing":
            value = None
        elif kind == "union_tag_invalid" and isinstance(value, dict):
            value, where = value.get("type"), f"{where}.type"
        raise ModelError(
            message + more,
            field=where,
            value=value,
            expected=expected,
            file=source or None,
        ) from None
    inp = data.bearing
    try:
        lubricant, thermal, viscosity, temperature = _thermal(inp)
        bearing = _build(inp, viscosity)
        _check_size(bearing, inp.grid)
        options = SolverOptions(
            grid=Grid(inp.grid.n_theta, inp.grid.n_z), cavitation=inp.cavitation, thermal=thermal
        )
    except ModelError as err:
        if err.field and not err.field.startswith("bearing."):
            err = ModelError(
                err.message, field=f"bearing.{err.field}", value=err.value, expected=err.expected
            )
        raise (err.with_file(source) if source else err) from None
    loads = tuple((ld.fx, ld.fy) for ld in inp.loads)
    names = tuple(ld.name for ld in inp.loads)
    return BearingCase(
        bearing, inp.speed, loads, names, options, source, inp.notes, lubricant, temperature
    )


def _lubricant(lu: _LubricantIn) -> Lubricant:
    ways = (("grade", lu.grade), ("nu40", lu.nu40), ("viscosity_points", lu.viscosity_points))
    given = [n for n, v in ways if v is not None]
    props = dict(
        density=lu.density,
        specific_heat=lu.specific_heat,
        thermal_conductivity=lu.thermal_conductivity,
        pour_point=lu.pour_point,
        max_temperature=lu.max_temperature,
    )
    if len(given) != 1 or (lu.nu40 is None) != (lu.nu100 is None):
        raise ModelError(
            "give the lubricant's viscosity one way",
            field="lubricant",
            value=", ".join(given + (["nu100"] if lu.nu100 is not None else [])) or None,
            expected="grade = 'ISO VG 32', or nu40 and nu100, or viscosity_points (with law)",
        )
    if lu.law is not None and lu.viscosity_points is None:
        raise ModelError(
            "'law' goes with viscosity_points (a grade or nu40/nu100 use ASTM D341)",
            field="lubricant.law",
            value=lu.law,
            expected="viscosity_points, or no law",
        )
    if lu.grade is not None:
        text = lu.grade.upper().replace("ISO", "").replace("VG", "").strip()
        try:
            grade = int(text)
        except ValueError:
            raise ModelError(
                "cannot read the ISO VG grade",
                field="lubricant.grade",
                value=lu.grade,
                expected="e.g. 'ISO VG 32'",
            ) from None
        return iso_vg(grade, vi=lu.viscosity_index, **props)
    name = lu.name
    if lu.nu40 is not None:
        return Lubricant.walther(lu.nu40, lu.nu100, name=name, **props)
    pts = [(float(t), float(m)) for t, m in lu.viscosity_points]
    law = lu.law or "walther"
    need = 3 if law == "vogel" else 2
    if len(pts) != need:
        raise ModelError(
            f"the {law} law takes {need} viscosity points",
            field="lubricant.viscosity_points",
            value=len(pts),
            expected=f"{need} [temperature, dynamic viscosity] pairs",
        )
    if law == "vogel":
        return Lubricant.vogel(pts, name=name, **props)
    if law == "exponential":
        return Lubricant.exponential(pts[0], pts[1], name=name, **props)
    # walther through two dynamic viscosities: ν = μ/ρ(T)
    probe = Lubricant.constant(1.0, density=lu.density)
    (t1, m1), (t2, m2) = pts
    nu1, nu2 = m1 / float(probe.density_at(t1)), m2 / float(probe.density_at(t2))
    return Lubricant.walther(nu1, nu2, t1, t2, name=name, **props)


def _thermal(inp: Any):
    """(lubricant, ThermalModel or None, the bearing's viscosity, isoviscous temperature)."""
    from .thermal import ThermalModel

    if inp.thermal is None and inp.lubricant is None:
        if inp.viscosity is None:
            raise ModelError(
                "missing required field",
                field="viscosity",
                expected="a viscosity, or [bearing.lubricant] with [bearing.thermal]",
            )
        return None, None, inp.viscosity, None
    if inp.lubricant is None or inp.thermal is None:
        have, need = ("thermal", "lubricant") if inp.lubricant is None else ("lubricant", "thermal")
        raise ModelError(
            f"[bearing.{have}] needs [bearing.{need}]",
            field=need,
            expected=(
                "the oil: grade, nu40 and nu100, or viscosity_points"
                if need == "lubricant"
                else "model ('isoviscous', 'effective' or 'thd') and supply_temperature"
            ),
        )
    if inp.viscosity is not None:
        raise ModelError(
            "the viscosity comes from the lubricant and its temperature",
            field="viscosity",
            value=inp.viscosity,
            expected="no 'viscosity' with [bearing.lubricant] (or drop the lubricant)",
        )
    lub = _lubricant(inp.lubricant)
    th = inp.thermal
    lub.check_temperature(th.supply_temperature, "thermal.supply_temperature")
    if th.model != "thd" and "cross_film_layers" in th.model_fields_set:
        raise ModelError(
            "cross_film_layers applies to the THD model only (the others have one temperature "
            "across the film)",
            field="thermal.cross_film_layers",
            value=th.cross_film_layers,
            expected="model = 'thd', or no cross_film_layers",
        )
    if th.model == "isoviscous":
        for name in ("carry_over", "effective_factor"):
            if name in th.model_fields_set:
                raise ModelError(
                    f"{name} has no effect on an isoviscous film",
                    field=f"thermal.{name}",
                    value=getattr(th, name),
                    expected="model = 'effective' or 'thd'",
                )
        t = th.temperature if th.temperature is not None else th.supply_temperature
        lub.check_temperature(t, "thermal.temperature")
        return lub, None, float(lub.viscosity(t)), t
    if th.temperature is not None:
        raise ModelError(
            "a film temperature is given only with model = 'isoviscous' (the thermal models "
            "compute it)",
            field="thermal.temperature",
            value=f"{th.temperature - CELSIUS:.6g} degC",
            expected="no 'temperature' here",
        )
    model = ThermalModel(
        th.model,
        lub,
        th.supply_temperature,
        carry_over=th.carry_over,
        effective_factor=th.effective_factor,
        pad_heat_transfer=th.pad_heat_transfer,
        journal_heat_transfer=th.journal_heat_transfer,
        journal_temperature=th.journal_temperature,
        cross_film_layers=th.cross_film_layers,
        tol=th.tolerance,
        max_iter=th.max_iterations,
        relaxation=th.relaxation,
    )
    return lub, model, float(lub.viscosity(th.supply_temperature)), None


def load_bearing(path: str | Path) -> BearingCase:
    """Read a bearing TOML file (see module docstring and ``docs/bearings.md``)."""
    path = Path(path)
    doc = read_toml(path, "bearing")
    if "bearing" not in doc and ("shafts" in doc or "materials" in doc):
        raise ModelError(
            "this is a rotor model file, not a bearing file",
            file=str(path),
            expected="a bearing file with a [bearing] table (see docs/bearings.md)",
        )
    return parse_bearing(doc, str(path))


def load_table_file(path: str | Path):
    """Read a bearing coefficient table file (CSV or TOML, as written by
    :func:`~gearrotor.bearings.save_table`), checked: the same as
    :func:`~gearrotor.bearings.load_table`."""
    from .coefficients import load_table

    return load_table(path)
