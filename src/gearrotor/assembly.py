"""One path from a model to the global matrices and the DOF map.

Global DOF order: the nodes of shaft 0 (6 DOFs each, ``x, y, z, θx, θy, θz``), then shaft 1, ...,
then the pedestal (support) nodes, 2 DOFs each (``x, y``), then the pad DOFs of the tilting-pad
bearings with ``pad_dynamics`` (per bearing its pads' ``tilt_1, radial_1?, tilt_2, …``: rad and
m, :mod:`gearrotor.elements.pad_bearing`). Element matrices are scattered as COO triplets and
summed into CSR matrices once.

The equations of motion at a reference speed Ω_ref are

    M q̈ + (C + Σ_s Ω_s G_s) q̇ + (K + Σ_s Ω_s Kc_s) q = f,    Ω_s = ratio_s · Ω_ref,

where C and K include speed-dependent bearings evaluated at each bearing's own shaft speed, C
the shafts' material damping, and Kc_s the circulatory stiffness of shaft s's rotating
material damping (per unit speed; empty without it).
"""

from __future__ import annotations

import contextlib
import functools
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from .elements import (
    CoefficientTable,
    CouplingElement,
    CrossCoupling,
    DiskElement,
    MeshGeometry,
    PadBearing,
    PadTable,
    RadialBearing,
    ShaftElement,
    ThrustBearing,
    TorsionalSupportElement,
    WhirlBearing,
    buckingham_stiffness,
    fit_rows,
    iso6336_stiffness,
)
from .errors import ModelError
from .inputs import WHIRL_TABLE_COLUMNS, read_whirl_table, table_columns
from .model import Train

__all__ = ["Assembly", "MeshInfo", "BearingInfo", "assemble", "DOF_NAMES"]

DOF_NAMES = ("x", "y", "z", "θx", "θy", "θz")
_TZ2 = [5, 11]  # θz of the two nodes of a shaft element


class _Triplets:
    def __init__(self) -> None:
        self.rows: list[NDArray] = []
        self.cols: list[NDArray] = []
        self.vals: list[NDArray] = []

    def add(self, dofs: NDArray, mat: NDArray) -> None:
        dofs = np.asarray(dofs)
        r, c = np.meshgrid(dofs, dofs, indexing="ij")
        self.rows.append(r.ravel())
        self.cols.append(c.ravel())
        self.vals.append(np.asarray(mat, float).ravel())

    def csr(self, n: int) -> sp.csr_array:
        if not self.rows:
            return sp.csr_array((n, n))
        m = sp.coo_array(
            (np.concatenate(self.vals), (np.concatenate(self.rows), np.concatenate(self.cols))),
            shape=(n, n),
        ).tocsr()
        m.sum_duplicates()
        m.eliminate_zeros()
        return m


@dataclass(frozen=True)
class MeshInfo:
    """A gear mesh resolved to global DOFs."""

    name: str
    dofs: NDArray  # (12,) global DOFs of gear i then gear j
    geometry: MeshGeometry
    w: NDArray  # (12,) kinematic vector, δ = w · q[dofs]
    stiffness: float  # average Kg, N/m
    damping: float  # N·s/m (resolved from the model's damping_ratio when it gives one)
    shafts: tuple[int, int]
    teeth: tuple[int, int]
    spec_index: int


@dataclass(frozen=True)
class BearingInfo:
    """A radial bearing resolved to global DOFs (x, y of the journal, and of its pedestal; the
    pad DOFs of a bearing with pad dynamics)."""

    name: str
    shaft: int
    dofs: NDArray  # (2,) journal x, y
    support_dofs: NDArray | None  # (2,) pedestal x, y, or None for ground
    element: RadialBearing | PadBearing | WhirlBearing
    kind: str = "bearing"  # "bearing" or "seal" (an annular seal to ground, any sign)
    pad_dofs: NDArray | None = None  # (m,) the pads' DOFs (PadBearing), in PadTable.dofs order

    def local(self) -> tuple[NDArray, NDArray]:
        """(global DOFs, T): the bearing's coordinates u = T q[dofs] (journal relative to the
        housing, then the pads), ``dofs`` = journal, pedestal (if any), pads."""
        parts = [self.dofs]
        if self.support_dofs is not None:
            parts.append(self.support_dofs)
        m = 0 if self.pad_dofs is None else len(self.pad_dofs)
        if m:
            parts.append(self.pad_dofs)
        d = np.concatenate(parts)
        T = np.zeros((2 + m, len(d)))
        T[:2, :2] = np.eye(2)
        if self.support_dofs is not None:
            T[:2, 2:4] = -np.eye(2)
        if m:
            T[2:, len(d) - m :] = np.eye(m)
        return d, T

    def scatter(self, K: _Triplets, C: _Triplets, speed: float) -> None:
        if self.pad_dofs is not None:
            k, c = self.element.pads.at(speed)
        else:
            k, c = self.element.K(speed), self.element.C(speed)
        d, T = self.local()
        K.add(d, T.T @ k @ T)
        C.add(d, T.T @ c @ T)

    def journal_force(self, q: NDArray, qdot: NDArray, speed: float) -> NDArray:
        """Film force (Fx, Fy) on the journal (N) about the equilibrium at global displacement
        ``q`` and velocity ``qdot`` (n_dof,) or (n_dof, n_t): ``−(K u + C u̇)[x, y]``."""
        d, T = self.local()
        if self.pad_dofs is not None:
            k, c = self.element.pads.at(speed)
        else:
            k, c = self.element.K(speed), self.element.C(speed)
        return -(k @ T @ q[d] + c @ T @ qdot[d])[:2]


