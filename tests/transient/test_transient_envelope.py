"""The meshes' step envelope: the least and largest normal tooth force and the time out of
contact (and in back-flank contact) over each recording interval, tracked at every integration
step (kernels._envelope), so that the extremes and the contact-loss fraction do not depend on
where the recorded samples fall in the mesh cycle.

Checks: the envelope of a run recorded coarsely has the extremes of the same run recorded at
every step (the same steps: the recording does not change the integration), for RK4, the
classical modal RK4 and the exponential scheme; it bounds every recorded sample; the per-step
contact-loss time equals the samples' fraction when every step is recorded and converges as
the step halves; NetCDF round trip with units; old files without it fall back to the samples
and say so."""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.transient import RK4, ModalRK4, Save, transient
from gearrotor.analyses.transient.results import FROM_SAMPLES, FROM_STEPS, dataset_mesh_extremes
from gearrotor.studies.metrics import transient_metrics

VARIATION = {
    "meshes[0].variation.ka_ratio": "0.2",
    "meshes[0].variation.terms": "5",
    "meshes[0].variation.contact_ratio": "1.592",
}
BACKLASH = {**VARIATION, "meshes[0].backlash.value": "0.001 mm"}


def _envelope_range(res):
    return res.mesh_force_min[:, 0].min(), res.mesh_force_max[:, 0].max()


# (integrator, its step): RK4 on the full model, the classical modal RK4 (explicit steps, so
# that the coarse and the every-step runs take the same steps)
CASES = [
    pytest.param(lambda dt: RK4(dt=dt), 4e-6, id="rk4"),
    pytest.param(lambda dt: ModalRK4(dt=dt, exact_linear=False), 4e-6, id="modal_rk4"),
]


@pytest.mark.parametrize(("make", "dt"), CASES)
def test_envelope_extremes_are_those_of_every_step(make_gearbox, make, dt):
    """Recorded every 13 steps, the envelope's extremes equal (to round-off) the extremes of
    the same run recorded at every step; a record every 13 steps alone misses them. Round-off:
    the envelope evaluates the force in the integration kernel (modal: Φ_sel η, with its
    fastmath flags), the samples from the recorded outputs (Φ_out η): 1e-9 of the peak."""
    train = make_gearbox({**VARIATION, "meshes[0].backlash.value": "0.0254 mm"}, elements=10)
    coarse = transient(train, t_end=0.01, integrator=make(dt), save=Save(dt=13 * dt))
    fine = transient(train, t_end=0.01, integrator=make(dt), save=Save(dt=dt))
    assert coarse.stats.dt == fine.stats.dt == dt
    assert (coarse.stats.save_every, fine.stats.save_every) == (13, 1)
    np.testing.assert_array_equal(coarse.final_q, fine.final_q)  # the same steps
    F = fine.mesh_force[:, 0]
    tol = 1e-9 * np.abs(F).max()
    lo, hi = _envelope_range(coarse)
    assert lo == pytest.approx(F.min(), abs=tol)
    assert hi == pytest.approx(F.max(), abs=tol)
    # recorded at every step the envelope of each interval is its one sample
    np.testing.assert_allclose(fine.mesh_force_min[:, 0], F, rtol=0, atol=tol)
    np.testing.assert_allclose(fine.mesh_force_max[:, 0], F, rtol=0, atol=tol)
    # it bounds every recorded sample, and the samples alone miss the extremes (impacts)
    Fc = coarse.mesh_force[:, 0]
    assert np.all(coarse.mesh_force_min[:, 0] <= Fc + tol)
    assert np.all(coarse.mesh_force_max[:, 0] >= Fc - tol)
    assert Fc.max() < hi - 0.01 * (hi - lo)
    # each sample's interval is the envelope's row: the coarse rows are the fine ones grouped
    for j in (0, 5, len(coarse.time) - 2):
        rows = F[13 * j : 13 * (j + 1)]
        assert coarse.mesh_force_min[j, 0] == pytest.approx(rows.min(), abs=tol)
        assert coarse.mesh_force_max[j, 0] == pytest.approx(rows.max(), abs=tol)
    assert coarse.envelope_interval.sum() == pytest.approx(0.01, rel=1e-12)


