"""Result of a transient run: time histories, derived channels, spectra, NetCDF.

All arrays are SI (s, m, rad, rad/s, N, N·m, W); names with ``_rpm``/``_cpm``/``_um`` convert.
Amplitudes are zero-to-peak. Whirl-promoting power of a component at a node is
``P = Fx ẋ + Fy ẏ`` with F the force the component applies to the rotor node (W): positive
feeds whirl energy, negative drains it.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ...errors import ModelError
from ...files import write_netcdf
from ...signals import amplitude_at, order_amplitudes, spectral_lines, spectrum
from . import kernels as kn
from .equations import TransientSystem
from .forces import pack_forces

__all__ = [
    "TransientResult",
    "MeshExtremes",
    "mesh_extremes",
    "dataset_mesh_extremes",
    "SolverStats",
    "spectrum",
    "amplitude_at",
    "spectral_lines",
    "check_result",
    "load_result",
    "build_result",
]

RPM = 30.0 / np.pi  # rad/s → rpm


@dataclass(frozen=True)
class SolverStats:
    """Work and settings of a run: method, step (s), steps, right-hand-side evaluations, wall
    time of the integration (s; the first run in a process includes numba compilation unless
    cached), setup time (assembly, modal basis; s), recording interval (steps), and for the
    modal method the number of modes, the cut-off and highest kept mode (Hz), the achieved
    1x harmonic check, the scheme (``"rk4"``, or ``"exponential"``: the modal oscillators
    integrated exactly, :class:`~.options.ModalRK4` ``exact_linear``) and the contact changes
    located within steps (exponential scheme)."""

    method: str
    dt: float
    steps: int
    rhs_evaluations: int
    wall_time_s: float
    save_every: int
    setup_time_s: float | None = None
    n_dof: int | None = None
    n_modes: int | None = None
    cutoff_hz: float | None = None
    highest_mode_hz: float | None = None
    harmonic_error: float | None = None
    scheme: str | None = None
    contact_events: int | None = None


def spectra_one_x_rpm(time: NDArray, shaft_speed: NDArray) -> NDArray:
    """(ns,) each shaft's 1x (rpm = cpm): its mean |speed| over the second half of the run, the
    window of the standard spectra (:func:`.plots.plot_spectra`); the summary reports the same
    number, so the table and the figure titles agree."""
    t = np.asarray(time)
    sl = t >= t[0] + 0.5 * (t[-1] - t[0])
    return np.mean(np.abs(np.asarray(shaft_speed)[sl]), axis=0) * RPM


#: where the mesh extremes come from (:func:`mesh_extremes`)
FROM_STEPS = "every step"
FROM_SAMPLES = "recorded samples only: no step envelope in the result"


@dataclass(frozen=True)
class MeshExtremes:
    """Per mesh (nm,): the least and largest normal tooth force (N), the fraction of time
    with the teeth separated and in back-flank contact only; ``source``: :data:`FROM_STEPS`
    or :data:`FROM_SAMPLES`; ``span`` the time covered (s)."""

    least: NDArray
    largest: NDArray
    loss: NDArray
    back: NDArray
    source: str
    span: float


def mesh_extremes(time, force, contact, envelope=None, since: float | None = None):
    """The meshes' force range and contact fractions from ``since`` (s, default the first
    sample) to the end of the run.

    ``envelope`` = (least, largest, loss time, back time (nt, nm), interval (nt,)): the step
    envelope of each recording interval (kernels.Record.env), so the range is that of every
    integration step, and the fractions are times over the time covered; None (a result file
    written before the envelope existed): the recorded samples (``force``, ``contact`` (nt,
    nm)), whose extremes depend on where the samples fall in the mesh cycle."""
    t = np.asarray(time)
    rows = np.flatnonzero(t >= (t[0] if since is None else since) - 1e-12)
    if envelope is not None:
        lo, hi, loss, back, span = (np.asarray(a)[rows] for a in envelope)
        total = float(span.sum())
        return MeshExtremes(
            lo.min(axis=0),
            hi.max(axis=0),
            loss.sum(axis=0) / total,
            back.sum(axis=0) / total,
            FROM_STEPS,
            total,
        )
    f = np.asarray(force)[rows]
    c = np.asarray(contact)[rows]
    return MeshExtremes(
        f.min(axis=0),
        f.max(axis=0),
        np.mean(c == 0, axis=0),
        np.mean(c == -1, axis=0),
        FROM_SAMPLES,
        float(t[-1] - t[rows[0]]),
    )


def dataset_mesh_extremes(ds, since: float | None = None) -> MeshExtremes:
    """:func:`mesh_extremes` of a saved result (:meth:`TransientResult.to_xarray` layout),
    from its step envelope when it has one, else from its samples."""
    names = (
        "mesh_force_min",
        "mesh_force_max",
        "mesh_contact_loss_time",
        "mesh_back_contact_time",
        "envelope_interval",
    )
    env = tuple(ds[n].values for n in names) if all(n in ds for n in names) else None
    return mesh_extremes(
        ds["time"].values, ds["mesh_force"].values, ds["contact"].values, env, since
    )


@dataclass(frozen=True)
class TransientResult:
    """Frozen result of :func:`~.driver.transient` (``status == "ok"`` when it finished).

    Shapes: nt time samples; ``q``/``qdot``/``qddot`` (nt, n_rec) at the global DOFs
    ``recorded_dofs`` (labels ``dof_labels``).
    """

    status: str
    time: NDArray
    shaft_names: tuple[str, ...]
    shaft_speed: NDArray  # (nt, ns) rad/s
    node_labels: tuple[str, ...]  # gear nodes, then probe/unbalance nodes
    node_x: NDArray  # (nt, nn) m
    node_y: NDArray
    node_shaft: NDArray  # (nn,) shaft index
    probe_names: tuple[str, ...]
    probes: NDArray  # (nt, np) m, along each probe's angle
    mesh_names: tuple[str, ...]
    mesh_force: NDArray  # (nt, nm) N: drive-flank force − back-flank force
    mesh_torque_gear: NDArray  # (nt, nm) N·m on gear i about +z
    mesh_torque_mate: NDArray  # (nt, nm) N·m on gear j about +z
    mesh_stiffness: NDArray  # (nt, nm) N/m
    dte: NDArray  # (nt, nm) m, dynamic transmission error δ − e along the line of action
    contact: NDArray  # (nt, nm) int8: +1 drive flank, 0 separated, −1 back flank, +2 both
    bearing_names: tuple[str, ...]
    bearing_force: NDArray  # (nt, nb, 2) N on the journal
    whirl_names: tuple[str, ...]
    whirl_power: NDArray  # (nt, nc) W
    recorded_dofs: NDArray
    dof_labels: tuple[str, ...]
    q: NDArray = field(repr=False)
    qdot: NDArray = field(repr=False)
    qddot: NDArray = field(repr=False)
    final_q: NDArray = field(repr=False)  # (n_active,) at t_end
    final_qdot: NDArray = field(repr=False)
    active_dofs: NDArray = field(repr=False)
    stats: SolverStats = field(repr=False)
    model_json: str = field(repr=False)
    frozen_speed: bool = False
    # the meshes' envelope over each recording interval [t_j, t_j+1), tracked at every step of
    # the integration (kernels.Record.env): (nt, nm) least and largest normal force (N), time
    # out of contact and in back-flank contact only (s); (nt,) the time each row covers (s).
    # None: not tracked (a result assembled from samples only), the samples stand in.
    mesh_force_min: NDArray | None = field(default=None, repr=False)
    mesh_force_max: NDArray | None = field(default=None, repr=False)
    mesh_contact_loss_time: NDArray | None = field(default=None, repr=False)
    mesh_back_contact_time: NDArray | None = field(default=None, repr=False)
    envelope_interval: NDArray | None = field(default=None, repr=False)

    # ---- conveniences ----------------------------------------------------------------------
    @property
    def shaft_speed_rpm(self) -> NDArray:
        return self.shaft_speed * RPM

    @property
    def contact_loss_fraction(self) -> NDArray:
        """(nm,) fraction of the run's time with the teeth separated, from the contact state
        at every step (the step envelope); the fraction of samples where there is none."""
        return self.mesh_extremes().loss

    def mesh_extremes(self, since: float | None = None) -> MeshExtremes:
        """The meshes' force range and contact-loss fraction from ``since`` (s; default the
        whole run) to the end, over every step of the integration (:func:`mesh_extremes`)."""
        env = None
        if self.mesh_force_min is not None:
            env = (
                self.mesh_force_min,
                self.mesh_force_max,
                self.mesh_contact_loss_time,
                self.mesh_back_contact_time,
                self.envelope_interval,
            )
        return mesh_extremes(self.time, self.mesh_force, self.contact, env, since)

    def channel(self, dof: int) -> NDArray:
        """Recorded displacement history of a global DOF."""
        k = np.flatnonzero(self.recorded_dofs == dof)
        if not len(k):
            raise KeyError(f"global DOF {dof} was not recorded")
        return self.q[:, k[0]]

    def amplitude_1x(self, window: float = 0.5) -> dict[str, dict[str, float]]:
        """1x and 2x (own shaft) zero-to-peak amplitudes (m) of node x, y over the last
        ``window`` seconds, tracked in the shaft-angle domain (:func:`order_amplitudes`)."""
        sl = self.time >= self.time[-1] - window
        out = {}
        for k, lab in enumerate(self.node_labels):
            om = self.shaft_speed[sl, self.node_shaft[k]]
            ax = order_amplitudes(self.time[sl], self.node_x[sl, k], om)
            ay = order_amplitudes(self.time[sl], self.node_y[sl, k], om)
            out[lab] = {
                "x": float(ax[0]),
                "y": float(ay[0]),
                "x2": float(ax[1]),
                "y2": float(ay[1]),
            }
        return out

    @property
    def _summary_window(self) -> float:
        """s, the span the summary evaluates: the last 0.5 s, or the whole run if shorter."""
        return min(0.5, float(self.time[-1] - self.time[0]))

    def summary(self) -> dict:
        """JSON-ready summary: wall time; per recorded node over the last 0.5 s, the 1x and 2x
        amplitudes (µm) and the strongest spectral lines of x (:func:`spectral_lines`: cpm,
        order of the node's shaft, µm); speed range per shaft (rpm); mesh force range and
        contact-loss fraction."""
        window = self._summary_window
        amp = self.amplitude_1x(window)
        s = {
            "status": self.status,
            "method": self.stats.method,
            "dt_s": self.stats.dt,
            "steps": self.stats.steps,
            "wall_time_s": self.stats.wall_time_s,
            "t_end_s": float(self.time[-1]),
            "nodes": {},
            "shafts": {},
            "meshes": {},
        }
        if self.stats.n_modes is not None:
            s["n_modes"] = self.stats.n_modes
        last = self.time >= self.time[-1] - window
        dt = float(np.median(np.diff(self.time)))
        for k, (lab, a) in enumerate(amp.items()):
            speed_rpm = float(np.mean(np.abs(self.shaft_speed_rpm[last, self.node_shaft[k]])))
            s["nodes"][lab] = {
                "x_1x_um": a["x"] * 1e6,
                "y_1x_um": a["y"] * 1e6,
                "x_2x_um": a["x2"] * 1e6,
                "y_2x_um": a["y2"] * 1e6,
                "x_lines": [
                    {
                        "cpm": fc,
                        "order": fc / speed_rpm if speed_rpm > 0 else None,
                        "um": mean * 1e6,
                        "growth_1_s": sigma,
                        "um_end": end * 1e6,
                    }
                    for fc, mean, sigma, end in spectral_lines(self.node_x[last, k], dt)
                ]
                if last.sum() >= 64
                else [],
            }
        fl = self.speed_fluctuation(window)
        one_x = spectra_one_x_rpm(self.time, self.shaft_speed)
        for k, name in enumerate(self.shaft_names):
            rpm = self.shaft_speed_rpm[:, k]
            s["shafts"][name] = {
                "speed_start_rpm": float(rpm[0]),
                "speed_end_rpm": float(rpm[-1]),
                "speed_min_rpm": float(rpm.min()),
                "speed_max_rpm": float(rpm.max()),
                "speed_mean_rpm": float(rpm.mean()),
                "speed_1x_rpm": float(one_x[k]),
                "speed_fluctuation_rpm": float(fl[k] * RPM),
            }
        s["drive"] = self.drive()
        run = self.mesh_extremes()
        win = self.mesh_extremes(float(self.time[-1]) - window)
        for k, name in enumerate(self.mesh_names):
            s["meshes"][name] = {
                "force_min_N": float(run.least[k]),
                "force_max_N": float(run.largest[k]),
                "contact_loss_fraction": float(run.loss[k]),
                "back_contact_fraction": float(run.back[k]),
                "window_s": window,
                "window_force_min_N": float(win.least[k]),
                "window_force_max_N": float(win.largest[k]),
                "window_contact_loss_fraction": float(win.loss[k]),
                "extremes_from": run.source,
            }
        return s

    def drive(self) -> str:
        """What sets the speed: ``"held"`` (frozen speed), ``"torques"`` (the model's driving or
        load torques), or ``"coast-down"`` (no torque: the train runs down freely, losing
        speed to the bearings' and the material damping)."""
        if self.frozen_speed:
            return "held"
        try:
            torques = json.loads(self.model_json).get("torques") or []
        except (TypeError, ValueError):
            return "torques"
        return "torques" if torques else "coast-down"

    def table(self) -> str:
        """Human-readable summary table."""
        s = self.summary()
        window = self._summary_window
        growing = 1.0  # a line is shown as growing/decaying when |σ|·window > 1 (factor e)
        lines = [
            f"transient: {s['method']}, dt = {s['dt_s']:.3g} s, {s['steps']} steps, "
            f"{s['wall_time_s']:.2f} s wall"
        ]
        lines.append(f"{'node':<16}{'x 1x µm':>10}{'y 1x µm':>10}{'x 2x µm':>10}{'y 2x µm':>10}")
        for lab, a in s["nodes"].items():
            lines.append(
                f"{lab:<16}{a['x_1x_um']:>10.3f}{a['y_1x_um']:>10.3f}"
                f"{a['x_2x_um']:>10.3f}{a['y_2x_um']:>10.3f}"
            )
        lines.append(
            f"strongest spectral lines of x over the last {window:.3g} s (cpm, order of the "
            "node's shaft, mean µm 0-pk; a line that grows or decays by more than a factor e "
            "over the window: its rate and its amplitude at the end):"
        )
        for lab, a in s["nodes"].items():
            text = "; ".join(_line_text(ln, growing / window) for ln in a["x_lines"])
            lines.append(f"  {lab:<14}{text}")
        lines.append(
            f"{'shaft':<16}{'start rpm':>12}{'end rpm':>12}{'mean rpm':>12}{'1x cpm':>12}"
            "   (1x: mean speed over the second half, the spectra's window)"
        )
        for name, a in s["shafts"].items():
            lines.append(
                f"{name:<16}{a['speed_start_rpm']:>12.2f}{a['speed_end_rpm']:>12.2f}"
                f"{a['speed_mean_rpm']:>12.2f}{a['speed_1x_rpm']:>12.2f}"
            )
        if s["drive"] == "coast-down":
            lines.append(
                "no driving torque: coast-down (the model has no torques; the train runs down "
                "freely; add [[torques]] to drive it)"
            )
        elif s["drive"] == "held":
            lines.append("speed held constant (frozen speed)")
        for name, a in s["meshes"].items():
            back = a["back_contact_fraction"]
            lines.append(
                f"mesh '{name}': force {a['force_min_N']:.1f} .. {a['force_max_N']:.1f} N, "
                f"contact loss {100 * a['contact_loss_fraction']:.2f} %"
                + (f", back flank {100 * back:.2f} %" if back > 0 else "")
                + f" over the run; {a['window_force_min_N']:.1f} .. "
                f"{a['window_force_max_N']:.1f} N, contact loss "
                f"{100 * a['window_contact_loss_fraction']:.2f} % over the last "
                f"{a['window_s']:.3g} s ({a['extremes_from']})"
            )
        return "\n".join(lines)

    def spectrum(
        self,
        signal: NDArray,
        *,
        window: str = "hann",
        segments: int = 1,
        overlap: float = 0.5,
        start: float | None = None,
    ) -> tuple[NDArray, NDArray]:
        """Amplitude spectrum (cpm, zero-to-peak) of a recorded signal, see :func:`spectrum`."""
        sl = slice(None) if start is None else self.time >= start
        return spectrum(
            np.asarray(signal)[sl],
            float(np.median(np.diff(self.time))),
            window=window,
            segments=segments,
            overlap=overlap,
        )

    def speed_fluctuation(self, window: float = 0.5) -> NDArray:
        """(ns,) half peak-to-peak speed fluctuation (rad/s) about a linear trend over the last
        ``window`` seconds (the trend is the coast-down or run-up)."""
        sl = self.time >= self.time[-1] - window
        t = self.time[sl]
        out = []
        for s in range(self.shaft_speed.shape[1]):
            w = self.shaft_speed[sl, s]
            out.append(0.5 * np.ptp(w - np.polyval(np.polyfit(t - t[0], w, 1), t - t[0])))
        return np.array(out)

    # ---- xarray / NetCDF -----------------------------------------------------------------
    def to_xarray(self):
        """An ``xarray.Dataset`` with units attributes and the model embedded (JSON)."""
        import xarray as xr

        t = ("time", self.time, {"units": "s"})
        ds = xr.Dataset(
            {
                "shaft_speed": (
                    ("time", "shaft"),
                    self.shaft_speed,
                    {"units": "rad/s", "long_name": "shaft spin speed"},
                ),
                "x": (("time", "node"), self.node_x, {"units": "m"}),
                "y": (("time", "node"), self.node_y, {"units": "m"}),
                "node_shaft": (("node",), self.node_shaft.astype(np.int64)),
                "probe_signal": (("time", "probe"), self.probes, {"units": "m"}),
                "mesh_force": (
                    ("time", "mesh"),
                    self.mesh_force,
                    {"units": "N", "long_name": "normal tooth force"},
                ),
                "mesh_torque_gear": (("time", "mesh"), self.mesh_torque_gear, {"units": "N m"}),
                "mesh_torque_mate": (("time", "mesh"), self.mesh_torque_mate, {"units": "N m"}),
                "mesh_stiffness": (("time", "mesh"), self.mesh_stiffness, {"units": "N/m"}),
                "dte": (
                    ("time", "mesh"),
                    self.dte,
                    {"units": "m", "long_name": "dynamic transmission error"},
                ),
                "contact": (
                    ("time", "mesh"),
                    self.contact.astype(np.int8),
                    {"units": "1", "long_name": "+1 drive side, 0 separated, -1 back side"},
                ),
                **self._envelope_variables(),
                "bearing_force": (
                    ("time", "bearing", "direction"),
                    self.bearing_force,
                    {"units": "N"},
                ),
                "whirl_power": (
                    ("time", "component"),
                    self.whirl_power,
                    {"units": "W", "long_name": "whirl-promoting power Fx*vx + Fy*vy"},
                ),
                "q": (("time", "dof"), self.q, {"units": "m or rad"}),
                "qdot": (("time", "dof"), self.qdot, {"units": "m/s or rad/s"}),
            },
            coords={
                "time": t,
                "shaft": list(self.shaft_names),
                "node": list(self.node_labels),
                "probe": list(self.probe_names),
                "mesh": list(self.mesh_names),
                "bearing": list(self.bearing_names),
                "direction": ["x", "y"],
                "component": list(self.whirl_names),
                "dof": list(self.dof_labels),
                "global_dof": ("dof", self.recorded_dofs.astype(np.int64)),
            },
            attrs={
                "title": "gearrotor transient",
                "status": self.status,
                "model_json": self.model_json,
                "solver_stats": json.dumps({k: v for k, v in asdict(self.stats).items()}),
                "frozen_speed": int(self.frozen_speed),
            },
        )
        return ds

    def _envelope_variables(self) -> dict:
        """The step envelope's NetCDF variables (none when it was not tracked)."""
        if self.mesh_force_min is None:
            return {}
        span = " over the interval from the sample to the next, at every integration step"
        return {
            "mesh_force_min": (
                ("time", "mesh"),
                self.mesh_force_min,
                {"units": "N", "long_name": "least normal tooth force" + span},
            ),
            "mesh_force_max": (
                ("time", "mesh"),
                self.mesh_force_max,
                {"units": "N", "long_name": "largest normal tooth force" + span},
            ),
            "mesh_contact_loss_time": (
                ("time", "mesh"),
                self.mesh_contact_loss_time,
                {"units": "s", "long_name": "time with the teeth separated" + span},
            ),
            "mesh_back_contact_time": (
                ("time", "mesh"),
                self.mesh_back_contact_time,
                {"units": "s", "long_name": "time in back-flank contact only" + span},
            ),
            "envelope_interval": (
                ("time",),
                self.envelope_interval,
                {"units": "s", "long_name": "time the mesh envelope of each sample covers"},
            ),
        }

    def save(self, path: str | Path) -> Path:
        """Write NetCDF (h5netcdf engine) atomically (:func:`gearrotor.files.write_netcdf`)."""
        return write_netcdf(path, self.to_xarray())


def load_result(path: str | Path):
    """Open a saved transient result as an ``xarray.Dataset`` (loaded into memory), after
    checking from the file's header that its arrays fit in memory (:func:`check_sizes`)."""
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise ModelError("result file not found", file=str(path))
    if path.is_dir():
        raise ModelError("the result file is a directory", file=str(path), expected=_RESULT)
    check_sizes(path)
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
    except (OSError, ValueError, KeyError, TypeError, RecursionError) as exc:
        text = str(exc).splitlines()[0][:120] if str(exc) else ""
        raise ModelError(
            f"cannot read the result file ({type(exc).__name__}{': ' + text if text else ''})",
            file=str(path),
            expected=_RESULT,
        ) from None
    check_result(ds, str(path))
    return ds


#: Most bytes of arrays a saved result may hold: four times the largest record a transient
#: keeps (:data:`.driver.MAX_RECORD_BYTES`, 2 GiB), room for the derived channels it saves.
MAX_RESULT_BYTES = 8 * 1024**3


def check_sizes(path: str | Path, limit: int | None = None) -> int | None:
    """Refuse, from the file's header alone (no data is read), a NetCDF/HDF5 file whose arrays
    would not fit: more than ``limit`` bytes (default :data:`MAX_RESULT_BYTES`), or more than
    half the memory this process can still get (:func:`memory_available`). A compressed file
    declares its arrays' full shapes, and HDF5 reads chunks never written as their fill value:
    a file of a few kB can unpack to terabytes (a decompression bomb), which crashed the reader
    (libhdf5 and numpy under a memory limit: SIGSEGV). Returns the bytes the arrays need, or
    None for a file that is not HDF5 at all (its reader says what is wrong with it)."""
    import h5py

    sizes: list[tuple[int, str]] = []

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset):
            sizes.append((int(np.prod(obj.shape, dtype=np.float64)) * obj.dtype.itemsize, name))

    try:
        with h5py.File(path, "r") as f:
            f.visititems(visit)
    except (OSError, ValueError, KeyError, TypeError, RecursionError):
        return None
    total = sum(s for s, _ in sizes)
    limit = MAX_RESULT_BYTES if limit is None else limit
    free = memory_available()
    allowed = limit if free is None else min(limit, free // 2)
    if total > allowed:
        size, name = max(sizes)
        why = (
            f"at most {allowed / 1024**3:.3g} GiB"
            + (" (half the memory available)" if allowed < limit else " (the largest result")
            + ("" if allowed < limit else " a transient writes)")
        )
        raise ModelError(
            f"the file's arrays would need {total / 1024**3:.3g} GiB of memory once unpacked "
            f"({name}: {size / 1024**3:.3g} GiB, from the header; nothing was read)",
            file=str(path),
            value=f"{Path(path).stat().st_size / 1024**2:.3g} MiB on disk",
            expected=f"{_RESULT}, {why}",
        )
    return total


def memory_available() -> int | None:
    """Bytes this process can still allocate, as far as the system says: the least of the
    free memory (Linux ``MemAvailable``), the address-space limit (``ulimit -v``) less what
    the process maps, and its cgroup's limit less its usage; None where none is known."""
    import resource

    out: list[int] = []
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                out.append(int(line.split()[1]) * 1024)
    except (OSError, ValueError, IndexError):
        pass
    soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    if soft != resource.RLIM_INFINITY:
        used = 0
        try:
            for line in Path("/proc/self/status").read_text().splitlines():
                if line.startswith("VmSize:"):
                    used = int(line.split()[1]) * 1024
        except (OSError, ValueError, IndexError):
            pass
        out.append(max(soft - used, 0))
    try:
        cg = Path("/sys/fs/cgroup")
        limit = (cg / "memory.max").read_text().strip()
        if limit != "max":
            out.append(max(int(limit) - int((cg / "memory.current").read_text()), 0))
    except (OSError, ValueError):
        pass
    return min(out) if out else None


_RESULT = "a NetCDF file written by 'gearrotor transient --output'"
#: variables every reader of a saved result uses
_REQUIRED = ("shaft_speed", "x", "y")
#: largest embedded model (characters)
_MAX_MODEL_JSON = 4 * 1024 * 1024


def check_result(ds, file: str) -> None:
    """Check what a saved transient result holds before anything reads it (a file may come from
    anywhere): the variables the figures use, a time axis that is finite and increasing, finite
    values, and an embedded model (``model_json``) that is a valid model. Raises
    :class:`ModelError` naming the file and what is wrong."""
    missing = [v for v in ("time", *_REQUIRED) if v not in ds.variables]
    if missing:
        raise ModelError(
            "not a gearrotor transient result",
            file=file,
            value=f"missing {', '.join(missing)}",
            expected=_RESULT,
        )
    t = np.asarray(ds["time"].values)
    if t.ndim != 1 or t.size < 2 or not np.issubdtype(t.dtype, np.number):
        raise ModelError(
            "the time axis must be one-dimensional with at least 2 samples",
            field="time",
            file=file,
            value=f"shape {t.shape}",
        )
    if not np.all(np.isfinite(t)) or not np.all(np.diff(t) > 0):
        raise ModelError(
            "the time axis must be finite and strictly increasing",
            field="time",
            file=file,
            expected="increasing sample times in s",
        )
    for name, var in ds.data_vars.items():
        vals = np.asarray(var.values)
        if not np.issubdtype(vals.dtype, np.number):
            if name in _REQUIRED:
                raise ModelError("not numeric", field=str(name), file=file, expected=_RESULT)
            continue
        if not np.all(np.isfinite(vals)):
            raise ModelError(
                "the result holds values that are not finite",
                field=str(name),
                file=file,
                expected="finite numbers (a saved run that did not diverge)",
            )
    if "model_json" in ds.attrs:
        _check_model_json(ds.attrs["model_json"], file)


def _check_model_json(text, file: str) -> None:
    from ...inputs import MAX_DEPTH, depth_ok
    from ...model import Train

    where = dict(field="model_json", file=file)
    if not isinstance(text, str) or len(text) > _MAX_MODEL_JSON:
        raise ModelError(
            "the embedded model is not JSON text of a sensible size",
            **where,
            expected=f"a JSON model of at most {_MAX_MODEL_JSON} characters",
        )
    try:
        model = json.loads(text)
    except (ValueError, RecursionError):
        raise ModelError("the embedded model is not valid JSON", **where) from None
    if not isinstance(model, dict) or not depth_ok(model):
        raise ModelError(
            "the embedded model is not a model",
            **where,
            expected=f"a JSON object nested at most {MAX_DEPTH} levels",
        )
    from pydantic import ValidationError

    from ...io import format_validation_error

    try:
        Train.model_validate(model).layout()
    except (ValidationError, ModelError) as exc:
        if isinstance(exc, ValidationError):
            exc = format_validation_error(exc, model, None, "the embedded model")
        detail = "; ".join(line.strip() for line in str(exc).splitlines()[:4])[:300]
        raise ModelError(f"the embedded model is invalid: {detail}", **where) from None


def _line_text(line: dict, rate: float) -> str:
    """One spectral line of the summary table: cpm (order) mean µm, and when it grows or
    decays faster than ``rate`` (1/s) its rate and end amplitude."""
    text = f"{line['cpm']:,.0f}"
    if line["order"] is not None:
        text += f" ({line['order']:.2f}x)"
    text += f" {line['um']:.3g}"
    if abs(line["growth_1_s"]) > rate:
        verb = "growing" if line["growth_1_s"] > 0 else "decaying"
        text += f" [{verb} {abs(line['growth_1_s']):.3g} 1/s, {line['um_end']:.3g} at the end]"
    return text


# ---- assembly of the result from recorded states ---------------------------------------------
def build_result(
    system: TransientSystem,
    out: NDArray,
    t,
    rq,
    rv,
    ra,
    rom,
    *,
    stats: dict,
    envelope=None,
    final_state,
    name: str,
    frozen: bool,
) -> TransientResult:
    asm, train = system.assembly, system.train
    gl = system.active[out]
    col = {int(g): k for k, g in enumerate(gl)}
    nt = len(t)

    def hist(arr, g):
        k = col.get(int(g))
        return arr[:, k] if k is not None else np.zeros(nt)

    # nodes: gear nodes, then probe and unbalance nodes
    nodes = []
    for m in asm.meshes:
        for side, s in ((m.dofs[0], m.shafts[0]), (m.dofs[6], m.shafts[1])):
            nodes.append((int(side), s))
    for group, prefix in ((train.probes, "probes"), (train.unbalances, "unbalances")):
        for k, it in enumerate(group):
            si, node = train.node_index(it, f"{prefix}[{k}]")
            nodes.append((int(asm.node_offset[si][node]), si))
    seen, node_list = set(), []
    for g, s in nodes:
        if g not in seen:
            seen.add(g)
            node_list.append((g, s))

    def node_label(g):
        return asm.dof_labels[g].rsplit(".", 1)[0]

    node_x = np.column_stack([hist(rq, g) for g, _ in node_list] + [np.zeros((nt, 0))])
    node_y = np.column_stack([hist(rq, g + 1) for g, _ in node_list] + [np.zeros((nt, 0))])
    probes = []
    for k, p in enumerate(train.probes):
        si, node = train.node_index(p, f"probes[{k}]")
        g = asm.node_offset[si][node]
        probes.append(hist(rq, g) * np.cos(p.angle) + hist(rq, g + 1) * np.sin(p.angle))

    # meshes
    forces = pack_forces(system, out, modal=False, bearing_ref=False)
    nm = len(system.meshes)
    mo = np.zeros((nt, nm, 8))
    if nm:
        kn.outputs_kernel(rq, rv, forces.meshes, mo)
    F = mo[:, :, 0]
    # generalised force on the 12 gear DOFs: −F_d w − F_b w_b
    w = np.array([law.w for law in system.meshes]).reshape(nm, 12)
    wb = np.array([law.w_back for law in system.meshes]).reshape(nm, 12)
    gforce = -(mo[:, :, 6, None] * w[None] + mo[:, :, 7, None] * wb[None])  # (nt, nm, 12)
    whirl_names, whirl = [], []
    # unbalances
    for k, u in enumerate(train.unbalances):
        si, node = train.node_index(u, f"unbalances[{k}]")
        g = asm.node_offset[si][node]
        th = hist(rq, g + 5) + u.phase
        thd, thdd = hist(rv, g + 5), hist(ra, g + 5)
        fx = u.amount * (thd**2 * np.cos(th) + thdd * np.sin(th))
        fy = u.amount * (thd**2 * np.sin(th) - thdd * np.cos(th))
        whirl_names.append(f"unbalance[{k}]@{node_label(g)}")
        whirl.append(fx * hist(rv, g) + fy * hist(rv, g + 1))
    # bearings
    bforce = np.zeros((nt, len(asm.bearings), 2))
    for j, b in enumerate(asm.bearings):
        el = b.element
        if b.pad_dofs is not None:  # pad dynamics: the full matrices at the nominal speed
            d, T = b.local()
            k, c = el.pads.at(system.nominal_speeds[b.shaft])
            qd = np.column_stack([hist(rq, g) for g in d])
            vd = np.column_stack([hist(rv, g) for g in d])
            f = -(qd @ (k @ T).T + vd @ (c @ T).T)[:, :2]
            if system.bearing_preload is not None:
                f = f + system.bearing_preload[j]
            bforce[:, j] = f
            whirl_names.append(f"bearing:{b.name}")
            whirl.append(f[:, 0] * hist(rv, b.dofs[0]) + f[:, 1] * hist(rv, b.dofs[1]))
            continue
        if el.speed_dependent:
            sp_ = np.abs(rom[:, b.shaft])
            c = np.column_stack(
                [np.interp(sp_, el.table.speed, el.table.values[:, i]) for i in range(8)]
            )
        else:
            c = np.tile(el.coefficients(), (nt, 1))
        x, y = hist(rq, b.dofs[0]), hist(rq, b.dofs[1])
        vx, vy = hist(rv, b.dofs[0]), hist(rv, b.dofs[1])
        if b.support_dofs is not None:
            x = x - hist(rq, b.support_dofs[0])
            y = y - hist(rq, b.support_dofs[1])
            vx = vx - hist(rv, b.support_dofs[0])
            vy = vy - hist(rv, b.support_dofs[1])
        fx = -(c[:, 0] * x + c[:, 1] * y + c[:, 4] * vx + c[:, 5] * vy)
        fy = -(c[:, 2] * x + c[:, 3] * y + c[:, 6] * vx + c[:, 7] * vy)
        if system.bearing_preload is not None:  # the journal's static film load
            fx = fx + system.bearing_preload[j, 0]
            fy = fy + system.bearing_preload[j, 1]
        bforce[:, j, 0], bforce[:, j, 1] = fx, fy
        whirl_names.append(f"bearing:{b.name}")
        whirl.append(fx * hist(rv, b.dofs[0]) + fy * hist(rv, b.dofs[1]))
    for k, m in enumerate(asm.meshes):
        for off, side in ((0, "gear"), (6, "mate")):
            g = m.dofs[off]
            whirl_names.append(f"mesh:{m.name}:{side}")
            gf = gforce[:, k]
            whirl.append(gf[:, off] * hist(rv, g) + gf[:, off + 1] * hist(rv, g + 1))
    for k, c in enumerate(train.couplings):
        si, ni = train.node_index(c.node_i, f"couplings[{k}].node_i")
        sj, nj = train.node_index(c.node_j, f"couplings[{k}].node_j")
        gi, gj = asm.node_offset[si][ni], asm.node_offset[sj][nj]
        dvx = hist(rv, gi) - hist(rv, gj)
        dvy = hist(rv, gi + 1) - hist(rv, gj + 1)
        fx = -(c.kx * (hist(rq, gi) - hist(rq, gj)) + c.cx * dvx)
        fy = -(c.ky * (hist(rq, gi + 1) - hist(rq, gj + 1)) + c.cy * dvy)
        whirl_names.append(f"coupling:{c.name or f'couplings[{k}]'}")
        whirl.append(fx * dvx + fy * dvy)

    st = SolverStats(**{k: stats.get(k) for k in SolverStats.__dataclass_fields__})
    return TransientResult(
        status="ok",
        time=np.asarray(t),
        shaft_names=tuple(s.name for s in train.shafts),
        shaft_speed=np.asarray(rom),
        node_labels=tuple(node_label(g) for g, _ in node_list),
        node_x=node_x,
        node_y=node_y,
        node_shaft=np.array([s for _, s in node_list], int),
        probe_names=tuple(p.name for p in train.probes),
        probes=np.column_stack(probes) if probes else np.zeros((nt, 0)),
        mesh_names=tuple(m.name for m in asm.meshes),
        mesh_force=F,
        mesh_torque_gear=gforce[:, :, 5],
        mesh_torque_mate=gforce[:, :, 11],
        mesh_stiffness=mo[:, :, 1],
        dte=mo[:, :, 2],
        contact=mo[:, :, 4].astype(np.int8),
        bearing_names=tuple(b.name for b in asm.bearings),
        bearing_force=bforce,
        whirl_names=tuple(whirl_names),
        whirl_power=np.column_stack(whirl) if whirl else np.zeros((nt, 0)),
        recorded_dofs=gl.astype(np.int64),
        dof_labels=tuple(asm.dof_labels[g] for g in gl),
        q=rq,
        qdot=rv,
        qddot=ra,
        final_q=final_state[0],
        final_qdot=final_state[1],
        active_dofs=system.active,
        stats=st,
        model_json=train.model_dump_json(),
        frozen_speed=frozen,
        **_envelope_fields(envelope, np.asarray(t)),
    )


def _envelope_fields(envelope, t: NDArray) -> dict:
    """TransientResult's envelope fields from the kernels' (nt, nm, 4) envelope and the end
    time of the run (each row covers the time to the next sample, the last to the end)."""
    if envelope is None:
        return {}
    env, t_end = envelope
    return {
        "mesh_force_min": env[:, :, 0].copy(),
        "mesh_force_max": env[:, :, 1].copy(),
        "mesh_contact_loss_time": env[:, :, 2].copy(),
        "mesh_back_contact_time": env[:, :, 3].copy(),
        "envelope_interval": np.diff(t, append=max(float(t_end), float(t[-1]))),
    }
