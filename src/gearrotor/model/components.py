"""What a machine is: shafts, disks, bearings, couplings, gear meshes, unbalance, probes.

These are validated, frozen pydantic models. Values accept plain numbers (SI) or strings with
units; unknown keys are rejected. Cross-references (shaft names, node indices, speeds) are
checked when a :class:`~gearrotor.model.Train` is built.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    Strict,
    field_validator,
    model_serializer,
    model_validator,
)

from ..units import (
    Angle,
    AngularSpeed,
    Damping,
    Density,
    Dimensionless,
    Force,
    Frequency,
    Inertia,
    Length,
    Mass,
    Modulus,
    Rate,
    RotDamping,
    RotStiffness,
    Stiffness,
    Time,
    Torque,
    UnbalanceAmount,
    to_si,
)
from .gear_pair import GearPair

__all__ = [
    "Int",
    "Flag",
    "Spec",
    "MaterialDamping",
    "Material",
    "Section",
    "Disk",
    "NodeRef",
    "Shaft",
    "BearingTable",
    "FluidFilm",
    "Support",
    "Bearing",
    "Seal",
    "ThrustBearing",
    "TorsionalSupport",
    "CrossCoupling",
    "Coupling",
    "GearSide",
    "MeshStiffness",
    "MeshVariation",
    "StiffnessTable",
    "TransmissionError",
    "Backlash",
    "Mesh",
    "Unbalance",
    "Probe",
    "ExternalTorque",
]


#: An integer field: only an integer is accepted (``node = true`` is not node 1, ``teeth = 37.0``
#: is refused rather than truncated).
Int = Annotated[int, Strict()]
#: A true/false field: only ``true`` or ``false`` (not 1, "yes").
Flag = Annotated[bool, Strict()]


class Spec(BaseModel):
    """Base of all model inputs: frozen, unknown keys rejected."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class MaterialDamping(Spec):
    """Material damping of the shaft elements, as equivalent viscous (Rayleigh) damping.

    Every shaft element made of the material gets the damping matrix ``C_e = α M_e + β K_e``
    (its own consistent mass and stiffness; disks, bearings, couplings and meshes get none).
    Give either

    * ``alpha`` (1/s, mass-proportional) and/or ``beta`` (s, stiffness-proportional): a mode of
      a uniform free shaft at natural frequency ω gets the damping ratio ζ = α/(2ω) + βω/2; or
    * ``loss_factor`` η with ``reference_frequency`` ω_ref (rad/s, or e.g. ``"100 Hz"``): the
      hysteretic stiffness K(1 + iη) replaced by the viscous damping that dissipates the same
      energy per cycle at ω_ref, i.e. α = 0 and β = η/ω_ref (ζ = η/2 at ω_ref, growing in
      proportion to frequency elsewhere).

    The mass-proportional term acts on the torsional vibration relative to each shaft's rigid
    rotation, so it never brakes the spin; on lateral and axial motion it also damps rigid-body
    motion, like an external damping proportional to mass.

    ``rotating = false`` (default): stationary damping, the matrix C_e in the fixed frame.
    ``rotating = true``: internal damping, acting on the strain rate seen by the spinning
    material. Its bending part then also gives the skew circulatory stiffness Ω Kc
    (:meth:`gearrotor.elements.ShaftElement.Kc`, Ω the shaft's spin speed; Zorzi & Nelson
    1977), which feeds energy into forward whirl above the speed ω_n (1 + c_e/c_i) of each mode
    (external/internal modal damping); its axial and torsional parts are unchanged. Rotating
    damping is stiffness-proportional only (``alpha = 0``): mass-proportional damping in the
    rotating frame would act on a rigid whirl, which strains nothing.
    """

    alpha: Rate = Field(default=0.0, ge=0, description="mass-proportional coefficient (1/s)")
    beta: Time = Field(default=0.0, ge=0, description="stiffness-proportional coefficient (s)")
    loss_factor: Dimensionless | None = Field(default=None, ge=0)
    reference_frequency: Frequency | None = Field(default=None, gt=0)
    rotating: Flag = False

    @model_validator(mode="after")
    def _one_form(self) -> MaterialDamping:
        if (self.loss_factor is None) != (self.reference_frequency is None):
            raise ValueError(
                "'loss_factor' and 'reference_frequency' go together: the loss factor is "
                "converted to viscous damping at that frequency (e.g. loss_factor = 0.002, "
                "reference_frequency = '100 Hz')"
            )
        if self.loss_factor is not None and (self.alpha or self.beta):
            raise ValueError(
                "give either 'loss_factor' (with 'reference_frequency') or the Rayleigh "
                "coefficients 'alpha'/'beta', not both"
            )
        if self.rotating and self.alpha:
            raise ValueError(
                f"rotating damping is stiffness-proportional only: got alpha = {self.alpha} "
                "1/s with rotating = true; expected alpha = 0 (use 'beta' or 'loss_factor')"
            )
        return self

    @property
    def rayleigh(self) -> tuple[float, float]:
        """(α in 1/s, β in s) of the equivalent viscous damping ``α M_e + β K_e``."""
        if self.loss_factor is not None:
            return 0.0, self.loss_factor / self.reference_frequency
        return self.alpha, self.beta


