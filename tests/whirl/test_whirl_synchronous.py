"""What reads a speed × whirl table at synchronous whirl (issue 24): a table constant in whirl is
today's speed table, bit for bit; the transient integrates the synchronous coefficients.

Oracles: identity of results (the same numbers must come out of the same model written two
ways, to the last bit), and agreement between methods (the transient of the whirl-table model
equals the transient of the speed table of its synchronous coefficients, which it uses).
"""

import numpy as np
import pytest
from whirl_models import RPM, base, pedestal_impedance, table_model, table_of

from gearrotor.analyses.lateral.campbell import campbell
from gearrotor.analyses.lateral.modal import modal
from gearrotor.analyses.lateral.unbalance import unbalance_response
from gearrotor.analyses.transient import ModalRK4, transient
from gearrotor.assembly import assemble
from gearrotor.elements import RadialBearing, WhirlBearing
from gearrotor.model import Train

NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
SPEEDS = [3000, 6000, 9000]


def _speed_table() -> dict:
    """A speed-dependent, cross-coupled table (one value per speed)."""
    return {
        "speed": [f"{s} rpm" for s in SPEEDS],
        "kxx": [2e7, 2.5e7, 3e7],
        "kxy": [3e6, 5e6, 8e6],
        "kyx": [-2e6, -4e6, -7e6],
        "kyy": [3e7, 3.3e7, 3.8e7],
        "cxx": [2e4, 1.8e4, 1.6e4],
        "cxy": [1e3, 9e2, 8e2],
        "cyx": [1e3, 9e2, 8e2],
        "cyy": [3e4, 2.8e4, 2.5e4],
    }


def _with_tables(table: dict) -> Train:
    data = base()
    data["bearings"] = [
        {"name": n, "shaft": "rotor", "node": node, "table": table}
        for n, node in (("left", 0), ("right", 6))
    ]
    return Train.model_validate(data)


@pytest.fixture(scope="module")
def pair():
    """The speed table, and the same numbers as a speed × whirl table constant in whirl."""
    one = _speed_table()
    two = {
        "speed": one["speed"],
        "whirl": ["0 rpm", "5000 rpm", "12000 rpm"],
        **{k: [[v] * 3 for v in one[k]] for k in NAMES},
    }
    return assemble(_with_tables(one)), assemble(_with_tables(two))


def test_a_table_constant_in_whirl_is_the_speed_table_bit_for_bit(pair):
    a, b = pair
    assert all(isinstance(x.element, RadialBearing) for x in b.bearings)
    for w in (3000 * RPM, 4500 * RPM):  # a table speed and one between
        ra, rb = modal(a, speed=w), modal(b, speed=w)
        np.testing.assert_array_equal(rb.eigenvalues, ra.eigenvalues)
        np.testing.assert_array_equal(rb.mode_shapes, ra.mode_shapes)
        assert rb.frequency_dependence is None
    speeds = np.linspace(3000, 9000, 7) * RPM
    ua, ub = unbalance_response(a, speeds=speeds), unbalance_response(b, speeds=speeds)
    np.testing.assert_array_equal(ub.response, ua.response)
    ca = campbell(a, speeds=speeds, max_frequency=20000 * RPM)
    cb = campbell(b, speeds=speeds, max_frequency=20000 * RPM)
    np.testing.assert_array_equal(cb.damped_frequency, ca.damped_frequency)
    np.testing.assert_array_equal(cb.log_dec, ca.log_dec)


def test_a_constant_whirl_table_file_is_the_speed_table_file(tmp_path):
    """The same through table files: a CSV with a whirl_rpm column, constant in whirl."""
    one = _speed_table()
    rows = ["speed_rpm," + ",".join(NAMES)]
    rows_w = ["speed_rpm,whirl_rpm," + ",".join(NAMES)]
    for i, s in enumerate(SPEEDS):
        vals = ",".join(repr(float(one[k][i])) for k in NAMES)
        rows.append(f"{s},{vals}")
        rows_w += [f"{s},{w},{vals}" for w in (0, 5000, 12000)]
    (tmp_path / "a.csv").write_text("\n".join(rows) + "\n")
    (tmp_path / "b.csv").write_text("\n".join(rows_w) + "\n")
    out = []
    for f in ("a.csv", "b.csv"):
        data = base()
        data["bearings"] = [
            {"shaft": "rotor", "node": node, "table_file": str(tmp_path / f)} for node in (0, 6)
        ]
        out.append(modal(Train.model_validate(data), speed=6000 * RPM))
    np.testing.assert_array_equal(out[1].eigenvalues, out[0].eigenvalues)


def test_transient_uses_the_synchronous_coefficients(tmp_path):
    """The transient reads a whirl table at synchronous whirl at the instantaneous speed (a
    speed table of each row's coefficients at its own speed): its run equals, to the last bit,
    the run of that speed table; the frequency dependence is not integrated (modal, Campbell
    and stability carry it)."""
    whirls = np.linspace(0, 30000, 9).tolist()
    tab = table_model(table_of(pedestal_impedance, SPEEDS, sorted({*whirls, *SPEEDS})))
    asm = assemble(tab)
    el = asm.bearings[0].element
    assert isinstance(el, WhirlBearing)
    sync = {"speed": [f"{s} rpm" for s in SPEEDS]}
    for j, k in enumerate(NAMES):
        sync[k] = [float(v) for v in el.table.values[:, j]]
    ref = _with_tables(sync)
    # the synchronous values are the table's own at whirl = speed
    z = pedestal_impedance(6000 * RPM)
    np.testing.assert_allclose(el.coefficients(6000 * RPM)[:4], z.real.ravel(), rtol=1e-14)
    runs = [transient(m, t_end=0.01, integrator=ModalRK4()) for m in (tab, ref)]
    np.testing.assert_array_equal(runs[0].probes, runs[1].probes)
    assert np.abs(runs[0].probes).max() > 0
    # and the synchronous unbalance response is that of the speed table too
    w = np.array(SPEEDS) * RPM
    np.testing.assert_array_equal(
        unbalance_response(tab, speeds=w).response, unbalance_response(ref, speeds=w).response
    )
