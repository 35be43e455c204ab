"""Undamped critical speed map of a train (API RP 684, 2nd ed. 2005; API 617 lateral analysis).

**What is swept.** Every radial bearing of the model is replaced by the same isotropic stiffness
k (kxx = kyy = k, no cross-coupling, no damping), swept on a log scale; everything else keeps its
stiffness: shafts, couplings, thrust bearings, pedestals (a bearing on a ``support`` is the spring
k between journal and pedestal) and the gear meshes, so on a geared train the lateral, torsional
and axial motions stay coupled through the mesh. Damping, the model's ``[[cross_couplings]]`` and
the circulatory stiffness of rotating shaft damping are left out (an *undamped* map).

**Synchronous critical speeds with gyroscopics.** At reference-shaft speed Ω each shaft s spins
at Ω_s = r_s Ω, so the undamped equations are ``M q̈ + Ω G₁ q̇ + K q = 0`` with
``G₁ = Σ_s r_s G_s`` (each shaft's gyroscopic matrix scaled by its own speed ratio). A critical
speed *of shaft s* is a reference speed at which a free vibration has the frequency of shaft s's
1x, ω = |r_s| Ω. With q = φ e^{iωt} and Ω = σ ω / |r_s| (σ the sense of the reference spin,
the sign of the model's speed):

    K φ = ω² (M − i (σ / |r_s|) G₁) φ,

a generalised eigenproblem with K symmetric and the second matrix Hermitian (G₁ is real skew),
so ω² is real. One solve per distinct |r_s| gives every synchronous critical of the shafts at
that speed, forward and backward together; they are told apart by the orbit sense of the
eigenvector on the shaft of interest relative to its spin (forward: same sense). The map lists
the **forward** criticals of each shaft whose lateral kinetic energy on that shaft is at least
``min_share`` of the mode's kinetic energy (a bull-gear mode reaches the pinion's 1x line too,
but pinion unbalance barely excites it), in that shaft's own speed. A repeated eigenvalue (an
isotropic, non-gyroscopic rotor: forward and backward coincide) is resolved into its forward and
backward circular orbits.

**Bearing curves and intersections.** Each bearing's Kxx and Kyy over its table's speeds (its
shaft's speed) are drawn on the same axes; a critical speed branch (the i-th lowest forward
critical at each k, interpolated linearly in log k) meets a bearing curve where
``ω_i(K(N)) = N``, found by a sign change on a fine speed grid and refined by Brent's method.

**Rigid supports** (``rigid_critical_speeds``): the journal x, y DOFs of every bearing are
removed (pinned journals), the limit of the map as k → ∞; API 617's critical speed ratio uses the
first of them.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..assembly import Assembly, _Triplets, assemble
from ..elements import RadialBearing
from ..errors import ModelError, SolverError
from ..model import Train
from ..threads import managed

__all__ = [
    "UCSResult",
    "UCSShaft",
    "BearingCurve",
    "Intersection",
    "ucs_map",
    "rigid_support_criticals",
]

RPM = 30 / np.pi
_LATERAL = (0, 1, 3, 4)  # x, y, θx, θy
#: a synchronous solution counts as a critical speed of a shaft when the forward circular part
#: of its orbits on that shaft holds at least this fraction of the orbit (|f|² / (|f|² + |b|²)):
#: 1 for a forward circle, 1/2 for a straight line (the x- and y-modes of a train made
#: anisotropic by its meshes: unbalance excites both), 0 for a backward circle (not excited)
MIN_FORWARD = 0.25
#: from this many DOFs "auto" uses the sparse solver: the dense one finds every eigenvalue of
#: the pencil (n³), the sparse one the lowest few (192 DOFs: 0.03 s a solve instead of 0.1 s)
SPARSE_FROM = 150


@dataclass(frozen=True)
class UCSShaft:
    """The map of one shaft: forward synchronous critical speeds in that shaft's own speed."""

    name: str
    index: int
    speed_ratio: float  # Ω_shaft / Ω_reference (signed)
    critical_speeds: NDArray  # (n_stiffness, n_modes) rad/s of this shaft; NaN: fewer modes
    rigid_critical_speeds: NDArray  # (n_modes,) rad/s of this shaft, journals pinned

    @property
    def first_rigid_critical(self) -> float | None:
        """The lowest forward critical speed on rigid supports (rad/s of this shaft)."""
        ok = np.isfinite(self.rigid_critical_speeds)
        return float(self.rigid_critical_speeds[ok][0]) if ok.any() else None


