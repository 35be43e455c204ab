"""Speed × whirl tables in the train analyses (issue 24): modal, Campbell, unbalance, Level I/II.

Oracle: a bearing on a pedestal (support mass on springs and dampers) presents the journal
impedance ``Z(s) = Z_b − Z_b (Z_b + Z_s + m s²)⁻¹ Z_b`` (static condensation of the pedestal
DOFs, exact at every s; Lund's pad assembly is the same algebra). The rotor with its bearings
given as the speed × whirl table of that impedance, without pedestals, must therefore have the
eigenvalues of the pedestal model — every one, damped or not — and its unbalance response at
the table's speeds. Agreement is to round-off once the table resolves the impedance's four
poles (a rational function of known order; Gustavsen & Semlyen 1999).
"""

import numpy as np
import pytest
from whirl_models import RPM, pedestal_impedance, pedestal_model, table_model, table_of

from gearrotor.analyses.audit.stability import level1, level2
from gearrotor.analyses.lateral.campbell import campbell
from gearrotor.analyses.lateral.modal import modal
from gearrotor.analyses.lateral.unbalance import unbalance_response
from gearrotor.assembly import assemble
from gearrotor.errors import ModelError
from gearrotor.model import Train

TOP = 30000 * RPM
SPEEDS = [3000, 4500, 6000, 7500, 9000]  # rpm: the table's speeds, also among its whirls
WHIRLS = sorted({*np.linspace(0, 30000, 9).tolist(), *SPEEDS})


@pytest.fixture(scope="module")
def models():
    ref = pedestal_model()
    tab = table_model(table_of(pedestal_impedance, SPEEDS, WHIRLS), fit_tolerance=1e-10)
    return ref, assemble(tab)


def _match(a, b):
    """Largest relative distance from each eigenvalue of a to the nearest of b."""
    return max(np.min(np.abs(b - x)) / abs(x) for x in a)


def test_eigenvalues_equal_the_pedestal_models(models):
    ref, asm = models
    r0 = modal(ref, max_frequency=TOP)
    r1 = modal(asm, max_frequency=TOP)
    assert len(r1) == len(r0) == 10
    # both directions: no mode missing, none spurious; round-off of two dense eigensolves and
    # of the fit (misfit 1e-15 at the samples)
    assert _match(r0.eigenvalues, r1.eigenvalues) < 1e-10
    assert _match(r1.eigenvalues, r0.eigenvalues) < 1e-10
    # the rigid-body (axial and torsional) eigenvalues are the same too
    assert r1.n_rigid_body == r0.n_rigid_body == 4
    # minimal realisation: per bearing the pedestal's 2 DOFs = 4 states; one eigensolve
    work = r1.frequency_dependence
    assert work["states"] == 8 and work["eigensolves"] == 1
    assert all(e["max_misfit"] < 1e-12 for e in work["elements"])
    assert r1.to_dict()["frequency_dependence"]["states"] == 8
    # the mode shapes on the rotor are the pedestal model's (MAC 1)
    n = asm.n_dof
    for i in range(len(r0)):
        j = int(np.argmin(np.abs(r1.eigenvalues - r0.eigenvalues[i])))
        a, b = r0.mode_shapes[i][:n], r1.mode_shapes[j]
        mac = abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)
        assert mac > 1 - 1e-10


def test_the_synchronous_model_misses_what_the_table_carries(models):
    """Reading the table at synchronous whirl only (today's speed table) moves the modes away
    from 1x by up to ~10 %: the frequency dependence the table carries is not small here."""
    ref, asm = models
    r0 = modal(ref, max_frequency=TOP)
    data = asm.train.model_dump()
    for b, info in zip(data["bearings"], asm.bearings, strict=True):
        c = info.element.coefficients(6000 * RPM)  # synchronous
        del b["table"], b["fit_tolerance"]
        b.update(zip(("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"), c, strict=True))
    rs = modal(Train.model_validate(data), max_frequency=TOP)
    assert _match(r0.eigenvalues[:3], rs.eigenvalues) > 1e-2


def test_convergence_with_table_density():
    """The fit needs n_w ≥ 6 whirl frequencies to resolve the pedestal's four poles (at most
    N + 2 ≤ n_w unknowns per entry): with the smallest tolerance each density can meet, the
    eigenvalue error falls with the density (measured 0.71, 0.15, 0.12 for 3, 4, 5
    frequencies: with three only a pole-free fit keeps the table's damping positive) and is
    round-off from 6 on (1.7e-13)."""
    r0 = modal(pedestal_model(), max_frequency=TOP)
    errors = []
    for n_w in (3, 4, 5, 6, 8):
        whirls = np.linspace(0, 30000, n_w)
        for tol in (1e-10, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2, 0.1, 0.5, 0.9):
            try:
                asm = assemble(
                    table_model(table_of(pedestal_impedance, [6000], whirls), fit_tolerance=tol)
                )
                break
            except ModelError:
                continue
        r1 = modal(asm, max_frequency=TOP)
        # the lightly damped modes (ζ < 0.3): those the fit must get right to matter
        light = r0.eigenvalues[r0.damping_ratio < 0.3]
        errors.append(_match(light, r1.eigenvalues))
    assert errors[-1] < 1e-10 and errors[-2] < 1e-10
    assert errors[0] > 0.1
    assert all(b <= max(a, 1e-12) for a, b in zip(errors, errors[1:], strict=False)), errors


