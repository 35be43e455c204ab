"""Seals in the static solution (issue 23): an annular seal carries no static load (its
coefficients are those of small motions about the running position, analyses/static), whether
its coefficients are constant or tabulated against speed; it still acts in every dynamic
analysis, and the transient at an operating point holds it centred on the static state.

Before, any ``[[seals]]`` broke ``gearrotor static`` and every ``--operating-point`` run
(``ValueError: zip() argument 2 is longer than argument 1``).

Oracles: the bearing loads of a uniform shaft on two end bearings are half its weight each
(statics, a determinate beam); the static state with seals equals the one without to round-off;
a transient at an operating point started there stays there (an equilibrium)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from test_static_transient_op import MODEL, R_PINION, TORQUE

from gearrotor.analyses import modal
from gearrotor.analyses.static import static
from gearrotor.io import load_model, model_from_dict
from reliability.conftest import SMALL, run

CONSTANT = '\n[[seals]]\nname = "S"\nshaft = "s1"\nnode = 2\nkxx = "-4e6 N/m"\nkyy = "-4e6 N/m"\n'
CONSTANT += 'kxy = "2e6 N/m"\nkyx = "-2e6 N/m"\nc = "300 N*s/m"\n'
TABLE = (
    '\n[[seals]]\nname = "S"\nshaft = "s1"\nnode = 2\n'
    'table = { speed = ["500 rpm", "5000 rpm"], kxx = ["-4e6 N/m", "-4e6 N/m"], '
    'kxy = ["2e6 N/m", "2e6 N/m"], kyx = ["-2e6 N/m", "-2e6 N/m"], '
    'kyy = ["-4e6 N/m", "-4e6 N/m"], cxx = [300, 300], cxy = [0, 0], cyx = [0, 0], '
    'cyy = [300, 300], extrapolate = "hold" }\n'
)


def _train(text):
    import tomllib

    return model_from_dict(tomllib.loads(text))


@pytest.mark.parametrize("seal", [CONSTANT, TABLE], ids=["constant", "tabulated"])
def test_seals_carry_no_static_load(seal):
    bare, sealed = _train(SMALL), _train(SMALL + seal)
    a, b = static(bare), static(sealed)
    # each end bearing carries half the weight of the uniform shaft (0.8 m, 50 mm, 7890 kg/m³)
    weight = math.pi / 4 * 0.05**2 * 0.8 * 7890 * 9.80665
    for bl in b.bearings:
        assert abs(bl.force[1]) == pytest.approx(weight / 2, rel=1e-12)
    assert [bl.name for bl in b.bearings] == ["B1", "B2"]  # seals are not bearings
    scale = np.max(np.abs(a.q))
    assert np.max(np.abs(b.q - a.q)) < 1e-12 * scale  # round-off of K0 − K_seal
    # the seal is still in the dynamics: with −4e6 N/m at mid-span the modes move
    w = 3000 * math.pi / 30
    lam_sealed, lam_bare = (modal(t, speed=w).eigenvalues[:4] for t in (sealed, bare))
    assert not np.allclose(lam_sealed, lam_bare)


def test_static_command_with_seals(tmp_path):
    path = tmp_path / "sealed.toml"
    path.write_text(SMALL + TABLE)
    r, _ = run("static", path, "--format", "json", "--plot", tmp_path / "figs")
    assert r.exit_code == 0, (r.output, r.exception)
    assert (tmp_path / "figs" / "static.json").exists()


@pytest.fixture(scope="module")
def sealed_pair(examples, tmp_path_factory) -> Path:
    """The geared pair on plain journals of test_static_transient_op, with a seal on each
    shaft (one constant, one tabulated)."""
    path = tmp_path_factory.mktemp("sealed") / "pair.toml"
    film = (examples / "bearings" / "plain_ld1.toml").as_posix()
    text = MODEL.format(film=film, rp=R_PINION, rg=3 * R_PINION, torque=TORQUE)
    text += '\n[[seals]]\nshaft = "p"\nnode = 2\nk = "-3e6 N/m"\nkxy = "1e6 N/m"\nc = 200\n'
    text += TABLE.replace('"s1"', '"g"').replace('name = "S"\n', "")
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "command",
    [
        ["static", "--operating-point", "P"],
        ["modal", "--operating-point", "P"],
        ["campbell", "--operating-point", "P", "--n-speeds", "3", "--min-speed", "2000"],
        ["unbalance", "--operating-point", "P", "--n-speeds", "5", "--min-speed", "2000"]
        + ["--set", "unbalances=[{shaft='p', node=4, amount='100 g*mm'}]"]
        + ["--set", "probes=[{name='x', shaft='p', node=4}]"],
        ["ucs", "--operating-point", "P", "--n-points", "3", "--n-modes", "1"],
    ],
    ids=lambda c: c[0],
)
def test_operating_point_runs_with_seals(sealed_pair, command):
    r, _ = run(command[0], sealed_pair, *command[1:])
    assert r.exit_code == 0, (r.output, r.exception)


def test_transient_at_operating_point_with_seals_stays_at_static_state(sealed_pair):
    """The seals act on the motion about the static state: with no unbalance and balanced
    torques the run stays at the static deflection (tolerance as test_static_transient_op's)."""
    from gearrotor.analyses.transient import transient
    from gearrotor.assembly import assemble

    train = load_model(sealed_pair)
    st = static(train, "P")
    res = transient(train, t_end=0.02, operating_point="P")
    act = res.active_dofs
    lateral = assemble(train).dof_kind()[act] == 0
    q_static = st.q[act]
    scale = np.max(np.abs(q_static[lateral]))
    assert scale > 1e-5
    assert np.max(np.abs(res.final_q[lateral] - q_static[lateral])) < 1e-7 * scale
    # the seals' forces are those about the static state: zero throughout
    seals = [k for k, n in enumerate(res.bearing_names) if n.startswith("seals[")]
    assert len(seals) == 2
    assert np.max(np.abs(res.bearing_force[:, seals, :])) < 1e-7 * TORQUE / R_PINION
