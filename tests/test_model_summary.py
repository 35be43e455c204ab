"""``gearrotor show``: the model summary (rigid-body properties, element fineness, mesh
convergence) and the drawings, against closed forms and the examples' own model files."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg as sl

import gearrotor as gr
from gearrotor.analyses.model_summary import COARSE_ERROR, element_error, summarize
from gearrotor.elements import ShaftElement
from gearrotor.plots.model_view import model_parts, plot_model

EXAMPLES = [
    "unity_gearbox",
    "steam_turbine_gearbox",
    "compressor_gearbox",
    "motor_gearbox_compressor",
]


def _shaft(elements=8, disks=(), bearings=((0,), (None,))):
    return gr.Train.model_validate(
        {
            "name": "beam",
            "materials": {"steel": {"E": 2.1e11, "poisson": 0.3, "density": 7800.0}},
            "shafts": [
                {
                    "name": "s",
                    "material": "steel",
                    "sections": [
                        {
                            "length": 1.2,
                            "outer_diameter": 0.08,
                            "inner_diameter": 0.02,
                            "elements": elements,
                        }
                    ],
                    "disks": list(disks),
                }
            ],
            "bearings": [
                {"shaft": "s", "node": 0, "k": 1e8},
                {"shaft": "s", "node": elements, "k": 1e8},
            ],
        }
    )


def test_rigid_properties_of_a_tube_with_a_disk():
    """Mass, polar and transverse inertia of a hollow tube plus a disk off centre equal the
    rigid-body formulas: m = ρAL, Ip = m(D² + d²)/8, It = m(L²/12 + (D² + d²)/16) about the
    centre, plus the disk by the parallel-axis theorem (the consistent mass matrix reproduces
    rigid motion exactly)."""
    md, ipd, itd = 40.0, 0.9, 0.5
    train = _shaft(disks=[{"node": 2, "mass": md, "polar": ipd, "transverse": itd}])
    s = summarize(train).shafts[0]
    L, D, d, rho = 1.2, 0.08, 0.02, 7800.0
    m = rho * np.pi / 4 * (D**2 - d**2) * L
    zd = 2 * L / 8
    zc = (m * L / 2 + md * zd) / (m + md)
    it = m * (L**2 / 12 + (D**2 + d**2) / 16) + m * (L / 2 - zc) ** 2 + itd + md * (zd - zc) ** 2
    assert s.mass == pytest.approx(m + md, rel=1e-12)
    assert s.center_of_mass == pytest.approx(zc, rel=1e-12)
    assert s.polar_inertia == pytest.approx(m * (D**2 + d**2) / 8 + ipd, rel=1e-12)
    assert s.transverse_inertia == pytest.approx(it, rel=1e-12)
    assert s.bearing_span == pytest.approx(L)
    assert s.n_dof == 6 * 9


def _beam_errors(n_elements: int, diameter: float, modes: int, plane=(0, 4, 6, 10)):
    """Relative frequency errors of the first modes of a pinned-pinned 1 m steel beam with
    ``n_elements`` against an 800-element solution (``plane``: the bending DOFs x, θy, or a
    rod's DOF pair for free-free torsion/axial motion), the element and the exact ω."""

    def freqs(n):
        el = ShaftElement(
            length=1.0 / n,
            outer_diameter=diameter,
            inner_diameter=0.0,
            E=2e11,
            shear_modulus=2e11 / 2.6,
            density=7800.0,
        )
        idx = list(plane)
        per = len(idx) // 2
        me, ke = el.M()[np.ix_(idx, idx)], el.K()[np.ix_(idx, idx)]
        size = per * (n + 1)
        M = np.zeros((size, size))
        K = np.zeros_like(M)
        for e in range(n):
            d = slice(per * e, per * e + 2 * per)
            M[d, d] += me
            K[d, d] += ke
        if per == 2:  # pinned-pinned bending
            keep = [i for i in range(size) if i not in (0, 2 * n)]
        else:  # free-free rod: drop the rigid mode
            keep = list(range(size))
        w2 = sl.eigh(K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True)
        w = np.sqrt(np.clip(w2, 0, None))
        return (w if per == 2 else w[1:]), el

    ref, _ = freqs(800)
    w, el = freqs(n_elements)
    return w[:modes] / ref[:modes] - 1, el, ref[:modes]


@pytest.mark.parametrize("diameter", [0.02, 0.05, 0.1, 0.2])
@pytest.mark.parametrize("n", [8, 32])
def test_bending_estimate_bounds_the_measured_error(n, diameter):
    """The bending estimate (kh)⁴(1 + 3.5Φ)/1000 is an upper bound within a factor 1.5 of the
    measured discretisation error, from slender (Φ = 0.05) to very thick elements (Φ = 86),
    where the error falls as h² only."""
    err, el, w = _beam_errors(n, diameter, modes=4)
    est = np.array([element_error(el, x)[2] for x in w])
    assert np.all(err > 0)
    assert np.all(est >= err) and np.all(est <= 1.5 * err)


@pytest.mark.parametrize("plane", [(5, 11), (2, 8)], ids=["torsion", "axial"])
def test_rod_estimate_matches_the_measured_error(plane):
    """Linear rod elements with consistent mass: ω_h² = ω²(1 + (kh)²/12 + ...), so the
    relative error is (kh)²/24 (within 10 % at kh ≤ 0.8)."""
    err, el, w = _beam_errors(16, 0.05, modes=4, plane=plane)
    c = np.sqrt((el.shear_modulus if plane[0] == 5 else el.E) / el.density)
    kh = w / c * el.length
    assert np.all(kh < 0.8)
    np.testing.assert_allclose(err, kh**2 / 24, rtol=0.1)
    for x in w:  # the summary's estimate for this element is at least the rod's own
        assert element_error(el, x)[2] >= (x / c * el.length) ** 2 / 24 * (1 - 1e-12)


def test_coarse_mesh_is_flagged_and_convergence_confirms_it():
    """A 2-element shaft is flagged for a range holding several bending modes and halving its
    elements moves them by more than the flag's threshold; a 64-element shaft is not flagged
    and halving moves no mode by more than the threshold."""
    coarse = summarize(_shaft(elements=2), max_frequency=2 * np.pi * 3000, convergence=True)
    assert coarse.shafts[0].coarsest.too_coarse and coarse.warnings
    assert "split it into" in coarse.warnings[0]
    assert max(abs(r.change) for r in coarse.convergence) > COARSE_ERROR
    fine = summarize(_shaft(elements=64), max_frequency=2 * np.pi * 3000, convergence=True)
    assert not fine.warnings
    assert fine.shafts[0].coarsest.estimated_error < COARSE_ERROR
    assert fine.convergence and max(abs(r.change) for r in fine.convergence) < COARSE_ERROR


@pytest.mark.parametrize("name", EXAMPLES)
def test_drawing_holds_every_component(examples, name):
    """Every bearing, seal, probe, unbalance, mesh side, coupling end and disk of the model file
    is drawn, on its own shaft and node."""
    train = gr.load_model(examples / f"{name}.toml")
    parts = model_parts(train)
    kinds = [p.kind for p in parts]
    assert kinds.count("bearing") == len(train.bearings)
    assert kinds.count("seal") == len(train.seals)
    assert kinds.count("probe") == len(train.probes)
    assert kinds.count("unbalance") == len(train.unbalances)
    assert kinds.count("gear") == 2 * len(train.meshes)
    assert kinds.count("coupling") == 2 * len(train.couplings)
    assert kinds.count("disk") == sum(len(s.disks) for s in train.shafts)
    assert kinds.count("section") == sum(len(s.sections) for s in train.shafts)
    for p, b in zip([p for p in parts if p.kind == "bearing"], train.bearings, strict=True):
        assert train.shafts[p.shaft].name == b.shaft
        assert p.node == train.node_index(b, "b")[1]


def test_plot_model_writes_png_and_svg(examples, tmp_path):
    train = gr.load_model(examples / "steam_turbine_gearbox.toml")
    fig = plot_model(train, tmp_path / "m.png")
    assert (tmp_path / "m.png").stat().st_size > 50_000
    # one side view per shaft, to scale, and the end view
    assert len(fig.axes) == len(train.shafts) + 1
    for ax in fig.axes:
        assert ax.get_aspect() == 1.0
    plot_model(train, tmp_path / "m.svg")
    assert (tmp_path / "m.svg").read_text().lstrip().startswith("<?xml")


def _cli(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "gearrotor", *args], capture_output=True, text=True, cwd=cwd
    )


