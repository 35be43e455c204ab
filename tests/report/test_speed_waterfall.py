"""Waterfall against speed (gearrotor.plots.waterfall): short-time spectra along a run-up placed at
the window's speed, with the shaft-order lines.

Oracles: a synthetic signal whose components follow the speed exactly (θ = ∫Ω dt): the spectral
ridge of each order must lie on its order line within one frequency bin (a Hann-windowed tone
peaks at the nearest bin, ±½ bin, plus the sweep during the window, which the default window
length keeps at one bin for 1x); its amplitude reads the tone's within the Hann scalloping loss
(≥ 0.85); a fixed-frequency component stays at its frequency while the speed sweeps. Then the
same on a real run-up of the unity gearbox, and the report's figure (PNG, interactive, JSON).
"""

from __future__ import annotations

import json
from dataclasses import fields

import numpy as np
import pytest

from gearrotor.errors import ModelError
from gearrotor.plots.waterfall import (
    SpeedWaterfall,
    short_time_spectra,
    speed_varies,
    speed_waterfall,
)

RPM = np.pi / 30
FS = 20_000.0  # Hz
T = 2.0  # s
RPM0, RPM1 = 3000.0, 6000.0  # linear run-up: 1500 rpm/s = 25 rev/s², default window 0.2 s
A1, A2, AM, AR = 10e-6, 3e-6, 1e-6, 2e-6  # 1x, 2x, 30x (mesh), fixed 150 Hz (resonance)
F_RES = 150 * 60.0  # cpm


def synthetic(t=None):
    t = np.arange(0, T, 1 / FS) if t is None else t
    w = (RPM0 + (RPM1 - RPM0) * t / T) * RPM
    th = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])
    x = (
        A1 * np.cos(th)
        + A2 * np.cos(2 * th + 0.4)
        + AM * np.cos(30 * th)
        + AR * np.cos(2 * np.pi * F_RES / 60 * t)
    )
    return t, x, w


def ridge_offsets(f, amp, sc, order, half=3):
    """Per window, (peak frequency − order line) in bins and the peak amplitude, searching ±half
    bins around the line."""
    b = f[1] - f[0]
    off, a = [], []
    for i, s in enumerate(sc):
        m = np.abs(f - order * s) <= half * b
        k = np.flatnonzero(m)[np.argmax(amp[i, m])]
        off.append((f[k] - order * s) / b)
        a.append(amp[i, k])
    return np.array(off), np.array(a)


def test_ridges_lie_on_the_order_lines():
    t, x, w = synthetic()
    f, amp, tc, sc, window = short_time_spectra(t, x, w)
    b = f[1] - f[0]
    assert window == pytest.approx(1 / np.sqrt(25.0), rel=1e-3)  # 1/√α, α = 25 rev/s²
    assert b == pytest.approx(60 / window, rel=1e-3)  # 300 cpm
    assert len(tc) == 40 and np.all(np.diff(tc) > 0)
    # window speeds are the mean speed over each window: linear ramp -> speed at the centre
    np.testing.assert_allclose(sc, RPM0 + (RPM1 - RPM0) * tc / T, rtol=1e-3)
    # 1x: the largest line of every spectrum, on the 1x line within a bin
    peak = f[np.argmax(amp, axis=1)]
    assert np.max(np.abs(peak - sc)) <= b
    off, a = ridge_offsets(f, amp, sc, 1)
    assert np.max(np.abs(off)) <= 1.0
    assert 0.84 * A1 <= a.min() and a.max() <= 1.01 * A1  # measured 0.845..0.992
    # 2x and 30x (mesh) ridges on their lines within a bin (30x is smeared over ~30 bins by
    # the sweep in each window, its centre stays on the line)
    for order in (2, 30):
        off, _ = ridge_offsets(f, amp, sc, order)
        assert np.max(np.abs(off)) <= 1.0, order
    # the fixed 150 Hz component stays at 9000 cpm wherever 2x is not near it
    far = np.abs(2 * sc - F_RES) > 5 * b
    for i in np.flatnonzero(far):
        m = np.abs(f - F_RES) <= 3 * b
        k = np.flatnonzero(m)[np.argmax(amp[i, m])]
        assert abs(f[k] - F_RES) <= b


