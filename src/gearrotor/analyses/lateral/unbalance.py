"""Steady-state unbalance response over a speed sweep (SPEC 3.2), API 684 / API 617 checks.

At reference speed Ω each shaft s turns at Ω_s = ratio_s·Ω; an unbalance m·e at phase φ on shaft
s rotates with angle θ = Ω_s t + φ and loads its node with
``F_x = m e Ω_s² cos θ``, ``F_y = m e Ω_s² sin θ``, i.e. complex amplitudes at ω = |Ω_s|
``F_x = m e ω² e^{iσφ}``, ``F_y = −iσ m e ω² e^{iσφ}`` with σ = sign(Ω_s) and x(t) = Re(X e^{iωt}).
Shafts at different speeds excite different frequencies: the response is computed per distinct
frequency; a probe reports the component synchronous with its own shaft (what a tracking filter
keyed to that shaft measures) and the total of all components is available too.

Amplitudes are zero-to-peak (m) unless a name says ``pp`` (peak-to-peak).

API 684 amplification factor by the half-power method: ``AF = N_c / (N_2 − N_1)`` with N_1, N_2
the speeds where the amplitude is ``peak/√2`` on either side of the peak ``N_c``. Separation
margins required by API 617 (8th ed.): none when AF < 2.5; otherwise
``SM = 17 (1 − 1/(AF − 1.5))`` % below the minimum operating speed and
``SM = 10 + 17 (1 − 1/(AF − 1.5))`` % (capped at 26 %) above the maximum continuous speed.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from ...assembly import Assembly, assemble
from ...errors import ModelError, SolverError
from ...model import Train
from ...model.speed_range import model_operating_range
from ...threads import managed

__all__ = [
    "UnbalanceResult",
    "ProbeResponse",
    "CriticalSpeed",
    "unbalance_response",
    "api617_unbalance",
    "api617_vibration_limit",
    "api617_required_margin",
    "critical_speeds",
    "shaft_masses",
]


def api617_unbalance(
    journal_mass: float, max_continuous_speed: float, factor: float = 4.0
) -> float:
    """API 617 residual unbalance for the response analysis, kg·m.

    ``U = factor × 6350 W/N`` g·mm with W the journal static load (kg) and N the maximum
    continuous speed (rpm); ``max_continuous_speed`` in rad/s. API 617 asks for 4× the
    allowable residual unbalance (factor = 4).
    """
    n_rpm = abs(max_continuous_speed) * 30 / np.pi
    if n_rpm <= 0:
        raise ModelError("API 617 unbalance needs a non-zero maximum continuous speed")
    return factor * 6350.0 * journal_mass / n_rpm * 1e-6  # g·mm -> kg·m


def api617_vibration_limit(max_continuous_speed: float) -> float:
    """API 617 allowable peak-to-peak vibration (m): 25.4 µm √(12000/N), at most 25.4 µm."""
    n_rpm = abs(max_continuous_speed) * 30 / np.pi
    return min(25.4, 25.4 * np.sqrt(12000.0 / n_rpm)) * 1e-6


def api617_required_margin(af: float, below: bool) -> float:
    """Required separation margin (%) for a critical with amplification factor ``af``."""
    if af < 2.5:
        return 0.0
    base = 17.0 * (1.0 - 1.0 / (af - 1.5))
    return base if below else min(10.0 + base, 26.0)


@dataclass(frozen=True)
class CriticalSpeed:
    speed: float  # reference-shaft speed of the peak, rad/s
    probe_speed: float  # the probe shaft's speed at the peak, rad/s
    amplitude: float  # 0-pk, m
    amplification_factor: float | None  # None when a half-power point lies outside the sweep
    half_power: tuple[float | None, float | None]  # probe-shaft speeds, rad/s
    separation_margin: float | None  # actual, % of the operating-speed bound
    required_margin: float | None  # API 617, %
    ok: bool | None


@dataclass(frozen=True)
class ProbeResponse:
    name: str
    shaft: int
    angle: float
    response: NDArray  # complex (n_speeds,), along the probe direction, synchronous component
    major: NDArray  # (n_speeds,) orbit semi-major axis (m)
    minor: NDArray  # (n_speeds,) semi-minor axis, signed: > 0 forward orbit
    criticals: tuple[CriticalSpeed, ...]

    @property
    def amplitude(self) -> NDArray:
        return np.abs(self.response)

    @property
    def phase(self) -> NDArray:
        """Phase lag (deg) of the response behind the shaft's keyphasor."""
        return -np.angle(self.response, deg=True)


