"""The :func:`transient` driver (SPEC 2.6): build the system (:mod:`.equations`), choose the
recorded DOFs (:mod:`.forces`), prepare the kernel arrays of the chosen integrator
(:mod:`.prepare`), integrate in chunks with the compiled kernels (:mod:`.kernels`; progress,
checkpoints: :mod:`.checkpoint`) and assemble the result (:func:`.results.build_result`).

Divergence (non-finite state, or a lateral displacement above ``blowup`` m / torsional deviation
above 1 rad from rigid rotation) stops the run with a SolverError that names the time.
"""

from __future__ import annotations

import sys
import time as _time
import warnings
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ...assembly import Assembly, assemble
from ...errors import ModelError, SolverError
from ...model import Train
from ...threads import managed
from ..limits import check_run_size
from . import kernels as kn
from .checkpoint import _check_state, _fingerprint, _read_checkpoint, _write_npz_atomic
from .equations import TransientSystem, build_system, static_state
from .forces import _output_dofs
from .options import RK4, Checkpoint, ModalRK4, Save, excitation_frequency
from .prepare import _prepare_modal, _prepare_physical
from .results import TransientResult, build_result

__all__ = ["transient", "transient_at_operating_point"]


def transient_at_operating_point(model: Train | Assembly, operating_point) -> tuple[Train, dict]:
    """The train a transient runs at an operating point, and the constant loads
    (:func:`.equations.build_system` keywords ``constant_force``, ``bearing_preload``; and
    ``name``, the point's).

    * the train at the point (:func:`~gearrotor.analyses.static.at_operating_point`): fluid-film
      bearings at the coefficients of the point's static loads (held at every speed), meshes on
      the flank the torque loads; its speed the point's;
    * the point's drive torque at its drive node and the reacting load torque at its load node
      (from the static analysis) added to the model's torques, so the train runs at the load;
    * constant loads: the weight (consistent mass times the gravity field), the static forces
      and moments, and on each fluid-film journal the constant part of its film force
      linearised about the static equilibrium, ``F = −W_s − K (d − d_s)`` (``W_s`` the static
      load, ``d_s`` the static journal position): the journals carry the static load through
      the run, and the static state of the point is an equilibrium of the transient; on each
      seal (which carries no static load) its force at the static deflection, so that it acts on
      the motion about the static state.
    """
    from ..static import static
    from ..static.analysis import _gravity_field
    from ..static.operating_point import model_at_operating_point

    if not isinstance(model, (Train, Assembly)):
        raise TypeError("transient(operating_point=...) takes a Train or its Assembly")
    train = model if isinstance(model, Train) else model.train
    op = train.operating_point(operating_point)
    at, w = model_at_operating_point(train, operating_point)
    st = static(train, op)
    data = at.model_dump()
    data["speed"] = w
    torques = list(data.get("torques") or [])
    if op.drive is not None and (op.power or op.torque):
        torques.append({"shaft": op.drive.shaft, "node": op.drive.node, "value": st.drive_torque})
        torques.append({"shaft": op.load.shaft, "node": op.load.node, "value": st.load_torque})
    data["torques"] = torques
    run = Train.model_validate(data)
    asm0 = assemble(train)
    asm = assemble(run)
    f = asm0.M @ _gravity_field(asm0, op)
    for j, sf in enumerate(op.forces):
        si, node = train.node_index(sf, f"operating_point.forces[{j}]")
        f[asm0.node_offset[si][node] + np.arange(6)] += np.concatenate([sf.force, sf.moment])
    preload = np.zeros((len(asm.bearings), 2))
    for k, info in enumerate(asm.bearings):  # the bearings, then the seals
        spec = train.bearings[k] if info.kind == "bearing" else None
        if spec is not None and spec.fluid_film is None:
            continue
        d = st.q[info.dofs].copy()
        if info.support_dofs is not None:
            d -= st.q[info.support_dofs]
        if info.pad_dofs is not None:
            # pad dynamics: the full matrices; the pads sit at their equilibrium for the static
            # journal position (pad DOFs 0 in the static state), so they carry K_pj d_s
            kf = info.element.pads.at(asm.shaft_speeds(w)[info.shaft])[0]
            kb = kf[:2, :2]
            f[info.pad_dofs] += kf[2:, :2] @ d
        else:
            kb = info.element.K(asm.shaft_speeds(w)[info.shaft])
        # a journal: −W_s + K d_s; a seal (no static load: analyses/static) K d_s, so that it
        # acts on the motion about the static state
        g = kb @ d - (st.bearings[k].force[:2] if spec is not None else 0.0)
        preload[k] = g
        f[info.dofs] += g
        if info.support_dofs is not None:
            f[info.support_dofs] -= g
    return run, {
        "constant_force": f if f.any() else None,
        "bearing_preload": preload if preload.any() else None,
        "name": op.name,
    }


