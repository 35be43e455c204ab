"""The pad equations integrated with the rotor (issue 24, item 3): the transient of a train with
pad dynamics, linearised at the operating point, against its own frequency-domain response.

Oracle: the model is linear apart from the unbalance's rotating force, so once the free motion
has decayed the 1x orbit equals the unbalance response of the same pad model (agreement
between methods; both integrators: RK4 on every DOF, ModalRK4 with the pads in its basis).
"""

import numpy as np
import pytest
from pad_models import write

from gearrotor.analyses.lateral.unbalance import unbalance_response
from gearrotor.analyses.transient import RK4, ModalRK4, transient
from gearrotor.analyses.transient.equations import build_system
from gearrotor.analyses.transient.forces import _output_dofs
from gearrotor.analyses.transient.prepare import _prepare_modal
from gearrotor.assembly import assemble


def _one_x(res, w):
    """1x complex amplitude of the disk probe over the second half of the run."""
    t = res.time
    keep = t >= 0.5 * t[-1]
    return 2 * np.mean(res.probes[keep, 0] * np.exp(-1j * w * t[keep]))


@pytest.mark.parametrize("integrator", [RK4(dt=5e-6), ModalRK4()], ids=["rk4", "modal"])
def test_transient_1x_equals_the_unbalance_response(tmp_path, integrator):
    train = write(tmp_path)
    asm = assemble(train)
    w = train.speed
    ref = unbalance_response(asm, speeds=[w]).probes[0].response[0]
    res = transient(train, t_end=0.1, integrator=integrator)
    # the slowest rotor mode decays at 117 1/s: after 0.05 s its start-up transient is below
    # 3e-3 of the 1x amplitude, and the 1x least-squares fit over 5 periods adds less
    assert abs(_one_x(res, w)) == pytest.approx(abs(ref), rel=5e-3)
    # the bearing forces come from the full matrices: the journal force balances the film
    # force of the pads' motion (its 1x amplitude as the frequency domain gives it)
    f = res.bearing_force[:, 0, 0]
    assert np.all(np.isfinite(f)) and np.abs(f).max() > 0


def test_modal_basis_holds_the_pads(tmp_path):
    """The modal integrator's basis spans every pad DOF, and its linear model is stable like
    the full one (a basis of truncated modes alone made a growing mode of the one-sided film
    coupling: +165 1/s on this model)."""
    train = write(tmp_path)
    system = build_system(train)
    prep = _prepare_modal(system, ModalRK4(), _output_dofs(system, False))
    Phi = prep.info["Phi"]
    pads = [system.index(int(g)) for g in system.assembly.pad_dofs]
    for i in pads:
        e = np.zeros(system.n)
        e[i] = 1.0
        # the unit vector of a pad DOF lies in the span of Φ (M-orthonormal projection)
        proj = Phi @ (Phi.T @ (prep.info["M"] @ e))
        assert np.linalg.norm(proj - e) < 1e-8


def test_operating_point_is_an_equilibrium_with_flexible_pivots(tmp_path):
    """At an operating point (weight) with the model's pivot stiffness override, the static
    solution puts the pads at their equilibrium (pad DOFs 0), the pivot springs of the bearing
    solve carry the journal load, and the transient started there stays there: the linearised
    film carries the static load through the run (no unbalance, so nothing moves)."""
    from gearrotor.analyses.static import static
    from gearrotor.model import OperatingPoint

    kp = 4e8
    extra = f'fluid_film.pivot_stiffness = "{kp} N/m"\nfluid_film.pad_mass = "0.5 kg"'
    train = write(tmp_path, extra=extra, unbalance=False)
    asm = assemble(train)
    assert asm.n_dof == 42 + 16  # a tilt and a radial DOF per pad
    st = static(train, None)
    eq = st.journals[0]
    assert len(eq.pad_dofs) == 8
    # the radial pad DOFs: the pivot springs carry the load (film force + load = 0)
    normals = np.array([[np.cos(a), np.sin(a)] for a in np.radians([45, 135, 225, 315])])
    np.testing.assert_allclose(kp * eq.pad_dofs[1::2] @ normals, eq.load, atol=1e-6 * 2500)
    np.testing.assert_array_equal(st.q[asm.pad_dofs], 0.0)
    res = transient(
        train, t_end=0.01, integrator=RK4(dt=5e-6), operating_point=OperatingPoint(name="w")
    )
    f = res.bearing_force[:, 0]
    w = st.bearings[0].force[:2]
    # the film force stays at the static load to round-off of the static solve (1e-9 of it)
    np.testing.assert_allclose(f, np.tile(-w, (len(f), 1)), rtol=0, atol=1e-6 * np.abs(w).max())
