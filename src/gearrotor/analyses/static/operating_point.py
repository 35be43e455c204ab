"""A train at an operating point: its fluid-film bearings carry the coefficients at the static
loads the operating point puts on them, and its meshes are loaded on the flank the torque
loads (issue 11). Every linear analysis (modal, Campbell, unbalance, floquet, stability, the
report) takes the returned train as it takes any other.

Over a speed sweep the point's ``hold`` (power or torque) is kept: the static solution is
recomputed at every speed, and each fluid-film bearing becomes a coefficient table whose row at
each speed holds the coefficients at that speed's static load (exact at the sweep speeds,
linear in between). Results are cached by value (model, point, speeds), so an analysis that
repeats an operating point, or a study, does not solve the same bearings again.
"""

from __future__ import annotations

import numpy as np

from ...assembly import _film_case, assemble
from ...model import OperatingPoint, Train
from ...progress import report
from .analysis import resolve_operating_point, static

__all__ = ["at_operating_point", "model_at_operating_point"]

_CACHE: dict = {}
_CACHE_SIZE = 64


def at_operating_point(
    train: Train, operating_point: str | OperatingPoint, *, speeds=None, progress=None
) -> Train:
    """The train at an operating point (see the module docstring).

    speeds : reference-shaft speeds (rad/s) the fluid-film coefficients are tabulated at, the
    loads following the speed with the point's ``hold``; default: the point's own speed only,
    a one-row table whose coefficients hold at every speed (an analysis at the operating
    point; pass the sweep's speeds for a sweep). A journal that cannot carry its load at one
    of the speeds is an error naming the speed.

    progress : a :data:`gearrotor.progress.Progress` callback (one static solve per speed,
    then the journals' coefficients)
    """
    from ...bearings import coefficients

    op = resolve_operating_point(train, operating_point)
    key = (
        train.model_dump_json(),
        op.model_dump_json(),
        None if speeds is None else tuple(np.atleast_1d(np.asarray(speeds, float)).tolist()),
    )
    hit = _CACHE.get(key)
    if hit is not None:
        return hit
    asm = assemble(train)
    layout = train.layout()
    w_nom = op.reference_speed(train.speed)
    sense = np.sign(w_nom) or np.sign(train.speed) or 1.0
    films = [k for k, b in enumerate(train.bearings) if b.fluid_film is not None]
    # the reference speeds at which each film bearing is tabulated
    plan: dict[int, list[float]] = {}
    sweep = [w_nom] if speeds is None else np.atleast_1d(np.asarray(speeds, float)).tolist()
    for k in films:
        plan[k] = [sense * abs(w) for w in sweep]
    needed = sorted({w for ws in plan.values() for w in ws}, key=abs)
    results = {}
    for i, w in enumerate(needed):
        report(progress, 0.8 * i / len(needed), f"static solve {i + 1}/{len(needed)}")
        results[w] = static(asm, op, speed=w)
    report(progress, 0.8, "bearing coefficients")
    if not needed:
        results[w_nom] = static(asm, op, speed=w_nom)
    # the flank the static solution loads, as each mesh's driver
    nominal = results.get(w_nom) or results[min(results, key=lambda w: abs(abs(w) - abs(w_nom)))]
    meshes = []
    spin = np.sign(train.speed) or 1.0
    for m, load in zip(train.meshes, nominal.meshes, strict=True):
        si = train.shaft_index(m.gear.shaft, "")
        gear_spin = np.sign(layout.shafts[si].speed_ratio * spin)
        driver = "gear" if gear_spin == -load.flank else "mate"
        meshes.append({**m.model_dump(), "driver": driver})
    bearings = [b.model_dump() for b in train.bearings]
    for k in films:
        spec = train.bearings[k]
        ff = spec.fluid_film
        # the bearing with the model's pad overrides (pad inertia, mass, pivot stiffness)
        case = _film_case(
            ff.file, (ff.pad_inertia, ff.pad_mass, ff.pivot_stiffness), f"bearings[{k}]", False
        )
        si = train.shaft_index(spec.shaft, "")
        ratio = layout.shafts[si].speed_ratio
        if spec.fluid_film.pad_dynamics:
            # pads carried into the train: the film solved again (cached) at each speed's static
            # load, its full coefficients tabulated by the assembly
            loads = {abs(ratio * w): tuple(results[w].journals[k].load) for w in plan[k]}
            speed = sorted(loads)
            ff = {
                **spec.fluid_film.model_dump(),
                "speeds": speed,
                "load": None,
                "loads": [loads[v] for v in speed],
            }
            hold = "hold" if len(speed) == 1 else spec.extrapolate
            bearings[k] = {**bearings[k], "fluid_film": ff, "extrapolate": hold}
            continue
        rows = {}
        for w in plan[k]:
            eq = results[w].journals[k]
            co = coefficients(case.bearing, eq, options=case.options)
            rows[abs(ratio * w)] = [*co.K.ravel(), *co.C.ravel()]
        speed = sorted(rows)
        vals = np.array([rows[s] for s in speed])
        # one speed: the point's coefficients, held at every speed (stated, not a fallback)
        hold = "hold" if len(speed) == 1 else spec.extrapolate
        table = {"speed": speed, "extrapolate": hold}
        for j, name in enumerate(("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")):
            table[name] = vals[:, j].tolist()
        bearings[k] = {**bearings[k], "fluid_film": None, "table": table}
    out = Train.model_validate({**train.model_dump(), "bearings": bearings, "meshes": meshes})
    if len(_CACHE) >= _CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = out
    report(progress, 1.0)
    return out


def model_at_operating_point(
    model, operating_point, speeds=None, progress=None
) -> tuple[Train, float]:
    """For the analyses' ``operating_point=`` keyword: ``(train at the point, the point's
    reference speed)`` of a :class:`Train` or an :class:`~gearrotor.assembly.Assembly`, the
    coefficients tabulated at ``speeds`` (default: the point's own speed)."""
    train = model if isinstance(model, Train) else model.train
    op = train.operating_point(operating_point)
    if isinstance(operating_point, OperatingPoint):
        train.check_operating_point(op)
    w = op.reference_speed(train.speed)
    at = at_operating_point(train, op, speeds=[w] if speeds is None else speeds, progress=progress)
    return at, w
