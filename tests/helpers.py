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


def rotor_toml(*, speed: float = 6000, elements: int = 6, disk_node: int = 3) -> str:
    """A model file's rotor without bearings (they follow): a 0.8 m steel shaft of 100 mm in
    ``elements`` elements with a 60 kg disk at ``disk_node``, at ``speed`` rpm; the rotor of the
    tilting-pad tests (``tests/pads/pad_models.py``) and of the whirl-table input tests."""
    return f"""
speed = "{speed} rpm"
[materials.steel]
E = "206 GPa"
poisson = 0.3
density = "7850 kg/m^3"
[[shafts]]
name = "rotor"
material = "steel"
sections = [{{ length = "0.8 m", outer_diameter = "0.1 m", elements = {elements} }}]
disks = [{{ node = {disk_node}, mass = "60 kg", polar = "1.2 kg*m^2", transverse = "0.7 kg*m^2" }}]
"""
