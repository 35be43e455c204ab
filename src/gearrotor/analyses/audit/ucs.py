"""Undamped critical speed map of a train (API RP 684, 2nd ed. 2005; API 617 lateral analysis).

**What is swept.** Every radial bearing of the model is replaced by the same isotropic stiffness
k (kxx = kyy = k, no cross-coupling, no damping), swept on a log scale; everything else keeps its
stiffness: shafts, couplings, thrust bearings, pedestals (a bearing on a ``support`` is the spring
k between journal and pedestal) and the gear meshes, so on a geared train the lateral, torsional
and axial motions stay coupled through the mesh. Damping, the model's ``[[cross_couplings]]`` and
the circulatory stiffness of rotating shaft damping are left out (an *undamped* map).

**Synchronous solutions.** At reference-shaft speed Ω each shaft s spins at Ω_s = r_s Ω, so the
undamped equations are ``M q̈ + Ω G₁ q̇ + K q = 0`` with ``G₁ = Σ_s r_s G_s`` (each shaft's
gyroscopic matrix scaled by its own speed ratio). A free vibration at the running frequency of
shaft s, ω = |r_s| Ω, with q = φ e^{iωt} and Ω = σ ω / |r_s| (σ the sense of the reference
spin, the sign of the model's speed), solves

    K(k) φ = ω² B_s φ,    K(k) = K₀ + k K_b,    B_s = M − i (σ / |r_s|) G₁,

a pencil with K symmetric and B_s Hermitian (G₁ is real skew), so ω² is real; one solve per
distinct |r_s| serves every shaft at that speed. Forward and backward whirl come out together
(a disk whose polar inertia exceeds its transverse inertia has no forward conical solution: its
ω² is negative and is dropped).

**Branches are monotone, by construction.** K_b (a unit spring at every journal) is positive
semi-definite, so along a branch dω²/dk = φᴴK_bφ / φᴴB_sφ ≥ 0 (φᴴB_sφ = φᴴKφ / ω² > 0), and by
the min–max principle for the pencil the j-th lowest ω² never decreases with k and stays below
the j-th ω² with the journals pinned (k → ∞). The solutions at neighbouring stiffnesses are
paired by mode shape: the pairing maximises the total mass-weighted MAC among the pairings that
lower no ω² (a linear assignment; the sorted order is always admissible, so the constraint only
decides where shapes alone are ambiguous), and a step whose worst pairing has MAC < ``MAC_OK`` is
bisected in log k (``MAX_REFINE`` levels) until the shapes follow each other. A branch is thus
one mode followed by shape; it never falls. The whole sweep follows every solution below
``CAP`` times the highest rigid-support critical kept (the branches that matter start below it,
and they only rise).

**A critical speed of shaft s** (the mesh couples the shafts, so a mode of the train belongs to
no single shaft): a branch at a stiffness where its mode can be excited by unbalance on shaft s,
namely where the *forward lateral kinetic energy on shaft s* holds at least ``min_share`` of the
mode's kinetic energy,

    q_s = φᴴ M_s P_s φ / φᴴ M φ,    P_s = (I − i σ_s J) / 2,

M_s the mass of shaft s's lateral DOFs (x, y, θx, θy), J the quarter turn about the shaft axis
((x, y, θx, θy) → (−y, x, −θy, θx)), which commutes with an axisymmetric shaft's mass, and σ_s
the sense of shaft s's spin: P_s projects the orbits on their circles turning with the shaft,
and the modal force of an unbalance (a force turning with the shaft) is the forward part of the
mode's motion at its node. A backward mode, a mode of another shaft or a torsional or axial
mode of the mesh has q_s ≈ 0; a straight-line orbit splits evenly (q_s = ½ of the shaft's
lateral share). A branch can be a critical of shaft s over part of the sweep only (through an
avoided crossing with a mode of the other shaft or of the mesh its shape, and the excitation,
changes): the map holds each branch's speeds where it is a critical of the shaft (``critical_
speeds``, NaN elsewhere) and the whole branch (``branch_speeds``). The branches of shaft s are
those among its ``n_modes`` lowest criticals at some stiffness of the sweep, numbered by their
speed at the softest stiffness. A repeated ω² (two identical shafts, an isotropic rotor without
gyroscopics) is split along the shafts' forward forms (``Σ_s (s + 1) M_s P_s``), so identical
shafts get identical maps.

**Bearing curves and intersections.** Each bearing's Kxx and Kyy over its table's speeds (its
shaft's speed) are drawn on its own shaft's panel; a critical speed branch meets a bearing curve
where ``ω_b(K(N)) = N`` (K(N) interpolated linearly in speed, as the bearing table is). The
roots are bracketed by exact values (the map's stiffnesses, the table's speeds) and found by
Brent's method on the eigenvalue itself: each evaluation solves the synchronous problem at K(N)
(Rayleigh-quotient iteration from the branch's neighbouring shape, checked against the branch's
bracket and shape; a full solve otherwise), so an intersection is an exact critical of the
bearing at that speed. Bearings with identical curves on the same shaft share a row.

**Rigid supports** (``rigid_support_criticals``): the journal x, y DOFs of every bearing are
removed (pinned journals), the limit of the map as k → ∞; API 617's critical speed ratio uses the
first of them.

**Determinism.** The dense solver finds every solution (LAPACK, no random start); the sparse one
(large models) starts ARPACK from a fixed vector and asks for more solutions until every one
below the bound is found. The same input gives the same map, bit for bit.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray
from scipy.optimize import brentq, linear_sum_assignment

from ...assembly import Assembly, _Triplets, assemble
from ...elements import RadialBearing
from ...errors import ModelError, SolverError
from ...model import Train
from ...progress import Progress, part, report
from ...threads import managed

__all__ = [
    "UCSResult",
    "UCSShaft",
    "BearingCurve",
    "Intersection",
    "ucs_map",
    "rigid_support_criticals",
    "MAX_MODES",
]

RPM = 30 / np.pi
_LATERAL = (0, 1, 3, 4)  # x, y, θx, θy
#: from this many DOFs "auto" uses the sparse solver: the dense one finds every solution of the
#: pencil (n³: 0.04 s at 192 DOFs, 0.08 s at 252 on the test machine), the sparse one the lowest
#: few dozen the tracking needs
SPARSE_FROM = 400
#: most branches per shaft a map asks for: an undamped critical speed map is read for the first
#: few modes (API RP 684 looks at the modes up to about twice the maximum continuous speed);
#: every branch asked for widens the band of solutions followed at every stiffness
MAX_MODES = 12
#: default forward lateral share from which a mode is a critical speed of a shaft (module
#: docstring): a mode with 10 % of its kinetic energy in the forward whirl of the shaft responds
#: there with about a tenth of a mode of the shaft alone at the same damping
MIN_SHARE = 0.1
#: the sweep follows every solution below CAP times the highest rigid-support critical kept
CAP = 1.5
#: a pairing of neighbouring solutions is trusted when every MAC is at least this; otherwise the
#: step is bisected in log k
MAC_OK = 0.7
#: bisection levels of one step of the sweep at most (2³ = 8 sub-steps)
MAX_REFINE = 3
#: pairings are checked for the branches up to WATCH times the highest of the lowest
#: ``n_modes`` criticals of the shafts (the rest only has to be admissible)
WATCH = 1.3
#: candidates beyond the followed branches offered to the pairing at each step
_EXTRA = 6
#: relative round-off allowed when checking that a pairing lowers no ω²
_MONO_TOL = 1e-8
#: rigid-body motions: eigenvalues of the stiffness below this times its largest (round-off of
#: exact zeros is ~1e-15; the softest spring of the test models, 30 N/m on a 1e10 N/m shaft,
#: stands at 3e-9)
_NULL = 1e-12
#: solutions whose ω² agree to this (relative) are not separated by bisecting the step
_TWINS = 1e-3


@dataclass(frozen=True)
class UCSShaft:
    """The map of one shaft (rad/s of that shaft). Columns are branches (modes followed by
    shape over the sweep), numbered by their speed at the softest stiffness."""

    name: str
    index: int
    speed_ratio: float  # Ω_shaft / Ω_reference (signed)
    critical_speeds: NDArray  # (n_stiffness, n_branches): the branch where it is a critical
    branch_speeds: NDArray  # (n_stiffness, n_branches): the whole branch (NaN: not followed)
    forward_share: NDArray  # (n_stiffness, n_branches): q_s of the branch's mode
    rigid_critical_speeds: NDArray  # (n_modes,) journals pinned, lowest first, NaN-padded

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
    """Where a critical speed branch of a shaft meets the stiffness curve of bearings on it
    (``bearings`` and ``directions`` list every bearing and direction with that same curve)."""

    shaft: str
    mode: int  # branch index of the shaft, 0-based ("critical mode + 1" in the table, figure)
    bearings: tuple[str, ...]
    directions: tuple[str, ...]  # "kxx" and/or "kyy"
    stiffness: float  # N/m
    speed: float  # rad/s of the shaft
    reference_speed: float  # rad/s of the reference shaft
    forward_share: float  # q_s of the mode there


@dataclass(frozen=True)
class UCSResult:
    """Undamped critical speed map: see the module docstring for the definitions."""

    stiffness: NDArray  # (n_stiffness,) N/m, the isotropic stiffness of every bearing
    shafts: tuple[UCSShaft, ...]
    bearings: tuple[BearingCurve, ...]
    intersections: tuple[Intersection, ...]
    n_modes: int
    min_share: float
    method: str
    n_solves: int  # full eigen-solves (sweep, bisections, rigid supports, fall-backs)
    n_refined: int  # stiffnesses added by bisection to follow the shapes
    n_iterations: int  # Rayleigh-quotient iterations of the intersection search
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

        def share(a):
            return [None if not np.isfinite(v) else float(v) for v in np.ravel(a)]

        return {
            "stiffness_N_per_m": [float(k) for k in self.stiffness],
            "n_modes": self.n_modes,
            "min_share": self.min_share,
            "method": self.method,
            "n_solves": self.n_solves,
            "n_refined": self.n_refined,
            "n_iterations": self.n_iterations,
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
                    "critical_speeds_rpm": [rpm(c) for c in s.critical_speeds.T],
                    "branch_speeds_rpm": [rpm(c) for c in s.branch_speeds.T],
                    "forward_share": [share(c) for c in s.forward_share.T],
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
                    "bearings": list(x.bearings),
                    "directions": list(x.directions),
                    "stiffness_N_per_m": x.stiffness,
                    "speed_rpm": x.speed * RPM,
                    "reference_speed_rpm": x.reference_speed * RPM,
                    "forward_share": x.forward_share,
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
            f"{'shaft':>12} {'critical':>8} {'dir':>7} {'k N/m':>11} {'rpm':>9} {'ref rpm':>9} "
            f"{'q':>5}  bearings"
        )
        rows += [
            "",
            "intersections with the stiffness curves of the shaft's own bearings "
            "(q: forward lateral share of the mode on the shaft)",
            head,
            "-" * len(head),
        ]
        for x in self.intersections:
            rows.append(
                f"{x.shaft:>12} {x.mode + 1:>8} {'='.join(x.directions):>7} {x.stiffness:>11.4g} "
                f"{x.speed * RPM:>9.0f} {x.reference_speed * RPM:>9.0f} {x.forward_share:>5.2f}"
                f"  {', '.join(x.bearings)}"
            )
        if not self.intersections:
            rows.append("  (none within the stiffness range)")
        return "\n".join(rows)


# --------------------------------------------------------------------------------------------
@dataclass
class _Solution:
    """Solutions of the synchronous pencil at one stiffness, lowest ω² first: M-normalised
    shapes, repeated roots split along the shafts' forward forms; q (n_shafts, m) the forward
    lateral shares."""

    w2: NDArray
    V: NDArray
    q: NDArray


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
        # per shaft: the forward lateral kinetic energy form M_s P_s (see the module docstring)
        self.forward_form = []
        for si, offs in enumerate(asm.node_offset):
            lat = np.concatenate([offs + d for d in _LATERAL])
            sel = sp.csr_array((np.ones(len(lat)), (np.arange(len(lat)), lat)), shape=(len(lat), n))
            Ms = (sel @ self.M @ sel.T).tocsr()
            J = sp.lil_array((n, n))
            for o in offs:
                J[o, o + 1], J[o + 1, o] = -1.0, 1.0  # x' = −y, y' = x
                J[o + 3, o + 4], J[o + 4, o + 3] = -1.0, 1.0
            Js = (sel @ J.tocsr() @ sel.T).tocsr()
            sigma = self.sense * (np.sign(asm.speed_ratio[si]) or 1.0)
            P = 0.5 * (sp.eye_array(len(lat)) - 1j * sigma * Js)
            F = sel.T @ (0.5 * (Ms @ P + (Ms @ P).conj().T)) @ sel
            self.forward_form.append(F.tocsr())
        self.combined_form = sum(
            ((i + 1.0) * F for i, F in enumerate(self.forward_form)), sp.csr_array((n, n))
        )
        self.n_solves = 0
        self.n_iterations = 0
        self.rigid_tol = rigid_tol
        self._reduction: dict[tuple, tuple] = {}
        self._B: dict[float, sp.csc_array] = {}
        self._v0 = np.random.default_rng(20240522).standard_normal(n).astype(complex)

    def B(self, ratio: float) -> sp.csc_array:
        """B_s of the shafts spinning at |ratio| (sparse, cached)."""
        hit = self._B.get(ratio)
        if hit is None:
            hit = self._B[ratio] = (self.M - 1j * (self.sense / abs(ratio)) * self.G1).tocsc()
        return hit

    def K(self, k: float) -> sp.csc_array:
        return (self.K0 + k * self.Kb).tocsc()

    # -- solving --------------------------------------------------------------------------
    def solve(self, k: float | None, ratio: float, method: str, m: int | None, cap2=np.inf):
        """The lowest positive ω² (at least ``m`` of them, or every one up to ``cap2`` when
        ``m`` is None) at bearing stiffness k (None: pinned journals) for the shafts spinning
        at |ratio|, as a :class:`_Solution` with full-length shapes."""
        self.n_solves += 1
        if method == "dense":
            w2, V = self._dense(k, ratio, m, cap2)
        else:
            B = self.B(ratio)
            if k is None:
                K = self.K0.tocsc()[self.free][:, self.free]
                B = B[self.free][:, self.free]
            else:
                K = self.K(k)
            w2, V = self._sparse(K, B, m, cap2)
        if k is None:
            full = np.zeros((self.asm.n_dof, V.shape[1]), complex)
            full[self.free] = V
            V = full
        ok = w2 > self.rigid_tol**2
        w2, V = w2[ok], V[:, ok]
        order = np.argsort(w2, kind="stable")
        Kk = self.K0[self.free][:, self.free] if k is None else self.K0 + k * self.Kb
        norm = float(abs(Kk).sum(axis=1).max())
        return self._resolve(w2[order], V[:, order], norm)

    def _resolve(self, w2: NDArray, V: NDArray, norm: float) -> _Solution:
        """M-normalise, split repeated roots along the combined forward form (one value per
        cluster), and evaluate every shaft's forward share. Two roots are one where they
        differ by less than their round-off, 10 ε ‖K‖ ‖φ‖² for M-normalised φ (the backward
        error of the factorisation is ε ‖K‖: on soft supports the forward and backward
        translation of an isotropic rotor, one root, came out 1e-7 apart), or 1e-7."""
        MV = self.M @ V
        V = V / np.sqrt(np.maximum(np.real(np.sum(V.conj() * MV, axis=0)), 1e-300))
        tol = np.maximum(
            1e-7 * np.abs(w2), 10 * np.finfo(float).eps * norm * np.sum(np.abs(V) ** 2, axis=0)
        )
        w2 = w2.copy()
        for idx in _clusters(w2, tol):
            if len(idx) < 2:
                continue
            Vc = V[:, idx]
            A = Vc.conj().T @ (self.M @ Vc)
            H = Vc.conj().T @ (self.combined_form @ Vc)
            _, U = la.eigh(0.5 * (H + H.conj().T), 0.5 * (A + A.conj().T))
            Vc = Vc @ U[:, ::-1]  # the largest forward share first
            V[:, idx] = Vc / np.sqrt(np.real(np.sum(Vc.conj() * (self.M @ Vc), axis=0)))
            w2[idx] = np.mean(w2[idx])
        for j in range(V.shape[1]):  # a deterministic phase: the largest entry real positive
            i = int(np.argmax(np.abs(V[:, j])))
            V[:, j] *= np.exp(-1j * np.angle(V[i, j]))
        q = np.array([np.real(np.sum(V.conj() * (F @ V), axis=0)) for F in self.forward_form])
        return _Solution(w2, V, q)

    def _reduced(self, rigid: bool, ratio: float):
        """(P, P^H K₀ P, P^H K_b P, P^H B P) of the dense solver, cached per (supports,
        speed): P spans the complement φ ⊥ B N of the rigid-body motions N of the train (free
        torsion, free axial motion: the null space of K₀ + k K_b at any k > 0, taken at a k
        as stiff as the stiffest element, where every spring of the model stands far above
        the round-off of the exact zeros: eigenvalues below ``_NULL`` times the largest)."""
        key = (rigid, ratio)
        hit = self._reduction.get(key)
        if hit is not None:
            return hit
        keep = self.free if rigid else np.arange(self.asm.n_dof)
        sub = np.ix_(keep, keep)
        K0 = self.K0.toarray()[sub]
        Kb = np.zeros_like(K0) if rigid else self.Kb.toarray()
        B = self.B(ratio).toarray()[sub]
        k_ref = max(float(np.abs(np.diag(K0)).max()), 1.0)
        lam, X = la.eigh(K0 + k_ref * Kb, check_finite=False)
        N = X[:, np.abs(lam) <= _NULL * np.abs(lam).max()]
        P = la.null_space((B @ N).conj().T) if N.shape[1] else np.eye(len(keep))
        Ph = P.conj().T
        out = (P, Ph @ K0 @ P, Ph @ Kb @ P, Ph @ B @ P)
        self._reduction[key] = out
        return out

    def _dense(self, k: float | None, ratio: float, m, cap2) -> tuple[NDArray, NDArray]:
        """The lowest ``m`` positive ω² of K φ = ω² B φ (``m`` None: every one up to
        ``cap2``): the rigid-body motions deflated (:meth:`_reduced`), the reduced K is
        positive definite and the Hermitian pencil (B, K) is solved for its largest
        μ = 1/ω² (real; μ ≤ 0 means no synchronous critical, e.g. the forward conical mode of
        a disk whose polar inertia exceeds its transverse inertia). LAPACK's bisection and
        inverse iteration (``gvx``) for the wanted ones only: exact, and every one of them."""
        P, K0, Kb, B = self._reduced(k is None, ratio)
        Kr = K0 if k is None else K0 + k * Kb
        Kr = 0.5 * (Kr + Kr.conj().T)
        Br = 0.5 * (B + B.conj().T)
        nr = Kr.shape[0]
        if m is not None:
            subset = {"subset_by_index": [max(0, nr - m), nr - 1]}
        elif np.isfinite(cap2):
            subset = {"subset_by_value": (1.0 / cap2, np.inf)}
        else:
            subset = {}
        try:
            mu, Y = la.eigh(Br, Kr, check_finite=False, **subset)
        except la.LinAlgError:
            raise SolverError(
                "the critical speed problem's stiffness is not positive definite once the "
                "rigid-body motions are removed (a rigid-body motion the null space missed)"
            ) from None
        pos = mu > 0
        return 1.0 / mu[pos], P @ Y[:, pos]

    def _sparse(self, K, B, m: int | None, cap2: float) -> tuple[NDArray, NDArray]:
        """The lowest ω² by shift-invert Arnoldi on (K − σB)⁻¹B, σ slightly below zero, from a
        fixed start vector; asks for more until ``m`` positive ones (or every one up to
        ``cap2``) are found."""
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
        count = max(2 * (m or 8) + 10, 20)
        v0 = self._v0[:n]
        while True:
            count = min(count, n - 2)
            try:
                nu, V = spla.eigs(op, k=count, which="LM", v0=v0)
            except spla.ArpackNoConvergence as exc:
                raise SolverError(
                    f"sparse critical-speed eigensolver did not converge: {exc}"
                ) from None
            w2 = sigma + 1.0 / nu
            real = np.isfinite(w2) & (np.abs(w2.imag) <= 1e-6 * np.maximum(np.abs(w2), 1e-30))
            w2, V = w2[real].real, V[:, real]
            pos = w2 > self.rigid_tol**2
            # every solution nearer the shift than the farthest found has been found
            enough = (pos.sum() >= m) if m is not None else (np.abs(w2).max() > cap2)
            if enough or count >= n - 2:
                return w2, V
            count *= 2

    def rqi(self, k: float, ratio: float, w2: float, v: NDArray, w2_range) -> tuple | None:
        """The solution near ``w2`` at stiffness k: one inverse iteration at that shift from
        the shape v, then Rayleigh-quotient iteration; None unless it converges (relative
        residual 1e-11) inside ``w2_range``."""
        K, B = self.K(k), self.B(ratio)
        x, shift = v.astype(complex), w2
        for _ in range(30):
            try:
                y = spla.splu((K - shift * B).tocsc()).solve(B @ x)
            except RuntimeError:  # the shift is a root to round-off: x is its shape
                y = x
            self.n_iterations += 1
            x = y / np.linalg.norm(y)
            Kx, Bx = K @ x, B @ x
            lam = np.real(x.conj() @ Kx) / np.real(x.conj() @ Bx)
            if np.linalg.norm(Kx - lam * Bx) <= 1e-11 * np.linalg.norm(Kx):
                break
            shift = lam
        else:
            return None
        lo, hi = w2_range
        if not lo <= lam <= hi:
            return None
        return lam, x


def _pair(wa: NDArray, Va: NDArray, sol: _Solution, M) -> tuple[NDArray, NDArray]:
    """Pair the branches (ω² ``wa``, M-normalised shapes ``Va``) with the solutions ``sol`` at
    the next stiffness: the largest total MAC among the pairings that lower no ω² (module
    docstring). Returns the partner of each branch (−1: none) and its MAC."""
    ra, cb = len(wa), len(sol.w2)
    pairs, macs = np.full(ra, -1), np.zeros(ra)
    if not ra or not cb:
        return pairs, macs
    mac = np.abs(Va.conj().T @ (M @ sol.V)) ** 2
    ok = sol.w2[None, :] >= wa[:, None] * (1 - _MONO_TOL)
    big = 1e6
    # the product of the MACs: no branch is sacrificed to a shape it does not have (a sum
    # would trade one MAC of 0 for another of 1 across a crossing too close to resolve)
    cost = np.where(ok, -np.log(np.maximum(mac, 1e-12)), big)
    rows, cols = linear_sum_assignment(cost)
    if (cost[rows, cols] >= big).any():
        # no admissible pairing by shape: the sorted order (admissible by the min–max
        # principle, up to round-off)
        rows = np.argsort(wa, kind="stable")[: min(ra, cb)]
        cols = np.arange(len(rows))
    pairs[rows] = cols
    macs[rows] = mac[rows, cols]
    return pairs, macs


def _resolvable(wa: NDArray, sol: _Solution, Va: NDArray, M, pairs: NDArray) -> NDArray:
    """Per branch: whether a bisection can sharpen its pairing, i.e. its shape is spread
    over solutions whose ω² differ by more than ``_TWINS`` (closer ones cross within a
    stiffness step too small to resolve; any admissible pairing of them is as good)."""
    mac = np.abs(Va.conj().T @ (M @ sol.V)) ** 2
    out = np.zeros(len(wa), bool)
    for i in range(len(wa)):
        where = np.flatnonzero(mac[i] >= 0.05)
        partner = [sol.w2[pairs[i]]] if pairs[i] >= 0 else []
        vals = np.concatenate([sol.w2[where], [wa[i]], partner])
        out[i] = vals.max() - vals.min() > _TWINS * vals.max()
    return out


class _Sweep:
    """The branches of the synchronous solutions at one speed ratio, followed by shape over
    increasing stiffness (grid points and bisections)."""

    def __init__(
        self, prob: _Synchronous, ratio: float, method: str, cap2: float, members, n_modes, share
    ) -> None:
        self.prob, self.ratio, self.method, self.cap2 = prob, ratio, method, cap2
        self.members, self.n_modes, self.share = members, n_modes, share
        self.ks: list[float] = []
        self.w2: list[NDArray] = []  # per point: ω² per branch (NaN: not followed there)
        self.V: list[NDArray] = []  # per point: (n_dof, n_branches) shapes
        self.q: list[NDArray] = []  # per point: (n_shafts, n_branches) forward shares
        self.n_refined = 0
        self._solutions: dict[float, _Solution] = {}

    def _solve(self, k: float, m: int | None) -> _Solution:
        hit = self._solutions.get(k)
        if hit is not None and m is not None and len(hit.w2) >= m:
            return hit
        sol = self.prob.solve(k, self.ratio, self.method, m, self.cap2)
        self._solutions[k] = sol
        return sol

    def run(self, grid: NDArray, progress: Progress | None = None) -> None:
        first = self._solve(float(grid[0]), None)
        nb = int(np.sum(first.w2 <= self.cap2))
        self._record(float(grid[0]), first.w2[:nb], first.V[:, :nb], first.q[:, :nb])
        for i, k in enumerate(grid[1:]):
            report(progress, (i + 1) / len(grid), f"stiffness {i + 2}/{len(grid)}")
            self._step(float(k), 0)
        self._solutions.clear()

    def _watched(self, w2: NDArray, q: NDArray) -> NDArray:
        """The branches whose pairing must be sure: the criticals of the member shafts up to
        ``WATCH`` times the highest of their ``n_modes`` lowest here (the branches a map may
        keep), below the bound."""
        top = 0.0
        crit = np.zeros(len(w2), bool)
        for si in self.members:
            crit |= q[si] >= self.share
            c = np.sort(w2[q[si] >= self.share])
            top = max(top, c[self.n_modes - 1] if len(c) >= self.n_modes else self.cap2)
        return crit & (w2 <= min(top * WATCH**2, self.cap2))

    def _record(self, k, w2, V, q) -> None:
        self.ks.append(k)
        self.w2.append(w2)
        self.V.append(V)
        self.q.append(q)

    def _step(self, kb: float, depth: int) -> None:
        ka, wa, Va = self.ks[-1], self.w2[-1], self.V[-1]
        alive = np.flatnonzero(np.isfinite(wa))
        sol = self._solve(kb, len(alive) + _EXTRA)
        pairs, macs = _pair(wa[alive], Va[:, alive], sol, self.prob.M)
        bad = self._watched(wa[alive], self.q[-1][:, alive]) & (macs < MAC_OK)
        if depth < MAX_REFINE and bad.any():
            bad[bad] = _resolvable(wa[alive][bad], sol, Va[:, alive[bad]], self.prob.M, pairs[bad])
        if depth < MAX_REFINE and bad.any():
            km = float(np.sqrt(ka * kb))
            self.n_refined += 1
            self._step(km, depth + 1)
            self._step(kb, depth + 1)
            return
        used = set(pairs[pairs >= 0].tolist())
        new = [c for c in range(len(sol.w2)) if c not in used and sol.w2[c] <= self.cap2]
        nb = len(wa) + len(new)
        n = self.prob.asm.n_dof
        w2 = np.full(nb, np.nan)
        V = np.zeros((n, nb), complex)
        q = np.full((len(self.prob.forward_form), nb), np.nan)
        for b, c in zip(alive, pairs, strict=True):
            if c >= 0:
                w2[b], V[:, b], q[:, b] = sol.w2[c], sol.V[:, c], sol.q[:, c]
        for j, c in enumerate(new):
            b = len(wa) + j
            w2[b], V[:, b], q[:, b] = sol.w2[c], sol.V[:, c], sol.q[:, c]
        self._record(kb, w2, V, q)

    def table(self, points: NDArray) -> tuple[NDArray, NDArray]:
        """ω² (n_points, n_branches) and q (n_shafts, n_points, n_branches) at the given
        followed points, NaN-padded for branches that start later."""
        nb = len(self.w2[-1])
        W = np.full((len(points), nb), np.nan)
        Q = np.full((len(self.prob.forward_form), len(points), nb), np.nan)
        for j, p in enumerate(points):
            m = len(self.w2[p])
            W[j, :m] = self.w2[p]
            Q[:, j, :m] = self.q[p]
        return W, Q

    def at(self, b: int, k: float) -> tuple[float, NDArray] | None:
        """Branch b at stiffness k inside the sweep: (ω², q per shaft), an exact solution of
        the synchronous problem at k (None where the branch is not followed)."""
        ks = self.ks
        i = int(np.searchsorted(ks, k))
        if i < len(ks) and ks[i] == k:
            w = self.w2[i][b] if b < len(self.w2[i]) else np.nan
            return None if not np.isfinite(w) else (float(w), self.q[i][:, b])
        if i == 0 or i == len(ks):
            return None
        a, c = i - 1, i
        wa = self.w2[a][b] if b < len(self.w2[a]) else np.nan
        wc = self.w2[c][b] if b < len(self.w2[c]) else np.nan
        if not (np.isfinite(wa) and np.isfinite(wc)):
            return None
        t = np.log(k / ks[a]) / np.log(ks[c] / ks[a])
        near = a if t <= 0.5 else c
        guess = wa + t * (wc - wa)
        lo, hi = wa * (1 - _MONO_TOL), wc * (1 + _MONO_TOL)
        got = self.prob.rqi(k, self.ratio, guess, self.V[near][:, b], (lo, hi))
        if got is not None:
            lam, x = got
            x = x / np.sqrt(np.real(x.conj() @ (self.prob.M @ x)))
            Vn = self.V[near]
            mac = np.abs(Vn.conj().T @ (self.prob.M @ x)) ** 2
            mac[~np.isfinite(self.w2[near])] = -1.0
            if int(np.argmax(mac)) == b and mac[b] >= MAC_OK:
                q = np.array([np.real(x.conj() @ (F @ x)) for F in self.prob.forward_form])
                return float(lam), q
        # not the branch's mode (or no convergence): a full solve, and the solution inside the
        # branch's bracket most like its neighbouring shape (none: the branch jumps here)
        sol = self.prob.solve(k, self.ratio, self.method, len(self.w2[a]) + _EXTRA, self.cap2)
        inside = np.flatnonzero((sol.w2 >= lo) & (sol.w2 <= hi))
        if not len(inside):
            return None
        mac = np.abs(self.V[near][:, b].conj() @ (self.prob.M @ sol.V[:, inside])) ** 2
        c = inside[int(np.argmax(mac))]
        return float(sol.w2[c]), sol.q[:, c]


def _bare_bearing(b):
    zero = {n: 0.0 for n in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")}
    return b.model_copy(
        update=zero | {"k": None, "c": None, "table": None, "table_file": None, "fluid_film": None}
    )


def _clusters(w2: NDArray, tol: NDArray) -> list[list[int]]:
    """Indices of (sorted) ω² grouped where consecutive values agree to their tolerance."""
    groups: list[list[int]] = []
    for i, v in enumerate(w2):
        j = groups[-1][-1] if groups else -1
        if groups and abs(v - w2[j]) <= max(tol[i], tol[j], 1e-30):
            groups[-1].append(i)
        else:
            groups.append([i])
    return groups


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
    at each speed of their own ``speeds``: the map's bearing curves answer "where is the
    critical at these loads", so the point's torque (and with it every static load) is held
    over the curve's speeds, whatever the point's ``hold`` says for sweeps of the running
    speed."""
    from ..static.operating_point import model_at_operating_point

    train = model if isinstance(model, Train) else model.train
    op = train.operating_point(operating_point)
    if op.power or op.torque:
        op = op.model_copy(update={"hold": "torque"})
    train.check_operating_point(op)
    layout = train.layout()
    sweep: set[float] = set()
    for b in train.bearings:
        if b.fluid_film is not None:
            ratio = abs(layout.shafts[train.shaft_index(b.shaft, "")].speed_ratio)
            sweep |= {abs(float(w)) / ratio for w in b.fluid_film.speeds}
    return model_at_operating_point(train, op, sorted(sweep) or None)[0]


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
        return "dense" if n_dof < SPARSE_FROM else "sparse"
    if method not in ("dense", "sparse"):
        raise ModelError(
            "unknown eigensolver method",
            field="method",
            value=method,
            expected="'auto', 'dense' or 'sparse'",
        )
    return method


