"""Couplings, cross-coupled stiffness, pedestals, thrust bearings, speed tables, disk geometry:
each against a closed form."""

import numpy as np
import pytest

from gearrotor.analyses import modal
from gearrotor.assembly import assemble
from gearrotor.errors import ModelError
from gearrotor.model import Train
from helpers import single_shaft

MAT = {"m": {"E": 2e11, "density": 7800, "poisson": 0.3}}


def jeffcott(extra_bearings=(), kb=1e14, **kw):
    """Disk (m = 20 kg) at mid-span of a light shaft on stiff bearings."""
    return single_shaft(
        length=0.8,
        diameter=0.03,
        elements=4,
        density=1.0,
        bearings=[{"node": 0, "k": kb}, {"node": 4, "k": kb}, *extra_bearings],
        disks=[{"node": 2, "mass": 20.0, "polar": 0.1, "transverse": 0.05}],
        **kw,
    )


def _kshaft(t):
    """Mid-span stiffness of the Jeffcott shaft from the model itself (static condensation)."""
    asm = assemble(t)
    K = asm.K0.toarray()
    keep = [i for i in range(asm.n_dof) if i % 6 in (0, 4)]
    Kx = K[np.ix_(keep, keep)]
    f = np.zeros(len(keep))
    f[2 * 2] = 1.0
    return 1 / np.linalg.solve(Kx, f)[4]


def test_cross_coupling_destabilises_forward_whirl():
    """m λ² + c λ + k − i q = 0 for forward whirl (u = x + iy): the exact eigenvalues."""
    c, q = 400.0, 3e5
    base = jeffcott()
    k = _kshaft(base)
    t = jeffcott(
        extra_bearings=[{"node": 2, "c": c}],
        cross_couplings=[{"shaft": "s", "node": 2, "q": q}],
    )
    res = modal(t, speed=100.0)
    m = 20.0 + 1.0 * np.pi * 0.03**2 / 4 * 0.8 / 2
    lat = [i for i in range(len(res)) if res.mode_type[i] == "L"][:2]
    fwd = [i for i in lat if res.whirl[i] == "F"][0]
    bwd = [i for i in lat if res.whirl[i] == "B"][0]
    lf = np.roots([m, c, k - 1j * q])
    lf = lf[lf.imag > 0][0]
    # the backward mode is the root with Im λ < 0 (u ∝ e^{-iωt}), reported as its conjugate
    lb = np.roots([m, c, k - 1j * q])
    lb = lb[lb.imag < 0][0].conjugate()
    # the light shaft's distributed mass (1e-5 of m) is lumped approximately: 1e-4
    assert res.eigenvalues[fwd] == pytest.approx(lf, rel=1e-4)
    assert res.eigenvalues[bwd] == pytest.approx(lb, rel=1e-4)
    # onset: q > c ω_n destabilises the forward mode
    assert (q > c * np.sqrt(k / m)) == (res.log_dec[fwd] < 0)
    assert not res.stable


def test_pedestal_two_mass_system():
    """Rigid rotor (mass m) on bearing kb to a pedestal (mass mp) on kp: 2-DOF closed form."""
    kb, kp, mp = 2e7, 5e7, 30.0
    sup = {"mass": mp / 2, "kxx": kp / 2, "kyy": kp / 2}
    t = single_shaft(
        length=0.5,
        diameter=0.05,
        elements=2,
        E=1e17,
        density=1.0,
        bearings=[
            {"node": 0, "k": kb / 2, "support": sup},
            {"node": 2, "k": kb / 2, "support": sup},
        ],
        disks=[{"node": 1, "mass": 50.0, "polar": 0.1, "transverse": 0.05}],
    )
    m = 50.0 + np.pi * 0.05**2 / 4 * 0.5
    Mm = np.diag([m, mp])
    Km = np.array([[kb, -kb], [-kb, kb + kp]])
    ref = np.sqrt(np.linalg.eigvals(np.linalg.solve(Mm, Km)).real)
    res = modal(t, speed=0.0)
    lat = res.damped_frequency[np.array(res.mode_type) == "L"]
    # both cylindrical 2-DOF frequencies appear (each twice: x and y); conical modes besides
    for f in ref:
        assert np.sum(np.abs(lat - f) < 1e-5 * f) == 2


