"""THD bearings against published measurements: the 4-pad tilting-pad rig of Fillon, Bligoud &
Frêne (1992), with the published THD/TEHD models of the same rig as the yardstick.

Sources
-------
.. [F92] Fillon, M., Bligoud, J.-C. & Frêne, J. (1992). Experimental study of tilting-pad
   journal bearings — comparison with theoretical thermoelastohydrodynamic results. ASME
   Journal of Tribology 114(3), 579–588. Four pads, load between pads, D = 100 mm,
   L = 70 mm, 75° pads, pivot offset 0.5, preload 0.47 on a 148 µm pad clearance (assembled
   clearance 78.4 µm), ISO VG 32 (0.0277 Pa·s at 40 °C, β = 0.0341 1/K, 860 kg/m³,
   1951.8 J/(kg·K), 0.149 W/(m·K)) supplied at 40 °C.
.. [KPG94] Kim, J., Palazzolo, A. & Gadangi, R. (1994). TEHD analysis for tilting-pad journal
   bearings using upwind finite element method. Tribology Transactions 37(4), 771–783:
   Table 3 (the rig's data) and Fig. 20 (the measured maximum pad temperature of [F92] at
   10 kN against speed, and [F92]'s own TEHD prediction); Gadangi, R. & Palazzolo, A. (1995),
   ASME J. Tribol. 117(2), Table 1.

The numbers are taken as transcribed by ROSS 3.1 (``ross/tests/test_fluid_film_literature.py``,
github.com/petrobras/ross commit 631a249a, shipped in ross-rotordynamics 3.1.0): geometry and
oil from [KPG94] Table 3 / Gadangi & Palazzolo Table 1, the temperatures digitized from
[KPG94] Fig. 20 (±1 °C). The primary papers were not available here; no eccentricity, flow or
power measurement of this rig could be obtained (Ferron, Frêne & Boncompain's 1983 plain
bearing and Daniel & Cavalca's 2013 steam-turbine pads were searched for, without numbers).

Maximum pad temperature at 10 kN (°C)::

    rpm                         1000   2000   3000   4000
    measured [F92]              49.5   59.5   67.5   76.5
    [F92] TEHD                  43.7   53.4   63.2   72.9
    ROSS 3.1 "full" (run here)  45.07  53.68  61.67  68.54

ROSS 3.1 runs (``TiltingPad``, the inputs of its Fillon benchmark: ``hot_oil_lambda = 1``,
pad conductivity 50 W/(m·K), pad-back convection 735.9 W/(m²·K) (its default), edge convection
73.59 W/(m²·K), 24 × 10 film elements, 10 through the pad, rigid pads; ``/work/ross-venv``):

* ``thermal_type="adiabatic"`` (a 2-D film, temperature uniform across it, as this package's
  adiabatic THD): 1000 rpm ε 0.9837, T_max 65.21 °C; 4000 rpm ε 0.6687, T_max 70.71 °C.
* ``thermal_type="full"`` (film and pad solved across the film, journal at the averaged film
  temperature): ε 0.9332, 0.7879, 0.7119, 0.6651; journal 42.74 °C (1000 rpm), 54.91 °C
  (4000 rpm); at 4000 rpm power 2084.8 W and pad outlet temperatures, flow-weighted
  (``temp_out_let_bulk``) 51.77, 53.13, 61.20, 61.66 °C and area means over the trailing edge
  (``temp_out_let``) 51.59, 53.15, 63.28, 63.88 °C (pads at 45°, 135°, 225°, 315°; the last two
  loaded; rerun here, T_max 68.54 °C as before).

Tolerances
----------
* The adiabatic film, one layer (uniform across the film), against ROSS's adiabatic film (one
  model class, two discretisations): T_max within 2.5 K, ε within 0.03 (measured +1.0/+1.2 K,
  +0.009/+0.014).
* With heat to the pads and the journal (``examples/bearings/tilting_4pad_thd.toml``, its
  inputs ROSS's benchmark's, not fitted here) against the measurement: within 9 K, the
  largest deviation of a published conduction model from these points (ROSS 3.1 full: 8.0 K
  at 4000 rpm; [F92]'s TEHD: 6.1 K at 2000 rpm) plus the ±1 K digitization (measured −1.3,
  −3.6, −5.0, −8.3 K, the film resolved across by 8 layers; the developed-profile model it
  replaced: −1.1, −3.4, −4.6, −8.0 K). Against [F92]'s TEHD within 6 K and ROSS 3.1 full
  within 5 K (measured +4.5…−4.7 K and +3.1…−0.4 K). All under-predict at 4000 rpm: rigid
  pads do not carry the pads' thermal crowning, which [F92]'s TEHD adds (−3.6 K).
* The measured rise from 1000 to 4000 rpm (27 K) within 30 % (ROSS full −13 %, TEHD +8 %,
  here −26 %: 20.0 K): the adiabatic film gives a fifth of it (+5.7 K; ROSS adiabatic +5.5 K), since
  at constant load its temperature rise hardly depends on speed; at 1000 rpm the pads and
  journal carry most of the heat.
* Eccentricity against ROSS 3.1 full within 0.04 (measured +0.028, +0.024, +0.012, −0.001):
  the adiabatic films agree to 0.014; the rest is the heat paths (ROSS conducts through the
  pad in 2-D and fixes the journal at the averaged film temperature, 3.3 K cooler than the
  journal here at 1000 rpm, so its film is more viscous where the load is carried).
* Bulk quantities against ROSS 3.1 full at 4000 rpm: pad outlet temperatures within 1.5 K,
  flow-weighted (measured −1.1…−0.2 K) and area means across the trailing edge (−1.0…−0.1 K),
  power 6 % (+4.0 %), journal 3.5 K (−0.6 K: ROSS sets the journal at the averaged film
  temperature, here it takes no net heat).
"""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gearrotor.bearings import equilibrium, load_bearing
from gearrotor.bearings.lubricant import CELSIUS

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "bearings"
RPM = (1000, 2000, 3000, 4000)
MEASURED = (49.5, 59.5, 67.5, 76.5)  # °C, [F92] via [KPG94] Fig. 20
TEHD = (43.7, 53.4, 63.2, 72.9)  # °C, [F92]'s own TEHD, same figure
ROSS_FULL = (45.069, 53.677, 61.672, 68.543)  # °C, ROSS 3.1 thermal_type="full"
ROSS_FULL_ECC = (0.9332, 0.7879, 0.7119, 0.6651)  # ROSS 3.1 thermal_type="full"
# ROSS 3.1 thermal_type="adiabatic": rpm → (ε, T_max °C)
ROSS_ADIABATIC = {1000: (0.98371, 65.211), 4000: (0.66874, 70.712)}
# ROSS 3.1 "full" at 4000 rpm: power W, journal °C, pad outlet °C: flow-weighted
# (``temp_out_let_bulk``) and area mean over the trailing edge (``temp_out_let``)
ROSS_FULL_4000 = (
    2084.84,
    54.906,
    (51.765, 53.129, 61.196, 61.661),
    (51.592, 53.150, 63.278, 63.877),
)


