"""Involute geometry of gear pairs (gearrotor.gears.geometry, .tooth): closed forms of ISO
21771 (base, tip, root radii, working pressure angle, contact and overlap ratios), the
rack-generated tooth profile against the involute and the closed-form root angle, and the
one-line errors for impossible geometry."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gearrotor.errors import ModelError
from gearrotor.gears import pair_geometry, tooth_profile
from gearrotor.gears.geometry import inv, inv_inverse

ROSS = json.loads((Path(__file__).with_name("ross_reference.json")).read_text())
A20 = np.deg2rad(20.0)


def test_inverse_involute():
    for a in (0.05, 0.3, 0.5, 0.9, 1.3):
        assert inv_inverse(float(inv(a))) == pytest.approx(a, abs=1e-13)


def test_radii_and_contact_ratio_closed_form():
    """ISO 21771: r_b = m z cos α / 2, r_a = r + m, r_f = r − 1.25 m; εα = (√(ra1² − rb1²)
    + √(ra2² − rb2²) − a sin α)/(π m cos α). ROSS 3.1 reports 1.7897798668 for its pair (same
    closed form)."""
    g = pair_geometry((62, 62), 0.002, A20, 0.02)
    t = g.pinion
    assert t.r_b == pytest.approx(0.062 * np.cos(A20), rel=1e-14)
    assert (t.r_a, t.r_f) == pytest.approx((0.064, 0.0595), rel=1e-14)
    eps = (2 * np.sqrt(0.064**2 - t.r_b**2) - 0.124 * np.sin(A20)) / (np.pi * 0.002 * np.cos(A20))
    assert g.contact_ratio == pytest.approx(eps, rel=1e-12)
    assert g.contact_ratio == pytest.approx(ROSS["contact_ratio"], rel=1e-12)


def test_profile_shift_working_pressure_angle():
    """inv α_w = inv α + 2 tan α (x1 + x2)/(z1 + z2) and a_w cos α_w = a cos α (ISO 21771)."""
    x = (0.4, 0.2)
    g = pair_geometry((18, 41), 0.004, A20, 0.03, profile_shift=x)
    a = 0.004 * (18 + 41) / 2
    assert float(inv(g.alpha_wt)) == pytest.approx(
        float(inv(A20)) + 2 * np.tan(A20) * 0.6 / 59, rel=1e-12
    )
    assert g.center_distance * np.cos(g.alpha_wt) == pytest.approx(a * np.cos(A20), rel=1e-12)
    assert g.pinion.r_a == pytest.approx(0.036 + 1.4 * 0.004)


def test_helical_transverse_quantities_and_overlap():
    """m_t = m_n / cos β, tan α_t = tan α_n / cos β, εβ = b sin β / (π m_n)."""
    b = np.deg2rad(15.0)
    g = pair_geometry((30, 60), 0.003, A20, 0.06, helix_angle=b)
    assert g.pinion.r == pytest.approx(0.003 / np.cos(b) * 15, rel=1e-14)
    assert g.pinion.alpha_t == pytest.approx(np.arctan(np.tan(A20) / np.cos(b)), rel=1e-14)
    assert g.overlap_ratio == pytest.approx(0.06 * np.sin(b) / (np.pi * 0.003), rel=1e-14)
    assert np.sin(g.beta_b) == pytest.approx(np.sin(b) * np.cos(A20), rel=1e-14)


@pytest.mark.parametrize("shift", [0.0, 0.3, -0.2])
def test_generated_flank_is_the_involute(shift):
    """The generation kinematics of the fillet (rack rolling on the reference circle, contact
    normal through the pitch point) applied to the rack's straight flank gives points on the
    involute of the base circle with the tooth's half angle ψ(r) = ψ_b − inv α_r: checks the
    frames the fillet is computed in."""
    g = pair_geometry((25, 40), 0.003, A20, 0.02, profile_shift=(shift, 0.0))
    t = g.pinion
    r, a, mt = t.r, t.alpha_t, t.transverse_module
    y_d = r + t.shift * t.module
    depth = np.linspace(0.2, 0.9, 7) * t.module  # points of the straight flank below the datum
    for d in depth:
        y = y_d - d
        u = np.pi * mt / 4 - d * np.tan(a)  # the right flank of the rack tooth
        # the rack position s where the flank normal at (u + s, y) passes through (0, r)
        n = np.array([np.cos(a), -np.sin(a)])
        # (u + s, y) + λ n = (0, r): λ = (r − y)/(−sin a); s = −u − λ cos a
        lam = (r - y) / (-np.sin(a))
        s = -u - lam * np.cos(a)
        px, py = u + s, y
        phi = s / r + np.pi / t.teeth
        c, sn = np.cos(phi), np.sin(phi)
        x_t, y_t = c * px - sn * py, sn * px + c * py
        R = np.hypot(x_t, y_t)
        assert -x_t == pytest.approx(R * np.sin(t.psi(R)), rel=1e-10)
        assert n @ n == pytest.approx(1.0)


def test_fillet_joins_the_involute_and_root_circle():
    """The trochoidal fillet starts on the root circle at the half angle θ_f = π/z − u_c/r
    (the rack tip circle's centre at u_c from the rack tooth's centre line; for the full-round
    ISO 53 rack θ_f z = π/2 + 2 tan α (h_a* + c* − ρ*) + 2ρ*/cos α) and ends on the form
    circle where the involute starts, with the same half thickness."""
    g = pair_geometry((62, 62), 0.002, A20, 0.02)
    t = g.pinion
    p = tooth_profile(t)
    assert np.hypot(*p.fillet[0]) == pytest.approx(t.r_f, rel=1e-12)
    rho = t.rho / t.module
    theta = (np.pi / 2 + 2 * np.tan(A20) * (1.25 - rho) + 2 * rho / np.cos(A20)) / 62
    assert p.theta_f == pytest.approx(theta, rel=1e-12)
    x_form = t.r_form * np.sin(t.psi(t.r_form))
    assert p.fillet[-1] == pytest.approx([x_form, t.r_form * np.cos(t.psi(t.r_form))], rel=1e-9)
    assert np.all(np.diff(p.y) > 0) and np.all(p.h > 0)


@pytest.mark.parametrize(
    ("kwargs", "field", "words"),
    [
        (dict(teeth=(12, 40), profile_shift=(0.0, 0.0)), "profile_shift[0]", "undercut"),
        (dict(teeth=(12, 40), profile_shift=(1.2, 0.0)), "profile_shift[0]", "pointed"),
        (dict(teeth=(20, 40), addendum=0.5), "addendum_coefficient", "contact ratio"),
        (dict(teeth=(20, 40), addendum=1.3), "addendum_coefficient", "tip circle"),
        (dict(teeth=(19, 200), addendum=1.1), "profile_shift", "interference"),
    ],
)
def test_impossible_geometry_one_line_errors(kwargs, field, words):
    teeth = kwargs.pop("teeth")
    with pytest.raises(ModelError) as exc:
        pair_geometry(teeth, 0.003, A20, 0.02, **kwargs)
    msg = str(exc.value)
    assert "\n" not in msg and exc.value.field == field and words in msg, msg
