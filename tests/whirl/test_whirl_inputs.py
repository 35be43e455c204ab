"""Inputs of speed × whirl tables (issue 24): one-line errors naming the file, the field, the
value and what was expected, before anything runs (exit status 2)."""

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor.assembly import assemble
from gearrotor.cli import app
from gearrotor.io import load_model
from helpers import rotor_toml

#: the rotor of the tilting-pad tests on a 4-element mesh, a plain bearing at node 0 and the
#: bearing under test at node 4
BEARINGS = """[[bearings]]
shaft = "rotor"
node = 0
k = "2e7 N/m"
c = "2e4 N*s/m"
[[bearings]]
shaft = "rotor"
node = 4
"""


def _model(bearing: str) -> str:
    return rotor_toml(elements=4, disk_node=2) + BEARINGS + bearing + "\n"


#: a valid 2 speeds × 3 whirl frequencies table, stiffening with whirl; three whirl frequencies
#: allow one pole: its fit misfits the table by 1.5 %, which the model accepts
TABLE = """fit_tolerance = 0.02
table.speed = ["3000 rpm", "9000 rpm"]
table.whirl = ["0 rpm", "6000 rpm", "12000 rpm"]
table.kxx = [[2e7, 2.2e7, 2.8e7], [2.1e7, 2.3e7, 2.9e7]]
table.kxy = [[0, 0, 0], [0, 0, 0]]
table.kyx = [[0, 0, 0], [0, 0, 0]]
table.kyy = [[2e7, 2.2e7, 2.8e7], [2.1e7, 2.3e7, 2.9e7]]
table.cxx = [[2e4, 1.8e4, 1.5e4], [2e4, 1.8e4, 1.5e4]]
table.cxy = [[0, 0, 0], [0, 0, 0]]
table.cyx = [[0, 0, 0], [0, 0, 0]]
table.cyy = [[2e4, 1.8e4, 1.5e4], [2e4, 1.8e4, 1.5e4]]
"""


def _write(tmp_path, bearing: str):
    p = tmp_path / "m.toml"
    p.write_text(_model(bearing))
    return p


def _one_line_error(tmp_path, bearing: str, *needles: str, file: str = "m.toml") -> str:
    """The command line's message for the model (exit 2, one line naming ``file``, the
    needles in it)."""
    p = _write(tmp_path, bearing)
    r = CliRunner().invoke(app, ["modal", str(p)])
    assert r.exit_code == 2, (r.exit_code, r.output, r.exception)
    msg = r.stderr.strip()
    assert len(msg.splitlines()) == 1 and "Traceback" not in r.output, msg
    assert file in msg
    for n in needles:
        assert n in msg, (n, msg)
    return msg


def test_a_valid_table_runs(tmp_path):
    train = load_model(_write(tmp_path, TABLE))
    asm = assemble(train)
    assert type(asm.bearings[1].element).__name__ == "WhirlBearing"
    r = CliRunner().invoke(app, ["modal", str(tmp_path / "m.toml"), "--format", "json"])
    assert r.exit_code == 0, r.output
    assert '"frequency_dependence"' in r.output


@pytest.mark.parametrize(
    "change, needles",
    [
        # rows without whirl frequencies
        (('table.whirl = ["0 rpm", "6000 rpm", "12000 rpm"]\n', ""), ("table", "'whirl'")),
        # a row of the wrong length
        (("[2e7, 2.2e7, 2.8e7], [2.1e7", "[2e7, 2.2e7], [2.1e7"), ("kxx", "row 0", "3 frequ")),
        # whirl frequencies that do not reach the highest speed
        (('"12000 rpm"]\n', '"8000 rpm"]\n'), ("whirl", "cover the speeds", "9000")),
        # not increasing
        (('["0 rpm", "6000 rpm", "12000 rpm"]', '["0 rpm", "12000 rpm", "6000 rpm"]'), ("whirl",)),
        # a value that is not a stiffness
        (("[[2e7, 2.2e7, 2.8e7]", '[["2e7 N", 2.2e7, 2.8e7]'), ("kxx", "stiffness")),
        # values and rows mixed
        (("[[0, 0, 0], [0, 0, 0]]\ntable.kyx", "[0, [0, 0, 0]]\ntable.kyx"), ("kxy", "mixes")),
    ],
)
def test_bad_tables_are_one_line_errors(tmp_path, change, needles):
    old, new = change
    assert old in TABLE
    _one_line_error(tmp_path, TABLE.replace(old, new, 1), "bearings[1]", *needles)


