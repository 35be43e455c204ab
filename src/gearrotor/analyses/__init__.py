"""Analyses: free functions over a train (or its assembly) returning frozen result objects."""

from .audit import StabilityAudit, level1_inputs, stability_audit
from .campbell import CampbellResult, ExcitationOrder, campbell, default_orders
from .modal import ModalResult, modal
from .operating import model_max_continuous_speed, model_operating_range
from .stability import Level1Result, Level2Result, Site, Stage, level1, level2
from .ucs import UCSResult, rigid_support_criticals, ucs_map
from .unbalance import (
    UnbalanceResult,
    api617_required_margin,
    api617_unbalance,
    api617_vibration_limit,
    unbalance_response,
)

__all__ = [
    "CampbellResult",
    "ExcitationOrder",
    "Level1Result",
    "Level2Result",
    "ModalResult",
    "Site",
    "Stage",
    "StabilityAudit",
    "UCSResult",
    "UnbalanceResult",
    "api617_required_margin",
    "api617_unbalance",
    "api617_vibration_limit",
    "campbell",
    "default_orders",
    "level1",
    "level1_inputs",
    "level2",
    "modal",
    "model_max_continuous_speed",
    "model_operating_range",
    "rigid_support_criticals",
    "stability_audit",
    "ucs_map",
    "unbalance_response",
]
