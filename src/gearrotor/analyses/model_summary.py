"""What a model is, before any analysis: per shaft mass, inertias, length, elements, DOFs,
bearing span and mesh fineness; the gear ratios and the operating points (``gearrotor show``).

Masses and inertias come from the assembled mass matrix (shafts with their mass-only diameters,
disks and gears; pedestals excluded) through rigid-body vectors, so they are exactly what every
analysis sees: the mass is ``rᵀMr`` for a unit translation ``r``, the polar inertia the same for a
unit spin and the transverse inertia for a unit tilt about the centre of mass.

Mesh fineness: a shaft element of length ``h`` misplaces the modes of local wavenumber ``k``
by about (relative frequency error, measured on pinned-pinned and free-free steel beams against
800-element solutions, tests/test_model_summary.py):

* bending (cubic Timoshenko element): ``(kh)⁴ (1 + 3.5 Φ) / 1000``, ``k = (ρAω²/EI)^¼`` and
  ``Φ = 12EI/(κGAh²)`` the element's shear parameter. While elements are slender (Φ ≪ 1) the
  error falls as h⁴; once they are shorter than about their diameter (Φ ≳ 1) the shear term
  dominates and it falls as h² only (measured 0.7–1.0 × the estimate for Φ = 0.05–86);
* torsion and axial motion (linear rod elements, consistent mass): ``(kh)² / 24`` with
  ``k = ω/c``, ``c = √(G/ρ)`` or ``√(E/ρ)`` (the leading term of ``ω_h² = ω²(1 + (kh)²/12)``).

The element with the largest estimate at the highest frequency of interest bounds the
discretisation error of the shaft's modes; one above :data:`COARSE_ERROR` is flagged. The
opt-in convergence check (``convergence=True``, as ROSS's ``run_mesh_convergence``) halves every
element and compares the damped modes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..assembly import Assembly, _shaft_elements, assemble
from ..model import Train

__all__ = [
    "COARSE_ERROR",
    "ElementFineness",
    "element_error",
    "ShaftSummary",
    "MeshRatio",
    "ConvergenceRow",
    "ModelSummary",
    "summarize",
    "default_max_frequency",
    "excitation_frequency_range",
    "top_speed",
    "SEPARATION_MARGIN",
    "HEADROOM",
    "MIN_SPEED_MULTIPLE",
]

RPM = np.pi / 30
#: estimated relative frequency error above which an element is too coarse (1 %)
COARSE_ERROR = 0.01


@dataclass(frozen=True)
class ElementFineness:
    """The coarsest element of a shaft for the frequency range (largest estimated error)."""

    element: int  # element index along the shaft (0-based)
    length: float  # m
    outer_diameter: float  # m
    slenderness: float  # length / outer diameter
    motion: str  # "bending", "torsion" or "axial": the estimate that governs
    kh: float  # wavenumber of that motion × element length at max_frequency
    estimated_error: float  # relative frequency error (module docstring)
    phi: float = 0.0  # the element's shear parameter Φ

    @property
    def too_coarse(self) -> bool:
        return self.estimated_error > COARSE_ERROR

    def elements_needed(self) -> int:
        """Into how many equal parts this element must be split to meet COARSE_ERROR."""
        n = 1
        while self._error(n) > COARSE_ERROR and n < 10_000:
            n += 1
        return n

    def _error(self, n: int) -> float:
        # bending ∝ h⁴ (1 + 3.5 Φ), Φ ∝ 1/h²; rods ∝ h²
        if self.motion != "bending":
            return self.estimated_error / n**2
        return self.estimated_error / n**4 * (1 + 3.5 * self.phi * n**2) / (1 + 3.5 * self.phi)


def element_error(el, omega: float) -> tuple[str, float, float]:
    """(motion, kh, estimated relative frequency error) of shaft element ``el`` at ``omega``
    (rad/s): the largest of bending, torsion and axial (module docstring)."""
    rho_a = el.mass / el.length
    kb = (rho_a * omega**2 / (el.E * el.inertia)) ** 0.25 * el.length
    bending = kb**4 * (1 + 3.5 * el.phi) / 1000
    kt = omega / np.sqrt(el.shear_modulus / el.density) * el.length
    ka = omega / np.sqrt(el.E / el.density) * el.length
    return max(
        ("bending", kb, bending),
        ("torsion", kt, kt**2 / 24),
        ("axial", ka, ka**2 / 24),
        key=lambda t: t[2],
    )


@dataclass(frozen=True)
class ShaftSummary:
    name: str
    index: int
    speed: float  # rad/s, signed, at the model's speed
    length: float  # m, first to last node
    n_elements: int
    n_nodes: int
    n_dof: int
    mass: float  # kg, shaft + disks and gears on it
    center_of_mass: float  # m, axial position
    polar_inertia: float  # kg·m² about the shaft axis
    transverse_inertia: float  # kg·m² about a transverse axis through the centre of mass
    bearings: tuple[str, ...]
    bearing_span: float | None  # m, between the outermost radial bearings (None with < 2)
    coarsest: ElementFineness

    def to_dict(self) -> dict:
        c = self.coarsest
        return {
            "name": self.name,
            "speed_rpm": self.speed / RPM,
            "length_m": self.length,
            "n_elements": self.n_elements,
            "n_nodes": self.n_nodes,
            "n_dof": self.n_dof,
            "mass_kg": self.mass,
            "center_of_mass_m": self.center_of_mass,
            "polar_inertia_kg_m2": self.polar_inertia,
            "transverse_inertia_kg_m2": self.transverse_inertia,
            "bearings": list(self.bearings),
            "bearing_span_m": self.bearing_span,
            "coarsest_element": {
                "element": c.element,
                "length_m": c.length,
                "outer_diameter_m": c.outer_diameter,
                "slenderness": c.slenderness,
                "motion": c.motion,
                "kh": float(c.kh),
                "estimated_error": float(c.estimated_error),
                "too_coarse": bool(c.too_coarse),
            },
        }


@dataclass(frozen=True)
class MeshRatio:
    name: str
    gear: tuple[str, int, int]  # shaft, node, teeth
    mate: tuple[str, int, int]
    ratio: float  # speed ratio |Ω_mate / Ω_gear| = N_gear / N_mate
    pitch_radii: tuple[float, float]  # m
    mesh_frequency: float  # Hz at the model's speed

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "gear": {"shaft": self.gear[0], "node": self.gear[1], "teeth": self.gear[2]},
            "mate": {"shaft": self.mate[0], "node": self.mate[1], "teeth": self.mate[2]},
            "speed_ratio": self.ratio,
            "pitch_radii_m": list(self.pitch_radii),
            "mesh_frequency_hz": self.mesh_frequency,
        }


@dataclass(frozen=True)
class ConvergenceRow:
    """One damped mode of the model and of the model with every element halved."""

    mode: int
    frequency: float  # Hz, the model's mesh
    refined_frequency: float  # Hz, every element halved
    log_dec: float
    refined_log_dec: float

    @property
    def change(self) -> float:
        return self.refined_frequency / self.frequency - 1.0


@dataclass(frozen=True)
class ModelSummary:
    name: str
    speed: float  # rad/s, reference shaft
    n_dof: int
    max_frequency: float  # rad/s, the frequency range the fineness refers to
    shafts: tuple[ShaftSummary, ...]
    meshes: tuple[MeshRatio, ...]
    operating_points: tuple[str, ...]
    convergence: tuple[ConvergenceRow, ...] | None
    warnings: tuple[str, ...]

    def to_dict(self) -> dict:
        out = {
            "name": self.name,
            "speed_rpm": self.speed / RPM,
            "n_dof": self.n_dof,
            "max_frequency_rpm": self.max_frequency / RPM,
            "shafts": [s.to_dict() for s in self.shafts],
            "meshes": [m.to_dict() for m in self.meshes],
            "operating_points": list(self.operating_points),
            "warnings": list(self.warnings),
        }
        if self.convergence is not None:
            out["convergence"] = [
                {
                    "mode": r.mode,
                    "frequency_hz": r.frequency,
                    "refined_frequency_hz": r.refined_frequency,
                    "relative_change": r.change,
                    "log_dec": r.log_dec,
                    "refined_log_dec": r.refined_log_dec,
                }
                for r in self.convergence
            ]
        return out

    def table(self) -> str:
        lines = [
            f"{'shaft':<14}{'speed rpm':>11}{'length m':>10}{'elem':>6}{'DOF':>6}"
            f"{'mass kg':>10}{'Ip kg·m²':>11}{'It kg·m²':>11}{'span m':>9}"
            f"{'coarsest L/D':>13}{'motion':>9}{'kh':>7}{'est. err':>10}"
        ]
        for s in self.shafts:
            c = s.coarsest
            span = "-" if s.bearing_span is None else f"{s.bearing_span:.4g}"
            flag = " COARSE" if c.too_coarse else ""
            lines.append(
                f"{s.name:<14}{s.speed / RPM:>11.1f}{s.length:>10.4g}{s.n_elements:>6}"
                f"{s.n_dof:>6}{s.mass:>10.4g}{s.polar_inertia:>11.4g}"
                f"{s.transverse_inertia:>11.4g}{span:>9}{c.slenderness:>13.3g}{c.motion:>9}{c.kh:>7.3f}"
                f"{c.estimated_error:>10.2e}{flag}"
            )
        lines.append(
            f"{self.n_dof} DOF; element fineness at {self.max_frequency / RPM:,.0f} cpm "
            f"(estimated frequency error of the coarsest element, flagged above "
            f"{COARSE_ERROR:.0%})"
        )
        if self.meshes:
            lines.append("")
            lines.append(
                f"{'mesh':<14}{'gear (shaft:node, N)':<26}{'mate (shaft:node, N)':<26}"
                f"{'ratio':>9}{'mesh Hz':>10}"
            )
            for m in self.meshes:
                g = f"{m.gear[0]}:{m.gear[1]}, {m.gear[2]}"
                t = f"{m.mate[0]}:{m.mate[1]}, {m.mate[2]}"
                lines.append(f"{m.name:<14}{g:<26}{t:<26}{m.ratio:>9.4f}{m.mesh_frequency:>10.1f}")
        if self.operating_points:
            lines.append("")
            lines.append("operating points: " + ", ".join(self.operating_points))
        if self.convergence is not None:
            lines.append("")
            lines.append(
                f"{'mode':>5}{'f Hz':>12}{'f Hz (h/2)':>12}{'change':>10}{'log dec':>10}"
                f"{'(h/2)':>10}"
            )
            for r in self.convergence:
                lines.append(
                    f"{r.mode:>5}{r.frequency:>12.4f}{r.refined_frequency:>12.4f}"
                    f"{r.change:>10.2e}{r.log_dec:>10.4f}{r.refined_log_dec:>10.4f}"
                )
        for w in self.warnings:
            lines.append(f"warning: {w}")
        return "\n".join(lines)


#: Separation margin (fraction) the excitation frequency range allows an excitation: API 617's
#: largest required margin of a critical from the operating range (10 + 17 (1 − 1/(AF − 1.5)) %,
#: at most 26 %, above the maximum continuous speed), which also covers its 10 % torsional margin.
SEPARATION_MARGIN = 0.26
#: Headroom (factor) of the range above the highest frequency an excitation reaches with its
#: margin: the modes just clear of every excitation are included too.
HEADROOM = 1.1
#: The range is at least this multiple of the top operating speed (a train without gears: its
#: first bending modes, above 1x and 2x with margin).
MIN_SPEED_MULTIPLE = 5.0


def excitation_frequency_range(asm: Assembly, top: float) -> tuple[float, str]:
    """(rad/s, why) the frequency range of a model's analyses: the highest frequency an
    excitation of the Campbell diagram (1x and 2x of every shaft, every gear-mesh frequency)
    reaches at the top operating speed ``top`` (rad/s) with its separation margin, with
    headroom, ``HEADROOM × (1 + SEPARATION_MARGIN) × max(multiple × |shaft speed|)``, and at
    least ``MIN_SPEED_MULTIPLE × top``. The report's default ``--max-frequency`` and the
    element fineness of ``gearrotor show`` use it."""
    from .lateral.campbell import default_orders

    ratios = np.abs(asm.speed_ratio)
    orders = [(o, o.multiple * ratios[o.shaft] * top) for o in default_orders(asm)]
    order, f = max(orders, key=lambda x: x[1])
    fmax = HEADROOM * (1 + SEPARATION_MARGIN) * f
    floor = MIN_SPEED_MULTIPLE * top
    if fmax >= floor:
        return (
            fmax,
            f"default: the highest excitation, {order.label} = {f / RPM:,.0f} cpm at "
            f"{top / RPM:,.0f} rpm, + {SEPARATION_MARGIN:.0%} separation margin, "
            f"× {HEADROOM:g} headroom",
        )
    return (
        floor,
        f"default: {MIN_SPEED_MULTIPLE:g} × the top operating speed {top / RPM:,.0f} rpm "
        f"(above the highest excitation, {order.label} = {f / RPM:,.0f} cpm, with its "
        f"{SEPARATION_MARGIN:.0%} separation margin and × {HEADROOM:g} headroom)",
    )


def top_speed(train: Train) -> float:
    """rad/s: the highest reference-shaft speed the model names (its speed, operating range,
    maximum continuous speed, operating points)."""
    ref = abs(train.speed)
    for v in (train.max_continuous_speed, *(train.operating_speed_range or ())):
        if v is not None:
            ref = max(ref, abs(v))
    for p in train.operating_points:
        if p.speed is not None:
            ref = max(ref, abs(p.speed))
    return ref


def default_max_frequency(train: Train, asm: Assembly | None = None) -> float:
    """The frequency range (rad/s) a model is meant for: :func:`excitation_frequency_range` at
    the highest speed the model names (:func:`top_speed`); 60,000 cpm for a model at rest."""
    top = top_speed(train)
    if top <= 0:
        return 1000.0 * RPM * 60
    return excitation_frequency_range(asm if asm is not None else assemble(train), top)[0]


def _rigid_properties(asm: Assembly, i: int) -> tuple[float, float, float, float]:
    """(mass, z of centre of mass, polar inertia, transverse inertia about the centre)."""
    M = asm.M
    z = asm.train.layout().shafts[i].z
    offs = asm.node_offset[i]

    def quad(r: NDArray) -> float:
        return float(r @ (M @ r))

    r = np.zeros(asm.n_dof)
    r[offs + 0] = 1.0
    mass = quad(r)
    # a rigid tilt θy = 1 about the origin moves node n by x = z_n (θ × p with θ = ŷ):
    # rᵀMr = It(0), r_txᵀ M r = first moment; the centre of mass follows
    t = np.zeros(asm.n_dof)
    t[offs + 4] = 1.0
    t[offs + 0] = z
    first = float(r @ (M @ t))
    zc = first / mass if mass > 0 else float(z.mean())
    tc = np.zeros(asm.n_dof)
    tc[offs + 4] = 1.0
    tc[offs + 0] = z - zc
    spin = np.zeros(asm.n_dof)
    spin[offs + 5] = 1.0
    return mass, zc, quad(spin), quad(tc)


def _fineness(train: Train, i: int, omega: float) -> ElementFineness:
    best = None
    for e, el in enumerate(_shaft_elements(train, i)):
        motion, kh, err = element_error(el, omega)
        if best is None or err > best.estimated_error:
            best = ElementFineness(
                element=e,
                length=el.length,
                outer_diameter=el.outer_diameter,
                slenderness=el.length / el.outer_diameter,
                motion=motion,
                kh=kh,
                estimated_error=err,
                phi=el.phi,
            )
    assert best is not None  # a shaft has at least one element (validated)
    return best


def _refined(train: Train) -> Train:
    data = train.model_dump()
    for s in data["shafts"]:
        for sec in s["sections"]:
            sec["elements"] *= 2
        for d in s["disks"]:  # node numbers double with the elements
            if d.get("node") is not None:
                d["node"] *= 2

    def renode(obj):
        if isinstance(obj, dict):
            if "shaft" in obj and obj.get("node") is not None:
                obj["node"] *= 2
            for v in obj.values():
                renode(v)
        elif isinstance(obj, list):
            for v in obj:
                renode(v)

    for key in data:
        if key not in ("shafts", "materials"):
            renode(data[key])
    return Train.model_validate(data)


def _convergence(train: Train, speed: float, max_frequency: float) -> tuple[ConvergenceRow, ...]:
    from .lateral.modal import modal

    coarse = modal(train, speed=speed, max_frequency=max_frequency)
    fine = modal(_refined(train), speed=speed, max_frequency=max_frequency * 1.2)
    rows = []
    fine_f = np.asarray(fine.frequency_hz)
    used = np.zeros(len(fine_f), bool)
    for m in range(len(coarse)):
        if coarse.overdamped[m]:
            continue
        f = coarse.frequency_hz[m]
        cand = np.where(~used & ~np.asarray(fine.overdamped))[0]
        if not len(cand):
            break
        j = cand[np.argmin(np.abs(fine_f[cand] - f))]
        used[j] = True
        rows.append(
            ConvergenceRow(m + 1, float(f), float(fine_f[j]), coarse.log_dec[m], fine.log_dec[j])
        )
    return tuple(rows)


def summarize(
    train: Train,
    *,
    max_frequency: float | None = None,
    convergence: bool = False,
    speed: float | None = None,
) -> ModelSummary:
    """Summary of ``train``: see the module docstring.

    ``max_frequency`` (rad/s): the frequency range the element fineness refers to (default
    :func:`default_max_frequency`); ``convergence``: also compare the damped modes below it with
    those of the model with every element halved (two modal solves); ``speed`` (rad/s): the
    reference-shaft speed of that comparison (default the model's).
    """
    asm = assemble(train)
    layout = train.layout()
    wmax = default_max_frequency(train, asm) if max_frequency is None else float(max_frequency)
    speed = train.speed if speed is None else float(speed)
    shafts = []
    warnings = []
    for i, sl in enumerate(layout.shafts):
        brg = [
            (b.name or f"bearings[{k}]", train.node_index(b, f"bearings[{k}]")[1])
            for k, b in enumerate(train.bearings)
            if b.shaft == sl.name
        ]
        nodes = [n for _, n in brg]
        span = float(sl.z[max(nodes)] - sl.z[min(nodes)]) if len(set(nodes)) >= 2 else None
        mass, zc, ip, it = _rigid_properties(asm, i)
        fine = _fineness(train, i, wmax)
        if fine.too_coarse:
            warnings.append(
                f"shaft '{sl.name}': element {fine.element} (L = {fine.length:.4g} m, "
                f"D = {fine.outer_diameter:.4g} m) is too coarse for {wmax / RPM:,.0f} cpm "
                f"({fine.motion}, kh = {fine.kh:.2f}, estimated frequency error "
                f"{fine.estimated_error:.1%}); split it into {fine.elements_needed()} or more "
                "elements"
            )
        shafts.append(
            ShaftSummary(
                name=sl.name,
                index=i,
                speed=sl.speed_ratio * speed,
                length=float(sl.z[-1] - sl.z[0]),
                n_elements=sl.n_nodes - 1,
                n_nodes=sl.n_nodes,
                n_dof=6 * sl.n_nodes,
                mass=mass,
                center_of_mass=zc,
                polar_inertia=ip,
                transverse_inertia=it,
                bearings=tuple(n for n, _ in brg),
                bearing_span=span,
                coarsest=fine,
            )
        )
    meshes = []
    for k, m in enumerate(train.meshes):
        si = train.shaft_index(m.gear.shaft, f"meshes[{k}].gear.shaft")
        meshes.append(
            MeshRatio(
                name=m.name or f"meshes[{k}]",
                gear=(m.gear.shaft, train.node_index(m.gear, f"meshes[{k}].gear")[1], m.gear.teeth),
                mate=(m.mate.shaft, train.node_index(m.mate, f"meshes[{k}].mate")[1], m.mate.teeth),
                ratio=m.gear.teeth / m.mate.teeth,
                pitch_radii=train.pitch_radii(k),
                mesh_frequency=abs(layout.shafts[si].speed_ratio * speed)
                * m.gear.teeth
                / (2 * np.pi),
            )
        )
    conv = _convergence(train, speed, wmax) if convergence else None
    return ModelSummary(
        name=train.name,
        speed=speed,
        n_dof=asm.n_dof,
        max_frequency=wmax,
        shafts=tuple(shafts),
        meshes=tuple(meshes),
        operating_points=tuple(p.name for p in train.operating_points),
        convergence=conv,
        warnings=tuple(warnings),
    )
