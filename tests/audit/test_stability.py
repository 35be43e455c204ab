"""API 617 Level I / Level II stability: the q_A formula by hand, Q_0 against the Jeffcott
closed form, the root search's tolerance, the verdicts, and bad input."""

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearrotor.analyses import Site, Stage, level1, level2, modal
from gearrotor.analyses.audit.stability import (
    _unit_coupling,
    anticipated_cross_coupling,
    csr_boundary,
    mid_span,
    screening_region,
)
from gearrotor.assembly import assemble
from gearrotor.errors import ModelError
from gearrotor.model import Train
from helpers import single_shaft

RPM = np.pi / 30
ROOT = Path(__file__).resolve().parents[2]
RHO = 7850.0
KB, CB = 1e6, 400.0  # bearing stiffness (N/m) and damping (N·s/m), each of two
L, D = 0.3, 0.2  # a stubby, practically rigid shaft: bending stiffness ~3e10 N/m


def jeffcott(speed=300.0, q=None, **extra):
    """A rigid rotor (mass m) on two isotropic bearings (k, c): its cylindrical mode is the
    Jeffcott rotor m z̈ + 2c ż + 2k z − i q z = 0 (z = x + iy, q at mid-span, spin +z)."""
    extra.setdefault("max_continuous_speed", abs(speed))
    if q is not None:
        extra["cross_couplings"] = [{"shaft": "s", "node": 2, "q": q}]
    return single_shaft(
        length=L,
        diameter=D,
        elements=4,
        density=RHO,
        bearings=[{"node": 0, "k": KB, "c": CB, "name": "A"}, {"node": 4, "k": KB, "c": CB}],
        speed=speed,
        **extra,
    )


MASS = RHO * np.pi * D**2 / 4 * L
WN = np.sqrt(2 * KB / MASS)
Q_ONSET = 2 * CB * WN  # m s² + c s + k − i q = 0 has s = iω_n when q = c ω_n (c = 2 CB)


def test_qa_formula_by_hand():
    """q_A = B_c C P / (D_c H_c N) (ρ_d/ρ_s), B_c = 3, C = 9.55, P in W, D and H in m, N in
    rpm -> N/m: 1.5 MW, D_c = 0.4 m, H_c = 25 mm, 9000 rpm, ρ_d/ρ_s = 1.3:
    3 × 9.55 × 1.5e6 × 1.3 / (0.4 × 0.025 × 9000) = 55 867 500 / 90 = 620 750 N/m."""
    st = Stage("s", 2, power="1.5 MW", diameter="400 mm", width="25 mm", density_ratio=1.3)
    assert st.power == 1.5e6 and st.diameter == 0.4 and st.width == 0.025
    q = anticipated_cross_coupling(st, 9000 * RPM)
    assert q == pytest.approx(620750.0, rel=1e-12)
    # the standard's US form: C = 63 with hp, in, rpm gives klbf/in; the two constants agree
    # to their rounding (63 vs 9.55 × 0.0254² × 745.7 / 4.448 / 0.0254 ... = 63.03): 0.05 %
    hp, inch = 1.5e6 / 745.6999, 0.4 / 0.0254
    q_us = 3 * 63 * hp * 1.3 / (inch * (0.025 / 0.0254) * 9000) * 1000 * 4.448222 / 0.0254
    assert q_us == pytest.approx(q, rel=1e-3)
    # an axial / turbine stage: B_t = 1.5, no density ratio
    ax = Stage("s", 2, power=1.5e6, diameter=0.4, width=0.025, kind="axial")
    assert anticipated_cross_coupling(ax, 9000 * RPM) == pytest.approx(1.5 * 9.55 * 1.5e6 / 90)


