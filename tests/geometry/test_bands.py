"""One-third-octave band levels in wavelength (EN 15610), limits (ISO 3095) and exceedance."""

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.geometry import bands
from railwear.geometry.roundness import grid_angles

UM = 1e-6


def _wheel_for(order, band):
    """The diameter (m) that puts wheel order ``order`` at the exact centre of band ``band``."""
    return order * bands.exact_wavelength(band) / np.pi


def test_r10_centres_are_the_preferred_numbers():
    # EN 15610's named wavelengths from 1 m down to 3.15 mm, and the long ones of a wheel
    named = [1.0, 0.8, 0.63, 0.5, 0.4, 0.315, 0.25, 0.2, 0.16, 0.125, 0.1, 0.08, 0.063, 0.05, 0.04,
             0.0315, 0.025, 0.02, 0.016, 0.0125, 0.01, 0.008, 0.0063, 0.005, 0.004, 0.00315]
    index = np.arange(0, 26)
    np.testing.assert_allclose(bands.nominal_wavelength(index), named, rtol=1e-12)
    np.testing.assert_array_equal(bands.band_index(named), index)
    assert bands.nominal_wavelength(-4) == pytest.approx(2.5, rel=1e-12)
    assert bands.nominal_wavelength(-5) == pytest.approx(3.15, rel=1e-12)
    # nominal within 1.3 % of the exact 10^(-k/10) (3.15 against 3.162)
    exact = bands.exact_wavelength(np.arange(-10, 30))
    assert np.max(np.abs(bands.nominal_wavelength(np.arange(-10, 30)) / exact - 1)) < 0.013
    lo, hi = bands.band_edges(np.arange(-3, 8))
    np.testing.assert_allclose(hi / lo, 10**0.1, rtol=1e-12)
    np.testing.assert_allclose(np.sqrt(lo * hi), 1 / exact[7:18], rtol=1e-12)
    assert np.all(lo[1:] == hi[:-1])  # shared edges, bit for bit


def test_order_wavelength_and_amplitudes():
    x = grid_angles(256)
    u = 3e-6 * np.cos(5 * x + 0.4) + 1e-6 * np.cos(17 * x) + 2e-4
    orders, amp = bands.order_amplitudes(u)
    assert orders[0] == 1 and orders[-1] == 128
    assert amp[4] == pytest.approx(3e-6, rel=1e-12) and amp[16] == pytest.approx(1e-6, rel=1e-12)
    assert np.max(np.delete(amp, [4, 16])) < 1e-18
    wl = bands.order_wavelength([1, 40], 0.92)
    np.testing.assert_allclose(wl, [np.pi * 0.92, np.pi * 0.92 / 40], rtol=1e-15)
    assert 2.8 < wl[0] < 2.9 and 0.07 < wl[1] < 0.073  # about 2.9 m down to 7 cm


@pytest.mark.parametrize("order, band", [(20, 9), (7, 3), (64, 15), (300, 22)])
def test_sinusoid_at_a_band_centre_has_the_exact_level(order, band):
    a = 5e-6
    d = _wheel_for(order, band)
    u = a * np.cos(order * grid_angles(1024) + 1.1)
    levels = bands.band_levels(u, d)
    at = list(levels.index).index(band)
    expected = 10 * np.log10(a**2 / 2 / UM**2)
    assert levels.level[at] == pytest.approx(expected, abs=1e-9)
    # every other band is empty (the line lies wholly inside its band)
    others = np.delete(levels.mean_square, at)
    assert np.max(others) < 1e-12 * levels.mean_square[at]
    assert levels.wavelength[at] == pytest.approx(bands.nominal_wavelength(band))
    # the same from the amplitudes per order
    by_order = bands.band_levels_of_orders([order], [a], d)
    assert by_order.level[list(by_order.index).index(band)] == pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize("fraction", [0.5, 0.3, 0.8])
def test_line_on_a_band_edge_is_shared_in_proportion(fraction):
    # Annex C: a line of width 1/L counts in each band for the share of its width inside it.
    # Put the upper edge of band 9 at the fraction `fraction` of the width of line 20.
    order, band, a = 20, 9, 4e-6
    edge = 10 ** ((band + 0.5) / 10)
    d = (order - 0.5 + fraction) / edge / np.pi  # (n - 1/2)/L + fraction/L = edge
    levels = bands.band_levels_of_orders([order], [a], d)
    i = list(levels.index).index(band)
    ms = a**2 / 2
    assert levels.mean_square[i] == pytest.approx(fraction * ms, rel=1e-9)
    assert levels.mean_square[i + 1] == pytest.approx((1 - fraction) * ms, rel=1e-9)
    assert np.sum(levels.mean_square) == pytest.approx(ms, rel=1e-12)
    if fraction == 0.5:  # half each: 3.01 dB under the whole line
        assert levels.level[i] == pytest.approx(10 * np.log10(ms / 2 / UM**2), abs=1e-9)


def test_line_wider_than_bands_spreads_in_proportion():
    # order 1 on a 0.92 m wheel covers 0.17 to 0.52 per metre, about five bands
    levels = bands.band_levels_of_orders([1], [1e-4], 0.92)
    shares = bands.line_shares([1], np.pi * 0.92, levels.index)[0]
    lo, hi = levels.lower, levels.upper
    L = np.pi * 0.92
    inside = np.clip(np.minimum(hi, 1.5 / L) - np.maximum(lo, 0.5 / L), 0, None) * L
    np.testing.assert_allclose(shares, inside, rtol=1e-12)
    assert np.count_nonzero(shares) == 6  # lg 3 = 0.48 decade: 4.8 bands wide, touching six
    assert np.sum(shares) == pytest.approx(1.0, rel=1e-12)
    assert not np.any(levels.resolved[shares > 0])  # all longer than L/4


