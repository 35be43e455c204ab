"""Dynamic coefficients by perturbation, load and speed sweeps, and coefficient tables.

Sign convention: F is the film reaction on the journal, K_ij = −∂F_i/∂x_j and
C_ij = −∂F_i/∂ẋ_j (i, j ∈ {x, y}), so a stable bearing has positive direct stiffness and
damping; the rotor sees ``f = −K u − C u̇`` about the static equilibrium.

Coefficients are central differences of the film forces in the journal (and pad) displacements
and velocities about the equilibrium (perturbation ``SolverOptions.perturbation`` · c and
· c·|ω|). For tilting-pad bearings the full matrices over [x, y, pad DOFs] are kept (pad
DOFs: tilt in rad, radial pivot displacement in m) together with the pad mass matrix, and
:meth:`Coefficients.reduced` condenses them to the journal at any whirl frequency; ``K``/``C``
are the synchronously reduced values (whirl = |speed|).

Dimensionless: K̄ = K c / W, C̄ = C c |ω| / W with W = |load|, and the Sommerfeld number
S = μ N L D / W (R/c)², N = |speed|/2π in rev/s.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ModelError, SolverError
from ..files import atomic_file, write_text
from .equilibrium import Equilibrium, equilibrium
from .film import SolverOptions, _Evaluator, _lever_scale, dof_names
from .geometry import Bearing, TiltingPadBearing

__all__ = [
    "Coefficients",
    "coefficients",
    "load_sweep",
    "BearingTable",
    "coefficients_table",
    "load_speed_sweep",
    "save_table",
    "load_table",
    "COEFFICIENT_NAMES",
    "static_stiffness",
]

COEFFICIENT_NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


@dataclass(frozen=True)
class Coefficients:
    """Eight dynamic coefficients at an equilibrium.

    Attributes
    ----------
    equilibrium
        The static equilibrium they linearise about.
    K
        Journal stiffness (N/m), 2×2 [[kxx, kxy], [kyx, kyy]] (synchronously reduced for
        tilting pads).
    C
        Journal damping (N·s/m), 2×2.
    K_full, C_full, M_full
        Full matrices over :attr:`dofs` (x, y in m; pad tilts in rad; radial pad DOFs in m);
        for fixed bearings equal to K, C and zeros.
    dofs
        Names of the full coordinates.
    """

    equilibrium: Equilibrium
    K: NDArray
    C: NDArray
    K_full: NDArray
    C_full: NDArray
    M_full: NDArray
    dofs: tuple[str, ...]

    def __getattr__(self, name: str) -> float:
        if name in COEFFICIENT_NAMES:
            mat = self.K if name[0] == "k" else self.C
            return float(mat["xy".index(name[1]), "xy".index(name[2])])
        raise AttributeError(name)

    @property
    def speed(self) -> float:
        """Journal speed (rad/s, signed)."""
        return self.equilibrium.speed

    @property
    def sommerfeld(self) -> float:
        """Sommerfeld number S = μ N L D / W (R/c)²."""
        return self.equilibrium.sommerfeld

    @property
    def load_magnitude(self) -> float:
        """|W| (N)."""
        return math.hypot(*self.equilibrium.load)

    def dimensionless(self, clearance: float) -> tuple[NDArray, NDArray]:
        """(K c/W, C c |ω|/W) with the given reference clearance c (m)."""
        w = self.load_magnitude
        if w == 0:
            raise ModelError(
                "dimensionless coefficients need a non-zero load",
                field="load",
                value=self.equilibrium.load,
                expected="|W| > 0",
            )
        return self.K * clearance / w, self.C * clearance * abs(self.speed) / w

    def as_array(self) -> NDArray:
        """The 8 coefficients in :data:`COEFFICIENT_NAMES` order."""
        return np.concatenate([self.K.ravel(), self.C.ravel()])

    def stability_threshold(self) -> tuple[float, float]:
        """Lund's rigid-rotor stability threshold of these (synchronous) coefficients.

        For a rigid mass m per bearing (no other damping), instability sets in at whirl
        frequency γ with ``K_eq = (kxx cyy + kyy cxx − kxy cyx − kyx cxy)/(cxx + cyy)`` and
        ``γ² = ((K_eq − kxx)(K_eq − kyy) − kxy kyx)/(cxx cyy − cxy cyx)``, at the critical mass
        ``m_c = K_eq/γ²``. Returns (whirl frequency ratio γ/|ω|, m_c in kg); (NaN, inf) when
        γ² ≤ 0, i.e. no threshold (stable for any mass).
        """
        (kxx, kxy), (kyx, kyy) = self.K
        (cxx, cxy), (cyx, cyy) = self.C
        k_eq = (kxx * cyy + kyy * cxx - kxy * cyx - kyx * cxy) / (cxx + cyy)
        g2 = ((k_eq - kxx) * (k_eq - kyy) - kxy * kyx) / (cxx * cyy - cxy * cyx)
        if not g2 > 0:
            return math.nan, math.inf
        return math.sqrt(g2) / abs(self.speed), k_eq / g2

    def reduced(self, whirl: float) -> tuple[NDArray, NDArray]:
        """Journal K, C condensed at whirl frequency ``whirl`` (rad/s) (pad DOFs eliminated).

        ``Z(Ω) = K + iΩC − Ω²M``, ``Z_r = Z_jj − Z_jp Z_pp⁻¹ Z_pj``; K = Re Z_r, C = Im Z_r / Ω.
        """
        return _reduce(self.K_full, self.C_full, self.M_full, whirl)


def _reduce(k: NDArray, c: NDArray, m: NDArray, whirl: float) -> tuple[NDArray, NDArray]:
    if k.shape[0] == 2:
        return k.copy(), c.copy()
    w = abs(whirl)
    if w == 0:
        w = 1e-9
    z = k + 1j * w * c - w**2 * m
    # an unloaded pad (its film fully cavitated) with no inertia has an all-zero row and column:
    # it carries no force, its tilt is free and does not couple to the journal; condensing it
    # would divide by zero, so it is left out (it contributes nothing to Z_r)
    row = np.abs(z).sum(axis=1) + np.abs(z).sum(axis=0)
    pads = np.arange(2, z.shape[0])
    live = pads[row[2:] > 1e-12 * max(float(row[2:].max(initial=0.0)), 1e-300)]
    zjj = z[:2, :2]
    if len(live):
        zjp, zpj, zpp = z[np.ix_([0, 1], live)], z[np.ix_(live, [0, 1])], z[np.ix_(live, live)]
        try:
            zr = zjj - zjp @ np.linalg.solve(zpp, zpj)
        except np.linalg.LinAlgError:
            raise SolverError(
                "tilting-pad coefficients: the pad equations are singular at whirl "
                f"{w:.6g} rad/s (a pad with neither film stiffness nor inertia that still "
                "couples to the journal); give the pads an inertia"
            ) from None
    else:
        zr = zjj
    return zr.real.copy(), zr.imag / w


def _pad_mass(bearing: Bearing) -> NDArray:
    names = dof_names(bearing)
    m = np.zeros((len(names), len(names)))
    if isinstance(bearing, TiltingPadBearing):
        k = 2
        for pad in bearing.pads:
            m[k, k] = pad.inertia
            k += 1
            if pad.pivot_stiffness is not None:
                m[k, k] = pad.mass
                k += 1
    return m


def coefficients(
    bearing: Bearing,
    load: Sequence[float] | Equilibrium,
    speed: float | None = None,
    *,
    options: SolverOptions | None = None,
) -> Coefficients:
    """Equilibrium and dynamic coefficients of a bearing.

    Parameters
    ----------
    bearing
        Fixed or tilting-pad bearing.
    load
        (Fx, Fy) static load on the journal (N), or an already solved :class:`Equilibrium`.
    speed
        Journal speed (rad/s, signed); taken from the equilibrium when one is given.
    options
        Solver options.
    """
    opts = options or SolverOptions()
    if isinstance(load, Equilibrium):
        eq = load
    else:
        if speed is None:
            raise ModelError(
                "speed is required with a load vector",
                field="speed",
                value=None,
                expected="a speed in rad/s",
            )
        eq = equilibrium(bearing, load, speed, options=opts)
    ev = _Evaluator(bearing, eq.speed, opts)
    if eq.thermal is not None:  # the temperatures frozen at the equilibrium
        ev.viscosity = list(eq.thermal.viscosity)
    u = np.concatenate([[eq.x, eq.y], eq.pad_dofs * _lever_scale(bearing)[2:]])
    k_lev, c_lev = ev.jacobians(u, velocity=True)
    s = _lever_scale(bearing)
    k_full = k_lev * s[:, None] * s[None, :]
    c_full = c_lev * s[:, None] * s[None, :]
    m_full = _pad_mass(bearing)
    kr, cr = _reduce(k_full, c_full, m_full, eq.speed)
    return Coefficients(eq, kr, cr, k_full, c_full, m_full, tuple(dof_names(bearing)))


def static_stiffness(
    bearing: Bearing, eq: Equilibrium, *, options: SolverOptions | None = None
) -> NDArray:
    """Static journal stiffness −∂F/∂x (N/m, 2×2) at an equilibrium: the stiffness part of
    :func:`coefficients` only (no velocity perturbations), tilting pads condensed statically
    (the pads settle, zero whirl frequency). Used by the static analysis's journal iteration."""
    opts = options or SolverOptions()
    ev = _Evaluator(bearing, eq.speed, opts)
    if eq.thermal is not None:
        ev.viscosity = list(eq.thermal.viscosity)
    s = _lever_scale(bearing)
    u = np.concatenate([[eq.x, eq.y], eq.pad_dofs * s[2:]])
    k_lev, _ = ev.jacobians(u, velocity=False)
    k = k_lev * s[:, None] * s[None, :]
    if k.shape[0] == 2:
        return k
    return k[:2, :2] - k[:2, 2:] @ np.linalg.solve(k[2:, 2:], k[2:, :2])


