"""Static analysis of a train at an operating point (issue 11).

The whole train is solved at once with :func:`.solver.solve_static`: the stiffness of the
shafts, couplings, thrust bearings and linear bearings (constant, or tabulated coefficients at
each shaft's speed), the gear meshes as contacts on the flank the torque loads, and the loads
of the operating point: weight (the consistent mass times the gravity field: shafts, disks,
gear bodies, pedestals), the drive and load torques and static forces. The rigid-body motions
the stiffness leaves free (the train's rotation, an axial float without thrust bearing) are
held by the solver's constraint; a load that one of them would have to react (a torque that
does not balance, an axial force without thrust bearing) is an input error. Everything stays
sparse (``method="sparse"``, memory and time linear in the mesh size; issue 23): the rigid
motions are the null space within the shafts' kinematic rigid motions
(:func:`.solver.rigid_modes_in`), the solve a sparse LU; ``method="dense"`` is the reference
(dense LU, SVD of the whole stiffness) the sparse path is tested against.

Fluid-film journals are nonlinear: each is replaced by its film force linearised about a
journal equilibrium, ``F(d) ≈ −W_b − K_b (d − d_b)`` (``d_b`` the equilibrium position of the
standalone bearing solver under load ``W_b``, ``K_b`` its stiffness); the train is solved, the
load the journal then carries, ``W = W_b + K_b (d − d_b)``, becomes the next ``W_b``, until it
changes by less than the bearing solver's force tolerance. On a shaft with two bearings the
loads are statically determinate and one bearing solve per journal settles it; three or more
bearings on a shaft converge like Newton's method. Journal solves are cached by (file, load,
speed), so a sweep or an analysis repeating an operating point reuses them.

Left out: cross-coupled destabilisers and the circulatory stiffness of rotating damping
(dynamic effects that need whirl), unbalance (a rotating load), and annular seals
(``[[seals]]``, constant or tabulated coefficients alike): a seal's coefficients are those of
small motions about the rotor's running position (computed for a centred rotor), not a support
that carries load, so the bearing loads are those of the bearings alone, as ROSS and the usual
bearing-load calculation have them, and a seal's negative direct stiffness (a labyrinth's)
cannot turn the static problem into a divergence. The seals act in every dynamic analysis about
the static state (the transient at an operating point holds them centred on it).
"""

from __future__ import annotations

import functools
import hashlib
import math
from collections import deque
from dataclasses import replace
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from ...assembly import Assembly, _shaft_elements, _Triplets, assemble
from ...elements import CrossCoupling
from ...errors import ModelError, SolverError
from ...model import OperatingPoint, Train
from ...threads import managed
from .results import (
    OVERLOAD_FILM_FRACTION,
    BearingLoad,
    MeshLoad,
    ShaftStatics,
    StaticResult,
    StaticSweep,
)
from .solver import Contact, rigid_modes, rigid_modes_in, solve_static

__all__ = ["static", "static_sweep", "resolve_operating_point", "journal_equilibrium"]

_MAX_OUTER = 50
_JOURNAL_CACHE: dict = {}
_LAST_K: dict = {}
_BY_SPEED: dict = {}  # (file, version, pivot) -> {speed: the last equilibrium solved at it}
_JOURNAL_CACHE_SIZE = 1024
#: a journal solved at a speed within this ratio starts the Newton iteration at another speed
#: (a speed sweep at an operating point: 0.6 % steps on the steam turbine's 161 speeds)
_NEAR_SPEED = 1.25
_counter = {"solves": 0}


def resolve_operating_point(train: Train, operating_point) -> OperatingPoint:
    """The operating point named (or given); None: weight only at the model's speed."""
    if operating_point is None:
        return OperatingPoint(name="weight")
    op = train.operating_point(operating_point)
    if isinstance(operating_point, OperatingPoint):
        train.check_operating_point(op)
    return op


