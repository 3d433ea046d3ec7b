"""The disk-contact wear rate against its closed-form limits (Kalker linear theory, Hertz, contact loss)."""

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.pde import DiskContact


@pytest.fixture(scope="module")
def disk():
    return DiskContact()


def test_kalker_linear_limit_far_from_saturation(disk):
    """Far above F/μ the creepage is F/k(N), k ∝ N^(2/3): Tγ = F² / (k0 (N/W)^(2/3))."""
    W = disk.static_load
    F = disk.traction_coefficient * W
    N = np.array([50.0, 200.0]) * W
    linear = F**2 / (disk.creep_stiffness * (N / W) ** (2 / 3))
    # The cubic saturation adds a relative F/(3 μ N) at first order.
    np.testing.assert_allclose(disk.frictional_energy(N), linear, rtol=F / (disk.friction_coefficient * N[0]))


def test_contact_loss_and_saturation_continuity(disk):
    assert np.all(disk.frictional_energy(np.array([-1e3, 0.0])) == 0)
    Np = disk.saturation_load
    below, above = disk.frictional_energy(np.array([Np * (1 - 1e-12), Np * (1 + 1e-12)]))
    # Above F/μ the creepage has a cube-root cusp: a step δ in load moves Tγ by about δ^(1/3).
    assert abs(above - below) < 2e-4 * below
    # At saturation the wheel slides at 3 μ N / k under μ N.
    k = disk.creep_stiffness * (Np / disk.static_load) ** (2 / 3)
    assert below == pytest.approx(3 * (disk.friction_coefficient * Np) ** 2 / k, rel=1e-6)


def test_scatter_slope_is_derivative_of_mean(disk):
    N = np.linspace(0.1, 2.0, 40) * disk.static_load
    d = 1e-3 * disk.static_load
    numeric = (disk.mean_frictional_energy(N + d) - disk.mean_frictional_energy(N - d)) / (2 * d)
    load, mean, slope = disk._scatter_table
    analytic = np.interp(N, load, slope)
    np.testing.assert_allclose(analytic, numeric, rtol=2e-3, atol=1e-4 * np.max(np.abs(numeric)))


def test_regime_change_follows_the_saturation_load():
    """With little scatter, ∂h/∂u_xx changes sign where the crest unloads to F/μ; that curvature ∝ 1/v²."""
    disk = DiskContact(load_scatter=0.01)
    for kmh in (150.0, 300.0):
        v = kmh / 3.6
        s_c = disk.crest_curvature(v)
        assert disk.slope(1.2 * s_c, v) < 0 < disk.slope(0.8 * s_c, v)
    assert disk.crest_curvature(100 / 3.6) == pytest.approx(4 * disk.crest_curvature(200 / 3.6))


def test_round_wheel_smooths_and_faster_smooths_more(disk):
    """At u_xx = 0 the slope is positive (smoothing) and grows like v²."""
    slopes = disk.slope(np.zeros(2), np.array([50.0, 100.0]))
    assert slopes[0] > 0
    assert slopes[1] == pytest.approx(4 * slopes[0], rel=1e-3)


def test_mean_wear_rate_order_of_magnitude(disk):
    """USFD mild regime k_e = 5.3 µg/J gives tread wear of order 1 mm per 10⁴-10⁵ km."""
    km_per_mm = disk.life_distance / 1e3 * 1e-3 / -float(disk(0.0, speed=0.0))
    assert 1e4 < km_per_mm < 1e5


@pytest.mark.parametrize("field, value", [("static_load", -1.0), ("poisson", 0.5), ("load_scatter", 0.0)])
def test_bad_parameters(field, value):
    with pytest.raises(ScenarioError, match=field):
        DiskContact(**{field: value})
