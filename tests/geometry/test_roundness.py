import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.geometry import roundness


def test_harmonics_spectrum_roundtrip():
    u = roundness.harmonics(256, [3, 7], [20e-6, 5e-6], [0.4, 1.0])
    s = roundness.polygon_spectrum(u)
    assert s["amplitude"][2] == pytest.approx(20e-6, rel=1e-12)
    assert s["amplitude"][6] == pytest.approx(5e-6, rel=1e-12)
    assert s["dominant_order"] == 3
    # rms of a 20 µm harmonic is 14.14 µm: 23.01 dB re 1 µm
    assert s["roughness_level"][2] == pytest.approx(20 * np.log10(20 / np.sqrt(2)), abs=1e-9)


@pytest.mark.parametrize("order", [1, 3, 5, 8])
def test_maxima_of_a_polygon(order):
    u = roundness.harmonics(512, [order, 3 * order], [1e-4, 2e-6], [0.3, 0.0])
    assert roundness.count_maxima(u) == order


def test_random_perturbation_rms_and_seed():
    a = roundness.random_perturbation(512, 40e-6, 2, 16, np.random.default_rng(3))
    b = roundness.random_perturbation(512, 40e-6, 2, 16, np.random.default_rng(3))
    assert np.sqrt(np.mean(a**2)) == pytest.approx(40e-6, rel=1e-12)
    np.testing.assert_array_equal(a, b)
    amp = roundness.harmonic_amplitudes(a)
    assert np.all(amp[17:] < 1e-18) and amp[1] < 1e-18


def test_resample_measured_is_periodic_and_accurate():
    angle = np.sort(np.random.default_rng(0).uniform(0, 2 * np.pi, 400))
    u = roundness.resample_measured(angle, 1e-5 * np.cos(3 * angle), 128)
    np.testing.assert_allclose(u, 1e-5 * np.cos(3 * roundness.grid_angles(128)), atol=2e-9)


def test_removed_depth():
    u0 = roundness.harmonics(64, [2], [1e-5])
    s = roundness.polygon_spectrum(u0 - 3e-4, u_initial=u0)
    assert s["max_removed_depth"] == pytest.approx(3e-4)
    assert s["mean_removed_depth"] == pytest.approx(3e-4)


def _history(rates, amplitude=1e-5, n_points=64, times=np.linspace(0.0, 1.0, 21), noise=0.0, seed=0):
    """Orders 2, 3, ... each growing as ``A e^(σ T)`` (rates ``σ`` per unit time), with a
    relative noise on every saved amplitude."""
    rng = np.random.default_rng(seed)
    orders = np.arange(2, 2 + len(rates))
    return times, np.array([roundness.harmonics(
        n_points, orders, amplitude * np.exp(np.asarray(rates) * T) * (1 + noise * rng.standard_normal(len(rates))))
        for T in times])


def test_log_growth_recovers_exponential_rates_and_their_noise():
    times, u = _history([0.7, -1.3])
    g = roundness.growth(times, u)
    np.testing.assert_allclose(g["order_rate"][[1, 2]], [0.7, -1.3], rtol=1e-10)
    assert np.all(g["order_rate_error"][[1, 2]] < 1e-10)
    assert g["leading_order"] == 2 and g["leading_factor"] == pytest.approx(np.exp(0.7), rel=1e-10)
    _, noisy = _history([0.7, -1.3], noise=0.05, seed=3)
    n = roundness.growth(times, noisy)
    # 5 % noise on 21 amplitudes over a unit of time: the slope's standard error ~ 0.05 / sqrt(21 / 12)
    assert 0.01 < n["order_rate_error"][1] < 0.1
    assert abs(n["order_rate"][1] - 0.7) < 4 * n["order_rate_error"][1]


def test_bad_orders():
    with pytest.raises(ScenarioError, match="orders"):
        roundness.harmonics(64, [40], [1e-6])


def _count_with_scipy(u, prominence=0.1):
    from scipy.signal import find_peaks

    u = np.asarray(u, float)
    span = np.ptp(u)
    if span == 0:
        return 0
    peaks, _ = find_peaks(np.concatenate([u, u, u]), prominence=prominence * span)
    return int(np.count_nonzero((peaks >= u.size) & (peaks < 2 * u.size)))


def test_maxima_count_is_scipy_find_peaks():
    """count_maxima follows find_peaks' rule (flat tops, prominence) without importing scipy.signal."""
    rng = np.random.default_rng(11)
    cases = [roundness.random_perturbation(n, 40e-6, 2, top, rng) for n in (64, 128, 512) for top in (8, 30)]
    cases += [np.round(rng.normal(size=n) * 3) for n in (16, 64, 256) for _ in range(20)]  # plateaus, ties
    cases += [np.zeros(8), np.array([0.0, 1.0, 1.0, 0.0]), np.array([1.0, 1.0, 0.0, 1.0, 1.0]), np.ones(5)]
    for u in cases:
        for prominence in (0.0, 0.1, 0.5):
            assert roundness.count_maxima(u, prominence) == _count_with_scipy(u, prominence)