@dataclass(frozen=True)
class Assembly:
    """Global matrices and DOF map of a train (SI units)."""

    train: Train
    n_dof: int
    node_offset: tuple[NDArray, ...]  # per shaft: global index of DOF x of each node
    M: sp.csr_array
    K0: sp.csr_array  # speed-independent stiffness (shafts, couplings, meshes, constant bearings)
    C0: sp.csr_array
    G_shaft: tuple[sp.csr_array, ...]  # per shaft, per unit of that shaft's speed
    Kc_shaft: tuple[sp.csr_array, ...]  # per shaft: rotating-damping circulatory, idem
    speed_ratio: NDArray  # per shaft, Ω_s / Ω_ref
    meshes: tuple[MeshInfo, ...]
    bearings: tuple[BearingInfo, ...] = field(repr=False)
    dof_labels: tuple[str, ...] = field(repr=False)
    support_offset: tuple[int, ...] = ()

    @property
    def pad_dofs(self) -> NDArray:
        """Global indices of every pad DOF (bearings with pad dynamics), ascending."""
        parts = [b.pad_dofs for b in self.bearings if b.pad_dofs is not None]
        return np.concatenate(parts) if parts else np.zeros(0, int)

    # --- DOF helpers ------------------------------------------------------------------------
    def dof(self, shaft: int, node: int, direction: int) -> int:
        return int(self.node_offset[shaft][node] + direction)

    def shaft_dofs(self, shaft: int, direction: int) -> NDArray:
        return self.node_offset[shaft] + direction

    def dof_kind(self) -> NDArray:
        """Per DOF: 0 lateral (x, y, θx, θy, pedestals), 1 axial (z), 2 torsional (θz), 3 pad
        (the tilts and radial pivot DOFs of bearings with pad dynamics)."""
        kind = np.zeros(self.n_dof, int)
        for offs in self.node_offset:
            kind[offs + 2] = 1
            kind[offs + 5] = 2
        kind[self.pad_dofs] = 3
        return kind

    # --- matrices at a speed -----------------------------------------------------------------
    def shaft_speeds(self, speed: float) -> NDArray:
        return self.speed_ratio * speed

    def matrices(
        self, speed: float
    ) -> tuple[sp.csr_array, sp.csr_array, sp.csr_array, sp.csr_array]:
        """(M, C, G, K) at reference-shaft speed ``speed`` (rad/s); G already scaled by speeds,
        K including the circulatory stiffness of rotating damping (:meth:`circulatory`)."""
        speeds = self.shaft_speeds(speed)
        G = sp.csr_array((self.n_dof, self.n_dof))
        for s, g in zip(speeds, self.G_shaft, strict=True):
            if s != 0.0:
                G = G + s * g
        Kt, Ct = _Triplets(), _Triplets()
        for b in self.bearings:
            if b.element.speed_dependent:
                b.scatter(Kt, Ct, speeds[b.shaft])
        K = self.K0 + Kt.csr(self.n_dof) + self.circulatory(speeds)
        return self.M, self.C0 + Ct.csr(self.n_dof), G, K

    def circulatory(self, speeds: NDArray) -> sp.csr_array:
        """Σ_s Ω_s Kc_s (skew, N/m, N, N·m) at the shaft speeds ``speeds`` (rad/s, per shaft):
        the circulatory stiffness of the shafts' rotating material damping."""
        out = sp.csr_array((self.n_dof, self.n_dof))
        for s, kc in zip(speeds, self.Kc_shaft, strict=True):
            if s != 0.0 and kc.nnz:
                out = out + s * kc
        return out

    @property
    def rotating_damping(self) -> bool:
        """True when a shaft has rotating (internal) material damping."""
        return any(kc.nnz for kc in self.Kc_shaft)

    @property
    def speed_dependent(self) -> bool:
        return any(b.element.speed_dependent for b in self.bearings)