def _warn_rotating_damping_speed(system: TransientSystem, speeds: NDArray) -> None:
    """Warn when a shaft with rotating material damping strayed more than 2 % from its
    nominal speed: its circulatory stiffness is applied at the nominal speed."""
    for s, kc in enumerate(system.Kc):
        nominal = abs(float(system.nominal_speeds[s]))
        if not kc.nnz or not len(speeds):
            continue
        dev = float(np.max(np.abs(np.abs(speeds[:, s]) - nominal))) / max(nominal, 1e-12)
        if dev > 0.02:
            warnings.warn(
                f"shaft {system.train.shafts[s].name!r} has rotating material damping, whose "
                f"circulatory stiffness the transient applies at the nominal speed, and its speed "
                f"departed from it by up to {100 * dev:.3g} %: that term is off by as much "
                "(docs/transient.md)",
                stacklevel=3,
            )


def _check_memory(n_rec: int, n_out: int, n_shafts: int, n_steps: int, t_end: float) -> None:
    """Refuse a run whose record would not fit in memory, or that would not end, before it
    starts (the bounds shared with the torsional transient, :mod:`..limits`)."""
    check_run_size(n_steps, n_rec, 3 * n_out + n_shafts + 1, t_end)


def _restore_drive_state(path, ck: dict, state: NDArray) -> None:
    """The drives' event state (synchronous motors' pull-in) from a checkpoint, in place."""
    saved = ck.get("drive_state")
    if saved is None or saved.shape != state.shape or not np.all(np.isfinite(saved)):
        raise ModelError(
            "the checkpoint lacks the drives' state (written before drives were saved, or damaged)",
            file=str(path),
            expected="delete it to start the run afresh",
        )
    state[:] = saved


def _check_checkpoint_options(ck: Checkpoint) -> None:
    if not (np.isfinite(ck.every) and ck.every >= 0):
        raise ModelError(
            "the wall-time interval of checkpoints must be finite and >= 0",
            field="checkpoint.every",
            value=ck.every,
            expected="seconds >= 0 (0: at every chunk of the run)",
        )
    if ck.simulated is not None and not (np.isfinite(ck.simulated) and ck.simulated > 0):
        raise ModelError(
            "the simulated-time interval of checkpoints must be positive",
            field="checkpoint.simulated",
            value=ck.simulated,
            expected="seconds > 0 (default: 5 % of t_end)",
        )


