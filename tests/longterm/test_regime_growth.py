"""The numbers behind the regime: fitted growth rates against the dispersion relation, and the
regime against the stability map on the same scenario."""

import numpy as np
import pytest

import railwear
from railwear.geometry import roundness
from railwear.longterm.phenomenological import Phenomenological
from railwear.pde import Cubic, DiskContact, stability_map
from railwear.units import kmh_to_m_s


@pytest.mark.parametrize("speed_kmh", [100.0, 220.0])
def test_fitted_growth_of_a_small_polygon_is_the_dispersion_relation(speed_kmh):
    """A 0.1 µm polygon of orders 3, 6, 9 evolves linearly: the rate fitted to each order's
    amplitude over the run is the dispersion relation's rate to 1e-3 (of the largest rate)."""
    h, eps, nu, v = DiskContact(), 1e-4, 1e-3, kmh_to_m_s(speed_kmh)
    u0 = roundness.harmonics(256, [3, 6, 9], [1e-7, 1e-7, 1e-7])
    ds = Phenomenological(h, v, eps, nu, options={"n_save": 41}).run(u0, until=0.05)
    expected = stability_map(h, [v], [3, 6, 9], eps, nu).growth_rate.values[0]
    fitted = ds.growth_rate.sel(order=[3, 6, 9]).values
    np.testing.assert_allclose(fitted, expected, atol=1e-3 * np.max(np.abs(expected)))
    assert np.all(ds.growth_rate_error.sel(order=[3, 6, 9]).values < 1e-3 * np.max(np.abs(expected)))


def test_the_regime_and_the_leading_order_agree_with_the_stability_map():
    """Linear wear-rate laws h = c1 u_xx (one batch row each) on a 0.1 µm wheel of orders 2-16:
    the leading order is the map's fastest of those orders and grows by the map's factor (1e-6);
    by the wheel's rule (railwear.longterm.regime, 50 000 km a unit of normed time) the regime is
    polygonalising where that order, largest at the end, grows the map's 10 % per 10 000 km or more
    (a factor 1.61 over the run; the rule before asked 3), onset where it grows 1 % or more, and
    stable or smoothing where no order grows. (At the built-in onset case's 40 µm the frozen-crest map
    and the runs part: at 160 km/h the map lets order 15 grow while the run smooths 3x; the label
    follows the run.)"""
    c1 = [-0.05, -0.02, -0.012, 0.0, 0.01]
    forms, eps, nu = [Cubic(0.0, c, 0.0) for c in c1], 1e-4, 1e-3
    u0 = roundness.random_perturbation(256, 1e-7, 2, 16, np.random.default_rng(1))
    batch = Phenomenological(forms, np.full(len(c1), 30.0), eps, nu, options={"n_save": 41}).run(u0, until=1.0)
    present = np.arange(2, 17)
    factor = np.exp(np.array([stability_map(f, [30.0], present, eps, nu).growth_rate.values[0] for f in forms]))
    per_10000_km = factor.max(axis=1) ** (1e4 / float(batch.distance[-1])) - 1  # the run is one unit
    expected = ["polygonalising" if g >= 0.10 else "onset" if g >= 0.01 else None for g in per_10000_km]
    for row, (label, f) in enumerate(zip(expected, factor)):
        regime = str(batch.regime.values[row])
        if label is None:
            assert regime in ("stable", "smoothing"), (row, regime)
            continue
        assert regime == label, (row, regime, f.max())
        assert int(batch.leading_order[row]) == present[f.argmax()] == int(batch.dominant_order[row])
        assert float(batch.leading_growth_factor[row]) == pytest.approx(f.max(), rel=1e-6)
    assert set(expected) == {"polygonalising", "onset", None}