def _shaft_elements(train: Train, i: int) -> list[ShaftElement]:
    s = train.shafts[i]
    out = []
    for sec in s.sections:
        mat = train.materials[sec.material or s.material]
        h = sec.length / sec.elements
        damping = mat.damping
        alpha, beta = damping.rayleigh if damping is not None else (0.0, 0.0)
        el = ShaftElement(
            length=h,
            outer_diameter=sec.outer_diameter,
            inner_diameter=sec.inner_diameter,
            E=mat.E,
            shear_modulus=mat.G,
            density=mat.density,
            mass_outer_diameter=sec.mass_outer_diameter,
            mass_inner_diameter=sec.mass_inner_diameter,
            shear_method=train.shear_method,
            alpha=alpha,
            beta=beta,
            rotating_damping=damping is not None and damping.rotating,
            # the torsional rod given directly: n elements in series, the inertia shared
            torsional_stiffness=None
            if sec.torsional_stiffness is None
            else sec.torsional_stiffness * sec.elements,
            polar_mass=None if sec.polar_inertia is None else sec.polar_inertia / sec.elements,
            torsional_damping=None
            if sec.torsional_damping is None
            else sec.torsional_damping * sec.elements,
        )
        out.extend([el] * sec.elements)
    return out


def _disk_element(train: Train, shaft_i: int, k: int) -> DiskElement:
    s = train.shafts[shaft_i]
    d = s.disks[k]
    if d.mass is not None:
        return DiskElement(d.mass, d.polar, d.transverse)
    mat = train.material(d.material or s.material, f"shafts[{shaft_i}].disks[{k}].material")
    D, di, w = d.outer_diameter, d.inner_diameter, d.width
    if di >= D:
        raise ModelError(
            "disk inner diameter must be smaller than its outer diameter",
            field=f"shafts[{shaft_i}].disks[{k}].inner_diameter",
            value=di,
        )
    m = mat.density * np.pi / 4 * (D**2 - di**2) * w
    return DiskElement(m, m / 8 * (D**2 + di**2), m / 16 * (D**2 + di**2) + m * w**2 / 12)


def mesh_stiffness(train: Train, k: int) -> float:
    """Average mesh stiffness Kg (N/m) of mesh k: given, Buckingham, ISO 6336-1, or the mean
    loaded stiffness of its tooth geometry (:func:`gearrotor.gears.model_mesh.model_mesh`)."""
    m = train.meshes[k]
    if m.geometry is not None:
        from .gears.model_mesh import model_mesh

        return model_mesh(train, k).curves.mean_stiffness
    if isinstance(m.stiffness, float):
        return m.stiffness
    if m.stiffness.method == "value":
        return m.stiffness.value

    def modulus(side, field):
        if side.E is not None:
            return side.E
        si = train.shaft_index(side.shaft, f"meshes[{k}].{field}.shaft")
        return train.materials[train.shafts[si].material].E

    Ei, Ej = modulus(m.gear, "gear"), modulus(m.mate, "mate")
    c = m.stiffness.contact_ratio
    if m.stiffness.method == "buckingham":
        return buckingham_stiffness(c, m.face_width, Ei, Ej)
    return iso6336_stiffness(
        m.gear.teeth, m.mate.teeth, m.face_width, c, m.helix_angle, m.pressure_angle, Ei, Ej
    )


