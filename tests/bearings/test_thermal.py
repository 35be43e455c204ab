"""Thermal bearings (gearrotor.bearings.thermal): the viscosity field in the Reynolds solver, the
pad flow field, the energy balances, and their closed forms, limits and conservation laws.

.. [RB] Raimondi, A. A. & Boyd, J. (1958). A solution for the finite journal bearing and its
   application to analysis and design: III. ASLE Transactions 1(1), 194–209. Full bearing,
   L/D = 1, film starting at the maximum film: flow variable Q/(r c N l) and side-flow ratio
   Qs/Q (as reproduced in Shigley's Mechanical Engineering Design, ch. 12).
"""

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from gearrotor.bearings import (
    FixedBearing,
    Grid,
    Pad,
    SolverOptions,
    axial_groove,
    coefficients,
    equilibrium,
    film_state,
    load_bearing,
    parse_bearing,
)
from gearrotor.bearings.film import _Evaluator
from gearrotor.bearings.lubricant import CELSIUS, Lubricant, iso_vg
from gearrotor.bearings.reynolds import pad_mesh, solve_pad
from gearrotor.bearings.thermal import ThermalModel, pad_flow
from gearrotor.cli.bearing import bearing_command
from gearrotor.errors import ModelError, SolverError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "bearings"
T40 = CELSIUS + 40.0


def _with(case, **thermal):
    """The case of an example file with a thermal model on its own viscosity law."""
    return replace(case.options, thermal=ThermalModel(**thermal))


# ---------------------------------------------------------------------------------------------
# Reynolds with a viscosity field
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["pinion_3lobe_dam.toml", "tilting_4pad.toml", "plain_ld1.toml"])
def test_uniform_viscosity_field_is_the_isoviscous_solution_bit_for_bit(name):
    case = load_bearing(EXAMPLES / name)
    b = case.bearing
    eq = equilibrium(b, case.loads[0], case.speed, options=case.options)
    ev = _Evaluator(b, case.speed, case.options)
    u = np.concatenate([[eq.x, eq.y], np.zeros(ev.n - 2)])
    for k, mesh in enumerate(ev.meshes):
        q = ev.local_q(k, u)
        qd = np.array([0.1, -0.2, 0.0, 0.0])
        kw = dict(radius=b.radius, clearance=b.clearance)
        a = solve_pad(mesh, q, qd, case.speed, viscosity=b.viscosity, **kw)
        field = np.full((len(mesh.theta), len(mesh.zeta)), b.viscosity)
        f = solve_pad(mesh, q, qd, case.speed, viscosity=field, **kw)
        for attr in ("pressure", "forces", "side_flow", "friction_power"):
            assert np.array_equal(getattr(a, attr), getattr(f, attr)), attr


@pytest.mark.parametrize("n_theta", [12, 24])
def test_viscosity_field_matches_the_long_bearing_integral(n_theta):
    """A converging 60° pad, L/D = 20, viscosity falling by 60 % along the arc: the mid-plane
    pressure is the 1-D Reynolds solution p(θ) = 6ωR² ∫ μ (h − h*)/h³ with h* = ∫μ/h² / ∫μ/h³
    (quadrature to 1e-13). The face conductances are exact 1-D resistances (3-point Gauss of
    μ/h³), so only the quadrature (~1e-11) separates them: 1e-9 of the peak."""
    r, c, omega, arc = 0.05, 1e-4, 300.0, math.radians(60)
    pad = Pad(0.0, arc, 0.5, 1.0)
    mesh = pad_mesh(pad, r, 40 * r, c, Grid(n_theta, 16))
    th = mesh.theta - mesh.theta[0]

    def mu(t):
        return 0.03 * (1.0 - 0.6 * t / arc)

    field = np.repeat(mu(th)[:, None], len(mesh.zeta), axis=1)
    film = solve_pad(
        mesh,
        np.zeros(4),
        np.zeros(4),
        omega,
        viscosity=field,
        radius=r,
        clearance=c,
        cavitation="none",
    )
    cp = c / 0.5

    def h(t):
        return cp - (cp - c) * math.cos(t - arc)

    i2 = quad(lambda t: mu(t) / h(t) ** 2, 0, arc, epsabs=0, epsrel=1e-13)[0]
    i3 = quad(lambda t: mu(t) / h(t) ** 3, 0, arc, epsabs=0, epsrel=1e-13)[0]
    p = [
        6 * omega * r**2 * quad(lambda s: mu(s) * (h(s) - i2 / i3) / h(s) ** 3, 0, t)[0] for t in th
    ]
    np.testing.assert_allclose(film.pressure[:, -1], p, rtol=0, atol=1e-9 * max(p))


# ---------------------------------------------------------------------------------------------
# The pad flow field
# ---------------------------------------------------------------------------------------------

# (ε, Q/(r c N l), Qs/Q) of [RB], L/D = 1
RB_FLOW = [(0.1, 3.37, 0.150), (0.2, 3.59, 0.280), (0.4, 3.99, 0.497), (0.6, 4.33, 0.680)]
RB_FLOW += [(0.8, 4.62, 0.842), (0.9, 4.74, 0.919)]


