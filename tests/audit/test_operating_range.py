"""The model's operating range (operating_speed_range, max_continuous_speed): parsing,
validation, serialisation, and its use by the unbalance response and the API 617 unbalance."""

import json

import numpy as np
import pytest

from gearrotor.analyses import model_operating_range, unbalance_response
from gearrotor.analyses.audit.api_unbalance import api617_basis, api617_unbalances
from gearrotor.errors import ModelError
from gearrotor.io import load_model, model_from_dict
from helpers import single_shaft

RPM = np.pi / 30


def rotor(**extra):
    return single_shaft(
        length=1.0,
        diameter=0.05,
        elements=6,
        bearings=[{"node": 0, "k": 2e6, "c": 300.0}, {"node": 6, "k": 2e6, "c": 300.0}],
        speed=3000 * RPM,
        unbalances=[{"shaft": "s", "node": 3, "amount": 1e-4}],
        probes=[{"name": "mid", "shaft": "s", "node": 3}],
        **extra,
    )


def test_fields_parse_with_units_and_round_trip(examples):
    t = load_model(
        examples / "steam_turbine_gearbox.toml",
        {"operating_speed_range": ["9000 rpm", "10800 rpm"], "max_continuous_speed": "11340 rpm"},
    )
    assert t.operating_speed_range == pytest.approx((9000 * RPM, 10800 * RPM))
    assert t.max_continuous_speed == pytest.approx(11340 * RPM)
    again = type(t).model_validate_json(t.model_dump_json())
    assert again.operating_speed_range == t.operating_speed_range
    assert model_operating_range(t) == pytest.approx((9000 * RPM, 11340 * RPM))


def test_models_without_the_fields_serialise_as_before(examples):
    """Study case keys and transient checkpoint fingerprints hash the model JSON: a model
    without an operating range must not gain keys."""
    t = load_model(examples / "unity_gearbox.toml")
    d = json.loads(t.model_dump_json())
    assert "operating_speed_range" not in d and "max_continuous_speed" not in d
    assert "api_audit" not in d
    assert model_operating_range(t) is None


@pytest.mark.parametrize(
    "fields, match",
    [
        ({"operating_speed_range": ["11000 rpm", "9000 rpm"]}, "operating_speed_range"),
        ({"operating_speed_range": ["-9000 rpm", "9000 rpm"]}, "operating_speed_range"),
        ({"max_continuous_speed": "0 rpm"}, "max_continuous_speed"),
        (
            {
                "operating_speed_range": ["9000 rpm", "12000 rpm"],
                "max_continuous_speed": "11000 rpm",
            },
            "exceeds max_continuous_speed",
        ),
        ({"operating_speed_range": ["9000 m", "10000 rpm"]}, "operating_speed_range"),
    ],
)
def test_bad_ranges_are_named(fields, match):
    base = json.loads(rotor().model_dump_json())
    with pytest.raises(ModelError, match=match):
        model_from_dict(base | fields)


def test_unbalance_response_takes_the_models_range():
    speeds = np.linspace(500, 6000, 12) * RPM
    plain = unbalance_response(rotor(), speeds=speeds)
    assert plain.operating_range == (3000 * RPM, 3000 * RPM)  # unchanged without the fields
    ranged = rotor(operating_speed_range=["2500 rpm", "3000 rpm"], max_continuous_speed="3150 rpm")
    res = unbalance_response(ranged, speeds=speeds)
    assert res.operating_range == pytest.approx((2500 * RPM, 3150 * RPM))
    # the API 617 limit is evaluated at the MCS: 25.4 µm √(12000 / 3150), capped at 25.4 µm
    assert res.vibration_limit[0] == pytest.approx(25.4e-6)
    explicit = unbalance_response(ranged, speeds=speeds, operating_range=(1.0, 2.0))
    assert explicit.operating_range == (1.0, 2.0)  # the caller's range wins


def test_api617_unbalance_defaults_to_the_models_mcs():
    t = rotor(max_continuous_speed="3150 rpm")
    assert api617_basis(t) == api617_basis(t, 3150 * RPM)
    assert [u.amount for u in api617_unbalances(t)] == [
        u.amount for u in api617_unbalances(t, 3150 * RPM)
    ]
    with pytest.raises(ModelError, match="max_continuous_speed"):
        api617_unbalances(rotor())
