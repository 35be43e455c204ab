"""Undamped critical speed map against closed forms and the literature's uniform-shaft map."""

import json
import sys

import numpy as np
import pytest
from scipy.optimize import brentq

from doc_examples import ROOT, run
from gearrotor.analyses import modal, rigid_support_criticals, ucs_map
from gearrotor.analyses.audit.ucs import MAX_MODES
from gearrotor.elements import shear_coefficient
from gearrotor.errors import ModelError
from gearrotor.io import load_model
from gearrotor.model import Train
from helpers import single_shaft

E, NU, RHO = 211e9, 0.3, 7850.0
G = E / (2 * (1 + NU))


def uniform(L, d, elements, k=1e7, speed=100.0, **extra):
    return single_shaft(
        length=L,
        diameter=d,
        elements=elements,
        E=E,
        density=RHO,
        poisson=NU,
        bearings=[{"node": 0, "k": k}, {"node": elements, "k": k}],
        speed=speed,
        **extra,
    )


def lowest(shaft, n):
    """The n lowest critical speeds of a shaft at every stiffness of the map (rad/s): the
    map's branches are modes followed by shape, so the i-th lowest can sit on any of them."""
    c = np.sort(np.where(np.isfinite(shaft.critical_speeds), shaft.critical_speeds, np.inf), 1)
    return np.where(np.isinf(c), np.nan, c)[:, :n]


def timoshenko_pinned_forward(L, d, n):
    """Forward synchronous (Ω = ω) critical of a pinned-pinned spinning Timoshenko shaft, mode n.

    With u = x + iy and ψ the complex slope, sin/cos(nπz/L) modes satisfy the Timoshenko
    equations exactly (Nelson & McVaugh 1976 kinematics; e.g. Friswell et al. 2010, sec. 5.6);
    with polar inertia 2ρI and Ω = ω the rotary-inertia term −ρIω² becomes +ρIω², giving
    ρAρI s² + (ρA EI k² + ρA κGA − κGA ρI k²) s − κGA EI k⁴ = 0, s = ω², k = nπ/L."""
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    kap = shear_coefficient(0.0, d, NU)
    k = n * np.pi / L
    a = RHO * A * RHO * I
    b = RHO * A * E * I * k**2 + RHO * A * kap * G * A - kap * G * A * RHO * I * k**2
    c = -kap * G * A * E * I * k**4
    return np.sqrt((-b + np.sqrt(b * b - 4 * a * c)) / (2 * a))


@pytest.mark.parametrize("speed", [100.0, -100.0])
def test_rigid_support_limit_is_the_pinned_spinning_timoshenko_shaft(speed):
    L, d = 1.0, 0.05
    t = uniform(L, d, 40, speed=speed)
    rigid = rigid_support_criticals(t, n_modes=3)["s"]
    for n in (1, 2, 3):
        # 40 cubic elements: the FE error grows as (n/40)^4 (h^4 convergence, slender elements;
        # tests/test_shaft_element.py); measured 1e-6, 2e-5, 9e-5
        assert rigid[n - 1] == pytest.approx(timoshenko_pinned_forward(L, d, n), rel=2e-4)
    # the map tends to it as k -> infinity: the springs' share of the mode's compliance is
    # ~ (m ω²/2) / k, 2.5e8 / 1e12 for mode 3, and the frequency moves by about half of it
    res = ucs_map(t, stiffness=np.array([1e6, 1e12]), n_modes=3)
    np.testing.assert_allclose(lowest(res.shafts[0], 3)[-1], rigid, rtol=5e-5)
    # the gyroscopic term matters: the forward critical is above the non-rotating frequency
    # (modal at zero speed, bearings 1e12 N/m)
    still = modal(uniform(L, d, 40, k=1e12, speed=0.0), speed=0.0)
    lat = still.damped_frequency[np.array(still.mode_type) == "L"]
    assert rigid[2] > lat[4] * (1 + 5e-3)  # mode 3 (x, y pair at 4, 5): +1.3 % here