@dataclass(frozen=True)
class UnbalanceResult:
    speeds: NDArray  # reference-shaft speeds, rad/s
    frequencies: NDArray  # (n_speeds, n_groups) excitation frequencies, rad/s
    group_of_shaft: NDArray  # (n_shafts,) index of each shaft's frequency group
    response: NDArray  # complex (n_speeds, n_groups, n_dof)
    probes: tuple[ProbeResponse, ...]
    shaft_names: tuple[str, ...]
    operating_range: tuple[float, float]  # reference-shaft speeds, rad/s
    vibration_limit: NDArray  # per probe, API 617 pk-pk (m)
    assembly: Assembly = field(repr=False)

    def node_response(self, shaft: int, node: int) -> tuple[NDArray, NDArray]:
        """(X, Y) complex amplitudes synchronous with the node's shaft, (n_speeds,) each."""
        g = self.group_of_shaft[shaft]
        d = self.assembly.dof(shaft, node, 0)
        return self.response[:, g, d], self.response[:, g, d + 1]

    def to_dict(self) -> dict:
        rpm = 30 / np.pi
        um = 1e6
        probes = []
        for p, lim in zip(self.probes, self.vibration_limit, strict=True):
            k = int(np.argmax(p.amplitude))
            probes.append(
                {
                    "name": p.name,
                    "shaft": self.shaft_names[p.shaft],
                    "peak_amplitude_um": float(p.amplitude[k] * um),
                    "peak_amplitude_pp_um": float(2 * p.amplitude[k] * um),
                    "peak_speed_rpm": float(self.speeds[k] * rpm),
                    "api617_limit_pp_um": float(lim * um),
                    "amplitude_um": (p.amplitude * um).tolist(),
                    "phase_deg": p.phase.tolist(),
                    "critical_speeds": [
                        {
                            "speed_rpm": c.speed * rpm,
                            "probe_shaft_speed_rpm": c.probe_speed * rpm,
                            "amplitude_um": c.amplitude * um,
                            "amplification_factor": c.amplification_factor,
                            "separation_margin_pct": c.separation_margin,
                            "required_margin_pct": c.required_margin,
                            "ok": c.ok,
                        }
                        for c in p.criticals
                    ],
                }
            )
        return {
            "speeds_rpm": (self.speeds * rpm).tolist(),
            "probes": probes,
            "operating_range_rpm": [self.operating_range[0] * rpm, self.operating_range[1] * rpm],
        }

    def table(self) -> str:
        """Peaks (pk-pk, as the API 617 limit beside them) and critical speeds (0-pk at the
        peak, AF, margins, result), with a legend of the columns."""
        rpm, um = 30 / np.pi, 1e6
        rows = [f"{'probe':>12} {'peak µm pk-pk':>14} {'at rpm':>9} {'limit µm pk-pk':>15}"]
        crit = [
            f"{'probe':>12} {'critical rpm':>13} {'µm 0-pk':>9} {'AF':>7} {'SM %':>7} "
            f"{'req %':>7} {'check':>6}"
        ]
        for p, lim in zip(self.probes, self.vibration_limit, strict=True):
            k = int(np.argmax(p.amplitude))
            rows.append(
                f"{p.name:>12} {2 * p.amplitude[k] * um:>14.3f} {self.speeds[k] * rpm:>9.0f} "
                f"{lim * um:>15.2f}"
            )
            for c in p.criticals:
                af = "-" if c.amplification_factor is None else f"{c.amplification_factor:.2f}"
                sm = "-" if c.separation_margin is None else f"{c.separation_margin:.1f}"
                rq = "-" if c.required_margin is None else f"{c.required_margin:.1f}"
                ok = {True: "pass", False: "FAIL", None: "n/a"}[c.ok]
                crit.append(
                    f"{p.name:>12} {c.speed * rpm:>13.0f} {c.amplitude * um:>9.3f} "
                    f"{af:>7} {sm:>7} {rq:>7} {ok:>6}"
                )
        legend = (
            "AF: amplification factor (API 684 half-power method); SM: separation margin of the "
            "critical from the operating range; req: the API 617 required margin; check: SM ≥ "
            "req; '-' and n/a: not determined (a half-power point outside the sweep)"
        )
        return "\n".join(rows) + "\n\n" + "\n".join(crit) + "\n" + legend


