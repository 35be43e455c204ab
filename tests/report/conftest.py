"""A run-up for the report tests: the unity gearbox (SPEC 6.1) started at 3000 rpm with a
10 N·m driving torque on shaft 1 and no load, 0.6 s with the modal integrator (~1 s): the train
accelerates to about 5800 rpm (J ≈ 0.0205 kg·m² for the two solid shafts, so about
4700 rpm/s)."""

from __future__ import annotations

import pytest

RUNUP_T_END = 0.6


def runup_model_text(examples) -> str:
    text = (examples / "unity_gearbox.toml").read_text()
    text = text.replace('speed = "6500 rpm"', 'speed = "3000 rpm"')
    text = text.replace('speed = "-6500 rpm"', 'speed = "-3000 rpm"')
    return text + '\n[[torques]]\nshaft = "shaft1"\nnode = 10\nvalue = "10 N*m"\n'


@pytest.fixture(scope="session")
def runup_result(tmp_path_factory, examples):
    """(TransientResult, path of its NetCDF file) of the run-up."""
    pytest.importorskip("xarray", reason="transient results need xarray (gearrotor[results])")
    pytest.importorskip("h5netcdf", reason="transient results need h5netcdf (gearrotor[results])")
    from gearrotor.analyses.transient import ModalRK4, transient
    from gearrotor.io import load_model

    d = tmp_path_factory.mktemp("runup")
    model = d / "runup.toml"
    model.write_text(runup_model_text(examples))
    res = transient(load_model(model), t_end=RUNUP_T_END, integrator=ModalRK4())
    return res, res.save(d / "runup.nc")
