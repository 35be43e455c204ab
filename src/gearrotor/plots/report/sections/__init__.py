"""The sections of the report, in page order (and in the order they run and write).

A new analysis adds one module here (a :class:`~gearrotor.plots.report.base.Section` subclass;
see ``docs/architecture.md``) and one line to :data:`SECTIONS`.
"""

from __future__ import annotations

from ..base import Section
from .audit import AuditSection
from .bearings import BearingsSection
from .campbell import CampbellSection
from .mesh_response import MeshResponseSection
from .model import ModelSection
from .modes import ModesSection
from .stability import StabilitySection
from .static import OperatingPointsSection
from .torsional import TorsionalSection
from .transient import TransientSection
from .unbalance import UnbalanceSection

__all__ = ["SECTIONS"]

SECTIONS: tuple[Section, ...] = (
    ModelSection(),
    ModesSection(),
    StabilitySection(),
    CampbellSection(),
    UnbalanceSection(),
    AuditSection(),
    OperatingPointsSection(),
    BearingsSection(),
    TorsionalSection(),
    TransientSection(),
    MeshResponseSection(),
)
