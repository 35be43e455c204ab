"""A tilting-pad journal bearing with its pad degrees of freedom (issue 24).

The bearing's coordinates, in the order of its full matrices (``PadTable.dofs``)::

    u = [x, y, p_1, …, p_m]

x, y: the journal relative to the bearing housing (ground or a pedestal), m; p: per pad its tilt
δ (rad) and, when its pivot is flexible, the outward radial displacement ξ (m) of the pivot
(``tilt_1, radial_1, tilt_2, …``). The film (and the pivot springs) act as
``f = −K u − C u̇`` with K, C the *full* film coefficients about the bearing's equilibrium
(:class:`gearrotor.bearings.Coefficients` ``K_full``/``C_full``); the pads have the inertia M
(the tilt inertia about the pivot, the pad mass on ξ; nothing on x, y). The pad coordinates are
relative to the housing: the inertia forces the housing's own acceleration puts on the pads are
left out, as in the reduced coefficients (a pad's mass is small against a pedestal's).

Condensing the pads at the Laplace variable s (Lund's pad assembly method, 1964)::

    Z(s) = K + s C + s² M,   Z_r(s) = Z_jj − Z_jp Z_pp⁻¹ Z_pj,

gives the journal impedance the pads present at s; at s = iω, ``K_r = Re Z_r`` and
``C_r = Im Z_r / ω`` are the reduced coefficients at whirl frequency ω, the synchronously
reduced ones at ω = |Ω| (the shaft speed). A train that carries the pad DOFs is therefore
exactly the reduced model at every frequency at once: its forced response at ω equals that of
the model with the coefficients reduced at ω, and its eigenvalues λ are the roots of the rotor's
impedance with Z_r(λ) (``tests/bearings/test_pad_dynamics.py``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from .bearing import CoefficientTable

__all__ = ["PadTable", "PadBearing", "condense"]


def condense(K: NDArray, C: NDArray, M: NDArray, s: complex) -> NDArray:
    """Journal impedance Z_r(s) (2, 2, complex) of full matrices (n, n) over [x, y, pads]:
    ``Z = K + sC + s²M``, ``Z_r = Z_jj − Z_jp Z_pp⁻¹ Z_pj`` (the module docstring)."""
    Z = np.asarray(K, complex) + s * np.asarray(C, complex) + s * s * np.asarray(M, complex)
    if Z.shape[0] == 2:
        return Z
    return Z[:2, :2] - Z[:2, 2:] @ np.linalg.solve(Z[2:, 2:], Z[2:, :2])


def _interp(speed: NDArray, values: NDArray, w: float) -> NDArray:
    """Values (n_s, …) linearly interpolated at w (held beyond the ends)."""
    if len(speed) == 1 or w <= speed[0]:
        return values[0].copy()
    if w >= speed[-1]:
        return values[-1].copy()
    i = int(np.searchsorted(speed, w)) - 1
    t = (w - speed[i]) / (speed[i + 1] - speed[i])
    return (1.0 - t) * values[i] + t * values[i + 1]


@dataclass(frozen=True)
class PadTable:
    """Full coefficients of a tilting-pad bearing tabulated against shaft speed.

    speed : (n_s,) rad/s, strictly increasing (|shaft speed|); K, C : (n_s, n, n) full film
    stiffness (N/m, N/rad, N·m/rad, …; pivot springs included) and damping over ``dofs``;
    M : (n, n) the pads' inertia (kg·m² on tilts, kg on radial DOFs, 0 on x, y); dofs : the
    names of the coordinates (``x, y, tilt_1, radial_1?, …``); lever : (n,) a length per
    coordinate that turns it into a displacement (1 for x, y and ξ; R + t for a tilt: the
    pad's surface motion), used to scale mode shapes. Between speeds the full matrices are
    interpolated linearly; beyond the table :meth:`at` raises unless ``extrapolate="hold"``.
    """

    speed: NDArray
    K: NDArray
    C: NDArray
    M: NDArray
    dofs: tuple[str, ...]
    lever: NDArray
    extrapolate: str = "error"

    def __post_init__(self) -> None:
        n = len(self.dofs)
        ns = len(self.speed)
        for name, shape in (("K", (ns, n, n)), ("C", (ns, n, n)), ("M", (n, n)), ("lever", (n,))):
            if np.shape(getattr(self, name)) != shape:
                raise ValueError(f"PadTable.{name} must have shape {shape}")
        if ns > 1 and np.any(np.diff(self.speed) <= 0):
            raise ValueError("PadTable.speed must be strictly increasing")

    @property
    def n(self) -> int:
        """Number of coordinates (2 + pad DOFs)."""
        return len(self.dofs)

    def at(self, speed: float) -> tuple[NDArray, NDArray]:
        """Full (K, C) at shaft speed ``speed`` (rad/s, its sign ignored)."""
        w = abs(speed)
        s = self.speed
        if self.extrapolate != "hold" and len(s) > 1 and not (s[0] - 1e-9 <= w <= s[-1] + 1e-9):
            from ..errors import ModelError

            raise ModelError(
                "speed outside the bearing coefficient table",
                value=f"{w * 30 / np.pi:.6g} rpm",
                expected=f"a speed within {s[0] * 30 / np.pi:.6g}..{s[-1] * 30 / np.pi:.6g} rpm "
                '(extend the table or set extrapolate = "hold")',
            )
        return _interp(s, self.K, w), _interp(s, self.C, w)

    def reduced(self, speed: float, whirl: float) -> tuple[NDArray, NDArray]:
        """Journal (K, C) (2, 2) at shaft speed ``speed`` condensed at whirl frequency ``whirl``
        (rad/s): ``K = Re Z_r(iω)``, ``C = Im Z_r(iω)/ω``."""
        k, c = self.at(speed)
        w = abs(whirl)
        if w == 0.0:  # the static limit: Z_r(0) = K_r, and C_r as the derivative at 0
            w = 1e-9 * max(abs(speed), 1.0)
        z = condense(k, c, self.M, 1j * w)
        return z.real.copy(), z.imag / w


@dataclass(frozen=True)
class PadBearing:
    """A radial bearing that carries its pads' DOFs into the train (module docstring).

    It answers as a :class:`~gearrotor.elements.RadialBearing` for what needs the journal's
    eight coefficients (static loads, bearing plots, critical speed maps, exports): ``K(speed)``
    and ``C(speed)`` are the synchronously reduced coefficients, condensed from the same full
    matrices at whirl = |speed|; ``table`` holds them at the table's speeds. The assembly scatters
    :meth:`K_full`, :meth:`C_full` and :attr:`M_full` on the journal, housing and pad DOFs.
    """

    pads: PadTable
    table: CoefficientTable = field(compare=False)

    @classmethod
    def from_pads(cls, pads: PadTable) -> PadBearing:
        """The element, with its synchronous table condensed at each tabulated speed."""
        vals = []
        for w in pads.speed:
            k, c = pads.reduced(w, w)
            vals.append([*k.ravel(), *c.ravel()])
        return cls(pads, CoefficientTable(np.asarray(pads.speed), np.array(vals), pads.extrapolate))

    @property
    def speed_dependent(self) -> bool:
        return True

    @property
    def n_pad_dofs(self) -> int:
        return self.pads.n - 2

    def coefficients(self, speed: float = 0.0) -> NDArray:
        """The 8 synchronously reduced coefficients at a shaft speed (rad/s)."""
        k, c = self.pads.reduced(speed, speed)
        return np.concatenate([k.ravel(), c.ravel()])

    def K(self, speed: float = 0.0) -> NDArray:
        return self.pads.reduced(speed, speed)[0]

    def C(self, speed: float = 0.0) -> NDArray:
        return self.pads.reduced(speed, speed)[1]

    def K_full(self, speed: float) -> NDArray:
        return self.pads.at(speed)[0]

    def C_full(self, speed: float) -> NDArray:
        return self.pads.at(speed)[1]

    @property
    def M_full(self) -> NDArray:
        return self.pads.M
