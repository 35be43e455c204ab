"""Analyses: free functions over a train (or its assembly) returning frozen result objects."""

from .campbell import CampbellResult, ExcitationOrder, campbell, default_orders
from .modal import ModalResult, modal
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
    "ModalResult",
    "UnbalanceResult",
    "api617_required_margin",
    "api617_unbalance",
    "api617_vibration_limit",
    "campbell",
    "default_orders",
    "modal",
    "unbalance_response",
]