def test_window_options_and_errors():
    t, x, w = synthetic()
    f, amp, tc, sc, window = short_time_spectra(t, x, w, window=0.1, n_windows=12)
    assert window == pytest.approx(0.1) and amp.shape == (12, len(f))
    with pytest.raises(ModelError, match="longer than the run"):
        short_time_spectra(t, x, w, window=5.0)
    with pytest.raises(ModelError, match="at least 2 windows"):
        short_time_spectra(t, x, w, n_windows=1)
    with pytest.raises(ModelError, match="too few samples"):
        short_time_spectra(t[:50], x[:50], w[:50])


def _result(t, x, w):
    """A TransientResult holding the synthetic signal as probe 'p' on shaft 's1' (a 30-tooth
    gear) and as the x of node 's1[3]'; shaft 's2' turns at −½ the speed."""
    from gearrotor.analyses.transient import SolverStats, TransientResult

    nt = len(t)
    z = np.zeros((nt, 1))
    model = {
        "probes": [{"name": "p", "shaft": "s1", "node": 3}],
        "meshes": [{"name": "m", "gear": {"shaft": "s1", "teeth": 30}}],
    }
    values = dict(
        status="ok",
        time=t,
        shaft_names=("s1", "s2"),
        shaft_speed=np.column_stack([w, -0.5 * w]),
        node_labels=("s1[3]",),
        node_x=x[:, None],
        node_y=z,
        node_shaft=np.array([0]),
        probe_names=("p",),
        probes=x[:, None],
        mesh_names=("m",),
        mesh_force=z,
        mesh_torque_gear=z,
        mesh_torque_mate=z,
        mesh_stiffness=z,
        dte=z,
        contact=np.ones((nt, 1), np.int8),
        bearing_names=("b",),
        bearing_force=np.zeros((nt, 1, 2)),
        whirl_names=("c",),
        whirl_power=z,
        recorded_dofs=np.array([0]),
        dof_labels=("s1[3].x",),
        q=z,
        qdot=z,
        qddot=z,
        final_q=np.zeros(1),
        final_qdot=np.zeros(1),
        active_dofs=np.array([0]),
        stats=SolverStats("modal", 1 / FS, nt, 4 * nt, 0.0, 1),
        model_json=json.dumps(model),
        # the step envelope (every step: here the recorded force itself, always in contact)
        mesh_force_min=z,
        mesh_force_max=z,
        mesh_contact_loss_time=np.zeros((nt, 1)),
        mesh_back_contact_time=np.zeros((nt, 1)),
        envelope_interval=np.full(nt, 1 / FS),
    )
    assert {f.name for f in fields(TransientResult)} - set(values) <= {"frozen_speed"}
    return TransientResult(**values)


def test_from_a_transient_result_and_its_dataset():
    pytest.importorskip("xarray", reason="the Dataset path needs xarray")
    res = _result(*synthetic())
    wf = speed_waterfall(res)
    assert isinstance(wf, SpeedWaterfall)
    assert wf.signal == "probe p" and wf.shaft == "s1"
    assert dict(wf.orders) == {"1x": 1.0, "2x": 2.0, "mesh": 30.0}
    f1, a1 = wf.ridge(1.0)
    assert np.nanmax(np.abs(f1 - wf.order_line(1.0))) <= wf.bin_cpm
    assert np.nanmin(a1) >= 0.84 * A1
    # the saved-result Dataset gives the same waterfall
    ds = speed_waterfall(res.to_xarray())
    np.testing.assert_array_equal(ds.amplitude, wf.amplitude)
    np.testing.assert_array_equal(ds.speed_rpm, wf.speed_rpm)
    # a node instead of a probe: same signal, same spectra
    wn = speed_waterfall(res, node="s1[3]", component="x")
    assert wn.signal == "s1[3] x"
    np.testing.assert_allclose(wn.amplitude, wf.amplitude)
    d = wf.to_dict()
    assert d["windows"] == 40 and d["orders"]["mesh"] == 30.0
    assert d["speed_range_rpm"][0] == pytest.approx(wf.speed_rpm.min())
    for kwargs, msg in (
        ({"probe": "q"}, "unknown probe"),
        ({"node": "s9[1]"}, "unknown node"),
        ({"probe": "p", "node": "s1[3]"}, "not both"),
        ({"node": "s1[3]", "component": "z"}, "unknown component"),
    ):
        with pytest.raises(ModelError, match=msg):
            speed_waterfall(res, **kwargs)


