"""Models for the transient tests: the SPEC 6.1 gearbox and a coarse copy of it."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from gearrotor.io.model_file import apply_overrides, model_from_dict

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "unity_gearbox.toml"


def gearbox(overrides: dict | None = None, *, elements: int = 20):
    """The unity-ratio gearbox (SPEC 6.1), optionally with ``elements`` per shaft (even)."""
    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    if elements != 20:
        mid = elements // 2
        for s in data["shafts"]:
            s["sections"][0]["elements"] = elements
        for b in data["bearings"]:
            b["node"] = 0 if b["node"] == 0 else elements
        for group in ("unbalances", "probes"):
            for it in data[group]:
                it["node"] = mid
        for m in data["meshes"]:
            m["gear"]["node"] = mid
            m["mate"]["node"] = mid
    return model_from_dict(apply_overrides(data, overrides))


@pytest.fixture(scope="session")
def make_gearbox():
    return gearbox
