"""Issue 22, "Consistency and small things" (the command line's part) and the steam turbine's
default speeds:

* ``--help`` prints help text as written: rich markup took ``[[operating_points]]``,
  ``[api_audit]`` or ``[default]`` for tags and dropped them ("operating point of the model
  ([] name)"); speed and time options show SPEED / TIME, not ``<float>``, and say which units
  they take;
* a ``--set`` path that names no field of the model gets "did you mean" (the closest field
  path of that model); an index past the end of a list names the list's range;
* ``--orders`` / ``--torque`` errors name the option, not the analysis's argument
  (``excitations[0].shaft``), and say what is wrong in words (no pydantic "Value error, ");
* ``campbell`` / ``unbalance`` with their default speeds sweep the speeds the model's bearing
  tables cover (the steam turbine's 2,000-16,000 rpm), and a speed given outside them is an
  error naming the option and the bearing.
"""

from __future__ import annotations

import json
import re

import pytest
import typer.main
from typer.testing import CliRunner

from gearrotor.cli import app
from gearrotor.cli.options import UNITS_HELP
from gearrotor.inputs import read_toml
from gearrotor.io.model_file import model_field_paths
from gearrotor.model import Train

STEAM = "examples/steam_turbine_gearbox.toml"
UNITY = "examples/unity_gearbox.toml"
MGC = "examples/motor_gearbox_compressor.toml"


def invoke(*args: str):
    return CliRunner().invoke(app, [str(a) for a in args])


def error_line(r, *needles: str) -> str:
    assert r.exit_code == 2, (r.exit_code, r.output)
    assert r.stderr.startswith("error: ") and len(r.stderr.strip().splitlines()) == 1, r.stderr
    for n in needles:
        assert n in r.stderr, (n, r.stderr)
    return r.stderr


def _commands(group, path=()):
    for name, cmd in group.commands.items():
        if hasattr(cmd, "commands"):
            yield from _commands(cmd, (*path, name))
        else:
            yield (*path, name), cmd


COMMANDS = list(_commands(typer.main.get_command(app)))


@pytest.mark.parametrize("path,cmd", COMMANDS, ids=[" ".join(p) for p, _ in COMMANDS])
def test_help_prints_bracketed_text_and_speed_units(path, cmd):
    r = invoke(*path, "--help")
    assert r.exit_code == 0, r.output
    shown = " ".join(r.output.split())
    for param in cmd.params:
        # every bracketed part of an option's help is printed ("([[operating_points]] name)",
        # "(default: the model's [api_audit] at)")
        for part in re.findall(r"\[[^\s\]]*\]+", param.help or ""):
            assert part in shown, (param.name, part, shown)
        # options that take a speed or a time with units say so
        if param.metavar in UNITS_HELP:
            opt = param.opts[-1]
            assert f"{opt} {param.metavar}" in shown, (opt, shown)
            assert UNITS_HELP[param.metavar] in shown
    speeds = [p for p in cmd.params if p.metavar == "SPEED"]
    assert not any(f"{p.opts[-1]} <float>" in shown for p in speeds)


def test_help_no_longer_drops_the_issue_examples():
    shown = " ".join(invoke("campbell", "--help").output.split())
    assert "([[operating_points]] name)" in shown
    assert "--min-speed SPEED" in shown and "--min-speed <float>" not in shown
    shown = " ".join(invoke("stability", "--help").output.split())
    assert "(default: the model's [api_audit] at)" in shown


@pytest.mark.parametrize(
    "override,wanted",
    [
        ("meshes[0].stifness=3e7", "meshes[0].stiffness"),
        ("meshs[0].stiffness=3e7", "meshes[0].stiffness"),
        ("meshes[0].variation.ka_raito=0.2", "meshes[0].variation.ka_ratio"),
        ("meshes[0].variaton.ka_ratio=0.2", "meshes[0].variation.ka_ratio"),
        ("unbalances[1].ammount=1", "unbalances[1].amount"),
        ("bearing[0].k=1", "bearings[0].k"),
        ("speeed=6000", "speed"),
    ],
)
def test_set_typo_did_you_mean(override, wanted):
    r = invoke("modal", UNITY, "--set", override)
    line = error_line(r, "unity_gearbox.toml", override.split("=")[0], "no such field")
    assert line.strip().endswith(f"did you mean {wanted!r}?"), line


def test_set_index_past_the_end_names_the_range():
    r = invoke("modal", UNITY, "--set", "bearings[9].k=1e7")
    error_line(r, "bearings[9].k", "index out of range", "0..3")


def test_field_paths_cover_every_documented_override():
    """The paths "did you mean" chooses from are the model's: every --set path of the README's
    override table and of the docs' commands is one of them (so that a valid path is never
    corrected)."""
    from doc_examples import ROOT, printed_commands

    readme = (ROOT / "README.md").read_text()
    table = readme[readme.index("Override paths of the flagship example") :]
    table = table[: table.index("## Layout")]
    unity = model_field_paths(read_toml(ROOT / UNITY, "model"))
    rows = 0
    for cell in re.findall(r"^\| (`[^|]+) \|", table, flags=re.M):
        spans = re.findall(r"`([^`]+)`", cell)
        parent = spans[0].rsplit(".", 1)[0]
        for span in spans:  # `meshes[0].variation.ka_ratio`, `.contact_ratio`; [k] is an index
            path = parent + span if span.startswith(".") else span
            path = re.sub(r"\[[a-z]\]", "[1]", path)
            assert path in unity, (cell, path)
            rows += 1
    assert rows >= 14
    sets = 0
    for cmd in printed_commands()[0]:
        model = next((a for a in cmd.argv if a.endswith(".toml")), None)
        if model is None or not (ROOT / model).is_file() or "study" in cmd.argv[:1]:
            continue
        paths = model_field_paths(read_toml(ROOT / model, "model"))
        for k, arg in enumerate(cmd.argv[:-1]):
            if arg == "--set":
                sets += 1
                path = cmd.argv[k + 1].split("=", 1)[0]
                assert re.sub(r"\.(\d+)", r"[\1]", path) in paths, (cmd.id, path)
    assert sets > 20