def load_sweep(
    bearing: Bearing,
    loads: Iterable[Sequence[float]],
    speed: float,
    *,
    options: SolverOptions | None = None,
) -> list[Coefficients]:
    """Coefficients for several load cases at one speed (rad/s)."""
    return [coefficients(bearing, tuple(w), speed, options=options) for w in loads]


@dataclass(frozen=True)
class BearingTable:
    """Bearing coefficients tabulated against speed, read by the rotor's bearing elements.

    Attributes
    ----------
    speed_rpm
        Speeds (rpm, signed as solved), shape (n,).
    kxx, kxy, kyx, kyy
        Stiffness (N/m), shape (n,).
    cxx, cxy, cyx, cyy
        Damping (N·s/m), shape (n,).
    load
        The static load (Fx, Fy) they were computed at (N).
    eccentricity_ratio, attitude_angle
        Equilibrium per speed (attitude in rad); NaN when read from a file without them.
    name
        The bearing's name.
    """

    speed_rpm: NDArray
    kxx: NDArray
    kxy: NDArray
    kyx: NDArray
    kyy: NDArray
    cxx: NDArray
    cxy: NDArray
    cyx: NDArray
    cyy: NDArray
    load: tuple[float, float] = (0.0, 0.0)
    eccentricity_ratio: NDArray | None = None
    attitude_angle: NDArray | None = None
    name: str = field(default="")

    def __post_init__(self) -> None:
        n = len(np.atleast_1d(self.speed_rpm))
        for name in ("speed_rpm", *COEFFICIENT_NAMES):
            arr = np.atleast_1d(np.asarray(getattr(self, name), dtype=float))
            if arr.shape != (n,):
                raise ModelError(
                    "coefficient table columns differ in length",
                    field=name,
                    value=arr.shape,
                    expected=f"shape ({n},)",
                )
            object.__setattr__(self, name, arr)

    def values(self) -> NDArray:
        """All coefficients, shape (n, 8), in :data:`COEFFICIENT_NAMES` order."""
        return np.stack([getattr(self, n) for n in COEFFICIENT_NAMES], axis=1)

    def to_coefficient_table(self, extrapolate: str = "error"):
        """The rotor model's :class:`gearrotor.elements.bearing.CoefficientTable` (rad/s)."""
        from ..elements.bearing import CoefficientTable

        if np.any(self.speed_rpm > 0) and np.any(self.speed_rpm < 0):
            raise ModelError(
                "a rotor coefficient table needs speeds of one sign",
                field="speed_rpm",
                value=self.speed_rpm.tolist(),
                expected="all positive or all negative speeds (one direction of rotation)",
            )
        speed = np.abs(self.speed_rpm) * math.pi / 30.0
        order = np.argsort(speed)
        return CoefficientTable(speed[order], self.values()[order], extrapolate)


