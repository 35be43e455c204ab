"""Torsional interference diagram and separation margins (API 617 / API RP 684).

Basis: API 617 *Axial and Centrifugal Compressors and Expander-compressors*, 8th ed. (2014),
Part 1 (general requirements), torsional analysis clause of 4.8 "Dynamics", and API RP 684
*Tutorial on the API Standard Paragraphs Covering Rotor Dynamics*, 2nd ed. (2005), torsional
section: the torsional natural frequencies of the complete train shall be at least 10 % above
or 10 % below any possible excitation frequency within the specified operating speed range
(minimum to maximum continuous speed). The excitations the standard lists include 1x and 2x
of every shaft, the gear-mesh frequency, the electrical line frequency and twice it, and the
drive's own harmonics; a mode that fails the margin needs a forced-response stress analysis
(:func:`~gearrotor.analyses.torsional.torsional_response`) showing no harm. (The clause numbers
vary between editions; the criterion is the same.)

Excitation lines (frequency against the reference-shaft speed Ω):

* ``order``: ``multiple × |Ω_shaft|`` (1x, 2x of every shaft, user orders; the gear-mesh
  frequency is ``N_i × |Ω_i|`` of each mesh);
* ``electrical``: ``multiple × (poles/2) × |Ω_shaft|``: harmonics of the stator frequency of a
  variable-speed drive (a 6-pulse inverter's current harmonics 6k ± 1 of the fundamental beat
  into torque pulsations at 6k × f_e; give the multiples the drive vendor states);
* ``fixed``: a constant frequency (line frequency f_line and 2 f_line, measured frequencies).

Separation margin of a natural frequency f_n from a line f_e(Ω) over the operating range
[Ω_min, Ω_max]: the smallest ``|f_n − f_e(Ω)| / f_e(Ω)`` over the range (0 when the line
crosses the mode inside the range); the crossing passes when it is at least ``margin``.
Crossings below the minimum speed are passed through during start-up: they pass the margin but
are listed, as the start-up transient must show their stresses are acceptable. Order lines are
listed up to the top of the diagram; fixed lines for the modes below twice their frequency.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ...errors import ModelError
from ...model import SynchronousMotor, Train
from ...model.drives import InductionMotor
from ...threads import managed
from .model import TorsionalModel
from .modes import TorsionalModes, torsional_modes

__all__ = ["ExcitationLine", "InterferenceCrossing", "InterferenceResult", "interference"]

RPM = 30 / np.pi
BASIS = (
    "API 617 8th ed. (2014) Part 1, torsional analysis / API RP 684 2nd ed. (2005): torsional "
    "natural frequencies at least {margin:.0%} above or below any excitation frequency over the "
    "operating speed range"
)


@dataclass(frozen=True)
class ExcitationLine:
    """An excitation: ``kind`` "order" (multiple × shaft speed), "electrical" (multiple ×
    pole pairs × shaft speed) or "fixed" (``frequency`` rad/s)."""

    label: str
    kind: str
    shaft: int = -1
    multiple: float = 0.0
    frequency: float = 0.0

    def slope(self, speed_ratio: NDArray) -> float:
        """d f / d Ω_ref (rad/s per rad/s); 0 for a fixed line."""
        if self.kind == "fixed":
            return 0.0
        return abs(self.multiple * speed_ratio[self.shaft])

    def at(self, speeds: NDArray, speed_ratio: NDArray) -> NDArray:
        """Line frequency (rad/s) at reference-shaft speeds (rad/s)."""
        speeds = np.abs(np.asarray(speeds, float))
        if self.kind == "fixed":
            return np.full_like(speeds, self.frequency)
        return self.slope(speed_ratio) * speeds


@dataclass(frozen=True)
class InterferenceCrossing:
    mode: int  # index into the modes
    natural_frequency: float  # rad/s
    line: str
    speed: float | None  # reference-shaft speed (rad/s) where the line meets the mode
    margin: float  # separation margin over the operating range (fraction)
    passes: bool
    location: str  # "in range", "below range", "above range", "fixed"


@dataclass(frozen=True)
class InterferenceResult:
    modes: TorsionalModes = field(repr=False)
    lines: tuple[ExcitationLine, ...]
    speed_range: tuple[float, float]  # operating range of the reference shaft, rad/s
    diagram_speed: float  # top of the diagram, rad/s
    max_frequency: float  # highest natural frequency checked, rad/s
    required_margin: float
    crossings: tuple[InterferenceCrossing, ...]

    @property
    def passes(self) -> bool:
        return all(c.passes for c in self.crossings)

    @property
    def failures(self) -> tuple[InterferenceCrossing, ...]:
        return tuple(c for c in self.crossings if not c.passes)

    @property
    def range_label(self) -> str:
        """Label of the operating band: "operating speed N rpm" or "operating range A–B rpm"."""
        lo, hi = (s * RPM for s in self.speed_range)
        if abs(hi - lo) <= 1e-9 * hi:
            return f"operating speed {lo:.0f} rpm"
        return f"operating range {lo:.0f}–{hi:.0f} rpm"

    def line_frequency(self, line: ExcitationLine, speeds: NDArray) -> NDArray:
        return line.at(speeds, self.modes.model.speed_ratio)

    def to_dict(self) -> dict:
        names = self.modes.model.shaft_names
        return {
            "basis": BASIS.format(margin=self.required_margin),
            "required_margin": self.required_margin,
            "operating_range_rpm": [s * RPM for s in self.speed_range],
            "max_frequency_hz": self.max_frequency / (2 * np.pi),
            "passes": self.passes,
            "modes": [
                {"index": int(i), "frequency_hz": float(self.modes.frequency_hz[i])}
                for i in self.modes.elastic
                if self.modes.natural_frequency[i] <= self.max_frequency
            ],
            "lines": [
                {
                    "label": ln.label,
                    "kind": ln.kind,
                    "shaft": names[ln.shaft] if ln.shaft >= 0 else None,
                    "multiple": ln.multiple if ln.kind != "fixed" else None,
                    "frequency_hz": ln.frequency / (2 * np.pi) if ln.kind == "fixed" else None,
                }
                for ln in self.lines
            ],
            "crossings": [
                {
                    "mode": c.mode,
                    "frequency_hz": c.natural_frequency / (2 * np.pi),
                    "line": c.line,
                    "speed_rpm": None if c.speed is None else c.speed * RPM,
                    "margin": c.margin,
                    "passes": c.passes,
                    "location": c.location,
                }
                for c in self.crossings
            ],
        }

    def table(self) -> str:
        head = (
            f"{'mode':>4} {'freq Hz':>9} {'excitation':<28} {'speed rpm':>10} "
            f"{'margin':>8}  {'result':<6} where"
        )
        rows = [
            f"{self.range_label} (reference shaft), required separation {self.required_margin:.0%}",
            head,
            "-" * len(head),
        ]
        for c in self.crossings:
            sp = "-" if c.speed is None else f"{c.speed * RPM:.0f}"
            rows.append(
                f"{c.mode:>4} {c.natural_frequency / (2 * np.pi):>9.2f} {c.line:<28} {sp:>10} "
                f"{c.margin:>8.1%}  {'pass' if c.passes else 'FAIL':<6} {c.location}"
            )
        return "\n".join(rows)


def _electric_drives(train: Train):
    if train.torsional is None:
        return []
    return [d for d in train.torsional.drives if isinstance(d, InductionMotor | SynchronousMotor)]


def default_lines(
    tm: TorsionalModel,
    *,
    line_frequency: float | None = None,
    orders: Sequence[tuple[str, float]] = (),
    vfd_harmonics: Sequence[float] = (),
    vfd_drive: int = 0,
    fixed: Sequence[tuple[str, float]] = (),
    mesh_frequency: bool = True,
) -> tuple[ExcitationLine, ...]:
    """1x and 2x of every shaft of distinct speed, each mesh frequency, f_line and 2 f_line,
    user ``orders`` (shaft name, multiple), VFD harmonics (multiples of the stator frequency
    of electric drive ``vfd_drive`` of the model) and ``fixed`` lines (label, rad/s)."""
    train = tm.train
    names = tm.shaft_names
    lines: list[ExcitationLine] = []
    seen = set()
    for s, r in enumerate(tm.speed_ratio):
        key = round(abs(r), 9)
        if key in seen:
            continue
        seen.add(key)
        for m in (1.0, 2.0):
            lines.append(ExcitationLine(f"{m:g}x {names[s]}", "order", s, m))
    if mesh_frequency:
        for k, name in enumerate(tm.mesh_names):
            s, teeth = int(tm.mesh_shafts[k, 0]), int(tm.mesh_teeth[k, 0])
            lines.append(ExcitationLine(f"mesh {name} ({teeth}x {names[s]})", "order", s, teeth))
    for k, (shaft, m) in enumerate(orders):
        s = train.shaft_index(shaft, f"orders[{k}]")
        lines.append(ExcitationLine(f"{m:g}x {names[s]}", "order", s, float(m)))
    drives = _electric_drives(train)
    if line_frequency is None and drives:
        freqs = {round(d.line_frequency, 9) for d in drives}
        if len(freqs) > 1:
            raise ModelError(
                "the electric drives have different line frequencies",
                field="line_frequency",
                value=sorted(f / (2 * np.pi) for f in freqs),
                expected="one line frequency (give line_frequency)",
            )
        line_frequency = drives[0].line_frequency
    if line_frequency is not None:
        if line_frequency <= 0:
            raise ModelError(
                "line frequency must be positive", field="line_frequency", value=line_frequency
            )
        f = line_frequency
        lines.append(ExcitationLine(f"line {f / (2 * np.pi):g} Hz", "fixed", frequency=f))
        lines.append(
            ExcitationLine(f"2x line {2 * f / (2 * np.pi):g} Hz", "fixed", frequency=2 * f)
        )
    if vfd_harmonics:
        if not drives or vfd_drive >= len(drives):
            raise ModelError(
                "VFD harmonics need an electric drive in the model",
                field="vfd_drive",
                value=vfd_drive,
                expected=f"an index 0..{len(drives) - 1} of the electric drives"
                if drives
                else "an induction or synchronous motor in [torsional] drives",
            )
        d = drives[vfd_drive]
        s, _ = train.node_index(d, "vfd_drive")
        for h in vfd_harmonics:
            lines.append(
                ExcitationLine(
                    f"VFD {h:g} f_e ({d.name or names[s]})", "electrical", s, float(h) * d.poles / 2
                )
            )
    for label, f in fixed:
        lines.append(ExcitationLine(label, "fixed", frequency=float(f)))
    return tuple(lines)


@managed
def interference(
    model: Train | TorsionalModel | TorsionalModes,
    *,
    speed_range: tuple[float, float] | None = None,
    margin: float = 0.10,
    mesh: str = "flexible",
    line_frequency: float | None = None,
    orders: Sequence[tuple[str, float]] = (),
    vfd_harmonics: Sequence[float] = (),
    vfd_drive: int = 0,
    fixed: Sequence[tuple[str, float]] = (),
    diagram_speed: float | None = None,
    max_frequency: float | None = None,
) -> InterferenceResult:
    """Interference diagram and separation margins (module docstring).

    Parameters
    ----------
    model : a train, its torsional model or its torsional modes
    speed_range : (minimum, maximum continuous) speed of the reference shaft, rad/s (default:
        the model's nominal speed for both)
    margin : required separation (fraction; API: 0.10)
    line_frequency : rad/s (e.g. 2π·60); default: the electric drives' line frequency
    orders : extra (shaft name, multiple) lines; vfd_harmonics, vfd_drive : multiples of the
        stator frequency of the model's electric drive number ``vfd_drive``; fixed : extra
        (label, rad/s) lines
    diagram_speed : top of the diagram (rad/s, default 1.2 × maximum speed): order-line
        crossings up to it are listed
    max_frequency : rad/s, highest natural frequency checked (default: 1.25 × the highest
        excitation other than the mesh frequency at the top of the diagram). A shaft model's
        modes in the kHz range depend on its discretisation: to check the mesh frequency
        against them, refine the model and raise ``max_frequency``.
    """
    modes = model if isinstance(model, TorsionalModes) else torsional_modes(model, mesh=mesh)
    tm = modes.model
    if speed_range is None:
        speed_range = (abs(tm.train.speed), abs(tm.train.speed))
    lo, hi = (abs(float(s)) for s in speed_range)
    if not 0 < lo <= hi:
        raise ModelError(
            "the operating speed range needs 0 < minimum ≤ maximum",
            field="speed_range",
            value=f"{lo * RPM:.6g}-{hi * RPM:.6g} rpm",
            expected="e.g. (0.7, 1.05) × rated speed",
        )
    if not 0 <= margin < 1:
        raise ModelError(
            "separation margin must be a fraction in [0, 1)", field="margin", value=margin
        )
    top = 1.2 * hi if diagram_speed is None else float(diagram_speed)
    lines = default_lines(
        tm,
        line_frequency=line_frequency,
        orders=orders,
        vfd_harmonics=vfd_harmonics,
        vfd_drive=vfd_drive,
        fixed=fixed,
    )
    if max_frequency is None:
        tops = [
            ln.at(np.array([top]), tm.speed_ratio)[0]
            for ln in lines
            if not ln.label.startswith("mesh ")
        ]
        max_frequency = 1.25 * max(tops) if tops else np.inf
    out = []
    for i in modes.elastic:
        fn = float(modes.natural_frequency[i])
        if fn > max_frequency:
            continue
        for ln in lines:
            if ln.kind == "fixed":
                sm = abs(fn - ln.frequency) / ln.frequency
                if sm >= 1.0:  # above twice the line: far from it, not listed
                    continue
                out.append(
                    InterferenceCrossing(int(i), fn, ln.label, None, sm, sm >= margin, "fixed")
                )
                continue
            a = ln.slope(tm.speed_ratio)
            wc = fn / a
            if wc > top:
                continue
            if wc > hi:
                sm, where = wc / hi - 1.0, "above range"
            elif wc < lo:
                sm, where = 1.0 - wc / lo, "below range"
            else:
                sm, where = 0.0, "in range"
            out.append(InterferenceCrossing(int(i), fn, ln.label, wc, sm, sm >= margin, where))
    out.sort(key=lambda c: (c.passes, c.margin, c.natural_frequency))
    return InterferenceResult(
        modes=modes,
        lines=lines,
        speed_range=(lo, hi),
        diagram_speed=top,
        max_frequency=float(max_frequency),
        required_margin=float(margin),
        crossings=tuple(out),
    )