@dataclass(frozen=True)
class BearingCurve:
    """A bearing's direct stiffnesses against its shaft's speed (``speeds`` None: constant)."""

    name: str
    shaft: str
    speeds: NDArray | None  # rad/s of its shaft (magnitude)
    kxx: NDArray  # N/m, one value per speed (a single value when constant)
    kyy: NDArray


@dataclass(frozen=True)
class Intersection:
    """Where a critical speed branch meets a bearing's Kxx or Kyy curve."""

    shaft: str
    mode: int  # branch index (0: the lowest forward critical)
    bearing: str
    direction: str  # "kxx" or "kyy"
    stiffness: float  # N/m
    speed: float  # rad/s of the shaft
    reference_speed: float  # rad/s of the reference shaft


@dataclass(frozen=True)
class UCSResult:
    """Undamped critical speed map: see the module docstring for the definitions."""

    stiffness: NDArray  # (n_stiffness,) N/m, the isotropic stiffness of every bearing
    shafts: tuple[UCSShaft, ...]
    bearings: tuple[BearingCurve, ...]
    intersections: tuple[Intersection, ...]
    min_share: float
    method: str
    n_solves: int
    operating_range: tuple[float, float] | None  # reference shaft, rad/s (from the model)
    max_continuous_speed: float | None  # reference shaft, rad/s (from the model)
    train: Train = field(repr=False)

    def shaft(self, name: str) -> UCSShaft:
        for s in self.shafts:
            if s.name == name:
                return s
        raise KeyError(name)

    def to_dict(self) -> dict:
        def rpm(a):
            return [None if not np.isfinite(v) else float(v * RPM) for v in np.ravel(a)]

        return {
            "stiffness_N_per_m": [float(k) for k in self.stiffness],
            "min_share": self.min_share,
            "method": self.method,
            "n_solves": self.n_solves,
            "operating_range_rpm": (
                None if self.operating_range is None else [v * RPM for v in self.operating_range]
            ),
            "max_continuous_speed_rpm": (
                None if self.max_continuous_speed is None else self.max_continuous_speed * RPM
            ),
            "shafts": [
                {
                    "name": s.name,
                    "speed_ratio": float(s.speed_ratio),
                    "critical_speeds_rpm": [
                        rpm(s.critical_speeds[:, j]) for j in range(s.critical_speeds.shape[1])
                    ],
                    "rigid_critical_speeds_rpm": rpm(s.rigid_critical_speeds),
                }
                for s in self.shafts
            ],
            "bearings": [
                {
                    "name": b.name,
                    "shaft": b.shaft,
                    "speeds_rpm": None if b.speeds is None else rpm(b.speeds),
                    "kxx_N_per_m": [float(v) for v in b.kxx],
                    "kyy_N_per_m": [float(v) for v in b.kyy],
                }
                for b in self.bearings
            ],
            "intersections": [
                {
                    "shaft": x.shaft,
                    "mode": x.mode,
                    "bearing": x.bearing,
                    "direction": x.direction,
                    "stiffness_N_per_m": x.stiffness,
                    "speed_rpm": x.speed * RPM,
                    "reference_speed_rpm": x.reference_speed * RPM,
                }
                for x in self.intersections
            ],
        }

    def table(self) -> str:
        rows = ["forward critical speeds on rigid supports (rpm of the shaft)"]
        for s in self.shafts:
            vals = ", ".join(f"{v * RPM:.0f}" for v in s.rigid_critical_speeds if np.isfinite(v))
            rows.append(f"  {s.name:>12}: {vals or '-'}")
        head = (
            f"{'shaft':>12} {'mode':>4} {'bearing':>28} {'dir':>4} {'k N/m':>11} "
            f"{'rpm':>9} {'ref rpm':>9}"
        )
        rows += ["", "intersections with the bearing stiffness curves", head, "-" * len(head)]
        for x in self.intersections:
            rows.append(
                f"{x.shaft:>12} {x.mode:>4} {x.bearing[:28]:>28} {x.direction:>4} "
                f"{x.stiffness:>11.4g} {x.speed * RPM:>9.0f} {x.reference_speed * RPM:>9.0f}"
            )
        if not self.intersections:
            rows.append("  (none within the stiffness range)")
        return "\n".join(rows)


