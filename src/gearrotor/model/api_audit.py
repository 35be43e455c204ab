"""The ``[api_audit]`` table of a model: the inputs of the API 617 Level I stability analysis
(where the anticipated cross-coupling acts, Q_A directly or the stages of its formula, the gas
densities, the edition), so that ``gearrotor stability`` and the report's "API audit" section
can run the audit from the file alone. The analysis is
:func:`gearrotor.analyses.audit.stability.level1`; its module docstring gives the formula.

.. code-block:: toml

    [api_audit]
    edition = "8th"                      # API 617 8th edition (2014) or "9th" (2022)
    qa = "5.68e7 N/m"                    # Q_A given directly, or [[api_audit.stages]]
    at = [{ shaft = "pinion", node = 1 }]  # where Q acts ("mid_span": middle of the span)
    # operating_speed = "10800 rpm"      # N_r of the formula (default: the model's speed)
    # suction_density / discharge_density, or average_density (kg/m^3): the screening chart
    # exclude_bearings = ["seal"]        # bearings or seals left out of Level I
    # clearances = [{ shaft = "rotor", node = 5, diametral = "0.3 mm", name = "eye seal" }]

    [[api_audit.stages]]                 # one impeller / blade row
    shaft = "rotor"
    node = 7
    power = "1.5 MW"
    diameter = "400 mm"                  # D_c (impeller) / D_t (blade pitch diameter)
    height = "25 mm"                     # H_c (min. diffuser / discharge width) / H_t (blade)
    density_ratio = 1.3                  # ρ_discharge / ρ_suction (centrifugal)
    kind = "centrifugal"                 # or "axial" (axial compressor or turbine stage)
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator, model_serializer, model_validator

from ..errors import ModelError
from ..units import AngularSpeed, Density, Dimensionless, Length, Power, Stiffness
from .components import Int, NodeRef, Spec

__all__ = ["ApiAudit", "AuditClearance", "AuditSite", "AuditStage", "EDITIONS"]

#: the ``edition`` values accepted (any case): the API 617 8th edition (2014) or 9th (2022)
EDITIONS = (
    "8",
    "8th",
    "API 617 8th edition",
    "API 617 8th edition (2014)",
    "9",
    "9th",
    "API 617 9th edition",
    "API 617 9th edition (2022)",
)


def _positive(v, what: str):
    if v is not None and not v > 0:
        raise ValueError(f"expected a positive {what}")
    return v


#: Densest gas of the screening chart (kg/m³): supercritical CO₂ of reinjection compressors,
#: the densest compressed gas in service, is about 1,100 kg/m³ at 1,000 bar; above 1,500 kg/m³ a
#: gas density means a unit mistake (g/cm³ given as kg/m³, or a liquid).
MAX_GAS_DENSITY = 1500.0


def gas_density(v, what: str = "gas density"):
    """A positive gas density of at most :data:`MAX_GAS_DENSITY` (ValueError otherwise)."""
    _positive(v, what)
    if v is not None and v > MAX_GAS_DENSITY:
        raise ValueError(
            f"a {what} above {MAX_GAS_DENSITY:.0f} kg/m^3 is denser than any compressed gas "
            "(supercritical CO2 at 1,000 bar is about 1,100 kg/m^3): a unit mistake, or a "
            f"liquid; expected 0 < {what} <= {MAX_GAS_DENSITY:.0f} kg/m^3"
        )
    return v


class AuditSite(Spec):
    """Where the Level I cross-coupling acts: a node of a shaft (``"mid_span"``: the node
    nearest the middle of the shaft's bearing span), with its share ``weight`` of Q."""

    shaft: str
    node: Int | Literal["mid_span"]
    weight: Dimensionless = 1.0

    @field_validator("node")
    @classmethod
    def _node(cls, v):
        if isinstance(v, int) and v < 0:
            raise ValueError("expected a node index >= 0 or 'mid_span'")
        return v

    @field_validator("weight")
    @classmethod
    def _weight(cls, v):
        return _positive(v, "weight")


class AuditStage(Spec):
    """One impeller or blade row of the anticipated cross-coupling formula."""

    shaft: str
    node: Int = Field(ge=0)
    power: Power
    diameter: Length
    height: Length
    density_ratio: Dimensionless = 1.0
    kind: Literal["centrifugal", "axial"] = "centrifugal"

    @field_validator("power", "diameter", "height", "density_ratio")
    @classmethod
    def _pos(cls, v, info):
        return _positive(v, info.field_name.replace("_", " "))


class AuditClearance(Spec):
    """A close running clearance (seal, bearing, impeller eye) for the API 617 9th edition's
    close-clearance check: its node and its minimum diametral clearance."""

    shaft: str
    node: Int = Field(ge=0)
    diametral: Length
    name: str = ""

    @field_validator("diametral")
    @classmethod
    def _gap(cls, v):
        return _positive(v, "diametral clearance")


class ApiAudit(Spec):
    """The Level I inputs (see the module docstring), and the close clearances of the 9th
    edition's close-clearance check (``clearances``, used by ``gearrotor unbalance --api
    --edition 9th`` when no ``--clearance`` is given)."""

    edition: str = "8th"
    qa: Stiffness | None = None
    at: list[AuditSite] = Field(default_factory=list)
    stages: list[AuditStage] = Field(default_factory=list)
    operating_speed: AngularSpeed | None = None
    average_density: Density | None = None
    suction_density: Density | None = None
    discharge_density: Density | None = None
    exclude_bearings: list[str] = Field(default_factory=list)
    clearances: list[AuditClearance] = Field(default_factory=list)

    @model_serializer(mode="wrap")
    def _without_empty_clearances(self, handler):
        # a table without clearances serialises as before the field existed (model JSON of
        # existing models, study case keys and checkpoint fingerprints kept)
        out = handler(self)
        if not self.clearances:
            out.pop("clearances", None)
        return out

    @field_validator("edition")
    @classmethod
    def _edition(cls, v):
        if str(v).strip().lower() not in {e.lower() for e in EDITIONS}:
            raise ValueError(
                "expected '8th' (API 617 8th edition, 2014) or '9th' (API 617 9th edition, 2022)"
            )
        return v

    @field_validator("qa")
    @classmethod
    def _pos(cls, v, info):
        return _positive(v, info.field_name.replace("_", " "))

    @field_validator("average_density", "suction_density", "discharge_density")
    @classmethod
    def _density(cls, v, info):
        return gas_density(v, info.field_name.replace("_", " "))

    @field_validator("operating_speed")
    @classmethod
    def _speed(cls, v):
        return None if v is None else _positive(abs(v), "operating speed")

    @model_validator(mode="after")
    def _consistent(self) -> ApiAudit:
        if (self.qa is None) == (not self.stages):
            raise ValueError(
                "give the anticipated cross-coupling either as qa (N/m) or as [[api_audit.stages]]"
                ", one of the two"
            )
        if self.qa is not None and not self.at:
            raise ValueError("qa given directly needs 'at', the nodes where it acts")
        pair = (self.suction_density, self.discharge_density)
        if (pair[0] is None) != (pair[1] is None):
            raise ValueError("give both suction_density and discharge_density, or neither")
        if self.average_density is not None and pair[0] is not None:
            raise ValueError("give average_density or suction/discharge densities, not both")
        return self

    @property
    def density(self) -> float | None:
        """kg/m³, the average gas density of the screening chart (None: not given)."""
        if self.average_density is not None:
            return self.average_density
        if self.suction_density is not None:
            return 0.5 * (self.suction_density + self.discharge_density)
        return None

    def check(self, train) -> None:
        """Cross-references against the train: shafts, nodes, excluded bearings."""
        for k, s in enumerate(self.at):
            if s.node == "mid_span":
                train.shaft_index(s.shaft, f"api_audit.at[{k}].shaft")
            else:
                train.node_index(NodeRef(shaft=s.shaft, node=s.node), f"api_audit.at[{k}]")
        for k, st in enumerate(self.stages):
            train.node_index(NodeRef(shaft=st.shaft, node=st.node), f"api_audit.stages[{k}]")
        for k, c in enumerate(self.clearances):
            train.node_index(NodeRef(shaft=c.shaft, node=c.node), f"api_audit.clearances[{k}]")
        names = [b.name or f"bearings[{k}]" for k, b in enumerate(train.bearings)]
        names += [sl.name or f"seals[{k}]" for k, sl in enumerate(train.seals)]
        for k, e in enumerate(self.exclude_bearings):
            if e not in names:
                raise ModelError(
                    "no such bearing or seal to exclude",
                    field=f"api_audit.exclude_bearings[{k}]",
                    value=e,
                    expected=f"one of {names}",
                )