def test_soft_support_limit_is_the_rigid_rotor_on_springs():
    """k -> 0: the shaft moves as a rigid body, translation ω² = 2k/m and forward conical
    synchronous whirl ω² = (2k (L/2)²) / (I_t − I_p), I_t − I_p = m (L²/12 + d²/16 − d²/8)
    (a rigid rotor's conical critical with gyroscopics, e.g. Vance et al. 2010, ch. 2)."""
    L, d, k = 1.0, 0.05, 10.0
    t = uniform(L, d, 20, k=k)
    m = RHO * np.pi * d**2 / 4 * L
    res = ucs_map(t, stiffness=np.array([k, 1e3]), n_modes=2)
    c = lowest(res.shafts[0], 2)[0]
    # the shaft's bending flexibility adds ~ k / (48 EI / L³) = 3e-6 of compliance
    assert c[0] == pytest.approx(np.sqrt(2 * k / m), rel=1e-5)
    assert c[1] == pytest.approx(np.sqrt(k * L**2 / 2 / (m * (L**2 / 12 - d**2 / 16))), rel=1e-5)


def test_no_forward_conical_critical_when_polar_exceeds_transverse_inertia():
    """A disk-like rigid rotor (I_p > I_t) has no forward synchronous conical critical: the
    pencil's μ = 1/ω² is negative; the translational one stays."""
    L, d, k = 0.05, 0.3, 1e3
    t = uniform(L, d, 2, k=k)
    m = RHO * np.pi * d**2 / 4 * L
    res = ucs_map(t, stiffness=np.array([k, 1e4]), n_modes=2, method="dense")
    c = lowest(res.shafts[0], 2)[0]
    assert c[0] == pytest.approx(np.sqrt(2 * k / m), rel=1e-6)
    assert np.isnan(c[1]) or c[1] > 100 * c[0]  # the next one is an elastic mode, far above


def _eb_spring_roots(K, count):
    """Roots x = βL/2 of the Euler–Bernoulli beam on two equal end springs, K = k (L/2)³/EI:
    symmetric modes x³(sin x + cos x tanh x) = 2K cos x, antisymmetric modes
    x³(sin x coth x − cos x) = 2K sin x (free ends: zero moment, shear = spring force).
    K -> ∞ gives the pinned shaft (x = π/2, π, ...), K -> 0 the rigid-body modes 2k/m, 6k/m."""

    def sym(x):
        return x**3 * (np.sin(x) + np.cos(x) * np.tanh(x)) - 2 * K * np.cos(x)

    def anti(x):
        return x**3 * (np.sin(x) / np.tanh(x) - np.cos(x)) - 2 * K * np.sin(x)

    grid = np.linspace(1e-4, 12.0, 24001)
    roots = []
    for f in (sym, anti):
        v = f(grid)
        for i in np.flatnonzero(np.sign(v[:-1]) != np.sign(v[1:])):
            roots.append(brentq(f, grid[i], grid[i + 1], xtol=1e-14))
    return np.sort(roots)[:count]


def test_uniform_shaft_map_against_the_euler_bernoulli_frequency_equation():
    """The classical critical speed map of a uniform shaft on two equal bearing springs, in
    the dimensionless form of the literature (critical speed / first pinned critical against
    kL³/EI; Vance 1988, Rotordynamics of Turbomachinery, ch. 3, and Vance, Zeidan & Murphy 2010)
    computed here from the Euler–Bernoulli frequency equation of the beam on end springs. A
    slender shaft (L/d = 200) makes the Timoshenko and gyroscopic corrections of the FE map
    small: ~ (nπ d / 4L)² ≤ 2e-4 for the first three modes."""
    L, d = 2.0, 0.01
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    t = uniform(L, d, 60)
    kbar = np.array([1e-3, 0.1, 1.0, 10.0, 100.0, 1e3, 1e4])  # k L³ / EI
    ks = kbar * E * I / L**3
    res = ucs_map(t, stiffness=ks, n_modes=3)
    w1 = (np.pi / L) ** 2 * np.sqrt(E * I / (RHO * A))
    for j, kb in enumerate(kbar):
        x = _eb_spring_roots(kb / 8, 3)  # K = k (L/2)³ / EI
        expect = (2 * x / L) ** 2 * np.sqrt(E * I / (RHO * A))
        got = lowest(res.shafts[0], 3)[j]
        np.testing.assert_allclose(got / w1, expect / w1, rtol=5e-4)
    # the two limits of the dimensionless map: pinned-pinned as k -> oo (the first pinned
    # critical), free-free as k -> 0 (the rigid-body modes, then the free-free beam's first
    # bending mode, βL = 4.7300, cos βL cosh βL = 1)
    assert lowest(res.shafts[0], 1)[-1, 0] / w1 == pytest.approx(1.0, rel=2e-3)
    free = brentq(lambda x: np.cos(x) * np.cosh(x) - 1, 4.5, 5.0, xtol=1e-14)
    assert lowest(res.shafts[0], 3)[0, 2] / w1 == pytest.approx((free / np.pi) ** 2, rel=2e-3)
    # and the branches rise between them (the min-max theorem; tracked by shape)
    for c in res.shafts[0].critical_speeds.T:
        c = c[np.isfinite(c)]
        assert np.all(np.diff(c) > 0)