@pytest.mark.parametrize("speed", [300.0, -300.0])
def test_threshold_against_the_jeffcott_closed_form(speed):
    """Q_0 = c ω_n. The shaft's flexibility makes mid-span move (1 + ε) times the journals,
    ε ~ 2k/k_shaft ≈ 7e-5, and the threshold drops by ~2ε: rel 1e-3. With the shaft turning
    about −z the applied Q must change sign to feed its forward whirl: the threshold and the
    (forward) mode at it are the same."""
    r = level1(jeffcott(speed), qa=Q_ONSET / 3, at=[("s", 2)], n_curve=0)
    assert r.threshold_q == pytest.approx(Q_ONSET, rel=1e-3)
    assert r.ratio == pytest.approx(3.0, rel=1e-3)
    m = r.threshold_mode
    assert m["whirl"] == "F" and m["type"] == "L"
    assert m["frequency_rpm"] * RPM == pytest.approx(WN, rel=1e-3)  # at onset λ = iω_n
    # just above the threshold the unstable mode is the forward one
    asm = assemble(jeffcott(speed))
    dK = _unit_coupling(asm, (Site("s", 2, 1.0),))
    res = modal(dataclasses.replace(asm, K0=asm.K0 + 1.01 * Q_ONSET * dK), speed=speed)
    bad = np.flatnonzero(res.unstable)
    assert len(bad) == 1 and res.whirl[bad[0]] == "F"


def test_sign_follows_the_shaft_on_a_geared_train():
    """Q on the gear, which turns opposite to the reference pinion: the gear's forward mode
    goes unstable at c ω_n of the gear on its bearings (the mesh is soft: 1e3 N/m)."""
    shafts, bearings = [], []
    for name in ("p", "g"):
        shafts.append(
            {
                "name": name,
                "material": "steel",
                "sections": [{"length": L, "outer_diameter": D, "elements": 4}],
            }
        )
        bearings += [{"shaft": name, "node": n, "k": KB, "c": CB} for n in (0, 4)]
    t = Train.model_validate(
        {
            "speed": 300.0,
            "max_continuous_speed": 300.0,
            "materials": {"steel": {"E": 211e9, "density": RHO, "poisson": 0.3}},
            "shafts": shafts,
            "bearings": bearings,
            "meshes": [
                {
                    "gear": {"shaft": "p", "node": 2, "teeth": 30, "radius": 0.15},
                    "mate": {"shaft": "g", "node": 2, "teeth": 30, "radius": 0.15},
                    "pressure_angle": 0.349,
                    "stiffness": 1e3,
                }
            ],
        }
    )
    assert t.shaft_speeds()[1] < 0
    r = level1(t, qa=Q_ONSET / 3, at=[("g", 2)], n_curve=0)
    assert r.threshold_q == pytest.approx(Q_ONSET, rel=2e-3)  # + the mesh's 1e3/2e6
    assert r.threshold_mode["shaft"] == "g"
    assert r.threshold_mode["whirl_per_shaft"]["g"] == "F"
    # the two shafts are identical: Q on the pinion gives the same threshold and log dec (the
    # modes they share are the first forward mode of either)
    rp = level1(t, qa=Q_ONSET / 3, at=[("p", 2)], n_curve=0)
    assert rp.threshold_q == pytest.approx(r.threshold_q, rel=1e-6)
    assert rp.log_dec_at_qa == pytest.approx(r.log_dec_at_qa, rel=1e-6)


def test_first_forward_mode_above_three_times_the_speed():
    """A stiff rotor run far below its first critical (MCS 30 rad/s, first forward mode at
    164 rad/s): the first forward mode lies above 3x the speed and is followed all the same
    (it was "no forward lateral mode" before); its threshold is the Jeffcott one, c ω_n."""
    r = level1(jeffcott(30.0), qa=Q_ONSET / 3, at=[("s", 2)], n_curve=0)
    assert r.threshold_q == pytest.approx(Q_ONSET, rel=1e-3)
    assert r.mode_at_qa["frequency_rpm"] * RPM > 3 * 30.0


def test_mid_span_site():
    t = jeffcott()
    assert mid_span(t, "s") == Site("s", 2, 1.0)
    over = single_shaft(
        length=1.0,
        diameter=0.1,
        elements=10,
        bearings=[{"node": 2, "k": 1e7}, {"node": 6, "k": 1e7}],
    )
    assert mid_span(over, "s").node == 4  # between the bearings, not the shaft's middle


