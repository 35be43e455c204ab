"""Matplotlib figures. Each function returns the Figure and optionally saves it (PNG/SVG).

matplotlib is imported lazily with the non-interactive Agg backend, so importing gearrotor has
no plotting side effects.
"""

from .figures import plot_bode, plot_campbell, plot_mode_shapes, plot_orbits

__all__ = ["plot_bode", "plot_campbell", "plot_mode_shapes", "plot_orbits"]
