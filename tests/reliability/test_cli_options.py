"""Generated corpus of bad command-line options (issue 17; issue 14 item 10): each is refused
when the command line is read, before anything runs: exit 2 and one line naming the option and
the value (parser errors included: no multi-line boxes). Speed options accept units."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from .conftest import check_refused, files_in, run

# (id, command and options after MODEL, substrings)
CASES = [
    ("speed-nan", ["modal", "MODEL", "--speed", "nan"], ["--speed", "'nan'", "finite"]),
    ("speed-inf", ["modal", "MODEL", "--speed", "inf"], ["--speed", "'inf'", "finite"]),
    ("speed-unit-typo", ["modal", "MODEL", "--speed", "6500 rpmm"], ["--speed", "rpmm"]),
    ("speed-wrong-unit", ["modal", "MODEL", "--speed", "3 m"], ["--speed", "'3 m'"]),
    ("speed-text", ["modal", "MODEL", "--speed", "fast"], ["--speed", "'fast'"]),
    ("maxf-zero", ["modal", "MODEL", "--max-frequency", "0"], ["--max-frequency", "> 0"]),
    ("maxf-neg", ["modal", "MODEL", "--max-frequency", "-100"], ["--max-frequency", "'-100'"]),
    ("maxf-nan", ["modal", "MODEL", "--max-frequency", "nan"], ["--max-frequency", "finite"]),
    ("n-modes-0", ["modal", "MODEL", "--n-modes", "0"], ["--n-modes", "'0'", ">= 1"]),
    ("n-modes-neg", ["modal", "MODEL", "--n-modes", "-3"], ["--n-modes", "'-3'"]),
    ("method-qr", ["modal", "MODEL", "--method", "qr"], ["--method", "'qr'", "'dense'"]),
    ("min-speed-neg", ["campbell", "MODEL", "--min-speed", "-100"], ["--min-speed", ">= 0"]),
    ("n-speeds-1e8", ["campbell", "MODEL", "--n-speeds", "1e8"], ["--n-speeds", "'1e8'"]),
    ("n-speeds-huge", ["unbalance", "MODEL", "--n-speeds", "100000000"], ["--n-speeds", "2.."]),
    ("max-speed-nan", ["unbalance", "MODEL", "--max-speed", "nan"], ["--max-speed", "finite"]),
    (
        "range-reversed",
        ["unbalance", "MODEL", "--operating-range", "7200,5800"],
        ["--operating-range", "7200,5800", "MIN <= MAX"],
    ),
    ("range-nan", ["unbalance", "MODEL", "--operating-range", "nan,nan"], ["--operating-range"]),
    ("range-one", ["unbalance", "MODEL", "--operating-range", "6000"], ["--operating-range"]),
    ("t-end-inf", ["transient", "MODEL", "--t-end", "inf"], ["--t-end", "'inf'", "finite"]),
    ("t-end-zero", ["transient", "MODEL", "--t-end", "0"], ["--t-end", "> 0"]),
    (
        "t-end-1e9",
        ["transient", "MODEL", "--t-end", "1e9", "--no-progress"],
        ["t_end", "GB", "memory"],
    ),
    ("dt-nan", ["transient", "MODEL", "--dt", "nan"], ["--dt", "finite"]),
    (
        "transient-0-rpm",
        ["transient", "MODEL", "--set", "speed=0", "--t-end", "0.01", "--no-progress"],
        ["speed", "non-zero speed"],
    ),
    ("report-speed-nan", ["report", "MODEL", "-o", "OUT", "--speed", "nan"], ["--speed"]),
    ("floquet-speeds-nan", ["floquet", "MODEL", "--speeds", "nan"], ["--speeds", "finite"]),
    ("floquet-n-0", ["floquet", "MODEL", "--n", "0"], ["--n", "'0'"]),
    # parser errors: one line too
    ("missing-value", ["modal", "MODEL", "--speed"], ["--speed", "requires an argument"]),
    ("unknown-option", ["modal", "MODEL", "--sped", "3"], ["--sped"]),
    ("unknown-command", ["modle", "MODEL"], ["modle"]),
    ("missing-argument", ["modal"], ["model"]),
    ("study-missing-argument", ["study", "run"], ["study"]),
    ("bad-int", ["modal", "MODEL", "--n-modes", "x"], ["--n-modes", "'x'"]),
]


@pytest.mark.parametrize("args, needles", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_option_refused(small, args, needles):
    before = files_in(small.parent)
    args = [small if a == "MODEL" else small.parent / "out" if a == "OUT" else a for a in args]
    r, dt = run(*args)
    check_refused(r, dt, *needles)
    assert files_in(small.parent) == before


@pytest.mark.parametrize(
    "speed", ["3000", "3000rpm", "3000 rpm", "314.159265358979 rad/s", "50 Hz"]
)
def test_speed_accepts_units(small, speed):
    """--speed 3000 (rpm) and the same speed with units give the same modes (50 Hz = 3000
    rpm = 100π rad/s: the units are converted, not ignored)."""
    ref, _ = run("modal", small, "--format", "json", "--speed", "3000")
    r, _ = run("modal", small, "--format", "json", "--speed", speed)
    assert r.exit_code == 0, r.output
    a, b = json.loads(ref.stdout), json.loads(r.stdout)
    assert a["speed_rpm"] == pytest.approx(3000, rel=1e-12)
    assert b["speed_rpm"] == pytest.approx(a["speed_rpm"], rel=1e-12)


def test_help_still_works():
    r, _ = run("modal", "--help")
    assert r.exit_code == 0 and "--speed" in r.stdout
    r, _ = run()
    assert "modal" in r.stdout  # a bare command prints its help


EX = Path(__file__).resolve().parents[2] / "examples"
MOTOR = EX / "motor_gearbox_compressor.toml"
UNITY = EX / "unity_gearbox.toml"
OTHER_COMMANDS = [
    (
        "torsional-maxf-nan",
        ["torsional", "modes", MOTOR, "--max-frequency", "nan"],
        ["--max-frequency"],
    ),
    ("torsional-t-end-inf", ["torsional", "transient", MOTOR, "--t-end", "inf"], ["--t-end"]),
    ("torsional-margin", ["torsional", "campbell", MOTOR, "--margin", "2"], ["--margin", "<= 1"]),
    (
        "torsional-n-speeds",
        ["torsional", "response", MOTOR, "--torque", "x", "--n-speeds", "1e8"],
        ["--n-speeds"],
    ),
    ("ucs-method", ["ucs", UNITY, "--method", "qr"], ["--method", "'qr'"]),
    ("ucs-n-points", ["ucs", UNITY, "--n-points", "1"], ["--n-points"]),
    ("stability-mcs", ["stability", UNITY, "--mcs", "-5"], ["--mcs", "> 0"]),
    ("static-speed", ["static", UNITY, "--speed", "nan"], ["--speed", "finite"]),
]


@pytest.mark.parametrize(
    "args, needles", [c[1:] for c in OTHER_COMMANDS], ids=[c[0] for c in OTHER_COMMANDS]
)
def test_bad_option_of_other_commands_refused(args, needles):
    r, dt = run(*args)
    check_refused(r, dt, *needles)
