import pytest


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the pyplot figures a test opened (they pile up in an xdist worker, and the 21st
    open figure is a RuntimeWarning, an error in this suite, in whichever test comes next)."""
    yield
    import sys

    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")
