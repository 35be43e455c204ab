"""Results of the static analysis: bearing loads, mesh forces, shaft curves (issue 11)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["BearingLoad", "MeshLoad", "ShaftStatics", "StaticResult", "StaticSweep"]

OVERLOAD_FILM_FRACTION = 0.05  # a journal whose minimum film is below 5 % of its clearance


def _num(v: float) -> float | None:
    v = float(v)
    return None if math.isnan(v) else v


@dataclass(frozen=True)
class BearingLoad:
    """The static load on one bearing.

    ``force``: (Fx, Fy, Fz) N, the force the journal puts on the bearing (radial bearings: Fz
    = 0; thrust bearings: Fx = Fy = 0). ``kind``: ``"fluid-film"`` (solved to equilibrium),
    ``"linear"`` (constant or tabulated coefficients at the shaft speed) or ``"thrust"``.
    Fluid-film journals also give the journal position ``journal`` (x, y in m from the bearing
    centre), ``eccentricity_ratio``, ``attitude`` (rad, from the load towards the journal
    displacement, positive with the rotation), ``min_film`` (m), ``peak_pressure`` (Pa),
    ``power_loss`` (W) and ``clearance`` (m); NaN for the others.
    """

    name: str
    shaft: str
    node: int
    kind: str
    force: NDArray
    journal: tuple[float, float] = (math.nan, math.nan)
    eccentricity_ratio: float = math.nan
    attitude: float = math.nan
    min_film: float = math.nan
    peak_pressure: float = math.nan
    power_loss: float = math.nan
    clearance: float = math.nan

    @property
    def magnitude(self) -> float:
        """|F| (N)."""
        return float(np.linalg.norm(self.force))

    @property
    def angle(self) -> float:
        """Direction of the radial load (rad, from +x towards +y)."""
        return float(np.arctan2(self.force[1], self.force[0]))

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "shaft": self.shaft,
            "node": self.node,
            "kind": self.kind,
            "force_N": [float(v) for v in self.force],
            "magnitude_N": self.magnitude,
            "angle_deg": math.degrees(self.angle),
            "journal_um": [_num(v * 1e6) for v in self.journal],
            "eccentricity_ratio": _num(self.eccentricity_ratio),
            "attitude_deg": _num(math.degrees(self.attitude)),
            "min_film_um": _num(self.min_film * 1e6),
            "peak_pressure_MPa": _num(self.peak_pressure / 1e6),
            "power_loss_kW": _num(self.power_loss / 1e3),
        }


@dataclass(frozen=True)
class MeshLoad:
    """Tooth forces of one mesh (N) from the static solution: ``normal`` along the line of
    action of the loaded ``flank`` (+1: SPEC 2.3's, −1: the other), its ``tangential``,
    ``separating`` and (signed with the helix) ``axial`` parts, the torques on the two gears
    (N·m, about +z) and the ``misalignment`` (m): the difference of the two gears' tilts in the
    plane of action times the face width (NaN without a face width), the input to a face-load
    factor."""

    name: str
    flank: int
    normal: float
    tangential: float
    separating: float
    axial: float
    torque_gear: float
    torque_mate: float
    misalignment: float

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "flank": self.flank,
            "normal_N": self.normal,
            "tangential_N": self.tangential,
            "separating_N": self.separating,
            "axial_N": self.axial,
            "torque_gear_Nm": self.torque_gear,
            "torque_mate_Nm": self.torque_mate,
            "misalignment_um": _num(self.misalignment * 1e6),
        }


@dataclass(frozen=True)
class ShaftStatics:
    """Deflection and internal loads along one shaft.

    ``z``: node positions (m); ``deflection``: (n_nodes, 6) x, y, z (m), θx, θy, θz (rad);
    ``z_section``: (2 n_elements,) the start and end of every element; at those sections the
    internal force the part of the shaft at larger z exerts on the part at smaller z:
    ``shear`` (·, 2) Vx, Vy (N), ``axial`` (N), ``moment`` (·, 2) Mx, My (N·m), ``torque``
    (N·m); ``von_mises`` (Pa) at the outer surface from the axial force, the bending moment
    and the torque (σ = N/A + M r/I, τ = T r/J, √(σ² + 3τ²); transverse shear is zero there).
    """

    name: str
    z: NDArray
    deflection: NDArray
    z_section: NDArray
    shear: NDArray
    axial: NDArray
    moment: NDArray
    torque: NDArray
    von_mises: NDArray

    def to_dict(self) -> dict:
        d = self.deflection
        return {
            "name": self.name,
            "z_m": self.z.tolist(),
            "deflection_x_um": (d[:, 0] * 1e6).tolist(),
            "deflection_y_um": (d[:, 1] * 1e6).tolist(),
            "deflection_z_um": (d[:, 2] * 1e6).tolist(),
            "slope_x_urad": (d[:, 3] * 1e6).tolist(),
            "slope_y_urad": (d[:, 4] * 1e6).tolist(),
            "twist_urad": (d[:, 5] * 1e6).tolist(),
            "z_section_m": self.z_section.tolist(),
            "shear_x_N": self.shear[:, 0].tolist(),
            "shear_y_N": self.shear[:, 1].tolist(),
            "axial_N": self.axial.tolist(),
            "moment_x_Nm": self.moment[:, 0].tolist(),
            "moment_y_Nm": self.moment[:, 1].tolist(),
            "torque_Nm": self.torque.tolist(),
            "von_mises_MPa": (self.von_mises / 1e6).tolist(),
            "max_deflection_um": float(np.max(np.hypot(d[:, 0], d[:, 1])) * 1e6),
            "max_von_mises_MPa": float(np.max(self.von_mises) / 1e6),
        }


@dataclass(frozen=True)
class StaticResult:
    """The static operating point of a train.

    ``q``: the deflection over the global DOFs (m, rad; assembly order); ``speed``: reference
    speed (rad/s); ``drive_torque``/``load_torque`` (N·m about +z at the drive/load nodes);
    ``applied``: the sum of the external forces (weight, static forces; N) and ``residual``:
    the sum of all ground reactions plus the applied forces (N; zero to round-off at
    equilibrium); ``iterations``: outer iterations of the fluid-film journals; ``bearing_solves``:
    journal equilibria solved (cached ones not counted).
    """

    operating_point: str
    speed: float
    drive_torque: float
    load_torque: float
    power: float
    gravity: bool
    bearings: tuple[BearingLoad, ...]
    meshes: tuple[MeshLoad, ...]
    shafts: tuple[ShaftStatics, ...]
    q: NDArray = field(repr=False)
    applied: NDArray = field(repr=False)
    residual: NDArray = field(repr=False)
    iterations: int = 0
    bearing_solves: int = 0
    # the journal equilibria of the fluid-film bearings, by index in the model's bearings
    journals: dict = field(default_factory=dict, repr=False, compare=False)

    def bearing(self, name: str) -> BearingLoad:
        for b in self.bearings:
            if b.name == name:
                return b
        raise KeyError(name)

    def mesh(self, name: str) -> MeshLoad:
        for m in self.meshes:
            if m.name == name:
                return m
        raise KeyError(name)

    def shaft(self, name: str) -> ShaftStatics:
        for s in self.shafts:
            if s.name == name:
                return s
        raise KeyError(name)

    def to_dict(self) -> dict:
        return {
            "operating_point": self.operating_point,
            "speed_rpm": self.speed * 30 / math.pi,
            "power_kW": self.power / 1e3,
            "drive_torque_Nm": self.drive_torque,
            "load_torque_Nm": self.load_torque,
            "gravity": self.gravity,
            "applied_force_N": self.applied.tolist(),
            "equilibrium_residual_N": self.residual.tolist(),
            "iterations": self.iterations,
            "bearing_solves": self.bearing_solves,
            "bearings": [b.to_dict() for b in self.bearings],
            "meshes": [m.to_dict() for m in self.meshes],
            "shafts": [s.to_dict() for s in self.shafts],
        }

    def to_json(self, **kw) -> str:
        return json.dumps(self.to_dict(), **kw)

    def table(self) -> str:
        """Bearing loads and mesh forces as text."""
        lines = [
            f"operating point {self.operating_point}: {self.speed * 30 / math.pi:.6g} rpm, "
            f"{self.power / 1e3:.6g} kW, drive torque {self.drive_torque:.6g} N*m",
            f"{'bearing':<32}{'Fx N':>12}{'Fy N':>12}{'Fz N':>12}{'|F| N':>12}{'angle':>8}"
            f"{'ecc':>7}{'att deg':>8}{'hmin um':>9}{'pmax MPa':>9}{'loss kW':>8}",
        ]
        big = max([b.magnitude for b in self.bearings] + [m.normal for m in self.meshes] + [1.0])

        def clean(v):  # round-off (1e-12 of the largest force) shown as 0
            return 0.0 if abs(v) < 1e-12 * big else float(v)

        for b in self.bearings:
            d = b.to_dict()
            f = [clean(v) for v in b.force]

            def fmt(v, spec, width):
                return f"{'-':>{width}}" if v is None else f"{v:>{width}{spec}}"

            lines.append(
                f"{b.name[:31]:<32}{f[0]:>12.6g}{f[1]:>12.6g}{f[2]:>12.6g}"
                f"{clean(b.magnitude):>12.6g}{d['angle_deg'] if clean(b.magnitude) else 0.0:>8.1f}"
                + fmt(d["eccentricity_ratio"], ".3f", 7)
                + fmt(d["attitude_deg"], ".1f", 8)
                + fmt(d["min_film_um"], ".1f", 9)
                + fmt(d["peak_pressure_MPa"], ".2f", 9)
                + fmt(d["power_loss_kW"], ".2f", 8)
            )
        if self.meshes:
            lines.append(
                f"{'mesh':<32}{'Ft N':>12}{'Fr N':>12}{'Fa N':>12}{'Fn N':>12}{'misalign um':>13}"
            )
            for m in self.meshes:
                mis = "-" if math.isnan(m.misalignment) else f"{m.misalignment * 1e6:.2f}"
                lines.append(
                    f"{m.name[:31]:<32}{clean(m.tangential):>12.6g}{clean(m.separating):>12.6g}"
                    f"{clean(m.axial):>12.6g}{clean(m.normal):>12.6g}{mis:>13}"
                )
        lines.append(f"{'shaft':<32}{'max defl um':>12}{'max vM MPa':>12}")
        for s in self.shafts:
            d = np.hypot(s.deflection[:, 0], s.deflection[:, 1])
            lines.append(f"{s.name[:31]:<32}{d.max() * 1e6:>12.4g}{s.von_mises.max() / 1e6:>12.4g}")
        return "\n".join(lines)


@dataclass(frozen=True)
class StaticSweep:
    """Static results at several operating points, in order."""

    results: tuple[StaticResult, ...]

    def __iter__(self):
        return iter(self.results)

    def __len__(self) -> int:
        return len(self.results)

    def __getitem__(self, i):
        return self.results[i]

    def to_dict(self) -> dict:
        return {"operating_points": [r.to_dict() for r in self.results]}

    def table(self) -> str:
        return "\n\n".join(r.table() for r in self.results)