def test_parseval_band_energies_sum_to_the_variance():
    rng = np.random.default_rng(7)
    for n in (1024, 255):  # with and without the alternating order N/2
        u = 2e-4 + 3e-5 * rng.standard_normal(n)
        levels = bands.band_levels(u, 0.84)
        assert np.sum(levels.mean_square) == pytest.approx(np.var(u), rel=1e-12)
        # and through the levels: 10 lg of the sum of 10^(L/10) is the overall level
        total = 10 * np.log10(np.sum(10 ** (levels.level / 10)))
        assert total == pytest.approx(10 * np.log10(np.var(u) / UM**2), abs=1e-9)
    # leading axes: each row on its own
    rows = 1e-5 * rng.standard_normal((3, 128))
    levels = bands.band_levels(rows, 0.92)
    np.testing.assert_allclose(levels.mean_square.sum(axis=-1), rows.var(axis=-1), rtol=1e-12)


def test_resolved_means_a_quarter_of_the_circumference():
    levels = bands.band_levels(np.zeros(512), 0.92)
    L = np.pi * 0.92
    np.testing.assert_array_equal(levels.resolved, levels.exact <= L / 4)
    assert np.all(levels.level == -np.inf)  # a round wheel: empty bands, no error
    assert levels.resolved.sum() > 15 and (~levels.resolved).sum() >= 5


def test_given_bands_drop_energy_outside_them():
    u = 1e-6 * np.cos(20 * grid_angles(256)) + 1e-6 * np.cos(60 * grid_angles(256))
    d = _wheel_for(20, 9)
    only = bands.band_levels(u, d, bands=[8, 9, 10])
    assert np.sum(only.mean_square) == pytest.approx(0.5e-12, rel=1e-9)
    with pytest.raises(ScenarioError, match="consecutive"):
        bands.band_levels(u, d, bands=[8, 10])
    with pytest.raises(ScenarioError, match="diameter"):
        bands.band_levels(u, 0.0)
    with pytest.raises(ScenarioError, match="whole numbers"):
        bands.band_levels_of_orders([0, 1], [1e-6, 1e-6], 0.9)


def test_iso3095_limit_is_the_shipped_table():
    lim = bands.iso3095_limit()
    assert lim.index.tolist() == list(range(4, 26))  # 40 cm to 3.15 mm
    assert lim.wavelength[0] == pytest.approx(0.4) and lim.wavelength[-1] == pytest.approx(0.00315)
    levels = dict(zip(np.round(lim.wavelength * 100, 3), lim.level))
    assert levels[40.0] == 17.1 and levels[10.0] == 4.9 and levels[3.15] == -5.0 and levels[0.315] == -11.0
    # the shape: 2 dB per band falling to 10 cm, 0.6 dB per band below 3.15 cm
    assert np.all(np.diff(lim.level) < 0)
    np.testing.assert_allclose(np.diff(lim.level)[11:], -0.6, atol=1e-9)
    assert "ISO 3095" in lim.name and "Figure 2" in lim.source


def test_limit_table_names_bands():
    lim = bands.limit_spectrum([0.032, 0.003, 0.013], [-5.0, -11.0, -7.4], name="listing")
    assert lim.index.tolist() == [15, 19, 25]
    np.testing.assert_allclose(lim.wavelength, [0.0315, 0.0125, 0.00315])
    with pytest.raises(ScenarioError, match="band centre"):
        bands.limit_spectrum([0.0355], [0.0])  # between 3.15 and 4 cm
    with pytest.raises(ScenarioError, match="twice"):
        bands.limit_spectrum([0.1, 0.1], [0.0, 1.0])
    with pytest.raises(ScenarioError, match="as many"):
        bands.limit_spectrum([0.1, 0.08], [0.0])


def test_exceedance_against_a_limit():
    order, band, a = 20, 9, 5e-6  # 10 lg(a²/2 / r0²) = 10.97 dB in the 12.5 cm band
    d = _wheel_for(order, band)
    levels = bands.band_levels_of_orders([order, 2 * order], [a, 1e-7], d, bands=np.arange(5, 20))
    lim = bands.limit_spectrum([0.16, 0.125, 0.1, 0.063, 0.0016], [0.0, 7.0, 0.0, -20.0, 0.0])
    ex = bands.exceedance(levels, lim)
    expected = 10 * np.log10(a**2 / 2 / UM**2)
    assert ex.excess[1] == pytest.approx(expected - 7.0, abs=1e-9) and ex.exceeds[1]
    assert ex.level[0] == -np.inf and not ex.exceeds[0]  # an empty band never exceeds
    # order 40 (6.3 cm band): 10 lg(1e-14 / 2 / 1e-12) = -23.0 dB, 3.0 dB under -20 dB
    assert ex.excess[3] == pytest.approx(10 * np.log10(1e-14 / 2 / UM**2) + 20.0, abs=1e-9)
    assert ex.excess[3] == pytest.approx(-3.01, abs=0.01) and not ex.exceeds[3]
    assert np.isnan(ex.excess[4]) and not ex.exceeds[4]  # 1.6 mm: beyond the wheel's bands
    assert ex.count == 1
