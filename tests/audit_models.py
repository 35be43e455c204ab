"""Small model files for the audit command tests (TOML text: the commands read files)."""

from __future__ import annotations

import numpy as np

RPM = np.pi / 30
# the Jeffcott rotor of test_stability.py: a stubby, practically rigid steel shaft (mass m) on
# two isotropic bearings k, c; its cylindrical mode is m z'' + 2c z' + 2k z - i q z = 0 and
# loses stability at q = 2 c ω_n, ω_n = sqrt(2k/m)
RHO, L, D = 7850.0, 0.3, 0.2
KB, CB = 1e6, 400.0
MASS = RHO * np.pi * D**2 / 4 * L
WN = np.sqrt(2 * KB / MASS)
Q_ONSET = 2 * CB * WN


def jeffcott_toml(
    extra: str = "", mcs_rpm: float | None = 2865.0, speed_rpm: float = 2865.0, top: str = ""
):
    """The Jeffcott rotor's model file; ``top``: top-level keys, ``extra``: tables."""
    mcs = f'max_continuous_speed = "{mcs_rpm} rpm"\n' if mcs_rpm is not None else ""
    mcs += top
    return f'''name = "jeffcott"
speed = "{speed_rpm} rpm"
{mcs}
[materials.steel]
E = 211e9
density = {RHO}
poisson = 0.3

[[shafts]]
name = "s"
material = "steel"
sections = [{{ length = {L}, outer_diameter = {D}, elements = 4 }}]

[[bearings]]
name = "A"
shaft = "s"
node = 0
k = {KB}
c = {CB}

[[bearings]]
name = "B"
shaft = "s"
node = 4
k = {KB}
c = {CB}
{extra}'''


def uniform_toml(
    k: float = 1e7, length: float = 1.0, diameter: float = 0.05, n: int = 10, extra: str = ""
) -> str:
    """A uniform steel shaft on two equal isotropic springs (the map's closed-form case)."""
    return f"""name = "uniform"
speed = "3000 rpm"
operating_speed_range = ["2700 rpm", "3000 rpm"]
max_continuous_speed = "3150 rpm"

[materials.steel]
E = 211e9
density = 7850.0
poisson = 0.3

[[shafts]]
name = "s"
material = "steel"
sections = [{{ length = {length}, outer_diameter = {diameter}, elements = {n} }}]

[[bearings]]
name = "A"
shaft = "s"
node = 0
k = {k}

[[bearings]]
name = "B"
shaft = "s"
node = {n}
k = {k}
{extra}"""
