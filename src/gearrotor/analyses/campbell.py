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
import scipy.sparse.linalg as spla
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from ..assembly import Assembly, assemble
from ..errors import SolverError
from ..model import Train
from .modal import DENSE_LIMIT, ModalResult, _classify, _solve_dense, modal

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

    ``reduced=True`` (default) solves the first speed on the full model and every later one in
    a reduced basis (:func:`_reduced_modes`): the undamped modes up to 2.25×max_frequency plus
    the real and imaginary parts of the tracked candidates' eigenvectors at the two previous
    speeds. Each eigenpair of the small
    damped problem is checked a posteriori on the full model by its relative residual
    ``‖P(λ)φ‖ / (|λ|²‖Mφ‖ + |λ|‖(C+G)φ‖ + ‖Kφ‖)``, ``P(λ) = λ²M + λ(C+G) + K``; when one
    exceeds ``residual_tol``, or the number of modes inside 1.5×max_frequency changed, that
    speed is solved on the full model instead. The default tolerance keeps the frequencies and
    log decrements within 1e-6 (relative) of the full solve (tests/perf): a Ritz value's error
    is second order in the residual when, as here, the left eigenvectors lie in the same basis
    (measured: residual 4e-5 → eigenvalue error 1e-10 to 5e-10). The residuals and
    the solver used at each speed are in the result (``residual``, ``solver``,
    ``full_solves``).

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
    basis = None
    carried = None
    n_cand = None
    for w in speeds:
        r = None
        if reduced and carried is not None:
            if basis is None:
                basis = _undamped_basis(asm, w, _UNDAMPED * radius)
            r, res = _reduced_modes(asm, w, basis, carried, radius)
            cand_r = _candidates(r, include_overdamped, radius)
            if len(cand_r) != n_cand or (len(cand_r) and np.max(res[cand_r]) > residual_tol):
                r = None
        if r is None:
            r = modal(asm, speed=w, max_frequency=radius, method=method, sparse_k=k_hint)
            k_hint = r.n_eigenvalues + 8  # those inside 1.5×max_frequency, and a margin
            res = _residuals(asm, w, r.eigenvalues, r.mode_shapes)
            solver.append("full")
        else:
            solver.append("reduced")
        idx = _candidates(r, include_overdamped, radius)
        n_cand = len(idx)
        carried = ([] if carried is None else carried) + [r.mode_shapes[idx]]
        carried = carried[-_N_CARRY:]
        if n_track is None:
            n_track = int(np.sum(r.damped_frequency[idx] <= max_frequency))
            if n_track == 0:
                raise ValueError("no modes below max_frequency at the first speed")
            chosen = idx[:n_track]
        else:
            cand = idx
            if len(cand) < n_track:
                raise ValueError(
                    f"only {len(cand)} modes below 1.5×max_frequency at "
                    f"{w * 30 / np.pi:.1f} rpm; raise max_frequency"
                )
            cost = 1.0 - mac(prev_phi, r.mode_shapes[cand])
            jump = np.abs(r.damped_frequency[cand][None, :] - prev_f[:, None])
            cost = cost + frequency_weight * jump / np.maximum(prev_f[:, None], 1e-9)
            rows, colsel = linear_sum_assignment(cost)
            chosen = cand[colsel[np.argsort(rows)]]
        prev_phi = r.mode_shapes[chosen]
        prev_f = r.damped_frequency[chosen]
        cols["f"].append(prev_f)
        cols["ld"].append(r.log_dec[chosen])
        cols["wh"].append(np.array(r.whirl, dtype=object)[chosen])
        cols["ty"].append(np.array(r.mode_type, dtype=object)[chosen])
        cols["od"].append(r.overdamped[chosen])
        cols["res"].append(res[chosen])
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


# the reduced basis: the undamped modes up to _UNDAMPED × 1.5 max_frequency and the tracked
# candidates' shapes at the last _N_CARRY speeds (two speeds span the first-order change of
# the shapes with speed, so the residual stays O(Δspeed²); measured on SPEC 6.1, 60 speeds to
# 12,000 rpm: 2 full solves instead of 9 with one speed carried)
_N_CARRY = 2
_UNDAMPED = 1.5
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
    MX, CX, KX = M @ X, (C + G) @ X, K @ X
    R = MX * lam**2 + CX * lam + KX
    a = np.abs(lam)
    den = (
        a**2 * np.linalg.norm(MX, axis=0)
        + a * np.linalg.norm(CX, axis=0)
        + np.linalg.norm(KX, axis=0)
    )
    return np.linalg.norm(R, axis=0) / np.maximum(den, 1e-300)


def _undamped_basis(asm: Assembly, speed: float, wmax: float) -> NDArray:
    """Undamped modes (n, r) of the symmetric part of K at ``speed`` with M, up to ``wmax``
    (rad/s): dense for models up to DENSE_LIMIT DOFs, else shift-invert Lanczos."""
    M, _, _, K = asm.matrices(speed)
    Ks = 0.5 * (K + K.T)
    n = asm.n_dof
    if n <= DENSE_LIMIT:
        _, V = la.eigh(Ks.toarray(), M.toarray(), subset_by_value=(-np.inf, wmax**2))
        return V
    k = 20
    while True:
        k = min(k, n - 2)
        w2, V = spla.eigsh(Ks.tocsc(), k=k, M=M.tocsc(), sigma=-1e-3 * wmax, which="LM")
        if w2.max() > wmax**2 or k >= n - 2:
            return V[:, w2 <= wmax**2]
        k *= 2


def _reduced_modes(
    asm: Assembly, speed: float, basis: NDArray, carried: NDArray, radius: float
) -> tuple[ModalResult, NDArray]:
    """Damped modes at ``speed`` within |λ| ≤ ``radius`` from the projection of the model on
    span(basis, Re carried, Im carried), classified as by :func:`modal`, and the relative
    residual of each returned mode on the full model (:func:`_residuals`)."""
    M, C, G, K = asm.matrices(speed)
    W = np.hstack([basis] + [x for c in carried for x in (c.real.T, c.imag.T)])
    Q, s, _ = la.svd(W, full_matrices=False, check_finite=False)
    Q = Q[:, s > _TRUNC * s[0]]
    Mr = Q.T @ (M @ Q)
    Cr = Q.T @ ((C + G) @ Q)
    Kr = Q.T @ (K @ Q)
    lam, Y = _solve_dense(Mr, Cr, Kr, asm)
    inside = np.abs(lam) <= radius
    lam, V = lam[inside], Q @ Y[:, inside]
    if not np.all(np.isfinite(lam)):
        raise SolverError("the reduced eigenproblem returned non-finite eigenvalues")
    w = float(speed)
    out = _classify(
        lam,
        V,
        asm,
        asm.shaft_speeds(w),
        K,
        rigid_tol=1e-2,
        overdamped_zeta=0.999,
        type_threshold=0.1,
        max_frequency=radius,
    )
    r = ModalResult(
        speed=w,
        shaft_speeds=asm.shaft_speeds(w),
        method="reduced",
        n_eigenvalues=len(lam),
        shaft_names=tuple(s.name for s in asm.train.shafts),
        assembly=asm,
        **out,
    )
    return r, _residuals(asm, w, r.eigenvalues, r.mode_shapes)


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
