import numpy as np
import pytest

from railwear.pde import Cubic, DiskContact, dispersion, fastest_order, stability_map, unstable_band


@pytest.mark.parametrize("a, epsilon, nu", [(1.0, 0.01, 0.0), (1.0, 0.01, 0.05), (0.3, 1e-4, 1e-3)])
def test_band_and_fastest_mode_against_dense_search(a, epsilon, nu):
    k = np.linspace(0, 200, 2_000_001)
    sigma = dispersion(a, k, epsilon, nu)
    edge, fast = unstable_band(a, epsilon, nu)
    assert fast == pytest.approx(k[np.argmax(sigma)], abs=2e-4)
    assert dispersion(a, edge, epsilon, nu) == pytest.approx(0, abs=1e-9)
    n = np.arange(1, 200)
    assert fastest_order(a, epsilon, nu) == n[np.argmax(dispersion(a, n, epsilon, nu))]


def test_stable_and_unregularised_cases():
    assert unstable_band(-1.0, 0.01) == (0.0, 0.0)
    assert fastest_order(-1.0, 0.01) == 0
    assert unstable_band(1.0, 0.0) == (np.inf, np.inf)


def test_round_wheel_map_is_the_dispersion_relation():
    disk = DiskContact()
    speeds = np.array([20.0, 50.0])
    m = stability_map(disk, speeds, np.arange(1, 11), 1e-4, 1e-3)
    a = -disk.slope(np.zeros(2), speeds)
    np.testing.assert_allclose(m.growth_rate.values, dispersion(a[:, None], np.arange(1, 11), 1e-4, 1e-3))
    assert np.all(m.growth_rate.values < 0)


def test_crest_map_of_cubic():
    """For h = c1 s + c3 s³ the slope at the crest of A cos(n x) is c1 + 3 c3 A² n⁴."""
    h = Cubic(c1=0.01, c3=-50.0)
    A, orders = 1e-3, np.arange(1, 6)
    m = stability_map(h, [1.0], orders, 0.0, 0.0, amplitude=A)
    a = -(0.01 + 3 * -50.0 * A**2 * orders**4.0)
    np.testing.assert_allclose(m.growth_rate.values[0], a * orders**2.0)
