"""docs/vehicle_track.md, "What the literature says about short wavelengths under braking": its
table of the metro wheel's growth in roughness units is the model's, the linear limit `R0 |ξ0|`
and the mean wear per e-fold are as stated, and the braking peak keeps its frequency while its
order falls with speed (the constant-frequency behaviour the section sets against the field)."""

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest
from helpers import doc_script

from railwear.longterm.vehicle_track import METRO
from railwear.scenario import build
from railwear.units import KM, kmh_to_m_s
from railwear.wear import EnergyLaw

DOC = Path(__file__).resolve().parents[2] / "docs" / "vehicle_track.md"
HEADER = "| duty | fastest order (wavelength) | rate per 10 000 km | dB per 10 000 km |"
PER_10000_KM = 1e4 * KM
DB = 20 / math.log(10)  # dB of amplitude per e-fold


def _doc_rows():
    """The section's table: label -> cells."""
    lines = DOC.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(HEADER))
    rows = {}
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        rows[cells[0]] = cells[1:]
    return rows


def _number(text):
    """The first number in ``text`` (thin spaces as thousands separators, ``e`` exponents)."""
    return float(re.search(r"[+-]?\d[\d ]*(?:\.\d+)?(?:e\d+)?", text).group().replace(" ", ""))


@pytest.fixture(scope="module")
def computed():
    """The four duties of docs/duty_cycles.py: fastest order (1-120), its rate per 10 000 km and
    the mean radial wear per 10 000 km (m)."""
    script = doc_script("duty_cycles.py")
    out = {}
    for label, operation in script.CASES.items():
        technique = build.fourier_technique(script.scenario(operation))
        rate = technique.rates(script.ORDERS).real / technique.speed * PER_10000_KM
        wear = -technique.mean_rate / technique.speed * PER_10000_KM
        i = int(np.argmax(rate))
        out[label] = (int(script.ORDERS[i]), float(rate[i]), wear)
    return out


def test_the_table_is_the_models(computed):
    rows = _doc_rows()
    labels = {"traction +0.05 at 70 km/h (built-in)": "traction +0.05 (built-in)",
              "braking -0.05 at 70 km/h": "braking −0.05",
              "metro line, motor wheel": "metro line, motor wheel",
              "metro line, trailer wheel": "metro line, trailer wheel"}
    assert set(rows) == set(labels.values())
    for label, (order, rate, wear) in computed.items():
        cells = rows[labels[label]]
        assert int(_number(cells[0])) == order
        wavelength_mm = np.pi * METRO.diameter / order * 1e3
        assert _number(cells[0].split("(")[1]) == pytest.approx(wavelength_mm, abs=0.5)
        assert _number(cells[1]) == pytest.approx(rate, abs=5e-4)
        assert _number(cells[2]) == pytest.approx(DB * rate, abs=0.05)
        assert _number(cells[3]) == pytest.approx(1e4 / rate, rel=0.01)  # km, three figures
        assert _number(cells[4]) * 1e-6 == pytest.approx(wear / rate, rel=0.02)  # two figures
        factor, decibels = cells[5].split(",")
        assert _number(factor.lstrip("×")) == pytest.approx(math.exp(10 * rate), rel=0.04)
        assert _number(decibels) == pytest.approx(10 * DB * rate, abs=0.5)


def test_linear_limit_and_wear_per_efold(computed):
    """`R0 |ξ0|` = 140 µm at ±0.05; the rolling-radius closed form gives an e-fold per
    `R0 |ξ0| / (2 (1 + ξ0))` = 70 µm of mean wear, the full rate (filter, rotation, load) per 90 µm."""
    wheel = dataclasses.replace(METRO, traction_coefficient=-0.05).wheel(kmh_to_m_s(70))
    xi0 = wheel.steady_creepage()
    assert xi0 < 0 and wheel.radius * abs(xi0) == pytest.approx(140e-6, abs=1e-6)
    closed_form = wheel.radius * abs(xi0) / (2 * (1 + xi0))
    assert closed_form == pytest.approx(70e-6, abs=0.5e-6)
    _, rate, wear = computed["braking -0.05 at 70 km/h"]
    assert wear / rate == pytest.approx(90e-6, abs=1e-6)
    assert 0.7 < closed_form / (wear / rate) < 0.85


def test_braking_peak_keeps_its_frequency():
    """Braking -0.05, orders 1-160: the fastest order falls 84, 55, 35 at 40, 70, 110 km/h (31-75
    mm) while its frequency stays in 350-410 Hz."""
    case = dataclasses.replace(METRO, traction_coefficient=-0.05)
    orders = np.arange(1, 161)
    fastest, frequency = [], []
    for kmh in (40.0, 70.0, 110.0):
        v = kmh_to_m_s(kmh)
        rate = case.fourier(v, EnergyLaw()).rates(orders).real
        n = int(orders[np.argmax(rate)])
        fastest.append(n)
        frequency.append(n * v / (np.pi * METRO.diameter))
    assert fastest == [84, 55, 35]
    assert all(350 < f < 410 for f in frequency)
    assert fastest[0] / fastest[-1] > 2.3 and max(frequency) / min(frequency) < 1.2