def test_unbalance_response_equals_the_pedestal_models(models):
    """Unbalance: whirl = speed, the table read at its synchronous points (exact at the table's
    speeds, which are among its whirl frequencies)."""
    ref, asm = models
    speeds = np.array(SPEEDS) * RPM
    a = unbalance_response(ref, speeds=speeds).probes[0].response
    b = unbalance_response(asm, speeds=speeds).probes[0].response
    # round-off of two LU solves; the synchronous table values are the condensed impedance
    np.testing.assert_allclose(b, a, rtol=1e-9)


def test_campbell_picks_it_up(models):
    ref, asm = models
    speeds = np.linspace(3000, 9000, 5) * RPM  # table speeds and speeds between them
    a = campbell(ref, speeds=speeds, max_frequency=20000 * RPM)
    b = campbell(asm, speeds=speeds, max_frequency=20000 * RPM)
    # the table model's two pedestal modes (12,856 and 16,226 rpm, where the pedestals move
    # more than the rotor) are modes of the fit's states: typed P and not tracked
    assert a.damped_frequency.shape == (5, 8) and b.damped_frequency.shape == (5, 6)
    np.testing.assert_allclose(b.damped_frequency, a.damped_frequency[:, :6], rtol=1e-10)
    np.testing.assert_allclose(b.log_dec, a.log_dec[:, :6], rtol=1e-8, atol=1e-10)
    # every speed one full eigensolve with the states, its residual on the nonlinear problem
    assert b.solver == ("full",) * 5
    assert np.max(b.residual) < 1e-10


def test_level1_and_level2_pick_it_up(models):
    ref, asm = models
    w = 6000 * RPM
    l2a, l2b = level2(ref, speeds=[w]), level2(asm, speeds=[w])
    fa = sorted(m.log_dec for e in l2a.evaluations for m in e.modes)
    fb = sorted(m.log_dec for e in l2b.evaluations for m in e.modes)
    np.testing.assert_allclose(fb, fa, rtol=1e-8)
    l1a = level1(ref, qa=2e6, at=[("rotor", 3)], speed=w, n_curve=0)
    l1b = level1(asm, qa=2e6, at=[("rotor", 3)], speed=w, n_curve=0)
    # Q0 by root search to rtol = 1e-4 on each model
    assert l1a.threshold_q is not None
    assert l1b.threshold_q == pytest.approx(l1a.threshold_q, rel=3e-4)
    assert l1b.log_dec_at_qa == pytest.approx(l1a.log_dec_at_qa, rel=1e-8)


def test_sparse_solve_agrees_with_dense(models):
    """The sparse path (shift-invert Arnoldi on the augmented pencil, ``method="sparse"``, what
    "auto" takes from 400 DOFs with a max_frequency) finds every eigenvalue with |λ| ≤
    max_frequency, those of the dense solve, refined to the dense solve's residual."""
    from gearrotor.analyses.lateral.whirl import residuals

    _, asm = models
    d = modal(asm, max_frequency=TOP, method="dense")
    s = modal(asm, max_frequency=TOP, method="sparse")
    inside = d.eigenvalues[np.abs(d.eigenvalues) <= TOP]
    assert len(s) == len(inside) >= 6
    assert _match(inside, s.eigenvalues) < 1e-10 and _match(s.eigenvalues, inside) < 1e-10
    assert residuals(asm, asm.train.speed, s.eigenvalues, s.mode_shapes).max() < 1e-10
    assert s.frequency_dependence["method"].startswith("sparse")
    assert s.mode_type == tuple(
        d.mode_type[i] for i in np.flatnonzero(np.abs(d.eigenvalues) <= TOP)
    )


def test_the_report_says_how_the_tables_were_solved(models):
    """The report's modes section (through modal) states the tables, the states and the work."""
    from gearrotor.plots.report.sections.modes import _modes_table

    ref, asm = models
    res = modal(asm, max_frequency=TOP)
    html = _modes_table(res, ["stable"] * len(res))
    assert "speed × whirl tables: left, right" in html and "8 states" in html
    assert "Frequency-dependent" not in _modes_table(modal(ref, max_frequency=TOP), ["stable"] * 10)