@pytest.mark.parametrize("eps, q_ref, qs_ref", RB_FLOW)
def test_pad_flows_match_raimondi_boyd(eps, q_ref, qs_ref):
    """The flows that carry the heat: the oil entering the film at the maximum film, Q, and the
    side leakage Qs, on the default 36×8 grid: Q within 0.5 % and Qs/Q within 0.005 of [RB]
    (measured −0.34 %…+0.08 % and ≤ 0.0032; the tables print three figures); the side flow
    agrees with the Reynolds solver's own to 0.5 %, and every control volume balances."""
    d, c, mu, omega = 0.1, 1e-4, 0.02, 100.0
    b = FixedBearing(d, d, c, mu, (Pad(math.pi, 2 * math.pi),))
    opts = SolverOptions(grid=Grid(36, 8))
    f = film_state(b, omega, eps * c, 0.0, options=opts)
    ev = _Evaluator(b, omega, opts)
    q = ev.local_q(0, np.array([eps * c, 0.0]))
    flow, *_ = pad_flow(ev.meshes[0], f.pads[0], q, omega, mu, d / 2, c)
    q_in = 2 * (flow.inlet.sum() + flow.makeup.sum())
    q_side = 2 * flow.side.sum()
    assert q_in / (d / 2 * c * omega / (2 * math.pi) * d) == pytest.approx(q_ref, rel=0.005)
    assert q_side / q_in == pytest.approx(qs_ref, abs=0.005)
    assert q_side == pytest.approx(f.side_flow, rel=0.005)
    assert np.abs(flow.imbalance()).max() < 1e-12 * q_in


@pytest.mark.parametrize(
    "name, sign", [("pinion_3lobe_dam.toml", 1), ("tilting_4pad.toml", -1), ("plain_ld1.toml", 1)]
)
def test_every_control_volume_balances(name, sign):
    """Mass conservation of the flow field on bearings with cavities, reformation, a pressure
    dam, a periodic film and a reversed speed: every cell to 1e-12 of the largest flow."""
    case = load_bearing(EXAMPLES / name)
    b, speed = case.bearing, sign * case.speed
    load = case.loads[-1]
    eq = equilibrium(b, load, speed, options=case.options)
    ev = _Evaluator(b, speed, case.options)
    u = np.concatenate([[eq.x, eq.y], _levers(b, eq)])
    for k in range(len(b.pads)):
        flow, *_ = pad_flow(
            ev.meshes[k],
            eq.film.pads[k],
            ev.local_q(k, u),
            speed,
            b.viscosity,
            b.radius,
            b.clearance,
        )
        assert np.abs(flow.imbalance()).max() <= 1e-12 * flow.flow.max()
        assert np.all(flow.flow >= 0) and np.all(flow.fill <= 1) and np.all(flow.fill >= 0)


def _levers(b, eq):
    from gearrotor.bearings.film import _lever_scale

    return eq.pad_dofs * _lever_scale(b)[2:]


# ---------------------------------------------------------------------------------------------
# Closed forms and limits
# ---------------------------------------------------------------------------------------------


def _concentric_pad(n_theta, lub, **kw):
    """A 120° pad without preload, journal centred, no load: no pressure, uniform film, the
    oil carried by Couette flow only."""
    d, length, c = 0.1, 0.05, 1e-4
    b = FixedBearing(d, length, c, float(lub.viscosity(T40)), (Pad(math.radians(30), 2.0944),))
    th = ThermalModel("thd", lub, T40, carry_over=0.0, tol=1e-10, max_iter=200, **kw)
    omega = 3000 * math.pi / 30
    eq = equilibrium(b, (0.0, 0.0), omega, options=SolverOptions(grid=Grid(n_theta, 4), thermal=th))
    return eq.thermal, omega * d / 2, c, d / 2 * 2.0944


def test_adiabatic_couette_pad_closed_form_and_first_order_convergence():
    """One layer across the film (the temperature uniform across it), no pressure:
    ρ c (U h/2) dT/dx = μ(T) U²/h, and with μ = μ₀ e^(−β(T − T₀))
    T(x) = T₀ + ln(1 + 2βμ₀Ux/(ρ c h²))/β. The outlet temperature converges at first order (the
    upwind convection): errors −0.031, −0.016, −0.008 K of a 5.3 K rise for 12, 24, 48
    intervals; ratio 2 within 10 %, error at 48 below 0.01 K."""
    lub = Lubricant.exponential((T40, 0.03), (CELSIUS + 100, 0.005), specific_heat=2000.0)
    errors = []
    for n in (12, 24, 48):
        th, u, h, x = _concentric_pad(n, lub, cross_film_layers=1)
        beta, mu0 = lub.coefficients[2], 0.03
        exact = T40 + math.log1p(2 * beta * mu0 * u * x / (th.rho_c * h * h)) / beta
        errors.append(th.pads[0].outlet_temperature - exact)
        assert abs(th.energy_residual) < 1e-9 * th.power_loss
        assert th.pads[0].side_flow == 0.0
    assert errors[0] / errors[1] == pytest.approx(2.0, rel=0.1)
    assert errors[1] / errors[2] == pytest.approx(2.0, rel=0.1)
    assert abs(errors[2]) < 0.01


