"""Seal coefficients at a speed and whirl frequency, and tables over speed for a rotor model.

:func:`seal_coefficients` solves a seal (labyrinth, liquid annular, hole-pattern or honeycomb)
at a rotor speed ω and a whirl frequency Ω (default synchronous, Ω = ω) and returns a frozen
:class:`SealResult`: leakage, the 8 coefficients at Ω (``H_xx(Ω) = kxx(Ω) + iΩ cxx(Ω)`` for an x
excitation at Ω), and, for liquid seals, Childs' constant coefficients with the added mass.
:func:`seal_table` tabulates the synchronous coefficients over speed, as a rotor model uses them.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from .annular import AnnularSeal, annular_flow, annular_impedance
from .labyrinth import (
    LabyrinthSeal,
    coefficients_from_impedance,
    labyrinth_flow,
    labyrinth_impedance,
    labyrinth_swirl,
)

__all__ = ["SealResult", "seal_coefficients", "seal_table", "seal_whirl_table", "COEFFICIENT_KEYS"]

#: JSON keys of the 8 coefficients, in the order kxx kxy kyx kyy cxx cxy cyx cyy.
COEFFICIENT_KEYS = (
    "kxx_N_per_m",
    "kxy_N_per_m",
    "kyx_N_per_m",
    "kyy_N_per_m",
    "cxx_Ns_per_m",
    "cxy_Ns_per_m",
    "cyx_Ns_per_m",
    "cyy_Ns_per_m",
)
#: Smallest whirl frequency used for the damping (rad/s): at Ω = 0 the damping is the limit
#: Ω → 0, evaluated here.
_MIN_WHIRL = 1e-3
#: Whirl frequencies (× ω) over which a liquid seal's constant coefficients are fitted.
_FIT_RATIOS = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0)


@dataclass(frozen=True)
class SealResult:
    """A seal solved at one speed and whirl frequency (SI units).

    speed, whirl : rotor speed ω and whirl frequency Ω, rad/s
    leakage : kg/s
    coefficients : (8,) kxx kxy kyx kyy (N/m), cxx cxy cyx cyy (N·s/m) at Ω
    constant : liquid seals: Childs' (K, k, C, c, M, m) fitted over Ω = 0.25ω … 2ω, else None
    z : (n,) axial position of the stations (cavities of a labyrinth, grid of an annular
        seal), m; pressure : (n,) Pa; swirl : (n,) circumferential velocity / (R ω)
    choked : the last tooth of a labyrinth passes Fliegner's choked flux
    """

    seal: LabyrinthSeal | AnnularSeal
    speed: float
    whirl: float
    leakage: float
    coefficients: tuple[float, ...]
    z: NDArray
    pressure: NDArray
    swirl: NDArray
    choked: bool = False
    constant: tuple[float, ...] | None = None
    wall_time: float = 0.0
    extra: dict = field(default_factory=dict)

    @property
    def kxx(self) -> float:
        return self.coefficients[0]

    @property
    def kxy(self) -> float:
        return self.coefficients[1]

    @property
    def cxx(self) -> float:
        return self.coefficients[4]

    @property
    def cxy(self) -> float:
        return self.coefficients[5]

    @property
    def effective_damping(self) -> float:
        """C_eff = cxx − kxy/Ω (N·s/m): the damping a forward synchronous whirl sees."""
        return self.coefficients[4] - self.coefficients[1] / self.whirl if self.whirl else math.nan

    def to_dict(self) -> dict:
        """JSON-ready: ``leakage_kg_per_s``, ``coefficients`` {kxx_N_per_m, ...}, stations."""
        s = self.seal
        out = {
            "type": s.kind,
            "name": s.name,
            "speed_rpm": self.speed * 30 / math.pi,
            "whirl_frequency_hz": self.whirl / (2 * math.pi),
            "leakage_kg_per_s": self.leakage,
            "coefficients": dict(zip(COEFFICIENT_KEYS, self.coefficients, strict=True)),
            "effective_damping_Ns_per_m": None
            if math.isnan(self.effective_damping)
            else self.effective_damping,
            "choked": self.choked,
            "stations": {
                "z_m": self.z.tolist(),
                "pressure_Pa": self.pressure.tolist(),
                "swirl_ratio": self.swirl.tolist(),
            },
            "wall_time_s": self.wall_time,
        }
        if self.constant is not None:
            K, k, C, c, M, m = self.constant
            out["constant_coefficients"] = {
                "K_N_per_m": K,
                "k_N_per_m": k,
                "C_Ns_per_m": C,
                "c_Ns_per_m": c,
                "M_kg": M,
                "m_kg": m,
            }
            out["added_mass"] = {"mxx_kg": M, "mxy_kg": m, "myx_kg": -m, "myy_kg": M}
        return out

    def table(self) -> str:
        """A short fixed-width report."""
        s = self.seal
        lines = [
            f"{s.name} ({s.kind}): {self.speed * 30 / math.pi:.0f} rpm, whirl "
            f"{self.whirl / (2 * math.pi):.2f} Hz; leakage {self.leakage:.6g} kg/s"
            + ("; last tooth choked" if self.choked else ""),
            "",
            f"{'kxx N/m':>12} {'kxy N/m':>12} {'kyx N/m':>12} {'kyy N/m':>12}",
            " ".join(f"{v:>12.5g}" for v in self.coefficients[:4]),
            f"{'cxx Ns/m':>12} {'cxy Ns/m':>12} {'cyx Ns/m':>12} {'cyy Ns/m':>12}",
            " ".join(f"{v:>12.5g}" for v in self.coefficients[4:]),
        ]
        if not math.isnan(self.effective_damping):
            lines.append(f"effective damping cxx - kxy/Ω = {self.effective_damping:.5g} N·s/m")
        if self.constant is not None:
            K, k, C, c, M, m = self.constant
            lines += [
                "",
                "constant coefficients (Childs, fitted over whirl 0.25-2x): "
                f"K {K:.5g} N/m, k {k:.5g} N/m, C {C:.5g} N·s/m, c {c:.5g} N·s/m, "
                f"M {M:.5g} kg, m {m:.5g} kg",
            ]
        label = "cavity" if s.kind == "labyrinth" else "z mm"
        lines += ["", f"{label:>8} {'P kPa':>10} {'swirl':>7}"]
        step = max(1, len(self.z) // 20)
        for j in range(0, len(self.z), step):
            tag = f"{j:>8d}" if s.kind == "labyrinth" else f"{self.z[j] * 1e3:>8.2f}"
            lines.append(f"{tag} {self.pressure[j] / 1e3:>10.3f} {self.swirl[j]:>7.3f}")
        lines.append(
            "swirl: circumferential velocity / rotor surface speed; coefficients at the whirl "
            "frequency (H_xx = kxx + iΩ cxx)"
        )
        return "\n".join(lines)


def _flow(seal):
    return labyrinth_flow(seal) if isinstance(seal, LabyrinthSeal) else None


@lru_cache(maxsize=32)
def _labyrinth_flow_cached(seal: LabyrinthSeal):
    return labyrinth_flow(seal)


def _impedances(seal, flow, speed: float, whirl: float, swirl=None):
    w = max(abs(whirl), _MIN_WHIRL)
    if isinstance(seal, LabyrinthSeal):
        return (
            labyrinth_impedance(seal, flow, speed, w, swirl),
            labyrinth_impedance(seal, flow, speed, -w, swirl),
            w,
        )
    return annular_impedance(seal, flow, w), annular_impedance(seal, flow, -w), w


def _eight(K, k, C, c):
    return (K, k, -k, K, C, c, -c, C)


def seal_coefficients(
    seal: LabyrinthSeal | AnnularSeal, speed: float, whirl: float | None = None
) -> SealResult:
    """Solve a seal at rotor speed ``speed`` (rad/s, ≥ 0) and whirl frequency ``whirl`` (rad/s;
    default synchronous). Raises ModelError for inputs the model cannot pass (a seal choked
    beyond its last tooth, a choked annular seal) and SolverError for a singular system."""
    t0 = time.perf_counter()
    speed = abs(float(speed))
    whirl = speed if whirl is None else abs(float(whirl))
    constant = None
    choked = False
    if isinstance(seal, LabyrinthSeal):
        flow = _labyrinth_flow_cached(seal)
        v = labyrinth_swirl(seal, flow, speed)
        hf, hb, w = _impedances(seal, flow, speed, whirl, v)
        z = (np.arange(seal.n_teeth + 1)) * seal.pitch
        pressure = flow.pressure
        rw = seal.radius * speed
        sw = np.append(v, v[-1]) / rw if rw else np.zeros(seal.n_teeth + 1)
        leakage = flow.mdot * seal.circumference
        choked = flow.choked
    else:
        flow = annular_flow(seal, speed)
        hf, hb, w = _impedances(seal, flow, speed, whirl)
        z, pressure = flow.z, flow.pressure
        rw = seal.radius * speed
        sw = flow.U / rw if rw else np.zeros_like(flow.U)
        leakage = flow.mdot * seal.circumference
        if not seal.fluid.compressible:
            constant = _fit_constant(seal, flow, speed)
    K, k, C, c = coefficients_from_impedance(hf, hb, w)
    return SealResult(
        seal,
        speed,
        whirl,
        float(leakage),
        tuple(float(x) for x in _eight(K, k, C, c)),
        np.asarray(z, float),
        np.asarray(pressure, float),
        np.asarray(sw, float),
        choked,
        constant,
        time.perf_counter() - t0,
    )


def _fit_constant(seal: AnnularSeal, flow, speed: float) -> tuple[float, ...]:
    """Childs' K, k, C, c, M, m by least squares of the frequency-dependent coefficients over
    Ω = 0.25ω … 2ω (K(Ω) = K − MΩ², k(Ω) = k − mΩ², C(Ω) = C, c(Ω) = c)."""
    ref = speed if speed > 0 else flow.W.mean() / seal.length
    rows = []
    for r in _FIT_RATIOS:
        om = r * ref
        hf, hb = annular_impedance(seal, flow, om), annular_impedance(seal, flow, -om)
        rows.append((om, *coefficients_from_impedance(hf, hb, om)))
    a = np.array(rows)
    om2 = a[:, 0] ** 2
    X = np.column_stack([np.ones_like(om2), -om2])
    (K, M), *_ = np.linalg.lstsq(X, a[:, 1], rcond=None)
    (k, m), *_ = np.linalg.lstsq(X, a[:, 2], rcond=None)
    return (float(K), float(k), float(a[:, 3].mean()), float(a[:, 4].mean()), float(M), float(m))


def seal_table(
    seal: LabyrinthSeal | AnnularSeal, speeds, sign: float = 1.0
) -> tuple[NDArray, NDArray]:
    """Synchronous coefficients at the speeds (rad/s): (|speeds| sorted, (n, 8) values). With
    ``sign = −1`` (a shaft turning about −z) the cross-coupled terms change sign."""
    w = np.unique(np.abs(np.asarray(speeds, float)))
    vals = np.empty((len(w), 8))
    for j, s in enumerate(w):
        vals[j] = seal_coefficients(seal, s).coefficients
    if sign < 0:
        vals[:, [1, 2, 5, 6]] *= -1.0
    return w, vals


def seal_whirl_table(
    seal: LabyrinthSeal | AnnularSeal, speeds, whirls, sign: float = 1.0
) -> tuple[tuple[float, NDArray, NDArray], ...]:
    """The coefficients over speed and whirl frequency (issue 24): one row per |speed| (rad/s,
    sorted), each at the ``whirls`` (rad/s, ≥ 0) and at its own speed (synchronous), as
    ``(speed, whirl (n_w,), values (n_w, 8))``. The flow is solved once per speed and the
    perturbation once per whirl frequency. With ``sign = −1`` (a shaft turning about −z) the
    cross-coupled terms change sign."""
    out = []
    for s in np.unique(np.abs(np.asarray(speeds, float))):
        om = np.unique(np.append(np.abs(np.asarray(whirls, float)), s))
        if isinstance(seal, LabyrinthSeal):
            flow = _labyrinth_flow_cached(seal)
            swirl = labyrinth_swirl(seal, flow, s)
        else:
            flow, swirl = annular_flow(seal, s), None
        vals = np.empty((len(om), 8))
        for j, w in enumerate(om):
            hf, hb, ww = _impedances(seal, flow, s, w, swirl)
            vals[j] = _eight(*coefficients_from_impedance(hf, hb, ww))
        if sign < 0:
            vals[:, [1, 2, 5, 6]] *= -1.0
        out.append((float(s), om, vals))
    return tuple(out)
