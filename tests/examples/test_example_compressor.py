"""Worked example: the power turbine – compressor gearbox (SPEC 6.3).

* every ``gearrotor ...`` command of docs/examples/compressor_gearbox.md runs as written
  (``--format json``; transients shortened to ``--t-end 0.05``, plots and outputs to a
  temporary folder); the one the doc says diverges exits with status 3 (slow);
* the modal finding: a pinion lateral-torsional mode at 10x (57,000 cpm);
* the transient findings: 1x at the blind end does not change with Ka/Kg (< 1 %); at rated load
  the 42x (mesh) component grows in proportion to Ka/Kg and the 10x band grows from the noise;
  the modal integrator agrees with RK4 at Δt = 1e-6 s;
* section 7, the seed's finding: with the thrust bearing on the pinion and no mesh damping the
  10x + 32x pair leads the Floquet exponents at 5,700 rpm and the seed's transient shows the
  10x line growing to about 1 µm at Ka/Kg = 0.75 while 1x stays within a few per cent (slow).

Numbers are regression values of this representative model. Tolerances: the mode frequency
±0.5 % and log dec ±0.03 (the bearing tables are solved on a 24x6 grid per pad at assembly;
the model has no other approximation that varies between runs); 1x changes with Ka/Kg by
0.1 % over 0.5 s (0.2 % allowed: 1 %), the 42x amplitude is linear in Ka/Kg within 1 %.
"""

from __future__ import annotations

import json
import sys

import pytest

from doc_examples import ROOT, doc_commands, find_run, run

DOC = ROOT / "docs" / "examples" / "compressor_gearbox.md"
T_END = "0.05"


@pytest.fixture(scope="module")
def doc_runs(tmp_path_factory) -> list[tuple[list[str], dict | None]]:
    tmp = tmp_path_factory.mktemp("compressor")
    out = []
    for c, comment in doc_commands(DOC):
        c = [str(tmp / a[4:]) if a.startswith("out/") else a for a in c]
        if "--t-end" in c:
            c[c.index("--t-end") + 1] = T_END
        if "--n-speeds" in c:
            c[c.index("--n-speeds") + 1] = "9"
        if c[0] == "transient-plot":
            run([sys.executable, "-m", "gearrotor", *c])
            out.append((c, None))
            continue
        if "--plot" in c and c[0] != "modal":
            k = c.index("--plot")
            c = c[:k] + c[k + 2 :]
        if "diverges" in comment:
            continue  # test_no_mesh_damping_diverges (slow) runs it as written
        r = run([sys.executable, "-m", "gearrotor", *c, "--format", "json"])
        out.append((c, json.loads(r.stdout)))
    return out


def test_doc_commands_run(doc_runs):
    kinds = [c[0] for c, _ in doc_runs]
    assert kinds.count("bearing") == 2 and kinds.count("transient") == 5
    assert {"modal", "campbell", "transient-plot"} <= set(kinds)


def test_pinion_mode_at_10x(doc_runs):
    res = find_run(doc_runs, "modal", without=("pad_dynamics",))
    modes = [m for m in res["modes"] if 9.5 <= m["frequency_rpm"] / 5700 <= 10.5]
    assert len(modes) == 1, modes
    m = modes[0]
    # with the 2 % mesh damper (modal uses damping_ratio since issue 14): 10.18x; without it
    # 56,974 cpm = 10.00x, the seed's ~57,000 cpm (the doc's tuning)
    assert m["frequency_rpm"] == pytest.approx(58009, rel=5e-3)
    assert m["log_dec"] == pytest.approx(0.203, abs=0.03)
    assert m["type"] == "L-T" and m["stable"]
    assert m["whirl_per_shaft"]["pinion"] == "B"
    assert m["energy_torsional"] > 0.5


def test_tilting_pad_bearings(doc_runs):
    """Rated-load reaction on each journal: synchronously reduced coefficients, a
    positive-definite direct stiffness of order 1e9 N/m and a safe minimum film."""
    for name, kyy in (("pinion", 3.195e9), ("bull", 2.701e9)):
        res = find_run(doc_runs, "bearing", f"compressor_{name}")
        rated = res["cases"][0]
        assert rated["name"] == "rated load"
        assert rated["kxx_N_per_m"] > 1e9 and rated["cxx_N_s_per_m"] > 1e6
        assert rated["kyy_N_per_m"] == pytest.approx(kyy, rel=0.01)
        assert rated["min_film_m"] > 50e-6


def test_seed_case_1x_does_not_change_with_ka(doc_runs):
    ka0 = find_run(doc_runs, "transient", without=("--set", "rk4"))
    ka75 = find_run(doc_runs, "transient", "ka_ratio=0.75", without=("rk4", "damping_ratio=0"))
    for d in ("x_1x_um", "y_1x_um"):
        a0 = ka0["nodes"]["pinion[0]"][d]
        a75 = ka75["nodes"]["pinion[0]"][d]
        assert 1.0 < a0 < 3.0
        assert abs(a75 / a0 - 1) < 0.01, (d, a0, a75)