def shaft_masses(asm: Assembly) -> NDArray:
    """Total translating mass (kg) of each shaft including its disks."""
    ones = np.zeros(asm.n_dof)
    out = []
    for offs in asm.node_offset:
        ones[:] = 0.0
        ones[offs] = 1.0
        out.append(float(ones @ (asm.M @ ones)))
    return np.array(out)


def _force_vectors(asm, unbalances, shaft_speeds, groups, n_groups):
    train = asm.train
    F = np.zeros((n_groups, asm.n_dof), complex)
    for k, u in enumerate(unbalances):
        si, node = train.node_index(u, f"unbalances[{k}]")
        w = shaft_speeds[si]
        s = np.sign(w) if w != 0 else 1.0
        amp = u.amount * w**2 * np.exp(1j * s * u.phase)
        d = asm.dof(si, node, 0)
        F[groups[si], d] += amp
        F[groups[si], d + 1] += -1j * s * amp
    return F


@managed
def unbalance_response(
    model: Train | Assembly,
    *,
    speeds: NDArray,
    unbalances=None,
    probes=None,
    operating_range: tuple[float, float] | None = None,
    operating_point=None,
) -> UnbalanceResult:
    """Steady-state response to unbalance over reference-shaft ``speeds`` (rad/s).

    ``unbalances``/``probes`` default to the model's. ``operating_range`` (rad/s, reference shaft):
    the bounds of the separation margins (minimum operating speed, maximum continuous speed; the
    upper one also sets the API 617 vibration limit); default: the model's
    (:func:`~gearrotor.model.speed_range.model_operating_range`), else its nominal speed for
    both bounds.

    ``operating_point`` (name or :class:`~gearrotor.model.OperatingPoint`): fluid-film bearings
    at the coefficients of the point's static loads at every speed, the point's ``hold``
    (power or torque) kept over the sweep (:func:`~gearrotor.analyses.static.at_operating_point`).
    """
    if operating_point is not None:
        # fluid-film bearings at the point's static loads at every speed (issue 11)
        from ..static.operating_point import model_at_operating_point

        model = model_at_operating_point(model, operating_point, np.asarray(speeds, float))[0]
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    unbalances = train.unbalances if unbalances is None else unbalances
    probes = train.probes if probes is None else probes
    if not unbalances:
        raise ModelError(
            "no unbalance to respond to",
            field="unbalances",
            expected="at least one [[unbalances]] entry",
        )
    speeds = np.asarray(speeds, float)
    ratio = np.abs(asm.speed_ratio)
    keys = sorted({round(r, 12) for r in ratio})
    groups = np.array([keys.index(round(r, 12)) for r in ratio])
    ng = len(keys)
    resp = np.zeros((len(speeds), ng, asm.n_dof), complex)
    freqs = np.zeros((len(speeds), ng))
    for i, w in enumerate(speeds):
        M, C, G, K = asm.matrices(w)
        shaft_speeds = asm.shaft_speeds(w)
        F = _force_vectors(asm, unbalances, shaft_speeds, groups, ng)
        for g in range(ng):
            om = keys[g] * abs(w)
            freqs[i, g] = om
            if not np.any(F[g]):
                continue
            D = (K - om**2 * M + 1j * om * (C + G)).tocsc()
            try:
                lu = spla.splu(D)
                x = lu.solve(F[g])
            except RuntimeError:
                raise SolverError(
                    f"singular dynamic stiffness at {w * 30 / np.pi:.6g} rpm: the model has an "
                    "unsupported (rigid-body) lateral motion or the speed is zero; add bearings "
                    "or start the sweep above 0 rpm"
                ) from None
            if not np.all(np.isfinite(x)):
                raise SolverError(f"non-finite unbalance response at {w * 30 / np.pi:.6g} rpm")
            resp[i, g] = x
    op = operating_range or model_operating_range(train) or (abs(train.speed), abs(train.speed))
    pres = []
    limits = []
    for k, p in enumerate(probes):
        si, node = train.node_index(p, f"probes[{k}]")
        d = asm.dof(si, node, 0)
        X, Y = resp[:, groups[si], d], resp[:, groups[si], d + 1]
        r = X * np.cos(p.angle) + Y * np.sin(p.angle)
        major, minor = _ellipse(X, Y)
        crits = critical_speeds(speeds, np.abs(r), ratio[si], op)
        pres.append(ProbeResponse(p.name, si, p.angle, r, major, minor, crits))
        limits.append(api617_vibration_limit(ratio[si] * op[1]) if op[1] else np.nan)
    return UnbalanceResult(
        speeds=speeds,
        frequencies=freqs,
        group_of_shaft=groups,
        response=resp,
        probes=tuple(pres),
        shaft_names=tuple(s.name for s in train.shafts),
        operating_range=op,
        vibration_limit=np.array(limits),
        assembly=asm,
    )


