"""The API 617 unbalance of a train's unbalance planes (used by ``gearrotor unbalance --api`` and
``gearrotor report --api``).

API 617 (8th ed.) asks for the unbalance response to 4× the allowable residual unbalance,
``U = 4 × 6350 W/N`` g·mm per plane, W the journal static load (kg) of the plane and N the maximum
continuous speed (rpm) of its shaft (:func:`~gearrotor.analyses.unbalance.api617_unbalance`).
Here W is the shaft's total translating mass (disks included) shared equally by the unbalance
planes of that shaft, and N follows from the reference-shaft maximum continuous speed and the gear
ratio; phases and nodes are the model's.
"""

from __future__ import annotations

from ..assembly import Assembly, assemble
from ..model import Train
from .operating import model_max_continuous_speed
from .unbalance import api617_unbalance, shaft_masses

__all__ = ["api617_basis", "api617_unbalances"]


def api617_basis(
    model: Train | Assembly, max_continuous_speed: float | None = None
) -> list[tuple[float, float]]:
    """Per unbalance plane of the model, ``(W, N)``: journal static load (kg; the shaft's mass
    shared by its unbalance planes) and the maximum continuous speed of its shaft (rad/s, > 0),
    for a reference-shaft maximum continuous speed ``max_continuous_speed`` (rad/s; default: the
    model's ``max_continuous_speed``)."""
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    if max_continuous_speed is None:
        max_continuous_speed = model_max_continuous_speed(train, "the API 617 unbalance")
    masses = shaft_masses(asm)
    planes: dict[str, int] = {}
    for u in train.unbalances:
        planes[u.shaft] = planes.get(u.shaft, 0) + 1
    out = []
    for k, u in enumerate(train.unbalances):
        si = train.shaft_index(u.shaft, f"unbalances[{k}].shaft")
        out.append(
            (
                float(masses[si] / planes[u.shaft]),
                float(abs(asm.speed_ratio[si] * max_continuous_speed)),
            )
        )
    return out


def api617_unbalances(
    model: Train | Assembly, max_continuous_speed: float | None = None, *, factor: float = 4.0
) -> list:
    """The model's unbalances with their amounts replaced by the API 617 amounts (kg·m).

    Parameters
    ----------
    model : the train (or its assembly); its ``unbalances`` give the planes and phases
    max_continuous_speed : rad/s, of the reference shaft (sign ignored); default: the model's
    factor : multiple of the allowable residual unbalance 6350 W/N g·mm (API 617: 4)

    Returns
    -------
    list of :class:`~gearrotor.model.Unbalance`, in the model's order.
    """
    asm = model if isinstance(model, Assembly) else assemble(model)
    basis = api617_basis(asm, max_continuous_speed)
    return [
        u.model_copy(update={"amount": api617_unbalance(w, n, factor=factor)})
        for u, (w, n) in zip(asm.train.unbalances, basis, strict=True)
    ]