def geared_pair(speed=300.0, k=5e6):
    shafts = []
    for name, dia in (("p", 0.06), ("g", 0.09)):
        shafts.append(
            {
                "name": name,
                "material": "steel",
                "sections": [{"length": 0.5, "outer_diameter": dia, "elements": 6}],
                "disks": [{"node": 3, "mass": 20.0, "polar": 0.4, "transverse": 0.25}],
            }
        )
    return Train.model_validate(
        {
            "speed": speed,
            "materials": {"steel": {"E": E, "density": RHO, "poisson": NU}},
            "shafts": shafts,
            "bearings": [{"shaft": s, "node": n, "k": k} for s in ("p", "g") for n in (0, 6)],
            "thrust_bearings": [{"shaft": "g", "node": 0, "kzz": 1e8}],
            "meshes": [
                {
                    "gear": {"shaft": "p", "node": 3, "teeth": 20, "radius": 0.05},
                    "mate": {"shaft": "g", "node": 3, "teeth": 50, "radius": 0.125},
                    "pressure_angle": 0.349,
                    "helix_angle": 0.2,
                    "stiffness": 3e8,
                }
            ],
        }
    )


@pytest.mark.parametrize("speed", [300.0, -300.0])
def test_geared_critical_is_a_free_vibration_at_the_shafts_1x(speed):
    """Cross-check of the synchronous problem on a geared train (each shaft's gyroscopics
    scaled by its own speed ratio, the helical mesh coupling lateral, axial and torsional
    motion): at the reference speed Ω = ω/|r_s| of a critical ω of shaft s, the damped-mode
    analysis of the same undamped train (modal) has a free vibration at exactly ω."""
    k = 5e6
    t = geared_pair(speed, k)
    res = ucs_map(t, stiffness=np.array([k, 1e8]), n_modes=3)
    for s in res.shafts:
        ratio = abs(s.speed_ratio)
        c = s.critical_speeds[0]
        for w in c[np.isfinite(c)]:
            m = modal(t, speed=np.sign(speed) * w / ratio)
            assert np.min(np.abs(m.damped_frequency - w)) <= 1e-7 * w
    # both shafts' maps hold their own modes: the gear's critical is not the pinion's
    assert lowest(res.shaft("g"), 1)[0, 0] != pytest.approx(
        lowest(res.shaft("p"), 1)[0, 0], rel=1e-3
    )


def test_dense_and_sparse_solvers_agree():
    t = geared_pair()
    a = ucs_map(t, stiffness=(1e6, 1e10), n_stiffness=4, method="dense")
    b = ucs_map(t, stiffness=(1e6, 1e10), n_stiffness=4, method="sparse")
    for sa, sb in zip(a.shafts, b.shafts, strict=True):
        np.testing.assert_allclose(sa.critical_speeds, sb.critical_speeds, rtol=1e-8)
        np.testing.assert_allclose(sa.rigid_critical_speeds, sb.rigid_critical_speeds, rtol=1e-8)


