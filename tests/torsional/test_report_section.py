"""The torsional section of ``gearrotor report`` (``--analyses torsional``): its numbers are the
torsional analyses' numbers (the same quantity shows the same number in the page, report.json
and the API), its verdict follows the margins, and the page stays self-contained."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")

from gearrotor.analyses.torsional import (  # noqa: E402
    interference,
    torsional_modes,
)
from gearrotor.plots.report import ANALYSES, make_report  # noqa: E402
from gearrotor.plots.report.sections.torsional import transient_duration  # noqa: E402
from torsional_helpers import driven_gear_pair  # noqa: E402

RPM = np.pi / 30


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    import matplotlib.pyplot as plt

    plt.close("all")  # figures other tests of this worker left open count towards pyplot's 20
    out = tmp_path_factory.mktemp("rep") / "tors"
    return make_report(driven_gear_pair(), out, analyses="torsional")


def test_not_run_by_default():
    assert "torsional" not in ANALYSES


def test_numbers_are_the_analyses_numbers(report):
    train = driven_gear_pair()
    data = json.loads(report.json.read_text())
    tors = data["torsional"]
    modes = torsional_modes(train)
    np.testing.assert_allclose(
        [m["frequency_hz"] for m in tors["modes"]], modes.frequency_hz, rtol=1e-12
    )
    inter = interference(modes, speed_range=(1500 * RPM, 1500 * RPM))
    assert tors["interference"]["passes"] == inter.passes
    assert len(tors["interference"]["crossings"]) == len(inter.crossings)
    verdict = [v for v in data["verdicts"] if "torsional" in v["check"]]
    assert len(verdict) == 1 and verdict[0]["ok"] == inter.passes
    # the transient: 20 s from rest (no event in the model), its section peaks
    tr = report.results["torsional"]["transient"]
    assert tr.time[-1] == pytest.approx(transient_duration(train))
    assert tors["transient"]["t_end_s"] == pytest.approx(20.0)
    peaks = [s["peak_torque_Nm"] for s in tors["transient"]["sections"]]
    np.testing.assert_allclose(peaks, [s["peak_torque_Nm"] for s in tr.section_table()])
    # the drive brings the train to the speed where 250 N·m balances the load (60 N·m at
    # 3750 rpm on the pinion, 150 N·m reflected at the drive's 1500 rpm: 1936 rpm, T ~ Ω²)
    final = tors["transient"]["final_speeds_rpm"]["g"]
    assert final == pytest.approx(1500 * np.sqrt(250 / 150), rel=0.01)
    # forced response: 1 % of the drive's rated torque at 1x and 2x
    assert "1 % of" in tors["response"]["excitation"]
    page = report.html.read_text(encoding="utf-8")
    peak = tors["response"]["peak"]
    assert f"{peak['shear_stress_Pa'] / 1e6:.3g} MPa" in page


def test_page_has_the_section_with_inline_figures(report):
    page = report.html.read_text(encoding="utf-8")
    assert "<section id='torsional'>" in page
    assert "Interference diagram" in page and "Torsional modes" in page
    # what the mesh damping_ratio refers to, and where each mode's damping comes from (as
    # `torsional modes` says it)
    assert "is the mesh damper&#x27;s ζ on its mesh mode" in page or (
        "is the mesh damper's ζ on its mesh mode" in page
    )
    assert "damped mostly by" in page
    # the section's figures inline (data URIs), nothing to fetch (other sections link theirs)
    section = page[page.index("<section id='torsional'>") :]
    section = section[: section.index("</section>")]
    assert not re.search(r"<img[^>]*\bsrc\s*=\s*['\"](?!data:)", section)
    assert page.count('title="torsional_') == 5  # the section's five figures
    names = {p.name for p in report.figures}
    assert {
        "torsional_modes.png",
        "torsional_interference.png",
        "torsional_response.png",
        "torsional_transient.png",
        "torsional_fatigue.png",
    } <= names


def test_transient_duration_covers_the_model_events(examples):
    from gearrotor.io import load_model

    train = load_model(examples / "motor_gearbox_compressor.toml")
    assert transient_duration(train) == pytest.approx(24.0)  # load step at 22 s, + 2 s
    assert transient_duration(driven_gear_pair()) == pytest.approx(20.0)
