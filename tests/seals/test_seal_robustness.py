"""The seal solvers over a seeded random sample of valid inputs (clearances 0.05-1 mm, 1-60
teeth, pressure ratios 0.01-0.99, speeds to 3000 rad/s, viscous oils to light gases): every case
solves (or, for an annular gas seal whose exit would choke, is the documented input error),
gives finite coefficients, and leaks more when the outlet pressure is lower."""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.errors import ModelError
from gearrotor.seals import AnnularSeal, IdealGas, LabyrinthSeal, Liquid, seal_coefficients

RNG_SEED = 20261127


def _labyrinths(n):
    rng = np.random.default_rng(RNG_SEED)
    out = []
    while len(out) < n:
        p_in = 10 ** rng.uniform(5, 7.5)
        seal = LabyrinthSeal(
            rng.uniform(0.03, 0.5),
            rng.uniform(0.05e-3, 1e-3),
            int(rng.integers(1, 60)),
            rng.uniform(2e-3, 8e-3),
            rng.uniform(1e-3, 8e-3),
            rng.uniform(0, 0.5e-3),
            str(rng.choice(["stator", "rotor", "interlocking"])),
            p_in,
            p_in * 10 ** rng.uniform(-2, -0.005),
            300.0,
            rng.uniform(-1, 1.5),
            IdealGas(rng.uniform(2, 60), rng.uniform(1.1, 1.67), 1.8e-5, 300.0),
        )
        if (seal.pitch - seal.tooth_width) / seal.radial_clearance > 1.3:
            out.append((seal, rng.uniform(0, 3000)))
    return out


def _annular(n):
    rng = np.random.default_rng(RNG_SEED + 1)
    out = []
    for k in range(n):
        liquid = k % 2 == 0
        fluid = (
            Liquid(rng.uniform(600, 1000), 10 ** rng.uniform(-4, -1))
            if liquid
            else IdealGas(rng.uniform(2, 60), rng.uniform(1.1, 1.67), 1.8e-5, 300.0)
        )
        p_in = 10 ** rng.uniform(5.5, 7.5)
        seal = AnnularSeal(
            "liquid_annular" if liquid else "hole_pattern",
            rng.uniform(0.05, 0.4),
            rng.uniform(0.05e-3, 0.6e-3),
            rng.uniform(0.01, 0.2),
            p_in,
            p_in * (rng.uniform(0.05, 0.95) if liquid else rng.uniform(0.5, 0.95)),
            rng.uniform(-0.5, 1.0),
            fluid,
            entrance_loss=rng.uniform(0, 1),
            cell_depth=0.0 if liquid else rng.uniform(0, 4e-3),
            hole_area_ratio=0.0 if liquid else rng.uniform(0, 1),
        )
        out.append((seal, rng.uniform(0, 3000)))
    return out


@pytest.mark.parametrize(("seal", "speed"), _labyrinths(16) + _annular(12))
def test_random_valid_inputs_solve(seal, speed):
    from dataclasses import replace

    try:
        r = seal_coefficients(seal, speed, 0.7 * speed + 10.0)
    except ModelError as exc:  # only a choked annular gas seal may refuse
        assert isinstance(seal, AnnularSeal) and seal.fluid.compressible, exc
        assert "chokes at the seal exit" in str(exc)
        return
    assert np.all(np.isfinite(r.coefficients)) and r.leakage > 0
    try:
        r2 = seal_coefficients(replace(seal, outlet_pressure=0.9 * seal.outlet_pressure), speed)
    except ModelError as exc:  # the lower outlet pressure chokes an annular gas seal
        assert "chokes at the seal exit" in str(exc)
        return
    # a choked last tooth passes the same flux at the lower outlet pressure
    assert r2.leakage >= r.leakage * (1 - 1e-9)
