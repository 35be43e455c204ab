"""The model's [api_audit] table (model/audit.py): parsing with units, validation with the
field named, and level1_inputs (the table, overridden by arguments)."""

from __future__ import annotations

import json

import pytest

from audit_models import jeffcott_toml
from gearrotor.analyses import Site, Stage, level1_inputs
from gearrotor.errors import ModelError
from gearrotor.io import load_model, model_from_dict

TABLE = """
[api_audit]
edition = "8th"
at = [{ shaft = "s", node = "mid_span" }]
suction_density = "20 kg/m^3"
discharge_density = "30 kg/m^3"
exclude_bearings = ["B"]

[[api_audit.stages]]
shaft = "s"
node = 1
power = "1.5 MW"
diameter = "400 mm"
height = "25 mm"
density_ratio = 1.3
"""


@pytest.fixture
def model(tmp_path):
    p = tmp_path / "m.toml"
    p.write_text(jeffcott_toml(TABLE))
    return load_model(p)


def test_table_parses_with_units_and_round_trips(model):
    a = model.api_audit
    st = a.stages[0]
    assert (st.power, st.diameter, st.height, st.density_ratio) == (1.5e6, 0.4, 0.025, 1.3)
    assert a.density == 25.0  # (20 + 30) / 2
    again = type(model).model_validate_json(model.model_dump_json())
    assert again.api_audit == a
    kw = level1_inputs(model)
    assert kw["stages"] == (Stage("s", 1, 1.5e6, 0.4, 0.025, 1.3),)
    assert kw["qa"] is None and kw["average_density"] == 25.0
    assert kw["at"] == (Site("s", 2, 1.0),)  # mid-span of the 4-element span
    assert kw["exclude_bearings"] == ("B",)
    # arguments replace the table's values
    kw = level1_inputs(model, qa=1e6, at=[("s", 3)], average_density=40.0, exclude_bearings=[])
    assert kw["qa"] == 1e6 and kw["stages"] == () and kw["at"] == (Site("s", 3),)
    assert kw["average_density"] == 40.0 and kw["exclude_bearings"] == ()
    # stages given as arguments act at their own nodes, not at the table's sites
    st = Stage("s", 3, 1e6, 0.3, 0.02, 1.1)
    kw = level1_inputs(model, stages=[st])
    assert kw["stages"] == (st,) and kw["at"] == ()


def test_absent_table_is_not_serialised(model):
    bare = model.model_copy(update={"api_audit": None})
    assert "api_audit" not in json.loads(bare.model_dump_json())
    with pytest.raises(ModelError, match="api_audit"):
        level1_inputs(bare)


@pytest.mark.parametrize(
    "audit, match",
    [
        ({"qa": "1e6 N/m", "at": [{"shaft": "s", "node": 9}]}, r"api_audit.at\[0\].node"),
        ({"qa": "1e6 N/m", "at": [{"shaft": "t", "node": 1}]}, r"api_audit.at\[0\].shaft"),
        ({"qa": "1e6 N/m"}, "needs 'at'"),
        ({"qa": "-1e6 N/m", "at": [{"shaft": "s", "node": 1}]}, "api_audit.qa"),
        ({"at": [{"shaft": "s", "node": 1}]}, "either as qa"),
        (
            {
                "stages": [
                    {
                        "shaft": "s",
                        "node": 1,
                        "power": 1e6,
                        "diameter": 0.4,
                        "height": 0.02,
                        "density_ratio": -1.3,
                    }
                ]
            },
            r"api_audit.stages\[0\].density_ratio",
        ),
        (
            {"stages": [{"shaft": "s", "node": 7, "power": 1e6, "diameter": 0.4, "height": 0.02}]},
            r"api_audit.stages\[0\].node",
        ),
        (
            {"qa": 1e6, "at": [{"shaft": "s", "node": 1}], "edition": "7th"},
            "api_audit.edition",
        ),
        (
            {"qa": 1e6, "at": [{"shaft": "s", "node": 1}], "suction_density": 2.0},
            "discharge_density",
        ),
        (
            {"qa": 1e6, "at": [{"shaft": "s", "node": 1}], "exclude_bearings": ["seal"]},
            r"api_audit.exclude_bearings\[0\]",
        ),
    ],
)
def test_bad_tables_name_the_field(model, audit, match):
    base = json.loads(model.model_dump_json())
    with pytest.raises(ModelError, match=match):
        model_from_dict(base | {"api_audit": audit})


SEAL = """
[[seals]]
name = "balance piston"
shaft = "s"
node = 2
kxx = "-2e5 N/m"
kyy = "-2e5 N/m"
kxy = "3e5 N/m"
kyx = "-3e5 N/m"
c = "200 N*s/m"

[api_audit]
edition = "9th"
qa = "1e4 N/m"
at = [{ shaft = "s", node = 2 }]
exclude_bearings = ["balance piston"]   # docs/model_format.md's own example: a seal's name
"""


def test_a_seal_name_can_be_excluded_and_the_edition_is_picked(tmp_path):
    """docs/model_format.md's [api_audit] example excludes "balance piston", which its own
    [[seals]] example names: the name is accepted (seals are always left out of Level I, like
    the cross-coupling destabilisers) and reported as excluded; edition "9th" reaches the
    result."""
    from gearrotor.analyses import stability_audit

    p = tmp_path / "m.toml"
    p.write_text(jeffcott_toml(SEAL))
    model = load_model(p)
    kw = level1_inputs(model)
    assert kw["exclude_bearings"] == ("balance piston",) and kw["edition"] == "9th"
    res = stability_audit(model, n_curve=0)
    assert res.level1.excluded["seals"] == ["balance piston"]
    assert res.level1.excluded["bearings"] == []
    assert res.level1.edition == "API 617 9th edition (2022)"
    assert res.level2.edition == res.level1.edition
    d = res.to_dict()
    assert d["edition"] == "API 617 9th edition (2022)" and d["edition_key"] == "9th"
    # the argument overrides the table
    assert stability_audit(model, n_curve=0, edition="8").level1.edition_key == "8th"
    assert "9th edition" in res.table()
