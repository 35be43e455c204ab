"""The train: any number of shafts joined by gear meshes and couplings, and its layout.

:func:`Train.layout` checks the cross-references (shaft names, node indices, gear geometry,
speeds) and resolves what follows from them: the nodes of every shaft, the shafts' centre
positions (from the mesh geometry) and every shaft's speed relative to the reference shaft
(propagated through the gear ratios, ``N_i Ω_i = −N_j Ω_j``, and couplings, ``Ω_i = Ω_j``).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, field_validator, model_serializer, model_validator

from ..errors import ModelError
from ..units import AngularSpeed
from .api_audit import ApiAudit
from .components import (
    Bearing,
    Coupling,
    CrossCoupling,
    ExternalTorque,
    Material,
    Mesh,
    NodeRef,
    Probe,
    Seal,
    Shaft,
    Spec,
    ThrustBearing,
    TorsionalSupport,
    Unbalance,
)
from .drives import Torsional
from .operating_point import OperatingPoint

__all__ = ["Train", "Layout", "ShaftLayout"]

_REL_TOL = 1e-6
# optional Train fields left out of the model JSON when absent
_OMIT_WHEN_ABSENT = ("torsional", "operating_speed_range", "max_continuous_speed", "api_audit")
# optional Train lists left out of the model JSON when empty
_OMIT_WHEN_EMPTY = ("operating_points", "seals", "torsional_supports")


@dataclass(frozen=True)
class ShaftLayout:
    """Resolved geometry of one shaft."""

    name: str
    index: int
    z: NDArray  # (n_nodes,) axial node positions, m
    position: tuple[float, float]  # (x, y) of the centre line, m
    speed_ratio: float  # Ω_shaft / Ω_reference (signed)
    outer_radius: NDArray  # (n_nodes,) largest outer radius of the elements at the node, m

    @property
    def n_nodes(self) -> int:
        return len(self.z)


@dataclass(frozen=True)
class Layout:
    shafts: tuple[ShaftLayout, ...]

    def shaft(self, name: str) -> ShaftLayout:
        for s in self.shafts:
            if s.name == name:
                return s
        raise KeyError(name)


class Train(Spec):
    """A geared machinery train.

    ``speed`` is the nominal speed of ``reference_shaft`` (default: the first shaft); other shafts'
    speeds follow from the gear ratios. A shaft may state its own ``speed`` as a check.
    """

    name: str = "train"
    reference_shaft: str | None = None
    speed: AngularSpeed = 0.0
    shear_method: str = Field(default="hutchinson", pattern="^(hutchinson|cowper)$")
    materials: dict[str, Material] = Field(min_length=1)
    shafts: list[Shaft] = Field(min_length=1)
    bearings: list[Bearing] = Field(default_factory=list)
    seals: list[Seal] = Field(default_factory=list)  # annular seals: like bearings, any sign
    thrust_bearings: list[ThrustBearing] = Field(default_factory=list)
    # torsional springs / dampers to ground (held ends, propeller damping)
    torsional_supports: list[TorsionalSupport] = Field(default_factory=list)
    cross_couplings: list[CrossCoupling] = Field(default_factory=list)
    couplings: list[Coupling] = Field(default_factory=list)
    meshes: list[Mesh] = Field(default_factory=list)
    unbalances: list[Unbalance] = Field(default_factory=list)
    probes: list[Probe] = Field(default_factory=list)
    torques: list[ExternalTorque] = Field(default_factory=list)
    torsional: Torsional | None = None  # drives, loads, stress concentrations (model/drives.py)
    # API 617 operating range of the reference shaft: speed magnitudes, min <= max <= MCS
    operating_speed_range: tuple[AngularSpeed, AngularSpeed] | None = None
    max_continuous_speed: AngularSpeed | None = None
    # static operating points: speed, power or torque, gravity, static forces (issue 11)
    operating_points: list[OperatingPoint] = Field(default_factory=list)
    api_audit: ApiAudit | None = None  # API 617 Level I inputs (model/audit.py)

    @field_validator("max_continuous_speed")
    @classmethod
    def _positive_mcs(cls, v):
        if v is not None and not v > 0:
            raise ValueError(f"expected a positive speed magnitude, got {v * 30 / np.pi:.6g} rpm")
        return v

    @field_validator("operating_speed_range")
    @classmethod
    def _ordered_range(cls, v):
        if v is not None and not 0 < v[0] <= v[1]:
            raise ValueError(
                "expected [minimum, maximum] speed magnitudes with 0 < minimum <= maximum, got "
                f"[{v[0] * 30 / np.pi:.6g}, {v[1] * 30 / np.pi:.6g}] rpm"
            )
        return v

    @model_validator(mode="after")
    def _range_within_mcs(self) -> Train:
        mcs, op = self.max_continuous_speed, self.operating_speed_range
        if mcs is not None and op is not None and op[1] > mcs * (1 + 1e-9):
            raise ValueError(
                f"operating_speed_range: the maximum operating speed {op[1] * 30 / np.pi:.6g} "
                f"rpm exceeds max_continuous_speed {mcs * 30 / np.pi:.6g} rpm; expected "
                "maximum <= max_continuous_speed"
            )
        return self

    @model_serializer(mode="wrap")
    def _without_absent_optionals(self, handler):
        # a train without these optional inputs serialises as before the fields existed, so
        # the model JSON (study case keys, transient checkpoint fingerprints) of existing
        # models is kept
        out = handler(self)
        for key in _OMIT_WHEN_ABSENT:
            if getattr(self, key) is None:
                out.pop(key, None)
        for key in _OMIT_WHEN_EMPTY:
            if not getattr(self, key):
                out.pop(key, None)
        return out

    @model_validator(mode="after")
    def _unique_names(self) -> Train:
        names = [s.name for s in self.shafts]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"shaft names must be unique, repeated: {sorted(dup)}")
        ops = [p.name for p in self.operating_points]
        dup = {n for n in ops if ops.count(n) > 1}
        if dup:
            raise ValueError(f"operating point names must be unique, repeated: {sorted(dup)}")
        return self

    def operating_point(self, name: str | OperatingPoint) -> OperatingPoint:
        """The operating point called ``name`` (an :class:`OperatingPoint` passes through)."""
        if isinstance(name, OperatingPoint):
            return name
        for p in self.operating_points:
            if p.name == name:
                return p
        raise ModelError(
            "unknown operating point",
            field="operating_point",
            value=name,
            expected=f"one of {[p.name for p in self.operating_points]}"
            if self.operating_points
            else "an [[operating_points]] entry in the model (it has none)",
        )

    # ------------------------------------------------------------------------------------
    @property
    def reference(self) -> str:
        return self.reference_shaft or self.shafts[0].name

    def shaft_index(self, name: str, field: str) -> int:
        for i, s in enumerate(self.shafts):
            if s.name == name:
                return i
        raise ModelError(
            "unknown shaft",
            field=field,
            value=name,
            expected=f"one of {[s.name for s in self.shafts]}",
        )

    def node_index(
        self, ref: NodeRef | object, field: str, shaft: str | None = None
    ) -> tuple[int, int]:
        """(shaft index, node index) of a node reference, checked against the layout."""
        sname = shaft if shaft is not None else ref.shaft
        si = self.shaft_index(sname, f"{field}.shaft")
        z = self.layout().shafts[si].z
        if getattr(ref, "node", None) is not None:
            if ref.node >= len(z):
                raise ModelError(
                    f"node is not on shaft '{sname}'",
                    field=f"{field}.node",
                    value=ref.node,
                    expected=f"a node index 0..{len(z) - 1}",
                )
            return si, ref.node
        at = ref.at
        zl = z - z[0]
        k = int(np.argmin(np.abs(zl - at)))
        if abs(zl[k] - at) > 1e-6 * max(zl[-1], 1.0):
            raise ModelError(
                f"no node of shaft '{sname}' at this axial position",
                field=f"{field}.at",
                value=f"{at} m",
                expected=f"a node position; nearest nodes at {zl[max(k - 1, 0)]:.6g}, "
                f"{zl[k]:.6g}, {zl[min(k + 1, len(zl) - 1)]:.6g} m",
            )
        return si, k

    def material(self, name: str, field: str) -> Material:
        if name not in self.materials:
            raise ModelError(
                "unknown material",
                field=field,
                value=name,
                expected=f"one of {sorted(self.materials)}",
            )
        return self.materials[name]

    # ------------------------------------------------------------------------------------
    def layout(self) -> Layout:
        """Resolve nodes, positions and speed ratios; raise :class:`ModelError` on bad input."""
        return self._resolved

    @cached_property
    def _resolved(self) -> Layout:
        nodes = []
        for i, s in enumerate(self.shafts):
            self.material(s.material, f"shafts[{i}].material")
            z = [s.start]
            rad = [0.0]
            for j, sec in enumerate(s.sections):
                if sec.material is not None:
                    self.material(sec.material, f"shafts[{i}].sections[{j}].material")
                h = sec.length / sec.elements
                for _ in range(sec.elements):
                    rad[-1] = max(rad[-1], sec.outer_diameter / 2)
                    z.append(z[-1] + h)
                    rad.append(sec.outer_diameter / 2)
            nodes.append((np.array(z), np.array(rad)))
        ref = self.shaft_index(self.reference, "reference_shaft")
        ratios, positions = self._propagate(ref, nodes)
        shafts = tuple(
            ShaftLayout(s.name, i, nodes[i][0], positions[i], ratios[i], nodes[i][1])
            for i, s in enumerate(self.shafts)
        )
        layout = Layout(shafts)
        # provisionally cached: the node checks read it; withdrawn if a check fails, so a second
        # call raises again instead of returning an unchecked layout
        self.__dict__["_resolved"] = layout
        try:
            self._check_nodes()
            self._check_speeds(ratios)
        except ModelError:
            del self.__dict__["_resolved"]
            raise
        return layout

    def _edges(self):
        """Graph edges: (shaft a, shaft b, ratio Ω_b/Ω_a, kind, index, field)."""
        for k, m in enumerate(self.meshes):
            a = self.shaft_index(m.gear.shaft, f"meshes[{k}].gear.shaft")
            b = self.shaft_index(m.mate.shaft, f"meshes[{k}].mate.shaft")
            if a == b:
                raise ModelError(
                    "a gear mesh must join two different shafts",
                    field=f"meshes[{k}].mate.shaft",
                    value=m.mate.shaft,
                )
            yield a, b, -m.gear.teeth / m.mate.teeth, "mesh", k
        for k, c in enumerate(self.couplings):
            a = self.shaft_index(c.node_i.shaft, f"couplings[{k}].node_i.shaft")
            b = self.shaft_index(c.node_j.shaft, f"couplings[{k}].node_j.shaft")
            if a != b:
                yield a, b, 1.0, "coupling", k

    def _propagate(self, ref: int, nodes) -> tuple[list[float], list[tuple[float, float]]]:
        n = len(self.shafts)
        ratios: list[float | None] = [None] * n
        positions: list[tuple[float, float] | None] = [None] * n
        ratios[ref] = 1.0
        p0 = self.shafts[ref].position
        positions[ref] = tuple(p0) if p0 is not None else (0.0, 0.0)
        adj: dict[int, list] = {i: [] for i in range(n)}
        for a, b, r, kind, k in self._edges():
            adj[a].append((b, r, kind, k, +1))
            adj[b].append((a, 1.0 / r, kind, k, -1))
        queue = deque([ref])
        while queue:
            a = queue.popleft()
            for b, r, kind, k, sign in adj[a]:
                ratio_b = ratios[a] * r
                pos_b = self._neighbour_position(positions[a], kind, k, sign)
                if ratios[b] is None:
                    ratios[b] = ratio_b
                    positions[b] = pos_b
                    queue.append(b)
                    continue
                if abs(ratios[b] - ratio_b) > _REL_TOL * abs(ratio_b):
                    raise ModelError(
                        f"inconsistent gear ratios around a loop of the train at shaft "
                        f"'{self.shafts[b].name}'",
                        field=f"{kind}es[{k}]" if kind == "mesh" else f"couplings[{k}]",
                        value=f"speed ratio {ratio_b:.6g} vs {ratios[b]:.6g}",
                        expected="tooth counts that close the loop",
                    )
                if np.hypot(pos_b[0] - positions[b][0], pos_b[1] - positions[b][1]) > 1e-6:
                    raise ModelError(
                        "the gear geometry places a shaft at two different positions",
                        field=f"meshes[{k}]" if kind == "mesh" else f"couplings[{k}]",
                        value=f"{pos_b} vs {positions[b]} m",
                        expected="consistent radii and orientation angles",
                    )
        missing = [self.shafts[i].name for i in range(n) if ratios[i] is None]
        if missing:
            raise ModelError(
                "the train is disconnected: these shafts are joined to the reference shaft "
                "by no gear mesh or coupling",
                field="shafts",
                value=missing,
                expected=f"every shaft connected to '{self.shafts[ref].name}'",
            )
        for i, s in enumerate(self.shafts):
            if s.position is not None:
                dx = np.hypot(s.position[0] - positions[i][0], s.position[1] - positions[i][1])
                if dx > 1e-6 * max(1.0, np.hypot(*positions[i])):
                    raise ModelError(
                        "shaft position disagrees with the gear geometry",
                        field=f"shafts[{i}].position",
                        value=f"{tuple(s.position)} m",
                        expected=f"({positions[i][0]:.6g}, {positions[i][1]:.6g}) m from the "
                        "mesh radii and orientation (or leave position out)",
                    )
        return ratios, positions

    def _neighbour_position(self, pa, kind, k, sign):
        if kind == "coupling":
            return pa
        m = self.meshes[k]
        ri, rj = self.pitch_radii(k)
        d = (ri + rj) * sign
        return (pa[0] + d * np.cos(m.orientation), pa[1] + d * np.sin(m.orientation))

    def pitch_radii(self, k: int) -> tuple[float, float]:
        """Pitch radii (m) of mesh k (converted from base radii when given so)."""
        m = self.meshes[k]
        ri, rj = m.gear.radius, m.mate.radius
        if m.radius_type == "base":
            at = np.arctan(np.tan(m.pressure_angle) / np.cos(m.helix_angle))
            ri, rj = ri / np.cos(at), rj / np.cos(at)
        return ri, rj

    def _named_groups(self) -> dict[str, list[tuple[str, object]]]:
        """The named components by kind: {kind: [(field, component), ...]}; a kind's names
        label its outputs (result columns, file names), so they must be unique within it."""
        groups: dict[str, list[tuple[str, object]]] = {}
        for gname in (
            "bearings",
            "seals",
            "thrust_bearings",
            "torsional_supports",
            "cross_couplings",
            "couplings",
            "meshes",
            "probes",
            "torques",
        ):
            items = getattr(self, gname, None) or []
            groups[gname] = [(f"{gname}[{k}]", it) for k, it in enumerate(items)]
        groups["disks"] = [
            (f"shafts[{i}].disks[{k}]", d)
            for i, s in enumerate(self.shafts)
            for k, d in enumerate(s.disks)
        ]
        return groups

    def _check_names(self) -> None:
        for items in self._named_groups().values():
            seen: dict[str, str] = {}
            for field, it in items:
                name = getattr(it, "name", None)
                if name is None:
                    continue
                if name in seen:
                    raise ModelError(
                        f"duplicate name: {seen[name]}.name is also {name!r}",
                        field=f"{field}.name",
                        value=name,
                        expected="a name not used by another component of this kind",
                    )
                seen[name] = field

    def _check_nodes(self) -> None:
        self._check_names()
        groups = [
            ("bearings", self.bearings),
            ("seals", self.seals),
            ("thrust_bearings", self.thrust_bearings),
            ("torsional_supports", self.torsional_supports),
            ("cross_couplings", self.cross_couplings),
            ("unbalances", self.unbalances),
            ("probes", self.probes),
            ("torques", self.torques),
        ]
        for gname, items in groups:
            for k, it in enumerate(items):
                self.node_index(it, f"{gname}[{k}]")
        for i, s in enumerate(self.shafts):
            for k, d in enumerate(s.disks):
                self.node_index(d, f"shafts[{i}].disks[{k}]", shaft=s.name)
                if d.material is not None:
                    self.material(d.material, f"shafts[{i}].disks[{k}].material")
        for k, c in enumerate(self.couplings):
            self.node_index(c.node_i, f"couplings[{k}].node_i")
            self.node_index(c.node_j, f"couplings[{k}].node_j")
        for k, m in enumerate(self.meshes):
            si, ni = self.node_index(m.gear, f"meshes[{k}].gear")
            sj, nj = self.node_index(m.mate, f"meshes[{k}].mate")
            zi = self._resolved.shafts[si].z[ni]
            zj = self._resolved.shafts[sj].z[nj]
            if abs(zi - zj) > 1e-6 * max(1.0, abs(zi)):
                raise ModelError(
                    "the two gears of a mesh are at different axial positions",
                    field=f"meshes[{k}].mate",
                    value=f"z = {zj:.6g} m vs gear at {zi:.6g} m",
                    expected="gear nodes in the same plane (adjust the shafts' 'start')",
                )
            ri, rj = self.pitch_radii(k)
            rr = (ri / rj) / (m.gear.teeth / m.mate.teeth)
            if abs(rr - 1) > 0.01:
                raise ModelError(
                    "pitch radii do not match the tooth counts",
                    field=f"meshes[{k}]",
                    value=f"r_i/r_j = {ri / rj:.5g}, N_i/N_j = {m.gear.teeth / m.mate.teeth:.5g}",
                    expected="r_i/r_j = N_i/N_j within 1%",
                )
            needs_w = (
                m.stiffness is not None
                and not isinstance(m.stiffness, float)
                and m.stiffness.method != "value"
            )
            if needs_w and m.face_width is None:
                raise ModelError(
                    f"mesh stiffness method '{m.stiffness.method}' needs face_width",
                    field=f"meshes[{k}].face_width",
                    expected="a length",
                )
        if self.torsional is not None:
            self.torsional.check(self)
        for k, p in enumerate(self.operating_points):
            self.check_operating_point(p, f"operating_points[{k}]")
        if self.api_audit is not None:
            self.api_audit.check(self)

    def check_operating_point(self, p: OperatingPoint, field: str = "operating_point") -> None:
        """Check an operating point's nodes and speed against the train (ModelError)."""
        nodes = {}
        for key in ("drive", "load"):
            ref = getattr(p, key)
            if ref is not None:
                nodes[key] = self.node_index(ref, f"{field}.{key}")
        if (p.power or p.torque) and len(nodes) == 2 and nodes["drive"] == nodes["load"]:
            si, node = nodes["load"]
            raise ModelError(
                "the load node is the drive node: the torque would react itself there and "
                "nothing would be transmitted through the train",
                field=f"{field}.load",
                value=f"shaft {self.shafts[si].name!r}, node {node}",
                expected="the node where the power leaves the train (another node than 'drive')",
            )
        for j, f in enumerate(p.forces):
            self.node_index(f, f"{field}.forces[{j}]")
        if p.power and p.reference_speed(self.speed) == 0.0:
            raise ModelError(
                "a power needs a non-zero speed (the torque is power / speed)",
                field=f"{field}.power",
                value=f"{p.power:.6g} W at 0 rpm",
                expected="a non-zero 'speed', or a 'torque' instead of the power",
            )

    def _check_speeds(self, ratios: list[float]) -> None:
        for i, s in enumerate(self.shafts):
            if s.speed is None:
                continue
            implied = ratios[i] * self.speed
            if abs(s.speed - implied) > 1e-3 * max(abs(implied), 1e-9) + 1e-9:
                raise ModelError(
                    "inconsistent speed set",
                    field=f"shafts[{i}].speed",
                    value=f"{s.speed * 30 / np.pi:.6g} rpm",
                    expected=f"{implied * 30 / np.pi:.6g} rpm from the reference speed "
                    f"{self.speed * 30 / np.pi:.6g} rpm of '{self.reference}' and the gear "
                    "ratios (N_i Ω_i = −N_j Ω_j)",
                )

    def shaft_speeds(self, reference_speed: float | None = None) -> NDArray:
        """Signed speed (rad/s) of every shaft for a reference-shaft speed (default nominal)."""
        w = self.speed if reference_speed is None else reference_speed
        return np.array([s.speed_ratio * w for s in self.layout().shafts])