@pytest.mark.parametrize(("make", "dt"), CASES)
def test_contact_loss_time_is_the_samples_fraction_at_every_step(make_gearbox, make, dt):
    """With backlash 2b = 2 µm (teeth separate and re-engage on both flanks every 1x cycle,
    test_transient_integrators.py), recorded at every step the time out of contact (and on the
    back flank) over the run is the fraction of samples separated (back-flank only), to one
    sample: the state is held over each step from its start (a left Riemann sum)."""
    train = make_gearbox(BACKLASH, elements=10)
    fine = transient(train, t_end=0.01, integrator=make(dt), save=Save(dt=dt))
    coarse = transient(train, t_end=0.01, integrator=make(dt), save=Save(dt=16 * dt))
    c = fine.contact[:, 0]
    assert {-1, 0, 1} <= set(np.unique(c))
    n = len(c)
    ext = fine.mesh_extremes()
    assert ext.source == FROM_STEPS
    assert abs(ext.loss[0] - np.mean(c == 0)) <= 1.0 / n
    assert abs(ext.back[0] - np.mean(c == -1)) <= 1.0 / n
    # the coarse record's accounting is the same steps': the same fractions
    assert coarse.mesh_extremes().loss[0] == pytest.approx(ext.loss[0], abs=1.0 / n)


def test_contact_loss_time_converges_as_the_step_halves(make_gearbox):
    """Per-step accounting of the time out of contact (RK4, backlash 2b = 2 µm, 0.02 s,
    recorded every 3.2e-5 s) at Δt = 8, 4, 2, 1 µs. Measured: 0.1236, 0.1244, 0.1245, 0.1245
    (changes 8e-4, 1e-4, < 5e-5: the resolution of a count of 1-µs steps over 0.02 s); the
    samples every 3.2e-5 s give 0.1216 at every step, 2.3 % off the converged time."""
    train = make_gearbox(BACKLASH, elements=10)
    runs = [
        transient(train, t_end=0.02, integrator=RK4(dt=dt), save=Save(dt=3.2e-5))
        for dt in (8e-6, 4e-6, 2e-6, 1e-6)
    ]
    f = [r.mesh_extremes().loss[0] for r in runs]
    d = np.abs(np.diff(f))
    assert 0.1 < f[-1] < 0.15
    assert d[1] < 0.5 * d[0] and d[2] <= d[1]  # the changes shrink as the step halves
    assert d[2] < 1e-4  # converged to 1e-4 of the run's time (two 1-µs steps)
    # the samples: the same at every step, off by more than the per-step changes
    samples = [np.mean(r.contact[:, 0] == 0) for r in runs]
    assert np.ptp(samples) < 1e-3 and abs(samples[-1] - f[-1]) > 10 * d[1]


def test_exponential_scheme_envelope_and_located_contact_changes(make_gearbox):
    """The exponential scheme cuts a step at each located contact change; each piece's time
    goes to its contact state (after a change the state it leads to). Its loss fraction at
    Δt and Δt/2 agrees with RK4's per-step accounting at 2 µs (0.0254 mm backlash, 0.03 s);
    the envelope bounds the samples and holds the extremes of a run recorded at every step."""
    train = make_gearbox({**VARIATION, "meshes[0].backlash.value": "0.0254 mm"}, elements=10)
    ref = transient(train, t_end=0.03, integrator=RK4(dt=2e-6), save=Save(dt=1e-4))
    dts = (2e-5, 1e-5)
    runs = [
        transient(train, t_end=0.03, integrator=ModalRK4(dt=dt), save=Save(dt=dt)) for dt in dts
    ]
    assert all(r.stats.scheme == "exponential" and r.stats.contact_events > 0 for r in runs)
    loss = [r.mesh_extremes().loss[0] for r in runs]
    assert loss[1] == pytest.approx(ref.mesh_extremes().loss[0], abs=0.02)
    assert abs(loss[0] - loss[1]) < 0.02
    coarse = transient(train, t_end=0.03, integrator=ModalRK4(dt=1e-5), save=Save(dt=8e-5))
    F = runs[1].mesh_force[:, 0]
    tol = 1e-9 * np.abs(F).max()
    lo, hi = _envelope_range(coarse)
    assert lo <= F.min() + tol and hi >= F.max() - tol
    Fc = coarse.mesh_force[:, 0]
    assert np.all(coarse.mesh_force_min[:, 0] <= Fc + tol)
    assert np.all(coarse.mesh_force_max[:, 0] >= Fc - tol)


