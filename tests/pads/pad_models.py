"""Small models with tilting-pad bearings for the pad-dynamics tests (issue 24)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gearrotor.io import load_model
from gearrotor.model import Train
from helpers import rotor_toml

#: 4 pads, load between pads, D = 100 mm, L = 50 mm, pads of 0.4 kg and 2e-4 kg*m^2: a coarse
#: grid keeps each film solve ~ms (its header says more)
BEARING = Path(__file__).resolve().parents[2] / "examples" / "bearings" / "tilting_4pad_pads.toml"
INERTIA = 'pad_inertia = "2e-4 kg*m^2"'  # the file's pad inertia

#: two identical tilting-pad bearings under the rotor of :func:`helpers.rotor_toml` (a 0.8 m
#: shaft with a 60 kg disk), unbalanced
BEARINGS = """[[bearings]]
name = "left"
shaft = "rotor"
node = 0
fluid_film.file = "pad.toml"
fluid_film.speeds = ["3000 rpm", "6000 rpm", "9000 rpm"]
fluid_film.pad_dynamics = {pads}
{extra}
[[bearings]]
name = "right"
shaft = "rotor"
node = 6
fluid_film.file = "pad.toml"
fluid_film.speeds = ["3000 rpm", "6000 rpm", "9000 rpm"]
fluid_film.pad_dynamics = {pads}
{extra}
{unbalance}
[[probes]]
name = "disk"
shaft = "rotor"
node = 3
angle = "0 deg"
"""


UNBALANCE = """[[unbalances]]
shaft = "rotor"
node = 3
amount = "500 g*mm"
"""


def write(tmp_path, *, speed=6000, pads=True, inertia=2e-4, extra="", unbalance=True) -> Train:
    """The model (in ``tmp_path``, its bearing file copied there as ``pad.toml``) with pad
    dynamics on or off; ``inertia``: the pads' inertia in the bearing file (kg*m^2);
    ``extra``: more ``fluid_film.*`` lines of both bearings (the model's pad overrides)."""
    text = BEARING.read_text(encoding="utf-8")
    assert text.count(INERTIA) == 1, INERTIA
    (tmp_path / "pad.toml").write_text(text.replace(INERTIA, f'pad_inertia = "{inertia} kg*m^2"'))
    p = tmp_path / "m.toml"
    p.write_text(
        rotor_toml(speed=speed)
        + BEARINGS.format(
            pads=str(pads).lower(),
            extra=extra,
            unbalance=UNBALANCE if unbalance else "",
        )
    )
    return load_model(p)


def reduced_at(train: Train, asm, whirl: float) -> Train:
    """The same train with every pad-dynamics bearing replaced by constant coefficients: its
    pad model condensed at ``whirl`` (rad/s) at the model's speed."""
    data = train.model_dump()
    bearings = []
    for b, info in zip(data["bearings"], asm.bearings, strict=True):
        speed = abs(asm.shaft_speeds(train.speed)[info.shaft])
        k, c = info.element.pads.reduced(speed, whirl)
        # a one-row table held at every speed (constants may not have a negative direct
        # stiffness, which the pads' reduction gives at high whirl frequencies)
        table = {"speed": [speed], "extrapolate": "hold"}
        for i, n in enumerate(("xx", "xy", "yx", "yy")):
            table["k" + n] = [float(k.ravel()[i])]
            table["c" + n] = [float(c.ravel()[i])]
        bearings.append({**b, "fluid_film": None, "table": table})
    data["bearings"] = bearings
    return Train.model_validate(data)


def rotor_impedance(asm, s: complex, speed: float) -> np.ndarray:
    """Impedance of the shafts' DOFs at Laplace variable s with every pad bearing condensed at s
    (``Z_r(s)``, Lund's pad assembly): the characteristic matrix whose singularity gives the pad
    model's eigenvalues."""
    from gearrotor.elements import condense

    M, C, G, K = asm.matrices(speed)
    Z = (s * s * M + s * (C + G) + K).toarray().astype(complex)
    keep = np.setdiff1d(np.arange(asm.n_dof), asm.pad_dofs)
    for b in asm.bearings:  # remove the pad model's own scatter, add the condensed one
        if b.pad_dofs is None:
            continue
        d, T = b.local()
        w = asm.shaft_speeds(speed)[b.shaft]
        kf, cf = b.element.pads.at(w)
        mf = b.element.pads.M
        Z[np.ix_(d, d)] -= T.T @ (kf + s * cf + s * s * mf) @ T
        zr = condense(kf, cf, mf, s)
        jd = d[: len(d) - len(b.pad_dofs)]
        Tj = T[:2, : len(jd)]
        Z[np.ix_(jd, jd)] += Tj.T @ zr @ Tj
    return Z[np.ix_(keep, keep)], keep