@functools.lru_cache(maxsize=32)
def _bearing_case(file: str, mtime_ns: int, pivot_stiffness: float | None = None):
    from ...bearings import load_bearing

    case = load_bearing(file)
    if pivot_stiffness is not None and hasattr(case.bearing.pads[0], "pivot_stiffness"):
        # the model's pivot stiffness (fluid_film.pivot_stiffness) replaces the file's
        pads = tuple(replace(p, pivot_stiffness=pivot_stiffness) for p in case.bearing.pads)
        case = replace(case, bearing=replace(case.bearing, pads=pads))
    return case


def _case(file: str, pivot_stiffness: float | None = None):
    p = Path(file)
    return _bearing_case(file, p.stat().st_mtime_ns if p.exists() else 0, pivot_stiffness)


def journal_equilibrium(
    file: str,
    load: tuple[float, float],
    speed: float,
    start=None,
    *,
    stiffness: bool = True,
    pivot_stiffness: float | None = None,
):
    """Equilibrium and static stiffness of the bearing of ``file`` under ``load`` (N) at
    ``speed`` (rad/s, signed), cached by value (file version, load, speed):
    ``(Equilibrium, K (2, 2))``. ``stiffness=False``: K may be that of the last journal of
    this bearing and speed (an estimate, enough for the static iteration to converge: on a
    statically determinate shaft it does not matter at all); it is computed when none is."""
    from ...bearings import equilibrium, static_stiffness

    case = _case(file, pivot_stiffness)
    p = Path(file)
    version = p.stat().st_mtime_ns if p.exists() else 0  # an edited bearing file is re-solved
    key = (file, version, float(load[0]), float(load[1]), float(speed), pivot_stiffness)
    last = (file, version, float(speed), pivot_stiffness)
    hit = _JOURNAL_CACHE.get(key)
    if hit is None:
        solved = _BY_SPEED.setdefault((file, version, pivot_stiffness), {})
        if start is None:  # warm start: the last journal of this bearing at this speed, or at
            start = _nearest_speed(solved, float(speed))  # the nearest speed solved
        eq = equilibrium(case.bearing, load, speed, options=case.options, start=start)
        solved.pop(float(speed), None)  # the newest last: the oldest speed goes first
        solved[float(speed)] = eq
        if len(solved) > _JOURNAL_CACHE_SIZE:
            solved.pop(next(iter(solved)))
        _counter["solves"] += 1
        if len(_JOURNAL_CACHE) >= _JOURNAL_CACHE_SIZE:
            _JOURNAL_CACHE.pop(next(iter(_JOURNAL_CACHE)))
        hit = _JOURNAL_CACHE[key] = [eq, None]
    eq, kb = hit
    if kb is None:
        if not stiffness and last in _LAST_K:
            return eq, _LAST_K[last]
        kb = hit[1] = static_stiffness(case.bearing, eq, options=case.options)
        _LAST_K[last] = kb
    return eq, kb


def _nearest_speed(solved: dict, speed: float):
    """The equilibrium solved at the speed nearest ``speed`` (that speed itself when it was
    solved; else the same sense of rotation within the ratio ``_NEAR_SPEED``), or None."""
    best, best_ratio = None, _NEAR_SPEED
    for w, eq in solved.items():
        if w * speed > 0:
            ratio = max(w / speed, speed / w)
            if ratio <= best_ratio:
                best, best_ratio = eq, ratio
    return best


_RIGID_CACHE: dict = {}


def _rigid_modes_cached(asm: Assembly, K) -> NDArray:
    """The right null space of K (the rigid-body motions it leaves free), cached by the
    matrix's bytes: the operating points of one train share it. Sparse K: within the span of
    the train's kinematic rigid motions (:func:`.solver.rigid_modes_in`, :func:`_candidates`);
    dense K: the SVD of the whole matrix (:func:`.solver.rigid_modes`)."""
    h = hashlib.blake2b(digest_size=16)
    if sp.issparse(K):
        K = sp.csr_array(K)
        K.sort_indices()
        for a in (K.data, K.indices, K.indptr):
            h.update(np.ascontiguousarray(a).tobytes())
    else:
        h.update(np.ascontiguousarray(K).tobytes())
    key = (sp.issparse(K), h.digest())
    hit = _RIGID_CACHE.get(key)
    if hit is None:
        if len(_RIGID_CACHE) >= 64:
            _RIGID_CACHE.pop(next(iter(_RIGID_CACHE)))
        hit = rigid_modes_in(K, _candidates(asm)) if sp.issparse(K) else rigid_modes(K)[0]
        _RIGID_CACHE[key] = hit
    return hit


