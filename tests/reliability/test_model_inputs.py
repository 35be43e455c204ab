"""Generated corpus of bad model files and values (issue 17, "inputs"): each is refused with exit
2 and one line naming the model file, the field and the value, within seconds, without a
traceback and without writing anything.

The cases are generated here (not stored files): every class the issue lists (non-finite
numbers, unbounded unit expressions, loose types, duplicate names, non-positive mesh stiffness,
non-UTF-8 text, deep nesting, huge files, table files) with the value that broke it.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from gearrotor.inputs import MAX_BYTES

from .conftest import SMALL, check_refused, files_in, run

UNITY = Path(__file__).resolve().parents[2] / "examples" / "unity_gearbox.toml"

# (id, --set overrides, substrings of the one-line message besides the file name)
SET_CASES = [
    ("E-nan", ["materials.steel.E=nan"], ["materials.steel.E", "finite", "nan"]),
    ("E-inf", ["materials.steel.E=inf"], ["materials.steel.E", "finite", "inf"]),
    ("E-1e999", ["materials.steel.E=1e999 Pa"], ["materials.steel.E", "finite", "1e999 Pa"]),
    ("E-tower", ["materials.steel.E=10**10**10 Pa"], ["materials.steel.E", "10**10**10 Pa"]),
    ("E-tower-caret", ["materials.steel.E=10^10^10 Pa"], ["materials.steel.E", "power"]),
    ("E-long", ["materials.steel.E=" + "1*" * 150 + "1 Pa"], ["materials.steel.E", "characters"]),
    ("bearing-k-nan", ["bearings[0].k=nan"], ["bearings[0].k", "finite"]),
    ("bearing-c-inf", ["bearings[1].c=-inf"], ["bearings[1].c", "finite"]),
    ("diameter-inf", ["shafts[0].sections[0].outer_diameter=inf"], ["outer_diameter", "finite"]),
    ("speed-nan", ["speed=nan"], ["speed", "finite"]),
    ("speed-1e999", ["speed=1e999 rpm"], ["speed", "finite"]),
    ("unbalance-huge", ["unbalances[0].amount=1e400 g*mm"], ["unbalances[0].amount", "finite"]),
    ("node-true", ["probes[0].node=true"], ["probes[0].node", "True"]),
    ("node-float", ["probes[0].node=2.0"], ["probes[0].node", "2.0"]),
    ("elements-float", ["shafts[0].sections[0].elements=4.5"], ["elements", "4.5"]),
    ("bearing-dup-name", ["bearings[1].name=B1"], ["bearings[1].name", "bearings[0].name", "B1"]),
    ("probe-angle-nan", ["probes[0].angle=nan"], ["probes[0].angle", "finite"]),
    ("set-deep", ["speed=" + "[" * 5000 + "]" * 5000], ["--set", "too deeply"]),
    ("set-bad-path", ["meshes[0]]x=1"], ["meshes[0]]x"]),
]


@pytest.mark.parametrize(
    "overrides, needles", [c[1:] for c in SET_CASES], ids=[c[0] for c in SET_CASES]
)
def test_bad_value_refused(small, overrides, needles):
    before = files_in(small.parent)
    args = ["modal", small]
    for o in overrides:
        args += ["--set", o]
    r, dt = run(*args)
    check_refused(r, dt, "small.toml", *needles)
    assert files_in(small.parent) == before


MESH_CASES = [
    ("mesh-k-zero", ["meshes[0].stiffness=0"], ["meshes[0].stiffness", "positive"]),
    ("mesh-k-negative", ["meshes[0].stiffness=-3e7 N/m"], ["meshes[0].stiffness", "positive"]),
    ("mesh-k-nan", ["meshes[0].stiffness=nan"], ["meshes[0].stiffness", "finite"]),
    ("helix-nan", ["meshes[0].helix_angle=nan"], ["meshes[0].helix_angle", "finite"]),
    ("teeth-float", ["meshes[0].gear.teeth=1e308"], ["meshes[0].gear.teeth", "1e+308"]),
    ("probe-dup-name", ["probes[1].name=gear1_x"], ["probes[1].name", "probes[0].name"]),
]


@pytest.mark.parametrize(
    "overrides, needles", [c[1:] for c in MESH_CASES], ids=[c[0] for c in MESH_CASES]
)
def test_bad_mesh_value_refused(overrides, needles):
    args = ["modal", UNITY]
    for o in overrides:
        args += ["--set", o]
    r, dt = run(*args)
    check_refused(r, dt, "unity_gearbox.toml", *needles)


def _unknown_keys(n: int) -> bytes:
    return (SMALL + "".join(f"\nkey{i} = {i}" for i in range(n))).encode()


# (id, file content, substrings)
FILE_CASES = [
    ("latin1-comment", SMALL.encode() + b"\n# caf\xe9\n", ["not UTF-8", "0xe9", "offset"]),
    ("utf16", SMALL.encode("utf-16"), ["not UTF-8", "UTF-16"]),
    ("random-bytes", bytes(range(128, 256)) * 8, ["not UTF-8", "offset 0"]),
    ("deep-array", b"a = " + b"[" * 50000 + b"]" * 50000, ["too deeply"]),
    ("deep-inline", b"a = " + b"{b = " * 40 + b"1" + b"}" * 40, ["too deeply"]),
    ("too-large", b"# " + b"x" * (MAX_BYTES + 10) + b"\n", ["larger than", "MiB"]),
    ("many-unknown-keys", _unknown_keys(5000), ["5000 unknown keys", "key0", "4990 more"]),
    ("bad-toml", SMALL.encode() + b"\nspeed = \n", ["invalid TOML"]),
    (
        "bom-then-nan",
        b"\xef\xbb\xbf" + SMALL.replace('"3000 rpm"', "nan").encode(),
        ["speed", "finite"],
    ),
]


@pytest.mark.parametrize(
    "content, needles", [c[1:] for c in FILE_CASES], ids=[c[0] for c in FILE_CASES]
)
def test_bad_file_refused(tmp_path, content, needles):
    path = tmp_path / "model.toml"
    path.write_bytes(content)
    r, dt = run("modal", path)
    check_refused(r, dt, "model.toml", *needles)
    assert "\n" not in r.stderr.strip()
    assert len(r.stderr) < 1000  # the many-keys case lists ten, not five thousand
    assert files_in(tmp_path) == {path}


def test_utf8_bom_is_read(tmp_path):
    path = tmp_path / "model.toml"
    path.write_bytes(b"\xef\xbb\xbf" + SMALL.encode())
    r, _ = run("modal", path, "--format", "json")
    assert r.exit_code == 0, r.output


def test_directory_as_model(tmp_path):
    r, dt = run("modal", tmp_path)
    check_refused(r, dt, str(tmp_path), "directory")


TABLE_COLUMNS = "speed_rpm,kxx,kxy,kyx,kyy,cxx,cxy,cyx,cyy"
TABLE_CASES = [
    ("empty", "t.csv", b"", ["empty"]),
    ("random", "t.csv", os.urandom(1) * 0 + bytes(range(200, 256)) * 20, ["not UTF-8"]),
    ("directory", "t.csv", None, ["directory"]),
    ("wrong-columns", "t.csv", b"a,b,c\n1,2,3\n", ["wrong columns", "a,b,c"]),
    ("header-only", "t.csv", TABLE_COLUMNS.encode() + b"\n", ["no rows"]),
    ("short-row", "t.csv", TABLE_COLUMNS.encode() + b"\n100,1,2\n", ["line 2", "100,1,2"]),
    ("text-value", "t.csv", TABLE_COLUMNS.encode() + b"\n100,x,0,0,1,1,0,0,1\n", ["line 2"]),
    (
        "nan-value",
        "t.csv",
        TABLE_COLUMNS.encode() + b"\n100,nan,0,0,1,1,0,0,1\n",
        ["kxx", "finite"],
    ),
    ("toml-columns", "t.toml", b"speed_rpm = [1.0]\n", ["missing", "kxx"]),
    (
        "toml-strings",
        "t.toml",
        ("\n".join(f'{c} = ["a"]' for c in TABLE_COLUMNS.split(","))).encode(),
        ["speed_rpm", "numbers"],
    ),
    ("suffix", "t.txt", b"1", ["unknown table format", ".txt"]),
    ("missing", "t.csv", False, ["not found"]),
]


@pytest.mark.parametrize(
    "name, content, needles", [c[1:] for c in TABLE_CASES], ids=[c[0] for c in TABLE_CASES]
)
def test_bad_table_file_refused(small, name, content, needles):
    table = small.parent / name
    if content is None:
        table.mkdir()
    elif content is not False:
        table.write_bytes(content)
    text = small.read_text().replace('k = "1e7 N/m"\nc = "1e3 N*s/m"', f'table_file = "{name}"', 1)
    small.write_text(text)
    before = files_in(small.parent)
    r, dt = run("modal", small)
    check_refused(r, dt, "small.toml", "bearings[0].table_file", name, *needles)
    assert files_in(small.parent) == before


EX = Path(__file__).resolve().parents[2] / "examples"
WRONG_KIND = [
    ("study-as-model", ["modal", EX / "unity_gearbox_study.toml"], ["a study file, not a rotor"]),
    ("bearing-as-model", ["modal", EX / "bearings" / "plain_ld1.toml"], ["a bearing file, not"]),
    ("model-as-study", ["study", "status", UNITY], ["rotor model file, not a study file"]),
]


@pytest.mark.parametrize(
    "args, needles", [c[1:] for c in WRONG_KIND], ids=[c[0] for c in WRONG_KIND]
)
def test_wrong_kind_of_file_named(args, needles):
    r, dt = run(*args)
    check_refused(r, dt, *needles)


def test_many_errors_one_line(small):
    """Several problems are one line (the README: errors are one line), at most ten listed."""
    text = small.read_text().replace('k = "1e7 N/m"', 'k = "nan"').replace("node = 2", "node = -1")
    small.write_text(text)
    r, dt = run("modal", small)
    check_refused(r, dt, "small.toml", "errors in the model", "bearings[0].k", "node")
