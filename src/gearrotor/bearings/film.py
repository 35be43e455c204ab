"""Bearing-level film forces: all pads of a bearing at one journal (and pad) state.

Generalised coordinates of a bearing (all in metres, "lever" form for pad tilts)::

    u = [x, y, a_1, ξ_1?, a_2, ξ_2?, ...]

x, y: journal centre displacement; a_k = δ_k (R + t_k): tilt δ_k (rad) of tilting pad k times
its lever; ξ_k: outward radial displacement of pad k's pivot (only for a flexible pivot).
Fixed-geometry bearings have only x, y. The generalised forces are ``∫ p ∂h/∂u dA`` (the film
reaction on the journal for x, y; the pad tilt force, times the lever = pad moment; the radial
pad force) plus the pivot spring force ``−k_p ξ`` on ξ.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from .geometry import Bearing, FixedBearing, TiltingPadBearing
from .reynolds import (
    Cavitation,
    FilmContact,
    Grid,
    PadFilm,
    WorkCounter,
    pad_mesh,
    solve_pad,
)

if TYPE_CHECKING:
    from .thermal import ThermalModel

__all__ = ["SolverOptions", "BearingFilm", "film_state", "dof_names"]


@dataclass(frozen=True)
class SolverOptions:
    """Numerical options of the bearing solvers.

    Attributes
    ----------
    grid
        Finite-volume grid of every pad.
    cavitation
        ``"swift_stieber"`` (default), ``"half_sommerfeld"`` or ``"none"``.
    tol
        Equilibrium tolerance: force residual ≤ tol · max(|W|, μ|ω|R³L/c² · 1e-3).
    max_iter
        Newton iterations per equilibrium attempt.
    perturbation
        Displacement perturbation for the coefficients, as a fraction of the clearance
        (reduced near contact to a fraction of the minimum film); the velocity perturbation is
        ``0.1 · perturbation · c · |ω|``. 1 % of c spans several nodes' cavitation switches, which
        smooths the piecewise-smooth force map of the discrete Swift–Stieber film; the central
        difference truncation error stays ~1e-4.
    thermal
        A thermal model (:class:`~gearrotor.bearings.thermal.ThermalModel`: effective
        temperature or THD, with the lubricant and supply temperature); None (default) is the
        isoviscous film at the bearing's ``viscosity``. With a thermal model the equilibrium
        iterates film and temperatures to a consistent state, and the coefficients are taken
        at its viscosity field.
    """

    grid: Grid = field(default_factory=Grid)
    cavitation: Cavitation = "swift_stieber"
    tol: float = 1e-9
    max_iter: int = 40
    perturbation: float = 1e-2
    thermal: ThermalModel | None = None

    def __post_init__(self) -> None:
        if self.cavitation not in ("swift_stieber", "half_sommerfeld", "none"):
            raise ModelError(
                "unknown cavitation model",
                field="cavitation",
                value=self.cavitation,
                expected="'swift_stieber', 'half_sommerfeld' or 'none'",
            )
        if not 0 < self.perturbation < 0.1:
            raise ModelError(
                "perturbation out of range",
                field="perturbation",
                value=self.perturbation,
                expected="0 < perturbation < 0.1",
            )


@dataclass(frozen=True)
class _PadSlot:
    """Where one pad's local coordinates (x, y, a, ξ) sit in the bearing's u (internal)."""

    index: tuple[int, int, int, int]  # −1 when the local coordinate is absent
    lever: float  # R + t (m) for tilting pads, 1 for fixed pads
    pivot_stiffness: float  # N/m (0 when rigid or fixed)


def _slots(bearing: Bearing) -> tuple[_PadSlot, ...]:
    if isinstance(bearing, FixedBearing):
        return tuple(_PadSlot((0, 1, -1, -1), 1.0, 0.0) for _ in bearing.pads)
    slots, k = [], 2
    for pad in bearing.pads:
        tilt = k
        k += 1
        radial = -1
        if pad.pivot_stiffness is not None:
            radial = k
            k += 1
        slots.append(
            _PadSlot(
                (0, 1, tilt, radial), bearing.radius + pad.thickness, pad.pivot_stiffness or 0.0
            )
        )
    return tuple(slots)


def n_dofs(bearing: Bearing) -> int:
    """Number of generalised coordinates (2 + pad DOFs)."""
    return 2 + (bearing.n_pad_dofs if isinstance(bearing, TiltingPadBearing) else 0)


def dof_names(bearing: Bearing) -> list[str]:
    """Names of the generalised coordinates: x, y, tilt_1, radial_1, …"""
    names = ["x", "y"]
    if isinstance(bearing, TiltingPadBearing):
        for k, pad in enumerate(bearing.pads, start=1):
            names.append(f"tilt_{k}")
            if pad.pivot_stiffness is not None:
                names.append(f"radial_{k}")
    return names


@dataclass(frozen=True)
class BearingFilm:
    """Films of all pads at one state, with the generalised forces.

    Attributes
    ----------
    forces
        Generalised forces on u (N): ``forces[:2]`` = (Fx, Fy), the film reaction on the journal;
        pad entries as in the module docstring (pivot springs included).
    pads
        The :class:`~gearrotor.bearings.reynolds.PadFilm` of every pad.
    """

    forces: NDArray
    pads: tuple[PadFilm, ...]

    @property
    def min_film(self) -> float:
        """Minimum film thickness over all pads (m)."""
        return min(float(p.film.min()) for p in self.pads)

    @property
    def peak_pressure(self) -> float:
        """Peak pressure (Pa)."""
        return max(float(p.pressure.max()) for p in self.pads)

    @property
    def side_flow(self) -> float:
        """Side leakage out of both ends (m³/s)."""
        return sum(p.side_flow for p in self.pads)

    @property
    def friction_power(self) -> float:
        """Viscous power loss (W)."""
        return sum(p.friction_power for p in self.pads)


class _Evaluator:
    """Evaluates pad films at a bearing state, keeping warm-start active sets (internal)."""

    def __init__(self, bearing: Bearing, speed: float, options: SolverOptions) -> None:
        self.bearing = bearing
        self.speed = float(speed)
        self.options = options
        self.slots = _slots(bearing)
        self.n = n_dofs(bearing)
        r, c = bearing.radius, bearing.clearance
        self.meshes = [pad_mesh(p, r, bearing.length, c, options.grid) for p in bearing.pads]
        self.active: list[NDArray | None] = [None] * len(bearing.pads)
        self.work = WorkCounter()
        #: per pad: μ (Pa·s), or a nodal viscosity field (thermal models)
        self.viscosity: list[float | NDArray] = [bearing.viscosity] * len(bearing.pads)

    def local_q(self, k: int, u: NDArray) -> NDArray:
        """Pad k's (X, Y, A, S) divided by the clearance."""
        slot = self.slots[k]
        q = np.zeros(4)
        for loc, glob in enumerate(slot.index):
            if glob >= 0:
                q[loc] = u[glob]
        return q / self.bearing.clearance

    def pad(self, k: int, q: NDArray, qdot: NDArray) -> PadFilm:
        b = self.bearing
        film = solve_pad(
            self.meshes[k],
            q,
            qdot,
            self.speed,
            viscosity=self.viscosity[k],
            radius=b.radius,
            clearance=b.clearance,
            cavitation=self.options.cavitation,
            active=self.active[k],
            work=self.work,
        )
        self.active[k] = film.active
        return film

    def evaluate(self, u: NDArray, udot: NDArray | None = None) -> BearingFilm:
        udot = np.zeros(self.n) if udot is None else udot
        total = np.zeros(self.n)
        films = []
        for k, slot in enumerate(self.slots):
            film = self.pad(k, self.local_q(k, u), self.local_q(k, udot))
            films.append(film)
            for loc, glob in enumerate(slot.index):
                if glob >= 0:
                    total[glob] += film.forces[loc]
            if slot.index[3] >= 0:
                total[slot.index[3]] -= slot.pivot_stiffness * u[slot.index[3]]
        return BearingFilm(total, tuple(films))

    def settle_pads(self, u: NDArray) -> NDArray:
        """Return ``u`` with every tilting pad at its moment equilibrium for the current journal
        position (a bracketed 1-D root find per pad, between the tilts that would close the
        film at the leading and trailing edges; radial pivot DOFs then take Q/k_p).

        Newton from zero tilt is unreliable because a preloaded pad with offset > 0.5 has a
        negative tilt stiffness at zero tilt; its equilibrium is found here instead.
        """
        from scipy.optimize import brentq

        u = u.copy()
        c = self.bearing.clearance
        for k, slot in enumerate(self.slots):
            it, ir = slot.index[2], slot.index[3]
            if it < 0:
                continue
            mesh = self.meshes[k]
            for _ in range(3 if ir >= 0 else 1):
                q = self.local_q(k, u)
                q[2] = 0.0
                h0 = mesh.h0_node + q @ mesh.phi_node
                phi = mesh.phi_node[2]
                margin = 0.02
                with np.errstate(divide="ignore"):
                    hi = np.min(np.where(phi < 0, (h0 - margin) / -phi, np.inf))
                    lo = np.max(np.where(phi > 0, -(h0 - margin) / phi, -np.inf))
                if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
                    continue

                def moment(a, k=k, q=q):
                    qq = q.copy()
                    qq[2] = a
                    return self.pad(k, qq, np.zeros(4)).forces[2]

                # scan from the trailing-edge contact limit down to the first bracket
                # (positive moment below, negative above); a fully diverging film gives a
                # zero-moment plateau that must not be taken for the equilibrium
                grid = np.linspace(hi, lo, 13)
                f_prev = moment(grid[0])
                for a0, a1 in zip(grid[:-1], grid[1:], strict=True):
                    f1 = moment(a1)
                    if f1 > 0 > f_prev:
                        u[it] = brentq(moment, a1, a0, xtol=1e-10, rtol=1e-12) * c
                        break
                    f_prev = f1
                if ir >= 0:
                    q = self.local_q(k, u)
                    u[ir] = self.pad(k, q, np.zeros(4)).forces[3] / slot.pivot_stiffness
        return u

    def jacobians(
        self, u: NDArray, velocity: bool = True, base: BearingFilm | None = None
    ) -> tuple[NDArray, NDArray]:
        """Stiffness and damping matrices K = −∂F/∂u, C = −∂F/∂u̇ by central differences.

        ``base`` is the film at ``u`` when already known. Every perturbed solve starts from the
        base state's cavitated set (deterministic, and the base set is kept afterwards).
        """
        c = self.bearing.clearance
        kmat = np.zeros((self.n, self.n))
        cmat = np.zeros((self.n, self.n))
        if base is None:
            base = self.evaluate(u)
        saved = list(self.active)
        hmin = base.min_film / c
        dx = self.options.perturbation * c * min(1.0, 5.0 * hmin)
        # velocity: a smaller step keeps the cavitated set fixed, so that C keeps the symmetry
        # of the discrete film operator (the force is linear in velocity on a fixed set)
        dv = 0.1 * self.options.perturbation * c * max(abs(self.speed), 1.0)
        zero = np.zeros(4)

        def solve(k: int, q: NDArray, qdot: NDArray) -> NDArray:
            self.active[k] = saved[k]
            return self.pad(k, q, qdot).forces

        for k, slot in enumerate(self.slots):
            q0 = self.local_q(k, u)
            present = [loc for loc, g in enumerate(slot.index) if g >= 0]
            for loc in present:
                e = np.zeros(4)
                e[loc] = 1.0
                step = dx
                for _ in range(4):  # near contact: shrink the step until both sides have a film
                    try:
                        fp = solve(k, q0 + e * step / c, zero)
                        fm = solve(k, q0 - e * step / c, zero)
                        break
                    except FilmContact:
                        step *= 0.1
                else:
                    raise FilmContact("no film left to perturb the journal position in")
                dk = -(fp - fm) / (2 * step)
                if velocity:
                    dc = -(solve(k, q0, e * dv / c) - solve(k, q0, -e * dv / c)) / (2 * dv)
                for row in present:
                    kmat[slot.index[row], slot.index[loc]] += dk[row]
                    if velocity:
                        cmat[slot.index[row], slot.index[loc]] += dc[row]
            if slot.index[3] >= 0:
                kmat[slot.index[3], slot.index[3]] += slot.pivot_stiffness
        self.active = saved
        return kmat, cmat


