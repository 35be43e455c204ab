"""Summary metrics of one case, computed from its dataset over a steady-state window.

Transient metrics (SPEC 3.4), all over the last ``window`` seconds of the run:

========================== =========== ==========================================================
variable (dims)            unit        meaning
========================== =========== ==========================================================
amp_1x (probe)             m           zero-to-peak 1x amplitude of the probe's shaft, tracked
                                       in the shaft-angle domain (:func:`order_amplitudes`)
amp_2x (probe)             m           the same for the 2x order (fitted jointly with 1x)
dominant_frequency (probe) cpm         highest peak of the probe's amplitude spectrum (Hann
                                       window, linear trend removed, DC bin excluded),
                                       refined between bins (parabolic, log amplitude)
speed_mean (shaft)         rpm         mean spin speed
speed_fluctuation (shaft)  rpm         half peak-to-peak speed about its linear trend
speed_dominant_frequency   cpm         highest peak of the speed spectrum
(shaft)
peak_mesh_force (mesh)     N           largest |normal tooth force| at any integration step
                                       (the result's step envelope; the samples in a file
                                       without one: the attribute ``source`` says which)
contact_loss_fraction      1           fraction of time with the teeth separated, from the
(mesh)                                 contact state at every step (as peak_mesh_force)
mesh_frequency (mesh)      cpm         tooth count × mean speed of the gear's shaft
whirl_power_peak           W           largest |P|, P = Fx ẋ + Fy ẏ of the component
(component)
whirl_power_mean           W           mean P (> 0 feeds whirl energy, < 0 drains it)
(component)
========================== =========== ==========================================================

Modal metrics: ``damped_frequency (mode)`` rpm, ``log_dec (mode)``, ``mode_type (mode)`` and
``whirl (mode)`` of the lowest elastic modes (over-damped and rigid-body modes excluded).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..signals import dominant_frequency, order_amplitudes

__all__ = ["TRANSIENT_METRICS", "MODAL_METRICS", "transient_metrics", "window_of"]

RPM = 30.0 / np.pi  # rad/s → rpm

TRANSIENT_METRICS = (
    "amp_1x",
    "amp_2x",
    "dominant_frequency",
    "speed_mean",
    "speed_fluctuation",
    "speed_dominant_frequency",
    "peak_mesh_force",
    "contact_loss_fraction",
    "mesh_frequency",
    "whirl_power_peak",
    "whirl_power_mean",
)
MODAL_METRICS = ("damped_frequency", "log_dec", "mode_type", "whirl")


def window_of(ds: xr.Dataset, window: float) -> xr.Dataset:
    """The samples of ``ds`` with time ≥ t_last − window (s)."""
    t = ds["time"].values
    return ds.isel(time=np.flatnonzero(t >= t[-1] - window - 1e-12))


def transient_metrics(
    ds: xr.Dataset,
    *,
    window: float,
    probe_shaft: np.ndarray,
    mesh_teeth: np.ndarray,
    mesh_shaft: np.ndarray,
) -> xr.Dataset:
    """Metrics of a transient dataset (:meth:`TransientResult.to_xarray` layout) over the last
    ``window`` s. ``probe_shaft`` (n_probe,), ``mesh_shaft`` (n_mesh,): shaft index of each
    probe and of each mesh's gear; ``mesh_teeth`` (n_mesh,): the gear's tooth count."""
    w = window_of(ds, window)
    t = w["time"].values
    dt = float(np.median(np.diff(t))) if len(t) > 1 else float("nan")
    speed = w["shaft_speed"].values  # (nt, ns) rad/s
    mean_speed = np.abs(speed).mean(axis=0)
    probes = w["probe_signal"].values
    n_probe = probes.shape[1]
    orders = np.array(
        [order_amplitudes(t, probes[:, k], speed[:, probe_shaft[k]]) for k in range(n_probe)]
    ).reshape(n_probe, 2)
    amp1, amp2 = orders[:, 0], orders[:, 1]
    dom = np.array([dominant_frequency(probes[:, k], dt) for k in range(n_probe)])
    fluct, sdom = [], []
    for s in range(speed.shape[1]):
        om = speed[:, s]
        tt = t - t[0]
        fluct.append(0.5 * np.ptp(om - np.polyval(np.polyfit(tt, om, 1), tt)) * RPM)
        sdom.append(dominant_frequency(om, dt))
    from ..analyses.transient.results import dataset_mesh_extremes  # numba: only when needed

    # the meshes over every step of the window's recording intervals (the last one to t_end)
    mesh = dataset_mesh_extremes(ds, float(t[0]))
    source = {"source": mesh.source}
    wp = w["whirl_power"].values
    out = xr.Dataset(
        {
            "amp_1x": ("probe", amp1, {"units": "m", "long_name": "1x amplitude (0-peak)"}),
            "amp_2x": ("probe", amp2, {"units": "m", "long_name": "2x amplitude (0-peak)"}),
            "dominant_frequency": (
                "probe",
                dom,
                {"units": "cpm", "long_name": "dominant displacement frequency"},
            ),
            "speed_mean": (
                "shaft",
                mean_speed * RPM * np.sign(speed.mean(axis=0)),
                {"units": "rpm", "long_name": "mean spin speed"},
            ),
            "speed_fluctuation": (
                "shaft",
                np.array(fluct),
                {"units": "rpm", "long_name": "speed fluctuation (half peak-to-peak, detrended)"},
            ),
            "speed_dominant_frequency": (
                "shaft",
                np.array(sdom),
                {"units": "cpm", "long_name": "dominant speed-fluctuation frequency"},
            ),
            "peak_mesh_force": (
                "mesh",
                np.maximum(np.abs(mesh.least), np.abs(mesh.largest)),
                {"units": "N", "long_name": "peak normal tooth force", **source},
            ),
            "contact_loss_fraction": (
                "mesh",
                mesh.loss,
                {"units": "1", "long_name": "fraction of time with the teeth separated", **source},
            ),
            "mesh_frequency": (
                "mesh",
                np.asarray(mesh_teeth, float) * mean_speed[np.asarray(mesh_shaft, int)] * RPM,
                {"units": "cpm", "long_name": "mesh frequency"},
            ),
            "whirl_power_peak": (
                "component",
                np.abs(wp).max(axis=0),
                {"units": "W", "long_name": "peak |whirl-promoting power|"},
            ),
            "whirl_power_mean": (
                "component",
                wp.mean(axis=0),
                {"units": "W", "long_name": "mean whirl-promoting power (>0 feeds whirl)"},
            ),
        },
        coords={k: ds[k].values for k in ("probe", "shaft", "mesh", "component")},
    )
    return out