def _film_table(b, field: str, shaft) -> CoefficientTable | PadBearing:
    """Speed table of a bearing from a saved file or from the fluid-film solver; a
    :class:`PadBearing` (full coefficients, pad DOFs) for ``fluid_film.pad_dynamics``."""
    from .bearings import load_bearing
    from .bearings.io import load_table_file

    try:
        if b.table_file is not None:
            t = load_table_file(b.table_file)
            speed = np.abs(np.asarray(t.speed_rpm)) * np.pi / 30
            vals = np.column_stack([t.kxx, t.kxy, t.kyx, t.kyy, t.cxx, t.cxy, t.cyx, t.cyy])
        else:
            ff = b.fluid_film
            sign = 1.0 if shaft.speed_ratio >= 0 else -1.0  # the journal turns with its shaft
            order = np.argsort(np.abs(ff.speeds), kind="stable")
            rpm = tuple(sign * np.abs(np.asarray(ff.speeds)[order]) * 30 / np.pi)
            if ff.loads is not None:
                loads = tuple(tuple(ff.loads[i]) for i in order)
            elif ff.load is not None:
                loads = (tuple(ff.load),) * len(rpm)
            else:
                case = load_bearing(ff.file)
                if ff.load_case >= len(case.loads):
                    raise ModelError(
                        "no such load case in the bearing file",
                        field=f"{field}.fluid_film.load_case",
                        value=ff.load_case,
                        expected=f"0..{len(case.loads) - 1} or a 'load'",
                    )
                loads = (tuple(case.loads[ff.load_case]),) * len(rpm)
            mtime = Path(ff.file).stat().st_mtime_ns if Path(ff.file).exists() else 0
            pads = (ff.pad_inertia, ff.pad_mass, ff.pivot_stiffness)
            if ff.pad_dynamics:
                tab = _solve_pad_table(ff.file, mtime, loads, rpm, pads, field)
                return PadBearing.from_pads(replace(tab, extrapolate=b.extrapolate))
            speed, vals = _solve_film_table(ff.file, mtime, loads, rpm, pads, field)
    except ModelError as exc:
        raise ModelError(
            exc.message,
            field=exc.field or field,
            value=exc.value,
            expected=exc.expected,
            file=exc.file,
        ) from None
    order = np.argsort(speed)
    return CoefficientTable(speed[order], vals[order], b.extrapolate)


def _film_case(file: str, pads: tuple, field: str, pad_dynamics: bool):
    """The bearing case of a file with the model's pad overrides (checked for pad dynamics)."""
    from .bearings import load_bearing
    from .bearings.geometry import TiltingPadBearing
    from .bearings.pads import with_pad_properties

    case = load_bearing(file)
    inertia, mass, kp = pads
    if pad_dynamics or any(v is not None for v in pads):
        if not pad_dynamics and not isinstance(case.bearing, TiltingPadBearing):
            raise ModelError(
                "pad properties are given for a bearing without tilting pads",
                field=f"{field}.fluid_film",
                value=f"a {type(case.bearing).__name__}",
                expected="pad_inertia, pad_mass and pivot_stiffness only with a tilting-pad file",
            )
        bearing = (
            with_pad_properties(
                case.bearing,
                inertia=inertia,
                mass=mass,
                pivot_stiffness=kp,
                field=f"{field}.fluid_film",
            )
            if pad_dynamics
            else replace(
                case.bearing,
                pads=tuple(
                    replace(
                        p,
                        inertia=p.inertia if inertia is None else inertia,
                        mass=p.mass if mass is None else mass,
                        pivot_stiffness=p.pivot_stiffness if kp is None else kp,
                    )
                    for p in case.bearing.pads
                ),
            )
        )
        case = replace(case, bearing=bearing)
    return case


#: The code a fluid-film table comes from (:mod:`gearrotor.cache` fingerprints it).
_FILM_SOURCES = ("bearings", "elements")


def _case_key(case) -> tuple:
    """What a bearing file's table depends on, as parsed: the bearing without its name, the
    solver options, the lubricant (not the file's path, name or notes, nor its load cases:
    the loads are part of the key on their own)."""
    return (
        replace(case.bearing, name=""),
        case.options,
        case.lubricant,
        case.temperature,
    )


@functools.lru_cache(maxsize=64)
def _solve_film_table(file: str, mtime_ns: int, loads: tuple, rpm: tuple, pads: tuple, field: str):
    """Solve a fluid-film table once per (file version, loads, speeds, pad overrides):
    re-assembling a model that only changes elsewhere (a destabiliser sweep, an override)
    reuses it. The synchronously reduced coefficients (:func:`gearrotor.bearings.coefficients`)
    at each speed's load."""
    from . import cache
    from .bearings import coefficients_table

    case = _film_case(file, pads, field, False)

    def solve() -> dict:
        if len(set(loads)) == 1:
            t = coefficients_table(case.bearing, loads[0], list(rpm), options=case.options)
            return {"values": t.values()}
        rows = [
            coefficients_table(case.bearing, load, [n], options=case.options).values()
            for load, n in zip(loads, rpm, strict=True)
        ]
        return {"values": np.vstack(rows)}

    vals = cache.arrays(
        "film-table", ("synchronous", _case_key(case), loads, rpm), solve, sources=_FILM_SOURCES
    )["values"]
    speed = np.abs(np.asarray(rpm)) * np.pi / 30
    speed.setflags(write=False)
    vals.setflags(write=False)
    return speed, vals


