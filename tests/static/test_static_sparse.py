"""The sparse static solver (issue 23): ``gearrotor static`` on a model at the documented
maximum mesh size (10,000 elements per shaft) built a 107 GiB dense matrix; the static solution
is now sparse (sparse LU of the stiffness grounded along its rigid modes, the rigid modes as
the null space within the shafts' kinematic rigid motions), and the dense path stays as the
reference it is checked against.

Oracles: the dense path (dense LU of the bordered system, SVD null space: the method of the
earlier releases) gives the same deflection, loads, tooth forces, journals and section forces
to round-off. Tolerance 1e-9 of each quantity's largest value: both solve the same equations in
float64; the bordered matrices' condition numbers (stiffness ratios up to 1e6) amplify eps
~2e-16 to ~1e-10 at most (the observed differences are ≤ 1e-11). And a uniform shaft's end
bearings carry half its weight each (statics), at 10,000 elements per shaft.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from test_static_gears import gear_pair

from gearrotor.analyses.static import static
from gearrotor.analyses.static.solver import rigid_modes, rigid_modes_in
from gearrotor.assembly import assemble
from gearrotor.errors import ModelError
from gearrotor.io import load_model, model_from_dict
from gearrotor.model import OperatingPoint
from helpers import single_shaft

REL = 1e-9


def _numbers(res) -> dict[str, np.ndarray]:
    """Every number of a static result, by name (arrays flattened)."""
    out: dict[str, np.ndarray] = {"q": res.q, "applied": res.applied}

    def walk(x, path):
        if isinstance(x, dict):
            for k, v in x.items():
                walk(v, f"{path}.{k}")
        elif isinstance(x, list) and x and all(isinstance(v, int | float) for v in x):
            out[path] = np.asarray(x, float)
        elif isinstance(x, list):
            for i, v in enumerate(x):
                walk(v, f"{path}[{i}]")
        elif isinstance(x, float):
            out[path] = np.array([x])

    walk(res.to_dict(), "")
    return out


def _unit(key: str) -> str:
    """The unit a quantity's name ends in (``force_N`` → ``N``): round-off is relative to the
    largest quantity of its kind (an unloaded mesh's force is round-off of the loaded ones)."""
    return key.rsplit("_", 1)[-1] if "_" in key.rsplit(".", 1)[-1] else key


def _same(a, b):
    na, nb = _numbers(a), _numbers(b)
    assert na.keys() == nb.keys()
    scales: dict[str, float] = {}
    for key, va in na.items():
        u = _unit(key)
        scales[u] = max(scales.get(u, 0.0), float(np.max(np.abs(va))))
    for key, va in na.items():
        atol = REL * scales[_unit(key)]
        np.testing.assert_allclose(nb[key], va, rtol=0, atol=atol, err_msg=key)


def _pedestal_model():
    """A shaft without thrust bearing (axial float and spin free) on two bearings, one on a
    pedestal, with a cross-coupled destabiliser and a seal, under weight and a side force."""
    t = single_shaft(
        elements=12,
        bearings=[
            {"node": 1, "kxx": 2e8, "kyy": 3e8, "kxy": 1e7, "kyx": -1e7},
            {"node": 11, "k": 1e8, "support": {"mass": 20.0, "kxx": 5e8, "kyy": 4e8}},
        ],
        disks=[{"node": 6, "mass": 30.0, "polar": 0.5, "transverse": 0.3}],
        speed=300.0,
        cross_couplings=[{"shaft": "s", "node": 6, "q": 2e6}],
        seals=[{"shaft": "s", "node": 4, "k": -1e6}],
    )
    op = OperatingPoint(
        name="side", forces=[{"shaft": "s", "node": 8, "force": (300.0, -100.0, 0.0)}]
    )
    return t, op


def _cases(examples):
    steam = load_model(examples / "steam_turbine_gearbox.toml")
    yield "unity gearbox, weight", load_model(examples / "unity_gearbox.toml"), None
    yield "steam turbine LC1 (journals)", steam, "LC1"
    yield "steam turbine LC10 (herringbone, journals)", steam, "LC10"
    pair = gear_pair(math.radians(15.0))
    op = OperatingPoint(
        name="T", torque=100.0, drive={"shaft": "p", "node": 0}, load={"shaft": "g", "node": 8}
    )
    yield "helical pair under torque", pair, op
    yield "pedestal, cross-coupling, seal, free float", *_pedestal_model()


@pytest.mark.parametrize("case", range(5))
def test_sparse_equals_dense(examples, case):
    name, train, op = list(_cases(examples))[case]
    asm = assemble(train)
    dense = static(asm, op, method="dense")
    sparse = static(asm, op)
    _same(dense, sparse)
    assert [b.name for b in sparse.bearings] == [b.name for b in dense.bearings], name


def test_rigid_modes_within_candidates(examples):
    """The null space within the kinematic candidates is the whole null space (the SVD of the
    whole matrix): the same subspace, to round-off (largest principal angle)."""
    from gearrotor.analyses.static.analysis import _candidates

    for train in (
        load_model(examples / "unity_gearbox.toml"),
        _pedestal_model()[0],
        gear_pair(0.3, thrust=False),
    ):
        asm = assemble(train)
        K = asm.K0
        a = rigid_modes(K.toarray())[0]
        b = rigid_modes_in(K, _candidates(asm))
        assert a.shape == b.shape and a.shape[1] >= 1
        qa, qb = np.linalg.qr(a)[0], np.linalg.qr(b)[0]
        sv = np.linalg.svd(qa.T @ qb, compute_uv=False)
        assert np.min(sv) > 1 - 1e-10
        assert np.max(np.abs(K @ b)) < 1e-12 * abs(K).max() * np.max(np.abs(b))


def _uniform_pair(elements: int, path) -> object:
    """The flagship's two shafts at ``elements`` elements each (gear at mid-span)."""
    text = (path / "unity_gearbox.toml").read_text()
    text = text.replace("elements = 20", f"elements = {elements}")
    text = re.sub(r"node = 20\b", f"node = {elements}", text)
    text = re.sub(r"node = 10\b", f"node = {elements // 2}", text)
    import tomllib

    return model_from_dict(tomllib.loads(text))


@pytest.fixture(scope="module")
def fine(examples):
    """2,000 elements per shaft: 24,012 DOF (a dense matrix: 4.3 GiB)."""
    return assemble(_uniform_pair(2000, examples))


def test_fine_mesh_without_dense_matrices(fine):
    """The sparse path allocates no n × n array: its peak (numpy's allocations, which
    tracemalloc sees) stays below 200 MB, where one dense matrix of this model is 4.3 GiB;
    the bearings carry half of each shaft's weight (statics)."""
    import tracemalloc

    tracemalloc.start()
    try:
        res = static(fine)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 200e6, peak
    weight = math.pi / 4 * 0.06**2 * 1.02 * 7890 * 9.80665
    for b in res.bearings:
        assert -b.force[1] == pytest.approx(weight / 2, rel=1e-9)


def test_dense_refused_before_allocating(fine, monkeypatch):
    def must_not_run(*a, **k):
        raise AssertionError("allocated before refusing")

    monkeypatch.setattr(fine.M, "toarray", must_not_run)
    with pytest.raises(ModelError, match=r"method: the dense static solver would need 4.3 GiB"):
        static(fine, method="dense")


@pytest.mark.slow
def test_documented_maximum_mesh(examples):
    """10,000 elements per shaft (the model's limit per section), 120,012 DOF: the command
    runs (it built a 107 GiB dense matrix), and the weight splits in halves."""
    res = static(_uniform_pair(10000, examples))
    weight = math.pi / 4 * 0.06**2 * 1.02 * 7890 * 9.80665
    for b in res.bearings:
        assert -b.force[1] == pytest.approx(weight / 2, rel=1e-9)