# --------------------------------------------------------------------------------------------
class _Synchronous:
    """The undamped synchronous eigenproblem of a train with every bearing k·I."""

    def __init__(self, train: Train, rigid_tol: float = 1e-2) -> None:
        bare = train.model_copy(
            update={
                "bearings": [_bare_bearing(b) for b in train.bearings],
                "cross_couplings": [],
                "seals": [],
            }
        )
        asm = assemble(bare)
        self.asm = asm
        n = asm.n_dof
        kb, unused = _Triplets(), _Triplets()
        unit = RadialBearing(kxx=1.0, kyy=1.0)
        journal = []
        for b in asm.bearings:  # every bearing as k = 1 N/m (to ground or to its pedestal)
            dataclasses.replace(b, element=unit).scatter(kb, unused, 0.0)
            journal.extend(b.dofs.tolist())
        self.Kb = kb.csr(n)
        self.K0 = asm.K0
        self.M = asm.M
        self.G1 = sum(
            (r * g for r, g in zip(asm.speed_ratio, asm.G_shaft, strict=True)),
            sp.csr_array((n, n)),
        )
        self.sense = 1.0 if train.speed >= 0 else -1.0
        self.free = np.setdiff1d(np.arange(n), np.asarray(journal, int))
        # per shaft: its lateral DOFs (x, y, θx, θy)
        self.lateral = []
        for offs in asm.node_offset:
            m = np.zeros(n, bool)
            for d in _LATERAL:
                m[offs + d] = True
            self.lateral.append(m)
        self.n_solves = 0
        self.rigid_tol = rigid_tol
        self._nullspace: dict[bool, NDArray] = {}

    def solve(self, k: float | None, ratio: float, method: str, n_want: int):
        """(ω², V) of K φ = ω² B φ at bearing stiffness k (None: pinned journals), for the
        shafts spinning at |ratio|; V has full-length columns."""
        B = (self.M - 1j * (self.sense / abs(ratio)) * self.G1).tocsc()
        if k is None:
            keep = self.free
            K = self.K0.tocsc()[keep][:, keep]
            B = B[keep][:, keep]
        else:
            keep = None
            K = (self.K0 + k * self.Kb).tocsc()
        self.n_solves += 1
        if method == "dense":
            w2, V = self._dense(K.toarray(), B.toarray(), k is None)
        else:
            w2, V = _sparse(K, B, n_want)
            ok = np.isfinite(w2)
            w2, V = w2[ok], V[:, ok]
            real = np.abs(w2.imag) <= 1e-6 * np.maximum(np.abs(w2), 1e-30)
            w2, V = w2[real].real, V[:, real]
        if keep is not None:
            full = np.zeros((self.asm.n_dof, V.shape[1]), complex)
            full[keep] = V
            V = full
        order = np.argsort(w2)
        return w2[order], V[:, order]

    def _dense(self, K: NDArray, B: NDArray, rigid: bool) -> tuple[NDArray, NDArray]:
        """Every finite ω² of K φ = ω² B φ: the rigid-body null space N of K (free torsion of
        the train, free axial motion) is deflated, φ ⊥ B N for ω ≠ 0, which leaves a reduced K
        that is positive definite, and the Hermitian pencil (B, K) is solved for μ = 1/ω²
        (real; μ ≤ 0 means no synchronous critical, e.g. the forward conical mode of a disk
        whose polar inertia exceeds its transverse inertia)."""
        N = self._null(K, rigid)
        if N.shape[1]:
            P = la.null_space((B @ N).conj().T)
            Kr, Br = P.conj().T @ K @ P, P.conj().T @ B @ P
        else:
            P, Kr, Br = None, K, B
        Kr = 0.5 * (Kr + Kr.conj().T)
        Br = 0.5 * (Br + Br.conj().T)
        try:
            mu, Y = la.eigh(Br, Kr, check_finite=False)
        except la.LinAlgError:
            # a rigid-body motion the null space missed (its round-off ω² above rigid_tol², in
            # a very stiff model): the general QZ algorithm needs no definite matrix
            w2, V = la.eig(K, B, check_finite=False)
            ok = np.isfinite(w2) & (np.abs(w2.imag) <= 1e-6 * np.maximum(np.abs(w2), 1e-30))
            return w2[ok].real, V[:, ok]
        pos = mu > 0
        V = Y[:, pos] if P is None else P @ Y[:, pos]
        return 1.0 / mu[pos], V

    def _null(self, K: NDArray, rigid: bool) -> NDArray:
        """Rigid-body modes of K (M-orthonormal columns), cached: they do not involve the
        bearings' journal DOFs, so they are the same at every bearing stiffness (checked)."""
        N = self._nullspace.get(rigid)
        scale = np.abs(np.diag(K)).max()
        if N is not None and (
            not N.shape[1] or np.abs(K @ N).max() <= 1e-9 * scale * np.abs(N).max()
        ):
            return N
        M = self.M.toarray()
        if rigid:
            M = M[np.ix_(self.free, self.free)]
        w2, V = la.eigh(K, M, subset_by_value=(-np.inf, self.rigid_tol**2), check_finite=False)
        self._nullspace[rigid] = V
        return V

    def forward(self, w2, V, shaft: int, min_share: float, rigid_tol: float) -> NDArray:
        """Forward synchronous critical frequencies (rad/s) of ``shaft`` among the solutions."""
        sigma = self.sense * np.sign(self.asm.speed_ratio[shaft])
        offs = self.asm.node_offset[shaft]
        lat = self.lateral[shaft]
        out = []
        # round-off of the small ω² of a stiff train is about eps · max ω² (absolute): the two
        # circular orbits of an isotropic rotor on soft supports (ω² ~ 1, max ω² ~ 1e12) came
        # out 5e-7 apart (relative), beyond the relative tolerance alone
        atol = 10 * np.finfo(float).eps * float(np.max(np.abs(w2), initial=0.0))
        for idx in _clusters(w2, atol):
            if w2[idx[0]] < rigid_tol**2:
                continue
            Vc = V[:, idx]
            if len(idx) > 1:  # a repeated root: split into circular forward/backward orbits
                X, Y = Vc[offs], Vc[offs + 1]
                H = (Y.conj().T @ X - X.conj().T @ Y) / 2j  # Σ Im(X conj(Y)), a Hermitian form
                A = X.conj().T @ X + Y.conj().T @ Y
                if np.linalg.cond(A) < 1e8:
                    _, U = la.eigh(0.5 * (H + H.conj().T), 0.5 * (A + A.conj().T))
                    Vc = Vc @ U
            for j in range(Vc.shape[1]):
                phi = Vc[:, j]
                total = np.real(phi.conj() @ (self.M @ phi))
                pl = np.where(lat, phi, 0.0)
                share = np.real(pl.conj() @ (self.M @ pl)) / total if total > 0 else 0.0
                X, Y = phi[offs], phi[offs + 1]
                # x + iy = ((X + iY) e^{iωt} + conj(X − iY) e^{−iωt}) / 2: the circular parts
                fwd = np.sum(np.abs(X + 1j * sigma * Y) ** 2)
                bwd = np.sum(np.abs(X - 1j * sigma * Y) ** 2)
                if share >= min_share and fwd >= MIN_FORWARD * (fwd + bwd):
                    out.append(np.sqrt(w2[idx[0]]))
        return np.array(out)