class Material(Spec):
    """Isotropic elastic material. Give ``poisson`` or ``shear_modulus``; optionally the shaft
    elements' material ``damping`` (:class:`MaterialDamping`; default: none)."""

    E: Modulus = Field(gt=0, description="Young's modulus (Pa)")
    density: Density = Field(gt=0, description="kg/m³")
    poisson: Dimensionless | None = Field(default=None, gt=-1, lt=0.5)
    shear_modulus: Modulus | None = Field(default=None, gt=0)
    damping: MaterialDamping | None = None

    @model_validator(mode="after")
    def _one_of(self) -> Material:
        if (self.poisson is None) == (self.shear_modulus is None):
            raise ValueError("give exactly one of 'poisson' or 'shear_modulus'")
        return self

    @model_serializer(mode="wrap")
    def _without_absent_damping(self, handler):
        # an undamped material serialises as before damping existed, so the model JSON (study
        # case keys, transient checkpoint fingerprints) of existing models does not change
        out = handler(self)
        if self.damping is None:
            out.pop("damping", None)
        return out

    @property
    def G(self) -> float:
        if self.shear_modulus is not None:
            return self.shear_modulus
        return self.E / (2 * (1 + self.poisson))


_SECTION_TORSION = ("torsional_stiffness", "polar_inertia", "torsional_damping")


class Section(Spec):
    """A uniform stretch of shaft, split into ``elements`` equal Timoshenko elements.

    The torsional rod may be given directly instead of from the diameters and the material:
    ``torsional_stiffness`` (N·m/rad) and ``polar_inertia`` (kg·m²) of the whole section (a
    quill shaft, a spline or a flexible element of known stiffness, an inertia from a data
    sheet; the section's ``elements`` are springs in series, each ``n k``, with ``J / n`` of
    consistent rod mass), and ``torsional_damping`` (N·m·s/rad, a dashpot across the whole
    section, ``n c`` per element). The lateral beam, the axial bar, the gyroscopic matrix and
    the surface shear stress still come from the diameters.
    """

    length: Length = Field(gt=0)
    outer_diameter: Length = Field(gt=0)
    inner_diameter: Length = Field(default=0.0, ge=0)
    elements: Int = Field(default=1, ge=1, le=10000)
    material: str | None = None
    mass_outer_diameter: Length | None = Field(default=None, gt=0)
    mass_inner_diameter: Length | None = Field(default=None, ge=0)
    # the torsional rod given directly (whole section; lateral beam and stress from diameters)
    torsional_stiffness: RotStiffness | None = Field(default=None, gt=0)
    polar_inertia: Inertia | None = Field(default=None, gt=0)
    torsional_damping: RotDamping | None = Field(default=None, ge=0)

    @model_serializer(mode="wrap")
    def _without_absent_torsion(self, handler):
        # a section without the torsional values serialises as before they existed (model
        # JSON: study case keys, checkpoint fingerprints)
        out = handler(self)
        for key in _SECTION_TORSION:
            if getattr(self, key) is None:
                out.pop(key, None)
        return out

    @model_validator(mode="after")
    def _hollow(self) -> Section:
        if self.inner_diameter >= self.outer_diameter:
            raise ValueError(
                f"inner_diameter {self.inner_diameter} m must be smaller than outer_diameter "
                f"{self.outer_diameter} m"
            )
        return self


class NodeRef(Spec):
    """A node of a shaft: by ``node`` index (0 at the shaft's start) or by axial position ``at``
    measured from the shaft's start (must fall on a node)."""

    shaft: str
    node: Int | None = Field(default=None, ge=0)
    at: Length | None = None

    @model_validator(mode="after")
    def _one_of(self) -> NodeRef:
        if (self.node is None) == (self.at is None):
            raise ValueError("give exactly one of 'node' (index) or 'at' (axial position)")
        return self


