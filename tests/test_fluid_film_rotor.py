"""Rotor bearings fed by the fluid-film solver (type fluid_film) and by saved tables."""

import numpy as np

from gearrotor.assembly import assemble
from gearrotor.bearings import coefficients, coefficients_table, load_bearing, save_table
from gearrotor.io import load_model
from helpers import rotor_toml

#: a 0.6 m rotor (no disk) on the bearing under test at node 0 and a stiff one at node 4
BEARINGS = """[[bearings]]
shaft = "rotor"
node = 0
{source}
[[bearings]]
shaft = "rotor"
node = 4
k = "1e8 N/m"
"""


def _model(speed: float, source: str) -> str:
    return rotor_toml(speed=speed, length=0.6, elements=4, disk_node=None) + BEARINGS.format(
        source=source
    )


def test_fluid_film_bearing_matches_the_solver(tmp_path, examples):
    src = examples / "bearings" / "plain_ld1.toml"
    (tmp_path / "b.toml").write_text(src.read_text())
    case = load_bearing(src)
    speeds = [3000.0, 6000.0]
    ff = 'fluid_film = { file = "b.toml", load_case = 0, speeds = ["3000 rpm", "6000 rpm"] }'
    p = tmp_path / "m.toml"
    p.write_text(_model(4500, ff))
    asm = assemble(load_model(p))  # relative path resolved against the model's folder
    el = asm.bearings[0].element
    for n in speeds:
        direct = coefficients(case.bearing, case.loads[0], n * np.pi / 30, options=case.options)
        np.testing.assert_allclose(el.K(n * np.pi / 30), direct.K, rtol=1e-9)
        np.testing.assert_allclose(el.C(n * np.pi / 30), direct.C, rtol=1e-9)
    # between table points the coefficients are interpolated linearly
    mid = 0.5 * (el.K(3000 * np.pi / 30) + el.K(6000 * np.pi / 30))
    np.testing.assert_allclose(el.K(4500 * np.pi / 30), mid, rtol=1e-12)

    # the same through a saved table file
    table = coefficients_table(case.bearing, case.loads[0], speeds, options=case.options)
    save_table(table, tmp_path / "t.csv")
    p.write_text(_model(4500, 'table_file = "t.csv"'))
    el2 = assemble(load_model(p)).bearings[0].element
    np.testing.assert_allclose(el2.K(3000 * np.pi / 30), el.K(3000 * np.pi / 30), rtol=1e-6)