def strict_brentq(f, a, b, **kw):
    """Brent's method as SciPy ≥ 1.18 runs it: a NaN value of ``f`` stops the search (SciPy
    1.17 went on regardless)."""

    def checked(x):
        v = f(x)
        assert np.isfinite(v), f"g({x!r}) = {v}"
        return v

    return brentq(checked, a, b, **kw)


def test_intersections_with_a_tabulated_bearing(monkeypatch):
    """A bearing stiffness rising linearly with speed meets the first critical where
    ω_1(K(N)) = N: re-solving the map at exactly K(N) returns N (to the map's log-k
    interpolation error, ~1e-4 with 61 points over 4 decades)."""
    import gearrotor.analyses.audit.ucs as ucs_module

    monkeypatch.setattr(ucs_module, "brentq", strict_brentq)
    L, d = 1.0, 0.05
    rpm = np.array([1000.0, 20000.0])
    kk = np.array([1e6, 4e8])
    table = {
        "speed": [f"{v} rpm" for v in rpm],
        "kxx": kk.tolist(),
        "kxy": [0.0, 0.0],
        "kyx": [0.0, 0.0],
        "kyy": (2 * kk).tolist(),
        "cxx": [0.0, 0.0],
        "cxy": [0.0, 0.0],
        "cyx": [0.0, 0.0],
        "cyy": [0.0, 0.0],
    }
    t = Train.model_validate(
        {
            "speed": 500.0,
            "materials": {"steel": {"E": E, "density": RHO, "poisson": NU}},
            "shafts": [
                {
                    "name": "s",
                    "material": "steel",
                    "sections": [{"length": L, "outer_diameter": d, "elements": 20}],
                }
            ],
            "bearings": [
                {"shaft": "s", "node": 0, "table": table, "name": "A"},
                {"shaft": "s", "node": 20, "table": table, "name": "B"},
            ],
        }
    )
    res = ucs_map(t, stiffness=(1e5, 1e9), n_stiffness=61, n_modes=2)
    first = [x for x in res.intersections if x.mode == 0]
    assert {x.directions for x in first} == {("kxx",), ("kyy",)}
    assert {x.bearings for x in first} == {("A", "B")}  # identical curves: one row
    for x in first:
        k_expect = np.interp(x.speed * 30 / np.pi, rpm, kk * (1 if x.directions == ("kxx",) else 2))
        assert x.stiffness == pytest.approx(k_expect, rel=1e-9)
        check = ucs_map(t, stiffness=np.array([x.stiffness, 2 * x.stiffness]), n_modes=1)
        # an exact critical of the bearing at that speed (the root search solves the map
        # there; interpolating it between 61 points was 1e-4 off)
        assert lowest(check.shafts[0], 1)[0, 0] == pytest.approx(x.speed, rel=1e-9)
    d = json.loads(json.dumps(res.to_dict()))
    assert d["intersections"][0]["speed_rpm"] == pytest.approx(
        res.intersections[0].speed * 30 / np.pi
    )


def test_bad_input():
    t = uniform(1.0, 0.05, 4)
    with pytest.raises(ModelError, match="stiffness"):
        ucs_map(t, stiffness=np.array([-1.0, 1e6]))
    with pytest.raises(ModelError, match="method"):
        ucs_map(t, method="qz")
    bare = single_shaft(length=1.0, diameter=0.05, elements=4)
    with pytest.raises(ModelError, match="bearings"):
        ucs_map(bare)


def test_bearings_on_pedestals_act_in_series():
    """A bearing on a ``support`` is the swept k between journal and pedestal: for a rigid
    rotor on light pedestals (k_p to ground) the translational critical is √(2 k_eff / m),
    k_eff = k k_p / (k + k_p) (pedestal mass 1e-6 kg: its inertia shifts k_eff by
    ~ m_p ω² / k_p = 1e-7; the shaft's bending adds ~ k_eff / (48 EI/L³) < 1e-5 of compliance)."""
    L, d, kp = 1.0, 0.05, 30.0
    sup = {"mass": 1e-6, "kxx": kp, "kyy": kp}
    t = single_shaft(
        length=L,
        diameter=d,
        elements=10,
        bearings=[{"node": 0, "k": 1.0, "support": sup}, {"node": 10, "k": 1.0, "support": sup}],
        speed=100.0,
    )
    m = RHO * np.pi * d**2 / 4 * L
    res = ucs_map(t, stiffness=np.array([10.0, 100.0]), n_modes=1)
    for k, c in zip(res.stiffness, res.shafts[0].critical_speeds[:, 0], strict=True):
        keff = k * kp / (k + kp)
        assert c == pytest.approx(np.sqrt(2 * keff / m), rel=1e-5)


