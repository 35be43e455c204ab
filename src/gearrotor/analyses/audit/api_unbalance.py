"""The API 617 unbalance of a train's unbalance planes (used by ``gearrotor unbalance --api`` and
``gearrotor report --api``), and the 9th edition's unbalance placed from the mode shape with its
close-clearance check.

API 617 (8th ed.) asks for the unbalance response to 4× the allowable residual unbalance,
``U = 4 × 6350 W/N`` g·mm per plane, W the journal static load (kg) of the plane and N the maximum
continuous speed (rpm) of its shaft
(:func:`~gearrotor.analyses.lateral.unbalance.api617_unbalance`).
Here W is the shaft's total translating mass (disks included) shared equally by the unbalance
planes of that shaft, and N follows from the reference-shaft maximum continuous speed and the gear
ratio; phases and nodes are the model's.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...assembly import Assembly, assemble
from ...errors import ModelError
from ...model import NodeRef, Train
from ...model.speed_range import model_max_continuous_speed
from ..lateral.unbalance import api617_unbalance, shaft_masses

__all__ = [
    "api617_basis",
    "api617_unbalances",
    "CloseClearance",
    "ClearanceCheck",
    "ModeUnbalance",
    "bearing_clearances",
    "clearance_check",
    "close_clearances",
    "mode_unbalances",
    "nodal_masses",
    "residual_unbalance",
]


def api617_basis(
    model: Train | Assembly, max_continuous_speed: float | None = None
) -> list[tuple[float, float]]:
    """Per unbalance plane of the model, ``(W, N)``: journal static load (kg; the shaft's mass
    shared by its unbalance planes) and the maximum continuous speed of its shaft (rad/s, > 0),
    for a reference-shaft maximum continuous speed ``max_continuous_speed`` (rad/s; default: the
    model's ``max_continuous_speed``)."""
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    if max_continuous_speed is None:
        max_continuous_speed = model_max_continuous_speed(train, "the API 617 unbalance")
    masses = shaft_masses(asm)
    planes: dict[str, int] = {}
    for u in train.unbalances:
        planes[u.shaft] = planes.get(u.shaft, 0) + 1
    out = []
    for k, u in enumerate(train.unbalances):
        si = train.shaft_index(u.shaft, f"unbalances[{k}].shaft")
        out.append(
            (
                float(masses[si] / planes[u.shaft]),
                float(abs(asm.speed_ratio[si] * max_continuous_speed)),
            )
        )
    return out


def api617_unbalances(
    model: Train | Assembly, max_continuous_speed: float | None = None, *, factor: float = 4.0
) -> list:
    """The model's unbalances with their amounts replaced by the API 617 amounts (kg·m).

    Parameters
    ----------
    model : the train (or its assembly); its ``unbalances`` give the planes and phases
    max_continuous_speed : rad/s, of the reference shaft (sign ignored); default: the model's
    factor : multiple of the allowable residual unbalance 6350 W/N g·mm (API 617: 4)

    Returns
    -------
    list of :class:`~gearrotor.model.Unbalance`, in the model's order.
    """
    asm = model if isinstance(model, Assembly) else assemble(model)
    basis = api617_basis(asm, max_continuous_speed)
    return [
        u.model_copy(update={"amount": api617_unbalance(w, n, factor=factor)})
        for u, (w, n) in zip(asm.train.unbalances, basis, strict=True)
    ]


# --------------------------------------------------------------------------------------------
# API 617 9th edition (2022): the unbalance placed from the mode shape, the close-clearance check
#
# Facts as API 617 9th ed. 6.8.2.7, 6.8.2.10 and 6.8.2.11 state them according to ROSS's
# implementation of that edition (petrobras/ross pull request #1377, "Rewrite clearance analysis
# to API 617 9th ed. and add api617_unbalance", and its tests); the standard's text was not
# available to the author.
#
# * Unbalance (6.8.2.7): 2 × U_r at the antinodes of the forward mode of interest, U_r = 6350 W/N
#   g·mm (W kg, N the maximum continuous speed in rpm, at most 25,000 rpm: above it
#   U_r = 0.254 W); one antinode between the bearings: W = the sum of the journal static loads;
#   antinodes of opposite phase (a conical or second bending mode): one unbalance at each, 180°
#   apart, W = the static load of the nearest journal; an antinode outboard of the bearings
#   (overhung): W = the mass outboard of the bearing.
# * Close clearances (6.8.2.10, 6.8.2.11): A_vl = 25.4 √(12000/N_mc) µm pk-pk, at most 25.4 µm;
#   A_max the largest pk-pk amplitude at the probes between the minimum operating speed N_ma and
#   N_mc; the scale factor S_cc = A_vl / A_max (at most 6: the 8th and 9th editions' cap, which
#   ROSS leaves optional); the scaled major-axis pk-pk response at every close-clearance location
#   over the speed range must stay below 75 % of its minimum diametral running clearance.

UNBALANCE_FACTOR_9TH = 2.0  # 9th ed.: 2 × U_r (8th ed.: 4 × U_r at the model's planes)
N_CAP_RPM = 25000.0  # U_r uses N = min(MCS, 25,000 rpm)
ANTINODE_MIN = 0.5  # an antinode's deflection, as a fraction of the mode's largest on the shaft
SCALE_FACTOR_CAP = 6.0
CLEARANCE_FRACTION = 0.75


def residual_unbalance(journal_mass: float, max_continuous_speed: float) -> float:
    """U_r = 6350 W/N g·mm as kg·m (W kg; N the maximum continuous speed, rad/s, taken at most
    25,000 rpm)."""
    n_rpm = min(abs(max_continuous_speed) * 30 / np.pi, N_CAP_RPM)
    if not n_rpm > 0:
        raise ModelError(
            "API 617 unbalance needs a non-zero maximum continuous speed",
            field="max_continuous_speed",
            value=max_continuous_speed,
        )
    return 6350.0 * journal_mass / n_rpm * 1e-6


def nodal_masses(asm: Assembly, shaft: int) -> NDArray:
    """Translational mass at each node of ``shaft`` (kg): the consistent mass matrix's response
    to a rigid unit translation (half of each adjacent element, disks whole)."""
    u = np.zeros(asm.n_dof)
    offs = asm.node_offset[shaft]
    u[offs] = 1.0
    return (asm.M @ u)[offs]


@dataclass(frozen=True)
class ModeUnbalance:
    """The 9th edition's unbalance for one forward mode (:func:`mode_unbalances`)."""

    edition: str
    shaft: str
    mode_index: int  # index into the modal result at the maximum continuous speed
    mode_frequency: float  # damped, rad/s
    nodes: tuple[int, ...]
    phases: tuple[float, ...]  # rad
    static_loads: tuple[float, ...]  # W per unbalance, kg
    amounts: tuple[float, ...]  # kg·m
    kinds: tuple[str, ...]  # "between bearings (sum of journal loads)", "nearest journal", ...
    max_continuous_speed: float  # of the shaft, rad/s

    def unbalances(self) -> list:
        """As :class:`~gearrotor.model.Unbalance` entries for
        :func:`~gearrotor.analyses.lateral.unbalance.unbalance_response`."""
        from ...model import Unbalance

        return [
            Unbalance(shaft=self.shaft, node=n, amount=a, phase=p)
            for n, a, p in zip(self.nodes, self.amounts, self.phases, strict=True)
        ]

    def to_dict(self) -> dict:
        return {
            "edition": self.edition,
            "shaft": self.shaft,
            "mode_frequency_rpm": self.mode_frequency * 30 / np.pi,
            "max_continuous_speed_rpm": float(self.max_continuous_speed * 30 / np.pi),
            "unbalances": [
                {
                    "node": n,
                    "phase_deg": float(np.rad2deg(p)),
                    "static_load_kg": w,
                    "amount_g_mm": float(a * 1e6),
                    "basis": k,
                }
                for n, p, w, a, k in zip(
                    self.nodes,
                    self.phases,
                    self.static_loads,
                    self.amounts,
                    self.kinds,
                    strict=True,
                )
            ],
        }


def _forward_modes_of(res, si: int, min_lateral: float) -> list[int]:
    from .stability import _shaft_amplitudes, forward_lateral_modes

    return [
        int(i)
        for i in forward_lateral_modes(res, min_lateral)
        if res.whirl_per_shaft[i][si] == "F"
        and int(np.argmax(_shaft_amplitudes(res, int(i)))) == si
    ]


def mode_unbalances(
    model: Train | Assembly,
    *,
    shaft: str | None = None,
    mode: int = 0,
    max_continuous_speed: float | None = None,
    min_lateral: float = 0.5,
) -> ModeUnbalance:
    """API 617 9th edition unbalance (6.8.2.7, see above) for the ``mode``-th forward mode
    (0: the first) of ``shaft`` (default: the reference shaft) at the maximum continuous speed
    (reference shaft, rad/s; default the model's). A forward mode of a shaft: lateral, not
    over-damped, whirling forward on that shaft and moving it more than any other shaft.

    Antinodes: the shaft's lateral deflection in the mode, projected on its phase at the largest
    deflection, splits at its sign changes into lobes; each lobe's largest deflection is an
    antinode if it is at least ``ANTINODE_MIN`` (one half) of the mode's largest. Journal static
    loads: the shaft's weight (nodal masses, :func:`nodal_masses`) shared by its two outermost
    radial bearings by the lever rule; the mass outboard of a bearing counts the bearing node's
    mass in proportion to the lengths of its two elements."""
    from ..lateral.modal import modal
    from .stability import _default_speed

    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    if shaft is None:
        ref = train.reference_shaft
        shaft = train.shafts[0 if ref is None else train.shaft_index(ref, "reference_shaft")].name
    name = shaft
    si = train.shaft_index(name, "shaft")
    w = _default_speed(train, max_continuous_speed, "the API 617 unbalance")
    sense = 1.0 if train.speed >= 0 else -1.0
    w_s = abs(asm.speed_ratio[si]) * w
    res = modal(asm, speed=sense * w, max_frequency=max(3.0 * w_s, 3.0 * w) * 2)
    fwd = _forward_modes_of(res, si, min_lateral)
    if not 0 <= mode < len(fwd):
        raise ModelError(
            "no such forward mode of the shaft",
            field="mode",
            value=mode,
            expected=f"0..{len(fwd) - 1} (the shaft's forward modes below 6x its speed)",
        )
    i = fwd[mode]
    layout = train.layout().shafts[si]
    z = layout.z
    offs = asm.node_offset[si]
    phi = res.mode_shapes[i]
    x = phi[offs]
    amp = np.sqrt(np.abs(x) ** 2 + np.abs(phi[offs + 1]) ** 2)
    k = int(np.argmax(amp))
    p = np.real(x * np.conj(x[k]) / abs(x[k]))  # real deflection, + at the largest
    p = p / np.max(np.abs(p))
    # lobes between sign changes; each lobe's extreme is a candidate antinode
    antinodes: list[int] = []
    start = 0
    for j in range(1, len(p) + 1):
        if j == len(p) or np.sign(p[j]) != np.sign(p[start]) and p[j] != 0:
            lobe = np.arange(start, j)
            a = int(lobe[np.argmax(np.abs(p[lobe]))])
            if abs(p[a]) >= ANTINODE_MIN:
                antinodes.append(a)
            start = j
    masses = nodal_masses(asm, si)
    bearing_nodes = sorted(
        {
            train.node_index(b, f"bearings[{n}]")[1]
            for n, b in enumerate(train.bearings)
            if b.shaft == name
        }
    )
    if not bearing_nodes:
        raise ModelError(
            "the API 617 unbalance needs the shaft's bearings",
            field="bearings",
            value=name,
            expected="radial bearings on the shaft",
        )
    ja, jb = bearing_nodes[0], bearing_nodes[-1]
    total = float(np.sum(masses))
    if jb > ja:
        load_b = float(np.sum(masses * (z - z[ja])) / (z[jb] - z[ja]))
        loads = {ja: total - load_b, jb: load_b}
    else:
        loads = {ja: total}

    def outboard(j: int) -> float:
        if j < ja:
            left = z[ja] - z[ja - 1] if ja > 0 else 0.0
            right = z[ja + 1] - z[ja] if ja + 1 < len(z) else 0.0
            share = left / (left + right) if left + right > 0 else 0.0
            return float(np.sum(masses[:ja]) + share * masses[ja])
        left = z[jb] - z[jb - 1] if jb > 0 else 0.0
        right = z[jb + 1] - z[jb] if jb + 1 < len(z) else 0.0
        share = right / (left + right) if left + right > 0 else 0.0
        return float(np.sum(masses[jb + 1 :]) + share * masses[jb])

    nodes, phases, w_list, kinds = [], [], [], []
    sign0 = np.sign(p[antinodes[0]])
    for a in antinodes:
        nodes.append(a)
        phases.append(0.0 if np.sign(p[a]) == sign0 else np.pi)
        if a < ja or a > jb:
            w_list.append(outboard(a))
            kinds.append("overhung: mass outboard of the bearing")
        elif len(antinodes) == 1:
            w_list.append(total)
            kinds.append("between bearings: sum of the journal static loads")
        else:
            near = min(loads, key=lambda j: abs(z[j] - z[a]))
            w_list.append(loads[near])
            kinds.append(f"static load of the nearest journal (node {near})")
    amounts = [UNBALANCE_FACTOR_9TH * residual_unbalance(wk, w_s) for wk in w_list]
    from .stability import EDITIONS

    return ModeUnbalance(
        edition=EDITIONS["9th"].name,
        shaft=name,
        mode_index=i,
        mode_frequency=float(res.damped_frequency[i]),
        nodes=tuple(nodes),
        phases=tuple(phases),
        static_loads=tuple(w_list),
        amounts=tuple(amounts),
        kinds=tuple(kinds),
        max_continuous_speed=w_s,
    )


@dataclass(frozen=True)
class CloseClearance:
    """A close running clearance of the machine (seal, bearing, impeller eye): its node and its
    minimum diametral clearance (m)."""

    shaft: str
    node: int
    diametral: float
    name: str = ""


def bearing_clearances(model: Train | Assembly) -> list[CloseClearance]:
    """The close clearances of the model's fluid-film journal bearings: at each bearing given
    by a bearing file (``fluid_film.file``), twice the file's assembled radial clearance (the
    minimum running clearance: a preloaded lobe's or tilting pad's clearance at its pivot,
    docs/bearings.md), named after the bearing."""
    from ...bearings import load_bearing

    train = model.train if isinstance(model, Assembly) else model
    out = []
    for k, b in enumerate(train.bearings):
        if b.fluid_film is None:
            continue
        si, node = train.node_index(b, f"bearings[{k}]")
        c = float(load_bearing(b.fluid_film.file).bearing.clearance)
        name = b.name or f"bearing {k}"
        out.append(CloseClearance(train.shafts[si].name, int(node), 2 * c, name))
    return out


def close_clearances(model: Train | Assembly) -> list[CloseClearance]:
    """The close clearances of the 9th edition's check: the model's ``[api_audit]
    clearances`` when it lists any, else its fluid-film journal bearings' diametral clearances
    (:func:`bearing_clearances`); empty when neither."""
    train = model.train if isinstance(model, Assembly) else model
    table = train.api_audit
    if table is not None and table.clearances:
        return [CloseClearance(c.shaft, c.node, c.diametral, c.name) for c in table.clearances]
    return bearing_clearances(train)


@dataclass(frozen=True)
class ClearanceLocation:
    name: str
    shaft: str
    node: int
    diametral: float  # m
    limit: float  # 75 % of it, m
    scaled_response: float  # largest scaled major-axis pk-pk amplitude over the speeds, m
    speed: float  # reference-shaft speed where it is largest, rad/s

    @property
    def passed(self) -> bool:
        return self.scaled_response < self.limit


@dataclass(frozen=True)
class ClearanceCheck:
    """API 617 9th ed. 6.8.2.10-6.8.2.11 close-clearance check (:func:`clearance_check`)."""

    edition: str
    vibration_limit: float  # A_vl, m pk-pk
    max_probe_amplitude: float  # A_max, m pk-pk, between N_ma and N_mc
    max_probe: str
    scale_factor: float  # S_cc (after the cap)
    scale_factor_cap: float | None
    locations: tuple[ClearanceLocation, ...]
    unbalance: ModeUnbalance | None

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.locations)

    @property
    def verdict(self) -> str:
        return "pass" if self.passed else "fail"

    def to_dict(self) -> dict:
        um = 1e6
        return {
            "edition": self.edition,
            "vibration_limit_pp_um": self.vibration_limit * um,
            "max_probe_amplitude_pp_um": self.max_probe_amplitude * um,
            "max_probe": self.max_probe,
            "scale_factor": self.scale_factor,
            "scale_factor_cap": self.scale_factor_cap,
            "verdict": self.verdict,
            "unbalance": None if self.unbalance is None else self.unbalance.to_dict(),
            "locations": [
                {
                    "name": c.name,
                    "shaft": c.shaft,
                    "node": c.node,
                    "diametral_clearance_um": c.diametral * um,
                    "limit_pp_um": c.limit * um,
                    "scaled_response_pp_um": c.scaled_response * um,
                    "speed_rpm": c.speed * 30 / np.pi,
                    "percent_of_limit": 100 * c.scaled_response / c.limit,
                    "ok": c.passed,
                }
                for c in self.locations
            ],
        }

    def table(self) -> str:
        rows = [
            f"{self.edition}: close-clearance check (6.8.2.10-6.8.2.11)",
            f"  A_vl = {self.vibration_limit * 1e6:.2f} um pk-pk, A_max = "
            f"{self.max_probe_amplitude * 1e6:.3f} um pk-pk ({self.max_probe}), S_cc = "
            f"{self.scale_factor:.3f}"
            + ("" if self.scale_factor_cap is None else f" (cap {self.scale_factor_cap:g})"),
        ]
        for c in self.locations:
            rows.append(
                f"  [{'pass' if c.passed else 'fail'}] {c.name}: scaled "
                f"{c.scaled_response * 1e6:.2f} um pk-pk at {c.speed * 30 / np.pi:.0f} rpm, "
                f"75 % of clearance {c.limit * 1e6:.2f} um"
            )
        rows.append(f"  verdict: {self.verdict}")
        return "\n".join(rows)


