"""Shaft material damping (``[materials.NAME] damping``): Rayleigh damping α M_e + β K_e of the
shaft elements, stationary or rotating with the shaft.

Oracles: the modal damping ratio ζ = α/(2ω) + βω/2 of proportional damping (free shaft); the
classical internal-damping threshold Ω_th = ω_n (1 + c_e/c_i) of a Jeffcott rotor (Zorzi &
Nelson 1977; Friswell et al. 2010, ch. 5); the absence of rotating-frame strain rate in a
synchronous forward whirl (internal damping leaves the unbalance response unchanged); agreement
between the modal, transient and Floquet paths."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gearrotor.analyses import campbell, modal, unbalance_response
from gearrotor.analyses.lateral.floquet import floquet
from gearrotor.analyses.transient import RK4, ModalRK4, Save, build_system, transient
from gearrotor.assembly import assemble
from gearrotor.errors import ModelError
from gearrotor.io import load_model, model_from_dict
from gearrotor.model import Train
from helpers import single_shaft

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _damped(train: Train, damping: dict | None) -> Train:
    """The train with ``damping`` on every material (None: as given)."""
    data = train.model_dump()
    if damping is not None:
        for m in data["materials"].values():
            m["damping"] = damping
    return Train.model_validate(data)


def _free_shaft(damping: dict | None, speed: float = 0.0) -> Train:
    """Free-free uniform steel shaft, 1 m × 50 mm, 20 elements (no bearings)."""
    return _damped(single_shaft(length=1.0, diameter=0.05, elements=20, speed=speed), damping)


def _jeffcott(
    damping: dict | None, c_ext: float, speed: float = 0.0, unbalance: float = 0.0
) -> Train:
    """Uniform shaft (1 m × 50 mm, 8 elements) with a 20 kg central disk, on very stiff
    undamped end bearings (1e10 N/m); external damping ``c_ext`` (N·s/m) and an optional
    ``unbalance`` (kg·m) at the disk."""
    bearings = [{"node": 0, "k": 1e10}, {"node": 8, "k": 1e10}]
    if c_ext:
        bearings.append({"node": 4, "c": c_ext})
    t = single_shaft(
        length=1.0,
        diameter=0.05,
        elements=8,
        speed=speed,
        bearings=bearings,
        disks=[{"node": 4, "mass": 20.0, "polar": 0.05, "transverse": 0.03}],
        unbalances=[{"shaft": "s", "node": 4, "amount": unbalance}] if unbalance else [],
    )
    return _damped(t, damping)


def _first_lateral(res, whirl: str | None = None) -> int:
    """Index of the lowest lateral, not over-damped mode (of the given whirl)."""
    for i in range(len(res)):
        if res.mode_type[i] == "L" and not res.overdamped[i] and whirl in (None, res.whirl[i]):
            return i
    raise AssertionError("no lateral mode")


# ---- input ------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("damping", "field", "text"),
    [
        ({"beta": -1e-6}, "materials.steel.damping.beta", "greater than or equal to 0"),
        ({"alpha": "-2 1/s"}, "materials.steel.damping.alpha", "greater than or equal to 0"),
        ({"beta": "2e-6 m"}, "materials.steel.damping.beta", "expected a time"),
        ({"gamma": 1.0}, "materials.steel.damping.gamma", "unknown key"),
        ({"loss_factor": 0.002}, "materials.steel.damping", "go together"),
        (
            {"loss_factor": 0.002, "reference_frequency": "100 Hz", "beta": "1e-6 s"},
            "materials.steel.damping",
            "not both",
        ),
        ({"alpha": 2.0, "rotating": True}, "materials.steel.damping", "alpha = 0"),
        (
            {"loss_factor": 0.002, "reference_frequency": "-5 Hz"},
            "materials.steel.damping.reference_frequency",
            "greater than 0",
        ),
    ],
)
def test_bad_damping_input_names_the_field(damping, field, text):
    data = single_shaft().model_dump()
    data["materials"]["steel"]["damping"] = damping
    with pytest.raises(ModelError) as exc:
        model_from_dict(data, file="model.toml")
    msg = str(exc.value)
    assert "model.toml" in msg and field in msg and text in msg, msg


def test_input_forms_and_units():
    """``loss_factor`` η at ``reference_frequency`` f is β = η/(2πf); units are converted."""
    mat = _free_shaft({"loss_factor": 0.004, "reference_frequency": "50 Hz"}).materials["steel"]
    assert mat.damping.rayleigh == (0.0, pytest.approx(0.004 / (2 * np.pi * 50)))
    mat = _free_shaft({"alpha": "0.5 1/s", "beta": "2 us"}).materials["steel"]
    assert mat.damping.rayleigh == (0.5, 2e-6)


# ---- zero damping changes nothing -------------------------------------------------------------
def _same(a, b) -> None:
    a, b = a.tocsr(), b.tocsr()
    a.sort_indices()
    b.sort_indices()
    assert np.array_equal(a.indptr, b.indptr) and np.array_equal(a.indices, b.indices)
    assert np.array_equal(a.data, b.data)


@pytest.mark.parametrize(
    "zero", [{}, {"alpha": 0.0, "beta": "0 s"}, {"beta": 0.0, "rotating": True}]
)
def test_zero_damping_leaves_the_matrices_exactly_unchanged(zero):
    """Zero coefficients (also rotating) give bit-identical matrices to a model without
    ``damping`` (SPEC 6.1 gearbox), in the assembly, at a speed and in the transient; an
    undamped material serialises without the key, so existing models keep their JSON (study
    case keys, checkpoint fingerprints)."""
    base = load_model(EXAMPLES / "unity_gearbox.toml")
    assert all("damping" not in m for m in base.model_dump()["materials"].values())
    other = _damped(base, zero)
    a, b = assemble(base), assemble(other)
    assert not b.rotating_damping
    for x, y in zip((a.M, a.K0, a.C0, *a.G_shaft), (b.M, b.K0, b.C0, *b.G_shaft), strict=True):
        _same(x, y)
    for x, y in zip(a.matrices(1.3 * base.speed), b.matrices(1.3 * base.speed), strict=True):
        _same(x, y)
    for x, y in zip(
        build_system(a).linear_matrices(), build_system(b).linear_matrices(), strict=True
    ):
        assert np.array_equal(x, y)


# ---- modal damping ratios ---------------------------------------------------------------------
@pytest.mark.parametrize(
    "damping",
    [
        {"alpha": "3 1/s", "beta": "2e-6 s"},
        {"beta": "2e-6 s", "rotating": True},
        {"loss_factor": 0.004, "reference_frequency": "1000 Hz"},
    ],
)
def test_free_shaft_modal_damping_ratio(damping):
    """Free-free uniform shaft at rest: C = α M + β K of the whole model (no other element), so
    the undamped modes are the damped ones with ζ = α/(2ω) + βω/2 and |λ| = ω, for bending,
    axial and torsional modes alike (the torsional α part is taken relative to the rigid
    rotation, which a free shaft's torsional modes are M-orthogonal to). Both hold to the
    eigensolver's round-off: measured ≤ 1.9e-10 (ζ) and 1.4e-12 (|λ|), asserted at 1e-9."""
    und = modal(_free_shaft(None), speed=0.0)
    train = _free_shaft(damping)
    alpha, beta = train.materials["steel"].damping.rayleigh
    res = modal(train, speed=0.0)
    n = 30
    assert res.mode_type[:n] == und.mode_type[:n]
    assert {"L", "A", "T"} <= set(und.mode_type[:n])
    w = und.damped_frequency[:n]
    np.testing.assert_allclose(res.natural_frequency[:n], w, rtol=1e-9)
    np.testing.assert_allclose(res.damping_ratio[:n], alpha / (2 * w) + beta * w / 2, rtol=1e-9)
    # the spin is not damped: the torsional rigid rotation stays a zero-frequency rigid mode
    assert res.n_rigid_body == und.n_rigid_body
    asm = assemble(train)
    spin = np.zeros(asm.n_dof)
    spin[asm.shaft_dofs(0, 5)] = 1.0
    assert np.abs(asm.C0 @ spin).max() < 1e-12 * np.abs(asm.C0).max()


# ---- rotating damping: the internal-damping instability ---------------------------------------
def test_rotating_damping_threshold_of_a_jeffcott_rotor():
    """Stiff bearings, central disk, internal damping β K (rotating) and external damping c_e
    at the disk. The forward mode is stable below and unstable above Ω_th = ω_n (1 + ζ_e/ζ_i)
    (c_e/c_i = ζ_e/ζ_i for one mode), with ω_n, ζ_i and ζ_e the model's own modal values at
    rest with each damping alone. Found by bisection on the forward mode's log dec: measured
    Ω_th 5.8e-4 above the formula, which is the forward mode's gyroscopic stiffening by the
    shaft's own rotary inertia (ν/ω_n − 1 = 5.8e-4 at Ω_th); with the forward frequency ν at
    Ω_th in place of ω_n they agree to 2e-6 (modal coupling through the skew term, O(ζ²)),
    asserted at 3e-5.
    Stationary damping of the same size never destabilises."""
    beta, c_ext = 1e-4, 120.0
    rest = modal(_jeffcott(None, 0.0), speed=0.0)
    i = _first_lateral(rest)
    wn = rest.natural_frequency[i]
    zi = modal(_jeffcott({"beta": beta}, 0.0), speed=0.0)
    ze = modal(_jeffcott(None, c_ext), speed=0.0)
    ratio = ze.damping_ratio[_first_lateral(ze)] / zi.damping_ratio[_first_lateral(zi)]
    analytic = wn * (1 + ratio)

    rot = assemble(_jeffcott({"beta": beta, "rotating": True}, c_ext))
    assert rot.rotating_damping

    def forward(speed):
        res = modal(rot, speed=speed)
        f = _first_lateral(res, "F")
        return res.log_dec[f], res.damped_frequency[f]

    lo, hi = wn, 3 * wn
    while hi - lo > 1e-7 * wn:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if forward(mid)[0] > 0 else (lo, mid)
    found = 0.5 * (lo + hi)
    nu = forward(found)[1]
    assert found == pytest.approx(analytic, rel=2e-3)
    assert found == pytest.approx(nu * (1 + ratio), rel=3e-5)
    below, above = modal(rot, speed=0.98 * found), modal(rot, speed=1.02 * found)
    assert below.stable and not above.stable
    unstable = np.flatnonzero(above.unstable)
    assert [(above.whirl[k], above.mode_type[k]) for k in unstable] == [("F", "L")]

    stationary = assemble(_jeffcott({"beta": beta}, c_ext))
    for factor in (0.5, 1.0, 1.5, 2.0, 3.0):
        assert modal(stationary, speed=factor * found).stable

    # the Campbell diagram tracks the same sign change of the forward mode's log dec
    cd = campbell(rot, speeds=[0.9 * found, 1.1 * found], max_frequency=1.2 * wn)
    fwd = [j for j in range(cd.log_dec.shape[1]) if cd.whirl[0, j] == "F"]
    assert cd.log_dec[0, fwd].min() > 0 > cd.log_dec[1, fwd].min()


def test_rotating_damping_leaves_the_unbalance_response_unchanged():
    """An unbalance drives a circular forward whirl at the spin speed: the material sees no
    strain rate, so rotating damping adds nothing (the damping C and the circulatory Ω Kc
    cancel), while stationary damping of the same size lowers the peak. Agreement to the
    sparse solve's round-off (measured 1.8e-12; the bearings are 1e10 N/m)."""
    speeds = np.linspace(100.0, 600.0, 26)  # through the critical speed, ≈ 335 rad/s
    ref = unbalance_response(_jeffcott(None, 120.0, unbalance=1e-4), speeds=speeds).response
    rot = _jeffcott({"beta": 1e-4, "rotating": True}, 120.0, unbalance=1e-4)
    got = unbalance_response(rot, speeds=speeds).response
    assert np.abs(got - ref).max() < 1e-9 * np.abs(ref).max()
    sta = _jeffcott({"beta": 1e-4}, 120.0, unbalance=1e-4)
    sta = unbalance_response(sta, speeds=speeds).response
    assert np.abs(sta).max() < 0.7 * np.abs(ref).max()


# ---- transient and Floquet ----------------------------------------------------------------------
@pytest.mark.parametrize(
    "integrator",
    [RK4(dt=2.5e-6), ModalRK4(dt=2.5e-6, cutoff=2000.0)],
    ids=["rk4", "modal-rk4"],
)
def test_transient_torsional_decay_matches_the_modal_eigenvalue(integrator):
    """Free shaft spinning at 300 rad/s, α = 20 1/s, β = 1e-6 s, released from a twist in its
    first torsional mode (1609 Hz): the twist (end-to-end) follows
    x₀ e^{σt}(cos ω_d t − σ/ω_d sin ω_d t) with λ = σ + iω_d from the modal analysis
    (σ = −61 1/s: the twist decays to 54 % in the 0.01 s run; a 1 % error in σ would be
    ~3e-3 of x₀); the spin is not braked by the mass-proportional term. The difference is
    RK4's phase error, ~ (ω dt)⁵/120 per step: measured 1.8e-7 of x₀ at ω dt = 0.025 (3e-6 at
    twice the step, the h⁴ of RK4), asserted at 1e-5. The speed stays at its start value to
    round-off (measured 4e-11 rad/s)."""
    train = _free_shaft({"alpha": 20.0, "beta": 1e-6}, speed=300.0)
    asm = assemble(train)
    res = modal(asm, speed=0.0)
    k = res.mode_type.index("T")
    lam = res.eigenvalues[k]
    tz = asm.shaft_dofs(0, 5)
    q0 = np.zeros(asm.n_dof)
    q0[tz] = 1e-3 * res.mode_shapes[k].real[tz]
    r = transient(
        train,
        t_end=0.01,
        integrator=integrator,
        initial_q=q0,
        save=Save(dt=2e-5, full_state=True),
    )
    twist = r.channel(tz[0]) - r.channel(tz[-1])
    x0 = q0[tz[0]] - q0[tz[-1]]
    s, wd = lam.real, lam.imag
    expect = x0 * np.exp(s * r.time) * (np.cos(wd * r.time) - s / wd * np.sin(wd * r.time))
    assert np.abs(twist - expect).max() < 1e-5 * abs(x0)
    assert np.ptp(r.shaft_speed) < 1e-9 * 300.0


def test_transient_applies_rotating_damping():
    """The transient's linear part equals the assembly's matrices at the nominal speed (the
    circulatory term at the nominal speed, see transient.equations) and at another speed via
    ``at_speed``; above the threshold the forward whirl of the Jeffcott rotor grows in the
    (modal) transient at the modal growth rate: measured 7.7669 vs 7.7665 1/s, a straight-line
    fit of log|x + iy| over 0.2–0.4 s, when the backward mode has decayed by e⁻⁸; 1e-3."""
    speed = 930.0  # 2× the threshold of the previous test
    train = _jeffcott({"beta": 1e-4, "rotating": True}, 120.0, speed=speed)
    asm = assemble(train)
    disk = asm.dof(0, 4, 0)
    q0 = np.zeros(asm.n_dof)
    q0[disk] = 1e-5
    system = build_system(asm, initial_q=q0)
    act = np.ix_(system.active, system.active)
    for s, sys_ in ((speed, system), (0.6 * speed, system.at_speed(0.6 * speed))):
        _, C, _, K = (m.toarray()[act] for m in asm.matrices(s))
        _, Kt, Ct = sys_.linear_matrices()
        np.testing.assert_allclose(Kt, K, rtol=0, atol=1e-12 * np.abs(K).max())
        assert np.array_equal(Ct, C)

    res = modal(asm)
    lam = res.eigenvalues[_first_lateral(res, "F")]
    assert lam.real > 0
    r = transient(
        train,
        t_end=0.4,
        integrator=ModalRK4(cutoff=200.0, dt=1e-4),
        initial_q=q0,
        save=Save(dt=2e-4, full_state=True),
    )
    late = r.time > 0.2
    amp = np.abs(r.channel(disk) + 1j * r.channel(disk + 1))[late]
    rate = np.polyfit(r.time[late], np.log(amp), 1)[0]
    assert rate == pytest.approx(lam.real, rel=1e-3)


def test_floquet_with_rotating_damping_gives_the_damped_eigenvalues():
    """SPEC 6.1 gearbox with rotating material damping at 1.3× its speed, constant mesh
    stiffness (Ka = 0), every mode kept: the Floquet exponents are the modal eigenvalues
    (growth = Re λ, frequency = Im λ), so the Floquet path has the material damping and the
    circulatory term at the analysis speed. Modes below ζ = 0.5 (heavily over-damped ones have
    |μ| = e^{σT} far below round-off); 1e-7 as in tests/test_floquet.py."""
    train = _damped(load_model(EXAMPLES / "unity_gearbox.toml"), {"beta": 2e-6, "rotating": True})
    w = 1.3 * train.speed
    fl = floquet(train, ka_ratio=0.0, cutoff=1e9, speed=w)
    res = modal(train, speed=w, max_frequency=1e12)
    om_m = fl.mesh_frequency.max()
    checked = 0
    for lam, zeta in zip(res.eigenvalues, res.damping_ratio, strict=True):
        if not (1.0 < lam.imag < 0.45 * om_m and zeta < 0.5):
            continue
        d = np.abs(fl.growth - lam.real) / abs(lam) + np.abs(fl.frequency - lam.imag) / abs(lam)
        assert d.min() < 1e-7, lam
        checked += 1
    assert checked >= 10


def test_shaft_element_circulatory_matrix():
    """Kc is skew, zero without rotating damping, and couples only the two bending planes."""
    from gearrotor.elements import ShaftElement

    el = ShaftElement(0.1, 0.05, 0.0, 211e9, 81e9, 7850.0, alpha=0.0, beta=2e-6)
    assert not el.Kc().any()
    kc = ShaftElement(0.1, 0.05, 0.0, 211e9, 81e9, 7850.0, beta=2e-6, rotating_damping=True).Kc()
    np.testing.assert_array_equal(kc, -kc.T)
    axial_torsion = [2, 5, 8, 11]
    assert not kc[axial_torsion].any() and not kc[:, axial_torsion].any()
    x_plane, y_plane = [0, 4, 6, 10], [1, 3, 7, 9]
    assert not kc[np.ix_(x_plane, x_plane)].any() and not kc[np.ix_(y_plane, y_plane)].any()


def test_transient_warns_when_a_rotating_damped_shaft_changes_speed():
    """The circulatory term is applied at the nominal speed: a run whose shaft turns 5 % faster
    (a uniform extra spin as the initial state) is warned about; at the nominal speed it is
    not."""
    import warnings

    speed = 300.0
    train = _jeffcott({"beta": 1e-4, "rotating": True}, 120.0, speed=speed)
    asm = assemble(train)
    spin = np.zeros(asm.n_dof)
    spin[[asm.dof(0, j, 5) for j in range(len(asm.node_offset[0]))]] = 0.05 * speed
    q0 = np.zeros(asm.n_dof)
    q0[asm.dof(0, 4, 0)] = 1e-6  # some whirl, so that the lateral DOFs take part
    run = dict(
        t_end=0.01, integrator=ModalRK4(cutoff=200.0, dt=1e-4), save=Save(dt=1e-3), initial_q=q0
    )
    with pytest.warns(UserWarning, match="rotating material damping.*5 %"):
        transient(train, initial_qdot=spin, **run)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        transient(train, **run)
