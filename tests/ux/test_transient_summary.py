"""Issue 14 item 5: the transient summary states start, end, mean speed per shaft, says when
no torque drives the train, and its 1x is the spectra figure's 1x."""

from __future__ import annotations

import re

import pytest

from gearrotor import load_model
from gearrotor.analyses.transient import ModalRK4, transient
from gearrotor.model import Train

pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def coast(examples):
    # the flagship has no torques: with speed as a state it runs down from 6500 rpm
    return transient(load_model(examples / "unity_gearbox.toml"), t_end=0.1, integrator=ModalRK4())


def test_summary_says_coast_down_and_gives_start_end_mean(coast):
    s = coast.summary()
    assert s["drive"] == "coast-down"
    for k, a in enumerate(s["shafts"].values()):
        assert abs(a["speed_start_rpm"]) == pytest.approx(6500.0, rel=1e-9)
        # the end is the last sample (the shafts' torsional oscillation rides on the run-down)
        assert a["speed_end_rpm"] == coast.shaft_speed_rpm[-1, k]
        assert min(a["speed_min_rpm"], a["speed_max_rpm"]) <= a["speed_mean_rpm"]
    table = coast.table()
    assert "no driving torque: coast-down" in table
    assert "start rpm" in table and "end rpm" in table and "1x cpm" in table


def test_driven_train_is_not_called_a_coast_down(examples):
    spec = load_model(examples / "unity_gearbox.toml").model_dump()
    spec["torques"] = [{"shaft": "shaft1", "node": 10, "value": 100.0}]
    train = Train.model_validate(spec)
    res = transient(train, t_end=0.02, integrator=ModalRK4())
    assert res.drive() == "torques"
    assert "coast-down" not in res.table()


def test_spectra_title_uses_the_summary_1x(coast):
    from gearrotor.analyses.transient.plots import plot_spectra

    fig = plot_spectra(coast)
    title = fig._suptitle.get_text()
    one_x = float(re.search(r"1x = ([\d.]+) cpm", title).group(1))
    shaft0 = coast.summary()["shafts"][coast.shaft_names[0]]
    assert one_x == pytest.approx(round(shaft0["speed_1x_rpm"]), abs=0.5)
    assert f"{shaft0['speed_1x_rpm']:.2f}" in coast.table()


def test_transient_plot_says_what_it_does(coast, tmp_path):
    import subprocess
    import sys

    nc = tmp_path / "run.nc"
    coast.save(nc)
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "gearrotor",
            "transient-plot",
            str(nc),
            "--output",
            str(tmp_path / "figs"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    assert "writing the standard figures" in p.stderr  # said before the ~10 s of plotting
    assert len(p.stdout.splitlines()) >= 5