def _check_counts(n_modes, min_share) -> None:
    if not (isinstance(n_modes, int | np.integer) and 1 <= n_modes <= MAX_MODES):
        raise ModelError(
            "the number of critical speeds per shaft is out of range",
            field="n_modes",
            value=n_modes,
            expected=f"an integer 1..{MAX_MODES} (a map is read for its first few modes)",
        )
    if not 0 < min_share < 1:
        raise ModelError(
            "min_share must be a fraction",
            field="min_share",
            value=min_share,
            expected="0 < min_share < 1",
        )


def rigid_support_criticals(
    model: Train | Assembly,
    *,
    n_modes: int = 3,
    min_share: float | None = None,
    method: str = "auto",
    rigid_tol: float = 1e-2,
) -> dict[str, NDArray]:
    """Forward synchronous critical speeds of every shaft with its journals pinned (rad/s of
    that shaft, lowest first, ``n_modes`` of them, NaN-padded): the API 617 rigid-support
    critical speeds (the critical speed ratio uses the first). A critical of a shaft as in
    the map (module docstring), ``min_share`` default ``MIN_SHARE``."""
    train = model.train if isinstance(model, Assembly) else model
    min_share = MIN_SHARE if min_share is None else min_share
    _check_counts(n_modes, min_share)
    prob = _Synchronous(train, rigid_tol)
    method = _check_method(method, prob.asm.n_dof)
    keys, group = _groups(prob.asm)
    out = {}
    for g, r in enumerate(keys):
        members = np.flatnonzero(group == g)
        for si, f in _rigid(prob, r, members, n_modes, min_share, method)[0].items():
            out[train.shafts[si].name] = f
    return out


