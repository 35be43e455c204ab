"""Seals as their own kind (issue 17): a negative direct stiffness is a seal's, not a bearing's.

Oracle: superposition. A seal is a set of 8 coefficients to ground at a node, exactly like a
bearing's, so splitting each bearing's stiffness and damping into a bearing half and a seal half
must leave every analysis unchanged to round-off (modal eigenvalues, unbalance response, the
transient's time history).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from gearrotor.analyses import modal, unbalance_response
from gearrotor.errors import ModelError
from gearrotor.io import model_from_dict
from gearrotor.plots.report.sections.stability import _stability, _verdicts

from .conftest import SMALL, check_refused, run


def _split(text: str) -> str:
    """SMALL with each bearing's k and c halved and the other half given as a seal."""
    text = text.replace('k = "1e7 N/m"\nc = "1e3 N*s/m"', 'k = "5e6 N/m"\nc = "500 N*s/m"')
    for node in (0, 4):
        text += (
            f'\n[[seals]]\nname = "S{node}"\nshaft = "s1"\nnode = {node}\n'
            'k = "5e6 N/m"\nc = "500 N*s/m"\n'
        )
    return text


def _train(text):
    import tomllib

    return model_from_dict(tomllib.loads(text))


@pytest.fixture(scope="module")
def pair():
    return _train(SMALL), _train(_split(SMALL))


def test_seal_assembles_like_a_bearing_modal(pair):
    a, b = (modal(t, speed=3000 * np.pi / 30) for t in pair)
    # same eigenvalues: the same matrices, summed in another order (round-off ~1e-12)
    np.testing.assert_allclose(b.eigenvalues, a.eigenvalues, rtol=1e-9)


def test_seal_assembles_like_a_bearing_unbalance(pair):
    speeds = np.linspace(500, 6000, 12) * np.pi / 30
    a, b = (unbalance_response(t, speeds=speeds).to_dict() for t in pair)
    np.testing.assert_allclose(_numbers(b), _numbers(a), rtol=1e-9, atol=1e-300)


def _numbers(d) -> np.ndarray:
    """Every float of a nested dict/list, in a fixed order."""
    out = []

    def walk(x):
        if isinstance(x, dict):
            for k in sorted(x):
                walk(x[k])
        elif isinstance(x, list):
            for v in x:
                walk(v)
        elif isinstance(x, float):
            out.append(x)

    walk(d)
    return np.array(out)


def test_seal_assembles_like_a_bearing_transient(pair):
    from gearrotor.analyses.transient import RK4, transient

    a, b = (transient(t, t_end=0.01, integrator=RK4(dt=2e-5)) for t in pair)
    np.testing.assert_allclose(b.probes, a.probes, rtol=1e-8, atol=1e-15)
    assert a.bearing_names == ("B1", "B2") and b.bearing_names == ("B1", "B2", "S0", "S4")


def test_negative_direct_stiffness_is_a_seal(small):
    """A labyrinth seal's negative direct stiffness is accepted as a seal and refused as a
    bearing, with a message that says where it belongs."""
    text = small.read_text()
    t = _train(text + '\n[[seals]]\nshaft = "s1"\nnode = 2\nkxx = "-2e6 N/m"\nkyy = "-2e6 N/m"\n')
    assert t.seals[0].kxx == -2e6
    small.write_text(text.replace('k = "1e7 N/m"', 'k = "-1e7 N/m"', 1))
    r, dt = run("modal", small)
    check_refused(r, dt, "small.toml", "bearings[0].k", ">= 0", "[[seals]]")


def test_negative_bearing_damping_refused():
    text = SMALL.replace('c = "1e3 N*s/m"', 'c = "1e3 N*s/m"\ncyy = -5.0', 1)
    with pytest.raises(ModelError, match=r"bearings\[0\]\.cyy.*>= 0"):
        _train(text)


def test_seals_json_only_when_given(pair):
    a, b = pair
    assert "seals" not in json.loads(a.model_dump_json())  # existing models' JSON unchanged
    assert len(json.loads(b.model_dump_json())["seals"]) == 2


def test_duplicate_seal_names_refused():
    text = _split(SMALL).replace('name = "S4"', 'name = "S0"')
    with pytest.raises(ModelError, match=r"seals\[1\]\.name.*seals\[0\]\.name"):
        _train(text)


def test_report_verdict_names_static_divergence():
    """A seal stiffness of −3e7 N/m at mid-span beats the two 1e7 N/m bearings: the shaft
    diverges statically (a positive real eigenvalue, no growing oscillation). The verdict says
    so instead of "UNSTABLE modes []"."""
    t = _train(SMALL + '\n[[seals]]\nshaft = "s1"\nnode = 2\nk = "-3e7 N/m"\n')
    res = modal(t, speed=0.0)  # at rest: the divergence is a pair of real eigenvalues (x, y)
    assert not res.stable
    from gearrotor.assembly import assemble
    from gearrotor.plots.report.base import Context

    ctx = Context(assembly=assemble(t), analyses=("modal",), speed=0.0, max_frequency=1e4)
    _verdicts(ctx, _stability(res, None, frozenset()))
    v = ctx.verdicts[0]
    assert not v["ok"]
    assert "[]" not in v["detail"]
    assert "2 positive real eigenvalues" in v["detail"] and "static divergence" in v["detail"]