def test_root_search_tolerance_and_cost():
    t = jeffcott()
    coarse = level1(t, qa=Q_ONSET / 4, at=[("s", 2)], rtol=1e-4, n_curve=0)
    fine = level1(t, qa=Q_ONSET / 4, at=[("s", 2)], rtol=1e-11, n_curve=0)
    assert abs(coarse.threshold_q - fine.threshold_q) <= 1e-4 * fine.threshold_q
    # f(0), f(Q_A), one secant step past the root, then Brent: a handful of eigen-solves
    assert coarse.n_solves <= 10
    # the log dec at the threshold is zero to the slope × tolerance
    slope = (coarse.log_dec_at_qa - coarse.curve_log_dec[0]) / coarse.qa
    assert abs(coarse.threshold_mode["log_dec"]) <= abs(slope) * 1e-4 * fine.threshold_q * 2


def test_level1_verdicts_on_crafted_models():
    t = jeffcott()
    ok = level1(t, qa=Q_ONSET / 20, at=[("s", 2)], n_curve=0)  # Q_0/Q_A = 20 > 10
    assert ok.verdict == "pass" and ok.log_dec_at_qa >= 0.1
    bad = level1(t, qa=Q_ONSET / 1.5, at=[("s", 2)], n_curve=0)  # Q_0/Q_A = 1.5 < 2
    assert bad.verdict == "level II required"
    failed = {c.name for c in bad.criteria if c.ok is False}
    assert "Q_0 / Q_A" in failed
    # beyond the threshold: log dec at Q_A < 0 fails both criteria
    worse = level1(t, qa=Q_ONSET * 1.5, at=[("s", 2)], n_curve=0)
    assert worse.log_dec_at_qa < 0 and worse.threshold_q == pytest.approx(Q_ONSET, rel=1e-3)
    assert {c.name for c in worse.criteria if c.ok is False} == {
        "log dec at Q_A",
        "least log dec of every forward lateral mode at Q_A",
        "Q_0 / Q_A",
    }
    # a criterion not met sends the machine to Level II: that is not a failure
    assert {c.status for c in worse.criteria if c.ok is False} == {"level II required"}


def test_screening_chart():
    """The region A/B boundary: CSR 2.5 up to 16.53 kg/m³, 2.69 − 0.0115 ρ to 60 kg/m³ (2.0),
    region B beyond the chart."""
    np.testing.assert_allclose(csr_boundary([0.0, 16.53, 38.0, 60.0]), [2.5, 2.5, 2.253, 2.0])
    assert screening_region(2.3, 10.0) == "A" and screening_region(2.3, 50.0) == "B"
    assert screening_region(1.2, 70.0) == "B"


