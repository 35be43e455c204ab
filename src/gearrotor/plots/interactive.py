"""Interactive (plotly) figures of the HTML report, importable from here as before; each lives in
the report section that shows it (:mod:`gearrotor.plots.report.sections`).

Every function takes an analysis result and returns a ``plotly.graph_objects.Figure``; nothing is
shown or written. plotly is imported inside the functions, so importing this module needs
nothing beyond numpy. Units on the axes: speeds in rpm, frequencies in cpm, amplitudes in µm
zero-to-peak, power in W.

* :func:`mode_shape_figure` (modes section);
* :func:`campbell_figure` (Campbell), :func:`bode_figure`, :func:`orbit_figure` (unbalance);
* :func:`bearing_coefficient_figure`: tabulated (fluid-film) bearing coefficients against speed;
* :func:`transient_spectrum_figure`, :func:`waterfall_figure`, :func:`whirl_power_figure`: a saved
  transient result (the ``xarray.Dataset`` of ``gearrotor.analyses.transient.load_result``);
  :func:`speed_waterfall_figure`: the waterfall against speed of a run-up or coast-down
  (:func:`gearrotor.plots.waterfall.speed_waterfall`) with the shaft-order lines.
"""

from .report.sections.bearings import bearing_coefficient_figure
from .report.sections.campbell import campbell_figure
from .report.sections.modes import mode_shape_figure
from .report.sections.transient import (
    speed_waterfall_figure,
    transient_spectrum_figure,
    waterfall_data,
    waterfall_figure,
    whirl_power_figure,
)
from .report.sections.unbalance import bode_figure, orbit_figure

__all__ = [
    "bearing_coefficient_figure",
    "bode_figure",
    "campbell_figure",
    "mode_shape_figure",
    "orbit_figure",
    "speed_waterfall_figure",
    "transient_spectrum_figure",
    "waterfall_figure",
    "whirl_power_figure",
    "waterfall_data",
]
