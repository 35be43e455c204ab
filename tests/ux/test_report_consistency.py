"""Issue 14 items 6 and 7 and issue 22 (the HTML report): one mode numbering in the report's
checks and tables, the orbit at the operating speed, pk-pk beside pk-pk, no Python booleans in
tables, a default frequency range that reaches every mode an excitation can reach (and says
so), one vocabulary for the modes the model cannot damp, no "pass" beside a failed row, and the
same number for the same quantity in table, JSON, figure and summary."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest

from gearrotor import load_model
from gearrotor.analyses import unbalance_response

pytest.importorskip("plotly")
pytest.importorskip("matplotlib")
RPM = np.pi / 30


@pytest.fixture(scope="module")
def full(examples, tmp_path_factory):
    """The flagship's default report (modal, Campbell; the default frequency range)."""
    from gearrotor.plots.report import make_report

    out = tmp_path_factory.mktemp("rep") / "r"
    rep = make_report(
        load_model(examples / "unity_gearbox.toml"),
        out,
        analyses=("modal", "campbell"),
        n_campbell=3,
    )
    return rep, json.loads((out / "report.json").read_text()), (out / "report.html").read_text()


@pytest.fixture(scope="module")
def report(full):
    return full[1], full[2]


def _section(html: str, sid: str) -> str:
    return html.split(f"<section id='{sid}'>")[1].split("</section>")[0]


def test_default_range_reaches_every_mode_an_excitation_can_reach(report):
    # issue 22: the flagship's lightly damped torsional mode at 215,670 cpm (log dec 0.0099,
    # docs/examples/unity_gearbox.md) lies 10.6 % above the mesh frequency 30 × 6500 = 195,000
    # cpm; the former default 1.1 × mesh frequency (214,500 cpm) cut it off. The default is now
    # the highest excitation at the top operating speed + API 617's largest separation margin
    # (26 %), × 1.1 headroom: 195,000 × 1.26 × 1.1 = 270,270 cpm
    summary, html = report
    inputs = summary["inputs"]
    teeth = load_model_teeth()
    assert inputs["max_frequency_rpm"] == pytest.approx(1.1 * 1.26 * teeth * 6500, rel=1e-9)
    assert "separation margin" in inputs["max_frequency_basis"]
    assert f"Modes and Campbell diagram up to {inputs['max_frequency_rpm']:,.0f} cpm" in html
    rows = summary["modal"]["modes"]
    (t,) = [r for r in rows if abs(r["frequency_rpm"] - 215670) < 100]
    assert t["type"] == "T" and t["log_dec"] == pytest.approx(0.0099, abs=5e-5)
    # ... and the summary shows it, with its numbers, beside the model's missing damping
    line = next(v for v in summary["verdicts"] if v["key"] == "not_judged_operating_speed")
    assert f"mode {t['index']} (215,670 cpm, T) log dec 0.0099" in line["detail"]
    assert "no torsional damping in the model" in line["detail"]
    assert line["result"] == "not judged"


def test_default_range_of_other_trains(examples):
    # the top operating speed is the MCS when the model states one (steam turbine: 11,340 rpm),
    # and a train without gears keeps at least 5 × that speed (1x, 2x with margin are lower)
    from gearrotor.assembly import assemble
    from gearrotor.plots.report.build import _default_max_frequency

    asm = assemble(load_model(examples / "steam_turbine_gearbox.toml"))
    mcs = float(asm.train.max_continuous_speed)
    fmax, why = _default_max_frequency(asm, mcs, None)
    highest = max(
        max(m.teeth[0] * abs(asm.speed_ratio[m.shafts[0]]) for m in asm.meshes),
        2 * max(abs(asm.speed_ratio)),
    )
    assert fmax == pytest.approx(1.1 * 1.26 * highest * mcs, rel=1e-12)
    assert "11,340 rpm" in why
    single = assemble(load_model(examples / "unity_gearbox_single_shaft.toml"))
    w = 6500 * RPM
    assert _default_max_frequency(single, w, None)[0] == pytest.approx(5 * w)
    assert _default_max_frequency(single, w, 123.0) == (123.0, "as given")