def test_thrust_bearing_axial_mode():
    kz = 1e8
    t = single_shaft(
        length=0.5,
        diameter=0.05,
        elements=2,
        E=1e17,
        density=7800.0,
        bearings=[{"node": 0, "k": 1e8}, {"node": 2, "k": 1e8}],
        thrust_bearings=[{"shaft": "s", "node": 0, "kzz": kz}],
    )
    m = 7800.0 * np.pi * 0.05**2 / 4 * 0.5
    res = modal(t, speed=0.0)
    ax = res.damped_frequency[np.array(res.mode_type) == "A"]
    assert ax[0] == pytest.approx(np.sqrt(kz / m), rel=1e-6)


def test_rigid_coupling_equals_one_shaft():
    """Two shafts joined by a very stiff coupling behave as one shaft of twice the length
    (the coupled node pair adds one node's worth of discretisation only)."""
    one = single_shaft(
        length=1.0,
        diameter=0.05,
        elements=20,
        bearings=[{"node": 0, "k": 1e7}, {"node": 20, "k": 1e7}],
    )
    half = {"length": 0.5, "outer_diameter": 0.05, "elements": 10}
    big = 1e13
    two = Train.model_validate(
        {
            "materials": {"steel": {"E": 211e9, "density": 7850.0, "poisson": 0.3}},
            "shafts": [
                {"name": "a", "material": "steel", "sections": [half]},
                {"name": "b", "material": "steel", "sections": [half], "start": 0.5},
            ],
            "bearings": [{"shaft": "a", "node": 0, "k": 1e7}, {"shaft": "b", "node": 10, "k": 1e7}],
            "couplings": [
                {
                    "node_i": {"shaft": "a", "node": 10},
                    "node_j": {"shaft": "b", "node": 0},
                    **{k: big for k in ("kx", "ky", "kz", "ktx", "kty", "ktz")},
                }
            ],
        }
    )
    r1 = modal(one, speed=0.0, max_frequency=3000.0)
    r2 = modal(two, speed=0.0, max_frequency=3000.0)

    def lateral(r):
        return np.sort(r.damped_frequency[["L" in t for t in r.mode_type]])

    # the coupled node pair (two nodes at z = 0.5 m joined by 1e13 springs) is the single
    # shaft's node split in two: the same mass and, to 1e-6, the same stiffness
    np.testing.assert_allclose(lateral(r2), lateral(r1), rtol=1e-6)
    assert np.array_equal(assemble(two).speed_ratio, [1.0, 1.0])


def test_speed_tabulated_bearing_is_interpolated():
    table = {
        "speed": ["1000 rpm", "3000 rpm"],
        "kxx": [1e7, 3e7],
        "kxy": [0, 0],
        "kyx": [0, 0],
        "kyy": [1e7, 3e7],
        "cxx": [0, 0],
        "cxy": [0, 0],
        "cyx": [0, 0],
        "cyy": [0, 0],
    }
    data = jeffcott().model_dump(exclude_none=True)
    data["bearings"][0] = {"shaft": "s", "node": 0, "table": table}
    t = Train.model_validate(data)
    asm = assemble(t)
    b = asm.bearings[0]
    assert b.element.speed_dependent
    np.testing.assert_allclose(b.element.K(2000 * np.pi / 30), np.diag([2e7, 2e7]), rtol=1e-12)
    with pytest.raises(ModelError, match="outside the bearing coefficient table"):
        asm.matrices(5000 * np.pi / 30)


def test_disk_from_geometry():
    """Solid/hollow cylinder: m = ρπ(D²−d²)w/4, Ip = m(D²+d²)/8, It = m(D²+d²)/16 + m w²/12."""
    D, d, w, rho = 0.3, 0.06, 0.05, 7800.0
    t = single_shaft(
        density=rho,
        disks=[{"node": 5, "outer_diameter": D, "inner_diameter": d, "width": w}],
        bearings=[{"node": 0, "k": 1e7}],
    )
    base = single_shaft(density=rho, bearings=[{"node": 0, "k": 1e7}])
    dm = (assemble(t).M - assemble(base).M).toarray()
    o = 6 * 5
    m = rho * np.pi * (D**2 - d**2) * w / 4
    assert dm[o, o] == pytest.approx(m)
    assert dm[o + 5, o + 5] == pytest.approx(m * (D**2 + d**2) / 8)
    assert dm[o + 3, o + 3] == pytest.approx(m * (D**2 + d**2) / 16 + m * w**2 / 12)