def _candidates(asm: Assembly) -> NDArray:
    """(n_dof, p) the motions the train's stiffness can leave free: the six rigid motions of
    each shaft (a chain of Timoshenko elements, elastic in every other motion: x, y, z, the
    tilts θx (y = −z θx) and θy (x = z θy) about its mid-length, and the spin θz), and each
    pedestal's x and y. Every null vector of the train is a combination of them."""
    layout = asm.train.layout()
    cols = []
    for i, offs in enumerate(asm.node_offset):
        z = layout.shafts[i].z
        z = z - 0.5 * (z.min() + z.max())
        for dofs, vals in (
            ((0,), (1.0,)),
            ((1,), (1.0,)),
            ((2,), (1.0,)),
            ((1, 3), (-z, 1.0)),
            ((0, 4), (z, 1.0)),
            ((5,), (1.0,)),
        ):
            v = np.zeros(asm.n_dof)
            for d, val in zip(dofs, vals, strict=True):
                v[offs + d] = val
            cols.append(v)
    for so in asm.support_offset:
        if so >= 0:
            for d in (0, 1):
                v = np.zeros(asm.n_dof)
                v[so + d] = 1.0
                cols.append(v)
    return np.column_stack(cols)


def _start_flanks(asm: Assembly, op: OperatingPoint) -> list[int]:
    """Starting flank of every mesh: the driver of each mesh is its gear nearer (through the
    train) to the operating point's drive shaft; without a drive, the model's flank."""
    train = asm.train
    if op.drive is None:
        return [m.geometry.flank for m in asm.meshes]
    start = train.shaft_index(op.drive.shaft, "operating_point.drive.shaft")
    dist = {start: 0}
    queue = deque([start])
    edges = [(m.shafts[0], m.shafts[1]) for m in asm.meshes] + [
        (
            train.shaft_index(c.node_i.shaft, "couplings"),
            train.shaft_index(c.node_j.shaft, "couplings"),
        )
        for c in train.couplings
    ]
    while queue:
        a = queue.popleft()
        for i, j in edges:
            for u, v in ((i, j), (j, i)):
                if u == a and v not in dist:
                    dist[v] = dist[a] + 1
                    queue.append(v)
    speed = train.speed if train.speed != 0 else 1.0
    out = []
    for m in asm.meshes:
        si, sj = m.shafts
        driver = si if dist.get(si, math.inf) <= dist.get(sj, math.inf) else sj
        spin = np.sign(asm.speed_ratio[driver] * speed)
        out.append(1 if spin < 0 else -1)  # as assembly._flank: the force opposes the driver
    return out


def _scatter(A: _Triplets, dofs: NDArray, sup: NDArray | None, k: NDArray) -> None:
    """A bearing's 2x2 stiffness ``k`` between its journal DOFs and ground or its pedestal."""
    if sup is None:
        A.add(dofs, k)
    else:
        A.add(np.concatenate([dofs, sup]), np.block([[k, -k], [-k, k]]))


#: Largest matrix the dense reference path (``method="dense"``) allocates, bytes.
DENSE_MAX_BYTES = 512 * 1024**2


def _gravity_field(asm: Assembly, op: OperatingPoint) -> NDArray:
    g = np.zeros(asm.n_dof)
    if not op.gravity or op.gravity_acceleration == 0:
        return g
    a = op.gravity_acceleration * np.asarray(op.gravity_direction)
    for offs in asm.node_offset:
        for d in range(3):
            g[offs + d] = a[d]
    for so in asm.support_offset:
        if so >= 0:
            g[so], g[so + 1] = a[0], a[1]
    return g


