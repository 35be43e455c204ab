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


class _Common(_Strict):
    name: str = ""
    diameter: Length
    length: Length
    clearance: Length
    viscosity: Viscosity
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
        Solver options (grid, cavitation) from the file.
    source
        The file it came from.
    notes
        Free text from the file.
    """

    bearing: Bearing
    speed: float | None
    loads: tuple[tuple[float, float], ...]
    load_names: tuple[str, ...] = ()
    options: SolverOptions = field(default_factory=SolverOptions)
    source: str = ""
    notes: str = ""


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


def _build(inp: Any) -> Bearing:
    common = dict(
        diameter=inp.diameter, length=inp.length, clearance=inp.clearance, viscosity=inp.viscosity
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
        bearing = _build(inp)
        _check_size(bearing, inp.grid)
        options = SolverOptions(
            grid=Grid(inp.grid.n_theta, inp.grid.n_z), cavitation=inp.cavitation
        )
    except ModelError as err:
        if err.field and not err.field.startswith("bearing."):
            err = ModelError(
                err.message, field=f"bearing.{err.field}", value=err.value, expected=err.expected
            )
        raise (err.with_file(source) if source else err) from None
    loads = tuple((ld.fx, ld.fy) for ld in inp.loads)
    names = tuple(ld.name for ld in inp.loads)
    return BearingCase(bearing, inp.speed, loads, names, options, source, inp.notes)


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