@functools.lru_cache(maxsize=64)
def _solve_pad_table(file: str, mtime_ns: int, loads: tuple, rpm: tuple, pads: tuple, field: str):
    """The full coefficients of a tilting-pad file (:func:`gearrotor.bearings.pads.pad_table`)
    once per (file version, loads, speeds, pad overrides)."""
    from . import cache
    from .bearings import equilibrium
    from .bearings.pads import pad_table_from_equilibria

    case = _film_case(file, pads, field, True)

    def solve() -> dict:
        eqs, prev = [], None
        for load, n in zip(loads, rpm, strict=True):
            eq = equilibrium(case.bearing, load, n * np.pi / 30, options=case.options, start=prev)
            eqs.append(eq)
            prev = eq
        t = pad_table_from_equilibria(case.bearing, eqs, options=case.options)
        return {
            "speed": t.speed,
            "K": t.K,
            "C": t.C,
            "M": t.M,
            "lever": t.lever,
            "dofs": np.array(t.dofs, dtype=str),
        }

    a = cache.arrays(
        "film-table", ("pads", _case_key(case), loads, rpm), solve, sources=_FILM_SOURCES
    )
    return PadTable(
        a["speed"], a["K"], a["C"], a["M"], tuple(str(d) for d in a["dofs"]), a["lever"]
    )


def _seal_file_state(sl, shaft, train_speed: float) -> tuple[int, float]:
    """A seal file's version (its mtime, for the caches) and the sense of its rotor surface:
    the surface turns with its shaft, about −z when the shaft's nominal speed is negative."""
    mtime = Path(sl.file).stat().st_mtime_ns if Path(sl.file).exists() else 0
    spin = shaft.speed_ratio * (train_speed if train_speed else 1.0)
    return mtime, 1.0 if spin >= 0 else -1.0


def _seal_table(sl, field: str, shaft, train_speed: float) -> CoefficientTable:
    """Synchronous coefficients of a seal file (``gearrotor.seals``) at the seal's speeds."""
    mtime, sign = _seal_file_state(sl, shaft, train_speed)
    with _errors_under(f"{field}.file"):
        speed, vals = _solve_seal_table(sl.file, mtime, tuple(sl.speeds), sign)
    return CoefficientTable(speed, vals, sl.extrapolate)


@functools.lru_cache(maxsize=64)
def _solve_seal_table(file: str, mtime_ns: int, speeds: tuple, sign: float):
    """A seal's table once per (file version, speeds, sense of rotation)."""
    from .seals import load_seal, seal_table

    speed, vals = seal_table(load_seal(file), speeds, sign)
    speed.setflags(write=False)
    vals.setflags(write=False)
    return speed, vals


def _table_element(t, tolerance: float | None, field: str) -> RadialBearing | WhirlBearing:
    """The element of a model's coefficient ``table``: a speed table, or a speed × whirl table
    (a whirl table whose rows are constant in whirl is the speed table of its values, exactly
    as the one-dimensional table gives it)."""
    names = (t.kxx, t.kxy, t.kyx, t.kyy, t.cxx, t.cxy, t.cyx, t.cyy)
    if t.whirl is not None and t.whirl_dependent:
        return _whirl_element(t.whirl_rows(), t.extrapolate, tolerance, field)
    if t.whirl is not None:
        names = tuple([row[0] for row in col] for col in names)
    vals = np.column_stack(names)
    return RadialBearing(table=CoefficientTable(np.asarray(t.speed), vals, t.extrapolate))


def _whirl_file_element(b, field: str) -> RadialBearing | WhirlBearing:
    """The element of a speed × whirl ``table_file`` (a ``whirl_rpm`` column)."""
    with _errors_under(f"{field}.table_file"):
        rows = read_whirl_table(b.table_file)
    return _whirl_element(
        rows, b.extrapolate, b.fit_tolerance, f"{field}.table_file", file=b.table_file
    )


def _seal_whirl_element(sl, field: str, shaft, train_speed: float) -> WhirlBearing | RadialBearing:
    """A seal file solved over speed × whirl (``[[seals]] whirls``)."""
    mtime, sign = _seal_file_state(sl, shaft, train_speed)
    with _errors_under(f"{field}.file"):
        rows = _solve_seal_whirl_table(sl.file, mtime, tuple(sl.speeds), tuple(sl.whirls), sign)
    return _whirl_element(rows, sl.extrapolate, sl.fit_tolerance, f"{field}.whirls")


@functools.lru_cache(maxsize=32)
def _solve_seal_whirl_table(file: str, mtime_ns: int, speeds: tuple, whirls: tuple, sign: float):
    """A seal's speed × whirl rows once per (file version, speeds, whirls, sense of rotation)."""
    from .seals import load_seal, seal_whirl_table

    rows = seal_whirl_table(load_seal(file), speeds, whirls, sign)
    for _, w, v in rows:
        w.setflags(write=False)
        v.setflags(write=False)
    return rows