def coefficients_table(
    bearing: Bearing,
    load: Sequence[float],
    speeds: ArrayLike,
    *,
    options: SolverOptions | None = None,
) -> BearingTable:
    """Coefficients at one load over several speeds.

    Parameters
    ----------
    bearing
        Fixed or tilting-pad bearing.
    load
        (Fx, Fy) static load on the journal (N).
    speeds
        Speeds in **rpm** (signed; the table's unit), any order.
    options
        Solver options.
    """
    rpm = np.atleast_1d(np.asarray(speeds, dtype=float))
    rows, ecc, att = [], [], []
    prev: Equilibrium | None = None
    for n in rpm:
        w = n * math.pi / 30.0
        eq = equilibrium(
            bearing,
            load,
            w,
            options=options,
            start=prev if prev is not None and prev.speed * w > 0 else None,
        )
        co = coefficients(bearing, eq, options=options)
        rows.append(co.as_array())
        ecc.append(eq.eccentricity_ratio)
        att.append(eq.attitude_angle)
        prev = eq
    vals = np.array(rows)
    return BearingTable(
        rpm,
        *vals.T,
        load=(float(load[0]), float(load[1])),
        eccentricity_ratio=np.array(ecc),
        attitude_angle=np.array(att),
        name=bearing.name,
    )


