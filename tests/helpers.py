"""Small model builders shared by the tests."""

from __future__ import annotations

from gearrotor.model import Train


def single_shaft(
    *,
    length=1.0,
    diameter=0.05,
    elements=20,
    E=211e9,
    density=7850.0,
    poisson=0.3,
    bearings=(),
    disks=(),
    speed=0.0,
    **extra,
) -> Train:
    data = {
        "name": "test",
        "speed": speed,
        "materials": {"steel": {"E": E, "density": density, "poisson": poisson}},
        "shafts": [
            {
                "name": "s",
                "material": "steel",
                "sections": [{"length": length, "outer_diameter": diameter, "elements": elements}],
                "disks": list(disks),
            }
        ],
        "bearings": [dict(b, shaft="s") for b in bearings],
    }
    data.update(extra)
    return Train.model_validate(data)