def _whirl_element(rows, extrapolate: str, tolerance: float | None, field: str, file=None):
    """A :class:`WhirlBearing` from checked rows ``(speed, whirl, values)``, each row's
    impedance fitted (:func:`~gearrotor.elements.fit_rows`); rows constant in whirl everywhere
    give the speed table of their values (a :class:`RadialBearing`)."""
    if all(np.all(v == v[0]) for _, _, v in rows):
        speed = np.array([s for s, _, _ in rows])
        vals = np.array([v[0] for _, _, v in rows])
        return RadialBearing(table=CoefficientTable(speed, vals, extrapolate))
    return WhirlBearing(fit_rows(rows, tolerance, field=field, file=file), extrapolate)


def _flank(train: Train, mesh, si: int, sj: int) -> int:
    """+1 (SPEC 2.3 normal) or −1 so that the contact force opposes the driver's rotation."""
    if mesh.driver is None:
        return 1
    shafts = train.layout().shafts
    ratio = shafts[si if mesh.driver == "gear" else sj].speed_ratio
    spin = np.sign(ratio * train.speed) if train.speed != 0 else np.sign(ratio)
    # with flank +1 a compressive contact force puts +z torque on both gears
    return 1 if spin < 0 else -1


#: The assemblies of the last trains assembled, by identity: a :class:`Train` is frozen, so its
#: assembly is too, and an analysis called again on the same train object (a loop over speeds,
#: ``modal(train, speed=w)``) does not rebuild its element matrices (issue 28: 0.1 s of the
#: ROSS compressor's 336-DOF eigen solve). The trains are held, so an id is never reused.
_ASSEMBLED: dict[int, tuple[Train, Assembly]] = {}
_ASSEMBLED_SIZE = 8


def assemble(train: Train) -> Assembly:
    """Build the global matrices of a train (raises :class:`ModelError` on bad input); the same
    train object gives the same (immutable) assembly."""
    hit = _ASSEMBLED.get(id(train))
    if hit is not None and hit[0] is train:
        return hit[1]
    asm = _assemble(train)
    if len(_ASSEMBLED) >= _ASSEMBLED_SIZE:
        _ASSEMBLED.pop(next(iter(_ASSEMBLED)))
    _ASSEMBLED[id(train)] = (train, asm)
    return asm