def test_modal_integrator_matches_rk4(doc_runs):
    modal_ = find_run(doc_runs, "transient", "ka_ratio=0.75", without=("rk4", "damping_ratio=0"))
    rk4 = find_run(doc_runs, "transient", "rk4")
    assert rk4["dt_s"] == pytest.approx(1e-6)
    for d in ("x_1x_um", "y_1x_um"):
        a, b = modal_["nodes"]["pinion[0]"][d], rk4["nodes"]["pinion[0]"][d]
        assert a == pytest.approx(b, rel=0.005), d


def test_floquet_finds_the_10x_pair(doc_runs):
    """Section 5: with 2 % mesh damping every exponent stays within its convergence tolerance
    of zero or below; without mesh damping the 13,678 + 225,581 cpm pair grows at 23.3 1/s at
    Ka/Kg = 0.25 (the transient of section 4 measured 23.07 1/s) and the 10x partner at
    182,400 cpm (32x) becomes unstable between Ka/Kg = 0.25 and 0.5 and grows faster at 0.75.
    Regression values of this model, 1 % (the bearings are solved on a grid at assembly)."""
    damped = find_run(doc_runs, "floquet", "--ka", without=("damping_ratio", "--speeds"))
    assert all(c["stable"] for c in damped["cases"])
    free = find_run(doc_runs, "floquet", "damping_ratio=0", without=("thrust_bearings",))
    by_ka = {c["ka_ratio"][0]: c for c in free["cases"]}
    assert by_ka[0.25]["exponents"][0]["growth_1_s"] == pytest.approx(23.31, rel=0.01)
    assert by_ka[0.25]["exponents"][0]["mode_cpm"] == pytest.approx(225_581, rel=0.005)

    assert _pair_growth(by_ka[0.25]) < 0 < _pair_growth(by_ka[0.5]) < _pair_growth(by_ka[0.75])
    sweep = find_run(doc_runs, "floquet", "--speeds")
    assert len(sweep["cases"]) == 5 and all(c["stable"] for c in sweep["cases"])


def _pair_growth(case: dict) -> float:
    """Largest exponent carried by the pinion's 32x torsional mode (182,396 cpm undamped)."""
    rows = [e for e in case["exponents"] if abs(e["mode_cpm"] - 182_396) < 1_000]
    return max(e["growth_1_s"] for e in rows)


def test_located_pinion_floquet_10x_pair_leads(doc_runs):
    """Section 7: thrust bearing on the pinion, no mesh damping. The 10x + 32x pair is stable
    at Ka/Kg = 0.25 and leads at 0.5 and 0.75 (6.99 and 18.22 1/s); the axial pair falls back.
    Regression values of this model, 1 % (the bearing tables are solved at assembly)."""
    located = find_run(doc_runs, "floquet", "thrust_bearings[0].shaft=pinion")
    by_ka = {c["ka_ratio"][0]: c for c in located["cases"]}
    assert _pair_growth(by_ka[0.25]) < 0
    assert by_ka[0.25]["stable"]
    for ka, rate in ((0.5, 6.99), (0.75, 18.22)):
        top = by_ka[ka]["exponents"][0]
        assert abs(top["mode_cpm"] - 182_396) < 1_000, top  # the pair leads
        assert top["growth_1_s"] == pytest.approx(rate, rel=0.01)


@pytest.mark.slow
def test_located_pinion_transient_10x_grows_1x_stays():
    """Section 7's two transients as written (0.5 s each, about 10 s): at Ka/Kg = 0 the
    blind-end spectrum has no line near 10x; at 0.75 the strongest line after 1x is at
    10.02x, growing at the Floquet rate (18.2 1/s; measured 19.1, the spectral estimate over
    the last 0.5 s of a transient with speed fluctuation: 10 % allowed) to several µm at
    0.5 s (measured 7.5 µm), and 1x changes by less than 5 % (measured -2.3 % in x, -3.2 % in
    y over the whole 0.5 s)."""
    cmds = [c for c, _ in doc_commands(DOC) if c[0] == "transient" and "thrust_bearings" in str(c)]
    assert len(cmds) == 2
    out = {}
    for c in cmds:
        r = run([sys.executable, "-m", "gearrotor", *c, "--format", "json"])
        ka = 0.75 if "meshes[0].variation.ka_ratio=0.75" in c else 0.0
        out[ka] = json.loads(r.stdout)["nodes"]["pinion[0]"]
    near_10x = [ln for ln in out[0.0]["x_lines"] if abs(ln["order"] - 10) < 0.5]
    assert not near_10x, out[0.0]["x_lines"]
    lines = out[0.75]["x_lines"]
    assert lines[0]["order"] == pytest.approx(1.0, abs=0.01)
    assert abs(lines[0]["growth_1_s"]) < 0.5
    ten = lines[1]
    assert ten["order"] == pytest.approx(10.02, abs=0.05)
    assert ten["growth_1_s"] == pytest.approx(18.22, rel=0.1)
    assert 2.0 < ten["um_end"] < 20.0
    for d in ("x_1x_um", "y_1x_um"):
        assert abs(out[0.75][d] / out[0.0][d] - 1) < 0.05, d