def test_summary_never_passes_beside_a_failed_row(report):
    # issue 22: the summary said "stability over the Campbell range: pass" beside rows 20, 21,
    # 26, 27, 32 marked FAIL (undamped torsional and axial modes of a model without torsional
    # or axial damping). Such rows are now "not judged" with the reason, and a check's line is
    # FAIL whenever one of its rows is.
    summary, html = report
    stab = summary["stability"]
    assert stab["undamped_dofs"] == ["axial", "torsional"]
    verdicts = {v["key"]: v for v in summary["verdicts"]}
    rows = stab["campbell"]["modes"]
    failed = [d for d in rows if d["result"] == "FAIL"]
    assert (verdicts["stability_campbell_range"]["result"] == "pass") == (not failed)
    table = _section(html, "stability")
    n_fail_badges = table.count('<span class="fail">FAIL</span>')
    assert n_fail_badges == len(failed) + (not stab["modal"]["stable"])
    if verdicts["stability_campbell_range"]["result"] == "pass":
        assert n_fail_badges == 0
    judged_out = [d for d in rows if not d["judged"] and d["min_log_dec"] < 0.1]
    assert len(judged_out) == 6  # modes 20, 21, 32, 33 (T), 26, 27 (A)
    for d in judged_out:
        assert d["result"] == "not judged"
        kind = {"T": "torsional", "A": "axial"}[d["type"]]
        assert d["status"] == f"no {kind} damping in the model"


def test_one_vocabulary_in_tables_json_figures_and_summary(full):
    # the status of a mode is the same words in the modes table, report.json (modes and
    # stability), the 3-D mode-shape titles, the mode-shape PNG and the summary
    import matplotlib.pyplot as plt

    from gearrotor.plots import plot_mode_shapes

    rep, summary, html = full
    rows = summary["modal"]["modes"]
    modes_table = _section(html, "modes")
    nj = {d["mode"]: d["status"] for d in summary["stability"]["modal"]["not_judged_modes"]}
    assert set(nj) == {20, 21, 26, 27, 32, 33}
    for i, st in nj.items():
        assert rows[i]["status"] == st
        assert f"<td class='l'>{st}</td>" in modes_table
        assert f"type {rows[i]['type']}, {st}" in html  # the 3-D mode-shape figure's title
    for r in rows:
        assert r["status"] in {"stable", "over-damped"} | set(nj.values()), r
    detail = " ".join(v["detail"] for v in summary["verdicts"])
    for st in set(nj.values()):
        assert st in detail
    fig = plot_mode_shapes(rep.modal, modes=[33], statuses=[r["status"] for r in rows])
    assert "no torsional damping in the model" in fig.axes[0].get_ylabel()
    plt.close(fig)


def test_crossing_and_stability_tables_number_modes_alike(full):
    # issue 22: the crossing table numbered modes by Campbell track, the stability table by
    # the modal table's row: one numbering, the modal table's, in both and in report.json
    rep, summary, html = full
    by_track = {d["track"]: d["mode"] for d in summary["stability"]["campbell"]["modes"]}
    crossings = summary["campbell"]["crossings"]
    assert crossings
    camp_html = _section(html, "campbell")
    rows = summary["modal"]["modes"]
    for c in crossings:
        assert c["mode"] == by_track[c["track"]]
        # the row's frequency at 6500 rpm is the crossing's, within the speed dependence of
        # these modes (< 0.1 % over 0..8125 rpm, docs/examples/unity_gearbox.md)
        assert rows[c["mode"]]["frequency_rpm"] == pytest.approx(c["frequency_rpm"], rel=2e-3)
        assert (
            f"<tr><td>mode {c['mode']}</td><td class='l'>{c['order']}</td>"
            f"<td>{c['speed_rpm']:.0f}</td><td>{c['frequency_rpm']:.0f}</td>"
        ) in camp_html


