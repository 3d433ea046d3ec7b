"""Wear laws against hand-computed values."""

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.wear import Archard, EnergyLaw, InternalStateLaw, USFD


def test_energy_law():
    law = EnergyLaw(specific_wear=5.3e-9, density=7850.0)
    # 100 W for one second removes 5.3e-7 kg = 6.752e-11 m³
    assert law.volume_rate(100.0) == pytest.approx(5.3e-7 / 7850.0, rel=1e-15)


def test_archard():
    law = Archard(coefficient=1e-4, hardness=3e9)
    # 80 kN sliding at 0.03 m/s: 1e-4 * 8e4 * 0.03 / 3e9
    assert law.volume_rate(80e3, -0.03) == pytest.approx(8e-11, rel=1e-15)


@pytest.mark.parametrize("x, continuous, as_printed", [
    (0.0, 0.0, 0.0), (5.0, 26.5, 26.5), (10.3, 5.3 * 10.3, 5.3 * 10.3), (10.39, 55.0, 5.3 * 10.39),
    (10.4, 55.0, 55.0),
    (50.0, 55.0, 55.0), (77.2, 55.0, 55.0), (77.5, 55.0, 61.9 * 77.5 - 4778.7),
    (78.0, 55.0, 61.9 * 78.0 - 4778.7), (100.0, 1411.3, 1411.3),
])
def test_usfd_breakpoints_and_conventions(x, continuous, as_printed):
    assert USFD().rate(x) == pytest.approx(continuous, abs=1e-9)
    assert USFD(convention="as_printed").rate(x) == pytest.approx(as_printed, abs=1e-9)


def test_usfd_continuous_is_monotone_and_meets_the_severe_branch():
    x = np.linspace(0, 200, 200001)
    k = USFD().rate(x)
    steps = np.diff(k)
    assert np.all(steps >= 0)
    # continuous: no step larger than the steepest slope (61.9) times the sampling (0.001)
    assert np.max(steps) < 61.9 * 1e-3 * 1.0001
    assert np.min(np.diff(USFD(convention="as_printed").rate(x))) < -54.9
    crossing = (4778.7 + 55.0) / 61.9
    assert USFD().rate(crossing + 1e-6) > 55.0 and USFD().rate(crossing - 1e-3) == 55.0


def test_usfd_volume_units():
    """Tγ/A = 5 N/mm² on 40 mm² at 30 m/s: K = 26.5 µg/(m mm²) -> 1060 µg per metre."""
    area = 40e-6
    power = 5.0 * 40 * 30.0  # Tγ = 200 N
    rate = USFD().volume_rate(power, 30.0, area)
    assert rate == pytest.approx(26.5 * 40 * 1e-9 * 30.0 / 7850.0, rel=1e-12)


def test_internal_state_with_no_state_change_is_the_plain_law():
    law = EnergyLaw()
    plain = InternalStateLaw.energy(law)
    p = np.array([0.0, 1e5, 3e6])
    u, z = np.zeros(3), np.zeros(3)
    u1, z1 = plain.advance(0.0, 2.0, p, u, z)
    np.testing.assert_allclose(u1, -law.beta * p * 2.0, rtol=1e-15)
    assert np.all(z1 == 0)


def test_hardening_lowers_the_wear_rate():
    law = EnergyLaw()
    hard = InternalStateLaw.hardening(law, saturation=1.0, power_scale=1e6, time_constant=10.0)
    p = np.full(2, 1e6)
    u, z = np.zeros(2), np.zeros(2)
    for _ in range(2000):
        u, z = hard.advance(0.0, 0.1, p, u, z)
    # z -> saturation * p / (p + scale) = 0.5, and the wear coefficient to beta / 1.5
    np.testing.assert_allclose(z, 0.5, rtol=1e-6)
    rate, _ = hard.rates(0.0, p, u, z)
    np.testing.assert_allclose(rate, -law.beta * 1e6 / 1.5, rtol=1e-6)


@pytest.mark.parametrize("make", [lambda: EnergyLaw(specific_wear=-1), lambda: Archard(hardness=0),
                                  lambda: USFD(convention="smooth")])
def test_bad_parameters(make):
    with pytest.raises(ScenarioError):
        make()