def test_speed_varies_only_for_run_ups_and_coast_downs():
    t = np.arange(0, 1.0, 1e-4)
    x = np.zeros_like(t)
    steady = 6500 * RPM * (1 + 0.005 * np.sin(2 * np.pi * 108 * t))  # ±0.5 % torsional ripple
    assert not speed_varies(_result(t, x, steady))
    coast = 6500 * RPM * (1 - 0.02 * t)  # 2 % over the run
    assert speed_varies(_result(t, x, coast))
    assert not speed_varies(_result(t, x, coast), threshold=0.05)


def test_real_run_up(runup_result):
    """The unity gearbox accelerating from 3000 rpm: its 1x ridge on the 1x line."""
    res, _ = runup_result
    assert speed_varies(res)
    wf = speed_waterfall(res)
    assert wf.signal == "probe gear1_x" and wf.shaft == "shaft1"
    assert dict(wf.orders)["mesh"] == pytest.approx(30.0, rel=1e-3)
    lo, hi = wf.speed_rpm.min(), wf.speed_rpm.max()
    assert 3000 < lo < 3600 and 5200 < hi < 6000, (lo, hi)
    peak = wf.frequency_cpm[np.argmax(wf.amplitude, axis=1)]
    assert np.max(np.abs(peak - wf.speed_rpm)) <= wf.bin_cpm
    # unbalance response grows with speed below the first critical
    _, a = wf.ridge(1.0)
    assert a[-1] > 2 * a[0]


def test_figures(runup_result, tmp_path):
    pytest.importorskip("matplotlib", reason="the PNG needs matplotlib")
    pytest.importorskip("plotly", reason="the interactive figure needs plotly")
    from gearrotor.plots.report.sections.transient import speed_waterfall_figure
    from gearrotor.plots.waterfall import plot_speed_waterfall

    wf = speed_waterfall(runup_result[0])
    fig = plot_speed_waterfall(wf, path=tmp_path / "w.png")
    assert (tmp_path / "w.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    ax = fig.axes
    assert len(ax) == 2  # 1x/2x and near the mesh frequency
    assert ax[0].get_ylabel() == "speed of shaft1 (rpm)"
    labels = [line.get_label() for line in ax[0].get_lines()]
    assert "1x" in labels and "2x" in labels
    assert "mesh" in [line.get_label() for line in ax[1].get_lines()]
    g = speed_waterfall_figure(wf)
    names = [tr.name for tr in g.data if tr.name]
    assert any(n.startswith("1x") for n in names) and any(n.startswith("mesh (") for n in names)
    spectra = [tr for tr in g.data if tr.fill == "toself"]
    assert len(spectra) == 2 * len(wf.time)
    # the hover amplitude is the spectrum in µm
    k = int(np.argmax(wf.speed_rpm))
    np.testing.assert_allclose(spectra[0].customdata[:-2].max(), wf.amplitude[k].max() * 1e6)


def test_report_of_a_run_up_has_the_waterfall_against_speed(runup_result, tmp_path):
    pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
    pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")
    from gearrotor.io import load_model
    from gearrotor.plots.report import make_report

    train = load_model(runup_model_path(runup_result))
    rep = make_report(
        train,
        tmp_path / "r",
        analyses="modal",
        max_frequency=20000 * RPM,
        transient=runup_result[1],
    )
    page = rep.html.read_text(encoding="utf-8")
    assert 'id="fig-waterfall-speed"' in page and 'id="fig-waterfall"' in page
    assert "<h3 id='waterfall-speed'>Waterfall against speed</h3>" in page
    png = rep.directory / "transient_waterfall_speed.png"
    assert png in rep.figures and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    d = json.loads(rep.json.read_text())["transient"]["waterfall_vs_speed"]
    wf = speed_waterfall(runup_result[0])
    assert d == json.loads(json.dumps(wf.to_dict()))
    assert d["signal"] == "probe gear1_x" and d["orders"]["mesh"] == pytest.approx(30, rel=1e-3)


def runup_model_path(runup_result):
    return runup_result[1].with_name("runup.toml")