def film_state(
    bearing: Bearing,
    speed: float,
    x: float = 0.0,
    y: float = 0.0,
    *,
    pad_dofs: NDArray | None = None,
    xdot: float = 0.0,
    ydot: float = 0.0,
    options: SolverOptions | None = None,
) -> BearingFilm:
    """Films and forces of a bearing at a given journal position and velocity.

    Parameters
    ----------
    bearing
        Fixed or tilting-pad bearing.
    speed
        Journal speed (rad/s, signed; positive = counter-clockwise seen from +z).
    x, y
        Journal centre displacement from the bearing centre (m).
    pad_dofs
        Tilting pads: the pad coordinates in :func:`dof_names` order after x, y, with tilts in
        rad and radial pivot displacements in m (default 0).
    xdot, ydot
        Journal velocity (m/s).
    options
        Solver options.
    """
    ev = _Evaluator(bearing, speed, options or SolverOptions())
    u = np.zeros(ev.n)
    u[0], u[1] = x, y
    if pad_dofs is not None:
        u[2:] = _pad_dofs_to_lever(bearing, np.asarray(pad_dofs, dtype=float))
    udot = np.zeros(ev.n)
    udot[0], udot[1] = xdot, ydot
    return ev.evaluate(u, udot)


def _lever_scale(bearing: Bearing) -> NDArray:
    """Per-DOF factor from physical units (m, rad) to lever units (m)."""
    s = [1.0, 1.0]
    if isinstance(bearing, TiltingPadBearing):
        for pad in bearing.pads:
            s.append(bearing.radius + pad.thickness)
            if pad.pivot_stiffness is not None:
                s.append(1.0)
    return np.array(s)


def _pad_dofs_to_lever(bearing: Bearing, pad_dofs: NDArray) -> NDArray:
    return pad_dofs * _lever_scale(bearing)[2:]