def _ellipse(X: NDArray, Y: NDArray) -> tuple[NDArray, NDArray]:
    """Semi-axes of the orbit x = Re(X e^{iωt}), y = Re(Y e^{iωt}); minor > 0 for a
    counter-clockwise (about +z) orbit."""
    # x + iy = ((X + iY) e^{iωt} + conj(X − iY) e^{−iωt}) / 2
    fwd = 0.5 * np.abs(X + 1j * Y)  # counter-clockwise circular component
    bwd = 0.5 * np.abs(X - 1j * Y)
    return fwd + bwd, fwd - bwd


@managed
def critical_speeds(
    speeds: NDArray, amplitude: NDArray, ratio: float, operating_range: tuple[float, float]
) -> tuple[CriticalSpeed, ...]:
    """Peaks of an amplitude curve with API 684 half-power amplification factors and API 617
    separation margins. ``ratio`` converts reference speeds to the probe shaft's speeds."""
    a = amplitude
    out = []
    n = len(a)
    lo_op, hi_op = (ratio * operating_range[0], ratio * operating_range[1])
    for k in range(1, n - 1):
        if not (a[k] > a[k - 1] and a[k] >= a[k + 1]):
            continue
        # parabolic refinement of the peak
        y0, y1, y2 = a[k - 1], a[k], a[k + 1]
        den = y0 - 2 * y1 + y2
        t = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        t = float(np.clip(t, -1, 1))
        sp_ = speeds[k] + t * (speeds[k + 1] - speeds[k] if t > 0 else speeds[k] - speeds[k - 1])
        peak = y1 - 0.25 * (y0 - y2) * t
        half = peak / np.sqrt(2)
        n1 = n2 = None
        j = k
        while j > 0 and a[j] > half:
            j -= 1
        if a[j] <= half and j < k:
            n1 = speeds[j] + (half - a[j]) / (a[j + 1] - a[j]) * (speeds[j + 1] - speeds[j])
        j = k
        while j < n - 1 and a[j] > half:
            j += 1
        if a[j] <= half and j > k:
            n2 = speeds[j - 1] + (a[j - 1] - half) / (a[j - 1] - a[j]) * (speeds[j] - speeds[j - 1])
        nc = ratio * sp_
        af = None
        if n1 is not None and n2 is not None and n2 > n1:
            af = float(sp_ / (n2 - n1))
        sm = req = ok = None
        if hi_op > 0:
            below = nc < lo_op
            if below:
                sm = 100.0 * (lo_op - nc) / lo_op
            elif nc > hi_op:
                sm = 100.0 * (nc - hi_op) / hi_op
            else:
                sm = 0.0
            if af is not None:
                req = api617_required_margin(af, below)
                ok = bool(sm >= req)
        out.append(
            CriticalSpeed(
                float(sp_),
                float(nc),
                float(peak),
                af,
                (
                    None if n1 is None else float(ratio * n1),
                    None if n2 is None else float(ratio * n2),
                ),
                sm,
                req,
                ok,
            )
        )
    return tuple(out)
