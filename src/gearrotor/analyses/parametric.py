"""Former name of :mod:`gearrotor.analyses.floquet` (parametric stability under the time-varying
mesh stiffness), kept so that existing imports work; "parametric" now names the studies only."""

from .floquet import FloquetResult, floquet

__all__ = ["FloquetResult", "floquet"]