def _bare_bearing(b):
    zero = {n: 0.0 for n in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")}
    return b.model_copy(
        update=zero | {"k": None, "c": None, "table": None, "table_file": None, "fluid_film": None}
    )


def _clusters(w2: NDArray, atol: float = 0.0) -> list[list[int]]:
    """Indices of (sorted) ω² grouped where consecutive values agree to 1e-7 (relative) or
    ``atol`` (absolute)."""
    groups: list[list[int]] = []
    for i, v in enumerate(w2):
        if groups and abs(v - w2[groups[-1][-1]]) <= max(1e-7 * abs(v), atol, 1e-30):
            groups[-1].append(i)
        else:
            groups.append([i])
    return groups


def _sparse_count(n_want: int) -> int:
    """Eigenvalues asked of ARPACK for ``n_want`` forward criticals: each comes with a backward
    one, and other shafts' and torsional/axial solutions lie in between."""
    return max(4 * n_want + 8, 20)


def _sparse(K, B, n_want: int):
    """The lowest ω² by shift-invert Arnoldi on (K − σB)⁻¹B, σ slightly below zero."""
    n = K.shape[0]
    scale = abs(K.diagonal()).max() / max(abs(B.diagonal()).max(), 1e-300)
    sigma = -1e-6 * scale
    try:
        lu = spla.splu((K - sigma * B).tocsc())
    except RuntimeError:
        raise SolverError(
            "the shifted stiffness of the critical speed problem is singular"
        ) from None
    op = spla.LinearOperator((n, n), matvec=lambda v: lu.solve(B @ v), dtype=complex)
    k = min(_sparse_count(n_want), n - 2)
    try:
        nu, V = spla.eigs(op, k=k, which="LM")
    except spla.ArpackNoConvergence as exc:
        raise SolverError(f"sparse critical-speed eigensolver did not converge: {exc}") from None
    return sigma + 1.0 / nu, V


def _groups(asm: Assembly) -> tuple[list[float], NDArray]:
    ratio = np.abs(asm.speed_ratio)
    keys = sorted({round(float(r), 12) for r in ratio})
    return keys, np.array([keys.index(round(float(r), 12)) for r in ratio])


def _default_stiffness(asm: Assembly, n: int) -> NDArray:
    vals = []
    for b in asm.bearings:
        if b.kind == "seal":  # the map is of the bearings' stiffness
            continue
        el = b.element
        if el.table is not None:
            vals.extend(el.table.values[:, 0])
            vals.extend(el.table.values[:, 3])
        else:
            vals.extend([el.kxx, el.kyy])
    vals = np.abs(np.asarray(vals, float))
    vals = vals[vals > 0]
    if not len(vals):
        return np.logspace(5, 10, n)
    lo = np.floor(np.log10(vals.min())) - 1
    hi = np.ceil(np.log10(vals.max())) + 1
    return np.logspace(lo, hi, n)


def _at_operating_point(model, operating_point) -> Train:
    """The train with its fluid-film bearings tabulated at the operating point's static loads
    at the reference speeds of their own ``speeds``."""
    from .static.operating import model_at_operating_point

    train = model if isinstance(model, Train) else model.train
    layout = train.layout()
    sweep: set[float] = set()
    for b in train.bearings:
        if b.fluid_film is not None:
            ratio = abs(layout.shafts[train.shaft_index(b.shaft, "")].speed_ratio)
            sweep |= {abs(float(w)) / ratio for w in b.fluid_film.speeds}
    return model_at_operating_point(train, operating_point, sorted(sweep) or None)[0]


def _bearing_curves(asm: Assembly) -> tuple[BearingCurve, ...]:
    names = [s.name for s in asm.train.shafts]
    out = []
    for b in asm.bearings:
        if b.kind == "seal":
            continue
        el = b.element
        if el.table is not None:
            t = el.table
            out.append(
                BearingCurve(
                    b.name,
                    names[b.shaft],
                    t.speed.copy(),
                    t.values[:, 0].copy(),
                    t.values[:, 3].copy(),
                )
            )
        else:
            out.append(
                BearingCurve(b.name, names[b.shaft], None, np.array([el.kxx]), np.array([el.kyy]))
            )
    return tuple(out)


def _check_method(method: str, n_dof: int) -> str:
    if method == "auto":
        return "dense" if n_dof <= SPARSE_FROM else "sparse"
    if method not in ("dense", "sparse"):
        raise ModelError(
            "unknown eigensolver method",
            field="method",
            value=method,
            expected="'auto', 'dense' or 'sparse'",
        )
    return method


def rigid_support_criticals(
    model: Train | Assembly,
    *,
    n_modes: int = 3,
    min_share: float = 0.2,
    method: str = "auto",
    rigid_tol: float = 1e-2,
) -> dict[str, NDArray]:
    """Forward synchronous critical speeds of every shaft with its journals pinned (rad/s of
    that shaft, lowest first, ``n_modes`` of them, NaN-padded): the API 617 rigid-support
    critical speeds (the critical speed ratio uses the first)."""
    train = model.train if isinstance(model, Assembly) else model
    prob = _Synchronous(train, rigid_tol)
    method = _check_method(method, prob.asm.n_dof)
    return _rigid(prob, n_modes, min_share, method, rigid_tol)


def _rigid(prob: _Synchronous, n_modes, min_share, method, rigid_tol) -> dict[str, NDArray]:
    keys, group = _groups(prob.asm)
    out = {}
    for g, r in enumerate(keys):
        members = np.flatnonzero(group == g)
        found = _criticals(prob, None, r, members, n_modes, min_share, method, rigid_tol)
        for si, f in found.items():
            out[prob.asm.train.shafts[si].name] = np.concatenate(
                [f, np.full(n_modes - len(f), np.nan)]
            )
    return out


def _criticals(prob, k, ratio, members, n_modes, min_share, method, rigid_tol) -> dict:
    """The lowest ``n_modes`` forward criticals of each member shaft at stiffness k; the
    sparse solver asks for twice as many eigenvalues until every shaft has ``n_modes`` of
    them (or the spectrum is exhausted)."""
    n_want = n_modes
    while True:
        w2, V = prob.solve(k, ratio, method, n_want)
        out = {si: prob.forward(w2, V, si, min_share, rigid_tol)[:n_modes] for si in members}
        done = all(len(f) >= n_modes for f in out.values())
        if method == "dense" or done or _sparse_count(n_want) >= prob.asm.n_dof - 2:
            return out
        n_want *= 2


@managed
def ucs_map(
    model: Train | Assembly,
    *,
    stiffness: NDArray | tuple[float, float] | None = None,
    n_stiffness: int = 31,
    n_modes: int = 4,
    min_share: float = 0.2,
    method: str = "auto",
    rigid_tol: float = 1e-2,
    operating_point=None,
) -> UCSResult:
    """Undamped critical speed map (see the module docstring).

    Parameters
    ----------
    model : the train, or its assembly (the bearing curves come from its bearings)
    stiffness : N/m, the bearing stiffnesses: an array, or ``(k_min, k_max)`` swept on a log
        scale with ``n_stiffness`` points (default: one decade beyond the lowest and highest
        direct stiffness of the model's bearings)
    n_modes : forward critical speeds kept per shaft (the lowest)
    min_share : fraction of a mode's kinetic energy in the shaft's lateral DOFs from which the
        mode counts as a critical speed of that shaft
    method : ``"auto"``, ``"dense"`` (every eigenvalue, LAPACK) or ``"sparse"`` (shift-invert
        Arnoldi for the lowest, asking for more until ``n_modes`` per shaft are found); auto:
        dense up to ``SPARSE_FROM`` DOFs
    rigid_tol : rad/s, frequencies below it are rigid-body motions (free torsion of the train)
    operating_point : name or :class:`~gearrotor.model.OperatingPoint` (issue 11): the
        fluid-film bearings' Kxx/Kyy curves at the point's static loads, at each of the speeds
        their ``fluid_film.speeds`` list, the point's ``hold`` (power or torque) kept
        (:func:`~gearrotor.analyses.static.at_operating_point`)
    """
    if operating_point is not None:
        model = _at_operating_point(model, operating_point)
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    if not train.bearings:
        raise ModelError(
            "the critical speed map sweeps the radial bearings' stiffness, but the model has none",
            field="bearings",
            expected="at least one [[bearings]] entry",
        )
    if not (isinstance(n_modes, int | np.integer) and n_modes >= 1):
        raise ModelError("n_modes must be a positive integer", field="n_modes", value=n_modes)
    if not 0 <= min_share < 1:
        raise ModelError(
            "min_share must be a fraction",
            field="min_share",
            value=min_share,
            expected="0 <= min_share < 1",
        )
    if stiffness is None:
        ks = _default_stiffness(asm, n_stiffness)
    else:
        arr = np.asarray(stiffness, float)
        if isinstance(stiffness, tuple) and len(stiffness) == 2:
            arr = np.logspace(np.log10(arr[0]), np.log10(arr[1]), n_stiffness)
        ks = np.sort(arr)
    if len(ks) < 2 or not np.all(ks > 0) or not np.all(np.isfinite(ks)):
        raise ModelError(
            "bearing stiffness values for the map must be positive and finite, at least two",
            field="stiffness",
            value=stiffness,
            expected="e.g. (1e6, 1e10) N/m",
        )
    prob = _Synchronous(train, rigid_tol)
    method = _check_method(method, prob.asm.n_dof)
    keys, group = _groups(prob.asm)
    ns = len(train.shafts)
    crit = np.full((ns, len(ks), n_modes), np.nan)
    for g, r in enumerate(keys):
        members = np.flatnonzero(group == g)
        for j, k in enumerate(ks):
            found = _criticals(prob, float(k), r, members, n_modes, min_share, method, rigid_tol)
            for si, f in found.items():
                crit[si, j, : len(f)] = f
    rigid = _rigid(prob, n_modes, min_share, method, rigid_tol)
    shafts = tuple(
        UCSShaft(s.name, i, float(asm.speed_ratio[i]), crit[i], rigid[s.name])
        for i, s in enumerate(train.shafts)
    )
    curves = _bearing_curves(asm)
    inter = _intersections(shafts, curves, ks, asm, group)
    return UCSResult(
        stiffness=ks,
        shafts=shafts,
        bearings=curves,
        intersections=inter,
        min_share=min_share,
        method=method,
        n_solves=prob.n_solves,
        operating_range=train.operating_speed_range,
        max_continuous_speed=train.max_continuous_speed,
        train=train,
    )


def _intersections(shafts, curves, ks, asm, group) -> tuple[Intersection, ...]:
    names = [s.name for s in asm.train.shafts]
    logk = np.log10(ks)
    out = []
    for s in shafts:
        ratio = abs(s.speed_ratio)
        for mode in range(s.critical_speeds.shape[1]):
            c = s.critical_speeds[:, mode]
            ok = np.isfinite(c)
            if ok.sum() < 2:
                continue
            lk, cc = logk[ok], c[ok]

            def branch(k, lk=lk, cc=cc):
                return np.interp(np.log10(k), lk, cc)

            for b in curves:
                bi = names.index(b.shaft)
                if group[bi] != group[s.index]:
                    continue  # a bearing on a shaft at another speed: different axis
                for direction, kv in (("kxx", b.kxx), ("kyy", b.kyy)):
                    for speed, kval in _meet(branch, b.speeds, kv, lk[0], lk[-1]):
                        out.append(
                            Intersection(
                                s.name,
                                mode,
                                b.name,
                                direction,
                                float(kval),
                                float(speed),
                                float(speed / ratio),
                            )
                        )
    return tuple(out)


def _meet(branch, speeds, kv, lk_min, lk_max):
    """Speeds N where branch(K(N)) = N on a bearing curve (within the swept stiffness)."""
    if speeds is None:  # constant bearing: the critical at its stiffness
        k = float(kv[0])
        if k > 0 and lk_min <= np.log10(k) <= lk_max:
            yield float(branch(k)), k
        return
    if len(speeds) < 2:
        return
    grid = np.unique(
        np.concatenate(
            [np.linspace(a, b, 41) for a, b in zip(speeds[:-1], speeds[1:], strict=True)]
        )
    )

    def kof(n):
        return np.interp(n, speeds, kv)

    inside = (
        (kof(grid) > 0)
        & (np.log10(np.maximum(kof(grid), 1e-300)) >= lk_min)
        & (np.log10(np.maximum(kof(grid), 1e-300)) <= lk_max)
    )

    def g(n):
        return float(branch(kof(n)) - n)

    vals = np.array([g(n) if ins else np.nan for n, ins in zip(grid, inside, strict=True)])
    for i in range(len(grid) - 1):
        a, b = vals[i], vals[i + 1]
        if np.isfinite(a) and np.isfinite(b) and a * b <= 0 and (a != 0 or i == 0):
            n0 = grid[i] if a == 0 else brentq(g, grid[i], grid[i + 1], xtol=1e-9, rtol=1e-12)
            yield float(n0), float(kof(n0))