def test_show_cli_json_and_html(examples, tmp_path):
    out = tmp_path / "m.html"
    r = _cli("show", str(examples / "unity_gearbox.toml"), "--format", "json", "--plot", str(out))
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert [s["name"] for s in d["shafts"]] == ["shaft1", "shaft2"]
    s1 = d["shafts"][0]
    # SPEC 6.1: a 1.02 m solid 60 mm steel shaft, ρ = 7890 kg/m³
    assert s1["mass_kg"] == pytest.approx(7890 * np.pi / 4 * 0.06**2 * 1.02, rel=1e-12)
    assert s1["n_elements"] == 20 and s1["n_dof"] == 126
    assert s1["bearing_span_m"] == pytest.approx(1.02, rel=1e-12)
    assert d["meshes"][0]["speed_ratio"] == 1.0
    assert d["meshes"][0]["mesh_frequency_hz"] == pytest.approx(30 * 6500 / 60)
    html = out.read_text()
    assert "plotly" in html and "shaft1 node 10" in html


def test_show_cli_bad_plot_suffix(examples, tmp_path):
    r = _cli("show", str(examples / "unity_gearbox.toml"), "--plot", str(tmp_path / "m.pdf"))
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "--plot" in r.stderr and ".png, .svg or .html" in r.stderr
    assert not (tmp_path / "m.pdf").exists()