def _unreacted(asm, R, acc, M, f, op) -> None:
    """Raise when the loads accelerate a rigid-body mode (nothing reacts them): the d'Alembert
    force ``M R a`` is the part of the loads the structure does not react."""
    if R.shape[1] == 0:
        return
    fa = M @ (R @ acc)
    scale = max(np.max(np.abs(f)), 1e-300)
    if np.max(np.abs(fa)) <= 1e-7 * scale:
        return
    kinds = asm.dof_kind()
    big = np.abs(fa) > 1e-3 * np.max(np.abs(fa))
    kind = ("lateral", "axial", "torsional")[
        int(np.argmax([np.max(np.abs(fa[kinds == k]), initial=0.0) for k in range(3)]))
    ]
    want = {"lateral": 0, "axial": 1, "torsional": 2}[kind]
    shafts = [
        asm.train.shafts[s].name
        for s, offs in enumerate(asm.node_offset)
        if np.any(
            big[np.concatenate([offs + d for d in range(6)])]
            & (kinds[np.concatenate([offs + d for d in range(6)])] == want)
        )
    ]
    if kind == "torsional":
        raise ModelError(
            f"nothing reacts the torque on shaft(s) {shafts}: the drive and load torques of "
            f"operating point '{op.name}' do not balance through the train",
            field="operating_point.load",
            value=None if op.load is None else f"{op.load.shaft}",
            expected="a load node on a shaft joined to the drive shaft by meshes or couplings "
            "that carry torque (coupling ktz > 0)",
        )
    if kind == "axial":
        raise ModelError(
            f"nothing reacts the axial load on shaft(s) {shafts} (helical mesh forces, static "
            "forces or gravity along z)",
            field="thrust_bearings",
            value=f"operating point '{op.name}'",
            expected="a thrust bearing on the shaft (or on a shaft it is geared to)",
        )
    raise ModelError(
        f"nothing reacts the lateral load on shaft(s) {shafts}",
        field="bearings",
        value=f"operating point '{op.name}'",
        expected="radial bearings that support every shaft",
    )


