import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


@pytest.fixture(scope="session")
def examples() -> Path:
    return EXAMPLES


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the pyplot figures a test leaves open: figure functions return their figure for the
    test to inspect, and with ``filterwarnings = error`` matplotlib's warning at more than 20
    open figures would fail whichever later test in the same worker opens the 21st."""
    yield
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close("all")