def test_netcdf_metrics_and_old_files(make_gearbox, tmp_path):
    """The envelope goes to the NetCDF file with units; the study metrics take peak force and
    contact loss from it over their window (attribute source: every step); a file written
    before it existed (its variables dropped) falls back to the samples and says so."""
    import xarray as xr

    train = make_gearbox({**VARIATION, "meshes[0].backlash.value": "0.0254 mm"}, elements=10)
    res = transient(train, t_end=0.02, integrator=RK4(dt=4e-6), save=Save(dt=6.4e-5))
    path = res.save(tmp_path / "r.nc")
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    for name, unit in (
        ("mesh_force_min", "N"),
        ("mesh_force_max", "N"),
        ("mesh_contact_loss_time", "s"),
        ("mesh_back_contact_time", "s"),
        ("envelope_interval", "s"),
    ):
        assert ds[name].attrs["units"] == unit and ds[name].attrs["long_name"]
    n_probe = ds.sizes["probe"]
    kw = dict(
        probe_shaft=np.zeros(n_probe, int), mesh_teeth=np.array([50]), mesh_shaft=np.zeros(1, int)
    )
    window = 0.01
    m = transient_metrics(ds, window=window, **kw)
    w = ds["time"].values >= ds["time"].values[-1] - window - 1e-12
    peak = max(-ds["mesh_force_min"].values[w, 0].min(), ds["mesh_force_max"].values[w, 0].max())
    assert float(m["peak_mesh_force"][0]) == peak
    assert m["peak_mesh_force"].attrs["source"] == FROM_STEPS
    assert peak > np.abs(ds["mesh_force"].values[w, 0]).max()  # the samples miss the impacts
    loss = ds["mesh_contact_loss_time"].values[w, 0].sum() / ds["envelope_interval"].values[w].sum()
    assert float(m["contact_loss_fraction"][0]) == pytest.approx(loss, rel=1e-12)
    assert dataset_mesh_extremes(ds).loss[0] == pytest.approx(res.contact_loss_fraction[0])
    old = ds.drop_vars(
        [
            "mesh_force_min",
            "mesh_force_max",
            "mesh_contact_loss_time",
            "mesh_back_contact_time",
            "envelope_interval",
        ]
    )
    m_old = transient_metrics(old, window=window, **kw)
    assert m_old["peak_mesh_force"].attrs["source"] == FROM_SAMPLES
    assert float(m_old["peak_mesh_force"][0]) == np.abs(ds["mesh_force"].values[w, 0]).max()
    assert float(m_old["contact_loss_fraction"][0]) == np.mean(ds["contact"].values[w, 0] == 0)


def test_summary_reports_run_and_window(make_gearbox):
    """Summary JSON and table: the force range over the run and over the summary window, from
    every step."""
    train = make_gearbox(VARIATION, elements=10)
    res = transient(train, t_end=0.02, integrator=RK4(dt=4e-6), save=Save(dt=6.4e-5))
    m = res.summary()["meshes"]["mesh"]
    assert m["extremes_from"] == FROM_STEPS
    assert m["force_min_N"] == res.mesh_force_min.min()
    assert m["force_max_N"] == res.mesh_force_max.max()
    assert m["force_min_N"] <= m["window_force_min_N"] <= m["window_force_max_N"]
    assert m["window_force_max_N"] <= m["force_max_N"]
    assert m["window_s"] == res.time[-1] - res.time[0]  # the run is shorter than 0.5 s
    assert FROM_STEPS in res.table()