# -- issue 22: physical branches, determinism, one definition, exact intersections ----------
EXAMPLES = ROOT / "examples"
MODELS = sorted(
    p.name for p in EXAMPLES.glob("*.toml") if "[[shafts]]" in p.read_text(encoding="utf-8")
)
_MAPS: dict[str, object] = {}


def example_map(name):
    """The map of an example at its default sweep (31 stiffnesses, 4 criticals per shaft)."""
    if name not in _MAPS:
        _MAPS[name] = ucs_map(load_model(EXAMPLES / name))
    return _MAPS[name]


# the steam turbine (the falls) and the unity gearbox (shared with the tests below)
# run by default; the other examples' maps (7 s each) are slow
@pytest.mark.parametrize(
    "name",
    [
        n
        if n in ("steam_turbine_gearbox.toml", "unity_gearbox.toml")
        else pytest.param(n, marks=pytest.mark.slow)
        for n in MODELS
    ],
)
def test_raising_the_support_stiffness_never_lowers_a_critical(name):
    """K(k) = K₀ + k K_b with K_b ⪰ 0: along a mode dω²/dk = φᴴK_bφ / φᴴBφ ≥ 0, so a branch
    that falls has jumped to another mode (the steam turbine's pinion branch 4 fell from
    52,019 to 29,356 rpm between neighbouring stiffnesses, 12 falls in all). Every branch of
    every shaft of every example rises or stays, to the eigenvalues' round-off (relative
    1e-8, the pairing's admissibility margin); the critical parts are the branch itself."""
    res = example_map(name)
    for s in res.shafts:
        for c in s.critical_speeds.T:
            ok = np.isfinite(c)
            assert np.all(np.diff(c[ok]) >= -1e-8 * c[ok][1:]), (s.name, c[ok])
    for s in res.shafts:
        for c, b in zip(s.critical_speeds.T, s.branch_speeds.T, strict=True):
            ok = np.isfinite(c)
            bb = b[np.isfinite(b)]
            assert np.all(np.diff(bb) >= -1e-8 * bb[1:]), (s.name, bb)
            np.testing.assert_array_equal(c[ok], b[ok])


def test_every_value_of_the_map_is_a_root_and_the_sorted_roots_rise():
    """The map's speeds are roots of the synchronous problem at their stiffness (a dense
    solve of the whole pencil), and the sorted roots never fall with k and stay below those
    with the journals pinned (the min-max theorem the branches rest on: K_b ⪰ 0, and pinning
    is the limit k -> oo), on the steam turbine's pinion."""
    from gearrotor.analyses.audit.ucs import _Synchronous

    res = example_map("steam_turbine_gearbox.toml")
    prob = _Synchronous(res.train)
    s = res.shaft("pinion")
    prev = None
    pinned = prob.solve(None, 1.0, "dense", 60).w2
    for j in (0, 12, 18, 24, 30):
        w2 = prob.solve(float(res.stiffness[j]), 1.0, "dense", 60).w2
        assert np.all(w2[:40] <= pinned[:40] * (1 + 1e-10))
        for v in s.branch_speeds[j][np.isfinite(s.branch_speeds[j])]:
            assert np.min(np.abs(w2 - v**2)) <= 1e-9 * v**2
        if prev is not None:
            assert np.all(w2[:40] >= prev[:40] * (1 - 1e-10))
        prev = w2