def _solve(case, rpm, thermal=None):
    opts = case.options if thermal is None else replace(case.options, thermal=thermal)
    return equilibrium(case.bearing, case.loads[0], rpm * math.pi / 30, options=opts)


@pytest.fixture(scope="module")
def rig():
    case = load_bearing(EXAMPLES / "tilting_4pad_thd.toml")
    return case, {rpm: _solve(case, rpm) for rpm in RPM}


def test_adiabatic_film_matches_ross_adiabatic_on_the_fillon_rig(rig):
    """The adiabatic THD film (no heat to pads or journal) on the same inputs as ROSS 3.1's
    adiabatic film: T_max within 2.5 K, ε within 0.03, and the same near-flat speed
    dependence (module docstring)."""
    case, _ = rig
    adiabatic = replace(
        case.options.thermal, pad_heat_transfer=0.0, journal_heat_transfer=0.0, cross_film_layers=1
    )
    t = {}
    for rpm, (ecc, t_max) in ROSS_ADIABATIC.items():
        eq = _solve(case, rpm, adiabatic)
        t[rpm] = eq.thermal.max_temperature - CELSIUS
        assert t[rpm] == pytest.approx(t_max, abs=2.5)
        assert eq.eccentricity_ratio == pytest.approx(ecc, abs=0.03)
    rise, ross_rise = t[4000] - t[1000], ROSS_ADIABATIC[4000][1] - ROSS_ADIABATIC[1000][1]
    assert rise == pytest.approx(ross_rise, abs=2.0)
    assert rise < 0.3 * (MEASURED[-1] - MEASURED[0])


@pytest.mark.parametrize("k", range(len(RPM)), ids=[f"{r} rpm" for r in RPM])
def test_pad_temperature_matches_the_measurement_and_the_published_models(rig, k):
    """Heat to the pads and the journal: the hottest pad surface within 9 K of the measured
    maximum pad temperature, 6 K of [F92]'s TEHD and 5 K of ROSS 3.1 full; the eccentricity
    within 0.04 of ROSS 3.1 full (module docstring)."""
    _, eqs = rig
    eq = eqs[RPM[k]]
    assert eq.eccentricity_ratio == pytest.approx(ROSS_FULL_ECC[k], abs=0.04)
    t_max = eq.thermal.max_temperature - CELSIUS
    assert t_max == pytest.approx(MEASURED[k], abs=9.0)
    assert t_max == pytest.approx(TEHD[k], abs=6.0)
    assert t_max == pytest.approx(ROSS_FULL[k], abs=5.0)


def test_speed_sensitivity_of_the_pad_temperature(rig):
    """The rise of the hottest pad temperature from 1000 to 4000 rpm within 30 % of the
    measured 27 K (measured −26 %); every speed step a rise."""
    _, eqs = rig
    t = [eqs[r].thermal.max_temperature - CELSIUS for r in RPM]
    assert all(b > a for a, b in zip(t, t[1:], strict=False))
    assert t[-1] - t[0] == pytest.approx(MEASURED[-1] - MEASURED[0], rel=0.30)


def test_bulk_temperatures_and_power_match_ross_full_at_4000_rpm(rig):
    """Pad outlet temperatures within 1.5 K of ROSS 3.1 full, both the flow-weighted
    (mixing-cup) one and the area mean across the trailing edge (the loaded pads' differ by
    2 K: the journal side of the film, cooler, carries most of the flow); power loss 6 %,
    journal 3.5 K: the films agree; the hottest-surface difference to the measurement is not
    the bulk's."""
    _, eqs = rig
    th = eqs[4000].thermal
    power, t_j, t_bulk, t_area = ROSS_FULL_4000
    assert th.power_loss == pytest.approx(power, rel=0.06)
    assert th.journal_temperature - CELSIUS == pytest.approx(t_j, abs=3.5)
    for p, bulk, area in zip(th.pads, t_bulk, t_area, strict=True):
        assert p.outlet_temperature - CELSIUS == pytest.approx(bulk, abs=1.5)
        trailing = p.layer_temperature[-1].mean(axis=1)  # mean across the film, per z node
        mean = np.trapezoid(trailing) / (len(trailing) - 1)  # the half bearing
        assert mean - CELSIUS == pytest.approx(area, abs=1.5)
    assert abs(th.energy_residual) < 1e-9 * th.power_loss
