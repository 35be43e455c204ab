"""Study files: schema, case expansion, keys, input errors (no analysis runs)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from gearrotor.cli.study import study_app
from gearrotor.errors import ModelError
from gearrotor.studies import load_study, plan

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
MODEL = (EXAMPLES / "unity_gearbox.toml").as_posix()

BASE = f"""
name = "t"
model = "{MODEL}"

[parameters]
unbalance = {{ paths = ["unbalances[0].amount", "unbalances[1].amount"], unit = "g*mm" }}
ka = {{ path = "meshes[0].variation.ka_ratio" }}

[cases]
columns = ["unbalance", "ka"]
rows = [[360, 0.0], [720, 0.2]]

[analysis]
type = "transient"
t_end = "0.1 s"
"""


def write(tmp_path: Path, text: str, name: str = "study.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_spec_matrix_example():
    """examples/unity_gearbox_study.toml is SPEC 6.1's 27-row matrix; rows 16 and 20 of the
    SPEC are identical and share one key."""
    st = load_study(EXAMPLES / "unity_gearbox_study.toml")
    assert len(st.cases) == 27
    assert st.cases[0].values == {
        "unbalance": 360,
        "ka_ratio": 0,
        "contact_ratio": 0,
        "backlash": 0,
        "terms": 0,
    }
    # contact ratio 0 (SPEC: no variation) leaves the base model's value
    assert "meshes[0].variation.contact_ratio" not in st.cases[0].overrides
    assert st.cases[17].overrides["meshes[0].variation.ka_ratio"] == 0.75
    assert st.cases[17].overrides["meshes[0].backlash.value"] == "0.0254 mm"
    assert st.cases[21].overrides["unbalances[1].amount"] == "1440 g*mm"
    keys = [p.key for p in plan(st)]
    assert all(p.error is None for p in plan(st))
    assert keys[15] == keys[19]
    assert len(set(keys)) == 26
    assert st.analysis.t_end == 3.0 and st.analysis.integrator == "modal-rk4"
    assert st.folder == (EXAMPLES / "unity_gearbox_study.study").resolve()


def test_product_expansion_and_keys(tmp_path):
    text = BASE.replace(
        'columns = ["unbalance", "ka"]\nrows = [[360, 0.0], [720, 0.2]]',
        "product = { unbalance = [360, 720], ka = [0.0, 0.1, 0.2] }",
    )
    st = load_study(write(tmp_path, text))
    assert [c.values for c in st.cases][:4] == [
        {"unbalance": 360, "ka": 0.0},
        {"unbalance": 360, "ka": 0.1},
        {"unbalance": 360, "ka": 0.2},
        {"unbalance": 720, "ka": 0.0},
    ]
    keys = [p.key for p in plan(st)]
    assert len(set(keys)) == 6
    # the key depends on the resolved model and the analysis settings, nothing else
    st2 = load_study(write(tmp_path, text.replace("0.1 s", "0.2 s"), "b.toml"))
    assert not set(keys) & {p.key for p in plan(st2)}
    st3 = load_study(write(tmp_path, text.replace('name = "t"', 'name = "u"'), "c.toml"))
    assert keys == [p.key for p in plan(st3)]


@pytest.mark.parametrize(
    ("old", "new", "needles"),
    [
        (
            't_end = "0.1 s"',
            't_end = "0.1 s"\nintegrater = "rk4"',
            ["analysis.integrater", "unknown key"],
        ),
        (
            "rows = [[360, 0.0], [720, 0.2]]",
            "rows = [[360, 0.0], [720]]",
            ["cases.rows[1]", "[720]", "2 values"],
        ),
        (
            'columns = ["unbalance", "ka"]',
            'columns = ["unbalance", "kb"]',
            ["cases.columns[1]", "'kb'", "unknown parameter"],
        ),
        ("[720, 0.2]]", '["720 g*mm", 0.2]]', ["cases.rows[1][0]", "720 g*mm", "a number in g*mm"]),
        ('t_end = "0.1 s"', 't_end = "0.1 s"\nintegrator = "rk4"', ["needs 'dt'"]),
        (
            't_end = "0.1 s"',
            't_end = "0.1 s"\nintegrator_options = { tolerence = 0.1 }',
            ["analysis: unknown integrator_options", "tolerence", "'tolerance'"],
        ),
        ('t_end = "0.1 s"', 't_end = "0.1 kg"', ["analysis.t_end", "0.1 kg"]),
        (f'model = "{MODEL}"', 'model = "nope.toml"', ["model", "nope.toml", "not found"]),
        (
            "ka = {",
            'probe = { path = "speed" }\nka = {',
            ["parameters.probe", "unusable parameter name"],
        ),
        ('type = "transient"', 'type = "static"', ["analysis", "static"]),
    ],
)
def test_input_errors_name_file_field_value(tmp_path, old, new, needles):
    assert old in BASE
    path = write(tmp_path, BASE.replace(old, new))
    with pytest.raises(ModelError) as err:
        load_study(path)
    text = str(err.value)
    assert str(path.resolve()) in text or str(path) in text
    for n in needles:
        assert n in text, text


def test_bad_override_value_is_a_case_error(tmp_path):
    """An invalid value fails its case (with the model's message), not the study."""
    st = load_study(write(tmp_path, BASE.replace("[720, 0.2]]", "[720, -0.5]]")))
    p = plan(st)
    assert p[0].error is None
    assert "meshes[0].variation.ka_ratio" in p[1].error and "-0.5" in p[1].error


def test_cli_input_error_exit_2(tmp_path):
    path = write(tmp_path, BASE.replace("[parameters]", "colour = 1\n[parameters]"))
    res = CliRunner().invoke(study_app, ["status", str(path)])
    assert res.exit_code == 2
    assert "colour" in res.stderr and "unknown key" in res.stderr


def test_cli_status_lists_pending(tmp_path):
    path = write(tmp_path, BASE)
    res = CliRunner().invoke(study_app, ["status", str(path)])
    assert res.exit_code == 0, res.output
    assert "2 cases, 0 done, 0 failed, 2 pending" in res.stdout
    assert "unbalance=720 g*mm, ka=0.2" in res.stdout