@managed
def static(
    model: Train | Assembly,
    operating_point: str | OperatingPoint | None = None,
    *,
    speed: float | None = None,
    method: str = "sparse",
) -> StaticResult:
    """Static deflection, bearing loads and tooth forces of a train at an operating point.

    model : the train (or its assembly); operating_point : the name of one of the model's
    ``operating_points``, an :class:`~gearrotor.model.OperatingPoint`, or None (weight only at
    the model's speed); speed : reference-shaft speed (rad/s) instead of the point's own (a
    sweep: the point's ``hold`` says whether its power or its torque is kept); method :
    ``"sparse"`` (sparse LU; the rigid-body motions as the null space of the stiffness within
    the shafts' kinematic rigid motions: memory and time linear in the mesh size) or
    ``"dense"`` (dense LU and the SVD of the whole stiffness: the reference the sparse path is
    tested against, refused above :data:`DENSE_MAX_BYTES` per matrix).

    Raises :class:`ModelError` on bad input (unknown point or shaft, power at zero speed, a
    torque or load nothing reacts, a journal that cannot carry its load: no equilibrium or a
    minimum film below 5 % of the clearance) and :class:`SolverError` when the journals do not
    settle.
    """
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    op = resolve_operating_point(train, operating_point)
    w_nom = op.reference_speed(train.speed)
    w_ref = w_nom if speed is None else float(speed)
    if op.power and w_ref == 0.0:
        raise ModelError(
            "a power needs a non-zero speed (the torque is power / speed)",
            field="operating_point.power",
            value=f"{op.power:.6g} W at 0 rpm",
            expected="a non-zero speed, or an operating point by torque",
        )
    if method not in ("sparse", "dense"):
        raise ValueError(f"unknown method {method!r}; expected 'sparse' or 'dense'")
    n = asm.n_dof
    if method == "dense" and 8 * (n + 8) ** 2 > DENSE_MAX_BYTES:
        raise ModelError(
            f"the dense static solver would need {8 * (n + 8) ** 2 / 1024**3:.3g} GiB per "
            f"matrix for {n:,} DOF",
            field="method",
            value="dense",
            expected=f"method='sparse' (dense up to {DENSE_MAX_BYTES / 1024**2:.0f} MiB)",
        )
    dense = method == "dense"
    speeds = asm.shaft_speeds(w_ref)
    M = asm.M.toarray() if dense else asm.M

    # --- stiffness without meshes, destabilisers and fluid-film journals ---------------------
    change = _Triplets()
    pads = asm.pad_dofs
    if len(pads):
        # tilting pads with pad dynamics: their DOFs are measured from the pads' equilibrium at
        # the journal's static position, so they are 0 in the static state (a unit spring)
        k_pad = max(float(np.max(np.abs(asm.K0.diagonal()))), 1.0)
        change.add(pads, k_pad * np.eye(len(pads)))
    for k, q in enumerate(train.cross_couplings):
        si, node = train.node_index(q, f"cross_couplings[{k}]")
        change.add(asm.node_offset[si][node] + np.arange(2), -CrossCoupling(q.q).K())
    for m in asm.meshes:
        change.add(m.dofs, -m.stiffness * np.outer(m.w, m.w))
    for info in _seals(asm):  # no static load on seals (module docstring)
        if not info.element.speed_dependent:  # a constant seal is in K0; a tabulated one never
            change.add(info.dofs, -info.element.K(0.0))
    films = []
    for k, (spec, info) in enumerate(zip(train.bearings, _bearings(asm), strict=True)):
        if spec.fluid_film is not None:
            if speeds[info.shaft] == 0.0:
                raise ModelError(
                    "a fluid-film journal needs its shaft turning to carry a static load",
                    field=f"bearings[{k}]",
                    value=f"{info.name} at 0 rpm",
                    expected="an operating point with a non-zero speed",
                )
            films.append((k, spec, info))
        elif info.element.speed_dependent:
            _scatter(change, info.dofs, info.support_dofs, info.element.K(speeds[info.shaft]))
    K = sp.csr_array(asm.K0 + change.csr(n))
    if dense:
        K = K.toarray()

    # --- loads ----------------------------------------------------------------------------
    f = M @ _gravity_field(asm, op)
    drive_t = load_t = 0.0
    torque_nodes = None
    if op.drive is not None and (op.power or op.torque):
        sd, nd = train.node_index(op.drive, "operating_point.drive")
        sl, nl = train.node_index(op.load, "operating_point.load")
        rd = asm.speed_ratio[sd]
        drive_t = op.drive_torque(rd * w_ref, rd * w_nom)
        torque_nodes = (asm.dof(sd, nd, 5), asm.dof(sl, nl, 5))
    for j, sf in enumerate(op.forces):
        si, node = train.node_index(sf, f"operating_point.forces[{j}]")
        f[asm.node_offset[si][node] + np.arange(6)] += np.concatenate([sf.force, sf.moment])
    applied = np.array(
        [f[np.concatenate([o + d for o in asm.node_offset])].sum() for d in range(3)]
    )
    applied[:2] += [f[[s + d for s in asm.support_offset if s >= 0]].sum() for d in range(2)]
    drive_speed = 0.0 if op.drive is None else speeds[train.shaft_index(op.drive.shaft, "")]
    power = drive_t * drive_speed

    # --- contacts ---------------------------------------------------------------------------
    contacts = []
    for m in asm.meshes:
        w_plus = replace(m.geometry, flank=1).w()
        w_minus = replace(m.geometry, flank=-1).w()
        contacts.append(Contact(m.dofs, w_plus, w_minus, m.stiffness))
    sides = _start_flanks(asm, op)

    # --- rigid-body modes of the linearised train -------------------------------------------
    k0 = max(float(np.max(np.abs(K.diagonal()))), 1.0)
    closing = _Triplets()
    for c, s in zip(contacts, sides, strict=True):
        w = c.w if s == 1 else c.w_back
        closing.add(c.dofs, c.stiffness * np.outer(w, w))
    for _, _, info in films:
        _scatter(closing, info.dofs, info.support_dofs, k0 * np.eye(2))
    K_all = K + (closing.csr(n).toarray() if dense else closing.csr(n))
    R = _rigid_modes_cached(asm, K_all)
    if torque_nodes is not None:
        # the load torque balances the drive torque in the train's rigid rotation (the ratio
        # of the meshes' pitch radii, which the tooth counts match to within 1 %)
        dd, dl = torque_nodes
        j = int(np.argmax(np.abs(R[dd]))) if R.shape[1] else -1
        if j < 0 or abs(R[dl, j]) < 1e-9 * abs(R[dd, j]):
            raise ModelError(
                f"nothing reacts the torque of operating point '{op.name}': its load node "
                "turns independently of its drive node",
                field="operating_point.load",
                value=f"{op.load.shaft}",
                expected="a load node on a shaft joined to the drive shaft by meshes or "
                "couplings that carry torque (coupling ktz > 0)",
            )
        load_t = -drive_t * R[dd, j] / R[dl, j]
        f[dd] += drive_t
        f[dl] += load_t

    # --- solve, iterating the fluid-film journals ------------------------------------------
    state = {
        k: [np.zeros(2), np.zeros(2), k0 * np.eye(2), None] for k, _, _ in films
    }  # W, d, K, eq
    solves0 = _counter["solves"]
    iterations = 0
    for it in range(_MAX_OUTER + 1):
        ft = f.copy()
        journals = _Triplets()
        for k, _, info in films:
            W, d, Kb, _ = state[k]
            _scatter(journals, info.dofs, info.support_dofs, Kb)
            g = Kb @ d - W
            ft[info.dofs] += g
            if info.support_dofs is not None:
                ft[info.support_dofs] -= g
        Kt = K + (journals.csr(n).toarray() if dense else journals.csr(n)) if films else K
        try:
            sol = solve_static(Kt, ft, M=M, rigid=R, contacts=contacts, sides=sides)
        except np.linalg.LinAlgError:
            raise ModelError(
                "no static state: with a mesh unloaded the train falls apart",
                field="operating_point",
                value=op.name,
            ) from None
        if it == 0:
            _unreacted(asm, R, sol.acceleration, M, ft, op)
        sides = list(sol.sides)
        if not films:
            break
        done = it > 0
        new = {}
        for k, spec, info in films:
            W, d_b, Kb, eq = state[k]
            d = _relative(sol.q, info)
            w_new = W + Kb @ (d - d_b)
            new[k] = w_new
            tol = _force_tol(spec, w_new, speeds[info.shaft])
            done &= bool(np.linalg.norm(w_new - W) <= tol)
        if done:
            break
        if it == _MAX_OUTER:
            raise SolverError(
                f"the fluid-film journals did not settle in {_MAX_OUTER} iterations at "
                f"operating point '{op.name}'"
            )
        iterations += 1
        for k, spec, info in films:
            eq, Kb = _solve_journal(
                k, spec, info, new[k], speeds[info.shaft], state[k][3], iterations > 1, op.name
            )
            state[k] = [new[k], np.array([eq.x, eq.y]), Kb, eq]

    q = sol.q
    # --- results ----------------------------------------------------------------------------
    bearings, reaction = [], np.zeros(3)
    film_of = {k: state[k] for k, _, _ in films}
    for k, (spec, info) in enumerate(zip(train.bearings, _bearings(asm), strict=True)):
        si, node = train.node_index(spec, f"bearings[{k}]")
        d = _relative(q, info)
        if k in film_of:
            W, d_b, Kb, eq = film_of[k]
            W = W + Kb @ (d - d_b)
            bl = BearingLoad(
                info.name,
                train.shafts[si].name,
                node,
                "fluid-film",
                np.array([W[0], W[1], 0.0]),
                journal=(eq.x, eq.y),
                eccentricity_ratio=eq.eccentricity_ratio,
                attitude=eq.attitude_angle,
                min_film=eq.min_film,
                peak_pressure=eq.peak_pressure,
                power_loss=eq.friction_power,
                clearance=_case(spec.fluid_film.file).bearing.clearance,
            )
        else:
            W = info.element.K(speeds[info.shaft]) @ d
            bl = BearingLoad(info.name, train.shafts[si].name, node, "linear", np.array([*W, 0]))
        bearings.append(bl)
        if info.support_dofs is None:
            reaction[:2] -= bl.force[:2]
        else:
            sup = spec.support
            reaction[:2] -= np.array([sup.kxx, sup.kyy]) * q[info.support_dofs]
    for k, t in enumerate(train.thrust_bearings):
        si, node = train.node_index(t, f"thrust_bearings[{k}]")
        fz = t.kzz * q[asm.dof(si, node, 2)]
        bearings.append(
            BearingLoad(
                t.name or f"thrust_bearings[{k}]",
                train.shafts[si].name,
                node,
                "thrust",
                np.array([0.0, 0.0, fz]),
            )
        )
        reaction[2] -= fz
    meshes = []
    force = sol.contact_force(contacts)
    for m, c, s, fn in zip(asm.meshes, contacts, sol.sides, force, strict=True):
        geo = replace(m.geometry, flank=s if s else m.geometry.flank)
        w = c.w if s == 1 else c.w_back
        cx, cy, cz = geo.direction_cosines
        n_vec = geo.n
        th = q[m.dofs[3:6]] - q[m.dofs[9:12]]
        spec = train.meshes[m.spec_index]
        width = spec.face_width
        mis = (th @ np.array([-n_vec[1], n_vec[0], 0.0])) * width if width else math.nan
        meshes.append(
            MeshLoad(
                m.name,
                int(s),
                float(fn),
                float(fn * abs(cx)),
                float(fn * cy),
                float(-fn * cz),
                float(-fn * w[5]),
                float(-fn * w[11]),
                float(mis),
            )
        )
    shafts = _shaft_curves(asm, q, _gravity_field(asm, op))
    return StaticResult(
        operating_point=op.name,
        speed=w_ref,
        drive_torque=drive_t,
        load_torque=load_t,
        power=power,
        gravity=op.gravity,
        bearings=tuple(bearings),
        meshes=tuple(meshes),
        shafts=shafts,
        q=q,
        applied=applied,
        residual=reaction + applied,
        iterations=iterations,
        bearing_solves=_counter["solves"] - solves0,
        journals={k: film_of[k][3] for k in film_of},
    )


