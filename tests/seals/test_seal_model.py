"""A seal file in a rotor model (``[[seals]] file = ..., speeds = [...]``): its synchronous
coefficients tabulated over speed reach the assembled matrices, the sense of rotation mirrors
the cross-coupling, a destabilising labyrinth lowers the forward mode's log dec, and bad seal
entries are one-line errors naming the model file, the field and the seal file."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

from doc_examples import ROOT
from gearrotor import assemble, load_model, modal
from gearrotor.errors import ModelError
from gearrotor.seals import load_seal, seal_coefficients

EX = ROOT / "examples" / "seals"
MODEL = EX / "compressor_with_seals.toml"
RPM = math.pi / 30


def _seal_block(asm, name):
    (info,) = [b for b in asm.bearings if b.name == name]
    return info


def test_tabulated_coefficients_reach_the_matrices():
    train = load_model(MODEL)
    asm = assemble(train)
    eye = _seal_block(asm, "eye seal")
    assert eye.kind == "seal" and eye.element.speed_dependent
    ref = seal_coefficients(load_seal(EX / "labyrinth_interlocking.toml"), 9000 * RPM)
    got = eye.element.coefficients(9000 * RPM)
    assert got == pytest.approx(ref.coefficients, rel=1e-12)
    # between tabulated speeds: linear interpolation, as for a bearing table
    mid = eye.element.coefficients(10000 * RPM)
    lo, hi = eye.element.coefficients(9000 * RPM), eye.element.coefficients(11000 * RPM)
    assert mid == pytest.approx(0.5 * (lo + hi), rel=1e-12)
    _, C, _, K = asm.matrices(11000 * RPM)
    d = eye.dofs
    k11 = seal_coefficients(load_seal(EX / "labyrinth_interlocking.toml"), 11000 * RPM)
    hp = _seal_block(asm, "balance piston")
    assert hp.element.coefficients(11000 * RPM)[1] != 0
    # the eye seal's node carries no bearing: its 2x2 block is shaft + seal; the seal's cross
    # terms are the whole skew part of that block
    Kd = K.toarray()[np.ix_(d, d)]
    assert 0.5 * (Kd[0, 1] - Kd[1, 0]) == pytest.approx(k11.kxy, rel=1e-9)
    Cd = C.toarray()[np.ix_(d, d)]
    assert 0.5 * (Cd[0, 1] - Cd[1, 0]) == pytest.approx(k11.cxy, rel=1e-9)


def test_a_shaft_turning_backwards_mirrors_the_cross_coupling(tmp_path):
    shutil.copy(EX / "labyrinth_interlocking.toml", tmp_path)
    shutil.copy(EX / "hole_pattern.toml", tmp_path)
    text = MODEL.read_text().replace('speed = "11000 rpm"', 'speed = "-11000 rpm"')
    (tmp_path / "m.toml").write_text(text)
    asm_n = assemble(load_model(tmp_path / "m.toml"))
    asm_p = assemble(load_model(MODEL))
    a = _seal_block(asm_n, "eye seal").element.coefficients(9000 * RPM)
    b = _seal_block(asm_p, "eye seal").element.coefficients(9000 * RPM)
    assert a[[0, 3, 4, 7]] == pytest.approx(b[[0, 3, 4, 7]])
    assert a[[1, 2, 5, 6]] == pytest.approx(-b[[1, 2, 5, 6]])


def test_destabilising_labyrinth_lowers_the_forward_log_dec(tmp_path):
    """The eye seal's kxy > 0 with negative effective damping takes damping from the first
    forward mode (and the hole-pattern seal adds damping)."""
    base = load_model(MODEL, {"seals[1].extrapolate": "hold"})
    data = base.model_dump()
    without = type(base).model_validate({**data, "seals": []})
    only_eye = type(base).model_validate({**data, "seals": [data["seals"][0]]})

    def first_forward(train):
        res = modal(train, speed=11000 * RPM, max_frequency=30000 * RPM)
        fw = [i for i in range(len(res)) if res.whirl_per_shaft[i][0] == "F"]
        return res.log_dec[fw[0]]

    assert first_forward(only_eye) < first_forward(without)
    assert first_forward(base) > first_forward(only_eye)


@pytest.mark.parametrize(
    ("entry", "needles"),
    [
        ('file = "labyrinth_interlocking.toml"', ["seals[0]", "speeds"]),
        ('file = "nope.toml"\nspeeds = ["1000 rpm"]', ["seals[0].file", "nope.toml", "not found"]),
        (
            'file = "bad_seal.toml"\nspeeds = ["1000 rpm"]',
            ["seals[0].file", "bad_seal.toml", "radial_clearance", "-0.3 mm"],
        ),
        (
            'file = "labyrinth_interlocking.toml"\nspeeds = ["1000 rpm"]\nk = "1e5 N/m"',
            ["seals[0]", "one coefficient source"],
        ),
    ],
)
def test_bad_seal_entries(tmp_path, entry, needles):
    shutil.copy(EX / "labyrinth_interlocking.toml", tmp_path)
    (tmp_path / "bad_seal.toml").write_text(
        (EX / "labyrinth_interlocking.toml")
        .read_text()
        .replace('radial_clearance = "0.3 mm"', 'radial_clearance = "-0.3 mm"')
    )
    model = (ROOT / "examples" / "unity_gearbox_single_shaft.toml").read_text()
    model += f'\n[[seals]]\nname = "s"\nshaft = "shaft1"\nnode = 5\n{entry}\n'
    path = tmp_path / "model.toml"
    path.write_text(model)
    with pytest.raises(ModelError) as err:
        assemble(load_model(path))
    msg = str(err.value)
    assert "\n" not in msg
    for n in needles:
        assert n in msg, (n, msg)