def test_a_tolerance_the_table_cannot_meet(tmp_path):
    """Three whirl frequencies allow at most one pole: a misfit of 1e-12 is out of reach."""
    msg = _one_line_error(
        tmp_path,
        TABLE.replace("fit_tolerance = 0.02", "fit_tolerance = 1e-12"),
        "bearings[1].table",
        "fit_tolerance = 1e-12",
        "best relative misfit",
        "rpm",
    )
    assert "expected" in msg


def test_fit_tolerance_only_with_a_table(tmp_path):
    _one_line_error(tmp_path, 'k = "2e7 N/m"\nfit_tolerance = 1e-6', "fit_tolerance", "table")


def test_seal_whirls_need_a_seal_file(tmp_path):
    seal = '[[seals]]\nshaft = "rotor"\nnode = 2\nk = "1e6 N/m"\nwhirls = ["0 rpm", "9000 rpm"]\n'
    p = tmp_path / "m.toml"
    p.write_text(_model('k = "2e7 N/m"') + seal)
    r = CliRunner().invoke(app, ["modal", str(p)])
    assert r.exit_code == 2 and "seals[0]" in r.stderr and "whirls" in r.stderr, r.stderr


@pytest.mark.parametrize(
    "rows, needles",
    [
        # the 9000 rpm row stops below its speed
        ([(3000, 0), (3000, 6000), (9000, 0), (9000, 6000)], ("whirl_rpm", "cover", "9000")),
        # whirl frequencies repeated at one speed
        ([(3000, 0), (3000, 0), (3000, 6000)], ("whirl_rpm", "increasing")),
    ],
)
def test_bad_whirl_table_files(tmp_path, rows, needles):
    lines = ["speed_rpm,whirl_rpm,kxx,kxy,kyx,kyy,cxx,cxy,cyx,cyy"]
    for s, w in rows:
        lines.append(f"{s},{w},{2e7 + 100 * w},0,0,2e7,2e4,0,0,2e4")
    (tmp_path / "t.csv").write_text("\n".join(lines) + "\n")
    _one_line_error(
        tmp_path, 'table_file = "t.csv"', "bearings[1].table_file", *needles, file="t.csv"
    )


def test_a_whirl_table_file_runs(tmp_path):
    """The CSV that :func:`gearrotor.bearings.pads.save_whirl_table` writes, read back: the
    same element as the model's own table."""
    lines = ["speed_rpm,whirl_rpm,kxx,kxy,kyx,kyy,cxx,cxy,cyx,cyy", "# N/m ..."]
    for s in (3000, 9000):
        for w, k, c in ((0, 2e7, 2e4), (6000, 2.2e7, 1.8e4), (12000, 2.8e7, 1.5e4)):
            k = k + (1e6 if s == 9000 else 0.0)
            lines.append(f"{s},{w},{k},0,0,{k},{c},0,0,{c}")
    (tmp_path / "t.csv").write_text("\n".join(lines) + "\n")
    a = assemble(load_model(_write(tmp_path, 'table_file = "t.csv"\nfit_tolerance = 0.02')))
    b = assemble(load_model(_write(tmp_path, TABLE)))
    ea, eb = a.bearings[1].element, b.bearings[1].element
    for ra, rb in zip(ea.rows, eb.rows, strict=True):
        np.testing.assert_allclose(ra.values, rb.values, rtol=1e-15)
        np.testing.assert_allclose(ra.whirl, rb.whirl, rtol=1e-15)


def test_a_seal_takes_a_whirl_table_with_negative_direct_terms(tmp_path):
    """[[seals]] take the same 2-D table; a seal's direct stiffness may be negative."""
    seal = TABLE.replace("fit_tolerance = 0.02", "fit_tolerance = 0.2").replace(
        "[[2e7, 2.2e7, 2.8e7], [2.1e7, 2.3e7, 2.9e7]]", "[[-2e6, -3e6, -5e6], [-2e6, -3e6, -5e6]]"
    )
    p = tmp_path / "m.toml"
    p.write_text(
        _model('k = "2e7 N/m"\nc = "2e4 N*s/m"') + '[[seals]]\nshaft = "rotor"\nnode = 2\n' + seal
    )
    asm = assemble(load_model(p))
    info = asm.bearings[-1]
    assert info.kind == "seal" and type(info.element).__name__ == "WhirlBearing"
    # synchronous at 3000 rpm: halfway between the whirl frequencies 0 and 6000 rpm
    assert info.element.coefficients(3000 * np.pi / 30)[0] == pytest.approx(-2.5e6)
