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
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from ..assembly import Assembly, assemble
from ..model import Train
from .modal import ModalResult, modal

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
) -> CampbellResult:
    """Track damped modes over reference-shaft ``speeds`` (rad/s) up to ``max_frequency`` (rad/s).

    The number of tracked modes is the number of (not over-damped) modes below ``max_frequency``
    at the first speed; at later speeds they are matched among the modes up to 1.5× that
    frequency. ``frequency_weight`` scales the relative-frequency-jump penalty added to 1 − MAC.

    ``method="sparse"`` (default) finds, at each speed, only the eigenvalues within the circle
    of radius 1.5×max_frequency about a small negative shift by shift-invert Arnoldi: the same
    eigenpairs as the dense solver (to round-off) at a fraction of the cost, since a Campbell
    diagram needs only the low modes. ``method="dense"`` computes the full spectrum.
    """
    asm = model if isinstance(model, Assembly) else assemble(model)
    speeds = np.asarray(speeds, float)
    orders = default_orders(asm, extra_orders) if orders is None else orders
    results = []
    prev_phi = prev_f = None
    n_track = None
    cols: dict[str, list] = {k: [] for k in ("f", "ld", "wh", "ty", "od")}
    k_hint = None
    for w in speeds:
        r = modal(asm, speed=w, max_frequency=1.5 * max_frequency, method=method, sparse_k=k_hint)
        k_hint = r.n_eigenvalues + 8  # those inside 1.5×max_frequency, and a margin
        keep = np.ones(len(r), bool) if include_overdamped else ~r.overdamped
        idx = np.flatnonzero(keep)
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
    )
    return _with_crossings(res)


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
