"""API 617 lateral stability analysis: Level I and Level II.

Editions: **API Standard 617, 8th edition (2014)** (chapter 1, 1.6.5 Level I, 1.6.6 Level II)
and **9th edition (2022)**, whose rotordynamics clause follows the numbering of API's Standard
Paragraphs (Level I 6.8.5, Level II 6.8.6; ROSS's former ``api_report.py`` cites the same
formulas as "API 684 SP6.8.5.6 – SP6.8.5.10"). API RP 684 (2nd edition, 2005) explains the
paragraphs in its stability chapter. The user picks the edition (``edition=``, the model's
``[api_audit] edition``, ``gearrotor stability --edition``); every result says which. The
standards' own text was not available to the author: the formulas and limits below are those
the public descriptions give (ROSS's Level I, its API 617 9th-edition pull request #1377, API
RP 684's published tutorial material), and no public source found shows the 9th edition
changing the Level I formula, its screening criteria or the Level II acceptance, so both
editions apply the same stability criteria here; what the 9th edition changed for the lateral
audit (the unbalance of the response analysis placed from the mode shape, 2× instead of 4× the
residual unbalance, and the close-clearance check) is in
:mod:`gearrotor.analyses.audit.api_unbalance`.

**Anticipated cross-coupling** (per stage, N/m with P in W, D and H in m, N in rpm):

* centrifugal compressor impeller: ``q_A = B_c C P_r / (D_c H_c N_r) · (ρ_d / ρ_s)``, B_c = 3;
* axial compressor / turbine stage: ``q_A = B_t C P_r / (D_t H_t N_r)``, B_t = 1.5;

C = 9.55 (the standard's constant, ≈ 60/2π: P/N is then the stage torque), P_r the rated power
of the stage, D_c the impeller diameter / D_t the blade pitch diameter, H_c the minimum of the
diffuser and impeller discharge widths / H_t the effective blade height, N_r the normal operating
speed of the stage's shaft, ρ_d/ρ_s the discharge-to-suction gas density ratio of the stage.
(The standard's US-unit form uses C = 63 with hp, in and rpm, giving klbf/in.) Q_A = Σ q_A.

**Level I.** The rotor on its bearings, without the model's destabilisers (its
``[[cross_couplings]]``, its ``[[seals]]`` and rotating shaft damping; bearings given for seals
can be left out too with ``exclude_bearings``), at the maximum continuous speed, with a
cross-coupled stiffness Q applied at chosen nodes (split by the stages' q_A, or by given
weights): on every such node ``kxy = σ q``, ``kyx = −σ q``, σ = +1 if the node's shaft turns
about +z and −1 if it turns about −z (meshing shafts turn oppositely), so that Q always feeds
*forward* whirl of that shaft (:class:`gearrotor.elements.CrossCoupling` is the σ = +1 case).

*The mode followed* is the one the standard names: the **first forward mode** (the log dec of
the first forward mode against the applied cross-coupling; ROSS's ``run_level1`` follows the
same mode). On a geared train that is the first forward mode *of the loaded shaft* (the shaft
carrying the largest share of Q): at Q = 0, the lowest-frequency mode that is not over-damped,
has at least ``min_lateral`` of its kinetic energy in lateral motion, whirls forward on that
shaft and moves that shaft at least as much as any other (identical shafts share their modes),
at whatever frequency (:func:`first_forward_mode`). That mode is then
followed over Q by continuation of its shape, not picked again at each Q by a rule: from the
last Q where it is known, the mode at the next Q is the one whose shape matches (mass-weighted
MAC ≥ ``MAC_MIN`` = 0.9, the runner-up at most ``MAC_MIN_GAP`` = 0.2 lower); when no mode
matches clearly, the step is halved. So the followed mode cannot leave the analysis as Q grows
(no frequency window judges it) and no other mode is substituted for it. Where the followed
mode's character changes along the way (its type, the shaft it mostly moves, its whirl on the
loaded shaft), the result lists the change (``mode_changes``) and the chart marks it.
*A continuation step* needs the followed mode and the least log dec of the forward lateral modes
(below), not every eigenvector: it computes every eigenvalue (the dense QR algorithm without the
eigenvectors, ~2/3 of the full solve's cost), then by inverse iteration the eigenvectors of only
the two modes nearest the predicted eigenvalue and of the least-damped candidates, in order of
log dec up to the first one judged, classified as :func:`modal` classifies them. Where that
cannot decide as the full solve would (the nearest mode is not clearly nearest, so the shape
rule, which reads every mode, decides; a mode read lies in a cluster or is rigid-body; inverse
iteration does not converge), the step is solved in full (:func:`modal`, every eigenvector), as
are the first-mode search at Q → 0+ and Q = 0; the two give the same followed mode and the same
numbers to round-off (``tests/audit/test_stability.py`` compares them). The least
log dec of every forward lateral mode below 3× the fastest shaft speed is reported beside it
(``curve_least_log_dec``; an unstable one up to twice that too), and judged as a fourth
criterion, gearrotor's addition to the standard's: another forward mode weaker than the
followed one at Q_A is visible, not hidden, and sends the machine to Level II as well.

*The threshold* Q_0 is the least Q > 0 where the rotor loses stability under the applied
cross-coupling: where the followed mode's log dec, or that of a weaker forward lateral mode
(below 3× the fastest shaft speed, or unstable at any frequency solved for), reaches zero
(``threshold_mode`` names the mode that does; on the steam turbine's original bearings it is not
the first forward mode, which veers away from the pinion's conical whirl). It is searched on
both sides of Q_A: the path from 0 to Q_A is sampled (at least quarters of Q_A, finer where the
continuation needs it) and the first sign change there is the bracket; when the log dec stays
positive up to Q_A, the bracket is found by secant extrapolation beyond Q_A up to
``ratio_limit × Q_A`` (10, the range the standard asks for). Brent's method then finds Q_0 to
``|Q_0 − Q_0*| ≤ rtol·Q_0``. Level I passes when

1. the log dec (of the followed mode) at Q_A is at least 0.1, and so is that of every forward
   lateral mode below 3× the fastest shaft speed, none being unstable above (gearrotor's
   addition);
2. Q_0 / Q_A ≥ 2.0;
3. not (2.0 ≤ Q_0/Q_A < 10 with the machine in region B of the screening chart): the critical
   speed ratio CSR = MCS / (first forward critical speed on rigid supports) against the average
   gas density ρ_avg = (ρ_suction + ρ_discharge)/2 of the casing. Region B is above the boundary
   CSR = 2.5 for ρ ≤ 16.53 kg/m³, CSR = 2.69 − 0.0115 ρ for 16.53 < ρ ≤ 60 kg/m³ (2.0 at 60), and
   every CSR beyond 60 kg/m³ (the chart's end). Applied when the average density is given
   (required with centrifugal stages); with Q_A given directly and no density it is reported as
   not evaluated, and the chart draws the machine's CSR as a line over every density;

otherwise a Level II analysis is required. A larger Q_A can never make Level I pass: the
log dec at Q_A falls and Q_0/Q_A shrinks as Q_A grows (``tests/audit/test_stability.py``
checks the verdict's monotony on the steam-turbine train).

**Level II.** The damped modes of the model as given (bearings and seals as coefficient tables,
``[[cross_couplings]]``, rotating shaft damping) at the given speed(s); acceptance: every forward
lateral mode below ``max_frequency`` has a log dec of at least 0.1, and no mode is unstable.

**The modes the criteria judge** (:func:`criterion_class`, the one definition Level I, Level II
and the HTML report's stability checks use): a mode that is not over-damped, whirls forward on
the shaft with the largest lateral amplitude, has at least ``min_lateral`` (0.5) of its
kinetic energy in lateral motion (a pad mode, type ``P``, never: its energy is mostly the
pads') and a damped frequency up to the window, ``WINDOW_MULTIPLE`` (3) × the fastest shaft's
speed (:func:`stability_window`; the destabilising forces the criteria guard against, the
aerodynamic and seal cross-coupling and the oil films, drive forward whirl below running
speed, and the window includes twice that with margin). Every other mode is shown with the
reason it is not judged (``"backward"``, ``"not lateral"``, ``"above window"``,
``"over-damped"``), and any mode that grows is a failure whatever it is (:func:`is_unstable`:
its damping ratio below −``ROUNDOFF``, modal's round-off level, so that a nearly free mode
computed at log dec ±1e-7 — an unloaded tilting pad — is not called unstable by its round-off).

**Verdict vocabulary** (one word per outcome, the same in tables, JSON and the report):
``"pass"``; ``"level II required"`` (Level I: a criterion not met sends the machine to Level II,
which is not a failure); ``"fail"`` (Level II); ``"not evaluated"``.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray
from scipy.optimize import brentq

from ...assembly import Assembly, assemble
from ...errors import ModelError
from ...model import NodeRef, Train
from ...model.speed_range import model_max_continuous_speed
from ...threads import limit, managed
from ...units import to_si
from ..lateral.modal import (
    ROUNDOFF,
    TYPE_THRESHOLD,
    ModalResult,
    _check_mass,
    _classify,
    auto_method,
    modal,
)
from ..lateral.whirl import frequency_dependent
from .ucs import rigid_support_criticals

__all__ = [
    "EDITION",
    "EDITIONS",
    "Edition",
    "edition",
    "Stage",
    "Site",
    "Criterion",
    "Level1Result",
    "Level2Result",
    "anticipated_cross_coupling",
    "csr_boundary",
    "screening_region",
    "first_forward_mode",
    "forward_lateral_modes",
    "criterion_class",
    "is_unstable",
    "stability_window",
    "WINDOW_MULTIPLE",
    "UNSTABLE_LOG_DEC",
    "level1",
    "level2",
    "mid_span",
    "SCREENING_DENSITY_LIMIT",
    "VERDICTS",
]

RPM = 30 / np.pi
B_CENTRIFUGAL = 3.0
B_AXIAL = 1.5
C_SI = 9.55  # the standard's constant with W, m, rpm -> N/m (≈ 60 / 2π)
LOG_DEC_MIN = 0.1  # Level I (at Q_A) and Level II acceptance
WINDOW_MULTIPLE = 3.0  # the criteria judge modes up to this multiple of the fastest shaft speed
#: log dec below which a mode grows: damping ratio < −ROUNDOFF (ζ = δ/√(4π² + δ²)), the level
#: at which modal reports a mode undamped (its log dec 0) and below which it calls it unstable
UNSTABLE_LOG_DEC = -2 * np.pi * ROUNDOFF / np.sqrt(1 - ROUNDOFF**2)
RATIO_MIN = 2.0  # Level I: Q_0 / Q_A
RATIO_SCREEN = 10.0  # Level I: the screening chart applies below this Q_0 / Q_A
MAC_MIN = 0.9  # continuation: least shape correlation of the followed mode between two Q
MAC_MIN_GAP = 0.2  # ... and by how much it must beat the runner-up
MAX_HALVINGS = 12  # continuation: step halvings before a tie is taken as a degeneracy
SOLVE_BUDGET = 200  # eigen-solves of one Level I after which every tie is taken so
START_FRACTION = 1e-3  # × Q_A: the small Q that splits a degenerate first forward mode
TIE = 1e-6  # relative: a shaft moving as much as the most moved one, to round-off
FIRST_MODE_REACH = (2.0, 4.0, 8.0)  # × the window: where the first forward mode is sought
#: targeted step: an eigenvalue this close (relative) to another is a cluster, solved in full
CLUSTER_GAP = 1e-4
#: targeted step: inverse iteration has converged when an iterate turns by less than this (rad)
VECTOR_TOL = 1e-10
#: targeted step: most modes it reads by inverse iteration (~0.4 ms each on the steam turbine's
#: 192 DOFs, where the full solve takes 55 ms and its eigenvalues alone 35 ms); beyond: in full
TARGETED_MODES = 40
#: targeted steps stop when the fall-backs outnumber them by this many (each costs ~2/3 of a
#: full solve more): e.g. a shaft free axially and in torsion, whose rigid-body eigenvalue
#: pairs at ~0 are candidates of the least log dec that inverse iteration cannot separate
FALLBACK_LIMIT = 4
_TARGETED = True  # the continuation steps by the targeted solve (False: every step in full)
#: the outcomes of a check, in every table, JSON file and report
VERDICTS = ("pass", "level II required", "fail", "not evaluated")


@dataclass(frozen=True)
class Edition:
    """An edition of API 617 as the audit applies it (see the module docstring)."""

    key: str  # "8th" or "9th"
    name: str  # "API 617 8th edition (2014)"
    level1: str  # paragraphs of Level I
    level2: str  # paragraphs of Level II
    unbalance: str  # paragraphs of the unbalance response analysis

    def __str__(self) -> str:
        return self.name


EDITIONS = {
    "8th": Edition(
        "8th",
        "API 617 8th edition (2014)",
        "1.6.5 (Level I)",
        "1.6.6 (Level II)",
        "1.6.2 (4x the residual unbalance at the model's unbalance planes)",
    ),
    "9th": Edition(
        "9th",
        "API 617 9th edition (2022)",
        "6.8.5 (Level I)",
        "6.8.6 (Level II)",
        "6.8.2.7 (2x the residual unbalance at the mode shape's antinodes), "
        "6.8.2.10-6.8.2.11 (close clearances)",
    ),
}
_ALIASES = {
    "8": "8th",
    "8th": "8th",
    "api 617 8th edition": "8th",
    "api 617 8th edition (2014)": "8th",
    "9": "9th",
    "9th": "9th",
    "api 617 9th edition": "9th",
    "api 617 9th edition (2022)": "9th",
}
#: the edition used when none is given
DEFAULT_EDITION = "8th"
EDITION = EDITIONS[DEFAULT_EDITION].name  # the default edition's title


def edition(value: str | Edition | None = None, field: str = "edition") -> Edition:
    """The :class:`Edition` named by ``value`` (``"8th"``, ``"9th"``, ``"8"``, ``"9"`` or the
    full title, any case; None: the default, the 8th)."""
    if isinstance(value, Edition):
        return value
    if value is None:
        return EDITIONS[DEFAULT_EDITION]
    key = _ALIASES.get(str(value).strip().lower())
    if key is None:
        raise ModelError(
            "unknown API 617 edition",
            field=field,
            value=value,
            expected="'8th' (API 617 8th edition, 2014) or '9th' (9th edition, 2022)",
        )
    return EDITIONS[key]


_edition = edition  # for the functions whose ``edition`` argument hides it


SCREENING_DENSITY_LIMIT = 60.0  # kg/m³, end of the screening chart's boundary


# --------------------------------------------------------------------------------------------
# inputs
@dataclass(frozen=True)
class Stage:
    """One impeller or blade row: the inputs of the anticipated cross-coupling q_A.

    ``power`` W (or e.g. ``"1.2 MW"``), ``diameter`` and ``width`` m (or with units): for
    ``kind="centrifugal"`` the impeller diameter D_c and the minimum of the diffuser and impeller
    discharge widths H_c, with the stage's discharge/suction gas ``density_ratio`` ρ_d/ρ_s; for
    ``kind="axial"`` (axial compressor or turbine stage) the blade pitch diameter D_t and the
    effective blade height H_t (no density ratio). ``shaft``/``node``: where q_A acts."""

    shaft: str
    node: int
    power: float | str
    diameter: float | str
    width: float | str
    density_ratio: float | str = 1.0
    kind: str = "centrifugal"

    def __post_init__(self) -> None:
        for name, kind in (
            ("power", "power"),
            ("diameter", "length"),
            ("width", "length"),
            ("density_ratio", "dimensionless"),
        ):
            raw = getattr(self, name)
            try:
                v = to_si(raw, kind)
            except ValueError as exc:
                raise ModelError(str(exc), field=f"stage.{name}", value=raw) from None
            if not (np.isfinite(v) and v > 0):
                raise ModelError(
                    f"a stage's {name.replace('_', ' ')} must be positive",
                    field=f"stage.{name}",
                    value=raw,
                    expected="a positive value" + (" (ρ_d/ρ_s)" if name == "density_ratio" else ""),
                )
            object.__setattr__(self, name, v)
        if self.kind not in ("centrifugal", "axial"):
            raise ModelError(
                "unknown stage kind",
                field="stage.kind",
                value=self.kind,
                expected="'centrifugal' (impeller) or 'axial' (axial compressor/turbine stage)",
            )


@dataclass(frozen=True)
class Site:
    """A node where the Level I cross-coupling acts, with its share ``weight`` of Q."""

    shaft: str
    node: int
    weight: float = 1.0


def mid_span(model: Train | Assembly, shaft: str, weight: float = 1.0) -> Site:
    """The :class:`Site` at the node nearest the middle of ``shaft``'s bearing span (its
    outermost radial bearings; the whole shaft without two bearings): where API 617 applies
    Q_A on a between-bearing rotor."""
    train = _train(model)
    si = train.shaft_index(shaft, "at.shaft")
    z = train.layout().shafts[si].z
    nodes = [
        train.node_index(b, f"bearings[{k}]")[1]
        for k, b in enumerate(train.bearings)
        if b.shaft == shaft
    ]
    lo, hi = (z[min(nodes)], z[max(nodes)]) if len(nodes) >= 2 else (z[0], z[-1])
    return Site(shaft, int(np.argmin(np.abs(z - 0.5 * (lo + hi)))), weight)


def anticipated_cross_coupling(stage: Stage, speed: float) -> float:
    """q_A (N/m) of one stage at the normal operating speed ``speed`` of its shaft (rad/s,
    sign ignored); see the module docstring for the formulas."""
    n_rpm = abs(speed) * RPM
    if not n_rpm > 0:
        raise ModelError(
            "the anticipated cross-coupling needs the stage's normal operating speed",
            field="operating_speed",
            value=speed,
            expected="a non-zero speed",
        )
    if stage.kind == "centrifugal":
        return (
            B_CENTRIFUGAL
            * C_SI
            * stage.power
            / (stage.diameter * stage.width * n_rpm)
            * stage.density_ratio
        )
    return B_AXIAL * C_SI * stage.power / (stage.diameter * stage.width * n_rpm)


def csr_boundary(density) -> NDArray:
    """The region A / B boundary CSR of the Level I screening chart at average gas densities
    ``density`` (kg/m³, up to ``SCREENING_DENSITY_LIMIT``)."""
    rho = np.asarray(density, float)
    return np.where(rho <= 16.53, 2.5, 2.69 - 0.0115 * rho)


def screening_region(csr: float, density: float) -> str:
    """``"A"`` (below the boundary) or ``"B"`` (on or above it, or beyond the chart)."""
    if density > SCREENING_DENSITY_LIMIT:
        return "B"
    return "A" if csr < float(csr_boundary(density)) else "B"


# --------------------------------------------------------------------------------------------
# results
@dataclass(frozen=True)
class Criterion:
    """One acceptance criterion: ``ok`` True (met), False (not met), None (not evaluated);
    ``if_not_met`` names the outcome of a criterion not met (Level I: ``"level II required"``,
    which is not a failure)."""

    name: str
    value: float | None
    requirement: str
    ok: bool | None  # None: not evaluated
    if_not_met: str = "level II required"

    @property
    def status(self) -> str:
        """``"pass"``, :attr:`if_not_met` or ``"not evaluated"`` (see :data:`VERDICTS`)."""
        return {True: "pass", False: self.if_not_met, None: "not evaluated"}[self.ok]

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "value": self.value,
            "requirement": self.requirement,
            "ok": self.ok,
            "status": self.status,
        }


def _mode_summary(res: ModalResult, i: int) -> dict:
    lat = [
        float(
            np.sum(
                np.abs(res.mode_shapes[i][offs]) ** 2 + np.abs(res.mode_shapes[i][offs + 1]) ** 2
            )
        )
        for offs in res.assembly.node_offset
    ]
    return {
        "frequency_rpm": float(res.frequency_rpm[i]),
        "frequency_hz": float(res.frequency_hz[i]),
        "log_dec": float(res.log_dec[i]),
        "whirl": res.whirl[i],
        "whirl_per_shaft": dict(zip(res.shaft_names, res.whirl_per_shaft[i], strict=True)),
        "type": res.mode_type[i],
        "shaft": res.shaft_names[int(np.argmax(lat))],
        "energy_lateral": float(res.energy_fractions[i, 0]),
    }


class _Verdict:
    """What the stability results share: a ``verdict``, one of :data:`VERDICTS`, and whether it
    is ``"pass"``."""

    verdict: str

    @property
    def passed(self) -> bool:
        return self.verdict == "pass"


@dataclass(frozen=True)
class Level1Result(_Verdict):
    """API 617 Level I stability (see the module docstring). Speeds rad/s, Q in N/m."""

    edition: str
    speed: float  # reference-shaft speed of the analysis (the MCS; signed as the model's), rad/s
    operating_speed: float | None  # reference-shaft N_r of the q_A formula, rad/s
    qa: float  # Q_A, N/m
    sites: tuple[Site, ...]  # where Q acts, weights summing to 1
    stage_q: tuple[float, ...]  # q_A per stage (empty when Q_A was given)
    log_dec_at_qa: float
    mode_at_qa: dict
    threshold_q: float | None  # Q_0; None: log dec > 0 up to q_max
    q_max: float
    threshold_mode: dict | None
    curve_q: NDArray
    curve_log_dec: NDArray
    csr: float | None
    csr_per_shaft: dict
    average_density: float | None
    region: str | None
    criteria: tuple[Criterion, ...]
    verdict: str  # "pass" or "level II required"
    n_solves: int
    rtol: float
    criterion_log_dec: float = LOG_DEC_MIN
    excluded: dict = field(default_factory=dict)
    edition_key: str = DEFAULT_EDITION
    followed_mode: str = ""  # which mode Level I follows, in words
    loaded_shaft: str = ""  # the shaft whose first forward mode is followed
    curve_least_log_dec: NDArray = field(default_factory=lambda: np.zeros(0))
    least_log_dec_at_qa: float | None = None  # least of every forward lateral mode at Q_A
    mode_changes: tuple[dict, ...] = ()  # where the followed mode's character changes
    unresolved_steps: int = 0  # continuation steps taken by the nearest eigenvalue after a tie

    @property
    def ratio(self) -> float | None:
        """Q_0 / Q_A (None when Q_0 lies beyond ``q_max``)."""
        return None if self.threshold_q is None else self.threshold_q / self.qa

    def to_dict(self) -> dict:
        return {
            "edition": self.edition,
            "edition_key": self.edition_key,
            "speed_rpm": self.speed * RPM,
            "followed_mode": self.followed_mode,
            "loaded_shaft": self.loaded_shaft,
            "operating_speed_rpm": (
                None if self.operating_speed is None else self.operating_speed * RPM
            ),
            "qa_N_per_m": self.qa,
            "stage_qa_N_per_m": list(self.stage_q),
            "sites": [{"shaft": s.shaft, "node": s.node, "weight": s.weight} for s in self.sites],
            "log_dec_at_qa": self.log_dec_at_qa,
            "least_forward_log_dec_at_qa": self.least_log_dec_at_qa,
            "mode_at_qa": self.mode_at_qa,
            "mode_changes": list(self.mode_changes),
            "threshold_q_N_per_m": self.threshold_q,
            "q_max_N_per_m": self.q_max,
            "ratio_q0_qa": self.ratio,
            "threshold_mode": self.threshold_mode,
            "csr": self.csr,
            "csr_per_shaft": self.csr_per_shaft,
            "average_density_kg_per_m3": self.average_density,
            "region": self.region,
            "criteria": [c.to_dict() for c in self.criteria],
            "verdict": self.verdict,
            "excluded": self.excluded,
            "n_solves": self.n_solves,
            "unresolved_steps": self.unresolved_steps,
            "rtol": self.rtol,
            "curve": {
                "q_N_per_m": [float(v) for v in self.curve_q],
                "log_dec": [float(v) for v in self.curve_log_dec],
                "least_forward_log_dec": [
                    None if not np.isfinite(v) else float(v) for v in self.curve_least_log_dec
                ],
            },
        }

    def table(self) -> str:
        q0 = (
            f"{self.threshold_q:.5g} N/m"
            if self.threshold_q is not None
            else f"> {self.q_max:.5g} N/m (no threshold)"
        )
        ratio = f"{self.ratio:.3f}" if self.ratio is not None else f"> {self.q_max / self.qa:g}"
        rows = [
            f"{self.edition}: Level I",
            f"  speed {self.speed * RPM:.0f} rpm (reference shaft)",
            f"  Q_A = {self.qa:.5g} N/m at "
            + ", ".join(f"{s.shaft}:{s.node} ({s.weight:.3g})" for s in self.sites),
            f"  mode followed: {self.followed_mode}",
            f"  log dec at Q_A = {self.log_dec_at_qa:.4f} ({self.mode_at_qa['frequency_rpm']:.0f}"
            f" rpm, {self.mode_at_qa['shaft']}, {self.mode_at_qa['type']})",
        ]
        if self.least_log_dec_at_qa is not None:
            rows.append(
                f"  least log dec of every forward lateral mode at Q_A = "
                f"{self.least_log_dec_at_qa:.4f}"
            )
        rows.append(f"  Q_0 = {q0}, Q_0/Q_A = {ratio}")
        if self.threshold_mode is not None:
            m = self.threshold_mode
            rows.append(
                f"  mode at Q_0: {m['frequency_rpm']:.0f} rpm, {m['shaft']}, whirl "
                f"{'/'.join(m['whirl_per_shaft'].values())}, {m['type']}"
            )
        for c in self.mode_changes:
            rows.append(
                f"  followed mode changes between Q = {c['q_from_N_per_m']:.4g} and "
                f"{c['q_to_N_per_m']:.4g} N/m: {c['from']} -> {c['to']}"
            )
        if self.csr is not None:
            dens = (
                f", average density {self.average_density:.4g} kg/m³, region {self.region}"
                if self.average_density is not None
                else ""
            )
            rows.append(f"  CSR = {self.csr:.3f}{dens}")
        for c in self.criteria:
            val = "-" if c.value is None else f"{c.value:.4g}"
            rows.append(f"  [{c.status}] {c.name}: {val} ({c.requirement})")
        rows.append(f"  Level I verdict: {self.verdict}")
        return "\n".join(rows)


@dataclass(frozen=True)
class Level2Mode:
    frequency: float  # damped, rad/s
    log_dec: float
    whirl: str
    whirl_per_shaft: tuple[str, ...]
    mode_type: str
    energy_lateral: float
    forward: bool  # a forward lateral mode: the acceptance applies
    unstable: bool
    ok: bool


@dataclass(frozen=True)
class Level2Evaluation:
    speed: float  # reference shaft, rad/s
    modes: tuple[Level2Mode, ...]
    ok: bool

    @property
    def min_forward_log_dec(self) -> float | None:
        d = [m.log_dec for m in self.modes if m.forward]
        return min(d) if d else None


@dataclass(frozen=True)
class Level2Result(_Verdict):
    """API 617 Level II: damped modes with every modelled destabiliser at each speed."""

    edition: str
    evaluations: tuple[Level2Evaluation, ...]
    shaft_names: tuple[str, ...]
    max_frequency: tuple[float, ...]  # rad/s, per speed
    min_lateral: float
    verdict: str  # "pass" or "fail"
    criterion_log_dec: float = LOG_DEC_MIN

    def to_dict(self) -> dict:
        return {
            "edition": self.edition,
            "criterion_log_dec": self.criterion_log_dec,
            "min_lateral": self.min_lateral,
            "verdict": self.verdict,
            "speeds": [
                {
                    "speed_rpm": ev.speed * RPM,
                    "max_frequency_rpm": fm * RPM,
                    "ok": ev.ok,
                    "min_forward_log_dec": ev.min_forward_log_dec,
                    "modes": [
                        {
                            "frequency_rpm": m.frequency * RPM,
                            "frequency_hz": m.frequency / (2 * np.pi),
                            "log_dec": m.log_dec,
                            "whirl": m.whirl,
                            "whirl_per_shaft": dict(
                                zip(self.shaft_names, m.whirl_per_shaft, strict=True)
                            ),
                            "type": m.mode_type,
                            "energy_lateral": m.energy_lateral,
                            "forward": m.forward,
                            "unstable": m.unstable,
                            "ok": m.ok,
                            "check": {"-": "not judged"}.get(_mode_check(m), _mode_check(m)),
                        }
                        for m in ev.modes
                    ],
                }
                for ev, fm in zip(self.evaluations, self.max_frequency, strict=True)
            ],
        }

    def table(self) -> str:
        rows = [
            f"{self.edition}: Level II (log dec >= {self.criterion_log_dec:g} per forward "
            "lateral mode, no unstable mode; '-': a mode the criterion does not judge)"
        ]
        head = (
            f"{'speed rpm':>10} {'freq rpm':>10} {'log dec':>9} {'whirl':>7} {'type':>5} "
            f"{'lat':>5} {'fwd':>4} {'check':>5}"
        )
        rows += [head, "-" * len(head)]
        for ev in self.evaluations:
            for m in ev.modes:
                rows.append(
                    f"{ev.speed * RPM:>10.0f} {m.frequency * RPM:>10.1f} {m.log_dec:>9.4f} "
                    f"{'/'.join(m.whirl_per_shaft):>7} {m.mode_type:>5} {m.energy_lateral:>5.2f} "
                    f"{'F' if m.forward else '-':>4} {_mode_check(m):>5}"
                )
        rows.append(f"Level II verdict: {self.verdict}")
        return "\n".join(rows)


def _mode_check(m: Level2Mode) -> str:
    """A Level II mode's check: pass/fail for a judged mode (forward lateral, or unstable), "-"
    for a mode the acceptance does not judge (backward, torsional, axial)."""
    if not (m.forward or m.unstable):
        return "-"
    return "pass" if m.ok else "fail"


# --------------------------------------------------------------------------------------------
def stability_window(speed_ratio: NDArray, speed: float) -> float:
    """rad/s: the highest damped frequency the criteria judge at reference-shaft ``speed``
    (rad/s), ``WINDOW_MULTIPLE`` × the fastest shaft's speed (``speed_ratio``: the shafts'
    speeds per unit reference speed, :attr:`Assembly.speed_ratio`)."""
    return WINDOW_MULTIPLE * abs(float(speed)) * float(np.max(np.abs(speed_ratio)))


def criterion_class(
    *,
    frequency: NDArray,
    energy_lateral: NDArray,
    whirl: Sequence[str],
    overdamped: NDArray,
    mode_type: Sequence[str] | None = None,
    window: float | None = None,
    min_lateral: float = 0.5,
) -> NDArray:
    """Per mode, whether the stability criteria judge it (module docstring): ``"judged"``,
    or why not: ``"over-damped"``, ``"not lateral"`` (less than ``min_lateral`` of its kinetic
    energy in lateral motion, or a bearing-internal mode ``P``: the pads', or the fitted
    states' of a speed × whirl table), ``"backward"`` (whirl on the shaft with
    the largest lateral amplitude), ``"above window"`` (damped ``frequency`` above ``window``,
    rad/s; None: no limit). Arrays of one value per mode (a modal result's, or one speed of a
    Campbell diagram's tracks; NaN frequencies are over-damped there). An unstable mode fails
    whatever its class (:func:`is_unstable`)."""
    f = np.asarray(frequency, float)
    out = np.full(f.shape, "judged", dtype=object)
    lat = np.asarray(energy_lateral, float) >= min_lateral
    if mode_type is not None:
        lat &= np.array([t != "P" for t in mode_type], bool).reshape(f.shape)
    fwd = np.array([w == "F" for w in whirl], bool).reshape(f.shape)
    if window is not None:
        out[~(f <= window)] = "above window"
    out[~fwd] = "backward"
    out[~lat] = "not lateral"
    out[np.asarray(overdamped, bool) | np.isnan(f)] = "over-damped"
    return out


def is_unstable(log_dec) -> NDArray:
    """Whether a mode of this log decrement grows: below ``UNSTABLE_LOG_DEC`` (damping
    ratio < −``ROUNDOFF``, as :attr:`ModalResult.unstable`); NaN (no mode) is not."""
    d = np.asarray(log_dec, float)
    return d < UNSTABLE_LOG_DEC


def forward_lateral_modes(
    res: ModalResult, min_lateral: float = 0.5, max_frequency: float | None = None
) -> NDArray:
    """Indices of the modes the stability criteria apply to (:func:`criterion_class`
    ``"judged"``): not over-damped, at least ``min_lateral`` of the kinetic energy in lateral
    motion (the helical mesh's axial, the train's torsional and the pads' modes are left out),
    whirling forward on the shaft with the largest lateral amplitude
    (:attr:`ModalResult.whirl`), below ``max_frequency`` (rad/s) when given."""
    cls = criterion_class(
        frequency=res.damped_frequency,
        energy_lateral=res.energy_fractions[:, 0],
        whirl=res.whirl,
        overdamped=res.overdamped,
        mode_type=res.mode_type,
        window=max_frequency,
        min_lateral=min_lateral,
    )
    return np.flatnonzero(cls == "judged")


def _train(model) -> Train:
    return model.train if isinstance(model, Assembly) else model


def _default_speed(train: Train, speed, what: str) -> float:
    if speed is not None:
        w = abs(float(speed))
        if not w > 0:
            raise ModelError(f"{what} needs a non-zero speed", field="speed", value=speed)
        return w
    return model_max_continuous_speed(train, f"{what} (evaluated at the maximum continuous speed)")


def _sites(train: Train, at, stages, qs) -> tuple[Site, ...]:
    if at:
        raw = [a if isinstance(a, Site) else Site(*a) for a in at]
    else:
        raw = [Site(s.shaft, s.node, q) for s, q in zip(stages, qs, strict=True)]
    for k, s in enumerate(raw):
        if not (isinstance(s.node, int | np.integer) and s.node >= 0):
            raise ModelError(
                "a node index must be a non-negative integer", field=f"at[{k}].node", value=s.node
            )
        train.node_index(NodeRef(shaft=s.shaft, node=int(s.node)), f"at[{k}]")
        if not (np.isfinite(s.weight) and s.weight > 0):
            raise ModelError(
                "a site weight must be positive", field=f"at[{k}].weight", value=s.weight
            )
    total = sum(s.weight for s in raw)
    return tuple(Site(s.shaft, int(s.node), s.weight / total) for s in raw)


def _level1_train(train: Train, exclude_bearings: Sequence[str]) -> tuple[Train, dict]:
    """The Level I model: the train without its destabilisers (cross-couplings, seals,
    rotating shaft damping) and without the bearings named in ``exclude_bearings`` (a
    ``[[seals]]`` entry's name is accepted too: seals are left out anyway)."""
    names = [b.name or f"bearings[{k}]" for k, b in enumerate(train.bearings)]
    seal_names = [sl.name or f"seals[{k}]" for k, sl in enumerate(train.seals)]
    for e in exclude_bearings:
        if e not in names and e not in seal_names:
            raise ModelError(
                "no such bearing or seal to exclude",
                field="exclude_bearings",
                value=e,
                expected=f"one of {names + seal_names}",
            )
    materials = {}
    dropped_damping = []
    for name, m in train.materials.items():
        if m.damping is not None and m.damping.rotating:
            materials[name] = m.model_copy(update={"damping": None})
            dropped_damping.append(name)
        else:
            materials[name] = m
    bare = train.model_copy(
        update={
            "cross_couplings": [],
            "seals": [],
            "bearings": [
                b for b, n in zip(train.bearings, names, strict=True) if n not in exclude_bearings
            ],
            "materials": materials,
        }
    )
    excluded = {
        "cross_couplings": [
            c.name or f"cross_couplings[{k}]" for k, c in enumerate(train.cross_couplings)
        ],
        "seals": seal_names,
        "bearings": [e for e in exclude_bearings if e in names],
        "rotating_damping_materials": dropped_damping,
    }
    return bare, excluded


def _unit_coupling(asm: Assembly, sites: tuple[Site, ...]) -> sp.csr_array:
    """Σ_sites weight·σ·[[0, 1], [−1, 0]] at the sites' x, y DOFs (per unit Q)."""
    rows, cols, vals = [], [], []
    train = asm.train
    for s in sites:
        si, node = train.node_index(NodeRef(shaft=s.shaft, node=s.node), "at")
        spin = asm.speed_ratio[si] * (train.speed if train.speed != 0 else 1.0)
        sigma = 1.0 if spin >= 0 else -1.0
        d = asm.dof(si, node, 0)
        rows += [d, d + 1]
        cols += [d + 1, d]
        vals += [sigma * s.weight, -sigma * s.weight]
    return sp.coo_array((vals, (rows, cols)), shape=(asm.n_dof, asm.n_dof)).tocsr()


def _mass_mac(M, a: NDArray, b: NDArray) -> NDArray:
    """Mass-weighted modal assurance criterion of shape ``a`` (n_dof,) against each row of
    ``b`` (m, n_dof): |aᴴMb|² / (aᴴMa · bᴴMb), in [0, 1], blind to a shape's complex scale."""
    Mb = (M @ b.T).T
    ab = np.abs(Mb @ np.conj(a)) ** 2
    aa = float(np.real(np.conj(a) @ (M @ a)))
    bb = np.real(np.einsum("ij,ij->i", np.conj(b), Mb))
    return ab / np.maximum(aa * bb, 1e-300)


def _shaft_amplitudes(res: ModalResult, i: int) -> NDArray:
    """Σ |x|² + |y|² over each shaft's nodes of mode i."""
    phi = res.mode_shapes[i]
    offsets = res.assembly.node_offset
    return np.array([float(np.sum(np.abs(phi[o]) ** 2 + np.abs(phi[o + 1]) ** 2)) for o in offsets])


def first_forward_mode(
    res: ModalResult,
    shaft: int,
    min_lateral: float = 0.5,
    max_frequency: float | None = None,
    among: NDArray | None = None,
) -> int | None:
    """Index of the first forward mode of shaft ``shaft`` (index into the train's shafts): the
    lowest-frequency mode (up to ``max_frequency``, rad/s) that is not over-damped, has at least
    ``min_lateral`` of its kinetic energy in lateral motion, whirls forward on that shaft and
    moves it more than any other shaft; None if there is none."""
    for i in range(len(res)):  # modes are sorted by damped frequency
        if max_frequency is not None and res.damped_frequency[i] > max_frequency:
            break
        if res.overdamped[i] or res.energy_fractions[i, 0] < min_lateral:
            continue
        if res.whirl_per_shaft[i][shaft] != "F":
            continue
        amp = _shaft_amplitudes(res, i)
        if amp[shaft] < (1.0 - TIE) * np.max(amp):  # ties: identical shafts share their modes
            continue
        return i
    return None


@dataclass
class _Point:
    q: float
    eigenvalue: complex
    shape: NDArray
    mode: dict  # _mode_summary of the followed mode
    least_log_dec: float | None  # least log dec of the forward lateral modes (see _store)
    halvings: int
    least_mode: dict | None = None  # _mode_summary of that least-damped forward mode

    @property
    def stability(self) -> float:
        """The log dec that decides Q_0: the followed mode's, or a forward lateral mode's that
        is weaker (:attr:`least_log_dec`), whichever is less."""
        d = self.mode["log_dec"]
        return d if self.least_log_dec is None else min(d, self.least_log_dec)

    @property
    def weakest_mode(self) -> dict:
        """The mode whose log dec is :attr:`stability`."""
        if self.least_log_dec is None or self.mode["log_dec"] <= self.least_log_dec:
            return self.mode
        return self.least_mode


class _Pencil:
    """The Level I eigenproblem at the analysis speed as a function of Q, built once for the
    targeted continuation step (:meth:`_Follower._targeted`): the quadratic pencil
    P_Q(λ) = λ²M + λ(C+G) + K + Q·ΔK and its first-order state matrix
    A(Q) = [[0, I], [−M⁻¹(K + QΔK), −M⁻¹(C+G)]], whose blocks per unit Q are kept."""

    def __init__(self, asm: Assembly, dK, speed: float):
        M, C, G, K = asm.matrices(speed)
        self.asm, self.speed = asm, speed
        self.M, self.Cg, self.K = M.tocsc(), sp.csc_array(C + G), K.tocsc()
        self.dK = sp.csc_array(dK)
        cho = _check_mass(M.toarray(), asm)
        n = asm.n_dof
        self.A0 = np.zeros((2 * n, 2 * n))
        self.A0[:n, n:] = np.eye(n)
        self.A0[n:, :n] = -la.cho_solve(cho, K.toarray())
        self.A0[n:, n:] = -la.cho_solve(cho, (C + G).toarray())
        self.dA = -la.cho_solve(cho, self.dK.toarray())  # A's lower-left block per unit Q
        # inverse iteration starts from a fixed generic vector (every mode's component non-zero)
        self.start = np.random.default_rng(20261128).standard_normal(n) + 0j

    def eigenvalues(self, q: float) -> NDArray:
        """Every eigenvalue at Q = ``q`` (the dense QR algorithm of the full solve, without its
        eigenvectors: about 2/3 of its cost)."""
        n = self.asm.n_dof
        A = self.A0.copy()
        A[n:, :n] += q * self.dA
        with limit(2 * n, "eig"):
            return la.eigvals(A, overwrite_a=True, check_finite=False)

    def vector(self, q: float, lam: complex) -> NDArray | None:
        """The eigenvector (n_dof,) of the eigenvalue ``lam`` at Q = ``q`` by inverse iteration
        on P_Q(lam) (one sparse LU): converged when an iterate turns by less than
        ``VECTOR_TOL`` (radians) from the last; None when it does not within four steps."""
        try:
            lu = spla.splu(sp.csc_array(lam * lam * self.M + lam * self.Cg + self.K + q * self.dK))
        except RuntimeError:  # P(lam) exactly singular: the full solve takes the step
            return None
        x = self.start / np.linalg.norm(self.start)
        for _ in range(4):
            y = lu.solve(x)
            if not np.all(np.isfinite(y)):
                return None
            y /= np.linalg.norm(y)
            turn = np.linalg.norm(y - (np.conj(x) @ y) * x)  # sine of the angle from x
            x = y
            if turn <= VECTOR_TOL:
                return x
        return None

    def modes(self, q: float, lam: NDArray, vectors: NDArray, fmax: float) -> ModalResult:
        """The modal result of the eigenpairs (``lam``, columns of ``vectors``) at Q = ``q``,
        classified as :func:`modal` classifies them (its default tolerances)."""
        res = _classify(
            lam,
            vectors,
            self.asm,
            self.asm.shaft_speeds(self.speed),
            self.K + q * self.dK,
            rigid_tol=1e-2,
            overdamped_zeta=0.999,
            type_threshold=TYPE_THRESHOLD,
            max_frequency=fmax,
        )
        return ModalResult(
            speed=self.speed,
            shaft_speeds=self.asm.shaft_speeds(self.speed),
            method="targeted",
            n_eigenvalues=len(lam),
            shaft_names=tuple(s.name for s in self.asm.train.shafts),
            assembly=self.asm,
            **res,
        )


class _Follower:
    """The first forward mode of the loaded shaft at Q = 0, followed over Q by continuation
    (see the module docstring); every solve cached by Q. ``targeted``: continuation steps by
    the targeted solve (:meth:`_targeted`), falling back to the full solve when it cannot
    decide; False: every step solved in full."""

    def __init__(self, asm, dK, speed, window, shaft, min_lateral, q_scale, targeted=True):
        self.asm, self.dK, self.speed = asm, dK, speed
        self.window, self.shaft, self.min_lateral = window, shaft, min_lateral
        self.points: dict[float, _Point] = {}
        self.n_solves = 0
        self.n_unresolved = 0  # steps that stayed ambiguous after MAX_HALVINGS (degenerate)
        self.n_targeted = 0  # steps taken by the targeted solve (the others: full solves)
        self.n_every_mode = 0  # ... of which read every mode (the nearest did not decide)
        # the targeted step reproduces modal's dense solve: not for speed × whirl tables (fitted
        # states added to the eigenproblem) nor for models modal solves sparsely
        self.targeted = (
            targeted and not frequency_dependent(asm) and auto_method(asm.n_dof, 1.0) == "dense"
        )
        self._pencil: _Pencil | None = None
        self.fallbacks: dict[str, int] = {}  # targeted steps solved in full, by reason
        # The first forward mode of the limit Q -> 0+, at whatever frequency (a stiff pinion's
        # may lie above 3x its speed: sought below 2, 4, then 8 times the window). It is chosen
        # at a small Q, q_s = START_FRACTION × Q_A, which splits degenerate eigenvalues (an
        # isotropic rigid rotor's forward and backward cylindrical modes, identical shafts'
        # shared modes: any basis of such a cluster is an eigenvector basis at Q = 0) the way Q
        # does; the point at Q = 0 is the mode of Q = 0 nearest in eigenvalue.
        q_s = START_FRACTION * q_scale
        for reach in FIRST_MODE_REACH:
            res_s = self._solve(q_s, reach * window)
            j = first_forward_mode(res_s, shaft, min_lateral)
            if j is not None:
                break
        if j is None:
            raise ModelError(
                "no forward lateral mode of the loaded shaft to follow",
                field="at",
                value=asm.train.shafts[shaft].name,
                expected="a shaft with a forward lateral mode below 24x the fastest shaft speed "
                "at Q = 0 (check the sites and the bearings)",
            )
        res = self._solve(0.0, reach * window)
        i = int(np.argmin(np.abs(res.eigenvalues - res_s.eigenvalues[j])))
        self._store(0.0, res, i, 0)
        self._store(q_s, res_s, j, 0)
        # at Q = 0 the eigenvalue of Q = 0, and the shape and character of the mode Q splits off
        p0, ps = self.points[0.0], self.points[q_s]
        p0.shape = ps.shape
        p0.mode = {
            **ps.mode,
            **{k: p0.mode[k] for k in ("frequency_rpm", "frequency_hz", "log_dec")},
        }

    def _solve(self, q: float, fmax: float) -> ModalResult:
        self.n_solves += 1
        a = dataclasses.replace(self.asm, K0=(self.asm.K0 + q * self.dK).tocsr())
        return modal(a, speed=self.speed, max_frequency=fmax)

    def _store(self, q: float, res: ModalResult, i: int, halvings: int) -> None:
        # least log dec of the forward lateral modes below the window (3x the fastest shaft
        # speed, as Level II), and of any unstable one found beyond it
        fwd = forward_lateral_modes(res, self.min_lateral)
        d = res.log_dec[fwd]
        judged = fwd[(res.damped_frequency[fwd] <= self.window) | (d < 0)]
        k = int(judged[np.argmin(res.log_dec[judged])]) if len(judged) else None
        self.points[q] = _Point(
            q,
            complex(res.eigenvalues[i]),
            res.mode_shapes[i],
            _mode_summary(res, i),
            None if k is None else float(res.log_dec[k]),
            halvings,
            None if k is None else _mode_summary(res, k),
        )

    def _predict(self, qa: float, qb: float) -> complex:
        """The followed eigenvalue at qb, extrapolated linearly from the last two path points
        at or below qa."""
        below = sorted(k for k in self.points if k <= qa)
        pa = self.points[below[-1]]
        if len(below) < 2:
            return pa.eigenvalue
        pp = self.points[below[-2]]
        return pa.eigenvalue + (pa.eigenvalue - pp.eigenvalue) * (qb - qa) / (qa - pp.q)

    def _match(self, qa: float, qb: float, res: ModalResult, last: bool) -> int | None:
        """The mode of ``res`` (at qb) that continues the followed mode from qa: the one nearest
        the predicted eigenvalue when it is clearly nearest (4× nearer than the next) with a
        similar shape, or the one whose shape clearly matches; None when neither is clear (or,
        on the ``last`` halving, the nearest eigenvalue: a persisting tie is a degenerate
        eigenvalue, where either choice has the same log dec)."""
        if not len(res):
            return None
        prev = self.points[qa]
        lam = np.asarray(res.eigenvalues)
        mac = _mass_mac(self.asm.M, prev.shape, np.asarray(res.mode_shapes))
        d = np.abs(lam - self._predict(qa, qb))
        by_d = np.argsort(d)
        k1 = int(by_d[0])
        d2 = float(d[by_d[1]]) if len(by_d) > 1 else np.inf
        if mac[k1] >= 0.5 and d[k1] <= 0.25 * d2:
            return k1
        by_m = np.argsort(mac)[::-1]
        m1 = int(by_m[0])
        m2 = float(mac[by_m[1]]) if len(by_m) > 1 else 0.0
        if mac[m1] >= MAC_MIN and m2 <= mac[m1] - MAC_MIN_GAP:
            return m1
        if last:
            self.n_unresolved += 1
            return k1
        return None

    def _targeted(self, qa: float, qb: float, fmax: float) -> ModalResult | None:
        """The step's modal result at qb without the full solve's every eigenvector, as good as
        the full solve's for :meth:`_match` and :meth:`_store`: every eigenvalue
        (:meth:`_Pencil.eigenvalues`), then by inverse iteration the eigenvectors of only

        * the two modes nearest the predicted eigenvalue, when the nearest decides the step by
          :meth:`_match`'s first rule (4× nearer than the next, MAC ≥ 0.5), which reads no
          other mode; else of every mode (up to ``TARGETED_MODES``), for its shape rule;
        * the least-damped candidates of :meth:`_store`'s least log dec (damped frequency up
          to the window, or growing), in order of log dec, up to the first one judged (with
          any of the same log dec): no mode left out can have a lower log dec;

        classified as the full solve classifies them (:meth:`_Pencil.modes`; a rigid-body
        eigenvalue is no mode there either). None — the step is solved in full — when a mode it
        reads is in a cluster (another eigenvalue within ``CLUSTER_GAP``·|λ|, where an
        eigenvector is a choice), inverse iteration does not converge, or it would read more
        than ``TARGETED_MODES`` modes."""
        if self._pencil is None:
            self._pencil = _Pencil(self.asm, self.dK, self.speed)
        pen = self._pencil
        lam = pen.eigenvalues(qb)
        if not np.all(np.isfinite(lam)):
            return self._fallback("non-finite")
        # the eigenvalues the full solve lists as modes (over Im λ > 0 beyond round-off, up to
        # fmax); a rigid-body one among those read is found by the classification
        mu = lam[(lam.imag > ROUNDOFF * np.maximum(np.abs(lam), 1.0)) & (lam.imag <= fmax)]
        if len(mu) < 2:
            return self._fallback("fewer than two modes")
        d = np.abs(mu - self._predict(qa, qb))
        k1, k2 = (int(j) for j in np.argsort(d)[:2])
        undamped = np.abs(mu.real) <= ROUNDOFF * np.abs(mu)
        log_dec = np.where(undamped, 0.0, -2 * np.pi * mu.real / mu.imag)
        cand = np.flatnonzero((mu.imag <= self.window) | (log_dec < 0))
        cand = cand[np.lexsort((mu.imag[cand], log_dec[cand]))]  # as _store's argmin breaks ties
        vectors: dict[int, NDArray] = {}

        def read(js) -> ModalResult | None:
            """The modal result of modes ``js`` (indices into mu), None if one cannot be read"""
            if len(js) > TARGETED_MODES:
                return self._fallback("too many modes")
            for j in js:
                if j not in vectors:
                    if np.sort(np.abs(lam - mu[j]))[1] <= CLUSTER_GAP * abs(mu[j]):
                        return self._fallback("cluster")
                    x = pen.vector(qb, complex(mu[j]))
                    if x is None:
                        return self._fallback("inverse iteration")
                    vectors[j] = x
            # (a rigid-body eigenvalue is no mode of the result, as in the full solve's)
            return pen.modes(qb, mu[js], np.array([vectors[j] for j in js]).T, fmax)

        js = list(dict.fromkeys([k1, k2, *cand[:1].tolist()]))  # the usual reads, in one go
        res = read(js)
        if res is None:
            return None
        i1 = np.flatnonzero(res.eigenvalues == mu[k1])
        nearest_decides = (
            np.isin(mu[[k1, k2]], res.eigenvalues).all()  # modes: the full solve's two nearest
            and d[k1] <= 0.25 * d[k2]
            and _mass_mac(self.asm.M, self.points[qa].shape, res.mode_shapes[i1])[0] >= 0.5
        )
        if not nearest_decides:
            self.n_every_mode += 1
            js = list(range(len(mu)))
            res = read(js)
            if res is None:
                return None
        judged_at = None
        for p, j in enumerate(cand):
            if judged_at is not None and log_dec[j] > log_dec[cand[judged_at]]:
                break
            if j not in js:
                js.append(int(j))
                res = read(js)
                if res is None:
                    return None
            if judged_at is None:
                fwd = res.eigenvalues[forward_lateral_modes(res, self.min_lateral)]
                judged_at = p if np.any(fwd == mu[j]) else None
        self.n_targeted += 1
        return res

    def _fallback(self, reason: str) -> None:
        """Count a targeted step handed to the full solve, by ``reason``."""
        self.fallbacks[reason] = self.fallbacks.get(reason, 0) + 1

    def _step(self, qa: float, qb: float, depth: int) -> None:
        """Continue the followed mode from qa (known) to qb, halving the step while the match
        is ambiguous."""
        prev = self.points[qa]
        fmax = max(2.0 * self.window, 3.0 * abs(prev.eigenvalue))
        res = self._targeted(qa, qb, fmax) if self.targeted else None
        if sum(self.fallbacks.values()) >= self.n_targeted + FALLBACK_LIMIT:
            self.targeted = False  # most steps fall back (e.g. free axial and torsional modes)
        if res is None:
            res = self._solve(qb, fmax)
        else:
            self.n_solves += 1
        k = self._match(qa, qb, res, depth >= MAX_HALVINGS or self.n_solves >= SOLVE_BUDGET)
        if k is not None:
            self._store(qb, res, k, depth)
            return
        mid = 0.5 * (qa + qb)
        self._step(qa, mid, depth + 1)
        self._step(mid, qb, depth + 1)

    def at(self, q: float) -> _Point:
        q = float(q)
        if q not in self.points:
            q_prev = max(k for k in self.points if k <= q)
            self._step(q_prev, q, 0)
        return self.points[q]

    def __call__(self, q: float) -> float:
        return self.at(q).stability

    def first_crossing(self, q_hi: float) -> tuple[float, float] | None:
        """The first interval (a, b) of the known path within [0, q_hi] where the deciding log
        dec (:attr:`_Point.stability`) goes from > 0 to <= 0."""
        qs = sorted(k for k in self.points if k <= q_hi)
        for a, b in itertools.pairwise(qs):
            if self.points[a].stability > 0 >= self.points[b].stability:
                return a, b
        return None


def _mode_key(m: dict, shaft: str, min_lateral: float) -> tuple:
    """What the chart calls the followed mode's character: the shaft it mostly moves, its whirl
    on the loaded shaft, and whether it is a lateral mode (lateral kinetic energy at least
    ``min_lateral``). Its type letters are not part of it: a share crossing the 5 % naming
    threshold (L-T to L-T-A) is no change of mode."""
    return (m["shaft"], m["whirl_per_shaft"].get(shaft, "-"), m["energy_lateral"] >= min_lateral)


def _mode_label(m: dict, shaft: str) -> str:
    return (
        f"{m['type']} ({m['energy_lateral']:.0%} lateral), mostly {m['shaft']}, whirl "
        f"{m['whirl_per_shaft'].get(shaft, '-')} on {shaft}"
    )


@managed
def level1(
    model: Train | Assembly,
    *,
    qa: float | None = None,
    stages: Sequence[Stage] = (),
    at: Sequence[Site | tuple] = (),
    speed: float | None = None,
    operating_speed: float | None = None,
    average_density: float | None = None,
    exclude_bearings: Sequence[str] = (),
    ratio_limit: float = RATIO_SCREEN,
    max_frequency: float | None = None,
    min_lateral: float = 0.5,
    rtol: float = 1e-4,
    n_curve: int = 11,
    edition: str | Edition | None = None,
) -> Level1Result:
    """API 617 Level I stability analysis (see the module docstring).

    Parameters
    ----------
    model : the train (or its assembly)
    qa : N/m, the anticipated cross-coupling Q_A given directly (then ``at`` is required); or
    stages : the stages whose q_A make up Q_A (:class:`Stage`); Q acts at their nodes in
        proportion to their q_A unless ``at`` is given
    at : sites ``(shaft, node[, weight])`` or :class:`Site` where Q acts, split by the weights
        (default equal): e.g. mid-span for a between-bearing rotor
    speed : rad/s, reference-shaft speed of the analysis (default: the model's
        ``max_continuous_speed``)
    operating_speed : rad/s, reference-shaft normal operating speed N_r of the q_A formula
        (default: the model's nominal ``speed``); each stage uses its own shaft's speed
    average_density : kg/m³, average of suction and discharge gas densities, for the screening
    exclude_bearings : names of ``[[bearings]]`` entries (seals given as bearings) left out of
        Level I; a ``[[seals]]`` entry's name is accepted too (seals are always left out)
    ratio_limit : Q_0 is searched up to ``ratio_limit × Q_A``
    max_frequency : rad/s, the least log dec of every forward lateral mode is taken below it
        (default 3× the fastest shaft speed), with any unstable forward lateral mode up to twice
        that (or 3× the followed mode's frequency) too; the first forward mode is sought at any
        frequency (below 24× the window) and traced wherever it goes
    min_lateral : lateral kinetic-energy fraction of a mode to be judged
    rtol : relative tolerance of Q_0
    n_curve : points of the log dec curve from 0 to beyond max(Q_A, Q_0) (the plot; 0: none)
    edition : ``"8th"`` (default) or ``"9th"`` (:func:`edition`)
    """
    ed = _edition(edition)
    train = _train(model)
    stages = tuple(stages)
    if (qa is None) == (not stages):
        raise ModelError(
            "Level I needs the anticipated cross-coupling: give either qa or the stages",
            field="qa / stages",
            expected="qa (N/m) with 'at' sites, or a list of Stage",
        )
    if qa is not None:
        qa = float(to_si(qa, "stiffness")) if isinstance(qa, str) else float(qa)
        if not (np.isfinite(qa) and qa > 0):
            raise ModelError("Q_A must be positive", field="qa", value=qa, expected="N/m > 0")
        if not at:
            raise ModelError(
                "Q_A given directly needs the nodes where it acts",
                field="at",
                expected="one or more (shaft, node) sites",
            )
    if average_density is not None and not (np.isfinite(average_density) and average_density > 0):
        raise ModelError(
            "the average gas density must be positive",
            field="average_density",
            value=average_density,
            expected="kg/m³ > 0",
        )
    if any(s.kind == "centrifugal" for s in stages) and average_density is None:
        raise ModelError(
            "centrifugal stages need the average gas density for the Level I screening chart",
            field="average_density",
            expected="(suction + discharge density)/2 in kg/m³",
        )
    if not (ratio_limit > RATIO_MIN and rtol > 0):
        raise ModelError(
            "bad search limits",
            field="ratio_limit / rtol",
            value=(ratio_limit, rtol),
            expected="ratio_limit > 2, rtol > 0",
        )
    w = _default_speed(train, speed, "Level I")
    stage_q: tuple[float, ...] = ()
    n_r = None
    if stages:
        n_r = abs(float(operating_speed)) if operating_speed is not None else abs(train.speed)
        if not n_r > 0:
            raise ModelError(
                "the q_A formula needs the normal operating speed",
                field="operating_speed",
                expected="the operating_speed argument or a non-zero model speed",
            )
        ratios = train.shaft_speeds(1.0)
        stage_q = tuple(
            anticipated_cross_coupling(
                s, ratios[train.shaft_index(s.shaft, f"stages[{k}].shaft")] * n_r
            )
            for k, s in enumerate(stages)
        )
        qa = float(sum(stage_q))
    sites = _sites(train, at, stages, stage_q)
    for e in exclude_bearings:
        if not isinstance(e, str):
            raise ModelError("bearings are excluded by name", field="exclude_bearings", value=e)
    bare, excluded = _level1_train(train, exclude_bearings)
    asm = assemble(bare)
    window = max_frequency if max_frequency is not None else stability_window(asm.speed_ratio, w)
    sense = 1.0 if train.speed >= 0 else -1.0
    share: dict[str, float] = {}
    for s in sites:
        share[s.shaft] = share.get(s.shaft, 0.0) + s.weight
    loaded = max(share, key=share.__getitem__)
    si_loaded = train.shaft_index(loaded, "at")
    f = _Follower(
        asm,
        _unit_coupling(asm, sites),
        sense * w,
        window,
        si_loaded,
        min_lateral,
        qa,
        targeted=_TARGETED,
    )

    # Q_0: the first zero of the followed log dec, on both sides of Q_A
    q_max = ratio_limit * qa
    f0 = f(0.0)
    q0 = None
    if f0 <= 0:
        q0 = 0.0
    else:
        for k in range(1, 5):  # the path from 0 to Q_A, at least by quarters
            f.at(qa * k / 4)
        bracket = f.first_crossing(qa)
        if bracket is None:
            bracket = _bracket(f, qa, f(qa * 0.75), f(qa), q_max)
        if bracket is not None:
            q0 = float(brentq(f, *bracket, xtol=1e-9 * qa, rtol=rtol))
    fa = f.at(qa).mode["log_dec"]
    threshold_mode = f.at(q0).weakest_mode if q0 is not None else None

    if n_curve:
        q_hi = min(q_max, 1.25 * max(qa, q0 or 0.0))
        for q in np.linspace(0.0, q_hi, n_curve):
            f.at(q)
    pts = [f.points[q] for q in sorted(f.points)]
    curve_q = np.array([p.q for p in pts])
    curve_d = np.array([p.mode["log_dec"] for p in pts])
    curve_least = np.array([np.nan if p.least_log_dec is None else p.least_log_dec for p in pts])
    changes = []
    for p, r in itertools.pairwise(pts):
        if _mode_key(p.mode, loaded, min_lateral) != _mode_key(r.mode, loaded, min_lateral):
            changes.append(
                {
                    "q_from_N_per_m": p.q,
                    "q_to_N_per_m": r.q,
                    "from": _mode_label(p.mode, loaded),
                    "to": _mode_label(r.mode, loaded),
                }
            )
    m0 = f.points[0.0].mode
    followed = (
        f"the first forward mode of shaft '{loaded}' at Q = 0 ({m0['frequency_rpm']:.0f} rpm, "
        f"{_mode_label(m0, loaded)}), followed over Q by continuation of its shape"
    )

    # critical speed ratio per loaded shaft
    rigid = rigid_support_criticals(bare)
    csr_per = {}
    for s in dict.fromkeys(site.shaft for site in sites):
        si = train.shaft_index(s, "at")
        nc1 = rigid[s][0]
        mcs_s = abs(asm.speed_ratio[si]) * w
        csr_per[s] = {
            "mcs_rpm": mcs_s * RPM,
            "first_rigid_critical_rpm": None if not np.isfinite(nc1) else float(nc1 * RPM),
            "csr": None if not np.isfinite(nc1) else float(mcs_s / nc1),
        }
    csrs = [v["csr"] for v in csr_per.values() if v["csr"] is not None]
    csr = max(csrs) if csrs else None
    region = (
        screening_region(csr, average_density)
        if csr is not None and average_density is not None
        else None
    )

    ratio = None if q0 is None else q0 / qa
    pa = f.at(qa)
    least = pa.least_log_dec
    crit = [
        Criterion("log dec at Q_A", fa, f">= {LOG_DEC_MIN:g}", bool(fa >= LOG_DEC_MIN)),
        Criterion(
            "least log dec of every forward lateral mode at Q_A",
            least,
            f">= {LOG_DEC_MIN:g} below 3x the fastest shaft speed, none unstable above "
            "(gearrotor's addition: the standard judges the first forward mode)",
            None if least is None else bool(least >= LOG_DEC_MIN),
        ),
        Criterion(
            "Q_0 / Q_A", ratio, f">= {RATIO_MIN:g}", bool(ratio is None or ratio >= RATIO_MIN)
        ),
    ]
    screen_needed = ratio is not None and RATIO_MIN <= ratio < ratio_limit
    if region is not None:
        ok = not (screen_needed and region == "B")
        req = f"region A when {RATIO_MIN:g} <= Q_0/Q_A < {ratio_limit:g}"
        crit.append(Criterion("screening chart region", csr, req, ok))
    else:
        crit.append(
            Criterion(
                "screening chart region",
                csr,
                "not evaluated: no average gas density given"
                if csr is not None
                else "not evaluated: no rigid-support critical speed",
                None,
            )
        )
    verdict = "pass" if all(c.ok is not False for c in crit) else "level II required"
    return Level1Result(
        edition=ed.name,
        edition_key=ed.key,
        speed=sense * w,
        operating_speed=n_r,
        qa=qa,
        sites=sites,
        stage_q=stage_q,
        log_dec_at_qa=fa,
        mode_at_qa=pa.mode,
        threshold_q=q0,
        q_max=q_max,
        threshold_mode=threshold_mode,
        curve_q=curve_q,
        curve_log_dec=curve_d,
        csr=csr,
        csr_per_shaft=csr_per,
        average_density=average_density,
        region=region,
        criteria=tuple(crit),
        verdict=verdict,
        n_solves=f.n_solves,
        rtol=rtol,
        excluded=excluded,
        followed_mode=followed,
        loaded_shaft=loaded,
        curve_least_log_dec=curve_least,
        least_log_dec_at_qa=pa.least_log_dec,
        mode_changes=tuple(changes),
        unresolved_steps=f.n_unresolved,
    )


def _bracket(f, qa, d_prev_q, fa, q_max):
    """A bracket (a, b) with f(a) > 0 >= f(b) beyond Q_A, by secant steps on the log dec
    (about linear in Q while the mode keeps its identity) from the last two points of the path
    (0.75 Q_A, Q_A), each step at least ×1.2 and at most ×4 the last Q; None when f stays
    positive up to q_max. Each new point is reached by continuation from the last."""
    q_prev, d_prev, q, d = 0.75 * qa, d_prev_q, qa, fa
    while q < q_max:
        slope = (d - d_prev) / (q - q_prev)
        guess = q - 1.05 * d / slope if slope < 0 else 4 * q
        guess = min(max(guess, 1.2 * q), 4 * q, q_max)
        dg = f(guess)
        if dg <= 0:
            return f.first_crossing(guess) or (q, guess)
        q_prev, d_prev, q, d = q, d, guess, dg
    return None


@managed
def level2(
    model: Train | Assembly,
    *,
    speeds: float | Sequence[float] | None = None,
    max_frequency: float | None = None,
    min_lateral: float = 0.5,
    edition: str | Edition | None = None,
) -> Level2Result:
    """API 617 Level II stability: damped modes of the model as given (every modelled
    destabiliser) at reference-shaft ``speeds`` (rad/s; default the model's
    ``max_continuous_speed``); acceptance: log dec >= 0.1 for every forward lateral mode
    (:func:`forward_lateral_modes`) below ``max_frequency`` (rad/s, default 3× the fastest shaft
    speed at each speed) and no unstable mode. ``edition``: ``"8th"`` (default) or ``"9th"``
    (the same acceptance; the result names it)."""
    ed = _edition(edition)
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    if speeds is None:
        ws = [_default_speed(train, None, "Level II")]
    else:
        ws = [_default_speed(train, s, "Level II") for s in np.atleast_1d(speeds)]
    evals, fmaxes = [], []
    for w in ws:
        fmax = max_frequency if max_frequency is not None else stability_window(asm.speed_ratio, w)
        sense = 1.0 if train.speed >= 0 else -1.0
        res = modal(asm, speed=sense * w, max_frequency=fmax)
        fwd = set(forward_lateral_modes(res, min_lateral, fmax).tolist())
        modes = []
        for i in range(len(res)):
            unstable = bool(is_unstable(res.log_dec[i]))
            is_fwd = i in fwd
            ok = not unstable and (not is_fwd or bool(res.log_dec[i] >= LOG_DEC_MIN))
            modes.append(
                Level2Mode(
                    float(res.damped_frequency[i]),
                    float(res.log_dec[i]),
                    res.whirl[i],
                    tuple(res.whirl_per_shaft[i]),
                    res.mode_type[i],
                    float(res.energy_fractions[i, 0]),
                    is_fwd,
                    unstable,
                    ok,
                )
            )
        growing = bool(np.any(res.real_eigenvalues[~res.rigid_body] > 0))
        evals.append(
            Level2Evaluation(sense * w, tuple(modes), all(m.ok for m in modes) and not growing)
        )
        fmaxes.append(float(fmax))
    return Level2Result(
        edition=ed.name,
        evaluations=tuple(evals),
        shaft_names=tuple(s.name for s in train.shafts),
        max_frequency=tuple(fmaxes),
        min_lateral=min_lateral,
        verdict="pass" if all(e.ok for e in evals) else "fail",
    )
