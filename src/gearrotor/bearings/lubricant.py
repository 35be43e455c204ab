"""Lubricants: viscosity against temperature, density and specific heat (SI: K, Pa·s, m²/s).

Viscosity–temperature laws (``Lubricant.law``)
-----------------------------------------------
``"walther"``
    ASTM D341 (Walther): ``lg lg Z = A − B lg T`` with T in K and
    ``Z = ν + 0.7 + exp(−1.47 − 1.84 ν − 0.51 ν²)`` (ν in mm²/s); the inverse is D341's
    ``ν = (Z − 0.7) − exp(−0.7487 − 3.295 (Z − 0.7) + 0.6119 (Z − 0.7)² − 0.3193 (Z − 0.7)³)``.
    Fitted through two kinematic viscosities (normally at 40 °C and 100 °C); μ = ρ(T) ν(T).
``"vogel"``
    Vogel (1921): ``μ = a exp(b / (T − c))``, through three (T, μ) points.
``"exponential"``
    Reynolds: ``μ = μ₁ exp(−β (T − T₁))`` through two (T, μ) points (the law of ROSS 3.1's
    fluid-film bearings, used to compare with them).

ISO VG grades (:func:`iso_vg`): ν at 40 °C is the grade's ISO 3448 mid-point; ν at 100 °C is the
value that gives the oil the viscosity index ``vi`` (default 100, typical of mineral turbine
oils) by ASTM D2270 (its Table 1, reproduced here from 2 to 15 mm²/s at 100 °C; the grades
10 to 100 fall in it).

Density: ASTM D1250 / API MPMS 11.1 volume correction for lubricating oils (Table 54D:
``α₁₅ = K₁/ρ₁₅``, K₀ = 0, K₁ = 0.6278 kg/(m³·K)), ``ρ(T) = ρ₁₅ exp(−α₁₅ ΔT (1 + 0.8 α₁₅ ΔT))``,
ΔT = T − 15 °C. Specific heat, unless given: Cragoe (1929, US Bureau of Standards Misc. Publ.
97), ``c = (1684.8 + 3.391 t) / √s`` J/(kg·K), t in °C, s the specific gravity ρ₁₅/999 kg/m³.

Every law is used only between the pour point and ``max_temperature`` (the range in which the
oil is a homogeneous liquid and the law is trusted): :meth:`Lubricant.check_temperature` raises
:class:`~gearrotor.errors.ModelError` outside it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ModelError

__all__ = [
    "Lubricant",
    "ISO_VG_GRADES",
    "iso_vg",
    "viscosity_index",
    "CELSIUS",
]

#: 0 °C in K
CELSIUS = 273.15
_T15 = CELSIUS + 15.0
_K1_LUBE = 0.6278  # ASTM D1250 Table 54D, lubricating oils, kg/(m³·K)
_WATER_60F = 999.0  # kg/m³, the reference of the specific gravity s (60 °F)

Law = Literal["walther", "vogel", "exponential"]

# ASTM D2270 Table 1: ν at 100 °C from 2.0 to 15.0 mm²/s in steps of 0.1, and the 40 °C viscosities
# L (viscosity index 0) and H (viscosity index 100) of the reference oils with that ν at 100 °C.
_D2270_NU = tuple(round(2.0 + 0.1 * k, 1) for k in range(131))
_D2270_L = (
    7.994,
    8.64,
    9.309,
    10.0,
    10.71,
    11.45,
    12.21,
    13.0,
    13.8,
    14.63,
    15.49,
    16.36,
    17.26,
    18.18,
    19.12,
    20.09,
    21.08,
    22.09,
    23.13,
    24.19,
    25.32,
    26.5,
    27.75,
    29.07,
    30.48,
    31.96,
    33.52,
    35.13,
    36.79,
    38.5,
    40.23,
    41.99,
    43.76,
    45.53,
    47.31,
    49.09,
    50.87,
    52.64,
    54.42,
    56.2,
    57.97,
    59.74,
    61.52,
    63.32,
    65.18,
    67.12,
    69.16,
    71.29,
    73.48,
    75.72,
    78.0,
    80.25,
    82.39,
    84.53,
    86.66,
    88.85,
    91.04,
    93.2,
    95.43,
    97.72,
    100.0,
    102.3,
    104.6,
    106.9,
    109.2,
    111.5,
    113.9,
    116.2,
    118.5,
    120.9,
    123.3,
    125.7,
    128.0,
    130.4,
    132.8,
    135.3,
    137.7,
    140.1,
    142.7,
    145.2,
    147.7,
    150.3,
    152.9,
    155.4,
    158.0,
    160.6,
    163.2,
    165.8,
    168.5,
    171.2,
    173.9,
    176.6,
    179.4,
    182.1,
    184.9,
    187.6,
    190.4,
    193.3,
    196.2,
    199.0,
    201.9,
    204.8,
    207.8,
    210.7,
    213.6,
    216.6,
    219.6,
    222.6,
    225.7,
    228.8,
    231.9,
    235.0,
    238.1,
    241.2,
    244.3,
    247.4,
    250.6,
    253.8,
    257.0,
    260.1,
    263.3,
    266.6,
    269.8,
    273.0,
    276.3,
    279.6,
    283.0,
    286.4,
    289.7,
    293.0,
    296.5,
)
_D2270_H = (
    6.394,
    6.894,
    7.41,
    7.944,
    8.496,
    9.063,
    9.647,
    10.25,
    10.87,
    11.5,
    12.15,
    12.82,
    13.51,
    14.21,
    14.93,
    15.66,
    16.42,
    17.19,
    17.97,
    18.77,
    19.56,
    20.37,
    21.21,
    22.05,
    22.92,
    23.81,
    24.71,
    25.63,
    26.57,
    27.53,
    28.49,
    29.46,
    30.43,
    31.4,
    32.37,
    33.34,
    34.32,
    35.29,
    36.26,
    37.23,
    38.19,
    39.17,
    40.15,
    41.13,
    42.14,
    43.18,
    44.24,
    45.33,
    46.44,
    47.51,
    48.57,
    49.61,
    50.69,
    51.78,
    52.88,
    53.98,
    55.09,
    56.2,
    57.31,
    58.45,
    59.6,
    60.74,
    61.89,
    63.05,
    64.18,
    65.32,
    66.48,
    67.64,
    68.79,
    69.94,
    71.1,
    72.27,
    73.42,
    74.57,
    75.73,
    76.91,
    78.08,
    79.27,
    80.46,
    81.67,
    82.87,
    84.08,
    85.3,
    86.51,
    87.72,
    88.95,
    90.19,
    91.4,
    92.65,
    93.92,
    95.19,
    96.45,
    97.71,
    98.97,
    100.2,
    101.5,
    102.8,
    104.1,
    105.4,
    106.7,
    108.0,
    109.4,
    110.7,
    112.0,
    113.3,
    114.7,
    116.0,
    117.4,
    118.7,
    120.1,
    121.5,
    122.9,
    124.2,
    125.6,
    127.0,
    128.4,
    129.8,
    131.2,
    132.6,
    134.0,
    135.4,
    136.8,
    138.2,
    139.6,
    141.0,
    142.4,
    143.9,
    145.3,
    146.8,
    148.2,
    149.7,
)


#: ISO 3448 grades with presets (mid-point kinematic viscosity at 40 °C, mm²/s)
ISO_VG_GRADES = (10, 15, 22, 32, 46, 68, 100)

#: Default pour point of the presets: −6 °C, the highest pour point ISO 8068 / DIN 51515-1 allow
#: a turbine oil of grades 32–100 (a conforming oil is liquid at least down to it).
PRESET_POUR_POINT = CELSIUS - 6.0
#: Default upper temperature of every law: 150 °C (mineral oil in a bearing film).
DEFAULT_MAX_TEMPERATURE = CELSIUS + 150.0
#: Default density of the presets at 15 °C (typical paraffinic mineral turbine oil).
PRESET_DENSITY = 870.0


def viscosity_index(nu40: float, nu100: float) -> float:
    """Viscosity index by ASTM D2270 (procedure A below 100, B above), unrounded.

    ``nu40``, ``nu100``: kinematic viscosities at 40 °C and 100 °C (m²/s); ν at 100 °C between
    2 and 15 mm²/s (the part of the standard's table held here).
    """
    u, y = nu40 * 1e6, nu100 * 1e6
    if not 2.0 <= y <= 15.0:
        raise ModelError(
            "viscosity index: kinematic viscosity at 100 °C outside the table held",
            field="nu100",
            value=f"{y:.6g} mm^2/s",
            expected="2 to 15 mm^2/s",
        )
    lo = float(np.interp(y, _D2270_NU, _D2270_L))
    hi = float(np.interp(y, _D2270_NU, _D2270_H))
    if u > hi:
        return (lo - u) / (lo - hi) * 100.0
    n = (math.log10(hi) - math.log10(u)) / math.log10(y)
    return (10.0**n - 1.0) / 0.00715 + 100.0


def _walther_z(nu_mm2: NDArray) -> NDArray:
    return nu_mm2 + 0.7 + np.exp(-1.47 - 1.84 * nu_mm2 - 0.51 * nu_mm2**2)


def _walther_nu(z: NDArray) -> NDArray:
    x = z - 0.7
    return x - np.exp(-0.7487 - 3.295 * x + 0.6119 * x**2 - 0.3193 * x**3)


@dataclass(frozen=True)
class Lubricant:
    """A lubricant: its viscosity law and properties (use the constructors :meth:`walther`,
    :meth:`vogel`, :meth:`exponential` or :func:`iso_vg`).

    Attributes
    ----------
    law
        ``"walther"``, ``"vogel"`` or ``"exponential"`` (module docstring).
    coefficients
        walther: (A, B); vogel: (a Pa·s, b K, c K); exponential: (μ₁ Pa·s, T₁ K, β 1/K).
    density
        Density at 15 °C (kg/m³).
    specific_heat
        J/(kg·K), constant; None = Cragoe's correlation of temperature.
    thermal_conductivity
        W/(m·K), constant; default 0.13 (mineral turbine oils near 40–80 °C: 0.13–0.14,
        falling slowly with temperature). Used by the THD film's conduction across its
        layers.
    pour_point
        Lowest temperature the laws are used at (K).
    max_temperature
        Highest temperature the laws are used at (K).
    name
        Free text (e.g. "ISO VG 32").
    """

    law: Law
    coefficients: tuple[float, ...]
    density: float = PRESET_DENSITY
    specific_heat: float | None = None
    thermal_conductivity: float = 0.13
    pour_point: float = PRESET_POUR_POINT
    max_temperature: float = DEFAULT_MAX_TEMPERATURE
    name: str = ""

    def __post_init__(self) -> None:
        for fld, v in (("density", self.density), ("pour_point", self.pour_point)):
            if not (math.isfinite(v) and v > 0):
                raise ModelError(
                    f"{fld} must be positive", field=f"lubricant.{fld}", value=v, expected="> 0"
                )
        if not (math.isfinite(self.thermal_conductivity) and self.thermal_conductivity > 0):
            raise ModelError(
                "thermal conductivity must be positive",
                field="lubricant.thermal_conductivity",
                value=self.thermal_conductivity,
                expected="> 0 W/(m*K)",
            )
        if self.specific_heat is not None and not self.specific_heat > 0:
            raise ModelError(
                "specific heat must be positive",
                field="lubricant.specific_heat",
                value=self.specific_heat,
                expected="> 0 J/(kg*K)",
            )
        if not self.max_temperature > self.pour_point:
            raise ModelError(
                "the lubricant's maximum temperature must exceed its pour point",
                field="lubricant.max_temperature",
                value=f"{self.max_temperature - CELSIUS:.6g} degC",
                expected=f"> pour point {self.pour_point - CELSIUS:.6g} degC",
            )
        if self.law == "vogel" and not self.coefficients[2] < self.pour_point:
            raise ModelError(
                "the Vogel law diverges at T = c, which lies above the pour point",
                field="lubricant.viscosity_points",
                value=f"c = {self.coefficients[2] - CELSIUS:.6g} degC",
                expected=f"points giving c below the pour point {self.pour_point - CELSIUS:.6g} "
                "degC",
            )
        lo, hi = self.viscosity(np.array([self.pour_point, self.max_temperature]))
        if not (np.isfinite(lo) and np.isfinite(hi) and lo >= hi > 0):
            raise ModelError(
                "the viscosity law does not decrease with temperature over the lubricant's range",
                field="lubricant",
                value=f"{lo:.4g} Pa*s at the pour point, {hi:.4g} Pa*s at the maximum temperature",
                expected="a viscosity that falls with temperature (check the points)",
            )

    # -- constructors -------------------------------------------------------------------------
    @classmethod
    def walther(
        cls,
        nu_a: float,
        nu_b: float,
        t_a: float = CELSIUS + 40.0,
        t_b: float = CELSIUS + 100.0,
        **props,
    ) -> Lubricant:
        """ASTM D341 through the kinematic viscosities ``nu_a`` at ``t_a`` and ``nu_b`` at
        ``t_b`` (m²/s, K); default temperatures 40 °C and 100 °C."""
        _two_points(t_a, nu_a, t_b, nu_b, "kinematic viscosity")
        za, zb = (_walther_z(np.array(v * 1e6)) for v in (nu_a, nu_b))
        la, lb = (math.log10(math.log10(float(z))) for z in (za, zb))
        b = (la - lb) / (math.log10(t_b) - math.log10(t_a))
        a = la + b * math.log10(t_a)
        return cls("walther", (a, b), **props)

    @classmethod
    def exponential(
        cls, point_a: tuple[float, float], point_b: tuple[float, float], **props
    ) -> Lubricant:
        """μ = μ₁ exp(−β (T − T₁)) through two (T K, μ Pa·s) points."""
        (t1, m1), (t2, m2) = point_a, point_b
        _two_points(t1, m1, t2, m2, "viscosity")
        beta = math.log(m1 / m2) / (t2 - t1)
        return cls("exponential", (m1, t1, beta), **props)

    @classmethod
    def constant(cls, viscosity: float, **props) -> Lubricant:
        """A viscosity that does not depend on temperature (the exponential law with β = 0):
        the isoviscous limit of the thermal models."""
        return cls("exponential", (viscosity, _T15, 0.0), **props)

    @classmethod
    def vogel(cls, points: Sequence[tuple[float, float]], **props) -> Lubricant:
        """μ = a exp(b / (T − c)) through three (T K, μ Pa·s) points."""
        if len(points) != 3:
            raise ModelError(
                "the Vogel law needs three points",
                field="lubricant.viscosity_points",
                value=len(points),
                expected="three (temperature, viscosity) pairs",
            )
        (t1, m1), (t2, m2), (t3, m3) = sorted(points)
        _two_points(t1, m1, t2, m2, "viscosity")
        _two_points(t2, m2, t3, m3, "viscosity")
        # ln μ = ln a + b/(T − c): r = (ln m1 − ln m2)/(ln m2 − ln m3) fixes c
        r = math.log(m1 / m2) / math.log(m2 / m3)

        def f(c: float) -> float:
            return (1 / (t1 - c) - 1 / (t2 - c)) / (1 / (t2 - c) - 1 / (t3 - c)) - r

        from scipy.optimize import brentq

        lo, hi = -1e4, t1 - 1e-6
        if not f(lo) * f(hi) < 0:
            raise ModelError(
                "no Vogel law passes through these three points",
                field="lubricant.viscosity_points",
                value=[(t - CELSIUS, m) for t, m in (points)],
                expected="viscosities that fall ever more slowly with temperature",
            )
        c = brentq(f, lo, hi, xtol=1e-12)
        b = math.log(m1 / m2) / (1 / (t1 - c) - 1 / (t2 - c))
        a = m1 / math.exp(b / (t1 - c))
        return cls("vogel", (a, b, c), **props)

    # -- properties ---------------------------------------------------------------------------
    def density_at(self, temperature: ArrayLike) -> NDArray:
        """ρ(T) (kg/m³), ASTM D1250 Table 54D."""
        dt = np.asarray(temperature, dtype=float) - _T15
        alpha = _K1_LUBE / self.density
        return self.density * np.exp(-alpha * dt * (1.0 + 0.8 * alpha * dt))

    def specific_heat_at(self, temperature: ArrayLike) -> NDArray:
        """c_p(T) (J/(kg·K)): the given constant, or Cragoe's correlation."""
        t = np.asarray(temperature, dtype=float)
        if self.specific_heat is not None:
            return np.full_like(t, self.specific_heat)
        s = self.density / _WATER_60F
        return (1684.8 + 3.391 * (t - CELSIUS)) / math.sqrt(s)

    def viscosity(self, temperature: ArrayLike) -> NDArray:
        """Dynamic viscosity μ(T) (Pa·s), no range check (see :meth:`check_temperature`)."""
        t = np.asarray(temperature, dtype=float)
        if self.law == "walther":
            a, b = self.coefficients
            z = 10.0 ** (10.0 ** (a - b * np.log10(t)))
            return _walther_nu(z) * 1e-6 * self.density_at(t)
        if self.law == "vogel":
            a, b, c = self.coefficients
            return a * np.exp(b / (t - c))
        m1, t1, beta = self.coefficients
        return m1 * np.exp(-beta * (t - t1)) + 0.0 * t

    def kinematic_viscosity(self, temperature: ArrayLike) -> NDArray:
        """ν(T) = μ/ρ (m²/s)."""
        return self.viscosity(temperature) / self.density_at(temperature)

    def check_temperature(self, temperature: float, field: str, source: str | None = None) -> None:
        """Raise :class:`ModelError` naming ``field`` when ``temperature`` (K) lies outside
        [pour point, max_temperature]."""
        if self.pour_point <= temperature <= self.max_temperature:
            return
        low = temperature < self.pour_point
        raise ModelError(
            "temperature below the lubricant's pour point"
            if low
            else "temperature above the lubricant's maximum temperature",
            field=field,
            value=f"{temperature - CELSIUS:.6g} degC",
            expected=(
                f"a temperature between the pour point {self.pour_point - CELSIUS:.6g} degC and "
                f"the maximum {self.max_temperature - CELSIUS:.6g} degC of "
                f"{self.name or 'the lubricant'}"
            ),
            file=source,
        )


def _two_points(t_a: float, v_a: float, t_b: float, v_b: float, what: str) -> None:
    if not (v_a > 0 and v_b > 0 and t_a > 0 and t_b > 0 and t_a != t_b):
        raise ModelError(
            f"two positive {what} values at two different temperatures are needed",
            field="lubricant",
            value=[(t_a - CELSIUS, v_a), (t_b - CELSIUS, v_b)],
            expected="distinct temperatures and positive values",
        )
    if (v_a - v_b) * (t_a - t_b) >= 0:
        raise ModelError(
            f"the {what} must fall as the temperature rises",
            field="lubricant",
            value=[(t_a - CELSIUS, v_a), (t_b - CELSIUS, v_b)],
            expected=f"a lower {what} at the higher temperature",
        )


def iso_vg(
    grade: int,
    *,
    vi: float = 100.0,
    density: float = PRESET_DENSITY,
    specific_heat: float | None = None,
    thermal_conductivity: float = 0.13,
    pour_point: float = PRESET_POUR_POINT,
    max_temperature: float = DEFAULT_MAX_TEMPERATURE,
) -> Lubricant:
    """A mineral oil of ISO 3448 grade ``grade`` (ν at 40 °C = the grade, mm²/s) and
    viscosity index ``vi`` (ν at 100 °C by ASTM D2270), by ASTM D341 (Walther)."""
    if grade not in ISO_VG_GRADES:
        raise ModelError(
            "no preset for this ISO VG grade",
            field="lubricant.grade",
            value=grade,
            expected="one of "
            + ", ".join(f"ISO VG {g}" for g in ISO_VG_GRADES)
            + " (or give nu40 and nu100)",
        )
    from scipy.optimize import brentq

    nu40 = grade * 1e-6
    lo, hi = 2.0e-6, 15.0e-6
    f_lo, f_hi = viscosity_index(nu40, lo) - vi, viscosity_index(nu40, hi) - vi
    if not f_lo * f_hi < 0:
        raise ModelError(
            "viscosity index out of reach for this grade",
            field="lubricant.viscosity_index",
            value=vi,
            expected=f"{viscosity_index(nu40, lo):.0f} to {viscosity_index(nu40, hi):.0f}",
        )
    nu100 = brentq(lambda y: viscosity_index(nu40, y) - vi, lo, hi, xtol=1e-14)
    return Lubricant.walther(
        nu40,
        nu100,
        density=density,
        specific_heat=specific_heat,
        thermal_conductivity=thermal_conductivity,
        pour_point=pour_point,
        max_temperature=max_temperature,
        name=f"ISO VG {grade} (VI {vi:g})",
    )
