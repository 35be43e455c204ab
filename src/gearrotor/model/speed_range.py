"""The operating speed range a model states (``operating_speed_range``,
``max_continuous_speed``), as the API 617 checks and the Campbell diagram use it (not an
operating point: :mod:`gearrotor.model.operating_point`)."""

from __future__ import annotations

from ..errors import ModelError
from .train import Train

__all__ = ["model_operating_range", "model_max_continuous_speed"]


def model_operating_range(train: Train) -> tuple[float, float] | None:
    """The API 617 separation-margin bounds of the reference shaft from the model (rad/s):
    ``(minimum operating speed, maximum continuous speed)``. The minimum is the lower bound of
    ``operating_speed_range`` (the MCS when only the MCS is given); the maximum is
    ``max_continuous_speed``, or the upper bound of the range without it. None when the model
    states neither."""
    op, mcs = train.operating_speed_range, train.max_continuous_speed
    if op is None and mcs is None:
        return None
    lo = op[0] if op is not None else mcs
    hi = mcs if mcs is not None else op[1]
    return (float(lo), float(hi))


def model_max_continuous_speed(train: Train, needed_by: str) -> float:
    """The model's maximum continuous speed (rad/s), or a ModelError saying ``needed_by``
    needs it."""
    if train.max_continuous_speed is None:
        raise ModelError(
            f"{needed_by} needs the maximum continuous speed, and the model states none",
            field="max_continuous_speed",
            expected="max_continuous_speed in the model (e.g. max_continuous_speed = "
            "'11340 rpm') or the argument",
        )
    return float(train.max_continuous_speed)