def test_field_paths_are_the_model_fields():
    paths = model_field_paths({"meshes": [{}], "materials": {"steel": {}}})
    assert {"meshes[0].variation.ka_ratio", "meshes[0].stiffness", "speed"} <= paths
    assert "materials.steel.E" in paths and "api_audit.exclude_bearings" in paths
    assert not any(p.startswith("bearings[") for p in paths)  # the data has no bearings
    assert set(Train.model_fields) <= paths


@pytest.mark.parametrize("orders", ["0", "-3", "nan", "inf", "1,,2", "x", ""])
def test_campbell_orders_checked(orders):
    r = invoke("campbell", UNITY, f"--orders={orders}", "--n-speeds", "2")
    error_line(r, "--orders", "positive multiples")


def test_torsional_orders_and_torque_errors_name_the_option():
    r = invoke("torsional", "campbell", MGC, "--orders", "motr:2")
    error_line(r, "--orders[0]: unknown shaft", "'motr'")
    base = "shaft=motor,node=4,amplitude=5 kN*m,order=2"
    r = invoke("torsional", "response", MGC, "--torque", base.replace("motor", "motr"))
    line = error_line(r, "--torque[0].shaft: unknown shaft")
    assert "excitations" not in line
    r = invoke("torsional", "response", MGC, "--torque", base.replace("node=4", "node=44"))
    error_line(r, "--torque[0].node")
    r = invoke("torsional", "response", MGC, "--torque", base.replace("amplitude", "amplitud"))
    error_line(r, "--torque[0].amplitud: unknown key")
    r = invoke("torsional", "response", MGC, "--torque", base.replace(",order=2", ""))
    line = error_line(r, "--torque[0]: give exactly one of 'order' or 'frequency'")
    assert "Value error" not in line


def test_steam_turbine_default_sweeps_stay_in_the_bearing_tables():
    # the pinion bearings are tabulated at 2,000-16,000 rpm, the bull gear's at 250-2,250 rpm
    # of the bull gear (1,800-16,200 rpm of the pinion): the sweeps start at 2,000 rpm (not at
    # 0 / 100 rpm) and the unbalance sweep's default 1.5 x 10,800 = 16,200 rpm stops at 16,000
    r = invoke("campbell", STEAM, "--n-speeds", "2", "--max-frequency", "20000", "--format", "json")
    assert r.exit_code == 0, r.output
    speeds = json.loads(r.stdout)["speeds_rpm"]
    assert speeds[0] == pytest.approx(2000, rel=1e-6)
    assert speeds[-1] == pytest.approx(1.25 * 10800, rel=1e-9)
    r = invoke("unbalance", STEAM, "--n-speeds", "2", "--format", "json")
    assert r.exit_code == 0, r.output
    speeds = json.loads(r.stdout)["speeds_rpm"]
    assert speeds[0] == pytest.approx(2000, rel=1e-6)
    assert speeds[-1] == pytest.approx(16000, rel=1e-6)


@pytest.mark.parametrize("command", ["campbell", "unbalance"])
def test_speed_outside_the_bearing_tables_names_option_and_bearing(command):
    r = invoke(command, STEAM, "--min-speed", "100", "--n-speeds", "2")
    error_line(r, "--min-speed", "'pinion brg 1 (coupling end)'", "2000 rpm")
    r = invoke(command, STEAM, "--max-speed", "17000", "--n-speeds", "2")
    error_line(r, "--max-speed", "bearing '", "16000 rpm")


def test_campbell_no_modes_names_max_frequency():
    # the flagship has no mode below 3,000 cpm at 0 rpm: an input error naming the option, not
    # a traceback
    r = invoke("campbell", UNITY, "--n-speeds", "2", "--max-frequency", "3000")
    error_line(r, "--max-frequency: no modes below max_frequency", "a higher max_frequency")


def test_models_without_tables_keep_their_defaults():
    r = invoke("campbell", UNITY, "--n-speeds", "2", "--max-frequency", "8000", "--format", "json")
    assert json.loads(r.stdout)["speeds_rpm"][0] == 0.0


@pytest.mark.parametrize("command", ["campbell", "unbalance"])
def test_sweep_at_an_operating_point_says_how_to_fix_a_lost_film(command):
    # LC10 holds 12.5 MW: at the tables' 2,000 rpm that is 5.4 x the rated torque, more than
    # the journals carry; the error names the speed, the option and the model field
    r = invoke(command, STEAM, "--operating-point", "LC10", "--n-speeds", "2")
    error_line(r, "cannot carry its load", "at 2000 rpm", "--min-speed", 'hold = "torque"')
