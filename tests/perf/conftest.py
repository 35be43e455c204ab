"""Models for the performance tests: the transient tests' SPEC 6.1 gearbox."""

from __future__ import annotations

import pytest

from transient.conftest import gearbox


@pytest.fixture(scope="session")
def make_gearbox():
    return gearbox