def test_couette_pad_with_heat_to_the_pad_matches_the_ode():
    """One layer across the film, heat α(T − T_s) to the oil behind the pad (α the back's
    coefficient in series with the film's half-layer conductance 2k/h):
    ρ c (U h/2) dT/dx = μU²/h − α(T − T_s), integrated by solve_ivp (rtol 1e-12); 48
    intervals within 0.02 K (the first-order upwind error), energy conserved with the heat
    conducted (1e-9)."""
    lub = Lubricant.exponential((T40, 0.03), (CELSIUS + 100, 0.005), specific_heat=2000.0)
    alpha = 2000.0
    th, u, h, x = _concentric_pad(48, lub, pad_heat_transfer=alpha, cross_film_layers=1)
    # the pad back's coefficient in series with the film's half-layer conductance 2k/h
    alpha_eff = 1 / (1 / alpha + h / (2 * lub.thermal_conductivity))

    def rhs(_, t):
        q = lub.viscosity(t[0]) * u * u / h - alpha_eff * (t[0] - T40)
        return [2 / (th.rho_c * u * h) * q]

    exact = solve_ivp(rhs, (0, x), [T40], rtol=1e-12, atol=1e-12).y[0, -1]
    assert th.pads[0].outlet_temperature == pytest.approx(exact, abs=0.02)
    assert th.heat_conducted > 0.03 * th.power_loss  # 4.8 % of the power here
    assert abs(th.energy_residual) < 1e-9 * th.power_loss


def test_developed_couette_film_over_an_isothermal_journal_has_brinkmans_temperatures():
    """A uniform Couette film (constant μ) over a journal whose surface is held at T_j
    (``journal_heat_transfer = inf``), adiabatic pad, fed at T_j: once developed, the profile
    is T_j + (μU²/(k h²)) (h y − y²/2) and the pad surface is at T_j + μU²/(2k), the temperature
    of an adiabatic wall facing a moving isothermal wall across a Couette film (Brinkman;
    Schlichting, Boundary-Layer Theory, plane Couette flow with dissipation), every
    dissipated watt going to the journal. The oil's conductivity is raised to 130 W/(m·K) so
    that the film develops within the pad (thermal entrance length U h²/a ≈ 2 mm against a
    105 mm pad). The finite-volume layers give the developed surface temperature exactly (the
    half-layer errors at the two walls cancel), so: 1e-9 K at the trailing edge, for 1, 3 and
    8 layers; the layers' own temperatures lie on the parabola shifted by the journal half
    layer's error S h²/(8 k n²) (S = μU²/h² the dissipation)."""
    mu, k = 0.03, 130.0
    d, length, c = 0.1, 0.05, 1e-4
    omega = 3000 * math.pi / 30
    u = omega * d / 2
    t_j = T40
    lub = Lubricant.constant(mu, specific_heat=2000.0, thermal_conductivity=k)
    b = FixedBearing(d, length, c, mu, (Pad(math.radians(30), 2.0944),))
    for n in (1, 3, 8):
        th = ThermalModel(
            "thd",
            lub,
            t_j,
            carry_over=0.0,
            journal_heat_transfer=math.inf,
            journal_temperature=t_j,
            cross_film_layers=n,
            tol=1e-10,
        )
        opts = SolverOptions(grid=Grid(24, 2), thermal=th)
        res = equilibrium(b, (0.0, 0.0), omega, options=opts).thermal
        pt = res.pads[0]
        np.testing.assert_allclose(
            pt.surface_temperature[-1], t_j + mu * u * u / (2 * k), rtol=0, atol=1e-9
        )
        eta = (np.arange(n) + 0.5) / n
        exact = t_j + mu * u * u / k * (eta - eta**2 / 2 + 1 / (8 * n * n))
        np.testing.assert_allclose(pt.layer_temperature[-1, -1], exact, rtol=0, atol=1e-9)
        assert abs(res.energy_residual) < 1e-9 * res.power_loss


def _couette_pad_across_the_film(n_theta, layers, lub, t_j, alpha_p):
    d, c = 0.1, 1e-4
    b = FixedBearing(d, 0.05, c, float(lub.viscosity(T40)), (Pad(math.radians(30), 2.0944),))
    th = ThermalModel(
        "thd",
        lub,
        T40,
        carry_over=0.0,
        journal_heat_transfer=math.inf,
        journal_temperature=t_j,
        pad_heat_transfer=alpha_p,
        cross_film_layers=layers,
        tol=1e-10,
    )
    omega = 3000 * math.pi / 30
    opts = SolverOptions(grid=Grid(n_theta, 2), thermal=th)
    return equilibrium(b, (0.0, 0.0), omega, options=opts).thermal, omega * d / 2, c, d / 2 * 2.0944


