"""API 617 lateral stability analysis: Level I and Level II.

Edition: **API Standard 617, 8th edition (2014)**, the rotor stability analysis of the lateral
analysis (Level I screening with the anticipated cross-coupling, Level II with every destabilising
source), whose paragraphs API RP 684 (2nd edition, 2005) reproduces and explains in its stability
chapter. The formulas and limits below are those of the standard as implemented and cited by
ROSS (``ross/api_report.py``, "API 684 SP6.8.5.6 – SP6.8.5.10"); the standard's own text was not
available to the author, so its paragraph numbers are not quoted here.

**Anticipated cross-coupling** (per stage, N/m with P in W, D and H in m, N in rpm):

* centrifugal compressor impeller: ``q_A = B_c C P_r / (D_c H_c N_r) · (ρ_d / ρ_s)``, B_c = 3;
* axial compressor / turbine stage: ``q_A = B_t C P_r / (D_t H_t N_r)``, B_t = 1.5;

C = 9.55 (the standard's constant, ≈ 60/2π: P/N is then the stage torque), P_r the rated power
of the stage, D_c the impeller diameter / D_t the blade pitch diameter, H_c the minimum of the
diffuser and impeller discharge widths / H_t the effective blade height, N_r the normal operating
speed of the stage's shaft, ρ_d/ρ_s the discharge-to-suction gas density ratio of the stage.
(The standard's US-unit form uses C = 63 with hp, in and rpm, giving klbf/in.) Q_A = Σ q_A.

**Level I.** The rotor on its bearings, without the model's destabilisers (its
``[[cross_couplings]]`` and rotating shaft damping; seals given as bearings can be left out with
``exclude_bearings``), at the maximum continuous speed, with a cross-coupled stiffness Q applied
at chosen nodes (split by the stages' q_A, or by given weights): on every such node
``kxy = σ q``, ``kyx = −σ q``, σ = +1 if the node's shaft turns about +z and −1 if it turns about
−z (meshing shafts turn oppositely), so that Q always feeds *forward* whirl of that shaft
(:class:`gearrotor.elements.CrossCoupling` is the σ = +1 case). The log dec of the least-stable
forward mode (see :func:`forward_lateral_modes`) is followed against Q; the threshold Q_0 where it
reaches zero is found by Brent's method on a bracket found by secant extrapolation from Q = 0 and
Q = Q_A, to ``|Q_0 − Q_0*| ≤ rtol·Q_0``, searched up to ``ratio_limit × Q_A`` (10, the range the
standard asks for). Level I passes when

1. the log dec at Q_A is at least 0.1;
2. Q_0 / Q_A ≥ 2.0;
3. not (2.0 ≤ Q_0/Q_A < 10 with the machine in region B of the screening chart): the critical
   speed ratio CSR = MCS / (first forward critical speed on rigid supports) against the average
   gas density ρ_avg = (ρ_suction + ρ_discharge)/2 of the casing. Region B is above the boundary
   CSR = 2.5 for ρ ≤ 16.53 kg/m³, CSR = 2.69 − 0.0115 ρ for 16.53 < ρ ≤ 60 kg/m³ (2.0 at 60), and
   every CSR beyond 60 kg/m³ (the chart's end). Applied when the average density is given
   (required with centrifugal stages); with Q_A given directly and no density it is reported as
   not evaluated;

otherwise a Level II analysis is required.

**Level II.** The damped modes of the model as given (bearings and seals as coefficient tables,
``[[cross_couplings]]``, rotating shaft damping) at the given speed(s); acceptance: every forward
lateral mode below ``max_frequency`` has a log dec of at least 0.1, and no mode is unstable.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..assembly import Assembly, assemble
from ..errors import ModelError
from ..model import NodeRef, Train
from ..threads import managed
from ..units import to_si
from .modal import ModalResult, modal
from .operating import model_max_continuous_speed
from .ucs import rigid_support_criticals

__all__ = [
    "EDITION",
    "Stage",
    "Site",
    "Criterion",
    "Level1Result",
    "Level2Result",
    "anticipated_cross_coupling",
    "csr_boundary",
    "screening_region",
    "forward_lateral_modes",
    "level1",
    "level2",
    "mid_span",
    "SCREENING_DENSITY_LIMIT",
]

EDITION = "API 617 8th edition (2014) lateral stability analysis (Level I / Level II)"
RPM = 30 / np.pi
B_CENTRIFUGAL = 3.0
B_AXIAL = 1.5
C_SI = 9.55  # the standard's constant with W, m, rpm -> N/m (≈ 60 / 2π)
LOG_DEC_MIN = 0.1  # Level I (at Q_A) and Level II acceptance
RATIO_MIN = 2.0  # Level I: Q_0 / Q_A
RATIO_SCREEN = 10.0  # Level I: the screening chart applies below this Q_0 / Q_A
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
    name: str
    value: float | None
    requirement: str
    ok: bool | None  # None: not evaluated

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "value": self.value,
            "requirement": self.requirement,
            "ok": self.ok,
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


@dataclass(frozen=True)
class Level1Result:
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

    @property
    def ratio(self) -> float | None:
        """Q_0 / Q_A (None when Q_0 lies beyond ``q_max``)."""
        return None if self.threshold_q is None else self.threshold_q / self.qa

    @property
    def passed(self) -> bool:
        return self.verdict == "pass"

    def to_dict(self) -> dict:
        return {
            "edition": self.edition,
            "speed_rpm": self.speed * RPM,
            "operating_speed_rpm": (
                None if self.operating_speed is None else self.operating_speed * RPM
            ),
            "qa_N_per_m": self.qa,
            "stage_qa_N_per_m": list(self.stage_q),
            "sites": [{"shaft": s.shaft, "node": s.node, "weight": s.weight} for s in self.sites],
            "log_dec_at_qa": self.log_dec_at_qa,
            "mode_at_qa": self.mode_at_qa,
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
            "rtol": self.rtol,
            "curve": {
                "q_N_per_m": [float(v) for v in self.curve_q],
                "log_dec": [float(v) for v in self.curve_log_dec],
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
            f"  log dec at Q_A = {self.log_dec_at_qa:.4f} ({self.mode_at_qa['frequency_rpm']:.0f}"
            f" rpm, {self.mode_at_qa['shaft']}, {self.mode_at_qa['type']})",
            f"  Q_0 = {q0}, Q_0/Q_A = {ratio}",
        ]
        if self.threshold_mode is not None:
            m = self.threshold_mode
            rows.append(
                f"  mode at Q_0: {m['frequency_rpm']:.0f} rpm, {m['shaft']}, whirl "
                f"{'/'.join(m['whirl_per_shaft'].values())}, {m['type']}"
            )
        if self.csr is not None:
            dens = (
                f", average density {self.average_density:.4g} kg/m³, region {self.region}"
                if self.average_density is not None
                else ""
            )
            rows.append(f"  CSR = {self.csr:.3f}{dens}")
        for c in self.criteria:
            mark = {True: "ok", False: "FAIL", None: "n/a"}[c.ok]
            val = "-" if c.value is None else f"{c.value:.4g}"
            rows.append(f"  [{mark:>4}] {c.name}: {val} ({c.requirement})")
        rows.append(f"  verdict: {self.verdict.upper()}")
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
class Level2Result:
    """API 617 Level II: damped modes with every modelled destabiliser at each speed."""

    edition: str
    evaluations: tuple[Level2Evaluation, ...]
    shaft_names: tuple[str, ...]
    max_frequency: tuple[float, ...]  # rad/s, per speed
    min_lateral: float
    verdict: str  # "pass" or "fail"
    criterion_log_dec: float = LOG_DEC_MIN

    @property
    def passed(self) -> bool:
        return self.verdict == "pass"

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
            "lateral mode, no unstable mode)"
        ]
        head = (
            f"{'speed rpm':>10} {'freq rpm':>10} {'log dec':>9} {'whirl':>7} {'type':>5} "
            f"{'lat':>5} {'fwd':>4} {'ok':>4}"
        )
        rows += [head, "-" * len(head)]
        for ev in self.evaluations:
            for m in ev.modes:
                rows.append(
                    f"{ev.speed * RPM:>10.0f} {m.frequency * RPM:>10.1f} {m.log_dec:>9.4f} "
                    f"{'/'.join(m.whirl_per_shaft):>7} {m.mode_type:>5} {m.energy_lateral:>5.2f} "
                    f"{'F' if m.forward else '-':>4} {'ok' if m.ok else 'FAIL':>4}"
                )
        rows.append(f"verdict: {self.verdict.upper()}")
        return "\n".join(rows)


# --------------------------------------------------------------------------------------------
def forward_lateral_modes(res: ModalResult, min_lateral: float = 0.5) -> NDArray:
    """Indices of the modes the stability criteria apply to: not over-damped, at least
    ``min_lateral`` of the kinetic energy in lateral motion (the helical mesh's axial and the
    train's torsional modes are left out), whirling forward on the shaft with the largest
    lateral amplitude (:attr:`ModalResult.whirl`)."""
    keep = (~res.overdamped) & (res.energy_fractions[:, 0] >= min_lateral)
    keep &= np.array([w == "F" for w in res.whirl], bool)
    return np.flatnonzero(keep)


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
    names = [b.name or f"bearings[{k}]" for k, b in enumerate(train.bearings)]
    for e in exclude_bearings:
        if e not in names:
            raise ModelError(
                "no such bearing to exclude",
                field="exclude_bearings",
                value=e,
                expected=f"one of {names}",
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
        "seals": [sl.name or f"seals[{k}]" for k, sl in enumerate(train.seals)],
        "bearings": list(exclude_bearings),
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


class _LogDec:
    """log dec of the least-stable forward lateral mode against Q (cached per Q)."""

    def __init__(self, asm, dK, speed, max_frequency, min_lateral):
        self.asm, self.dK = asm, dK
        self.speed, self.max_frequency, self.min_lateral = speed, max_frequency, min_lateral
        self.cache: dict[float, tuple[float, dict]] = {}

    def eval(self, q: float) -> tuple[float, dict]:
        q = float(q)
        if q not in self.cache:
            a = dataclasses.replace(self.asm, K0=(self.asm.K0 + q * self.dK).tocsr())
            res = modal(a, speed=self.speed, max_frequency=self.max_frequency)
            idx = forward_lateral_modes(res, self.min_lateral)
            if not len(idx):
                raise ModelError(
                    "no forward lateral mode below max_frequency to judge the stability by",
                    field="max_frequency",
                    value=f"{self.max_frequency * RPM:.6g} rpm",
                    expected="a limit above the rotor's first forward lateral mode",
                )
            i = idx[int(np.argmin(res.log_dec[idx]))]
            self.cache[q] = (float(res.log_dec[i]), _mode_summary(res, i))
        return self.cache[q]

    def __call__(self, q: float) -> float:
        return self.eval(q)[0]


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
    exclude_bearings : names of ``[[bearings]]`` entries (seals) left out of Level I
    ratio_limit : Q_0 is searched up to ``ratio_limit × Q_A``
    max_frequency : rad/s, modes above it are not judged (default 3× the fastest shaft speed)
    min_lateral : lateral kinetic-energy fraction of a mode to be judged
    rtol : relative tolerance of Q_0
    n_curve : points of the log dec curve from 0 to beyond max(Q_A, Q_0) (the plot; 0: none)
    """
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
    fmax = max_frequency if max_frequency is not None else 3 * w * np.max(np.abs(asm.speed_ratio))
    sense = 1.0 if train.speed >= 0 else -1.0
    f = _LogDec(asm, _unit_coupling(asm, sites), sense * w, fmax, min_lateral)

    q_max = ratio_limit * qa
    f0, fa = f(0.0), f(qa)
    q0 = None
    if f0 <= 0:
        q0 = 0.0
    else:
        bracket = (0.0, qa) if fa <= 0 else _bracket(f, qa, f0, fa, q_max)
        if bracket is not None:
            q0 = float(brentq(f, *bracket, xtol=1e-9 * qa, rtol=rtol))
    threshold_mode = f.eval(q0)[1] if q0 is not None else None

    if n_curve:
        q_hi = min(q_max, 1.25 * max(qa, q0 or 0.0))
        for q in np.linspace(0.0, q_hi, n_curve):
            f(q)
    pts = sorted(f.cache.items())
    curve_q = np.array([p[0] for p in pts])
    curve_d = np.array([p[1][0] for p in pts])

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
    crit = [
        Criterion("log dec at Q_A", fa, f">= {LOG_DEC_MIN:g}", bool(fa >= LOG_DEC_MIN)),
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
        edition=EDITION,
        speed=sense * w,
        operating_speed=n_r,
        qa=qa,
        sites=sites,
        stage_q=stage_q,
        log_dec_at_qa=fa,
        mode_at_qa=f.eval(qa)[1],
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
        n_solves=len(f.cache),
        rtol=rtol,
        excluded=excluded,
    )


def _bracket(f, qa, f0, fa, q_max):
    """A bracket (a, b) with f(a) > 0 >= f(b) beyond Q_A, by secant steps on the log dec
    (about linear in Q while the mode keeps its identity), each step at least ×1.2 and at most
    ×4 the last Q; None when f stays positive up to q_max."""
    q_prev, d_prev, q, d = 0.0, f0, qa, fa
    while q < q_max:
        slope = (d - d_prev) / (q - q_prev)
        guess = q - 1.05 * d / slope if slope < 0 else 4 * q
        guess = min(max(guess, 1.2 * q), 4 * q, q_max)
        dg = f(guess)
        if dg <= 0:
            return q, guess
        q_prev, d_prev, q, d = q, d, guess, dg
    return None


@managed
def level2(
    model: Train | Assembly,
    *,
    speeds: float | Sequence[float] | None = None,
    max_frequency: float | None = None,
    min_lateral: float = 0.5,
) -> Level2Result:
    """API 617 Level II stability: damped modes of the model as given (every modelled
    destabiliser) at reference-shaft ``speeds`` (rad/s; default the model's
    ``max_continuous_speed``); acceptance: log dec >= 0.1 for every forward lateral mode
    (:func:`forward_lateral_modes`) below ``max_frequency`` (rad/s, default 3× the fastest shaft
    speed at each speed) and no unstable mode."""
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    if speeds is None:
        ws = [_default_speed(train, None, "Level II")]
    else:
        ws = [_default_speed(train, s, "Level II") for s in np.atleast_1d(speeds)]
    evals, fmaxes = [], []
    for w in ws:
        fmax = (
            max_frequency if max_frequency is not None else 3 * w * np.max(np.abs(asm.speed_ratio))
        )
        sense = 1.0 if train.speed >= 0 else -1.0
        res = modal(asm, speed=sense * w, max_frequency=fmax)
        fwd = set(forward_lateral_modes(res, min_lateral).tolist())
        modes = []
        for i in range(len(res)):
            unstable = bool(res.unstable[i])
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
        edition=EDITION,
        evaluations=tuple(evals),
        shaft_names=tuple(s.name for s in train.shafts),
        max_frequency=tuple(fmaxes),
        min_lateral=min_lateral,
        verdict="pass" if all(e.ok for e in evals) else "fail",
    )
