"""A radial bearing or seal whose eight coefficients depend on shaft speed and whirl frequency
(a speed × whirl table, issue 24).

Each row of the table holds the coefficients at one shaft speed over a set of whirl
frequencies ω (rad/s, ≥ 0). Two readings of the same numbers:

* **on the whirl axis** (a harmonic motion at a known frequency): the coefficients
  interpolated linearly in whirl within each row, then linearly in speed between rows
  (:meth:`WhirlBearing.coefficients`). What needs the journal's eight coefficients at a speed
  (the unbalance response, where ω = |Ω|; static loads, critical speed maps, the transient,
  plots, exports) gets the **synchronous** ones: each row's at its own speed (ω = Ω, exact at
  the table's speeds), interpolated linearly in speed like a speed table (:attr:`table`);
* **off the axis** (a damped mode λ = σ + iω of the eigenproblem): each row's impedance
  ``Z(iω) = K(ω) + iω C(ω)`` fitted by a rational function of s
  (:class:`~gearrotor.elements.rational_fit.RationalImpedance`), blended linearly in speed
  between rows, ``Z(Ω, s) = (1 − t) Z_i(s) + t Z_{i+1}(s)`` (the same linear interpolation in
  speed, now for every s); :meth:`WhirlBearing.realization` gives it in state form, whose
  states the modal analysis adds to the rotor's (``gearrotor.analyses.lateral.whirl``).

At a tabulated (speed, whirl) point the two agree to the fit's misfit (at most the model's
``fit_tolerance``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from .bearing import CoefficientTable
from .rational_fit import RationalImpedance, fit_row

__all__ = ["FIT_TOLERANCE", "WhirlRow", "WhirlBearing", "fit_rows"]

#: default largest relative misfit of a table row's rational fit (a model's ``fit_tolerance``)
FIT_TOLERANCE = 1e-4


@dataclass(frozen=True)
class WhirlRow:
    """One shaft speed of a speed × whirl table: speed (rad/s, ≥ 0), whirl (n_w,) rad/s
    increasing, values (n_w, 8) kxx … cyy (N/m, N·s/m), and the rational fit of its
    impedance."""

    speed: float
    whirl: NDArray
    values: NDArray
    fit: RationalImpedance

    def at_whirl(self, whirl: float) -> NDArray:
        """The eight coefficients at whirl frequency ``whirl`` (rad/s), linear in whirl (held
        beyond the row's ends)."""
        w = abs(whirl)
        return np.array([np.interp(w, self.whirl, self.values[:, j]) for j in range(8)])


@dataclass(frozen=True)
class Realization:
    """``Z(s) = D + sE + s²F + C (sI − A)⁻¹ B`` of a whirl-dependent bearing at one speed."""

    D: NDArray
    E: NDArray
    F: NDArray
    A: NDArray
    B: NDArray
    C: NDArray

    @property
    def n_states(self) -> int:
        return self.A.shape[0]

    def at(self, s: complex) -> NDArray:
        z = self.D + s * self.E + s * s * self.F
        if self.n_states:
            z = z + self.C @ np.linalg.solve(s * np.eye(self.n_states) - self.A, self.B)
        return np.asarray(z, complex)


@dataclass(frozen=True)
class WhirlBearing:
    """Radial bearing or seal from a speed × whirl table (module docstring).

    rows : the table's speeds, ascending; extrapolate : ``"error"`` (default) or ``"hold"``
    beyond the speeds. ``table``: the synchronous coefficients (ω = Ω) at the row speeds, which
    code that reads a bearing's table (plots, exports) sees.
    """

    rows: tuple[WhirlRow, ...]
    extrapolate: str = "error"
    table: CoefficientTable = field(init=False, compare=False)

    def __post_init__(self) -> None:
        speed = np.array([r.speed for r in self.rows])
        vals = np.array([r.at_whirl(r.speed) for r in self.rows])
        object.__setattr__(self, "table", CoefficientTable(speed, vals, self.extrapolate))

    @property
    def speed_dependent(self) -> bool:
        return True

    @property
    def whirl_dependent(self) -> bool:
        return True

    @property
    def whirl_range(self) -> tuple[float, float]:
        """(lowest, highest) tabulated whirl frequency over the rows, rad/s."""
        return (
            min(float(r.whirl[0]) for r in self.rows),
            max(float(r.whirl[-1]) for r in self.rows),
        )

    def _weights(self, speed: float) -> list[tuple[float, WhirlRow]]:
        """The rows and their weights at shaft speed ``speed`` (linear in |speed|)."""
        self.table.at(speed)  # the speed-range check (ModelError beyond it unless "hold")
        w = abs(speed)
        s = self.table.speed
        if len(s) == 1 or w <= s[0]:
            return [(1.0, self.rows[0])]
        if w >= s[-1]:
            return [(1.0, self.rows[-1])]
        i = int(np.searchsorted(s, w)) - 1
        t = (w - s[i]) / (s[i + 1] - s[i])
        out = [(1.0 - t, self.rows[i]), (t, self.rows[i + 1])]
        return [(a, r) for a, r in out if a != 0.0]

    def coefficients(self, speed: float = 0.0, whirl: float | None = None) -> NDArray:
        """The eight coefficients at shaft speed ``speed`` (rad/s) and whirl frequency
        ``whirl`` (rad/s): linear in whirl within the rows, then linear in speed. Without
        ``whirl``, the synchronous coefficients: each row's at its own speed (whirl = speed),
        interpolated linearly in speed (:attr:`table`; a speed table of the synchronous values,
        which the transient also interpolates at the instantaneous speed)."""
        if whirl is None:
            return self.table.at(speed)
        om = abs(whirl)
        parts = self._weights(speed)
        out = parts[0][0] * parts[0][1].at_whirl(om)
        for a, r in parts[1:]:
            out = out + a * r.at_whirl(om)
        return out

    def K(self, speed: float = 0.0) -> NDArray:
        c = self.coefficients(speed)
        return np.array([[c[0], c[1]], [c[2], c[3]]])

    def C(self, speed: float = 0.0) -> NDArray:
        c = self.coefficients(speed)
        return np.array([[c[4], c[5]], [c[6], c[7]]])

    def realization(self, speed: float) -> Realization:
        """The fitted impedance at shaft speed ``speed``, blended between rows, in state form
        (the states of both rows between two speeds)."""
        parts = self._weights(speed)
        D = sum(a * r.fit.D for a, r in parts)
        E = sum(a * r.fit.E for a, r in parts)
        F = sum(a * r.fit.F for a, r in parts)
        fits = [(a, r.fit) for a, r in parts if r.fit.n_states]
        m = sum(f.n_states for _, f in fits)
        A, B, C = np.zeros((m, m)), np.zeros((m, 2)), np.zeros((2, m))
        i = 0
        for a, f in fits:
            k = f.n_states
            A[i : i + k, i : i + k] = f.A
            B[i : i + k] = f.B
            C[:, i : i + k] = a * f.C
            i += k
        return Realization(np.asarray(D), np.asarray(E), np.asarray(F), A, B, C)

    def impedance(self, speed: float, s: complex) -> NDArray:
        """Z(Ω, s) (2, 2) complex: the fitted impedance at shaft speed ``speed`` (rad/s)."""
        return self.realization(speed).at(s)


def fit_rows(
    rows, tolerance: float | None = None, *, field: str, file: str | None = None
) -> tuple[WhirlRow, ...]:
    """The rows ``(speed, whirl, values)`` of a speed × whirl table with their fits
    (:func:`~gearrotor.elements.rational_fit.fit_row`, computed once per row); a row whose
    misfit exceeds ``tolerance`` (default :data:`FIT_TOLERANCE`) is a one-line ModelError
    naming ``field`` (and ``file``)."""
    tol = FIT_TOLERANCE if tolerance is None else float(tolerance)
    out = []
    for s, w, v in rows:
        fit, misfit = fit_row(w, v, tol)
        if misfit > tol:
            raise ModelError(
                f"the whirl dependence at {s * 30 / np.pi:.6g} rpm is not fitted within "
                f"fit_tolerance = {tol:.3g} (best relative misfit {misfit:.3g}, "
                f"{fit.n_poles} poles from {len(w)} whirl frequencies)",
                field=field,
                expected="a fit_tolerance of at least the misfit the table's accuracy allows, "
                "or more whirl frequencies",
                file=file,
            )
        out.append(WhirlRow(float(s), np.asarray(w, float), np.asarray(v, float), fit))
    return tuple(out)
