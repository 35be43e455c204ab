"""Shaft fatigue from transient shear-stress histories: rainflow, S–N curve, Miner's rule.

* Cycle counting: the rainflow method of ASTM E1049-85 (reapproved 2017), section 5.4.4, by the
  PyPI package ``rainflow`` (3.2), which implements exactly that procedure (three-point
  counting, half cycles for the residue). The histories are first reduced to their turning
  points with numpy — the rainflow count depends on nothing else, and this keeps the pure-Python
  counter fast on long start-ups.
* S–N curve (Basquin): ``N = C · S^(−m)`` with S the shear stress amplitude (or range, as the
  curve says), optionally an endurance limit below which cycles do no damage, and optionally
  Goodman's mean-stress correction ``S_eq = S_a / (1 − |S_m| / S_u)`` with the ultimate shear
  strength S_u.
* Miner's rule: damage ``D = Σ n_i / N_i`` per element per event (one transient); failure at
  D = 1, so the allowable number of events (e.g. starts) is 1 / D.

Stresses are the surface shear stresses τ = T r / J_p × SCF of the shaft elements (the stress
concentration factors of the model's ``stress_concentrations``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import rainflow
from numpy.typing import NDArray

from ...errors import ModelError
from ...units import to_si
from .transient import TorsionalTransient

__all__ = [
    "SNCurve",
    "FatigueResult",
    "fatigue",
    "miner_damage",
    "rainflow_cycles",
    "turning_points",
]


@dataclass(frozen=True)
class SNCurve:
    """Basquin S–N curve ``N = C · S^(−m)`` (S in Pa).

    m : exponent (> 0); C : Pa^m; endurance_limit : Pa (amplitudes or ranges below it do no
    damage; None: none); measure : ``"amplitude"`` (S = τ_a) or ``"range"`` (S = Δτ = 2 τ_a).
    Build it from one point of the curve with :meth:`from_point`.
    """

    m: float
    C: float
    endurance_limit: float | None = None
    measure: str = "amplitude"

    def __post_init__(self) -> None:
        if not np.isfinite(self.m) or self.m <= 0:
            raise ModelError(
                "the S-N exponent must be positive (N = C S^-m falls with stress)",
                field="sn_curve.m",
                value=self.m,
                expected="m > 0 (steels: about 3 to 12)",
            )
        if not np.isfinite(self.C) or self.C <= 0:
            raise ModelError(
                "the S-N constant must be positive",
                field="sn_curve.C",
                value=self.C,
                expected="C > 0 (Pa^m)",
            )
        if self.endurance_limit is not None and self.endurance_limit < 0:
            raise ModelError(
                "the endurance limit must be ≥ 0",
                field="sn_curve.endurance_limit",
                value=self.endurance_limit,
            )
        if self.measure not in ("amplitude", "range"):
            raise ModelError(
                "unknown stress measure of the S-N curve",
                field="sn_curve.measure",
                value=self.measure,
                expected="'amplitude' or 'range'",
            )

    @classmethod
    def from_point(
        cls,
        *,
        m: float,
        stress: float | str,
        cycles: float,
        endurance_limit: float | str | None = None,
        measure: str = "amplitude",
    ) -> SNCurve:
        """The curve of exponent m through (stress, cycles): C = cycles · stress^m. Stresses
        in Pa or with units (``"250 MPa"``)."""
        s = to_si(stress, "stress")
        if s <= 0 or cycles <= 0:
            raise ModelError(
                "the S-N reference point needs a positive stress and cycles",
                field="sn_curve",
                value=(s, cycles),
            )
        if not np.isfinite(m) or m <= 0:
            cls(m=m, C=1.0)  # raises the exponent error
        e = None if endurance_limit is None else to_si(endurance_limit, "stress")
        return cls(m=m, C=cycles * s**m, endurance_limit=e, measure=measure)

    def cycles_to_failure(self, amplitude: NDArray) -> NDArray:
        """N for stress amplitudes τ_a (Pa); inf below the endurance limit or at 0."""
        s = np.abs(np.asarray(amplitude, float))
        if self.measure == "range":
            s = 2 * s
        with np.errstate(divide="ignore"):
            n = self.C * s ** (-self.m)
        if self.endurance_limit is not None:
            n = np.where(s < self.endurance_limit, np.inf, n)
        return np.where(s > 0, n, np.inf)


def turning_points(x: NDArray) -> NDArray:
    """The reversals of a history (first and last points included, plateaus merged)."""
    x = np.asarray(x, float)
    if len(x) < 3:
        return x
    d = np.diff(x)
    keep = d != 0
    xs = np.concatenate([[x[0]], x[1:][keep]])
    if len(xs) < 3:
        return xs
    ds = np.diff(xs)
    rev = np.flatnonzero(ds[:-1] * ds[1:] < 0) + 1
    return np.concatenate([[xs[0]], xs[rev], [xs[-1]]])


def rainflow_cycles(history: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Rainflow cycles of a history per ASTM E1049-85 §5.4.4: (ranges, means, counts), counts
    1 for full cycles and 0.5 for half cycles."""
    cyc = list(rainflow.extract_cycles(turning_points(history)))
    if not cyc:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    a = np.array([(r, m, c) for r, m, c, _, _ in cyc], float)
    return a[:, 0], a[:, 1], a[:, 2]


