"""Option objects of the transient (SPEC 2.6): the integrator (:class:`RK4`, :class:`ModalRK4`),
what to record (:class:`Save`) and checkpointing (:class:`Checkpoint`), and the excitation
frequency their defaults derive from.

Contract of an integrator option object: it is frozen data; :func:`~.driver.transient` prepares
the compiled kernel's arrays from it once (:mod:`.prepare`), then advances the state in chunks
(progress, checkpoints) with a fixed step ``dt``. Work is counted: ``steps`` and
``rhs_evaluations`` (4 per RK4 step) are reported in :class:`~.results.SolverStats`.

* :class:`RK4` — classical fixed-step 4th-order Runge–Kutta on the first-order state
  (q, q̇) of the full (active-DOF) model: the reference. Explicit, so every eigenvalue λ of the
  model linearised at the nominal speeds must satisfy ``|R(λ Δt)| ≤ 1``,
  ``R(z) = 1 + z + z²/2 + z³/6 + z⁴/24`` (``ω Δt ≤ 2√2`` for an undamped mode,
  ``|λ| Δt ≤ 2.785`` for an overdamped one: heavily damped journals of tilting-pad bearings
  can set the limit); this is checked before the run and a step that violates it raises
  :class:`~gearrotor.errors.SolverError` with the largest stable step
  (:func:`~.step_limits.rk4_max_step`).
* :class:`ModalRK4` — the same RK4 on a modal reduction (:mod:`.reduction`): the undamped modes
  of the constant-speed linear model (meshes at Kg, bearings at the nominal speeds) up to a
  cut-off frequency, always including the rigid-body rotation, so θz stays the absolute angle.
  Damping, gyroscopics (Σ Ω_s(t) Φᵀ G_s Φ), the angular-acceleration and unbalance θ̈ terms
  (exact Woodbury solve with M_r = I) and every nonlinear force (mesh minus its Kg part,
  unbalance, torques, speed-dependent bearings) are evaluated through the rows Φ_sel of the DOFs
  they act on. The modes are those of the symmetric part of K; its skew part (cross-coupled
  bearings, seals) acts through the rows of its DOFs too. Dropping the modes above the cut-off
  removes the stiff shear/axial modes, so the step is set by accuracy, not by stability (the
  same stability check applies to the reduced system). With backlash (or
  ``exact_linear=True``) the modal oscillators are integrated exactly instead (exponential
  RK4, one linear operator per contact state, contact changes located within the step:
  :func:`~.kernels.etd_modal`), and the step resolves the excitation, not the highest mode.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .equations import TransientSystem

__all__ = ["RK4", "ModalRK4", "Save", "Checkpoint", "excitation_frequency"]


@dataclass(frozen=True)
class RK4:
    """Classical RK4 on the full active-DOF model. dt : s (at most :func:`rk4_max_step`).
    ``check_stability`` checks the eigenvalues of the linearised model against RK4's
    stability region before the run (raises SolverError when a step is outside)."""

    dt: float
    check_stability: bool = True
    name: str = field(default="rk4", init=False)


@dataclass(frozen=True)
class ModalRK4:
    """RK4 on the modal reduction of the linear part.

    dt : s (default: ``accuracy / ω_k``, ω_k the highest kept mode, or 0.95× the reduced
    system's stability limit when its damped eigenvalues set a smaller one); cutoff : Hz, keep
    the undamped modes up to this frequency (default: ``cutoff_factor`` × the highest excitation
    frequency, which is the highest mesh frequency |N Ω| or, without meshes, 10× the highest
    shaft speed); accuracy : ω_k·dt of the default step; separated_modes : also include the
    modes of the train with the meshes removed (each shaft free, with its rigid rotation) up to
    the cut-off, re-diagonalised with the rest (Ritz) on the engaged model: ``True`` all of
    them, ``"torsional"`` those with more than half their kinetic energy in torsion, ``False``
    none. Default: ``"torsional"`` when a mesh has backlash (they carry the speeds while the
    teeth are apart: the speed fluctuation of SPEC 6.1 with 0.0254 mm backlash within 0.2 % of
    RK4, 4.7 % off without them), else ``False``. The lateral free-shaft modes, made
    M-orthogonal to the kept modes, consist of the engaged modes above the cut-off: with them
    (``True``, the default until issue 16) the highest Ritz frequency was 18.5 kHz for SPEC 6.1
    and the default step 7.7e-6 s; with the torsional ones and the static shape it is 15.5 kHz
    and 9.3e-6 s, and more accurate (tests/perf, docs/performance.md); static_correction : add
    the static deflection shapes under each mesh's normal force and each external torque (the
    modes alone miss much of the mesh compliance, ~20 % for SPEC 6.1, so a transmitted torque
    would load the mesh wrongly); this raises the highest Ritz frequency (≈ 9 kHz for SPEC 6.1:
    the gears vibrating on the mesh spring) and so shortens the default step. Default: when the
    model has external torques or a mesh has backlash (teeth separation removes the mesh force,
    a rank-one change of the stiffness along the mesh's line w, whose quasi-static response is
    that shape); tolerance : without
    an explicit ``cutoff``, the cut-off is raised (×1.25 at a time) until the reduced model's
    linear 1x unbalance response at the recorded lateral DOFs is within ``tolerance``
    (relative to its largest amplitude) of the full model's; the achieved value is reported
    as ``stats.harmonic_error``.

    exact_linear : integrate the modal oscillators exactly (exponential RK4, ETDRK4 of Cox &
    Matthews 2002: the rest of the equations, damping, gyroscopics, mesh-stiffness variation,
    unbalance, torques, through the φ-functions, exact for a constant forcing) instead of
    classical RK4, with one linear operator per combination of the meshes' contact states
    (diag Λ with the mesh stiffness Kg w wᵀ removed while the teeth are apart) and the contact
    changes located within the step (cubic Hermite interpolation of the gap functions; the
    step is redone up to the crossing and continued with the new state's operator). The step
    then resolves the excitation, not the highest kept mode: default 4 steps per period of
    the highest mesh frequency (ω·dt = π/2), reduced (×0.8) until the scheme's one-step matrix
    on the linearised reduced model (damping, gyroscopics, skew stiffness) amplifies no mode
    beyond the model's own growth; an explicit ``dt`` outside that is refused. Default: when a
    mesh has backlash (issue 16: SPEC 6.1 case 15 at 7.7e-5 s instead of 9.3e-6 s, 1x and
    speed fluctuation as before against RK4, observed order 4 across contact changes where
    classical RK4 drops to 2–3); without backlash classical RK4 (the exponential scheme is as
    accurate at twice the step there, each step ~1.3× dearer: ``exact_linear=True``).

    The defaults (1.25, 0.9) were measured on the SPEC 6.1 gearbox against RK4
    (benchmarks/transient_app2.py): 1x within 0.5 %, speed fluctuation within 0.5 %.
    """

    dt: float | None = None
    cutoff: float | None = None
    cutoff_factor: float = 1.25
    accuracy: float = 0.9
    separated_modes: bool | str | None = None
    static_correction: bool | None = None
    tolerance: float = 0.005
    exact_linear: bool | None = None
    name: str = field(default="modal-rk4", init=False)


@dataclass(frozen=True)
class Save:
    """What to record: every ``dt`` seconds (default: 4 samples per period of the highest
    mesh frequency, or 64 per revolution without meshes); ``full_state`` records every active
    DOF (for checks; memory grows with the model)."""

    dt: float | None = None
    full_state: bool = False


@dataclass(frozen=True)
class Checkpoint:
    """Write the state of the run to ``path`` (atomically) every ``simulated`` seconds of
    simulated time (default: 5 % of ``t_end``, so a killed run loses at most a twentieth) and at
    the latest every ``every`` seconds of wall time, whichever comes first; resume from it when
    it exists and matches the run (model, method, step, end time, what is saved).

    The run advances in chunks of about 0.05 s of simulated time; an interval longer than that
    is rounded to whole chunks, a shorter one to whole save intervals (:class:`Save`). A resumed
    run is bit-identical to an uninterrupted run with the same checkpoint settings (and to a run
    without checkpoints when the interval is at least a chunk).

    A checkpoint holds the state and everything recorded so far (its size grows to that of the
    result). It is removed when the run ends. A file that cannot be read (truncated, not a
    checkpoint) is an input error naming it; a checkpoint of another run is ignored and replaced.
    """

    path: Path
    every: float = 60.0
    simulated: float | None = None


def excitation_frequency(system: TransientSystem) -> float:
    """Highest excitation frequency (rad/s): mesh frequency |N_i Ω_i|, else 10× shaft speed."""
    if system.meshes:
        return float(np.abs(system.mesh_rates()).max())
    return 10.0 * float(np.max(np.abs(system.nominal_speeds)))
