"""Campbell diagram: damped modes over a speed range, tracked by MAC, with excitation orders and
the crossing speeds (SPEC 3.1).

Mode tracking: at each speed the modes are matched to those of the previous speed by maximising
the modal assurance criterion ``MAC = |φᵢᴴψⱼ|² / (|φᵢ|²|ψⱼ|²)`` over an optimal one-to-one
assignment (Hungarian algorithm), with a small penalty on the frequency jump, so that a mode keeps
its identity through crossings and veerings with other modes. A track may also end: a heavily
damped mode becomes over-damped (a real pair) as the bearings' damping grows with speed, and
then no damped mode continues it. Matching it to whatever mode is left would shift the other
tracks down the list one after another (the steam turbine's 10,000 cpm bearing mode, log dec
27 at 12,100 rpm and a real pair at 12,320 rpm, had its track jump to 66,000 cpm, which
jumped to 315,000 cpm, which jumped off the top of the diagram). The assignment therefore
offers every track the option of no mode at that speed at the cost ``END_COST``; the track
is NaN there (frequency, log dec; whirl and type ``-``, counted as over-damped) and continues
if its mode returns.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from ...assembly import Assembly, assemble
from ...errors import ModelError
from ...model import Train
from ...progress import Progress, part, report
from ...threads import managed
from .modal import (
    SPARSE_FRACTION,
    TYPE_THRESHOLD,
    ModalResult,
    _classify,
    _relative_residual,
    modal,
)
from .modal import _residuals as _residuals_of
from .whirl import frequency_dependent
from .whirl import residuals as whirl_residuals

__all__ = [
    "CampbellResult",
    "ExcitationOrder",
    "Crossing",
    "campbell",
    "default_orders",
    "mac",
    "END_COST",
]

#: Cost of leaving a track without a mode at a speed. A continuation costs 1 − MAC plus the
#: frequency penalty; a mode of orthogonal shape at the same frequency costs 1. A candidate
#: costing more is another mode, and the track ends instead (module docstring).
END_COST = 1.0


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
    """Tracked modes over speed: arrays (n_speeds, n_modes); where a track has no mode (its
    mode became over-damped, module docstring) its frequency and log dec are NaN, its whirl
    and type ``-`` and ``overdamped`` True."""

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
    # (n_speeds, n_modes, 3): the lateral, axial and torsional kinetic-energy fractions of each
    # tracked mode (ModalResult.energy_fractions; NaN where a track has no mode): the stability
    # criteria judge a mode by its lateral share (analyses.stability.criterion_class)
    energy_fractions: NDArray | None = field(repr=False, default=None)

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
                    # None where the track has no mode (END_COST)
                    "frequency_rpm": _json_list(self.damped_frequency[:, j] * rpm),
                    "log_dec": _json_list(self.log_dec[:, j]),
                    "whirl": self.whirl[:, j].tolist(),
                    "type": self.mode_type[:, j].tolist(),
                    **(
                        {"energy_lateral": _json_list(self.energy_fractions[:, j, 0])}
                        if self.energy_fractions is not None
                        else {}
                    ),
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


def _json_list(x: NDArray) -> list:
    return [float(v) if np.isfinite(v) else None for v in x]


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


@managed
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
    method: str = "auto",
    operating_point=None,
    reduced: bool = True,
    residual_tol: float = 3e-4,
    progress: Progress | None = None,
) -> CampbellResult:
    """Track damped modes over reference-shaft ``speeds`` (rad/s) up to ``max_frequency`` (rad/s).

    The number of tracked modes is the number of (not over-damped) modes below ``max_frequency``
    at the first speed; at later speeds they are matched among the modes with |λ| up to 1.5×
    that frequency. ``frequency_weight`` scales the relative-frequency-jump penalty added to
    1 − MAC.

    ``reduced=True`` (default) solves the first speed on the full model and every later one by a
    two-sided Rayleigh–Ritz step (:class:`_Subspace`): trial space the real and imaginary parts
    of the tracked modes' right eigenvectors and of their first derivatives in speed at the last
    speed solved on the full model, test space those of their left eigenvectors and derivatives
    (:func:`_speed_vectors`: one sparse LU per mode at the full solve). Each candidate Ritz pair
    is checked on the full model by its relative residual ``‖P(λ)φ‖ / (|λ|²‖Mφ‖ + |λ|‖(C+G)φ‖ +
    ‖Kφ‖)``, ``P(λ) = λ²M + λ(C+G) + K``, and only those within ``residual_tol`` may continue a
    track (the same MAC assignment as for the full solve; a spurious Ritz pair in a multiple
    mode's subspace can resemble one of its copies); when fewer remain than there are tracks, or
    a track finds no continuation, that speed is solved on the full model instead and its
    vectors replace the subspaces. The residual is second order in the speed change (the
    derivatives), and with the left eigenvectors in the test space a Ritz value's error is
    second order in the residual (with the right ones alone it was first order where fluid-film
    cross-coupling makes the model far from symmetric: the steam turbine's log decs erred 0.024
    × the residual). The default tolerance 3e-4 keeps the frequencies and log decrements within
    1e-6 (relative) of the full solve (tests/perf; measured within 1.5e-8 and 8e-8 on the three
    example machines with 1–3 full solves). The reduced speeds' ``modal_results`` hold the
    tracked modes only; the residuals and the solver used at each speed are in the result
    (``residual``, ``solver``, ``full_solves``). Cost per reduced speed: the eigenvalues of a
    dense first-order problem of twice the subspace's dimension (LAPACK geev without vectors,
    100 states for the flagship's 13 tracked modes), the vectors of the candidates by one
    batched inverse-iteration step (:meth:`_Subspace.ritz_vectors`) and O(n·m) work; subspaces
    beyond half the model's DOFs are not used (every speed is then solved on the full model).
    The first sparse solve asks for as many eigenvalues as the circle is expected to hold
    (:func:`_expected_count`).

    With speed × whirl tables (:mod:`gearrotor.analyses.lateral.whirl`) every speed is one
    eigensolve of the model with the tables' states and ``reduced`` does not apply; the
    residual is that of the nonlinear problem with the fitted impedances.

    ``method`` is the full solver: ``"sparse"`` finds only the eigenvalues within the circle of
    radius 1.5×max_frequency about a small negative shift by shift-invert Arnoldi, ``"dense"``
    computes the full spectrum (see :func:`~gearrotor.analyses.lateral.modal.modal`); ``"auto"``
    (default) solves sparsely from 200 DOFs (the measured crossover when only the circle's
    modes are wanted; the flagship's 252 DOFs: 0.05 s against 0.11 s dense), densely below,
    and switches to dense when a full solve finds more than ``SPARSE_FRACTION`` of the 2n
    eigenvalues inside the circle (then the Arnoldi iteration costs as much as the dense
    solve: 70 modes of the 222-DOF motor–gearbox–compressor train to 80,000 cpm took 0.25 s
    sparse, 0.05 s dense).

    ``operating_point`` (name or :class:`~gearrotor.model.OperatingPoint`): fluid-film bearings
    at the coefficients of the point's static loads at every speed, the point's ``hold``
    (power or torque) kept over the sweep (:func:`~gearrotor.analyses.static.at_operating_point`).

    ``progress``: a :data:`gearrotor.progress.Progress` callback (the speeds; with an operating
    point first its static solves).
    """
    sweep = progress
    if operating_point is not None:
        # fluid-film bearings at the point's static loads at every speed (issue 11)
        from ..static.operating_point import model_at_operating_point

        at = part(progress, 0.0, 0.5, "operating point")
        model = model_at_operating_point(model, operating_point, np.asarray(speeds, float), at)[0]
        sweep = part(progress, 0.5, 1.0)
    asm = model if isinstance(model, Assembly) else assemble(model)
    speeds = np.asarray(speeds, float)
    orders = default_orders(asm, extra_orders) if orders is None else orders
    results = []
    prev_phi = prev_f = None
    n_track = None
    cols: dict[str, list] = {k: [] for k in ("f", "ld", "wh", "ty", "od", "res", "ef")}
    solver: list[str] = []
    k_hint = None
    radius = 1.5 * max_frequency
    # speed × whirl tables: every speed is one eigensolve of the model with the tables'
    # states (analyses/whirl.py); the reduced basis is for the quadratic problem
    whirl_tables = frequency_dependent(asm)
    space = _Subspace(asm) if reduced and not whirl_tables else None
    full_method = method
    if method == "auto":  # only the circle's modes are wanted: the measured crossover applies
        full_method = "sparse" if asm.n_dof >= _SPARSE_FROM else "dense"

    def assign(cand_phi: NDArray, cand_f: NDArray) -> NDArray:
        """Indices into the candidates of the modes that continue the tracked ones, -1 for a
        track that no candidate continues (``END_COST``)."""
        cost = 1.0 - mac(prev_phi, cand_phi)
        jump = np.abs(cand_f[None, :] - prev_f[:, None])
        cost = cost + frequency_weight * jump / np.maximum(prev_f[:, None], 1e-9)
        from scipy.optimize import linear_sum_assignment  # scipy.optimize: on use

        n, m = cost.shape
        rows, colsel = linear_sum_assignment(np.hstack([cost, np.full((n, n), END_COST)]))
        colsel = colsel[np.argsort(rows)]
        return np.where(colsel < m, colsel, -1)

    for i, w in enumerate(speeds):
        report(sweep, i / len(speeds), f"speed {i + 1}/{len(speeds)}")
        r = None
        if space is not None and space.ready:
            out = space.tracked_modes(w, radius, n_track, include_overdamped, assign, residual_tol)
            if out is not None and np.max(out[2]) <= residual_tol:
                r, chosen, res = out
                solver.append("reduced")
        if r is None:
            if k_hint is None and full_method == "sparse":
                k_hint = _expected_count(asm, w, radius)
            r = modal(asm, speed=w, max_frequency=radius, method=full_method, sparse_k=k_hint)
            k_hint = r.n_eigenvalues + 8  # those inside 1.5×max_frequency, and a margin
            if method == "auto":
                many = r.n_eigenvalues > SPARSE_FRACTION * 2 * asm.n_dof
                full_method = "dense" if many else "sparse"
            idx = _candidates(r, include_overdamped, radius)
            if n_track is None:
                n_track = int(np.sum(r.damped_frequency[idx] <= max_frequency))
                if n_track == 0:
                    raise ModelError(
                        "no modes below max_frequency at the first speed",
                        field="max_frequency",
                        value=f"{max_frequency * 30 / np.pi:.6g} rpm",
                        expected="a higher max_frequency",
                    )
                chosen = idx[:n_track]
            else:
                a = assign(r.mode_shapes[idx], r.damped_frequency[idx])
                chosen = np.where(a >= 0, idx[np.maximum(a, 0)], -1)
            on = chosen >= 0
            res = np.zeros(n_track)
            # speed × whirl tables: the residual of the nonlinear problem (analyses/whirl.py)
            of = whirl_residuals if whirl_tables else _residuals
            res[on] = of(asm, w, r.eigenvalues[chosen[on]], r.mode_shapes[chosen[on]])
            solver.append("full")
            if space is not None and space.fits(2 * int(on.sum())):
                lam_c = r.eigenvalues[chosen[on]]
                space.add(*_speed_vectors(asm, w, lam_c, r.mode_shapes[chosen[on]]))
        on = chosen >= 0
        c = chosen[on]
        if prev_phi is None:
            prev_phi, prev_f = r.mode_shapes[c], r.damped_frequency[c]
        else:  # an ended track keeps its last mode, to continue where that mode returns
            prev_phi, prev_f = prev_phi.copy(), prev_f.copy()
            prev_phi[on], prev_f[on] = r.mode_shapes[c], r.damped_frequency[c]
        for key, values, empty in (
            ("f", r.damped_frequency, np.nan),
            ("ld", r.log_dec, np.nan),
            ("wh", np.array(r.whirl, dtype=object), "-"),
            ("ty", np.array(r.mode_type, dtype=object), "-"),
            ("od", r.overdamped, True),
        ):
            col = np.full(n_track, empty, dtype=np.asarray(values).dtype)
            col[on] = values[c]
            cols[key].append(col)
        cols["res"].append(res)
        ef = np.full((n_track, 3), np.nan)
        ef[on] = r.energy_fractions[c]
        cols["ef"].append(ef)
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
        energy_fractions=np.array(cols["ef"]),
    )
    report(progress, 1.0)
    return _with_crossings(res)


_N_KEEP = 1  # full-solve speeds whose vectors span the subspaces
_TRUNC = 1e-10
# DOFs from which a full solve of the circle's modes is sparse: the measured dense/sparse
# crossover (~200 DOFs, docs/performance.md); modal()'s "auto" waits until 400 because its
# dense result lists every eigenvalue, which a Campbell diagram does not use
_SPARSE_FROM = 200


def _candidates(r: ModalResult, include_overdamped: bool, radius: float) -> NDArray:
    """The modes that may be tracked: |λ| ≤ ``radius`` (what the sparse solver encloses, so
    that every solver offers the same set), over-damped ones only when asked; not the modes of
    a speed × whirl table's fitted states (their number follows the fit's order, which differs
    between the table's rows: they have no identity over speed)."""
    keep = np.ones(len(r), bool) if include_overdamped else ~r.overdamped
    if r.state_mode is not None:
        keep &= ~r.state_mode
    return np.flatnonzero(keep & (np.abs(r.eigenvalues) <= radius))


def _expected_count(asm: Assembly, speed: float, radius: float) -> int | None:
    """How many eigenvalues the sparse solver should first ask for to enclose |λ| ≤ ``radius``:
    twice the number of undamped modes below it (Sylvester's inertia: the negative pivots of a
    symmetric LDLᵀ of Kₛ − radius²M, Kₛ the symmetric part of K; SuperLU without row pivoting,
    ~0.4 ms for the flagship) and 8 more, as after a full solve. The damping moves eigenvalues
    across the circle, so this is a first guess: the solver asks for more if it falls short.
    Measured: 52 of the flagship's 52 eigenvalues within 1.5 × 80,000 cpm, 62 for the steam
    turbine's 60; without it the first ARPACK run asked for 20, then for enough (two runs, a
    quarter of the first speed's solve). None when the factorisation fails."""
    try:
        M, _, _, K = asm.matrices(speed)
    except ModelError:  # e.g. a speed outside a bearing table: the full solve says so
        return None
    A = sp.csc_array((K + K.T) * 0.5 - (radius * radius) * M)
    try:
        lu = spla.splu(
            A,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError:  # a zero pivot: no estimate
        return None
    d = lu.U.diagonal()
    if not np.all(np.isfinite(d)):
        return None
    return 2 * int(np.sum(d < 0)) + 8


def _residuals(asm: Assembly, speed: float, lam: NDArray, phi: NDArray) -> NDArray:
    """Relative residual of each eigenpair (λ_j, φ_j = phi[j]) on the full model at ``speed``:
    ‖P(λ)φ‖ / (|λ|²‖Mφ‖ + |λ|‖(C+G)φ‖ + ‖Kφ‖), P(λ) = λ²M + λ(C+G) + K."""
    if not len(lam):
        return np.zeros(0)
    M, C, G, K = asm.matrices(speed)
    return _residuals_of(M, C + G, K, lam, phi.T)


def _speed_vectors(
    asm: Assembly, speed: float, lam: NDArray, phi: NDArray
) -> tuple[NDArray, NDArray]:
    """For the eigenpairs (λ_j, φ_j = phi[j]) at ``speed``: the trial vectors [φ_j, ∂φ_j/∂Ω]
    and the test vectors [y_j, ∂y_j/∂Ω] (rows), y_j the left eigenvector (y_jᴴP(λ_j) = 0).

    One sparse LU of P(λ_j) per mode, just off the eigenvalue (P(λ_j) is singular), serves
    all three solves: y_j by one inverse-iteration step from a fixed generic vector (the step
    amplifies the null direction by ~1/round-off; the k copies of a k-fold eigenvalue get
    different start vectors and span its left eigenspace), and the first-order changes with
    the speed Ω from P(λ)∂φ = −(∂λ P'(λ) + ∂P/∂Ω)φ, P'(λ) = 2λM + C + G, ∂P/∂Ω = λ Σ r_s G_s
    + Σ r_s Kc_s (r_s the shafts' speed ratios; with bearings whose coefficients change with
    speed, their one-sided difference over 1e-4 of the speed), the right-hand side made
    orthogonal to the left eigenvectors of λ_j's cluster (|λ_k − λ_j| ≤ 1e-6|λ_j|) so that the
    near-singular solve does not amplify it; its component along the cluster's shapes is
    arbitrary and
    already in the subspace. ``_Subspace`` spans both, so a Ritz step from one full solve is
    accurate to second order in the speed change."""
    M, C, G, K = asm.matrices(speed)
    CG = C + G
    ratio = asm.shaft_speeds(1.0)
    zero = sp.csr_array(M.shape)
    dG = sum((r * g for r, g in zip(ratio, asm.G_shaft, strict=True) if g.nnz), zero)
    dK = sum((r * k for r, k in zip(ratio, asm.Kc_shaft, strict=True) if k.nnz), zero)
    if asm.speed_dependent:  # bearing coefficients: a one-sided difference inside the table
        h = 1e-4 * max(abs(float(speed)), 1.0)
        for step in (h, -h):
            try:
                _, C1, _, K1 = asm.matrices(speed + step)
            except ModelError:
                continue
            dG = dG + (C1 - C) / step
            dK = dK + (K1 - K - asm.circulatory(asm.shaft_speeds(step))) / step
            break
    rng = np.random.default_rng(20261126)
    n, m = asm.n_dof, len(lam)
    lus, left = [], np.empty((m, n), complex)
    for j, x in enumerate(lam):
        x = x + 1e-9 * abs(x) * (1 + 1j)  # off the eigenvalue: P(λ) exactly singular
        P = sp.csc_array((x * x) * M + x * CG + K)
        try:
            lu = spla.splu(P)
        except RuntimeError:  # exactly singular: the eigenvalue is exact to round-off
            lu = spla.splu(sp.csc_array(P + 1e-12 * abs(x) ** 2 * M))
        b = rng.standard_normal(n) + 1j * rng.standard_normal(n)
        y = lu.solve(b, trans="H")
        left[j] = y / np.linalg.norm(y)
        lus.append(lu)
    X = phi.T
    dright, dleft = np.empty((m, n), complex), np.empty((m, n), complex)
    for j, x in enumerate(lam):
        c = np.flatnonzero(np.abs(lam - x) <= 1e-6 * abs(x))
        Pd = 2 * x * M + CG  # P'(λ)
        D = x * dG + dK  # ∂P/∂Ω
        Phc, Yc = X[:, c], left[c].T
        B = Pd @ Phc
        rhs = -(D @ X[:, j])
        rhs -= B @ np.linalg.lstsq(Yc.conj().T @ B, Yc.conj().T @ rhs, rcond=None)[0]
        v = lus[j].solve(rhs)
        dright[j] = v / max(np.linalg.norm(v), 1e-300)
        Bl = Pd.conj().T @ Yc
        rhs = -(D.conj().T @ left[j])
        rhs -= Bl @ np.linalg.lstsq(Phc.conj().T @ Bl, Phc.conj().T @ rhs, rcond=None)[0]
        v = lus[j].solve(rhs, trans="H")
        dleft[j] = v / max(np.linalg.norm(v), 1e-300)
    return np.vstack([phi, dright]), np.vstack([left, dleft])


def _real_span(sets: list[NDArray]) -> NDArray:
    """Orthonormal basis (n, m) of the real and imaginary parts of the rows of ``sets``."""
    Z = np.vstack(sets).T
    Q, s, _ = la.svd(np.hstack([Z.real, Z.imag]), full_matrices=False, check_finite=False)
    return Q[:, s > _TRUNC * s[0]]


class _Subspace:
    """Trial and test subspaces for a two-sided Rayleigh–Ritz step: the real span of the
    tracked modes' right eigenvectors and their speed derivatives (real and imaginary parts)
    at the last speed solved on the full model, and that of their left eigenvectors and
    theirs. With the left eigenvectors in the test space a Ritz value's error is second order
    in the residual also where the model is far from symmetric (fluid-film cross-coupling;
    with the right vectors alone the steam turbine's log decs erred 0.024 × the residual,
    first order). The model's speed-independent matrices and per-shaft gyroscopic and
    circulatory matrices are applied to the subspaces once; at a speed the reduced matrices
    are sums of m×m blocks (the bearings whose coefficients change with speed are applied
    again)."""

    def __init__(self, asm: Assembly):
        self.asm = asm
        # K changes with speed: bearing coefficients, rotating material damping (kept: the
        # Assembly works them out on every call)
        self.bearings_vary = asm.speed_dependent
        self.varies = self.bearings_vary or asm.rotating_damping
        self.sets: list[tuple[NDArray, NDArray]] = []
        self.ready = False

    def fits(self, n_modes: int) -> bool:
        """Whether one speed's real and imaginary parts of ``n_modes`` shapes fit in half the
        model's DOFs: beyond that the reduced eigenproblem (twice the subspace's dimension)
        costs as much as the full dense one (e.g. 70 tracked modes of a 222-DOF model: every
        speed is solved on the full model)."""
        return 2 * n_modes <= self.asm.n_dof // 2

    def add(self, phi: NDArray, left: NDArray) -> None:
        # the latest sets that fit together (see fits)
        sets = [*self.sets, (phi, left)][-_N_KEEP:]
        while sets and not self.fits(sum(len(x) for x, _ in sets)):
            sets = sets[1:]
        self.sets = sets
        self.ready = False
        if not sets:
            return
        Q = _real_span([x for x, _ in sets])
        W = _real_span([y for _, y in sets])
        # equal dimensions: a shape that does not change with speed (an axial or torsional
        # mode) appears once in Q, while its left vectors from inverse iteration differ by
        # round-off and stay two directions of W; the leading singular directions are kept
        m = min(Q.shape[1], W.shape[1])
        Q, W = Q[:, :m], W[:, :m]
        asm = self.asm
        self.Q, self.W = Q, W
        self.MQ = asm.M @ Q
        self.C0Q = asm.C0 @ Q
        self.K0Q = asm.K0 @ Q
        self.GQ = [g @ Q if g.nnz else None for g in asm.G_shaft]
        self.KcQ = [k @ Q if k.nnz else None for k in asm.Kc_shaft]
        Mr = W.T @ self.MQ
        # the test space must see the mass on the trial space (a well-conditioned Mr)
        sv = np.linalg.svd(Mr, compute_uv=False)
        if not sv[-1] > 1e-8 * sv[0]:
            return
        # the reductions Mr⁻¹Wᵀ A Q, formed once: a speed's first-order matrix is then sums of
        # them (no solve with Mr per speed)
        self.WT = WT = la.lu_solve(la.lu_factor(Mr, check_finite=False), W.T, check_finite=False)
        self.C0r, self.K0r = WT @ self.C0Q, WT @ self.K0Q
        self.Gr = [None if g is None else WT @ g for g in self.GQ]
        self.Kcr = [None if k is None else WT @ k for k in self.KcQ]
        # the fixed start vectors of ritz_vectors' inverse-iteration step
        rng = np.random.default_rng(20261128)
        self.start = rng.standard_normal((m, m)) + 1j * rng.standard_normal((m, m))
        self.ready = True

    def applied(self, speed: float):
        """(C+G)Q, KQ (n, m) and their reductions Mr⁻¹Wᵀ(C+G)Q, Mr⁻¹WᵀKQ (m, m) at ``speed``
        (Mr = WᵀMQ), and K (sparse) when it changes with speed."""
        asm = self.asm
        speeds = asm.shaft_speeds(speed)
        CQ, KQ = self.C0Q.copy(), self.K0Q.copy()
        Cr, Kr = self.C0r.copy(), self.K0r.copy()
        for s, gq, kq, gr, kr in zip(speeds, self.GQ, self.KcQ, self.Gr, self.Kcr, strict=True):
            if s != 0.0:
                if gq is not None:
                    CQ += s * gq
                    Cr += s * gr
                if kq is not None:
                    KQ += s * kq
                    Kr += s * kr
        K = None
        if self.varies:
            _, C, _, K = asm.matrices(speed)
        if self.bearings_vary:  # the bearings' speed-dependent parts
            dCQ = (C - asm.C0) @ self.Q
            KQ = K @ self.Q
            CQ += dCQ
            Cr += self.WT @ dCQ
            Kr = self.WT @ KQ
        return CQ, KQ, Cr, Kr, K

    def geev(self, n: int):
        """LAPACK's real geev (eigenvalues only) and its workspace size for order ``n`` (kept
        per order)."""
        got = getattr(self, "_geev", None)
        if got is None or got[0] != n:
            geev, geev_lwork = la.get_lapack_funcs(("geev", "geev_lwork"), (np.zeros(1),))
            lwork = la.lapack._compute_lwork(geev_lwork, n, compute_vl=0, compute_vr=0)
            self._geev = got = (n, geev, lwork)
        return got[1], got[2]

    def ritz_vectors(self, lam: NDArray, Kt: NDArray, Ct: NDArray) -> NDArray | None:
        """(m, k) reduced vectors z_j of the Ritz values λ_j: (λ_j² I + λ_j C̃ + K̃) z_j = 0
        with C̃ = Mr⁻¹Cr, K̃ = Mr⁻¹Kr (the pencil whose first-order form geev solved), by one
        step of inverse iteration at λ_j from a fixed generic vector, its own for each λ_j (the
        copies of a multiple Ritz value then span its eigenspace), all k in one batched LU.
        λ_j is an eigenvalue to round-off, so the step amplifies its eigen-direction by
        ~1/round-off against 1/gap for the others: the vector is as accurate as geev's own
        (geev computed all 2m vectors, 40 % of its time, for the ~13 of 100 wanted). None if
        the solve fails."""
        m, k = len(Kt), len(lam)
        d = np.arange(m)
        N = np.multiply.outer(lam, Ct)
        N += Kt
        N[:, d, d] += (lam * lam)[:, None]
        start = self.start[:k, :, None]  # k ≤ m: the Ritz values with Im λ > 0
        for _ in range(2):
            try:
                z = np.linalg.solve(N, start)[..., 0]
            except np.linalg.LinAlgError:  # an exactly zero pivot: off λ_j by round-off
                N[:, d, d] += 1e-13 * np.abs(lam)[:, None] ** 2
                continue
            return z.T if np.isfinite(z).all() else None
        return None

    def tracked_modes(
        self, speed, radius, n_track, include_overdamped, assign, residual_tol=np.inf
    ):
        """(result holding the tracked modes, their indices in it, their relative residuals on
        the full model) at ``speed``, or None when the projection offers fewer Ritz pairs than
        tracked modes whose residual is within ``residual_tol`` (the caller then solves the
        full model)."""
        asm, Q = self.asm, self.Q
        CQ, KQ, Ct, Kt, K = self.applied(speed)
        m = Q.shape[1]
        A = np.zeros((2 * m, 2 * m))
        A[:m, m:] = np.eye(m)
        A[m:, :m] = -Kt
        A[m:, m:] = -Ct
        if not np.isfinite(A).all():
            return None
        # LAPACK geev as la.eig calls it, eigenvalues only; the vectors of the candidates by
        # inverse iteration (ritz_vectors)
        geev, lwork = self.geev(2 * m)
        wr, wi, _, _, info = geev(A, lwork=lwork, compute_vl=0, compute_vr=0, overwrite_a=1)
        if info != 0:
            return None
        lam = wr + 1j * wi
        sel = (lam.imag > 0) & (np.abs(lam) <= radius)
        if not include_overdamped:  # as _candidates: ζ < 0.999 (spurious near-real Ritz pairs)
            sel &= -lam.real < 0.999 * np.abs(lam)
        sel = np.flatnonzero(sel)
        if len(sel) < n_track:
            return None
        lam = lam[sel]
        Y = self.ritz_vectors(lam, Kt, Ct)
        if Y is None:
            return None
        # a Ritz pair whose residual fails the check continues no track (a spurious pair in a
        # multiple mode's subspace may look like one of its copies)
        k = len(lam)
        YY = np.hstack([Y.real, Y.imag])  # real products (a real matrix times complex Y)

        def times(A: NDArray) -> NDArray:
            P = A @ YY
            return P[:, :k] + 1j * P[:, k:]

        res = _relative_residual(lam, times(self.MQ), times(CQ), times(KQ))
        ok = np.flatnonzero(res <= residual_tol)
        if len(ok) < n_track:
            return None
        X = times(Q)[:, ok]  # the Ritz vectors on the full model
        lam, res = lam[ok], res[ok]
        pick = assign(X.T, lam.imag)
        if np.any(pick < 0):  # a track ends here: the full solve decides
            return None
        lam, X, res = lam[pick], X[:, pick], res[pick]
        order = np.argsort(lam.imag, kind="stable")
        w = float(speed)
        out = _classify(
            lam[order],
            X[:, order],
            asm,
            asm.shaft_speeds(w),
            asm.K0 if K is None else K,
            rigid_tol=1e-2,
            overdamped_zeta=0.999,
            # the full solves' (modal's default): one type per mode at every speed
            type_threshold=TYPE_THRESHOLD,
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