def _bearings(asm: Assembly) -> list:
    """The assembly's radial bearings (``asm.bearings`` also holds the seals, after them)."""
    return [b for b in asm.bearings if b.kind == "bearing"]


def _seals(asm: Assembly) -> list:
    return [b for b in asm.bearings if b.kind == "seal"]


def _relative(q: NDArray, info) -> NDArray:
    d = q[info.dofs].copy()
    if info.support_dofs is not None:
        d -= q[info.support_dofs]
    return d


def _force_tol(spec, load: NDArray, speed: float) -> float:
    case = _case(spec.fluid_film.file)
    b = case.bearing
    fref = 1e-3 * b.viscosity * abs(speed) * b.radius**3 * b.length / b.clearance**2
    return 10 * case.options.tol * max(float(np.linalg.norm(load)), fref)


def _solve_journal(k, spec, info, load, speed, start, exact, point):
    file = spec.fluid_film.file
    name = f"{info.name} (bearings[{k}]) at operating point '{point}'"
    try:
        eq, Kb = journal_equilibrium(
            file,
            (float(load[0]), float(load[1])),
            speed,
            start,
            stiffness=exact,
            pivot_stiffness=spec.fluid_film.pivot_stiffness,
        )
    except SolverError:
        raise ModelError(
            f"journal bearing {name} cannot carry its load (no film equilibrium: the "
            "eccentricity ratio tends to 1)",
            field=f"bearings[{k}].fluid_film",
            value=f"load ({load[0]:.6g}, {load[1]:.6g}) N at {speed * 30 / math.pi:.6g} rpm",
            expected="a bearing with the capacity for this load (larger, or a higher speed)",
        ) from None
    c = _case(file).bearing.clearance
    if eq.min_film < OVERLOAD_FILM_FRACTION * c:
        raise ModelError(
            f"journal bearing {name} cannot carry its load: minimum film "
            f"{eq.min_film * 1e6:.3g} um is below {100 * OVERLOAD_FILM_FRACTION:.0f} % of the "
            f"clearance {c * 1e6:.4g} um (eccentricity ratio {eq.eccentricity_ratio:.3f})",
            field=f"bearings[{k}].fluid_film",
            value=f"load ({load[0]:.6g}, {load[1]:.6g}) N at {speed * 30 / math.pi:.6g} rpm",
            expected="a bearing with the capacity for this load",
        )
    return eq, Kb


