"""Analyses: free functions over a train (or its assembly) returning frozen result objects.

``modal`` and ``campbell`` are imported with the package (their names are also those of their
modules); the others on first use (PEP 562), so that a command importing one analysis does not
load the rest (the stability audit and the UCS map bring scipy.optimize).
"""

from ..model.speed_range import model_max_continuous_speed, model_operating_range
from .lateral.campbell import CampbellResult, ExcitationOrder, campbell, default_orders
from .lateral.modal import ModalResult, modal

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

_LAZY = {
    **dict.fromkeys(
        ("StabilityAudit", "level1_inputs", "stability_audit"), ".audit.stability_audit"
    ),
    **dict.fromkeys(
        ("Level1Result", "Level2Result", "Site", "Stage", "level1", "level2"), ".audit.stability"
    ),
    **dict.fromkeys(("UCSResult", "rigid_support_criticals", "ucs_map"), ".audit.ucs"),
    **dict.fromkeys(
        (
            "UnbalanceResult",
            "api617_required_margin",
            "api617_unbalance",
            "api617_vibration_limit",
            "unbalance_response",
        ),
        ".lateral.unbalance",
    ),
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