class Disk(Spec):
    """Rigid disk on a shaft node: mass and inertias, or a solid/hollow cylinder geometry."""

    node: Int | None = Field(default=None, ge=0)
    at: Length | None = None
    name: str | None = None
    mass: Mass | None = Field(default=None, ge=0)
    polar: Inertia | None = Field(default=None, ge=0)
    transverse: Inertia | None = Field(default=None, ge=0)
    outer_diameter: Length | None = Field(default=None, gt=0)
    inner_diameter: Length = Field(default=0.0, ge=0)
    width: Length | None = Field(default=None, gt=0)
    material: str | None = None

    @model_validator(mode="after")
    def _given(self) -> Disk:
        if (self.node is None) == (self.at is None):
            raise ValueError("give exactly one of 'node' (index) or 'at' (axial position)")
        lumped = self.mass is not None
        geom = self.outer_diameter is not None or self.width is not None
        if lumped == geom:
            raise ValueError(
                "give either mass/polar/transverse or outer_diameter/width (+ material)"
            )
        if lumped and (self.polar is None or self.transverse is None):
            raise ValueError("a lumped disk needs mass, polar and transverse")
        if geom and (self.outer_diameter is None or self.width is None):
            raise ValueError("a disk by geometry needs outer_diameter and width")
        return self


class Shaft(Spec):
    """A rotor: sections along +z from ``start`` (axial coordinate of node 0)."""

    name: str
    material: str
    sections: list[Section] = Field(min_length=1)
    disks: list[Disk] = Field(default_factory=list)
    position: tuple[Length, Length] | None = None
    start: Length = 0.0
    speed: AngularSpeed | None = None


_COEFFICIENT_NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


def _table_values(kind: str):
    """A coefficient column of a table: an array of values (one per speed) or, in a speed ×
    whirl table, an array of rows (one per speed, one value per whirl frequency); each value a
    number (SI) or a string with units."""

    def convert(v):
        if not isinstance(v, list):
            raise ValueError(
                "expected an array of values, one per speed (with 'whirl': one row per speed)"
            )
        rows = [isinstance(r, list) for r in v]
        if any(rows) and not all(rows):
            raise ValueError(
                "mixes values and rows: give one value per speed, or (with 'whirl') one row "
                "of values per speed"
            )
        try:
            if v and all(rows):
                return [[to_si(x, kind) for x in r] for r in v]
            return [to_si(x, kind) for x in v]
        except ValueError as exc:
            raise ValueError(str(exc)) from None

    return Annotated[list, BeforeValidator(convert)]


def _drop_absent(handler, obj, keys: tuple[str, ...]):
    # optional fields added later serialise only when given, so the model JSON (study case
    # keys, transient checkpoint fingerprints) of existing models does not change
    out = handler(obj)
    for key in keys:
        if getattr(obj, key) is None:
            out.pop(key, None)
    return out