def _shaft_curves(asm: Assembly, q: NDArray, g: NDArray) -> tuple[ShaftStatics, ...]:
    """Section forces at both ends of every shaft element (its end forces ``K q − M g``) and
    the von Mises stress there; the elements of a section are alike, so each distinct element's
    matrices are formed once and applied to all its instances at once."""
    out = []
    layout = asm.train.layout()
    for i, sl in enumerate(layout.shafts):
        offs = asm.node_offset[i]
        els = _shaft_elements(asm.train, i)
        ne = len(els)
        dofs = np.concatenate([offs[:-1, None] + np.arange(6), offs[1:, None] + np.arange(6)], 1)
        fe = np.empty((ne, 12))
        groups: dict = {}
        for e, el in enumerate(els):
            groups.setdefault(el, []).append(e)
        for el, idx in groups.items():
            idx = np.asarray(idx)
            fe[idx] = q[dofs[idx]] @ el.K().T - g[dofs[idx]] @ el.M().T
        S = np.empty((2 * ne, 6))
        S[0::2], S[1::2] = -fe[:, :6], fe[:, 6:]
        zs = np.repeat(sl.z, 2)[1:-1]  # each element's start and end
        D = np.repeat([el.outer_diameter for el in els], 2)
        di = np.repeat([el.inner_diameter for el in els], 2)
        area = np.pi / 4 * (D**2 - di**2)
        inertia = np.pi / 64 * (D**4 - di**4)
        sig = np.abs(S[:, 2]) / area + np.hypot(S[:, 3], S[:, 4]) * D / 2 / inertia
        tau = np.abs(S[:, 5]) * D / 2 / (2 * inertia)
        vm = np.sqrt(sig**2 + 3 * tau**2)
        defl = np.stack([q[offs + d] for d in range(6)], axis=1)
        out.append(
            ShaftStatics(
                sl.name,
                sl.z.copy(),
                defl,
                zs,
                S[:, 0:2],
                S[:, 2],
                S[:, 3:5],
                S[:, 5],
                vm,
            )
        )
    return tuple(out)


@managed
def static_sweep(model: Train | Assembly, operating_points=None) -> StaticSweep:
    """:func:`static` at several operating points (default: all of the model's, in order)."""
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    if operating_points is None:
        if not train.operating_points:
            raise ModelError(
                "the model has no operating points",
                field="operating_points",
                expected="[[operating_points]] entries in the model",
            )
        operating_points = [p.name for p in train.operating_points]
    for p in operating_points:  # all checked before any runs
        resolve_operating_point(train, p)
    return StaticSweep(tuple(static(asm, p) for p in operating_points))