def _assemble(train: Train) -> Assembly:
    layout = train.layout()
    offsets = []
    n = 0
    labels: list[str] = []
    for sl in layout.shafts:
        offsets.append(n + 6 * np.arange(sl.n_nodes))
        n += 6 * sl.n_nodes
        labels += [f"{sl.name}[{j}].{d}" for j in range(sl.n_nodes) for d in DOF_NAMES]
    support_offset = []
    for k, b in enumerate(train.bearings):
        if b.support is not None:
            support_offset.append(n)
            labels += [f"bearings[{k}].support.x", f"bearings[{k}].support.y"]
            n += 2
        else:
            support_offset.append(-1)
    # the bearing elements first: a bearing with pad dynamics adds its pads' DOFs
    elements, shaft_of = [], []
    for k, b in enumerate(train.bearings):
        si, _ = train.node_index(b, f"bearings[{k}]")
        shaft_of.append(si)
        if b.table is not None:
            el = _table_element(b.table, b.fit_tolerance, f"bearings[{k}].table")
        elif b.table_file is not None and table_columns(b.table_file) == WHIRL_TABLE_COLUMNS:
            el = _whirl_file_element(b, f"bearings[{k}]")
        elif b.table_file is not None or b.fluid_film is not None:
            tab = _film_table(b, f"bearings[{k}]", layout.shafts[si])
            el = tab if isinstance(tab, PadBearing) else RadialBearing(table=tab)
        else:
            el = RadialBearing(*b.coefficients())
        elements.append(el)
    pad_offset = []
    for k, el in enumerate(elements):
        if isinstance(el, PadBearing):
            pad_offset.append(n + np.arange(el.n_pad_dofs))
            labels += [f"bearings[{k}].{d}" for d in el.pads.dofs[2:]]
            n += el.n_pad_dofs
        else:
            pad_offset.append(None)

    M, K, C = _Triplets(), _Triplets(), _Triplets()
    G, Kc = [], []
    for i, sl in enumerate(layout.shafts):
        Gi, Kci = _Triplets(), _Triplets()
        spin = np.zeros(sl.n_nodes)  # torsional mass-proportional damping force of a unit spin
        for e, el in enumerate(_shaft_elements(train, i)):
            dofs = np.concatenate([offsets[i][e] + np.arange(6), offsets[i][e + 1] + np.arange(6)])
            M.add(dofs, el.M())
            K.add(dofs, el.K())
            Gi.add(dofs, el.G())
            if el.damped:
                C.add(dofs, el.C())
                spin[e : e + 2] += el.alpha * el.M()[np.ix_(_TZ2, _TZ2)].sum(axis=1)
            if el.rotating_damping:
                Kci.add(dofs, el.Kc())
        if spin.any():
            # material damping cannot brake the spin: the torsional α M part C_t becomes
            # C_t − c cᵀ / (rᵀc), c = C_t r, r the rigid rotation (rank one, symmetric, C_t r = 0);
            # for a uniform α this is α(M − M r rᵀM / rᵀMr) on the shaft's elements, which leaves
            # the damping α of a vibration mode M-orthogonal to r (a free shaft's) unchanged
            nz = np.flatnonzero(spin)
            C.add(offsets[i][nz] + 5, -np.outer(spin[nz], spin[nz]) / spin.sum())
        Kc.append(Kci.csr(n))
        for k, d in enumerate(train.shafts[i].disks):
            _, node = train.node_index(d, f"shafts[{i}].disks[{k}]", shaft=sl.name)
            el = _disk_element(train, i, k)
            dofs = offsets[i][node] + np.arange(6)
            M.add(dofs, el.M())
            Gi.add(dofs, el.G())
        G.append(Gi.csr(n))

    def node_dofs(ref, field, dirs):
        si, node = train.node_index(ref, field)
        return si, offsets[si][node] + np.asarray(dirs)

    bearings = []
    for k, b in enumerate(train.bearings):
        si, dofs = node_dofs(b, f"bearings[{k}]", [0, 1])
        el = elements[k]
        if pad_offset[k] is not None:  # the pads' inertia (constant), on their own DOFs
            M.add(pad_offset[k], el.M_full[2:, 2:])
        sup = None
        if b.support is not None:
            so = support_offset[k]
            sup = np.array([so, so + 1])
            M.add(sup, np.eye(2) * b.support.mass)
            K.add(sup, np.diag([b.support.kxx, b.support.kyy]))
            C.add(sup, np.diag([b.support.cxx, b.support.cyy]))
        info = BearingInfo(b.name or f"bearings[{k}]", si, dofs, sup, el, pad_dofs=pad_offset[k])
        if not el.speed_dependent:
            info.scatter(K, C, 0.0)
        bearings.append(info)
    for k, sl in enumerate(train.seals):  # seals: like a bearing to ground, any sign
        si, dofs = node_dofs(sl, f"seals[{k}]", [0, 1])
        if sl.table is not None:
            el = _table_element(sl.table, sl.fit_tolerance, f"seals[{k}].table")
        elif sl.table_file is not None and table_columns(sl.table_file) == WHIRL_TABLE_COLUMNS:
            el = _whirl_file_element(sl, f"seals[{k}]")
        elif sl.table_file is not None:
            el = RadialBearing(table=_film_table(sl, f"seals[{k}]", layout.shafts[si]))
        elif sl.file is not None and sl.whirls is not None:
            el = _seal_whirl_element(sl, f"seals[{k}]", layout.shafts[si], train.speed)
        elif sl.file is not None:
            el = RadialBearing(table=_seal_table(sl, f"seals[{k}]", layout.shafts[si], train.speed))
        else:
            el = RadialBearing(*sl.coefficients())
        info = BearingInfo(sl.name or f"seals[{k}]", si, dofs, None, el, kind="seal")
        if not el.speed_dependent:
            info.scatter(K, C, 0.0)
        bearings.append(info)
    for k, t in enumerate(train.thrust_bearings):
        _, dofs = node_dofs(t, f"thrust_bearings[{k}]", [2])
        el = ThrustBearing(t.kzz, t.czz)
        K.add(dofs, el.K())
        C.add(dofs, el.C())
    for k, t in enumerate(train.torsional_supports):
        _, dofs = node_dofs(t, f"torsional_supports[{k}]", [5])
        el = TorsionalSupportElement(t.k, t.c)
        K.add(dofs, el.K())
        C.add(dofs, el.C())
    for k, q in enumerate(train.cross_couplings):
        _, dofs = node_dofs(q, f"cross_couplings[{k}]", [0, 1])
        K.add(dofs, CrossCoupling(q.q).K())
    for k, c in enumerate(train.couplings):
        _, di = node_dofs(c.node_i, f"couplings[{k}].node_i", range(6))
        _, dj = node_dofs(c.node_j, f"couplings[{k}].node_j", range(6))
        el = CouplingElement(
            (c.kx, c.ky, c.kz, c.ktx, c.kty, c.ktz), (c.cx, c.cy, c.cz, c.ctx, c.cty, c.ctz)
        )
        K.add(np.concatenate([di, dj]), el.K())
        C.add(np.concatenate([di, dj]), el.C())
    meshes = []
    for k, m in enumerate(train.meshes):
        si, di = node_dofs(m.gear, f"meshes[{k}].gear", range(6))
        sj, dj = node_dofs(m.mate, f"meshes[{k}].mate", range(6))
        ri, rj = train.pitch_radii(k)
        geo = MeshGeometry(
            ri, rj, m.pressure_angle, m.helix_angle, m.orientation, _flank(train, m, si, sj)
        )
        kg = mesh_stiffness(train, k)
        dofs = np.concatenate([di, dj])
        K.add(dofs, geo.K(kg))
        C.add(dofs, geo.C(m.damping))
        meshes.append(
            MeshInfo(
                m.name or f"meshes[{k}]",
                dofs,
                geo,
                geo.w(),
                kg,
                m.damping,
                (si, sj),
                (m.gear.teeth, m.mate.teeth),
                k,
            )
        )

    asm = Assembly(
        train=train,
        n_dof=n,
        node_offset=tuple(offsets),
        M=M.csr(n),
        K0=K.csr(n),
        C0=C.csr(n),
        G_shaft=tuple(G),
        Kc_shaft=tuple(Kc),
        speed_ratio=np.array([s.speed_ratio for s in layout.shafts]),
        meshes=tuple(meshes),
        bearings=tuple(bearings),
        dof_labels=tuple(labels),
        support_offset=tuple(support_offset),
    )
    return _with_mesh_damping_ratios(asm)