class BearingTable(Spec):
    """Eight coefficients tabulated against shaft speed (linear interpolation), or against
    shaft speed and whirl frequency: with ``whirl`` (whirl frequencies, increasing, >= 0,
    covering the speeds) each coefficient is one row per speed with one value per whirl
    frequency (a speed × whirl table, ``docs/model_format.md``)."""

    speed: list[AngularSpeed] = Field(min_length=1)
    whirl: list[AngularSpeed] | None = Field(default=None, min_length=1)
    kxx: _table_values("stiffness")
    kxy: _table_values("stiffness")
    kyx: _table_values("stiffness")
    kyy: _table_values("stiffness")
    cxx: _table_values("damping")
    cxy: _table_values("damping")
    cyx: _table_values("damping")
    cyy: _table_values("damping")
    extrapolate: Literal["error", "hold"] = "error"

    @model_serializer(mode="wrap")
    def _without_absent_whirl(self, handler):
        return _drop_absent(handler, self, ("whirl",))

    @model_validator(mode="after")
    def _lengths(self) -> BearingTable:
        n = len(self.speed)
        for name in _COEFFICIENT_NAMES:
            vals = getattr(self, name)
            if len(vals) != n:
                raise ValueError(f"'{name}' has {len(vals)} values, 'speed' has {n}")
            two_d = bool(vals) and isinstance(vals[0], list)
            if self.whirl is None and two_d:
                raise ValueError(
                    f"'{name}' has rows (a speed × whirl table) but the table has no 'whirl': "
                    "give the whirl frequencies of the columns, e.g. whirl = ['0 rpm', "
                    "'3000 rpm', '6000 rpm']"
                )
            if self.whirl is not None:
                m = len(self.whirl)
                bad = [i for i, r in enumerate(vals) if not isinstance(r, list) or len(r) != m]
                if bad:
                    got = vals[bad[0]]
                    size = len(got) if isinstance(got, list) else "a single value"
                    raise ValueError(
                        f"'{name}' row {bad[0]} has {size}, 'whirl' has {m} frequencies: one "
                        "row per speed, one value per whirl frequency"
                    )
        if any(b <= a for a, b in zip(self.speed, self.speed[1:], strict=False)):
            raise ValueError("'speed' must be strictly increasing")
        if self.whirl is not None:
            w = self.whirl
            if w[0] < 0 or any(b <= a for a, b in zip(w, w[1:], strict=False)):
                raise ValueError("'whirl' must be >= 0 and strictly increasing")
            lo, hi = min(abs(s) for s in self.speed), max(abs(s) for s in self.speed)
            if w[0] > lo * (1 + 1e-12) or w[-1] < hi * (1 - 1e-12):
                raise ValueError(
                    f"'whirl' ({w[0] * 30 / math.pi:.6g}..{w[-1] * 30 / math.pi:.6g} rpm) must "
                    f"cover the speeds ({lo * 30 / math.pi:.6g}..{hi * 30 / math.pi:.6g} rpm): "
                    "the synchronous coefficients (whirl = speed) are read from the table"
                )
        return self

    def whirl_rows(self) -> tuple:
        """A speed × whirl table's rows ``(|speed|, whirl (n_w,), values (n_w, 8))`` in SI,
        by increasing |speed| (valid by construction: the validator checked the whirl
        frequencies and that they cover the speeds)."""
        import numpy as np

        w = np.asarray(self.whirl, float)
        rows = []
        for i, s in enumerate(self.speed):
            cols = [np.asarray(getattr(self, n)[i], float) for n in _COEFFICIENT_NAMES]
            rows.append((abs(float(s)), w.copy(), np.column_stack(cols)))
        return tuple(sorted(rows, key=lambda r: r[0]))

    @property
    def whirl_dependent(self) -> bool:
        """True when a coefficient changes along a row (over whirl)."""
        if self.whirl is None:
            return False
        return any(
            any(v != r[0] for v in r) for name in _COEFFICIENT_NAMES for r in getattr(self, name)
        )


class Support(Spec):
    """A pedestal under a bearing: lumped mass on its own stiffness/damping to ground (x, y)."""

    mass: Mass = Field(gt=0)
    kxx: Stiffness = 0.0
    kyy: Stiffness = 0.0
    cxx: Damping = 0.0
    cyy: Damping = 0.0


def _distinct_speeds(v):
    """Tabulation speeds (rad/s) are distinct in magnitude (the table's rows are at |speed|):
    two rows at one speed would hold two sets of coefficients for it (issue 23)."""
    if v is None:
        return v
    mags = [abs(float(x)) for x in v]
    seen: dict[float, int] = {}
    for k, m in enumerate(mags):
        if m in seen:
            raise ValueError(
                f"speeds[{seen[m]}] and speeds[{k}] are the same speed "
                f"({m * 30 / math.pi:.6g} rpm): a table has one row per speed; expected "
                "distinct speeds"
            )
        seen[m] = k
    return v


class FluidFilm(Spec):
    """Coefficients from the fluid-film bearing solver: a bearing file (see docs/bearings.md),
    the static ``load`` (Fx, Fy) on this journal (default: the file's load case ``load_case``)
    and the ``speeds`` (absolute shaft speeds) at which to tabulate them."""

    file: str
    load: tuple[Force, Force] | None = None
    load_case: Int = Field(default=0, ge=0)
    speeds: list[AngularSpeed] = Field(min_length=1)
    #: one static load per speed instead of ``load`` (an operating point's loads, which follow
    #: the speed when its power is held)
    loads: list[tuple[Force, Force]] | None = None
    #: tilting pads only: carry the pads' tilt (and, with a pivot stiffness, radial) DOFs into
    #: the train with the full film coefficients, instead of synchronously reduced coefficients
    pad_dynamics: Flag = False
    #: overrides of the bearing file's pad properties (every pad): inertia about the pivot,
    #: pad mass (on the radial DOF of a flexible pivot), radial pivot stiffness
    pad_inertia: Inertia | None = Field(default=None, gt=0)
    pad_mass: Mass | None = Field(default=None, gt=0)
    pivot_stiffness: Stiffness | None = Field(default=None, gt=0)

    _speeds = field_validator("speeds")(_distinct_speeds)

    @model_validator(mode="after")
    def _loads(self) -> FluidFilm:
        if self.loads is not None:
            if self.load is not None:
                raise ValueError("give either 'load' or 'loads' (one per speed), not both")
            if len(self.loads) != len(self.speeds):
                raise ValueError(
                    f"'loads' has {len(self.loads)} entries, 'speeds' has {len(self.speeds)}: "
                    "one load per speed"
                )
        return self