def test_same_number_in_table_json_figure_and_summary(full):
    import matplotlib.pyplot as plt

    from gearrotor.plots import plot_campbell
    from gearrotor.plots.report.sections.campbell import campbell_figure

    rep, summary, html = full
    # the frequency range: report.json, the note, the summary's check, both Campbell figures
    fmax = summary["inputs"]["max_frequency_rpm"]
    assert f"up to {fmax:,.0f} cpm" in html
    assert f"up to {fmax:,.0f} cpm" in summary["verdicts"][0]["check"]
    fig = campbell_figure(rep.campbell, max_frequency=fmax * RPM)
    assert fig.layout.yaxis.range[1] == pytest.approx(fmax)
    png = plot_campbell(rep.campbell, max_frequency=fmax * RPM)
    assert png.axes[0].get_ylim()[1] == pytest.approx(fmax)
    plt.close(png)
    # the lowest log dec of a lateral mode: modes table row, stability table, summary
    low = summary["stability"]["modal"]["lowest_log_dec"]
    row = summary["modal"]["modes"][low["mode"]]
    assert row["log_dec"] == low["log_dec"] and row["frequency_rpm"] == low["frequency_rpm"]
    assert f"{low['log_dec']:.4g} (mode {low['mode']}, {low['frequency_rpm']:.0f} cpm" in html
    assert (
        f"{low['log_dec']:.3g} (mode {low['mode']}, {low['frequency_rpm']:,.0f} cpm"
        in (summary["verdicts"][0]["detail"])
    )


def load_model_teeth() -> int:
    from pathlib import Path

    train = load_model(Path(__file__).resolve().parents[2] / "examples" / "unity_gearbox.toml")
    return train.meshes[0].gear.teeth


def test_least_stable_mode_has_one_number(report):
    summary, _ = report
    stab = summary["stability"]
    low = stab["modal"]["lowest_log_dec"]
    # every Campbell track named by a mode number is that row of the modal table at the
    # operating speed (same frequency there)
    camp = stab["campbell"]
    named = [d for d in camp["modes"] if d["mode"] is not None]
    assert named, "the operating speed is a Campbell sweep point"
    rows = summary["modal"]["modes"]
    for d in named:  # a track is named by its row of the modal table (an elastic mode)
        assert rows[d["mode"]]["class"] != "over-damped"
    # the modal check and the Campbell check speak of the lowest modal mode by the same number
    verdicts = " ".join(v["detail"] for v in summary["verdicts"])
    nums = {int(n) for n in re.findall(r"mode (\d+)", verdicts)}
    assert low["mode"] in nums
    assert nums <= {r["index"] for r in rows}


def test_unbalance_table_pk_pk_and_words(examples):
    res = unbalance_response(
        load_model(examples / "unity_gearbox.toml"),
        speeds=np.linspace(5000, 7500, 26) * RPM,
        operating_range=(5800 * RPM, 7200 * RPM),
    )
    table = res.table()
    assert "False" not in table and "True" not in table
    p = res.probes[0]
    peak_pp = 2 * p.amplitude.max() * 1e6
    assert f"{peak_pp:.3f}" in table.splitlines()[1]  # pk-pk beside the pk-pk limit
    assert "µm pk-pk" in table.splitlines()[0] and "0-pk" not in table.splitlines()[0]


def test_cli_orbits_at_the_end_of_the_operating_range(examples):
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "gearrotor",
            "unbalance",
            str(examples / "unity_gearbox.toml"),
            "--operating-range",
            "5800,7200",
            "--n-speeds",
            "40",
            "--format",
            "json",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    speeds = json.loads(p.stdout)["speeds_rpm"]
    assert any(abs(s - 7200) < 1e-6 for s in speeds) and any(abs(s - 5800) < 1e-6 for s in speeds)
