"""A seal from its geometry tabulated over whirl in a rotor model (issue 24): the hole-pattern
balance piston of ``examples/seals/compressor_with_seals.toml`` solved at whirl frequencies
0–60,000 rpm at 11,000 rpm.

Oracles: the seal solver itself (``gearrotor.seals``, verified in ``tests/seals``). (1) The fit
the eigenproblem uses reproduces the solver's coefficients between the tabulated whirl
frequencies. (2) A mode's eigenvalue moves from the synchronous model's by what the seal's
frequency dependence predicts: the model whose seal carries the solver's coefficients at the
mode's own frequency ω = Im λ has that eigenvalue up to ``Z(σ + iω) − Z(iω) ≈ σ Z'(iω)``,
first order in the damping ratio (as for tilting pads, ``tests/pads/test_pad_train.py``),
and the synchronous model misses it by more for every mode away from 1x.
"""

import numpy as np
import pytest

from gearrotor.analyses.lateral.modal import modal
from gearrotor.assembly import assemble
from gearrotor.io import load_model
from gearrotor.model import Train
from gearrotor.seals import load_seal, seal_coefficients

RPM = np.pi / 30
W = 11000 * RPM
TOP = 60000 * RPM
NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


@pytest.fixture(scope="module")
def models(examples):
    data = load_model(examples / "seals" / "compressor_with_seals.toml").model_dump()
    hole = data["seals"][1]
    assert hole["name"] == "balance piston"
    hole["speeds"] = [W]
    sync = Train.model_validate(data)
    hole["whirls"] = (np.linspace(0, 60000, 13) * RPM).tolist()
    whirl = assemble(Train.model_validate(data))
    return data, sync, whirl, load_seal(hole["file"])


def test_the_fit_reproduces_the_seal_solver_between_the_whirl_frequencies(models):
    *_, whirl, seal = models
    el = next(b.element for b in whirl.bearings if b.name == "balance piston")
    row = el.rows[0]
    assert row.fit.misfit <= 1e-4  # the default fit_tolerance
    for rpm in (2500.0, 7000.0, 17000.0, 33000.0, 52000.0):
        om = rpm * RPM
        ref = np.array(seal_coefficients(seal, W, om).coefficients)
        z_ref = ref[:4] + 1j * om * ref[4:]
        z_fit = row.fit.at(1j * om).ravel()
        # between the samples the fit interpolates a smooth impedance: 1e-3 of |Z|
        assert np.linalg.norm(z_fit - z_ref) < 1e-3 * np.linalg.norm(z_ref), rpm


def test_modes_move_as_the_seals_frequency_dependence_predicts(models):
    data, sync, whirl, seal = models
    rs = modal(sync, max_frequency=TOP)
    rw = modal(whirl, max_frequency=TOP)
    assert rw.frequency_dependence["eigensolves"] == 1
    rotor = [i for i in range(len(rw)) if rw.mode_type[i] != "P"]
    assert len(rotor) == len(rs) == 6
    away = 0
    for i in rotor:
        lw = rw.eigenvalues[i]
        zeta = rw.damping_ratio[i]
        err_sync = np.min(np.abs(rs.eigenvalues - lw)) / abs(lw)
        # the seal solver's coefficients at the mode's own frequency, as constants
        co = seal_coefficients(seal, W, lw.imag).coefficients
        frozen = {**data, "seals": [data["seals"][0], dict(data["seals"][1])]}
        s = frozen["seals"][1]
        for k in ("file", "speeds", "whirls", "fit_tolerance"):
            s.pop(k, None)
        s.update(zip(NAMES, co, strict=True))
        rf = modal(Train.model_validate(frozen), max_frequency=TOP)
        err_frozen = np.min(np.abs(rf.eigenvalues - lw)) / abs(lw)
        # first order in ζ: measured 0.013 ζ at most (the 25,000 rpm pair)
        assert err_frozen < 0.02 * zeta, (lw.imag / RPM, err_frozen, zeta)
        if abs(lw.imag / W - 1.0) > 0.5:  # away from 1x the synchronous seal is wrong
            away += 1
            assert err_sync > 1e-3
            assert err_frozen < 0.5 * err_sync
    assert away == 4


def test_level2_judges_the_rotor_modes_not_the_seals_own(models):
    """API 617 Level II on the whirl model: the modes of the seal fit's states (type P, the
    rotor barely moves) are not forward lateral modes; the rotor's forward modes are judged."""
    from gearrotor.analyses.audit.stability import level2

    *_, whirl, _ = models
    modes = level2(whirl, speeds=[W]).evaluations[0].modes
    p = [m for m in modes if m.mode_type == "P"]
    assert p and not any(m.forward for m in p)
    assert all(m.energy_lateral < 0.1 for m in p)
    judged = [m for m in modes if m.forward]
    assert len(judged) == 2 and all(m.mode_type == "L" for m in judged)


def test_campbell_tracks_the_rotor_modes(models):
    """Campbell leaves the fitted states' own modes out: their number follows each row's fit
    order (no identity over speed); the six rotor modes are tracked, their residual on the
    nonlinear problem at round-off."""
    from gearrotor.analyses.lateral.campbell import campbell

    *_, whirl, _ = models
    c = campbell(whirl, speeds=np.array([10000.0, 11000.0, 12000.0]) * RPM, max_frequency=TOP)
    assert c.damped_frequency.shape == (3, 6)
    assert set(np.ravel(c.mode_type)) == {"L"}
    assert np.max(c.residual) < 1e-9
