"""Summary metrics on synthetic signals with known answers (closed form)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from gearrotor.studies.metrics import transient_metrics

RPM = 30.0 / np.pi


def synthetic(*, t_end=1.0, dt=1e-4, om=2 * np.pi * 100.0, a1=3e-5, a2=4e-6, fl=2.0):
    """Probes: a1 at 1x plus a2 at 2x; speed: om + fl·sin(7 om t) (rad/s) on a linear
    trend; mesh force 10 + 15 sin(2π 250 t) with teeth separated where negative."""
    t = np.arange(0.0, t_end, dt)
    probe = a1 * np.cos(om * t + 0.3) + a2 * np.sin(2 * om * t) + 1e-6
    speed = om + fl * np.sin(7 * om * t) - 0.5 * t
    force = 10 + 15 * np.sin(2 * np.pi * 250.0 * t)  # 40 samples a period
    contact = (force > 0).astype(np.int8)
    force = np.where(contact == 1, force, 0.0)
    wp = np.column_stack([2.0 + np.cos(om * t), -1.0 + 0 * t])
    return xr.Dataset(
        {
            "probe_signal": (("time", "probe"), np.column_stack([probe, 2 * probe])),
            "shaft_speed": (("time", "shaft"), speed[:, None]),
            "mesh_force": (("time", "mesh"), force[:, None]),
            "contact": (("time", "mesh"), contact[:, None]),
            "whirl_power": (("time", "component"), wp),
        },
        coords={
            "time": t,
            "probe": ["p1", "p2"],
            "shaft": ["s"],
            "mesh": ["m"],
            "component": ["unbalance", "bearing"],
        },
    )


def test_metrics_of_known_signals():
    om = 2 * np.pi * 100.0  # 6000 rpm
    ds = synthetic(om=om)
    m = transient_metrics(
        ds,
        window=0.5,
        probe_shaft=np.array([0, 0]),
        mesh_teeth=np.array([30]),
        mesh_shaft=np.array([0]),
    )
    # the mean speed over the window differs from om by the trend only (0.375 rad/s)
    assert m["amp_1x"].values == pytest.approx([3e-5, 6e-5], rel=2e-3)
    assert m["amp_2x"].values == pytest.approx([4e-6, 8e-6], rel=2e-2)
    assert m["dominant_frequency"].values == pytest.approx([6000.0, 6000.0], rel=2e-3)
    assert m["speed_fluctuation"].values[0] == pytest.approx(2.0 * RPM, rel=5e-3)
    assert m["speed_dominant_frequency"].values[0] == pytest.approx(42000.0, rel=2e-3)
    assert m["speed_mean"].values[0] == pytest.approx((om - 0.375) * RPM, rel=1e-5)
    assert m["mesh_frequency"].values[0] == pytest.approx(30 * (om - 0.375) * RPM, rel=1e-5)
    assert m["peak_mesh_force"].values[0] == pytest.approx(25.0, rel=1e-3)
    # 10 + 15 sin x < 0 for a fraction (π - 2 asin(2/3)) / 2π of the time
    assert m["contact_loss_fraction"].values[0] == pytest.approx(
        (np.pi - 2 * np.arcsin(2 / 3)) / (2 * np.pi), abs=1 / 40
    )
    assert m["whirl_power_peak"].values == pytest.approx([3.0, 1.0], rel=1e-6)
    assert m["whirl_power_mean"].values == pytest.approx([2.0, -1.0], abs=2e-3)