def clearance_check(
    model: Train | Assembly,
    clearances: Sequence[CloseClearance | tuple],
    *,
    speeds: NDArray,
    operating_range: tuple[float, float] | None = None,
    unbalance: ModeUnbalance | None = None,
    mode: int = 0,
    shaft: str | None = None,
    probes=None,
    scale_factor_cap: float | None = SCALE_FACTOR_CAP,
) -> ClearanceCheck:
    """API 617 9th edition close-clearance check (see above): the response to ``unbalance``
    (default :func:`mode_unbalances` of ``mode`` of ``shaft``) over reference-shaft ``speeds``
    (rad/s), scaled by S_cc = A_vl / A_max, at every close clearance
    (:class:`CloseClearance` or ``(shaft, node, diametral[, name])``), against 75 % of its
    diametral clearance. ``operating_range``: (N_ma, N_mc) of the reference shaft, rad/s
    (default the model's); ``probes`` default to the model's."""
    from ...model.speed_range import model_operating_range
    from ..lateral.unbalance import api617_vibration_limit, unbalance_response

    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    op = operating_range or model_operating_range(train)
    if op is None:
        raise ModelError(
            "the close-clearance check needs the operating range (N_ma, N_mc)",
            field="operating_speed_range",
            expected="operating_speed_range and max_continuous_speed in the model",
        )
    locs = []
    for k, c in enumerate(clearances):
        c = c if isinstance(c, CloseClearance) else CloseClearance(*c)
        train.node_index(NodeRef(shaft=c.shaft, node=int(c.node)), f"clearances[{k}]")
        if not (np.isfinite(c.diametral) and c.diametral > 0):
            raise ModelError(
                "a diametral clearance must be positive",
                field=f"clearances[{k}].diametral",
                value=c.diametral,
                expected="m > 0",
            )
        locs.append(c)
    if not locs:
        raise ModelError(
            "the close-clearance check needs the close clearances",
            field="clearances",
            expected="one or more (shaft, node, diametral clearance)",
        )
    probes = train.probes if probes is None else probes
    if not probes:
        raise ModelError(
            "the close-clearance check scales the response by the probes' amplitude",
            field="probes",
            expected="at least one [[probes]] entry",
        )
    if unbalance is None:
        unbalance = mode_unbalances(asm, shaft=shaft, mode=mode, max_continuous_speed=op[1])
    speeds = np.union1d(np.asarray(speeds, float), [v for v in op])
    res = unbalance_response(
        asm, speeds=speeds, unbalances=unbalance.unbalances(), probes=probes, operating_range=op
    )
    inside = (speeds >= op[0] * (1 - 1e-12)) & (speeds <= op[1] * (1 + 1e-12))
    amps = [2 * float(np.max(p.amplitude[inside])) for p in res.probes]
    j = int(np.argmax(amps))
    a_max = amps[j]
    probe_shaft = res.probes[j].shaft
    a_vl = api617_vibration_limit(abs(asm.speed_ratio[probe_shaft]) * op[1])
    if not a_max > 0:
        raise ModelError(
            "no response at the probes between the operating range's ends",
            field="probes",
            expected="probes on the shafts the unbalance excites",
        )
    scc = a_vl / a_max
    if scale_factor_cap is not None:
        scc = min(scc, scale_factor_cap)
    out = []
    for c in locs:
        si = train.shaft_index(c.shaft, "clearances")
        X, Y = res.node_response(si, int(c.node))
        major = 0.5 * np.abs(X + 1j * Y) + 0.5 * np.abs(X - 1j * Y)
        pp = 2 * scc * major
        m = int(np.argmax(pp))
        out.append(
            ClearanceLocation(
                c.name or f"{c.shaft}:{c.node}",
                c.shaft,
                int(c.node),
                c.diametral,
                CLEARANCE_FRACTION * c.diametral,
                float(pp[m]),
                float(speeds[m]),
            )
        )
    from .stability import EDITIONS

    return ClearanceCheck(
        edition=EDITIONS["9th"].name,
        vibration_limit=a_vl,
        max_probe_amplitude=a_max,
        max_probe=res.probes[j].name,
        scale_factor=scc,
        scale_factor_cap=scale_factor_cap,
        locations=tuple(out),
        unbalance=unbalance,
    )