def _rigid(prob, ratio, members, n_modes, min_share, method) -> tuple[dict, float]:
    """The pinned-journal criticals of the member shafts (NaN-padded to ``n_modes``) and the
    highest ω² among the lowest ``n_modes`` pinned solutions (a fall-back bound)."""
    m = 4 * n_modes * len(members) + 8
    while True:
        sol = prob.solve(None, ratio, method, m)
        found = {si: np.sqrt(sol.w2[sol.q[si] >= min_share])[:n_modes] for si in members}
        done = all(len(f) >= n_modes for f in found.values())
        if method == "dense" or done or m >= len(prob.free) - 2:
            break
        m *= 2
    top = float(sol.w2[min(n_modes, len(sol.w2)) - 1]) if len(sol.w2) else np.inf
    pad = {si: np.concatenate([f, np.full(n_modes - len(f), np.nan)]) for si, f in found.items()}
    return pad, top


@managed
def ucs_map(
    model: Train | Assembly,
    *,
    stiffness: NDArray | tuple[float, float] | None = None,
    n_stiffness: int = 31,
    n_modes: int = 4,
    min_share: float = MIN_SHARE,
    method: str = "auto",
    rigid_tol: float = 1e-2,
    operating_point=None,
    progress: Progress | None = None,
) -> UCSResult:
    """Undamped critical speed map (see the module docstring).

    Parameters
    ----------
    model : the train, or its assembly (the bearing curves come from its bearings)
    stiffness : N/m, the bearing stiffnesses: an array, or ``(k_min, k_max)`` swept on a log
        scale with ``n_stiffness`` points (default: one decade beyond the lowest and highest
        direct stiffness of the model's bearings)
    n_modes : criticals of each shaft kept at each stiffness (the lowest), 1..``MAX_MODES``;
        a shaft's branches are those among them somewhere in the sweep
    min_share : forward lateral share q_s of a mode's kinetic energy on a shaft from which the
        mode is a critical speed of that shaft (0 < min_share < 1)
    method : ``"auto"``, ``"dense"`` (every solution, LAPACK) or ``"sparse"`` (shift-invert
        Arnoldi from a fixed start vector for the lowest, as many as the tracking needs);
        auto: dense below ``SPARSE_FROM`` DOFs
    rigid_tol : rad/s, frequencies below it are rigid-body motions (free torsion of the train)
    operating_point : name or :class:`~gearrotor.model.OperatingPoint`: the fluid-film
        bearings' Kxx/Kyy curves at the point's static loads (its torque held), at each of the
        speeds their ``fluid_film.speeds`` list
    progress : a :data:`gearrotor.progress.Progress` callback (the stiffness sweep)
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
    _check_counts(n_modes, min_share)
    if stiffness is None:
        ks = _default_stiffness(asm, n_stiffness)
    else:
        arr = np.asarray(stiffness, float)
        if isinstance(stiffness, tuple) and len(stiffness) == 2:
            arr = np.logspace(np.log10(arr[0]), np.log10(arr[1]), n_stiffness)
        ks = np.unique(arr)
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
    curves = _bearing_curves(asm)
    shafts: list[UCSShaft | None] = [None] * len(train.shafts)
    inter: list[Intersection] = []
    n_refined = 0
    for g, r in enumerate(keys):
        report(progress, g / len(keys), f"speed-ratio group {g + 1}/{len(keys)}")
        members = np.flatnonzero(group == g)
        rigid, top = _rigid(prob, r, members, n_modes, min_share, method)
        highest = np.nanmax(np.concatenate(list(rigid.values())), initial=-np.inf)
        cap2 = (CAP * (highest if np.isfinite(highest) else np.sqrt(top))) ** 2
        sweep = _Sweep(prob, r, method, cap2, members, n_modes, min_share)
        sweep.run(ks, part(progress, g / len(keys), (g + 1) / len(keys)))
        n_refined += sweep.n_refined
        grid = np.searchsorted(sweep.ks, ks)
        W, Q = sweep.table(grid)
        for si in members:
            branches = _branches_of(W, Q[si], n_modes, min_share)
            w = np.sqrt(W[:, branches])
            q = Q[si][:, branches]
            crit = np.where(q >= min_share, w, np.nan)
            s = UCSShaft(
                train.shafts[si].name, int(si), float(asm.speed_ratio[si]), crit, w, q, rigid[si]
            )
            shafts[si] = s
            inter += _intersections(s, branches, sweep, curves, ks, min_share)
    order = {s.name: i for i, s in enumerate(train.shafts)}
    inter.sort(key=lambda x: (order[x.shaft], x.mode, x.speed))
    report(progress, 1.0)
    return UCSResult(
        stiffness=ks,
        shafts=tuple(shafts),
        bearings=curves,
        intersections=tuple(inter),
        n_modes=int(n_modes),
        min_share=float(min_share),
        method=method,
        n_solves=prob.n_solves,
        n_refined=n_refined,
        n_iterations=prob.n_iterations,
        operating_range=train.operating_speed_range,
        max_continuous_speed=train.max_continuous_speed,
        train=train,
    )


def _branches_of(W: NDArray, Q: NDArray, n_modes: int, min_share: float) -> list[int]:
    """The branches among a shaft's ``n_modes`` lowest criticals at some stiffness, numbered
    by their speed where they are first followed (the softest stiffness for all but branches
    that start inside the sweep)."""
    chosen: set[int] = set()
    for j in range(W.shape[0]):
        cand = np.flatnonzero(np.isfinite(W[j]) & (Q[j] >= min_share))
        chosen |= set(cand[np.argsort(W[j, cand], kind="stable")][:n_modes].tolist())

    def key(b):
        j = int(np.flatnonzero(np.isfinite(W[:, b]))[0])
        return (j, W[j, b], b)

    return sorted(chosen, key=key)


def _intersections(s: UCSShaft, branches, sweep: _Sweep, curves, ks, min_share):
    """Roots of ω_b(K(N)) = N of the shaft's branches on its own bearings' curves."""
    ratio = abs(s.speed_ratio)
    same: dict[tuple, list[tuple[str, str]]] = {}  # identical curves share one search
    for c in curves:
        if c.shaft != s.name:
            continue
        for direction, kv in (("kxx", c.kxx), ("kyy", c.kyy)):
            key = (None if c.speeds is None else tuple(c.speeds.tolist()), tuple(kv.tolist()))
            same.setdefault(key, []).append((c.name, direction))
    out = []
    for (speeds, kv), owners in same.items():
        names = tuple(dict.fromkeys(n for n, _ in owners))
        dirs = tuple(dict.fromkeys(d for _, d in owners))
        for mode, b in enumerate(branches):
            for N, k, q in _meet(sweep, b, s.index, speeds, kv, ks[0], ks[-1]):
                if q >= min_share:
                    out.append(Intersection(s.name, mode, names, dirs, k, N, N / ratio, q))
    return out


#: Relative round-off of a stiffness interpolated at a speed computed from it (np.interp).
_ROUND = 1e-12


def _meet(sweep: _Sweep, b: int, si: int, speeds, kv, k_lo: float, k_hi: float):
    """(N, K(N), q_s) where branch b meets the curve K(N) (``speeds`` None: a constant k).

    g(N) = ω_b(K(N)) − N is known exactly, without a solve, where the curve crosses a
    stiffness the sweep followed; the table's end speeds are solved for. An interval with a
    sign change is split at the table speeds inside it (solved) and the root found by Brent's
    method on exact solutions (:meth:`_Sweep.at`)."""
    if speeds is None:
        k = float(kv[0])
        got = sweep.at(b, k) if k_lo <= k <= k_hi else None
        if got is not None:
            yield float(np.sqrt(got[0])), k, float(got[1][si])
        return
    S, K = np.asarray(speeds, float), np.asarray(kv, float)
    if len(S) < 2:
        return

    def kof(n):
        return float(np.interp(n, S, K))

    known: dict[float, float] = {}  # N -> g(N), exact

    def g(n):
        if n in known:  # Brent's method starts at the bracket's ends: their exact values
            return known[n]
        k = kof(n)
        if k_lo * (1 - _ROUND) <= k <= k_hi * (1 + _ROUND):  # a range end to round-off is in
            k = min(max(k, k_lo), k_hi)
            got = sweep.at(b, k)
        else:
            got = None
        return np.nan if got is None else float(np.sqrt(got[0]) - n)

    ks = np.asarray(sweep.ks)
    for i in range(len(S) - 1):
        n0, n1, k0, k1 = S[i], S[i + 1], K[i], K[i + 1]
        if k1 == k0:
            continue
        t = (ks - k0) / (k1 - k0)
        for p in np.flatnonzero((t > 0) & (t < 1)):
            w = sweep.w2[p][b] if b < len(sweep.w2[p]) else np.nan
            known[float(n0 + t[p] * (n1 - n0))] = float(np.sqrt(w)) - float(n0 + t[p] * (n1 - n0))
    for n in (S[0], S[-1]):
        known[float(n)] = g(float(n))
    pts = np.array(sorted(known))
    vals = np.array([known[n] for n in pts])
    roots = [float(n) for n, v in zip(pts, vals, strict=True) if v == 0]
    for i in range(len(pts) - 1):
        a, c = vals[i], vals[i + 1]
        if not (np.isfinite(a) and np.isfinite(c) and a * c < 0):
            continue
        # split at the table's speeds inside (the curve's kinks)
        inner = S[(S > pts[i]) & (S < pts[i + 1])]
        xs = [pts[i], *inner.tolist(), pts[i + 1]]
        gs = [a, *[g(float(n)) for n in inner], c]
        for j in range(len(xs) - 1):
            if gs[j] == 0 and j > 0:
                roots.append(float(xs[j]))
            elif np.isfinite(gs[j]) and np.isfinite(gs[j + 1]) and gs[j] * gs[j + 1] < 0:
                roots.append(brentq(g, xs[j], xs[j + 1], xtol=1e-10, rtol=4 * np.finfo(float).eps))
    for n in sorted(roots):
        k = min(max(kof(n), k_lo), k_hi)
        yield n, k, float(sweep.at(b, k)[1][si])