def test_a_branch_is_followed_by_shape_through_a_crossing():
    """Tracked by shape, not by sorting: on a single shaft the axial mode on a thrust spring,
    ω_z = √(k_z/m) = 3000 rpm, does not depend on the radial bearings and does not couple to
    bending, so the lateral branches rising through it cross it. Followed by shape every
    branch of the map stays a forward lateral mode all along (q = 1; an axisymmetric rotor's
    orbits are circles), although the sorted roots swap at the crossing (the 1st lowest root
    is the axial mode on one side); and the forward and backward whirl (q = 0) never mix."""
    L, d = 1.0, 0.05
    m = RHO * np.pi * d**2 / 4 * L
    wz = 3000 * np.pi / 30
    t = uniform(L, d, 20, thrust_bearings=[{"shaft": "s", "node": 0, "kzz": m * wz**2}])
    res = ucs_map(t, stiffness=(1e5, 1e10), n_stiffness=31, n_modes=2)
    s = res.shafts[0]
    b, q = s.branch_speeds, s.forward_share
    assert np.all(np.abs(q[np.isfinite(q)] - 1) < 1e-6)
    first = b[:, 0]
    assert first[0] < wz < first[-1]  # the first branch crosses the axial mode
    from gearrotor.analyses.audit.ucs import _Synchronous

    prob = _Synchronous(t)
    j = int(np.searchsorted(first, wz))  # just above the crossing
    sol = prob.solve(float(res.stiffness[j]), 1.0, "dense", 10)
    # the lowest root is the axial mode (the shaft's own axial compliance, k_z L / EA = 4e-3,
    # lowers it by about a sixth of that: 6e-4)
    assert np.sqrt(sol.w2[0]) == pytest.approx(wz, rel=1e-3)
    assert sol.q[0, 0] < 1e-9
    # the branch there is another root, above the axial one
    assert np.min(np.abs(np.sqrt(sol.w2[1:]) - first[j])) <= 1e-12 * first[j]


def test_identical_shafts_get_identical_maps_bit_for_bit_every_run():
    """The unity gearbox's two shafts are mirror images: their maps are the same numbers (a
    repeated root, one shaft's antisymmetric mode and the other's, is split along the shafts'
    forward forms and keeps one value); two runs in separate processes print the same JSON
    byte for byte (ARPACK's random start vector gave maps 40 % apart between runs)."""
    args = [
        sys.executable,
        "-m",
        "gearrotor",
        "ucs",
        "examples/unity_gearbox.toml",
        "--n-points",
        "5",
        "--format",
        "json",
    ]
    a = run(args).stdout
    assert run(args).stdout == a
    d = json.loads(a)
    one, two = d["shafts"]
    for key in ("critical_speeds_rpm", "branch_speeds_rpm", "rigid_critical_speeds_rpm"):
        assert one[key] == two[key], key
    np.testing.assert_allclose(
        np.array(one["forward_share"], float), np.array(two["forward_share"], float), atol=1e-9
    )
    rows = {
        name: [(x["mode"], x["speed_rpm"]) for x in d["intersections"] if x["shaft"] == name]
        for name in ("shaft1", "shaft2")
    }
    assert rows["shaft1"] == rows["shaft2"]


def test_sparse_solver_is_deterministic_and_agrees_with_dense():
    """The sparse path starts ARPACK from a fixed vector: the same map twice, equal to the
    dense one to the solvers' round-off (1e-8)."""
    t = load_model(EXAMPLES / "unity_gearbox.toml")
    a = ucs_map(t, n_stiffness=5, method="sparse")
    b = ucs_map(t, n_stiffness=5, method="sparse")
    c = ucs_map(t, n_stiffness=5, method="dense")
    for sa, sb, sc in zip(a.shafts, b.shafts, c.shafts, strict=True):
        np.testing.assert_array_equal(sa.critical_speeds, sb.critical_speeds)
        np.testing.assert_allclose(sa.critical_speeds, sc.critical_speeds, rtol=1e-8)