def _with_mesh_damping_ratios(asm: Assembly) -> Assembly:
    """Resolve ``Mesh.damping_ratio`` into the mesh damper ``c w wᵀ`` of C0, once, for every
    analysis (modal, Campbell, unbalance, transient, Floquet).

    The mesh mode is the undamped mode φ_i (mass-normalised; the model at its nominal speed
    without gyroscopics, the symmetric part of its stiffness, the meshes at Kg) with the largest
    mesh strain-energy fraction ``Kg (w·φ_i)² / ω_i²``. A damper ``c w wᵀ`` adds ``c (w·φ_i)²``
    to that mode's modal damping ``2 ζ ω_i``, hence ``c = 2 ζ ω_i / (w·φ_i)²``.
    """
    train = asm.train
    specs = [train.meshes[m.spec_index] for m in asm.meshes]
    if all(s.damping_ratio is None for s in specs):
        return asm
    import scipy.linalg as la

    for m, s in zip(asm.meshes, specs, strict=True):
        if s.damping_ratio is not None and s.damping > 0:
            raise ModelError(
                "give either mesh 'damping' or 'damping_ratio', not both",
                field=f"meshes[{m.spec_index}].damping_ratio",
                value=s.damping_ratio,
            )
    M, _, _, K = asm.matrices(train.speed)
    Kd = K.toarray()
    try:
        w2, V = la.eigh(0.5 * (Kd + Kd.T), M.toarray())
    except la.LinAlgError:
        raise ModelError(
            "mesh damping_ratio needs a positive definite mass matrix (mass on every DOF)",
            field=f"meshes[{asm.meshes[0].spec_index}].damping_ratio",
        ) from None
    # rigid-body modes: ω² at round-off, ~ε·max ω² (1e-16); elastic modes of stiff models (a
    # mesh mode under 1e14 N/m bearings) can be 1e-8 of max ω², so the cut is at 1e-10
    elastic = w2 > 1e-10 * w2.max()
    C = _Triplets()
    meshes = []
    for m, s in zip(asm.meshes, specs, strict=True):
        if s.damping_ratio is None:
            meshes.append(m)
            continue
        wphi = V[m.dofs].T @ m.w
        frac = np.where(elastic, m.stiffness * wphi**2 / np.where(elastic, w2, 1.0), 0.0)
        i = int(np.argmax(frac))
        c = 2.0 * s.damping_ratio * float(np.sqrt(w2[i])) / wphi[i] ** 2
        C.add(m.dofs, c * np.outer(m.w, m.w))
        meshes.append(replace(m, damping=float(c)))
    return replace(asm, C0=asm.C0 + C.csr(asm.n_dof), meshes=tuple(meshes))


@contextlib.contextmanager
def _errors_under(field: str):
    """A referenced file's input error named under the model field that references it
    (``bearings[0].table_file (kxx)``; its own field in brackets, its file kept)."""
    try:
        yield
    except ModelError as exc:
        raise ModelError(
            exc.message,
            field=field + (f" ({exc.field})" if exc.field else ""),
            value=exc.value,
            expected=exc.expected,
            file=exc.file,
        ) from None