def _couette_film_by_lines(rho_c, mu, k, u, h, x_end, t_in, t_j, alpha_p, t_s, m=400):
    """The oracle: ρc u(y) ∂T/∂x = k ∂²T/∂y² + μ(U/h)², u = U(1 − y/h), T(0, y) = t_in,
    T(x, 0) = t_j, −k ∂T/∂y(x, h) = α_p (T(x, h) − t_s), by the method of lines (second-order
    finite differences at m + 1 points across the film, one-sided at the pad wall) integrated in
    x by BDF: the outlet's mixing-cup temperature and the pad surface's (m = 200 → 400 changes
    them by 5e-5 and 1.6e-4 K)."""
    dy = h / m
    y = np.arange(m + 1) * dy
    vel = u * (1 - y / h)
    src = mu * (u / h) ** 2

    def wall(ti):
        return (k * (4 * ti[-1] - ti[-2]) / (2 * dy) + alpha_p * t_s) / (3 * k / (2 * dy) + alpha_p)

    def rhs(_, ti):
        t = np.concatenate([[t_j], ti, [wall(ti)]])
        return (k * (t[2:] - 2 * t[1:-1] + t[:-2]) / dy**2 + src) / (rho_c * vel[1:-1])

    sol = solve_ivp(rhs, (0, x_end), np.full(m - 1, t_in), method="BDF", rtol=1e-10, atol=1e-10)
    ti = sol.y[:, -1]
    t = np.concatenate([[t_j], ti, [wall(ti)]])
    return np.trapezoid(vel * t, y) / np.trapezoid(vel, y), t[-1]


def test_film_resolved_across_its_thickness_matches_the_method_of_lines():
    """A Couette pad (constant μ, no pressure) fed at 40 °C between a journal held 10 K hotter
    and a pad cooled through 2000 W/(m²·K) to the 40 °C oil behind it: the thermal entrance
    problem (the pad is 1/20 of an entrance length U h²/a long), solved independently by the
    method of lines (:func:`_couette_film_by_lines`). The outlet mixing-cup and trailing-edge
    pad surface temperatures converge at second order in the layers (measured errors, 96
    intervals: −1.04, −0.25, −0.057 K (outlet) and −0.82, −0.18, −0.057 K (surface) for 2, 4,
    8 layers of an 8.7 K rise; each doubling at least 3 times smaller) and are within 0.1 K on
    8 layers (the rest is the first-order upwind error along the pad). No temperature below the
    40 °C of the inlet and the pad's back: the developed-profile model this replaced put this
    pad's surface 6.5 K below it near the leading edge (and 3 K too cool at the trailing
    edge)."""
    mu, k = 0.03, 0.13
    lub = Lubricant.constant(mu, specific_heat=2000.0, thermal_conductivity=k)
    t_j, alpha_p = T40 + 10.0, 2000.0
    err_out, err_surf = [], []
    mixed = surface = math.nan
    for n in (2, 4, 8):
        th, u, h, x = _couette_pad_across_the_film(96, n, lub, t_j, alpha_p)
        if n == 2:
            mixed, surface = _couette_film_by_lines(
                th.rho_c, mu, k, u, h, x, T40, t_j, alpha_p, T40
            )
        pt = th.pads[0]
        err_out.append(pt.outlet_temperature - mixed)
        err_surf.append(pt.surface_temperature[-1, -1] - surface)
        assert pt.layer_temperature.min() > T40 and pt.surface_temperature.min() > T40
        assert pt.layer_temperature.max() < t_j + 5.0
        assert abs(th.energy_residual) < 1e-9 * th.power_loss
    for e in (err_out, err_surf):
        assert abs(e[0]) > 3 * abs(e[1]) > 9 * abs(e[2])
        assert abs(e[2]) < 0.1
    assert mixed - T40 == pytest.approx(8.73, abs=0.01)  # the oracle's rise


MAXIMUM_PRINCIPLE_CASES = [
    ("tilting_4pad_thd.toml", 1000, {}),
    ("tilting_4pad_thd.toml", 2500, {}),
    ("tilting_4pad_thd.toml", 4000, {}),
    ("tilting_5pad_thd.toml", 3000, {}),
    ("tilting_5pad_thd.toml", 6000, {}),
    ("tilting_5pad_thd.toml", 6000, {"pad_heat_transfer": 568.5, "journal_heat_transfer": 1e9}),
    ("plain_ld1.toml", 3000, {"pad_heat_transfer": 1000.0, "journal_heat_transfer": 1e9}),
]


