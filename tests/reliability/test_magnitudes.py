"""Generated corpus of meaningless magnitudes and unclear refusals (issue 23): each was accepted
with exit 0 (or refused without naming what) and is now refused before anything runs, with
exit 2 and one line naming the model file, the field, the value and the bound with its reason.

The bounds (model/operating_point.py, model/audit.py) sit far above any machine and far below
where the numbers stop meaning anything: 100 g of steady acceleration, 1e9 N (the weight of
100,000 t), 1e9 N·m of torque (a hundred times a 100 MW ship's shaft), 1e11 W, a gas density
of 1,500 kg/m³ (supercritical CO₂ at 1,000 bar is 1,100 kg/m³). Each case also checks that a
value at the bound's real-world end is still accepted, so a bound cannot be set too tight
unnoticed.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .conftest import SMALL, check_refused, files_in, run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: two operating points of the small model (the 'torque' one: drive at node 0, load at node 4)
POINTS = """
[[operating_points]]
name = "side"
forces = [ { shaft = "s1", node = 2, force = ["0 N", "-500 N", "0 N"] } ]

[[operating_points]]
name = "driven"
torque = "100 N*m"
drive = { shaft = "s1", node = 0 }
load = { shaft = "s1", node = 4 }

[[operating_points]]
name = "powered"
power = "50 kW"
drive = { shaft = "s1", node = 0 }
load = { shaft = "s1", node = 4 }
"""

# (id, --set overrides, substrings besides the file name, an accepted real-world value)
CASES = [
    (
        "gravity-1e9",
        ["operating_points[0].gravity_acceleration=1e9 m/s^2"],
        ["operating_points[0].gravity_acceleration", "1e+09 m/s^2", "100 g"],
        ["operating_points[0].gravity_acceleration=3 m/s^2"],  # a ship in a seaway
    ),
    (
        "force-1e15",
        ["operating_points[0].forces[0].force=[0, 1e15, 0]"],
        ["operating_points[0].forces[0].force", "1e+15 N", "100,000 t"],
        ["operating_points[0].forces[0].force=[0, '-2 MN', 0]"],
    ),
    (
        "moment-1e12",
        ["operating_points[0].forces[0].moment=[1e12, 0, 0]"],
        ["operating_points[0].forces[0].moment", "1e+12 N*m"],
        ["operating_points[0].forces[0].moment=['5 kN*m', 0, 0]"],
    ),
    (
        "torque-1e12",
        ["operating_points[1].torque=1e12 N*m"],
        ["operating_points[1].torque", "1e+12 N*m", "ship's shaft"],
        ["operating_points[1].torque=2000 N*m"],
    ),
    (
        "power-1e13",
        ["operating_points[2].power=1e13 W"],
        ["operating_points[2].power", "1e+13 W", "turbine-generator"],
        ["operating_points[2].power=5 MW"],
    ),
    (
        "drive-is-load",
        ["operating_points[1].load.node=0"],
        ["operating_points[1].load", "the load node is the drive node", "node 0"],
        ["operating_points[1].load.node=3"],
    ),
]


@pytest.mark.parametrize(
    "overrides, needles, accepted", [c[1:] for c in CASES], ids=[c[0] for c in CASES]
)
def test_meaningless_operating_point_refused(small, overrides, needles, accepted):
    small.write_text(SMALL + POINTS)
    before = files_in(small.parent)
    args = ["static", small, "--all"]
    r, dt = run(*args, *(x for o in overrides for x in ("--set", o)))
    check_refused(r, dt, "small.toml", *needles)
    assert files_in(small.parent) == before
    r, _ = run(*args, *(x for o in accepted for x in ("--set", o)))
    assert r.exit_code == 0, (r.output, r.exception)


AUDIT = """
max_continuous_speed = "3000 rpm"
[api_audit]
qa = "1e5 N/m"
at = [{ shaft = "s1", node = 2 }]
average_density = "DENSITY"
"""


@pytest.mark.parametrize(
    "density, ok",
    [("1e6 kg/m^3", False), ("1.2 g/cm^3", True), ("2 g/cm^3", False), ("40 kg/m^3", True)],
)
def test_gas_density_bounded(small, density, ok):
    """A gas density of 1e6 kg/m³ went into the API 617 screening chart; 2 g/cm³ is a unit
    mistake or a liquid. Both refused; 1.2 g/cm³ (1,200 kg/m³: supercritical CO₂) and a
    40 kg/m³ process gas pass."""
    text = SMALL.replace('speed = "3000 rpm"\n', 'speed = "3000 rpm"\n' + AUDIT, 1)
    small.write_text(text.replace("DENSITY", density))
    r, dt = run("stability", small)
    if ok:
        assert r.exit_code in (0, 1) or "FAIL" in r.stdout, (r.output, r.exception)
        assert "average density" not in r.stderr
    else:
        check_refused(r, dt, "small.toml", "api_audit.average_density", "1500 kg/m^3")


def test_gas_density_option_bounded(small):
    args = ["stability", small, "--mcs", "3000", "--qa", "1e5", "--at", "s1:2"]
    r, dt = run(*args, "--average-density", "1e6")
    check_refused(r, dt, "--average-density", "'1e6'", "denser than any compressed gas")


TABLE = "speed_rpm,kxx,kxy,kyx,kyy,cxx,cxy,cyx,cyy\n"


@pytest.mark.parametrize(
    "rows, needles",
    [
        ("1000,1e7,0,0,1e7,1e3,0,0,1e3\n1000,2e7,0,0,2e7,1e3,0,0,1e3\n", ["rows 1 and 2"]),
        ("-1000,1e7,0,0,1e7,1e3,0,0,1e3\n1000,2e7,0,0,2e7,1e3,0,0,1e3\n", ["sense of rotation"]),
    ],
    ids=["same-row-twice", "plus-and-minus"],
)
def test_duplicate_speed_row_in_a_table_file(small, rows, needles):
    """Two rows at one speed held two sets of coefficients for it; the interpolation took
    either, silently."""
    (small.parent / "t.csv").write_text(TABLE + rows + "3000,1e7,0,0,1e7,1e3,0,0,1e3\n")
    text = small.read_text().replace(
        'k = "1e7 N/m"\nc = "1e3 N*s/m"', 'table_file = "t.csv"\nextrapolate = "hold"', 1
    )
    small.write_text(text)
    r, dt = run("modal", small)
    check_refused(
        r, dt, "small.toml", "bearings[0].table_file", "t.csv", "speed_rpm", "one row per speed",
        *needles,
    )  # fmt: skip


@pytest.mark.parametrize(
    "entry",
    [
        '[[bearings]]\nshaft = "s1"\nnode = 1\nfluid_film = {{ file = "{film}", '
        'speeds = ["3000 rpm", "100 Hz", "50 Hz"] }}\n',
        '[[seals]]\nshaft = "s1"\nnode = 1\nfile = "{seal}"\nspeeds = ["3000 rpm", "3000 rpm"]\n',
    ],
    ids=["fluid-film", "seal-file"],
)
def test_duplicate_tabulation_speed(small, entry):
    """``speeds`` of a solved table: 50 Hz is 3000 rpm."""
    seal = next((EXAMPLES / "seals").glob("*.toml"))
    film = EXAMPLES / "bearings" / "plain_ld1.toml"
    small.write_text(SMALL + entry.format(film=film.as_posix(), seal=seal.as_posix()))
    r, dt = run("modal", small)
    check_refused(r, dt, "small.toml", "speeds", "the same speed (3000 rpm)")


def test_fluid_film_overload_names_the_operating_point(examples, tmp_path):
    """Issue 23: under ``static --all`` a journal that cannot carry its load was refused
    without saying at which operating point; the line now names it (LC10 at 200 MW)."""
    r, dt = run(
        "static", examples / "steam_turbine_gearbox.toml", "--all",
        "--set", "operating_points[9].power=200 MW",
    )  # fmt: skip
    check_refused(r, dt, "bearings[0].fluid_film", "at operating point 'LC10'", "cannot carry")