class _Coefficients(NodeRef):
    """What a bearing and a seal share: a node, a name and 8 coefficients given as constants
    (``k``/``c`` isotropic shortcuts or kxx..cyy), a ``table`` against speed or a saved
    ``table_file``."""

    name: str | None = None
    k: Stiffness | None = None
    c: Damping | None = None
    kxx: Stiffness = 0.0
    kxy: Stiffness = 0.0
    kyx: Stiffness = 0.0
    kyy: Stiffness = 0.0
    cxx: Damping = 0.0
    cxy: Damping = 0.0
    cyx: Damping = 0.0
    cyy: Damping = 0.0
    table: BearingTable | None = None
    table_file: str | None = None

    def constant(self) -> bool:
        """Whether any constant coefficient is given."""
        return any(
            getattr(self, n)
            for n in ("k", "c", "kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
        )

    def coefficients(self) -> tuple[float, ...]:
        """The constant coefficients kxx kxy kyx kyy cxx cxy cyx cyy (isotropic shortcuts added)."""
        k = self.k or 0.0
        c = self.c or 0.0
        return (
            self.kxx + k,
            self.kxy,
            self.kyx,
            self.kyy + k,
            self.cxx + c,
            self.cxy,
            self.cyx,
            self.cyy + c,
        )


class Bearing(_Coefficients):
    """Radial bearing or seal with 8 coefficients: constant (``k``/``c`` isotropic shortcuts or
    kxx..cyy), a ``table`` against speed, a saved table file ``table_file`` (CSV/TOML written by
    ``gearrotor.bearings.save_table``) or ``fluid_film`` (solved at assembly); optionally on a
    ``support`` pedestal. Relative file paths are relative to the model file. Outside the
    speeds of a ``table_file``/``fluid_film`` table, ``extrapolate = "hold"`` holds the end
    values; the default is an error."""

    fluid_film: FluidFilm | None = None
    extrapolate: Literal["error", "hold"] = "error"
    support: Support | None = None
    #: speed × whirl tables: the largest relative misfit accepted of the rational fit that the
    #: eigenproblem uses off the whirl axis (default 1e-4)
    fit_tolerance: Dimensionless | None = Field(default=None, gt=0, lt=1)

    @model_serializer(mode="wrap")
    def _without_absent_fit(self, handler):
        return _drop_absent(handler, self, ("fit_tolerance",))

    @model_validator(mode="after")
    def _one_source(self) -> Bearing:
        sources = [self.table is not None, self.table_file is not None, self.fluid_film is not None]
        constant = self.constant()
        if sum(sources) + constant > 1:
            raise ValueError(
                "give one coefficient source: constants, 'table', 'table_file' or 'fluid_film'"
            )
        if self.fit_tolerance is not None and self.table is None and self.table_file is None:
            raise ValueError(
                "'fit_tolerance' belongs to a speed × whirl table ('table' with 'whirl', or a "
                "'table_file' with a whirl_rpm column)"
            )
        return self

    @field_validator("k", "kxx", "kyy", "c", "cxx", "cyy")
    @classmethod
    def _direct_nonnegative(cls, v, info):
        # a bearing's direct stiffness and damping are >= 0: a negative direct stiffness is a
        # seal's (labyrinth seals), a [[seals]] entry; computed tables (fluid film) may differ
        if v is not None and v < 0:
            unit = "N/m" if info.field_name.startswith("k") else "N*s/m"
            raise ValueError(
                f"a bearing's direct {'stiffness' if unit == 'N/m' else 'damping'} must be >= 0, "
                f"got {v:.6g} {unit}; a negative direct stiffness or damping belongs to a seal: "
                "give it as [[seals]]"
            )
        return v


class Seal(_Coefficients):
    """An annular seal (labyrinth, damper, hole-pattern) between a shaft node and ground: 8
    coefficients, constant (``k``/``c`` isotropic shortcuts or kxx..cyy) or a ``table`` against
    speed, or a saved ``table_file``, or a seal ``file`` (``docs/seals.md``: the seal computed
    from its geometry, tabulated at the absolute shaft ``speeds`` at synchronous whirl). Unlike
    a bearing's, its direct stiffness and damping may be negative (a labyrinth seal's direct
    stiffness often is). It assembles like a bearing to ground in every analysis; API 617 Level
    I analyses and undamped critical speed maps leave seals out, as they leave out the
    cross-coupling destabilisers."""

    file: str | None = None
    speeds: list[AngularSpeed] | None = Field(default=None, min_length=1)
    #: a seal ``file`` solved at these whirl frequencies too (and at each speed's own): a
    #: speed × whirl table (docs/seals.md)
    whirls: list[AngularSpeed] | None = Field(default=None, min_length=2)
    extrapolate: Literal["error", "hold"] = "error"
    fit_tolerance: Dimensionless | None = Field(default=None, gt=0, lt=1)

    @model_serializer(mode="wrap")
    def _without_absent_whirl(self, handler):
        return _drop_absent(handler, self, ("whirls", "fit_tolerance"))

    _speeds = field_validator("speeds")(_distinct_speeds)

    @model_validator(mode="after")
    def _one_source(self) -> Seal:
        constant = self.constant()
        sources = (self.table is not None) + (self.table_file is not None)
        if sources + (self.file is not None) + constant > 1:
            raise ValueError(
                "give one coefficient source: constants, 'table', 'table_file' or 'file'"
            )
        if (self.file is None) != (self.speeds is None):
            raise ValueError(
                "a seal 'file' goes with 'speeds', the shaft speeds at which its coefficients "
                "are tabulated (e.g. speeds = ['4000 rpm', '8000 rpm', '12000 rpm'])"
            )
        if self.whirls is not None:
            if self.file is None:
                raise ValueError(
                    "'whirls' are the whirl frequencies at which a seal 'file' is solved; a "
                    "table gives its own ('table.whirl' or a whirl_rpm column)"
                )
            w = self.whirls
            if w[0] < 0 or any(b <= a for a, b in zip(w, w[1:], strict=False)):
                raise ValueError("'whirls' must be >= 0 and strictly increasing")
        if self.fit_tolerance is not None and self.whirls is None and self.table is None:
            if self.table_file is None:
                raise ValueError(
                    "'fit_tolerance' belongs to a speed × whirl table ('table' with 'whirl', a "
                    "'table_file' with a whirl_rpm column, or a seal 'file' with 'whirls')"
                )
        return self


class TorsionalSupport(NodeRef):
    """Torsional spring ``k`` (N·m/rad) and damper ``c`` (N·m·s/rad) from a node's θz to ground:
    a held or elastically restrained end, propeller or windage damping (the slope dT/dΩ of
    the load curve at the operating speed). In a transient ``c`` is a torque ``−c θ̇`` on the
    absolute speed (a viscous brake); a spring to ground holds the shaft, so the transients
    refuse it."""

    name: str | None = None
    k: RotStiffness = Field(default=0.0, ge=0)
    c: RotDamping = Field(default=0.0, ge=0)

    @model_validator(mode="after")
    def _something(self) -> TorsionalSupport:
        if self.k == 0 and self.c == 0:
            raise ValueError("a torsional support needs k > 0 or c > 0 (both are 0)")
        return self


class ThrustBearing(NodeRef):
    name: str | None = None
    kzz: Stiffness = Field(default=0.0, ge=0)
    czz: Damping = Field(default=0.0, ge=0)


class CrossCoupling(NodeRef):
    """Destabiliser kxy = −kyx = q (N/m) at a node."""

    name: str | None = None
    q: Stiffness


class Coupling(Spec):
    """Flexible coupling between two shaft nodes (shafts at the same speed). Stiffness and
    damping are ≥ 0 (a negative spring or damper between two hubs is no coupling; 0: the
    direction is not connected)."""

    name: str | None = None
    node_i: NodeRef
    node_j: NodeRef
    kx: Stiffness = Field(default=0.0, ge=0)
    ky: Stiffness = Field(default=0.0, ge=0)
    kz: Stiffness = Field(default=0.0, ge=0)
    ktx: RotStiffness = Field(default=0.0, ge=0)
    kty: RotStiffness = Field(default=0.0, ge=0)
    ktz: RotStiffness = Field(default=0.0, ge=0)
    cx: Damping = Field(default=0.0, ge=0)
    cy: Damping = Field(default=0.0, ge=0)
    cz: Damping = Field(default=0.0, ge=0)
    ctx: RotDamping = Field(default=0.0, ge=0)
    cty: RotDamping = Field(default=0.0, ge=0)
    ctz: RotDamping = Field(default=0.0, ge=0)


class GearSide(NodeRef):
    """One gear of a mesh: its shaft node, tooth count and radius."""

    teeth: Int = Field(gt=0, le=100_000)
    radius: Length = Field(gt=0)
    E: Modulus | None = Field(default=None, gt=0)


class MeshStiffness(Spec):
    """Average mesh stiffness along the line of action: given ``value``, or ``method`` =
    ``"buckingham"`` (needs contact_ratio and face width) or ``"iso6336"``."""

    method: Literal["value", "buckingham", "iso6336"] = "value"
    value: Stiffness | None = Field(default=None, gt=0)
    contact_ratio: Dimensionless | None = Field(default=None, gt=0)

    @model_validator(mode="after")
    def _given(self) -> MeshStiffness:
        if self.method == "value" and self.value is None:
            raise ValueError("method 'value' needs 'value' (N/m)")
        if self.method != "value" and self.contact_ratio is None:
            raise ValueError(f"method {self.method!r} needs 'contact_ratio'")
        return self


class MeshVariation(Spec):
    """Time-varying stiffness for transient analysis (SPEC 2.4): Ka/Kg, contact ratio, mesh phase,
    number of Fourier terms. ``ka_ratio = 0`` or ``terms = 0`` switches it off."""

    ka_ratio: Dimensionless = Field(default=0.0, ge=0)
    contact_ratio: Dimensionless = Field(default=1.0, gt=0)
    phase: Dimensionless = 0.0
    terms: Int = Field(default=0, ge=0, le=1000)


class Backlash(Spec):
    """Backlash for transient analysis. ``convention = "total"`` means value = 2b (total
    clearance), ``"one_side"`` means value = b."""

    value: Length = Field(default=0.0, ge=0)
    convention: Literal["total", "one_side"] = "one_side"

    @property
    def half(self) -> float:
        """b, the one-side clearance (m)."""
        return self.value / 2 if self.convention == "total" else self.value


class StiffnessTable(Spec):
    """Measured or computed mesh stiffness over one mesh cycle (transient): ``angle`` is the mesh
    angle φ_m = N_i θ_i in [0, 2π) (rad, or with units), ``stiffness`` the total k(φ_m) (N/m);
    it replaces the Fourier series of ``variation``."""

    angle: list[Angle] = Field(min_length=2)
    stiffness: list[Stiffness] = Field(min_length=2)

    @model_validator(mode="after")
    def _lengths(self) -> StiffnessTable:
        if len(self.angle) != len(self.stiffness):
            raise ValueError("'angle' and 'stiffness' must have the same length")
        if any(b <= a for a, b in zip(self.angle, self.angle[1:], strict=False)):
            raise ValueError("'angle' must be strictly increasing")
        return self


class TransmissionError(Spec):
    """Transmission error e(φ_m) = Σ_s [cos_s cos(sφ_m) + sin_s sin(sφ_m)] (m), s = 1, 2, ...;
    the mesh deflection becomes δ − e (transient)."""

    cos: list[Length] = Field(default_factory=list)
    sin: list[Length] = Field(default_factory=list)

    @model_validator(mode="after")
    def _lengths(self) -> TransmissionError:
        if len(self.cos) != len(self.sin):
            raise ValueError("'cos' and 'sin' must have the same number of harmonics")
        return self


class Mesh(Spec):
    """A gear mesh between ``gear`` (i) and ``mate`` (j) (SPEC 2.3).

    ``driver`` (``"gear"`` or ``"mate"``) selects the loaded tooth flank: the one on which the
    driver's torque is transmitted at the nominal speeds (the contact force opposes the driver's
    rotation). Without it the flank is SPEC 2.3's normal, which is the loaded flank when the
    mate drives and the gear turns about +z.
    """

    name: str | None = None
    gear: GearSide
    mate: GearSide
    radius_type: Literal["pitch", "base"] = "pitch"
    pressure_angle: Angle = Field(gt=0, lt=1.5)
    helix_angle: Angle = 0.0
    orientation: Angle = 0.0
    driver: Literal["gear", "mate"] | None = None
    face_width: Length | None = Field(default=None, gt=0)
    stiffness: Stiffness | MeshStiffness | None = None
    damping: Damping = Field(default=0.0, ge=0)
    damping_ratio: Dimensionless | None = Field(default=None, ge=0, lt=1)
    variation: MeshVariation = MeshVariation()
    stiffness_table: StiffnessTable | None = None
    transmission_error: TransmissionError | None = None
    backlash: Backlash = Backlash()
    #: the tooth geometry (a gear pair, inline or ``{ file = "pair.toml" }``, docs/gears.md):
    #: the mean loaded mesh stiffness replaces ``stiffness``, and with ``excitation =
    #: "geometry"`` (the default with a geometry) its TVMS and loaded STE harmonics replace
    #: the square wave of ``variation`` in the transient, Floquet and mesh-response analyses
    geometry: GearPair | None = None
    excitation: Literal["geometry", "square_wave"] | None = None

    @model_validator(mode="after")
    def _stiffness_source(self) -> Mesh:
        if self.geometry is None:
            if self.stiffness is None:
                raise ValueError(
                    "a mesh needs 'stiffness' (a value or a method) or 'geometry' (the tooth "
                    "geometry, docs/gears.md)"
                )
            if self.excitation == "geometry":
                raise ValueError("excitation = 'geometry' needs the mesh's 'geometry'")
        elif self.stiffness is not None:
            raise ValueError(
                "give 'stiffness' or 'geometry' (whose mean loaded stiffness is the mesh "
                "stiffness), not both"
            )
        elif self.excitation != "square_wave":
            if self.stiffness_table is not None:
                raise ValueError(
                    "a 'stiffness_table' and the geometry's own stiffness curve exclude each "
                    "other: leave the table out, or set excitation = 'square_wave'"
                )
            if self.variation.ka_ratio > 0:
                raise ValueError(
                    f"variation.ka_ratio = {self.variation.ka_ratio:g} acts on the square wave; "
                    "with a 'geometry' the stiffness varies as the teeth give it: set "
                    "excitation = 'square_wave' to use the square wave instead, or ka_ratio = 0"
                )
        return self

    @model_serializer(mode="wrap")
    def _without_absent_geometry(self, handler):
        # a mesh without geometry serialises as before (model JSON: study case keys,
        # transient checkpoint fingerprints)
        out = handler(self)
        for key in ("geometry", "excitation"):
            if getattr(self, key) is None:
                out.pop(key, None)
        if self.stiffness is None:
            out.pop("stiffness", None)
        return out

    @property
    def excitation_law(self) -> str:
        """``"geometry"`` (TVMS and STE of the tooth geometry), ``"square_wave"`` (the Fourier
        series of ``variation``) or ``"table"`` (``stiffness_table``)."""
        if self.geometry is not None and self.excitation != "square_wave":
            return "geometry"
        return "table" if self.stiffness_table is not None else "square_wave"

    @field_validator("stiffness")
    @classmethod
    def _positive_stiffness(cls, v):
        # the table form (MeshStiffness.value) has its own gt=0; the plain-number form too
        if isinstance(v, float) and not v > 0:
            raise ValueError(f"expected a positive mesh stiffness such as '1e9 N/m', got {v!r} N/m")
        return v


class Unbalance(NodeRef):
    amount: UnbalanceAmount = Field(ge=0)
    phase: Angle = 0.0


class Probe(NodeRef):
    """Displacement probe at a node, measuring along ``angle`` from +x towards +y."""

    name: str
    angle: Angle = 0.0


class ExternalTorque(NodeRef):
    """External torque about +z at a shaft node (transient analysis), N·m.

    ``T(t, Ω) = f_time(t) · (|Ω| / reference_speed) ** speed_exponent`` where ``f_time`` is
    ``value`` (constant) or linear interpolation in the table ``time``/``values`` (held constant
    outside it: a start-up ramp or a trip). ``speed_exponent = 2`` with a ``reference_speed`` gives
    a load proportional to Ω² (fan/compressor law); ``speed_exponent = 0`` (default) none.
    A positive torque accelerates a shaft spinning about +z.
    """

    name: str | None = None
    value: Torque = 0.0
    time: list[Time] | None = None
    values: list[Torque] | None = None
    speed_exponent: Dimensionless = 0.0
    reference_speed: AngularSpeed | None = Field(default=None, gt=0)

    @model_validator(mode="after")
    def _table(self) -> ExternalTorque:
        if (self.time is None) != (self.values is None):
            raise ValueError("a torque table needs both 'time' and 'values'")
        if self.time is not None:
            if len(self.time) != len(self.values) or len(self.time) < 1:
                raise ValueError("'time' and 'values' must have the same, non-zero length")
            if any(b <= a for a, b in zip(self.time, self.time[1:], strict=False)):
                raise ValueError("'time' must be strictly increasing")
        if self.speed_exponent != 0 and self.reference_speed is None:
            raise ValueError("a speed-dependent torque needs 'reference_speed'")
        return self