@pytest.mark.parametrize(
    "name, rpm, walls",
    MAXIMUM_PRINCIPLE_CASES,
    ids=[f"{n.split('.')[0]}-{r}rpm{'-walls' if w else ''}" for n, r, w in MAXIMUM_PRINCIPLE_CASES],
)
def test_no_temperature_below_the_coldest_oil_fed_in(name, rpm, walls):
    """Maximum principle of the energy equation: with heat only generated in the film
    (dissipation ≥ 0) and the journal and pads taking heat only from it, no temperature in
    the film (every layer) or on a pad surface lies below the coldest temperature fed in (the
    supply: fresh oil, make-up and the oil behind the pads; the pads' inlets mix hot oil into
    it; the free journal takes the film's heat), on the 4-pad Fillon rig with heat to its pads
    and journal, the 5-pad example (adiabatic, and with heat to pads and a nearly isothermal
    journal) and a plain bearing, at several speeds. The developed-profile model this
    replaced put the Fillon rig's unloaded pads' surfaces at 35.4–36.3 °C against the 40 °C
    supply at every speed. Every control volume's energy balances: the scheme is monotone
    (upwind, an M-matrix), so the bound holds to round-off, not to a tolerance."""
    case = load_bearing(EXAMPLES / name)
    th_model = case.options.thermal
    if th_model is None:
        th_model = ThermalModel("thd", iso_vg(32), T40)
    th_model = replace(th_model, **walls)
    opts = replace(case.options, thermal=th_model)
    th = equilibrium(case.bearing, case.loads[0], rpm * math.pi / 30, options=opts).thermal
    t_s = th.supply_temperature
    floor = t_s - 1e-9 * (th.max_temperature - t_s)
    for pt in th.pads:
        assert pt.layer_temperature.min() >= floor
        assert pt.surface_temperature.min() >= floor
        assert pt.inlet_temperature >= floor
        # and no temperature above the hottest layer (no heat source outside the film)
        assert pt.surface_temperature.max() <= th.max_temperature
    if th_model.journal_heat_transfer > 0:
        hottest = max(p.layer_temperature.max() for p in th.pads)
        assert t_s < th.journal_temperature < hottest
    assert abs(th.energy_residual) < 1e-9 * th.power_loss


@pytest.mark.parametrize("name", ["tilting_4pad.toml", "plain_ld1.toml"])
def test_free_journal_takes_no_net_heat(name):
    """Heat only to the journal (adiabatic pads), its temperature left free: the journal is
    solved within every energy balance (the fields are affine in its temperature), so the
    converged journal takes no net heat to round-off, although the film's hot end gives it
    heat and its cool end takes it back. Its temperature lies between the supply and the
    hottest oil, and the iteration takes at most twice the steps it takes with the journal
    held at that temperature (measured 9/9 and 11/7; updating the journal only between
    steps took 68 on the Fillon rig at 1000 rpm, test_thermal_published.py, against 4 now)."""
    case = load_bearing(EXAMPLES / name)
    kw = dict(model="thd", lubricant=iso_vg(32), supply_temperature=T40, tol=1e-3)
    free = _with(case, journal_heat_transfer=2000.0, **kw)
    th = equilibrium(case.bearing, case.loads[0], case.speed, options=free).thermal
    assert abs(th.heat_conducted) < 1e-9 * th.power_loss
    assert abs(th.energy_residual) < 1e-9 * th.power_loss
    hottest_oil = max(p.temperature.max() for p in th.pads)
    assert T40 + 1.0 < th.journal_temperature < hottest_oil - 1.0
    held = _with(
        case, journal_heat_transfer=2000.0, journal_temperature=th.journal_temperature, **kw
    )
    th_held = equilibrium(case.bearing, case.loads[0], case.speed, options=held).thermal
    assert th.iterations <= 2 * th_held.iterations
    assert th_held.max_temperature == pytest.approx(th.max_temperature, abs=0.01)


@pytest.mark.parametrize("name", ["pinion_3lobe_dam.toml", "tilting_4pad.toml", "plain_ld1.toml"])
@pytest.mark.parametrize("model", ["effective", "thd"])
def test_isoviscous_limit_is_the_isoviscous_result_exactly(name, model):
    """A lubricant whose viscosity does not depend on temperature: the thermal iteration ends on
    the isoviscous equilibrium and coefficients, bit for bit (temperatures still computed)."""
    case = load_bearing(EXAMPLES / name)
    b = case.bearing
    co0 = coefficients(b, case.loads[0], case.speed, options=case.options)
    opts = _with(
        case, model=model, lubricant=Lubricant.constant(b.viscosity), supply_temperature=T40
    )
    co = coefficients(b, case.loads[0], case.speed, options=opts)
    assert (co.equilibrium.x, co.equilibrium.y) == (co0.equilibrium.x, co0.equilibrium.y)
    assert np.array_equal(co.equilibrium.pad_dofs, co0.equilibrium.pad_dofs)
    assert np.array_equal(co.K_full, co0.K_full) and np.array_equal(co.C_full, co0.C_full)
    assert co.equilibrium.thermal.max_temperature > T40 + 5