def test_each_shaft_meets_only_its_own_bearings_once_per_curve():
    """Intersections pair a shaft's branches with its own bearings (not the other shaft's at
    the same speed), identical curves in one row: the unity gearbox's 2 × 4 branches meet
    their constant 1e7 N/m bearings in 8 rows (64 before, mostly 4× duplicates)."""
    res = example_map("unity_gearbox.toml")
    own = {"shaft1": {"S1-B1", "S1-B2"}, "shaft2": {"S2-B1", "S2-B2"}}
    assert len(res.intersections) == 8
    for x in res.intersections:
        assert set(x.bearings) == own[x.shaft]
        assert x.directions == ("kxx", "kyy")
        assert x.stiffness == 1e7
    keys = [(x.shaft, x.mode) for x in res.intersections]
    assert len(keys) == len(set(keys))


def test_intersections_are_exact_roots_against_a_brute_force_solve():
    """The steam turbine's pinion branches meet its bearings' Kxx/Kyy curves (10 speeds,
    linear in speed) where ω_b(K(N)) = N: a dense solve at K(N) has a root at exactly N
    (1e-9; interpolating the branch between stiffnesses was up to 0.85 % off), and a
    brute-force bisection of that sorted root against the curve with dense solves finds the
    same N (1e-9)."""
    from gearrotor.analyses.audit.ucs import _Synchronous

    res = example_map("steam_turbine_gearbox.toml")
    prob = _Synchronous(res.train)
    curve = next(b for b in res.bearings if b.shaft == "pinion")
    pinion = [x for x in res.intersections if x.shaft == "pinion"]
    assert len(pinion) >= 4
    for x in pinion:
        w2 = prob.solve(x.stiffness, 1.0, "dense", 60).w2
        assert np.min(np.abs(np.sqrt(w2) - x.speed)) <= 1e-9 * x.speed
    for x in pinion:
        kv = curve.kxx if x.directions == ("kxx",) else curve.kyy
        assert x.stiffness == pytest.approx(np.interp(x.speed, curve.speeds, kv), rel=1e-12)
    # brute force for the first one: the sorted root i nearest N, bisected on the curve
    x = pinion[0]
    kv = curve.kxx if x.directions == ("kxx",) else curve.kyy
    i = int(np.argmin(np.abs(np.sqrt(prob.solve(x.stiffness, 1.0, "dense", 60).w2) - x.speed)))

    def f(n):
        k = float(np.interp(n, curve.speeds, kv))
        return np.sqrt(prob.solve(k, 1.0, "dense", 60).w2[i]) - n

    lo, hi = x.speed * 0.98, x.speed * 1.02
    assert f(lo) * f(hi) < 0
    assert brentq(f, lo, hi, xtol=1e-12, rtol=1e-14) == pytest.approx(x.speed, rel=1e-9)


def test_n_modes_is_bounded():
    t = uniform(1.0, 0.05, 4)
    with pytest.raises(ModelError, match="n_modes"):
        ucs_map(t, n_modes=MAX_MODES + 1)
    with pytest.raises(ModelError, match="min_share"):
        ucs_map(t, min_share=0.0)


def test_figure_shows_the_operating_range_and_mcs(tmp_path):
    """The operating range is a labelled band and the MCS a labelled line inside the panel's
    vertical range, on every shaft's own speed axis; a panel draws its own shaft's bearings
    only."""
    from gearrotor.plots.audit import plot_ucs_map

    t = load_model(EXAMPLES / "unity_gearbox.toml")
    rpm = np.pi / 30
    t = t.model_copy(
        update={
            "operating_speed_range": (5000 * rpm, 6000 * rpm),
            "max_continuous_speed": 6300 * rpm,
        }
    )
    res = ucs_map(t, n_stiffness=9, n_modes=2)
    fig = plot_ucs_map(res, path=tmp_path / "ucs.png")
    assert (tmp_path / "ucs.png").stat().st_size > 20_000
    for ax, own in zip(fig.axes, ("S1", "S2"), strict=True):
        lo, hi = ax.get_ylim()
        band = [p for p in ax.patches if p.get_label() == "operating range"]
        assert len(band) == 1
        ys = band[0].get_patch_transform().transform(band[0].get_path().vertices)[:, 1]
        assert (ys.min(), ys.max()) == pytest.approx((5000, 6000))
        assert lo < 5000 and 6300 < hi
        mcs = [ln for ln in ax.get_lines() if ln.get_label() == "MCS"]
        assert len(mcs) == 1 and mcs[0].get_ydata()[0] == pytest.approx(6300)
        texts = " ".join(a.get_text() for a in ax.texts)
        assert "operating range 5,000–6,000 rpm" in texts and "MCS 6,300 rpm" in texts
        curves = [
            ln.get_label() for ln in ax.get_lines() if ln.get_label().endswith(("Kxx", "Kyy"))
        ]
        assert curves and all(lab.startswith(own) for lab in curves)