def miner_damage(
    history: NDArray, sn_curve: SNCurve, *, ultimate_strength: float | None = None
) -> tuple[float, float, float]:
    """Miner damage ``Σ n_i / N_i`` of a stress history (Pa) by rainflow counting: (damage,
    counted cycles, largest amplitude). ``ultimate_strength`` (Pa) applies Goodman's
    correction ``S_a / (1 − |S_m| / S_u)`` (a mean at or beyond S_u fails at once)."""
    rng, mean, cnt = rainflow_cycles(history)
    if not len(rng):
        return 0.0, 0.0, 0.0
    amp = rng / 2
    if ultimate_strength is not None:
        su = ultimate_strength
        amp = np.where(np.abs(mean) < su, amp / (1 - np.abs(mean) / su), np.inf)
    return float(np.sum(cnt / sn_curve.cycles_to_failure(amp))), float(cnt.sum()), float(amp.max())


@dataclass(frozen=True)
class FatigueResult:
    """Miner damage per shaft element for one event (the transient), and allowable events."""

    transient: TorsionalTransient = field(repr=False)
    sn_curve: SNCurve
    elements: NDArray  # indices of the evaluated elements
    damage: NDArray  # (k,) per event
    cycles: NDArray  # (k,) counted cycles (half cycles as 0.5)
    max_amplitude: NDArray  # (k,) Pa, largest (mean-corrected) amplitude
    mean_stress_correction: str | None

    @property
    def allowable_events(self) -> NDArray:
        """1 / D per element (inf where nothing is damaged)."""
        with np.errstate(divide="ignore"):
            return np.where(self.damage > 0, 1.0 / self.damage, np.inf)

    @property
    def governing(self) -> int:
        """Position (in ``elements``) of the most damaged element."""
        return int(np.argmax(self.damage))

    @property
    def allowable_starts(self) -> float:
        """Allowable number of events for the train: that of the most damaged element."""
        return float(self.allowable_events[self.governing]) if len(self.damage) else np.inf

    def to_dict(self) -> dict:
        labels = self.transient.model.element_labels()
        g = self.governing if len(self.damage) else None
        return {
            "sn_curve": {
                "m": self.sn_curve.m,
                "C": self.sn_curve.C,
                "endurance_limit_Pa": self.sn_curve.endurance_limit,
                "measure": self.sn_curve.measure,
            },
            "mean_stress_correction": self.mean_stress_correction,
            "governing_element": None if g is None else labels[self.elements[g]],
            "damage_per_event": None if g is None else float(self.damage[g]),
            "allowable_events": None if g is None else _json_inf(self.allowable_starts),
            "elements": [
                {
                    "element": labels[e],
                    "damage": float(d),
                    "cycles": float(c),
                    "max_amplitude_Pa": float(a),
                    "allowable_events": _json_inf(n),
                }
                for e, d, c, a, n in zip(
                    self.elements,
                    self.damage,
                    self.cycles,
                    self.max_amplitude,
                    self.allowable_events,
                    strict=True,
                )
            ],
        }

    def table(self) -> str:
        labels = self.transient.model.element_labels()
        rows = [
            f"{'element':<18} {'damage/event':>13} {'cycles':>9} {'max ampl MPa':>13} "
            f"{'allowable':>11}"
        ]
        rows.append("-" * len(rows[0]))
        for k in np.argsort(-self.damage)[:10]:
            n = self.allowable_events[k]
            rows.append(
                f"{labels[self.elements[k]]:<18} {self.damage[k]:>13.3e} {self.cycles[k]:>9.1f} "
                f"{self.max_amplitude[k] / 1e6:>13.4g} {'inf' if np.isinf(n) else f'{n:.4g}':>11}"
            )
        return "\n".join(rows)


def _json_inf(x: float) -> float | None:
    return None if np.isinf(x) else float(x)


def fatigue(
    transient: TorsionalTransient,
    sn_curve: SNCurve,
    *,
    elements: Sequence[int] | None = None,
    mean_stress_correction: str | None = None,
    ultimate_strength: float | str | None = None,
) -> FatigueResult:
    """Miner damage of one transient event per shaft element (module docstring).

    elements : element indices (default all); mean_stress_correction : None or ``"goodman"``
    (needs ``ultimate_strength``, the ultimate shear strength, Pa or with units).
    """
    if mean_stress_correction not in (None, "goodman"):
        raise ModelError(
            "unknown mean-stress correction",
            field="mean_stress_correction",
            value=mean_stress_correction,
            expected="None or 'goodman'",
        )
    su = None
    if mean_stress_correction == "goodman":
        if ultimate_strength is None:
            raise ModelError(
                "Goodman's correction needs the ultimate shear strength",
                field="ultimate_strength",
                expected="a stress, e.g. '550 MPa'",
            )
        su = to_si(ultimate_strength, "stress")
        if su <= 0:
            raise ModelError(
                "the ultimate strength must be positive", field="ultimate_strength", value=su
            )
    stress = transient.element_stress
    idx = np.arange(stress.shape[1]) if elements is None else np.asarray(elements, int)
    per = np.array(
        [miner_damage(stress[:, e], sn_curve, ultimate_strength=su) for e in idx], float
    ).reshape(-1, 3)
    dmg, ncyc, amax = per.T
    return FatigueResult(
        transient=transient,
        sn_curve=sn_curve,
        elements=idx,
        damage=np.array(dmg, float),
        cycles=np.array(ncyc, float),
        max_amplitude=np.array(amax, float),
        mean_stress_correction=mean_stress_correction,
    )