@pytest.mark.parametrize(
    "name, extra",
    [
        ("pinion_3lobe_dam.toml", {}),
        ("plain_ld1.toml", {}),
        ("tilting_4pad.toml", {"pad_heat_transfer": 800.0, "journal_heat_transfer": 1500.0}),
    ],
)
def test_energy_is_conserved(name, extra):
    """Power loss = enthalpy carried out by the oil (side leakage, drain and spill out, fresh
    oil in at the supply temperature) + heat conducted: to 1e-9 of the power (THD; the
    effective model balances by construction). With the journal's temperature left free, the
    journal takes no net heat (to the iteration's tolerance)."""
    case = load_bearing(EXAMPLES / name)
    opts = _with(case, model="thd", lubricant=iso_vg(32), supply_temperature=T40, **extra)
    eq = equilibrium(case.bearing, case.loads[0], case.speed, options=opts)
    th = eq.thermal
    assert th.power_loss > 0 and th.supply_flow > 0
    assert abs(th.energy_residual) < 1e-9 * th.power_loss
    assert th.max_temperature > T40
    hottest_oil = max(p.layer_temperature.max() for p in th.pads)
    for pt in th.pads:  # a 360° film: its inlet where the cavity ends, mixed with the make-up
        assert T40 <= pt.inlet_temperature <= hottest_oil
        assert T40 <= pt.outlet_temperature <= hottest_oil
        if not extra:  # adiabatic: the oil only heats up; the surface is the pad-side layer's
            assert pt.inlet_temperature <= pt.outlet_temperature
            assert np.array_equal(pt.surface_temperature, pt.layer_temperature[..., -1])
    if extra:
        assert th.heat_conducted > 0
        assert T40 < th.journal_temperature < th.max_temperature


def test_negative_speed_mirrors_the_temperatures():
    """A two-axial-groove bearing (symmetric) with the load mirrored x → −x and the speed
    reversed is the mirror problem: same temperatures, power and flows (1e-9) and the
    temperature fields mirrored."""
    b = axial_groove(0.1, 0.05, 1e-4, 0.03, groove_arc=math.radians(20), first_groove=0.0)
    opts = SolverOptions(
        grid=Grid(24, 6),
        thermal=ThermalModel("thd", iso_vg(46), T40, tol=1e-8),
    )
    w = 314.16
    a = equilibrium(b, (800.0, -4000.0), w, options=opts).thermal
    m = equilibrium(b, (-800.0, -4000.0), -w, options=opts).thermal
    assert m.power_loss == pytest.approx(a.power_loss, rel=1e-9)
    assert m.max_temperature == pytest.approx(a.max_temperature, abs=1e-9)
    # pad 1 (upper, 10°…170°) mirrors onto itself, reversed along the arc
    np.testing.assert_allclose(m.pads[0].temperature, a.pads[0].temperature[::-1], atol=1e-9)
    np.testing.assert_allclose(m.pads[1].temperature, a.pads[1].temperature[::-1], atol=1e-9)