def load_speed_sweep(
    bearing: Bearing,
    loads: Iterable[Sequence[float]],
    speeds: ArrayLike,
    *,
    options: SolverOptions | None = None,
) -> list[BearingTable]:
    """One :class:`BearingTable` per load case (N) over ``speeds`` (rpm)."""
    return [coefficients_table(bearing, load, speeds, options=options) for load in loads]


_CSV_UNITS = ["rpm"] + ["N/m"] * 4 + ["N*s/m"] * 4


def save_table(table: BearingTable, path: str | Path) -> Path:
    """Write a table as CSV (``.csv``) or TOML (``.toml``); returns the path.

    CSV: one header line ``speed_rpm,kxx,…,cyy``, one units line starting with ``#``, then
    rows. TOML: ``name``, ``load = [Fx, Fy]`` and one array per column.
    """
    path = Path(path)
    cols = ["speed_rpm", *COEFFICIENT_NAMES]
    if path.suffix.lower() == ".csv":
        with atomic_file(path, "w", encoding="utf-8", newline="") as fh:
            fh.write(
                f"# bearing: {table.name}; load Fx,Fy = {table.load[0]!r},{table.load[1]!r} N\n"
            )
            w = csv.writer(fh)
            w.writerow(cols)
            fh.write("# " + ",".join(_CSV_UNITS) + "\n")
            for row in zip(*(getattr(table, c) for c in cols), strict=True):
                w.writerow([repr(float(v)) for v in row])
    elif path.suffix.lower() == ".toml":
        lines = [
            f"name = {_toml_str(table.name)}",
            f"load = [{table.load[0]!r}, {table.load[1]!r}]  # N",
            "# units: speed_rpm rpm; k* N/m; c* N*s/m",
        ]
        for c in cols:
            vals = ", ".join(repr(float(v)) for v in getattr(table, c))
            lines.append(f"{c} = [{vals}]")
        write_text(path, "\n".join(lines) + "\n")
    else:
        raise ModelError(
            "unknown table format", field="path", value=str(path), expected="a .csv or .toml file"
        )
    return path


def _toml_str(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def load_table(path: str | Path) -> BearingTable:
    """Read a table written by :func:`save_table` (CSV or TOML) through the checked reader
    :func:`gearrotor.inputs.read_table`: whatever the file holds, the result is a table or one
    :class:`~gearrotor.errors.ModelError` naming the file (and line or column)."""
    from ..inputs import read_table

    t = read_table(path, ("speed_rpm", *COEFFICIENT_NAMES))
    return BearingTable(*(np.array(v) for v in t.columns.values()), load=t.load, name=t.name)
