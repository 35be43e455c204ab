"""Campbell diagram: damped modes over a speed range, tracked by MAC, with excitation orders and
the crossing speeds (SPEC 3.1).

Mode tracking: at each speed the modes are matched to those of the previous speed by maximising
the modal assurance criterion ``MAC = |φᵢᴴψⱼ|² / (|φᵢ|²|ψⱼ|²)`` over an optimal one-to-one
assignment (Hungarian algorithm), with a small penalty on the frequency jump, so that a mode keeps
its identity through crossings and veerings with other modes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from ..assembly import Assembly, assemble
from ..model import Train
from .modal import ModalResult, _classify, modal

__all__ = ["CampbellResult", "ExcitationOrder", "Crossing", "campbell", "default_orders", "mac"]


@dataclass(frozen=True)
class ExcitationOrder:
    """An excitation line: frequency = ``multiple`` × |speed of ``shaft``| (rad/s)."""

    label: str
    shaft: int
    multiple: float


@dataclass(frozen=True)
class Crossing:
    mode: int
    order: str
    speed: float  # reference-shaft speed, rad/s
    frequency: float  # rad/s
    log_dec: float
    whirl: str
    mode_type: str


@dataclass(frozen=True)
class CampbellResult:
    """Tracked modes over speed: arrays (n_speeds, n_modes)."""

    speeds: NDArray  # reference-shaft speeds, rad/s
    damped_frequency: NDArray
    log_dec: NDArray
    whirl: NDArray  # str
    mode_type: NDArray  # str
    overdamped: NDArray  # bool
    orders: tuple[ExcitationOrder, ...]
    crossings: tuple[Crossing, ...]
    speed_ratio: NDArray
    shaft_names: tuple[str, ...]
    modal_results: tuple[ModalResult, ...] = field(repr=False, default=())
    # per speed: how it was solved ("full" or "reduced") and, per tracked mode, the relative
    # residual ‖P(λ)φ‖ / (|λ|²‖Mφ‖ + |λ|‖(C+G)φ‖ + ‖Kφ‖) of the eigenpair (~1e-10 for a dense
    # full solve, ~1e-6 for the sparse one's converged Arnoldi pairs, at most ``residual_tol``
    # for a reduced one)
    solver: tuple[str, ...] = ()
    residual: NDArray | None = field(repr=False, default=None)

    @property
    def full_solves(self) -> int:
        """Number of speeds solved on the full model (the others in the reduced basis)."""
        return sum(s == "full" for s in self.solver)

    def order_frequency(self, order: ExcitationOrder) -> NDArray:
        return order.multiple * np.abs(self.speed_ratio[order.shaft] * self.speeds)

    def to_dict(self) -> dict:
        rpm = 30 / np.pi
        return {
            "speeds_rpm": (self.speeds * rpm).tolist(),
            "modes": [
                {
                    "index": j,
                    "frequency_rpm": (self.damped_frequency[:, j] * rpm).tolist(),
                    "log_dec": self.log_dec[:, j].tolist(),
                    "whirl": self.whirl[:, j].tolist(),
                    "type": self.mode_type[:, j].tolist(),
                }
                for j in range(self.damped_frequency.shape[1])
            ],
            "solver": list(self.solver),
            "full_solves": self.full_solves,
            "max_residual": (float(np.max(self.residual)) if self.residual is not None else None),
            "orders": [
                {"label": o.label, "shaft": self.shaft_names[o.shaft], "multiple": o.multiple}
                for o in self.orders
            ],
            "crossings": [
                {
                    "mode": c.mode,
                    "order": c.order,
                    "speed_rpm": c.speed * rpm,
                    "frequency_rpm": c.frequency * rpm,
                    "log_dec": c.log_dec,
                    "whirl": c.whirl,
                    "type": c.mode_type,
                }
                for c in self.crossings
            ],
        }

    def table(self) -> str:
        rpm = 30 / np.pi
        wo = max([len("order"), *(len(str(c.order)) for c in self.crossings)])  # fits its text
        rows = [
            f"{'mode':>4} {'order':<{wo}} {'speed rpm':>11} {'freq rpm':>11} {'log dec':>8} "
            f"{'whirl':>5} {'type':>5}"
        ]
        rows.append("-" * len(rows[0]))
        for c in self.crossings:
            rows.append(
                f"{c.mode:>4} {c.order!s:<{wo}} {c.speed * rpm:>11.1f} "
                f"{c.frequency * rpm:>11.1f} {c.log_dec:>8.3g} {c.whirl:>5} "
                f"{c.mode_type:>5}"
            )
        return "\n".join(rows)


def mac(a: NDArray, b: NDArray) -> NDArray:
    """MAC matrix between the rows of a (m, n) and b (k, n)."""
    num = np.abs(a.conj() @ b.T) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=1), np.sum(np.abs(b) ** 2, axis=1))
    return num / np.maximum(den, 1e-300)


def default_orders(asm: Assembly, extra: tuple[float, ...] = ()) -> tuple[ExcitationOrder, ...]:
    """1x and 2x of every shaft of distinct speed, each gear-mesh frequency, and ``extra`` orders
    of the reference shaft."""
    names = [s.name for s in asm.train.shafts]
    ref = names.index(asm.train.reference)
    out: list[ExcitationOrder] = []
    seen: set[float] = set()
    multi = len({round(abs(r), 9) for r in asm.speed_ratio}) > 1
    for i, r in enumerate(asm.speed_ratio):
        key = round(abs(r), 9)
        if key in seen:
            continue
        seen.add(key)
        for m in (1.0, 2.0):
            label = f"{m:g}x {names[i]}" if multi else f"{m:g}x"
            out.append(ExcitationOrder(label, i, m))
    for m in asm.meshes:
        out.append(
            ExcitationOrder(
                f"{m.name} ({m.teeth[0]}x {names[m.shafts[0]]})", m.shafts[0], float(m.teeth[0])
            )
        )
    for m in extra:
        out.append(ExcitationOrder(f"{m:g}x {names[ref]}" if multi else f"{m:g}x", ref, float(m)))
    return tuple(out)


def campbell(
    model: Train | Assembly,
    *,
    speeds: NDArray,
    max_frequency: float,
    orders: tuple[ExcitationOrder, ...] | None = None,
    extra_orders: tuple[float, ...] = (),
    include_overdamped: bool = False,
    frequency_weight: float = 0.2,
    keep_results: bool = False,
    method: str = "sparse",
    operating_point=None,
    reduced: bool = True,
    residual_tol: float = 1e-4,
) -> CampbellResult:
    """Track damped modes over reference-shaft ``speeds`` (rad/s) up to ``max_frequency`` (rad/s).

    The number of tracked modes is the number of (not over-damped) modes below ``max_frequency``
    at the first speed; at later speeds they are matched among the modes with |λ| up to 1.5×
    that frequency. ``frequency_weight`` scales the relative-frequency-jump penalty added to
    1 − MAC.

    ``reduced=True`` (default) solves the first speed on the full model and every later one
    by a Rayleigh–Ritz step on a subspace (:class:`_Subspace`): the real and imaginary parts of
    the tracked modes' eigenvectors at the speeds solved on the full model (the last three).
    The Ritz pairs that continue the tracked modes (the same MAC assignment as for the full
    solve) are checked a posteriori on the full model by their relative residual
    ``‖P(λ)φ‖ / (|λ|²‖Mφ‖ + |λ|‖(C+G)φ‖ + ‖Kφ‖)``, ``P(λ) = λ²M + λ(C+G) + K``; when one
    exceeds ``residual_tol`` that speed is solved on the full model instead and its shapes join
    the subspace. The default tolerance keeps the frequencies and log decrements within 1e-6
    (relative) of the full solve (tests/perf): a Ritz value's error is second order in the
    residual when, as here, the left eigenvectors lie in the same real subspace (measured on
    SPEC 6.1: residuals ≤ 8.3e-5 → frequencies within 4e-9 and log decs within 7e-8 of the
    dense solve). The reduced speeds' ``modal_results`` hold the tracked modes only; the
    residuals and the solver used at each speed are in the result (``residual``, ``solver``,
    ``full_solves``). Cost per reduced speed: one dense eigenproblem of twice the subspace's
    dimension (104 states for the flagship's 13 tracked modes at two speeds) and O(n·m) work.

    ``method`` is the full solver: ``"sparse"`` (default) finds only the eigenvalues within the
    circle of radius 1.5×max_frequency about a small negative shift by shift-invert Arnoldi,
    ``"dense"`` computes the full spectrum (see :func:`~gearrotor.analyses.modal.modal`).

    ``operating_point`` (name or :class:`~gearrotor.model.OperatingPoint`): fluid-film bearings
    at the coefficients of the point's static loads at every speed, the point's ``hold``
    (power or torque) kept over the sweep (:func:`~gearrotor.analyses.static.at_operating_point`).
    """
    if operating_point is not None:
        # fluid-film bearings at the point's static loads at every speed (issue 11)
        from .static.operating import model_at_operating_point

        model = model_at_operating_point(model, operating_point, np.asarray(speeds, float))[0]
    asm = model if isinstance(model, Assembly) else assemble(model)
    speeds = np.asarray(speeds, float)
    orders = default_orders(asm, extra_orders) if orders is None else orders
    results = []
    prev_phi = prev_f = None
    n_track = None
    cols: dict[str, list] = {k: [] for k in ("f", "ld", "wh", "ty", "od", "res")}
    solver: list[str] = []
    k_hint = None
    radius = 1.5 * max_frequency
    space = _Subspace(asm) if reduced else None

    def assign(cand_phi: NDArray, cand_f: NDArray) -> NDArray:
        """Indices into the candidates of the modes that continue the tracked ones."""
        cost = 1.0 - mac(prev_phi, cand_phi)
        jump = np.abs(cand_f[None, :] - prev_f[:, None])
        cost = cost + frequency_weight * jump / np.maximum(prev_f[:, None], 1e-9)
        rows, colsel = linear_sum_assignment(cost)
        return colsel[np.argsort(rows)]

    for w in speeds:
        r = None
        if space is not None and space.ready:
            out = space.tracked_modes(w, radius, n_track, include_overdamped, assign)
            if out is not None and np.max(out[2]) <= residual_tol:
                r, chosen, res = out
                solver.append("reduced")
        if r is None:
            r = modal(asm, speed=w, max_frequency=radius, method=method, sparse_k=k_hint)
            k_hint = r.n_eigenvalues + 8  # those inside 1.5×max_frequency, and a margin
            idx = _candidates(r, include_overdamped, radius)
            if n_track is None:
                n_track = int(np.sum(r.damped_frequency[idx] <= max_frequency))
                if n_track == 0:
                    raise ValueError("no modes below max_frequency at the first speed")
                chosen = idx[:n_track]
            else:
                if len(idx) < n_track:
                    raise ValueError(
                        f"only {len(idx)} modes below 1.5×max_frequency at "
                        f"{w * 30 / np.pi:.1f} rpm; raise max_frequency"
                    )
                chosen = idx[assign(r.mode_shapes[idx], r.damped_frequency[idx])]
            res = _residuals(asm, w, r.eigenvalues[chosen], r.mode_shapes[chosen])
            solver.append("full")
            if space is not None:
                space.add(r.mode_shapes[idx if _ADD == "cand" else chosen])
        prev_phi = r.mode_shapes[chosen]
        prev_f = r.damped_frequency[chosen]
        cols["f"].append(prev_f)
        cols["ld"].append(r.log_dec[chosen])
        cols["wh"].append(np.array(r.whirl, dtype=object)[chosen])
        cols["ty"].append(np.array(r.mode_type, dtype=object)[chosen])
        cols["od"].append(r.overdamped[chosen])
        cols["res"].append(res)
        if keep_results:
            results.append(r)
    f = np.array(cols["f"])
    ld = np.array(cols["ld"])
    wh = np.array(cols["wh"], dtype=object)
    ty = np.array(cols["ty"], dtype=object)
    res = CampbellResult(
        speeds=speeds,
        damped_frequency=f,
        log_dec=ld,
        whirl=wh,
        mode_type=ty,
        overdamped=np.array(cols["od"]),
        orders=orders,
        crossings=(),
        speed_ratio=asm.speed_ratio,
        shaft_names=tuple(s.name for s in asm.train.shafts),
        modal_results=tuple(results),
        solver=tuple(solver),
        residual=np.array(cols["res"]),
    )
    return _with_crossings(res)


_N_KEEP = 3
_ADD = "tracked"
_TRUNC = 1e-10


def _candidates(r: ModalResult, include_overdamped: bool, radius: float) -> NDArray:
    """The modes that may be tracked: |λ| ≤ ``radius`` (what the sparse solver encloses, so
    that every solver offers the same set), over-damped ones only when asked."""
    keep = np.ones(len(r), bool) if include_overdamped else ~r.overdamped
    return np.flatnonzero(keep & (np.abs(r.eigenvalues) <= radius))


def _residuals(asm: Assembly, speed: float, lam: NDArray, phi: NDArray) -> NDArray:
    """Relative residual of each eigenpair (λ_j, φ_j = phi[j]) on the full model at ``speed``:
    ‖P(λ)φ‖ / (|λ|²‖Mφ‖ + |λ|‖(C+G)φ‖ + ‖Kφ‖), P(λ) = λ²M + λ(C+G) + K."""
    if not len(lam):
        return np.zeros(0)
    M, C, G, K = asm.matrices(speed)
    X = phi.T
    return _relative_residual(lam, M @ X, (C + G) @ X, K @ X)


def _relative_residual(lam: NDArray, MX: NDArray, CX: NDArray, KX: NDArray) -> NDArray:
    R = MX * lam**2 + CX * lam + KX
    a = np.abs(lam)
    den = (
        a**2 * np.linalg.norm(MX, axis=0)
        + a * np.linalg.norm(CX, axis=0)
        + np.linalg.norm(KX, axis=0)
    )
    return np.linalg.norm(R, axis=0) / np.maximum(den, 1e-300)


class _Subspace:
    """The real span of the tracked modes' shapes (real and imaginary parts) at the speeds
    solved on the full model, with the model's speed-independent matrices and per-shaft
    gyroscopic and circulatory matrices applied to it once; at any speed the damped problem is
    projected on it (a Rayleigh–Ritz step) in O(n·m²) without touching the sparse matrices
    again (except the bearings whose coefficients change with speed)."""

    def __init__(self, asm: Assembly):
        self.asm = asm
        self.shapes: list[NDArray] = []
        self.ready = False

    def add(self, phi: NDArray) -> None:
        self.shapes = [*self.shapes, phi][-_N_KEEP:]
        Z = np.vstack(self.shapes).T
        Z = np.hstack([Z.real, Z.imag])
        Q, s, _ = la.svd(Z, full_matrices=False, check_finite=False)
        Q = Q[:, s > _TRUNC * s[0]]
        asm = self.asm
        self.Q = Q
        self.MQ = asm.M @ Q
        self.C0Q = asm.C0 @ Q
        self.K0Q = asm.K0 @ Q
        self.GQ = [g @ Q if g.nnz else None for g in asm.G_shaft]
        self.KcQ = [k @ Q if k.nnz else None for k in asm.Kc_shaft]
        self.Mr = Q.T @ self.MQ
        try:
            self.cho = la.cho_factor(self.Mr, lower=True, check_finite=False)
        except la.LinAlgError:
            self.ready = False
            return
        self.ready = True

    def applied(self, speed: float) -> tuple[NDArray, NDArray, sp.csr_array | None]:
        """(C+G)Q and KQ at ``speed``, and K (sparse) when it changes with speed."""
        asm = self.asm
        speeds = asm.shaft_speeds(speed)
        CQ, KQ = self.C0Q.copy(), self.K0Q.copy()
        for s, gq, kq in zip(speeds, self.GQ, self.KcQ, strict=True):
            if s != 0.0:
                if gq is not None:
                    CQ += s * gq
                if kq is not None:
                    KQ += s * kq
        K = None
        if asm.speed_dependent:
            _, C, _, K = asm.matrices(speed)
            CQ += (C - asm.C0) @ self.Q
        if asm.speed_dependent or asm.rotating_damping:
            K = asm.matrices(speed)[3] if K is None else K
            if asm.speed_dependent:
                KQ = K @ self.Q
        return CQ, KQ, K

    def tracked_modes(self, speed, radius, n_track, include_overdamped, assign):
        """(result holding the tracked modes, their indices in it, their relative residuals on
        the full model) at ``speed``, or None when the projection offers fewer Ritz pairs than
        tracked modes (the caller then solves the full model)."""
        asm, Q = self.asm, self.Q
        CQ, KQ, K = self.applied(speed)
        m = Q.shape[1]
        A = np.zeros((2 * m, 2 * m))
        A[:m, m:] = np.eye(m)
        A[m:, :m] = -la.cho_solve(self.cho, Q.T @ KQ, check_finite=False)
        A[m:, m:] = -la.cho_solve(self.cho, Q.T @ CQ, check_finite=False)
        if not np.isfinite(A).all():
            return None
        lam, Y = la.eig(A, overwrite_a=True, check_finite=False)
        sel = np.flatnonzero((lam.imag > 0) & (np.abs(lam) <= radius))
        if len(sel) < n_track:
            return None
        lam, Y = lam[sel], Y[:m, sel]
        pick = assign((Q @ Y).T, lam.imag)
        lam, Y = lam[pick], Y[:, pick]
        res = _relative_residual(lam, self.MQ @ Y, CQ @ Y, KQ @ Y)
        order = np.argsort(lam.imag, kind="stable")
        w = float(speed)
        out = _classify(
            lam[order],
            Q @ Y[:, order],
            asm,
            asm.shaft_speeds(w),
            asm.K0 if K is None else K,
            rigid_tol=1e-2,
            overdamped_zeta=0.999,
            type_threshold=0.1,
            max_frequency=radius,
        )
        if len(out["eigenvalues"]) != n_track:  # a chosen Ritz pair classified as real/rigid
            return None
        if not include_overdamped and np.any(out["overdamped"]):
            return None
        r = ModalResult(
            speed=w,
            shaft_speeds=asm.shaft_speeds(w),
            method="reduced",
            n_eigenvalues=n_track,
            shaft_names=tuple(s.name for s in asm.train.shafts),
            assembly=asm,
            **out,
        )
        chosen = np.empty(n_track, int)
        chosen[order] = np.arange(n_track)
        return r, chosen, res


def _with_crossings(res: CampbellResult) -> CampbellResult:
    out = []
    s = res.speeds
    for o in res.orders:
        line = res.order_frequency(o)
        for j in range(res.damped_frequency.shape[1]):
            d = res.damped_frequency[:, j] - line
            for k in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
                t = d[k] / (d[k] - d[k + 1])
                sp = s[k] + t * (s[k + 1] - s[k])
                fr = res.damped_frequency[k, j] + t * (
                    res.damped_frequency[k + 1, j] - res.damped_frequency[k, j]
                )
                ld = res.log_dec[k, j] + t * (res.log_dec[k + 1, j] - res.log_dec[k, j])
                kk = k if t < 0.5 else k + 1
                out.append(
                    Crossing(
                        j,
                        o.label,
                        float(sp),
                        float(fr),
                        float(ld),
                        str(res.whirl[kk, j]),
                        str(res.mode_type[kk, j]),
                    )
                )
    out.sort(key=lambda c: (c.speed, c.frequency))
    return CampbellResult(**{**res.__dict__, "crossings": tuple(out)})
