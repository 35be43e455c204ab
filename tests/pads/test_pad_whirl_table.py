"""A tilting-pad bearing as its condensed speed × whirl table against the same bearing with its
pad DOFs in the train (issue 24).

Oracle: Lund's pad assembly (Lund 1964, ASLE Trans. 7; Dimond, Younan & Allaire 2011, IJRM
908469): the pads' equations condensed at s give the journal impedance ``Z_r(s)``, a rational
function of s whose poles are those of the pads (``K_pp + s C_pp + s² M_pp``). The pad model's
eigenvalues are the roots of the rotor impedance with ``Z_r(λ)``
(``test_pad_train.py``); the table of ``Z_r(iω)`` (:func:`gearrotor.bearings.pads.whirl_table`)
carries the same function once its fit resolves those poles, so the two models have the same
eigenvalues at the table's speeds. Reading the table at ω = Im λ instead (the classical
per-mode use of frequency-dependent coefficients) would miss ``Z_r(σ + iω) − Z_r(iω)``, first
order in the damping (``test_pad_train.py``: 0.04 ζ).
"""

import numpy as np
import pytest
from pad_models import write

from gearrotor.analyses.lateral.modal import modal
from gearrotor.analyses.lateral.unbalance import unbalance_response
from gearrotor.assembly import assemble
from gearrotor.bearings import load_bearing
from gearrotor.bearings.pads import save_whirl_table, whirl_table
from gearrotor.elements import WhirlBearing
from gearrotor.errors import ModelError
from gearrotor.model import Train

RPM = np.pi / 30
TOP = 40000 * RPM
SPEEDS = [3000.0, 6000.0, 9000.0]  # the pad model's fluid_film.speeds


@pytest.fixture(scope="module")
def pad_model(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("padwhirl")
    train = write(tmp)
    return tmp, train, modal(assemble(train), max_frequency=TOP)


def _table_model(tmp, train, whirls, name, tolerance=1e-10):
    """The pad model's train with both bearings given by the condensed whirl table file."""
    case = load_bearing(tmp / "pad.toml")
    wt = whirl_table(case.bearing, case.loads[0], SPEEDS, whirls, options=case.options)
    path = save_whirl_table(wt, tmp / name)
    data = train.model_dump()
    for b in data["bearings"]:
        b.update(fluid_film=None, table_file=str(path), fit_tolerance=tolerance)
    return assemble(Train.model_validate(data))


def _errors(ref, res):
    """Per mode of the pad model that is not a pad mode: relative distance to the nearest
    eigenvalue of ``res``; split into (damped, over-damped)."""
    keep = [i for i in range(len(ref)) if ref.mode_type[i] != "P"]
    err = np.array([np.min(np.abs(res.eigenvalues - ref.eigenvalues[i])) for i in keep])
    err /= np.abs(ref.eigenvalues[keep])
    over = ref.overdamped[keep]
    return err[~over], err[over]


def test_the_condensed_table_has_the_pad_models_eigenvalues(pad_model):
    tmp, train, ref = pad_model
    whirls = sorted({*np.linspace(0, 40000, 9).tolist(), *SPEEDS})
    asm = _table_model(tmp, train, whirls, "dense.csv")
    assert isinstance(asm.bearings[0].element, WhirlBearing)
    assert asm.n_dof == 42  # no pad DOFs: the pads live in the fit's states
    res = modal(asm, max_frequency=TOP)
    damped, over = _errors(ref, res)
    assert len(damped) >= 6
    # the damped rotor modes: round-off of the two eigensolves (measured 4e-13)
    assert damped.max() < 1e-10
    # the over-damped pairs are nearly double (left and right bearing alike), whose
    # eigenvalues move by ~√ε: measured 3e-8
    assert over.max() < 1e-6
    # the fit found the pads' poles: 4 pads, identical in pairs (rank-2 residues)
    work = res.frequency_dependence
    assert work["eigensolves"] == 1
    assert all(e["max_misfit"] < 1e-10 for e in work["elements"])


def test_convergence_with_whirl_table_density(pad_model):
    """Whirl frequencies: the speeds (0, 3000, 6000, 9000 rpm), then 40,000, then 20,000 and
    40,000, then thirds of 40,000 rpm. With 4 or 5 the fit cannot resolve the pads' four poles
    (at most N + 2 ≤ n_w unknowns per entry); each density uses the smallest tolerance it can
    meet. The damped rotor modes' largest error, measured: 1.2e-3, 1.7e-6, 3e-13, 3e-13."""
    tmp, train, ref = pad_model
    grids = (
        [0, 3000, 6000, 9000],
        [0, 3000, 6000, 9000, 40000],
        [0, 3000, 6000, 9000, 20000, 40000],
        [0, 3000, 6000, 9000, 13333, 26667, 40000],
    )
    errors = []
    for k, whirls in enumerate(grids):
        for tol in (1e-10, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2, 0.1, 0.5, 0.9):
            try:
                asm = _table_model(tmp, train, whirls, f"grid{k}.csv", tol)
                break
            except ModelError:
                continue
        damped, _ = _errors(ref, modal(asm, max_frequency=TOP))
        errors.append(damped.max())
    assert errors[0] > 1e-4
    assert errors[1] < 0.1 * errors[0]
    assert errors[2] < 1e-10 and errors[3] < 1e-10
    assert all(b <= max(a, 1e-11) for a, b in zip(errors, errors[1:], strict=False)), errors


def test_unbalance_response_at_the_table_speeds(pad_model):
    """Whirl = speed: the table's synchronous coefficients are the synchronously reduced ones,
    the pad model's response at 1x (``test_pad_train.py``)."""
    tmp, train, _ = pad_model
    whirls = sorted({*np.linspace(0, 40000, 5).tolist(), *SPEEDS})
    asm = _table_model(tmp, train, whirls, "unb.csv")
    w = np.array(SPEEDS) * RPM
    a = unbalance_response(assemble(train), speeds=w).probes[0].response
    b = unbalance_response(asm, speeds=w).probes[0].response
    np.testing.assert_allclose(b, a, rtol=1e-9)