@pytest.mark.slow
def test_bearing_curves_at_an_operating_point_carry_its_loads():
    """docs/ucs.md and docs/static.md: `ucs --operating-point LC10` (12.5 MW) draws the pinion
    journals' curves under the point's own static loads at every speed (its torque held; with
    the power held a journal had to carry 350 kN at 2,000 rpm and the command stopped). At the
    point's speed a curve holds the coefficients of the point itself (to 1e-6, the journal
    equilibrium's tolerance amplified by the coefficients' sensitivity); the doc's numbers:
    the loaded films are stiffer and only Kxx meets the pinion's criticals, 13,618-14,518 rpm."""
    from gearrotor.analyses.static import at_operating_point

    t = load_model(EXAMPLES / "steam_turbine_gearbox.toml")
    res = ucs_map(t, operating_point="LC10")
    point = at_operating_point(t, "LC10")
    rpm = np.pi / 30
    for k in (0, 1):
        c = res.bearings[k]
        assert len(c.speeds) == 10
        i = int(np.argmin(np.abs(c.speeds - 10800 * rpm)))
        table = point.bearings[k].table
        assert c.kxx[i] == pytest.approx(table.kxx[0], rel=1e-6)
        assert c.kyy[i] == pytest.approx(table.kyy[0], rel=1e-6)
        assert 2.95e8 < c.kxx.min() and c.kxx.max() < 3.95e8  # "3.0-3.9e8"
        assert 1.75e9 < c.kyy.min() and c.kyy.max() < 5.05e9  # "1.8-5.0e9"
    pin = [x for x in res.intersections if x.shaft == "pinion"]
    assert pin and all(x.directions == ("kxx",) for x in pin)
    assert all(13610 <= x.speed / rpm <= 14520 for x in pin)  # "13,618-14,518 rpm"


def test_root_search_at_a_range_end_to_round_off(monkeypatch):
    """Brent's method starts at the bracket's ends; an end where the curve crosses the sweep's
    last stiffness gives back, through np.interp, a stiffness 1 ulp above it (these numbers do:
    7.5e-9 N/m above 44,959,564.59 N/m). That end was "outside the sweep", g = NaN: SciPy 1.17
    went on, SciPy 1.18 raised ValueError (`ucs` on a tabulated bearing failed with Python
    3.12's newer SciPy). A sweep of ω² = c·√k (exact at every k) over [2e6, 44,959,564.59] N/m
    and a bearing whose stiffness rises linearly from 1e6 to 4e8 N/m between 100 and 2000 rad/s
    meet once, where c·√K(N) = N²."""
    import gearrotor.analyses.audit.ucs as ucs_module

    k_lo, k_hi, c = 2e6, 44959564.59045085, 10.0
    S, K = (100.0, 2000.0), (1e6, 4e8)
    n_hi = S[0] + (k_hi - K[0]) / (K[1] - K[0]) * (S[1] - S[0])
    assert np.interp(n_hi, S, K) > k_hi  # the round-off this test is about

    class Sweep:
        ks = [k_lo, k_hi]
        w2 = [np.array([c * np.sqrt(k)]) for k in ks]

        def at(self, b, k):
            assert k_lo <= k <= k_hi, k
            return c * np.sqrt(k), np.array([1.0])

    monkeypatch.setattr(ucs_module, "brentq", strict_brentq)
    (got,) = ucs_module._meet(Sweep(), 0, 0, S, K, k_lo, k_hi)
    n, k, q = got
    assert k == pytest.approx(np.interp(n, S, K), rel=1e-12) and k_lo <= k <= k_hi
    assert c * np.sqrt(k) == pytest.approx(n**2, rel=1e-9) and q == 1.0
