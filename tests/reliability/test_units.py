"""Unit expressions (issue 17): what pint reads is still read, to the same value; what would
compute without bound (power towers, huge exponents, very long expressions) or is not a finite
number is refused with a ValueError that says why, at once."""

from __future__ import annotations

import math
import time

import pytest

from gearrotor.units import registry, to_si

# (text, kind, SI unit pint converts to): the forms the examples and docs use, and pint's own
ACCEPTED = [
    ("6500 rpm", "angular_speed", "rad/s"),
    ("6500rpm", "angular_speed", "rad/s"),
    ("720 g*mm", "unbalance", "kg*m"),
    ("0.5 kg*m^2", "inertia", "kg*m^2"),
    ("0.5 kg·m²", "inertia", "kg*m^2"),
    ("5 kg m**2", "inertia", "kg*m^2"),
    ("2 N⋅m", "torque", "N*m"),
    ("1.75e4 N*s/m", "damping", "N*s/m"),
    ("2.1*10**11 Pa", "modulus", "Pa"),
    ("211 GPa", "modulus", "Pa"),
    ("7890 kg/m³", "density", "kg/m^3"),
    ("-3e6 N/m", "stiffness", "N/m"),
    ("1,000 N", "force", "N"),
    ("3 µm", "length", "m"),
    ("2 in", "length", "m"),
    ("20 deg", "angle", "rad"),
    ("10 1/min", "rate", "1/s"),
    ("(2+3) m", "length", "m"),
    ("13.8 kV", "voltage", "V"),
]


@pytest.mark.parametrize("text, kind, unit", ACCEPTED, ids=[a[0] for a in ACCEPTED])
def test_pint_forms_still_read(text, kind, unit):
    expected = registry().Quantity(text.replace("rpm", " rpm")).to(unit).magnitude
    assert to_si(text, kind) == pytest.approx(expected, rel=1e-15)


REFUSED = [
    ("10**10**10 Pa", "power"),
    ("10^10^10 Pa", "power"),
    ("(10**10)**10 Pa", "power"),
    ("10**(10**10) Pa", "power"),
    ("9**99999 Pa", "64"),
    ("10⁹⁹⁹⁹⁹⁹⁹⁹⁹ Pa", "64"),
    ("2**x Pa", "exponents"),
    ("1e999 Pa", "finite"),
    ("1e300*1e300 Pa", "finite"),
    ("nan Pa", "finite"),
    ("1" + "*1" * 150 + " Pa", "characters"),
    ("1" + "*1" * 60 + " Pa", "operators"),
    ("m @ 3", "unexpected character"),
]


@pytest.mark.parametrize("text, why", REFUSED, ids=[r[0][:30] for r in REFUSED])
def test_unbounded_or_non_finite_refused_at_once(text, why):
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=why):
        to_si(text, "modulus" if "Pa" in text else "length")
    assert time.perf_counter() - t0 < 0.5  # before: hours and gigabytes for a power tower


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, 10**400])
def test_non_finite_numbers_refused(value):
    with pytest.raises(ValueError, match="finite"):
        to_si(value, "stiffness")


def test_registry_is_built_on_first_use():
    import subprocess
    import sys

    code = "import gearrotor.units, sys; print('pint' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# ---- pint's cache of its parsed definitions (units.registry) ---------------------------------
_CONVERT = (
    "import sys\n"
    "from gearrotor.units import to_si\n"
    "cases = [l.split('|') for l in sys.argv[1:]]\n"
    "print(' '.join(repr(to_si(t, k)) for t, k in cases))\n"
)


def test_registry_cache_reads_the_same_and_survives_damage(tmp_path):
    """pint's parsed definitions are kept in ``<user cache>/gearrotor/pint`` (the registry
    builds in ~0.05 s instead of ~0.5 s): a process that builds the registry from them converts
    every accepted form to the same float, bit for bit, as the process that wrote them; a
    damaged entry (each pickle cut in half, as a killed writer would leave it) and a cache
    folder that cannot be created are not errors: the registry is built without them."""
    import os
    import subprocess
    import sys

    cases = [f"{text}|{kind}" for text, kind, _ in ACCEPTED]

    def convert(xdg) -> str:
        env = {**os.environ, "XDG_CACHE_HOME": str(xdg)}
        r = subprocess.run(
            [sys.executable, "-c", _CONVERT, *cases], env=env, capture_output=True, text=True
        )
        assert r.returncode == 0, r.stderr
        return r.stdout

    folder = tmp_path / "gearrotor" / "pint"
    first = convert(tmp_path)  # builds and writes the cache
    pickles = sorted(folder.glob("*.pickle"))
    assert pickles
    assert convert(tmp_path) == first  # read from the cache
    for p in pickles:
        p.write_bytes(p.read_bytes()[: p.stat().st_size // 2])
    assert convert(tmp_path) == first  # damaged: built without it
    assert not folder.exists()  # and removed
    assert convert(tmp_path) == first  # the next process writes it again
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    assert convert(blocked) == first  # <blocked>/gearrotor cannot be created