@pytest.mark.slow
def test_no_mesh_damping_diverges():
    """The doc's undamped command, as written (0.5 s; diverges at 0.21 s, about 15 s)."""
    cmds = [c for c, comment in doc_commands(DOC) if "diverges" in comment]
    assert len(cmds) == 1
    c = cmds[0]
    assert "damping_ratio=0" in " ".join(c) and c[c.index("--t-end") + 1] == "0.5"
    r = run([sys.executable, "-m", "gearrotor", *c, "--format", "json"], status=3)
    assert "diverged at t = 0.2" in r.stderr


RATED = """
import json, sys
import numpy as np
sys.path.insert(0, "examples/scripts")
import compressor_gearbox as cg
from gearrotor.analyses.transient import RK4, ModalRK4, Save, transient

out = {}
for ka in (0.0, 0.25, 0.75):
    r = transient(cg.model(ka, None, True), t_end=0.5, initial="static",
                  integrator=ModalRK4(static_correction=True))
    out[str(ka)] = cg.metrics(r, 0.25, cg.probe_spectra(r, 0.25))
r = transient(cg.model(0.75, None, True), t_end=0.1, initial="static",
              integrator=RK4(dt=1e-6))
run, steady = r.mesh_extremes(), r.mesh_extremes(0.05)
out["rk4_force_N"] = [float(run.least[0]), float(run.largest[0])]
out["rk4_steady_force_N"] = [float(steady.least[0]), float(steady.largest[0])]
out["rk4_samples_N"] = [float(r.mesh_force[:, 0].min()), float(r.mesh_force[:, 0].max())]
out["rk4_min_at_s"] = float(r.time[np.argmin(r.mesh_force_min[:, 0])])
print(json.dumps(out))
"""


@pytest.mark.slow
def test_rated_load_mesh_component_grows_1x_stays(tmp_path):
    """Rated load, 0.5 s as in the seed (about 10 s on one process): 1x unchanged, 42x ∝
    Ka/Kg, the 10x band rises from the noise by orders of magnitude but stays at picometres.
    The three 0.5-s runs use the modal integrator with its static-correction shapes, which
    agrees with RK4 at Δt = 1e-6 s at rated load (1x within 0.04 %, mesh-frequency force within
    0.02 %: tests/transient/test_transient_compressor.py); measured against the doc's RK4
    table: 1x within 0.06 %, 42x 1.1266 / 3.4324 µm against 1.125 / 3.427 (0.15 %), 10x band
    9.4e-8 / 4.5e-5 µm against 7.6e-8 / 4.6e-5. (Shorter runs do not do: over 0.1 s the start
    transient leaks into the 1x fit by 2 %.) The teeth staying in contact at Ka/Kg = 0.75 is
    checked with RK4 itself over the first 0.1 s, its force range taken at every step (the
    step envelope, 4 samples per mesh period recorded): the start transient, where the force
    dips lowest (7.24 kN, in the interval from 0.88 ms), and 0.05 s of steady mesh cycles
    (26.2 … 327.6 kN); the recorded samples alone give 22.9 … 332.2 kN over the run (recorded
    every 2e-6 s: 7.2 kN and 26 … 328 kN). The modal basis, without the higher mesh
    harmonics' local compliance, swings wider: 11 … 347 kN, so its peaks are not used here."""
    script = tmp_path / "rated.py"
    script.write_text(RATED)
    r = json.loads(run([sys.executable, str(script)]).stdout.splitlines()[-1])
    m0, m25, m75 = r["0.0"], r["0.25"], r["0.75"]
    for d in ("x_1x_um", "y_1x_um"):
        assert abs(m75[d] / m0[d] - 1) < 0.01, d  # measured: +0.03 %, -0.03 %
    assert m0["x_42x_um"] < 0.01
    assert m25["x_42x_um"] == pytest.approx(1.125, rel=0.02)  # the doc's RK4 value
    assert m75["x_42x_um"] / m25["x_42x_um"] == pytest.approx(3.0, rel=0.02)
    assert m75["x_10x_run_um"] > 100 * m0["x_10x_run_um"]  # measured: 480x (RK4: 600x)
    assert m75["x_10x_run_um"] < 1e-3  # below a nanometre: not a vibration anyone would see
    f_min, f_max = r["rk4_force_N"]
    assert 2e3 < f_min < 15e3  # teeth stay in contact (measured 7.24 kN)
    assert r["rk4_min_at_s"] < 2e-3  # in the start transient
    assert f_max == pytest.approx(339.2e3, rel=0.02)
    lo, hi = r["rk4_steady_force_N"]  # steady mesh cycles, t >= 0.05 s
    assert lo == pytest.approx(26.2e3, rel=0.03) and hi == pytest.approx(327.6e3, rel=0.01)
    s_lo, s_hi = r["rk4_samples_N"]  # the samples miss the dip and the peak
    assert s_lo > f_min + 10e3 and s_hi < f_max