@managed
def transient(
    model: Train | Assembly,
    *,
    t_end: float,
    integrator: RK4 | ModalRK4 | None = None,
    save: Save | None = None,
    frozen_speed: bool = False,
    reactions: bool = True,
    initial_q: NDArray | None = None,
    initial_qdot: NDArray | None = None,
    initial: str | None = None,
    stiffness_tables: dict[int, tuple[NDArray, NDArray]] | None = None,
    transmission_error: dict[int, NDArray] | None = None,
    back_flank: str = "same",
    blowup: float = 0.05,
    progress: bool = False,
    checkpoint: Checkpoint | None = None,
    operating_point=None,
) -> TransientResult:
    """Nonlinear transient of a train from t = 0 to ``t_end`` (s).

    Parameters
    ----------
    model : Train or its Assembly
    t_end : s
    integrator : :class:`ModalRK4` (fast, the default ``ModalRK4()``) or :class:`RK4` (reference)
    save : what to record (:class:`Save`)
    frozen_speed : keep every θz at nominal rigid rotation (constant speed, SPEC's linear case)
    reactions : include the reaction torques of the gyroscopic and unbalance θ̈ terms (the
        Lagrangian, energy-consistent form); False gives the dissertation's form
    initial : ``"zero"`` displacement (the default without an operating point), or
        ``"static"``: the static deflection under the external
        torques at t = 0 (:func:`.equations.static_state`); both at the nominal speeds;
        ``"rest"``: zero displacement and speed (a start-up by the model's ``[torsional]``
        drives, which act as in :func:`~gearrotor.analyses.torsional.torsional_transient`)
    initial_q, initial_qdot : (n_dof,) global perturbations added to the initial displacement and
        the nominal speeds (m, rad, m/s, rad/s)
    stiffness_tables, transmission_error : per mesh index, see :mod:`.mesh`
    back_flank : ``"same"`` (SPEC 2.4) or ``"mirrored"`` line of action for back-flank contact
    blowup : m, a displacement of a recorded non-torsional DOF beyond which the run is declared
        divergent (non-finite values always are)
    progress : print progress to stderr
    checkpoint : :class:`Checkpoint` for long runs (resume when the file matches)
    operating_point : name or :class:`~gearrotor.model.OperatingPoint` of a Train model: run at
        the point (:func:`transient_at_operating_point`): its speed, fluid-film bearings at the
        coefficients of its static loads, meshes on the loaded flank, its drive and load torques
        added to the model's, its weight and static forces (and the journals' static film
        loads) as constant loads; ``initial`` defaults to ``"static"``, the point's static state

    Returns a :class:`~.results.TransientResult`.
    """
    setup0 = _time.perf_counter()

    if not (0 < t_end < np.inf):
        raise ModelError(
            "t_end must be positive and finite", field="t_end", value=t_end, expected="> 0 s"
        )
    if checkpoint is not None:
        _check_checkpoint_options(checkpoint)
    integ = integrator if integrator is not None else ModalRK4()
    if isinstance(integ, RK4) and not integ.dt > 0:
        raise ModelError("the time step must be positive", field="dt", value=integ.dt)
    save = save or Save()
    extra = {}
    op_name = ""
    if operating_point is not None:
        model, extra = transient_at_operating_point(model, operating_point)
        op_name = f"|op={extra.pop('name')}"
        initial = "static" if initial is None else initial
    initial = "zero" if initial is None else initial
    system = build_system(
        model,
        **extra,
        frozen_speed=frozen_speed,
        reactions=reactions,
        initial_q=initial_q,
        stiffness_tables=stiffness_tables,
        transmission_error=transmission_error,
        back_flank=back_flank,
    )
    if not excitation_frequency(system) > 0:
        raise ModelError(
            "the train does not turn: a transient needs a non-zero speed (its step, modal "
            "cut-off and sampling follow the shaft and mesh frequencies)",
            field="speed",
            value=0.0,
            expected="a non-zero speed of the reference shaft",
        )
    out = _output_dofs(system, save.full_state)
    if isinstance(integ, RK4):
        prep = _prepare_physical(system, integ, out, frozen_speed)
    elif isinstance(integ, ModalRK4):
        if frozen_speed:
            raise ModelError("frozen speed is available with RK4 only", field="frozen_speed")
        prep = _prepare_modal(system, integ, out, save.dt)
    else:
        raise TypeError(f"unknown integrator {integ!r}; expected RK4(...) or ModalRK4(...)")
    dt = prep.dt
    n_steps = int(np.ceil(t_end / dt - 1e-9))
    fexc = excitation_frequency(system)
    save_dt = (
        save.dt
        if save.dt is not None
        else (2 * np.pi / (4 * fexc) if system.meshes else 2 * np.pi / (64 * fexc / 10))
    )
    save_every = max(1, int(round(save_dt / dt)))
    n_rec = n_steps // save_every + 1
    _check_memory(n_rec, len(out), len(system.a_weights), n_steps, t_end)

    # initial state
    q0, v0 = system.initial_state()
    if initial == "static":
        q0 += static_state(system)[0]
    elif initial == "rest":  # a start-up: the train at standstill (drives: [torsional])
        v0[:] = 0.0
    elif initial != "zero":
        raise ModelError(
            "unknown initial state",
            field="initial",
            value=initial,
            expected="'zero', 'static' or 'rest'",
        )
    if initial_q is not None:
        q0 += np.asarray(initial_q, float)[system.active]
    if initial_qdot is not None:
        v0 += np.asarray(initial_qdot, float)[system.active]
    if prep.kind == "physical":
        q, v = q0, v0
    else:
        Phi, M = prep.info["Phi"], prep.info["M"]
        q = Phi.T @ (M @ q0)
        v = Phi.T @ (M @ v0)
    nout = len(out)
    ns = len(system.a_weights)
    rec_q = np.zeros((n_rec, nout))
    rec_v = np.zeros((n_rec, nout))
    rec_a = np.zeros((n_rec, nout))
    rec_om = np.zeros((n_rec, ns))
    rec_t = np.zeros(n_rec)
    # the meshes' envelope over each recording interval, tracked at every step (kn.Record)
    rec_env = np.zeros((n_rec, len(system.meshes), 4))
    # divergence scale per output DOF: lateral → 1/blowup, torsional deviation → 1 rad
    kind = system.assembly.dof_kind()[system.active[out]]
    scale = np.where(kind == 2, 0.0, 1.0 / blowup)

    step0 = 0
    fp = _fingerprint(
        system.train,
        prep.kind,
        dt,
        f"{t_end}|{save_every}|{frozen_speed}|{reactions}|{integ!r}|{initial}|{back_flank}"
        + op_name,
    )
    ck = _read_checkpoint(checkpoint.path, fp) if checkpoint is not None else None
    if ck is not None:
        step0 = _check_state(
            checkpoint.path,
            ck,
            n_steps=n_steps,
            save_every=save_every,
            q=q,
            rec_q=rec_q,
            rec_om=rec_om,
            rec_env=rec_env,
        )
        q, v = ck["q"].copy(), ck["v"].copy()
        if prep.drive_state.size:  # synchronous motors that pulled in stay in step
            _restore_drive_state(checkpoint.path, ck, prep.drive_state)
        nr = step0 // save_every
        rec_q[:nr], rec_v[:nr], rec_a[:nr] = ck["rec_q"], ck["rec_v"], ck["rec_a"]
        rec_om[:nr], rec_t[:nr], rec_env[:nr] = ck["rec_om"], ck["rec_t"], ck["rec_env"]
        if progress:
            print(
                f"resuming from {checkpoint.path} at t = {step0 * dt:.4g} s",
                file=sys.stderr,
            )
    chunk = save_every * max(1, int(0.05 / (dt * save_every)))  # ~0.05 s of simulated time
    # checkpoints every ck_steps steps, and the chunks end there: an interval longer than a
    # chunk is rounded to whole chunks (the chunks stay those of a run without checkpoints,
    # whose time stamps t0 + k dt are then bit-identical), a shorter one to whole save
    # intervals (the records stay aligned)
    ck_steps = n_steps
    if checkpoint is not None:
        want = (checkpoint.simulated or 0.05 * t_end) / dt
        unit = chunk if want >= chunk else save_every
        ck_steps = unit * max(1, round(want / unit))
    last_ck_step = step0
    wall0 = _time.perf_counter()
    setup = wall0 - setup0
    last_ck = wall0
    last_pr = wall0
    step = step0
    runner = kn.rk4_physical if prep.kind == "physical" else kn.rk4_modal
    extra = () if prep.operators is None else (prep.operators,)
    if extra:
        runner = kn.etd_modal
    rec = kn.Record(
        out if prep.kind == "physical" else prep.Phi_out,
        rec_q,
        rec_v,
        rec_a,
        rec_om,
        rec_t,
        scale,
        rec_env,
    )
    substeps = 0
    while step < n_steps:
        nst = min(chunk, n_steps - step, last_ck_step + ck_steps - step)
        status, done, *more = runner(
            step * dt,
            dt,
            nst,
            q,
            v,
            save_every,
            step // save_every,
            rec,
            prep.model,
            prep.work,
            prep.stages,
            *extra,
        )
        substeps += more[0] if more else 0
        if status != kn.STATUS_OK:
            t_bad = (step + done) * dt
            what = (
                "non-finite values"
                if status == kn.STATUS_NONFINITE
                else (f"a lateral displacement above {blowup} m")
            )
            raise SolverError(
                f"the transient diverged at t = {t_bad:.6g} s ({what}); likely causes: a step "
                f"too large for the integrator (dt = {dt:.3g} s), or an unstable mode of the "
                "train (negative damping, e.g. cross-coupling or a mesh parametric resonance); "
                "check modal() at the running speed and try a smaller dt"
            )
        step += nst
        now = _time.perf_counter()
        if progress and (now - last_pr > 2.0 or step == n_steps):
            frac = step / n_steps
            el = now - wall0
            eta = el / max(frac - step0 / n_steps, 1e-12) * (1 - frac)
            print(
                f"t = {step * dt:.4g}/{t_end:.4g} s ({100 * frac:.0f} %), {el:.1f} s elapsed, "
                f"~{eta:.1f} s left",
                file=sys.stderr,
            )
            last_pr = now
        if (
            checkpoint is not None
            and step < n_steps
            and (step - last_ck_step >= ck_steps or now - last_ck > checkpoint.every)
        ):
            nr = step // save_every
            _write_npz_atomic(
                Path(checkpoint.path),
                fingerprint=np.array(fp),
                step=step,
                q=q,
                v=v,
                rec_q=rec_q[:nr],
                rec_v=rec_v[:nr],
                rec_a=rec_a[:nr],
                rec_om=rec_om[:nr],
                rec_t=rec_t[:nr],
                rec_env=rec_env[:nr],
                drive_state=prep.drive_state,
            )
            last_ck = now
            last_ck_step = step
    wall = _time.perf_counter() - wall0
    if checkpoint is not None and Path(checkpoint.path).exists():
        Path(checkpoint.path).unlink()
    nr = (n_steps - 1) // save_every + 1
    _warn_rotating_damping_speed(system, rec_om[:nr])
    stats = {
        "method": prep.kind if prep.kind == "physical" else "modal",
        "dt": dt,
        "steps": n_steps,
        "rhs_evaluations": 4 * (n_steps - step0) + 8 * substeps,
        "wall_time_s": wall,
        "setup_time_s": setup,
        "save_every": save_every,
        "scheme": None if prep.kind == "physical" else ("exponential" if extra else "rk4"),
        "contact_events": substeps if extra else None,
        **{k: v for k, v in prep.info.items() if k not in ("Phi", "M")},
    }
    final = (q.copy(), v.copy())
    if prep.kind == "modal":
        Phi = prep.info["Phi"]
        final = (Phi @ q, Phi @ v)
    return build_result(
        system,
        out,
        rec_t[:nr],
        rec_q[:nr],
        rec_v[:nr],
        rec_a[:nr],
        rec_om[:nr],
        stats=stats,
        envelope=(rec_env[:nr], n_steps * dt),
        final_state=final,
        name=integ.name,
        frozen=frozen_speed,
    )