def test_screening_decides_between_two_and_ten():
    """A flexible shaft on soft bearings run at MCS = 2.3 × its first rigid-support critical:
    with Q_0/Q_A = 4 the verdict follows the screening region (density 10 kg/m³: region A,
    50 kg/m³: region B)."""
    Ls, d, el = 1.0, 0.05, 10
    base = single_shaft(
        length=Ls,
        diameter=d,
        elements=el,
        bearings=[{"node": 0, "k": 2e6, "c": 3e3}, {"node": el, "k": 2e6, "c": 3e3}],
        speed=1.0,
    )
    from gearrotor.analyses import rigid_support_criticals

    nc1 = rigid_support_criticals(base)["s"][0]
    t = base.model_copy(update={"speed": 2.3 * nc1, "max_continuous_speed": 2.3 * nc1})
    probe = level1(t, qa=1e5, at=[("s", el // 2)], n_curve=0)
    q0 = probe.threshold_q
    assert q0 is not None and probe.csr == pytest.approx(2.3, rel=1e-9)
    a = level1(t, qa=q0 / 4, at=[("s", el // 2)], average_density=10.0, n_curve=0)
    b = level1(t, qa=q0 / 4, at=[("s", el // 2)], average_density=50.0, n_curve=0)
    assert a.ratio == pytest.approx(4.0, rel=1e-3) and a.log_dec_at_qa >= 0.1
    assert a.region == "A" and a.verdict == "pass"
    assert b.region == "B" and b.verdict == "level II required"


def test_stages_split_the_cross_coupling_by_their_q():
    t = jeffcott()
    st = [
        Stage("s", 1, power=2e5, diameter=0.3, width=0.02, density_ratio=1.2),
        Stage("s", 3, power=1e5, diameter=0.3, width=0.02, density_ratio=1.2),
    ]
    r = level1(t, stages=st, average_density=5.0, operating_speed=300.0, n_curve=0)
    q = [anticipated_cross_coupling(s, 300.0) for s in st]
    assert r.qa == pytest.approx(sum(q))
    assert [s.weight for s in r.sites] == pytest.approx([2 / 3, 1 / 3])
    d = json.loads(json.dumps(r.to_dict()))  # JSON-ready
    assert d["qa_N_per_m"] == r.qa and d["threshold_q_N_per_m"] == r.threshold_q
    assert d["ratio_q0_qa"] == pytest.approx(r.threshold_q / r.qa)


def test_level2_against_the_jeffcott_eigenvalue():
    """Level II judges the model as given: its cross-coupling q in the Jeffcott rotor gives
    m s² + 2c s + 2k − i q = 0; the forward root's log dec −2π Re s / Im s (rel 1e-3: the
    shaft's flexibility as above)."""
    for q, verdict in ((0.5 * Q_ONSET, "pass"), (1.2 * Q_ONSET, "fail")):
        r = level2(jeffcott(q=q))
        s = np.roots([MASS, 2 * CB, 2 * KB - 1j * q])
        s = s[np.argmax(s.imag)]
        expect = -2 * np.pi * s.real / s.imag
        fwd = [m for m in r.evaluations[0].modes if m.forward and m.mode_type == "L"]
        assert min(m.log_dec for m in fwd) == pytest.approx(expect, rel=1e-3)
        assert r.verdict == verdict
        d = json.loads(json.dumps(r.to_dict()))
        assert d["verdict"] == verdict
        # per mode: pass/fail where the criterion judges it, "not judged" elsewhere
        checks = {m["check"] for m in d["speeds"][0]["modes"] if not m["forward"]}
        assert checks <= {"not judged", "fail"}
        assert {m["check"] for m in d["speeds"][0]["modes"] if m["forward"]} <= {"pass", "fail"}
    # Level I ignores the model's destabiliser: same threshold with or without it
    r1 = level1(jeffcott(q=1.2 * Q_ONSET), qa=Q_ONSET / 3, at=[("s", 2)], n_curve=0)
    assert r1.threshold_q == pytest.approx(Q_ONSET, rel=1e-3)
    assert r1.excluded["cross_couplings"] == ["cross_couplings[0]"]


def test_bad_input():
    t = jeffcott()
    no_mcs = jeffcott(max_continuous_speed=None)
    with pytest.raises(ModelError, match="max_continuous_speed"):
        level1(no_mcs, qa=1e5, at=[("s", 2)])
    with pytest.raises(ModelError, match="max_continuous_speed"):
        level2(no_mcs)
    with pytest.raises(ModelError, match=r"at\[0\].node.*node is not on shaft"):
        level1(t, qa=1e5, at=[("s", 9)])
    with pytest.raises(ModelError, match="unknown shaft"):
        level1(t, qa=1e5, at=[("rotor", 1)])
    with pytest.raises(ModelError, match="density_ratio"):
        Stage("s", 2, power=1e6, diameter=0.4, width=0.02, density_ratio=-1.2)
    with pytest.raises(ModelError, match="power"):
        Stage("s", 2, power="1 m", diameter=0.4, width=0.02)
    with pytest.raises(ModelError, match="qa / stages"):
        level1(t)
    with pytest.raises(ModelError, match="at"):
        level1(t, qa=1e5)
    with pytest.raises(ModelError, match="average_density"):
        level1(t, stages=[Stage("s", 2, power=1e6, diameter=0.4, width=0.02)])
    with pytest.raises(ModelError, match="qa"):
        level1(t, qa=-5.0, at=[("s", 2)])
    with pytest.raises(ModelError, match="exclude_bearings"):
        level1(t, qa=1e5, at=[("s", 2)], exclude_bearings=["seal"])


# ---------------------------------------------------------------------------------------------
# which mode Level I follows, and the verdict's monotony in Q_A
W_DISK = 600.0  # rad/s
L_D, D_D, M_D, IP_D = 0.6, 0.15, 50.0, 6.0  # shaft (m), disk mass (kg) and polar inertia


def disk_rotor():
    """A stiff shaft with a thin disk at mid-span on two isotropic bearings: its cylindrical
    mode (123 rad/s) is the first forward mode; gyroscopic stiffening lifts the forward conical
    mode to 711 rad/s at 600 rad/s spin, where the bearings damp it less (log dec 0.107 < 0.154).
    Q at mid-span acts on the cylindrical mode alone."""
    return single_shaft(
        length=L_D,
        diameter=D_D,
        elements=4,
        density=RHO,
        bearings=[{"node": 0, "k": KB, "c": CB}, {"node": 4, "k": KB, "c": CB}],
        disks=[{"node": 2, "mass": M_D, "polar": IP_D, "transverse": IP_D / 2}],
        speed=W_DISK,
        max_continuous_speed=W_DISK,
    )


def _log_dec(s):
    return -2 * np.pi * s.real / s.imag


def test_level1_follows_the_first_forward_mode():
    """API 617 (8th ed. 1.6.5, API RP 684 2nd ed. stability chapter): Level I plots the log dec
    of the *first forward mode* against the applied cross-coupling (ROSS's run_level1 follows
    the same mode). Rigid-rotor closed forms (z = x + iy, ψ the tilt, a = half span):
    cylindrical m s² + 2c s + 2k − iq = 0, forward conical I_t s² + (2c a² − i I_p Ω) s + 2k a²
    = 0. The followed mode at Q = 0 is the cylindrical one (the lower frequency), not the less
    damped conical one, which is reported beside it as the least forward log dec. Tolerances:
    the shaft's flexibility (2k/k_shaft ≈ 2e-3) moves the cylindrical mode by ~2e-3 and, with the
    disk's tilt bending the shaft, the conical mode by ~1 %."""
    ms = RHO * np.pi * D_D**2 / 4 * L_D
    m, r, a = ms + M_D, D_D / 2, L_D / 2
    it = IP_D / 2 + ms * (L_D**2 / 12 + r**2 / 4)
    ip = IP_D + ms * r**2 / 2
    cyl = np.roots([m, 2 * CB, 2 * KB])
    cyl = cyl[np.argmax(cyl.imag)]
    con = np.roots([it, 2 * CB * a**2 - 1j * ip * W_DISK, 2 * KB * a**2])
    con = con[np.argmax(con.imag)]
    assert _log_dec(con) < _log_dec(cyl)  # the least-stable forward mode is not the first
    r1 = level1(disk_rotor(), qa=1e4, at=[("s", 2)])
    assert r1.curve_q[0] == 0.0
    assert r1.curve_log_dec[0] == pytest.approx(_log_dec(cyl), rel=3e-3)
    assert r1.curve_least_log_dec[0] == pytest.approx(_log_dec(con), rel=2e-2)
    assert "first forward mode of shaft 's'" in r1.followed_mode
    # the followed mode is the cylindrical one at every Q: its onset is c_total ω_n = 2c √(2k/m)
    assert r1.threshold_q == pytest.approx(2 * CB * np.sqrt(2 * KB / m), rel=5e-3)
    assert r1.threshold_mode["frequency_rpm"] * RPM == pytest.approx(cyl.imag, rel=3e-3)
    assert r1.mode_changes == ()
    # Q does not touch the conical mode: the least forward log dec is the lesser of the two
    np.testing.assert_allclose(
        r1.curve_least_log_dec,
        np.minimum(r1.curve_least_log_dec[0], r1.curve_log_dec),
        rtol=1e-9,
    )
    d = r1.to_dict()
    assert d["followed_mode"] == r1.followed_mode and d["curve"]["least_forward_log_dec"][0]


@settings(max_examples=6, deadline=None, derandomize=True)
@given(st.floats(3.0, 5.5), st.floats(0.01, 1.5))
def test_level1_verdict_is_monotone_in_qa(log_q, step):
    """A larger anticipated cross-coupling can never make Level I pass."""
    t = disk_rotor()
    small, large = 10**log_q, 10 ** (log_q + step)
    r_small = level1(t, qa=small, at=[("s", 2)], n_curve=0)
    r_large = level1(t, qa=large, at=[("s", 2)], n_curve=0)
    if r_large.passed:
        assert r_small.passed
    assert r_large.log_dec_at_qa <= r_small.log_dec_at_qa + 1e-12


def test_steam_turbine_large_qa_is_no_pass():
    """The steam turbine (examples/steam_turbine_gearbox.toml) at the pinion: Q_A = 1e9 N/m
    gave PASS when the destabilised mode left a 3x MCS frequency window and Q_0 was sought only
    above Q_A. The followed mode's Q_0 (7.29e7, as for Q_A = 5.68e7) lies below Q_A, and the
    rotor's violently unstable mode at Q_A is reported (log dec about -4.6)."""
    from gearrotor.io import load_model

    t = load_model(ROOT / "examples" / "steam_turbine_gearbox.toml")
    r = level1(t, qa=1e9, at=[("pinion", 1)], n_curve=0)
    assert r.verdict == "level II required"
    assert r.threshold_q == pytest.approx(7.29e7, rel=2e-3)
    assert r.least_log_dec_at_qa < -4.0
    failed = {c.name for c in r.criteria if c.ok is False}
    assert failed == {"Q_0 / Q_A", "least log dec of every forward lateral mode at Q_A"}


@pytest.mark.slow
def test_steam_turbine_verdict_monotone_over_qa():
    from gearrotor.io import load_model

    t = load_model(ROOT / "examples" / "steam_turbine_gearbox.toml")
    verdicts = [
        level1(t, qa=q, at=[("pinion", 1)], n_curve=0).passed
        for q in (1e7, 3.6e7, 3.7e7, 5.68e7, 1e8, 3e8, 1e9)
    ]
    assert verdicts == [True, True, False, False, False, False, False]


# ROSS 2.3.0's run_level1 on its rotor_example with damped anisotropic bearings (the script
# tests/audit/data/ross_level1_reference.py regenerates these numbers): log dec of its first
# forward mode at Q = 0, 2e4, 5e4, 1e5 N/m, and Q_0 by Brent's method on the same function
ROSS_Q = (0.0, 2e4, 5e4, 1e5)
ROSS_LOG_DEC = (
    0.062023211371919594,
    0.02062324210205123,
    -0.13279561610922108,
    -0.4014049828010764,
)
ROSS_Q0 = 25912.56423976306


def test_level1_against_ross():
    """Same rotor, same element (Timoshenko with Cowper's shear coefficient, consistent mass,
    gyroscopics), same followed mode: gearrotor's Level I curve and Q_0 equal ROSS's to round-off
    (observed 1e-11 on the log decs, 1e-8 on Q_0; tolerances 1e-8 and the root search's 1e-6).
    Disks as ROSS computes them from geometry (mass, polar, transverse inertia)."""
    w = 4000 * RPM
    disks = [
        {
            "node": n,
            "mass": 32.58972765304033,
            "polar": 0.32956362089137037,
            "transverse": 0.17808928257067666,
        }
        for n in (2, 4)
    ]
    t = single_shaft(
        length=1.5,
        diameter=0.05,
        elements=6,
        E=211e9,
        density=7810.0,
        poisson=211e9 / (2 * 81.2e9) - 1,
        bearings=[
            {"node": n, "kxx": 1e6, "kyy": 0.8e6, "cxx": 500.0, "cyy": 500.0} for n in (0, 6)
        ],
        disks=disks,
        speed=w,
        max_continuous_speed=w,
        shear_method="cowper",
    )
    r = level1(t, qa=1e4, at=[("s", 3)], rtol=1e-9, n_curve=0)
    assert r.threshold_q == pytest.approx(ROSS_Q0, rel=1e-6)
    assert r.curve_q[0] == 0.0 and r.curve_log_dec[0] == pytest.approx(ROSS_LOG_DEC[0], rel=1e-8)
    for q, d in zip(ROSS_Q[1:], ROSS_LOG_DEC[1:], strict=True):
        rq = level1(t, qa=q, at=[("s", 3)], n_curve=0)
        assert rq.log_dec_at_qa == pytest.approx(d, rel=1e-8)


def test_continuation_cost_is_bounded(monkeypatch):
    """Where no mode matches clearly at any step (forced here), the continuation halves each step
    at most MAX_HALVINGS times and stops halving after SOLVE_BUDGET solves: the cost stays
    bounded (without the budget the halvings of every sub-step would compound)."""
    from gearrotor.analyses.audit import stability

    real = stability._Follower._match

    def never_clear(self, qa, qb, res, last):
        return real(self, qa, qb, res, last) if last else None

    monkeypatch.setattr(stability._Follower, "_match", never_clear)
    r = level1(jeffcott(), qa=Q_ONSET / 3, at=[("s", 2)], n_curve=0)
    assert (
        stability.MAX_HALVINGS < r.n_solves <= stability.SOLVE_BUDGET + 4 * stability.MAX_HALVINGS
    )
    assert r.threshold_q == pytest.approx(Q_ONSET, rel=1e-3)  # the nearest eigenvalue is right


def _full_and_targeted(monkeypatch, model, **kw):
    """Level I with every continuation step solved in full (``_TARGETED`` off) and with the
    targeted step, and the targeted run's follower (its counts of targeted steps and
    fall-backs)."""
    from gearrotor.analyses.audit import stability

    made = []
    real_init = stability._Follower.__init__

    def init(self, *args, **kwargs):
        real_init(self, *args, **kwargs)
        made.append(self)

    monkeypatch.setattr(stability._Follower, "__init__", init)
    out = []
    for targeted in (False, True):
        monkeypatch.setattr(stability, "_TARGETED", targeted)
        out.append(level1(model, **kw))
    return out[0], out[1], made[-1]


def _assert_same_level1(full, fast, atol=1e-10, n_curve=11):
    """The same Level I to round-off. The targeted step's eigenvalues come from the same QR
    algorithm as the full solve's, without eigenvectors: they differ by round-off (observed
    up to 4e-10 relative on a log dec, 3e-11 on Q_0); the tolerance is 1e-8, and 1e-10
    absolute on a log dec near 0 (-2π Re λ / Im λ with Re λ's round-off, ~1e-13 |λ|: observed
    9e-12 at Q_0) unless ``atol`` says otherwise."""
    assert fast.verdict == full.verdict
    assert [c.ok for c in fast.criteria] == [c.ok for c in full.criteria]
    assert (fast.threshold_q is None) == (full.threshold_q is None)
    if full.threshold_q is not None:
        assert fast.threshold_q == pytest.approx(full.threshold_q, rel=1e-8)
        assert fast.threshold_mode["frequency_rpm"] == pytest.approx(
            full.threshold_mode["frequency_rpm"], rel=1e-8
        )
    assert fast.log_dec_at_qa == pytest.approx(full.log_dec_at_qa, rel=1e-8, abs=atol)
    assert fast.least_log_dec_at_qa == pytest.approx(full.least_log_dec_at_qa, rel=1e-8, abs=atol)
    assert fast.mode_at_qa["frequency_rpm"] == pytest.approx(
        full.mode_at_qa["frequency_rpm"], rel=1e-8
    )
    assert fast.mode_at_qa["shaft"] == full.mode_at_qa["shaft"]
    assert [(c["from"], c["to"]) for c in fast.mode_changes] == [
        (c["from"], c["to"]) for c in full.mode_changes
    ]
    # the curve at the same Q (Brent's last iterates may differ by round-off): the n_curve
    # points from 0 to beyond max(Q_A, Q_0) and the path's quarters are in both
    j = np.array([np.argmin(np.abs(fast.curve_q - q)) for q in full.curve_q])
    same_q = np.abs(fast.curve_q[j] - full.curve_q) <= 1e-8 * full.q_max
    assert same_q.sum() >= max(n_curve, 5)
    np.testing.assert_allclose(
        fast.curve_log_dec[j[same_q]], full.curve_log_dec[same_q], rtol=1e-8, atol=atol
    )
    np.testing.assert_allclose(
        fast.curve_least_log_dec[j[same_q]],
        full.curve_least_log_dec[same_q],
        rtol=1e-8,
        atol=atol,
    )


@pytest.mark.parametrize(
    "case",
    [
        ("steam_turbine_gearbox.toml", "pinion", 5.68e7, 11),
        pytest.param(("steam_turbine_gearbox.toml", "pinion", 1e9, 0), marks=pytest.mark.slow),
        ("motor_gearbox_compressor.toml", "compressor", 1e7, 11),
    ],
    ids=["steam-turbine", "steam-turbine-1e9", "flagship-compressor"],
)
def test_targeted_continuation_equals_the_full_solves(monkeypatch, case):
    """The targeted continuation step (every eigenvalue, eigenvectors only of the modes the
    step reads) follows the same mode to the same Q_0, log decs and verdict as the full solve
    at every step; on these trains every step after Q = 0 is targeted (no fall-back). The
    flagship's compressor at mid-span loses stability below Q_A (Q_0 found on the path), the
    steam turbine beyond it (by secant extrapolation); with Q_A = 1e9 N/m the steam turbine's
    followed mode passes close modes, where the nearest eigenvalue does not decide some steps
    and the shapes of every mode do (read by inverse iteration too)."""
    from gearrotor.io import load_model

    name, shaft, qa, n_curve = case
    t = load_model(ROOT / "examples" / name)
    speed = None if t.max_continuous_speed is not None else 1.05 * abs(t.speed)
    full, fast, f = _full_and_targeted(
        monkeypatch, t, qa=qa, at=[mid_span(t, shaft)], speed=speed, n_curve=n_curve
    )
    _assert_same_level1(full, fast, n_curve=n_curve)
    assert full.threshold_q is not None
    assert f.targeted and f.n_targeted == f.n_solves - 2 and not f.fallbacks
    assert fast.n_solves == f.n_solves
    if qa == 1e9:
        assert f.n_every_mode > 0


def test_targeted_continuation_falls_back_on_close_eigenvalues(monkeypatch):
    """The Jeffcott rotor's forward and backward cylindrical modes are one double eigenvalue at
    Q = 0 that Q splits (ω_n ± ~q/(2 m ω_n)), and its free axial and torsional motions give
    pairs of eigenvalues at ~0 that round-off splits: inverse iteration cannot separate those,
    so steps fall back to the full solve (and, once the fall-backs outnumber the targeted steps
    by FALLBACK_LIMIT, every later step is solved in full). The followed mode is still the
    forward cylindrical one: Q_0 is its closed-form onset c_total ω_n, as with full solves."""
    from gearrotor.analyses.audit import stability

    full, fast, f = _full_and_targeted(monkeypatch, jeffcott(), qa=Q_ONSET / 3, at=[("s", 2)])
    # the practically rigid shaft (bending stiffness ~3e10 N/m) makes the QR algorithm's
    # round-off on Re λ of the 130 rad/s mode ~1e-8 rad/s: 3e-10 on its log dec near Q_0
    _assert_same_level1(full, fast, atol=1e-9)
    assert fast.threshold_q == pytest.approx(Q_ONSET, rel=1e-3)
    assert f.fallbacks.get("inverse iteration", 0) >= 1 and f.n_targeted >= 1
    assert sum(f.fallbacks.values()) == f.n_targeted + stability.FALLBACK_LIMIT
    assert not f.targeted