def test_thd_grid_convergence_on_the_tilting_pad_example():
    """The 5-pad THD example on 10×4, 20×8, 40×16 intervals per pad: eccentricity, power loss
    and kxx change less at each doubling (measured successive changes: ε 0.0106 → 0.0029,
    power 2.3 → 1.0 W, kxx 1.1e6 → 2.9e5 N/m), and the hottest pad within 0.1 K."""
    case = load_bearing(EXAMPLES / "tilting_5pad_thd.toml")
    out = []
    for n in (10, 20, 40):
        opts = replace(case.options, grid=Grid(n, max(4, n * 2 // 5)))
        co = coefficients(case.bearing, case.loads[0], case.speed, options=opts)
        th = co.equilibrium.thermal
        out.append((co.equilibrium.eccentricity_ratio, th.power_loss, co.kxx, th.max_temperature))
    out = np.array(out)
    d1, d2 = np.abs(out[1] - out[0]), np.abs(out[2] - out[1])
    assert np.all(d2[:3] < 0.5 * d1[:3])
    assert d2[3] < 0.1


def test_effective_model_is_close_to_thd():
    """The effective-temperature model (f = 0.5) against the THD solution of the same 5-pad
    bearing: the same power loss within 3 %, eccentricity within 0.03, the hottest outlet within
    1.5 K (measured 1.2 %, 0.022, 0.3 K): the bulk balance and the 2-D one share the flows."""
    case = load_bearing(EXAMPLES / "tilting_5pad_thd.toml")
    eff = replace(case.options, thermal=replace(case.options.thermal, model="effective"))
    a = equilibrium(case.bearing, case.loads[0], case.speed, options=case.options)
    b = equilibrium(case.bearing, case.loads[0], case.speed, options=eff)
    assert b.thermal.power_loss == pytest.approx(a.thermal.power_loss, rel=0.03)
    assert b.eccentricity_ratio == pytest.approx(a.eccentricity_ratio, abs=0.03)
    t_a = max(p.outlet_temperature for p in a.thermal.pads)
    t_b = max(p.outlet_temperature for p in b.thermal.pads)
    assert t_b == pytest.approx(t_a, abs=1.5)


def test_overheating_is_a_solver_error():
    """A lubricant that may not exceed 45 °C in a bearing whose film would: one line, exit 3."""
    case = load_bearing(EXAMPLES / "tilting_5pad_thd.toml")
    lub = replace(case.options.thermal.lubricant, max_temperature=CELSIUS + 45)
    opts = replace(case.options, thermal=replace(case.options.thermal, lubricant=lub))
    with pytest.raises(SolverError, match="above the lubricant's maximum temperature"):
        equilibrium(case.bearing, case.loads[0], case.speed, options=opts)


# ---------------------------------------------------------------------------------------------
# Bearing files and the command
# ---------------------------------------------------------------------------------------------

BASE = {
    "type": "plain",
    "diameter": "100 mm",
    "length": "50 mm",
    "clearance": "100 um",
    "speed": "3000 rpm",
    "loads": [{"fx": 0.0, "fy": "-2 kN"}],
}


def _doc(**over):
    d = json.loads(json.dumps(BASE))
    for k, v in over.items():
        if v is None:
            d.pop(k, None)
        else:
            d[k] = v
    return {"bearing": d}


def test_bearing_file_wall_coefficients_and_conductivity():
    """``"inf"`` (or TOML's inf) holds a wall at its sink's temperature; the oil's thermal
    conductivity takes units."""
    for inf in ("inf", math.inf):
        case = parse_bearing(
            _doc(
                lubricant={"grade": "ISO VG 32", "thermal_conductivity": "0.149 W/(m*K)"},
                thermal={
                    "model": "thd",
                    "supply_temperature": "40 degC",
                    "journal_heat_transfer": inf,
                    "pad_heat_transfer": "568.5 W/(m^2*K)",
                },
                viscosity=None,
            )
        )
        th = case.options.thermal
        assert th.journal_heat_transfer == math.inf and th.pad_heat_transfer == 568.5
        assert th.lubricant.thermal_conductivity == pytest.approx(0.149)


def test_bearing_file_thermal_tables():
    case = parse_bearing(
        _doc(
            lubricant={"grade": "ISO VG 46"},
            thermal={"model": "effective", "supply_temperature": "45 degC", "carry_over": 0.6},
        )
    )
    th = case.options.thermal
    assert th.model == "effective" and th.carry_over == 0.6
    assert th.supply_temperature == pytest.approx(CELSIUS + 45)
    assert case.bearing.viscosity == pytest.approx(float(iso_vg(46).viscosity(CELSIUS + 45)))
    iso = parse_bearing(
        _doc(
            lubricant={"nu40": "32 mm^2/s", "nu100": "5.4 mm^2/s"},
            thermal={"model": "isoviscous", "supply_temperature": "40 degC", "temperature": 328.15},
        )
    )
    assert iso.options.thermal is None and iso.temperature == pytest.approx(328.15)
    assert iso.bearing.viscosity == pytest.approx(
        17.96e-6 * iso.lubricant.density_at(328.15), rel=1e-3
    )


@pytest.mark.parametrize(
    "over, field, words",
    [
        (
            dict(
                lubricant={"grade": "ISO VG 32"},
                thermal={"model": "thd", "supply_temperature": "-20 degC"},
            ),
            "bearing.thermal.supply_temperature",
            "below the lubricant's pour point",
        ),
        (
            dict(thermal={"model": "thd", "supply_temperature": "40 degC"}),
            "bearing.lubricant",
            "needs [bearing.lubricant]",
        ),
        (
            dict(
                lubricant={"grade": "ISO VG 32"},
                viscosity="0.02 Pa*s",
                thermal={"model": "thd", "supply_temperature": "40 degC"},
            ),
            "bearing.viscosity",
            "comes from the lubricant",
        ),
        (
            dict(
                lubricant={"grade": "ISO VG 32", "nu40": "30 mm^2/s"},
                thermal={"model": "thd", "supply_temperature": "40 degC"},
            ),
            "bearing.lubricant",
            "one way",
        ),
        (
            dict(
                lubricant={
                    "viscosity_points": [["40 degC", "0.03 Pa*s"], ["100 degC", "0.005 Pa*s"]],
                    "law": "vogel",
                },
                thermal={"model": "thd", "supply_temperature": "40 degC"},
            ),
            "bearing.lubricant.viscosity_points",
            "takes 3 viscosity points",
        ),
        (
            dict(
                lubricant={"grade": "ISO VG 32"},
                thermal={
                    "model": "effective",
                    "supply_temperature": "40 degC",
                    "pad_heat_transfer": "500 W/(m^2*K)",
                },
            ),
            "bearing.thermal.pad_heat_transfer",
            "THD model only",
        ),
        (
            dict(
                lubricant={"grade": "ISO VG 32"},
                thermal={"model": "thd", "supply_temperature": "40 degC", "carry_overr": 0.5},
            ),
            "bearing.thermal",
            "did you mean 'carry_over'",
        ),
        (
            dict(lubricant={"grade": "ISO VG 32", "thermal_conductivity": "0 W/(m*K)"}),
            "bearing.lubricant.thermal_conductivity",
            "greater than 0",
        ),
        (
            dict(
                lubricant={"grade": "ISO VG 32"},
                thermal={
                    "model": "thd",
                    "supply_temperature": "40 degC",
                    "journal_heat_transfer": "-5 W/(m^2*K)",
                },
            ),
            "bearing.thermal.journal_heat_transfer",
            "greater than or equal to 0",
        ),
        (
            dict(
                lubricant={"grade": "ISO VG 32"},
                thermal={"model": "thd", "supply_temperature": "40 degC", "cross_film_layers": 0},
            ),
            "bearing.thermal.cross_film_layers",
            "greater than or equal to 1",
        ),
        (
            dict(
                lubricant={"grade": "ISO VG 32"},
                thermal={
                    "model": "effective",
                    "supply_temperature": "40 degC",
                    "cross_film_layers": 4,
                },
            ),
            "bearing.thermal.cross_film_layers",
            "THD model only",
        ),
        (dict(viscosity=None), "bearing.viscosity", "missing required field"),
    ],
)
def test_thermal_input_errors(over, field, words):
    if "viscosity" not in over:
        over["viscosity"] = None
    with pytest.raises(ModelError) as err:
        parse_bearing(_doc(**over), source="b.toml")
    text = str(err.value)
    assert "\n" not in text and text.startswith("b.toml: " + field), text
    assert words in text, text


def test_bearing_command_prints_and_writes_the_temperatures(capsys):
    path = EXAMPLES / "tilting_5pad_thd.toml"
    bearing_command(path, fmt="json")
    doc = json.loads(capsys.readouterr().out)
    th = doc["cases"][0]["thermal"]
    assert doc["bearing"]["thermal_model"] == "thd"
    assert len(th["pads"]) == 5 and th["max_temperature_K"] > th["supply_temperature_K"]
    assert abs(th["energy_residual_W"]) < 1e-6 * th["power_loss_W"]
    bearing_command(path, fmt="table")
    text = capsys.readouterr().out
    assert "T_max °C" in text and "thd model, supply 40.0 °C" in text


MODEL = """
speed = "3000 rpm"
[materials.steel]
E = "206 GPa"
poisson = 0.3
density = "7850 kg/m^3"
[[shafts]]
name = "s"
material = "steel"
sections = [{ length = "0.6 m", outer_diameter = "0.1 m", elements = 4 }]
[[bearings]]
shaft = "s"
node = 0
fluid_film = { file = "b.toml", load_case = 0, speeds = ["3000 rpm", "4000 rpm"] }
[[bearings]]
shaft = "s"
node = 4
k = "1e8 N/m"
"""


def test_train_fluid_film_bearing_takes_the_files_thermal_model(tmp_path):
    """A rotor's ``fluid_film`` bearing whose file asks for THD gets the THD coefficients (the
    solver's, 1e-9), which differ from the isoviscous ones at the supply viscosity by more than
    10 % (the film runs 5–20 K hotter than the supply)."""
    from gearrotor.assembly import assemble
    from gearrotor.io import load_model

    src = EXAMPLES / "tilting_5pad_thd.toml"
    (tmp_path / "b.toml").write_text(src.read_text())
    (tmp_path / "m.toml").write_text(MODEL)
    el = assemble(load_model(tmp_path / "m.toml")).bearings[0].element
    case = load_bearing(src)
    w = 3000 * math.pi / 30
    thd = coefficients(case.bearing, case.loads[0], w, options=case.options)
    iso = coefficients(case.bearing, case.loads[0], w, options=replace(case.options, thermal=None))
    np.testing.assert_allclose(el.K(w), thd.K, rtol=1e-9)
    np.testing.assert_allclose(el.C(w), thd.C, rtol=1e-9)
    assert abs(el.C(w)[0, 0] / iso.C[0, 0] - 1) > 0.1


def test_plot_writes_a_temperature_map_for_thd(tmp_path, capsys):
    """``--plot`` adds a film-temperature map per case for a THD bearing (none for isoviscous);
    ``plot_temperature`` refuses an equilibrium without a temperature field."""
    from gearrotor.bearings.plots import plot_temperature

    bearing_command(EXAMPLES / "tilting_5pad_thd.toml", plot=tmp_path / "thd")
    assert (tmp_path / "thd" / "temperature_case01.png").stat().st_size > 10_000
    bearing_command(EXAMPLES / "plain_ld1.toml", plot=tmp_path / "iso")
    assert not list((tmp_path / "iso").glob("temperature_*"))
    case = load_bearing(EXAMPLES / "plain_ld1.toml")
    eq = equilibrium(case.bearing, case.loads[0], case.speed, options=case.options)
    with pytest.raises(ValueError, match="needs a THD equilibrium"):
        plot_temperature(eq, case.bearing)
    capsys.readouterr()
