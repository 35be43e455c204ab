"""Static equilibrium of a journal (and its tilting pads) under a load vector.

The load W = (Fx, Fy) is the external static force applied to the journal (N); equilibrium is
``F_film(u) + W = 0`` on the journal and zero net force on every pad DOF (moment-free pivots,
pivot springs balancing radial pad forces).

Method: Newton on the generalised coordinates u with the Jacobian by central differences of the
film forces (the stiffness matrix), a step limited to a quarter clearance, and a backtracking
line search that also rejects steps into contact (h ≤ 0). When Newton from the bearing centre
fails, the load is applied by continuation (load fraction 0 → 1 with adaptive steps, each
solved by the same Newton from the previous solution). Failure of both raises
:class:`~gearrotor.errors.SolverError` with the residual reached.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError, SolverError
from .film import BearingFilm, SolverOptions, _Evaluator, _lever_scale
from .geometry import Bearing
from .reynolds import FilmContact

if TYPE_CHECKING:
    from .thermal import ThermalResult

__all__ = ["Equilibrium", "equilibrium", "sommerfeld_number"]


@dataclass(frozen=True)
class Equilibrium:
    """Static equilibrium of a bearing.

    Attributes
    ----------
    speed
        Journal speed (rad/s, signed).
    load
        Applied load (Fx, Fy) on the journal (N).
    x, y
        Journal centre position relative to the bearing centre (m).
    pad_dofs
        Tilting pads: pad coordinates after x, y (tilt in rad, radial in m); empty otherwise.
    eccentricity_ratio
        |(x, y)| / c (c = assembled clearance).
    attitude_angle
        Angle from the load direction to the journal displacement, positive in the direction
        of rotation (rad); NaN at zero eccentricity.
    min_film
        Minimum film thickness (m).
    peak_pressure
        Maximum film pressure (Pa).
    friction_power
        Viscous power loss (W), full-film shear on the pads.
    side_flow
        Axial leakage out of both bearing ends (m³/s).
    sommerfeld
        S = μ N L D / W (R/c)², N = |speed|/(2π) in rev/s (inf at zero load).
    film
        The pad films at equilibrium.
    iterations
        Newton iterations (summed over continuation steps).
    film_solves, factorizations
        Work of the film solver.
    status
        ``"converged"`` (Newton) or ``"converged (load continuation)"`` (after the fallback);
        failures raise instead.
    thermal
        With a thermal model (``SolverOptions.thermal``): temperatures, flows, power loss and
        the viscosity field the film was solved with; None for an isoviscous film.
    """

    speed: float
    load: tuple[float, float]
    x: float
    y: float
    pad_dofs: NDArray
    eccentricity_ratio: float
    attitude_angle: float
    min_film: float
    peak_pressure: float
    friction_power: float
    side_flow: float
    sommerfeld: float
    film: BearingFilm
    iterations: int
    film_solves: int
    factorizations: int
    status: str = "converged"
    thermal: ThermalResult | None = None

    @property
    def speed_rpm(self) -> float:
        """Speed in rpm (signed)."""
        return self.speed * 30.0 / math.pi


def sommerfeld_number(bearing: Bearing, load: float, speed: float) -> float:
    """S = μ N L D / W (R/c)² with N = |speed|/2π (rev/s), W = |load| (N)."""
    n = abs(speed) / (2.0 * math.pi)
    r_c = bearing.radius / bearing.clearance
    if load == 0:
        return math.inf
    return bearing.viscosity * n * bearing.length * bearing.diameter / abs(load) * r_c**2


def _check_inputs(load: Sequence[float], speed: float) -> tuple[float, float]:
    try:
        fx, fy = (float(v) for v in load)
    except (TypeError, ValueError):
        raise ModelError(
            "load must be a pair (Fx, Fy)", field="load", value=load, expected="two numbers in N"
        ) from None
    if not (math.isfinite(fx) and math.isfinite(fy)):
        raise ModelError("load must be finite", field="load", value=load, expected="finite N")
    if not (math.isfinite(speed) and speed != 0.0):
        raise ModelError(
            "a hydrodynamic bearing needs a non-zero speed",
            field="speed",
            value=speed,
            expected="a non-zero speed in rad/s",
        )
    return fx, fy


def _newton(
    ev: _Evaluator, u: NDArray, wg: NDArray, ftol: float, max_iter: int
) -> tuple[NDArray, BearingFilm, int]:
    """Damped Newton with backtracking; raises SolverError on failure.

    The stiffness (Jacobian) is recomputed by central differences whenever the last step was
    not a full step that at least halved the residual; otherwise it gets a Broyden rank-one
    update (``K s = −Δr`` for the step just taken), which saves most of the film solves.
    """
    c = ev.bearing.clearance
    film = ev.evaluate(u)
    r = film.forces + wg
    norm = float(np.linalg.norm(r))
    kmat, fresh = None, False
    it = 0
    while it < max_iter:
        if norm <= ftol:
            return u, film, it
        if kmat is None:
            kmat, _ = ev.jacobians(u, velocity=False, base=film)
            fresh = True
        try:
            du = np.linalg.solve(kmat, r)  # r − K du = 0
        except np.linalg.LinAlgError:
            du = np.linalg.lstsq(kmat, r, rcond=None)[0]
        big = float(np.max(np.abs(du)))
        t = min(1.0, 0.25 * c / big) if big > 0 else 1.0
        accepted = False
        while t > 1e-6:
            trial = u + t * du
            try:
                film_t = ev.evaluate(trial)
            except FilmContact:
                t *= 0.5
                continue
            r_t = film_t.forces + wg
            n_t = float(np.linalg.norm(r_t))
            if n_t < (1.0 - 1e-4 * t) * norm:
                accepted = True
                break
            t *= 0.5
        it += 1
        if not accepted:
            if fresh:
                break
            kmat = None  # the updated Jacobian misled the step: take a fresh one
            continue
        if t == 1.0 and n_t < 0.5 * norm:
            step = t * du
            kmat = kmat - np.outer(r_t - r + kmat @ step, step) / (step @ step)
            fresh = False
        else:
            kmat = None
        u, film, r, norm = trial, film_t, r_t, n_t
    if norm <= ftol:
        return u, film, it
    raise SolverError(
        f"equilibrium Newton iteration stalled at residual {norm:.3g} N "
        f"(tolerance {ftol:.3g} N) after {it} iterations"
    )


def equilibrium(
    bearing: Bearing,
    load: Sequence[float],
    speed: float,
    *,
    options: SolverOptions | None = None,
    start: Equilibrium | None = None,
) -> Equilibrium:
    """Static equilibrium of the journal (and pads) under ``load``.

    Parameters
    ----------
    bearing
        Fixed or tilting-pad bearing.
    load
        (Fx, Fy): external static load on the journal (N).
    speed
        Journal speed (rad/s, signed; positive = counter-clockwise seen from +z).
    options
        Solver options (grid, cavitation, tolerances).
    start
        A previous equilibrium to start from (continuation over load or speed).

    Raises
    ------
    SolverError
        No equilibrium found (e.g. the load exceeds the capacity at this speed).
    """
    opts = options or SolverOptions()
    fx, fy = _check_inputs(load, speed)
    ev = _Evaluator(bearing, speed, opts)
    wg = np.zeros(ev.n)
    wg[0], wg[1] = fx, fy
    b = bearing
    fref = 1e-3 * b.viscosity * abs(speed) * b.radius**3 * b.length / b.clearance**2
    ftol = opts.tol * max(math.hypot(fx, fy), fref)
    u0 = np.zeros(ev.n)
    if start is not None and len(start.pad_dofs) == ev.n - 2:
        u0[0], u0[1] = start.x, start.y
        u0[2:] = start.pad_dofs * _lever_scale(bearing)[2:]

    def solve(u_start: NDArray | None) -> tuple[NDArray, BearingFilm, int, str]:
        if u_start is None:
            u_start = u0 if start is not None else ev.settle_pads(u0)
        try:
            return (*_newton(ev, u_start, wg, ftol, opts.max_iter), "converged")
        except SolverError as first:
            res = _continuation(ev, wg, ftol, opts.max_iter, first)
            return (*res, "converged (load continuation)")

    if opts.thermal is None:
        u, film, iterations, status = solve(None)
        return _result(bearing, speed, (fx, fy), u, film, iterations, ev, status)
    from .thermal import solve_thermal

    if start is not None and start.thermal is not None:
        ev.viscosity = list(start.thermal.viscosity)
    u, film, iterations, status, state = solve_thermal(
        ev, solve, opts.thermal, start.thermal if start is not None else None
    )
    return _result(bearing, speed, (fx, fy), u, film, iterations, ev, status, state)


def _continuation(
    ev: _Evaluator, wg: NDArray, ftol: float, max_iter: int, first: SolverError
) -> tuple[NDArray, BearingFilm, int]:
    """Apply the load in adaptive fractions, Newton at each (after direct Newton failed)."""
    u = ev.settle_pads(np.zeros(ev.n))
    lam, step, total = 0.0, 0.25, 0
    film = None
    while lam < 1.0:
        target = min(1.0, lam + step)
        try:
            u_new, film_new, it = _newton(
                ev, u.copy(), wg * target, ftol * max(target, 1e-3), max_iter
            )
        except SolverError:
            step *= 0.5
            if step < 1e-3:
                raise SolverError(
                    f"no equilibrium found: Newton failed ({first}) and load continuation "
                    f"stalled at {100 * lam:.1f} % of the load (|W| = "
                    f"{np.linalg.norm(wg[:2]):.4g} N). The load may exceed the bearing's "
                    "capacity at this speed, or the grid may be too coarse."
                ) from None
            continue
        u, film, lam = u_new, film_new, target
        total += it
        step = min(2.0 * step, 0.5)
    assert film is not None
    return u, film, total


def _result(
    bearing: Bearing,
    speed: float,
    load: tuple[float, float],
    u: NDArray,
    film: BearingFilm,
    iterations: int,
    ev: _Evaluator,
    status: str,
    thermal: ThermalResult | None = None,
) -> Equilibrium:
    x, y = float(u[0]), float(u[1])
    e = math.hypot(x, y)
    w = math.hypot(*load)
    if e > 0 and w > 0:
        phi = math.atan2(y, x) - math.atan2(load[1], load[0])
        phi = math.copysign(1.0, speed) * math.remainder(phi, 2 * math.pi)
    else:
        phi = math.nan
    return Equilibrium(
        speed=float(speed),
        load=load,
        x=x,
        y=y,
        pad_dofs=u[2:] / _lever_scale(bearing)[2:],
        eccentricity_ratio=e / bearing.clearance,
        attitude_angle=phi,
        min_film=film.min_film,
        peak_pressure=film.peak_pressure,
        friction_power=film.friction_power,
        side_flow=film.side_flow,
        sommerfeld=sommerfeld_number(bearing, w, speed),
        film=film,
        iterations=iterations,
        film_solves=ev.work.film_solves,
        factorizations=ev.work.factorizations,
        status=status,
        thermal=thermal,
    )
