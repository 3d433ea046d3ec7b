"""Strategy 4's fit of h(u_xx, v) from frozen-geometry statistics (paper Fig. 8)."""

import numpy as np
import pytest
import xarray as xr

from railwear.errors import ScenarioError
from railwear.wear import EnergyLaw
from railwear.geometry import roundness
from railwear.longterm.fitting import curvature, fit_h, gather
from railwear.longterm.disk_wheel import DiskWheel, ServiceSpeeds
from railwear.pde import Table

BETA = 5.3e-9 / 7850.0  # m³/J, the energy law of EnergyLaw(5.3e-9, 7850)
WEAR = {"law": EnergyLaw(5.3e-9, 7850.0), "band_width": 0.01, "life_distance": 5e7}


def synthetic(h, speeds, noise, rng, cells=4000, drift=(0.0, 0.0), dispersion=(0.0, 0.0)):
    s = rng.normal(0.0, 5e-3, (len(speeds), 1, cells))
    ux, uxxx = rng.normal(0.0, 1e-3, s.shape), rng.normal(0.0, 1e-2, s.shape)
    rate = np.stack([h(s[i], v) + drift[i] * ux[i] + dispersion[i] * uxxx[i] for i, v in enumerate(speeds)])
    rate = rate + noise * rng.standard_normal(s.shape)
    dims = ("speed", "geometry", "angle")
    return xr.Dataset({"curvature": (dims, s), "slope": (dims, ux), "third_derivative": (dims, uxxx), "rate": (dims, rate),
                       "standard_error": (dims, np.full(s.shape, noise))},
                      coords={"speed": ("speed", np.asarray(speeds, float))})


def test_curvature_is_exact_for_a_harmonic():
    x = 2 * np.pi * np.arange(64) / 64
    np.testing.assert_allclose(curvature(1e-5 * np.cos(7 * x)), -49e-5 * np.cos(7 * x), atol=1e-15)


def test_recovers_a_known_cubic_from_noisy_statistics_and_emits_a_table():
    def h(s, v):
        return -1.6e-3 + 0.02 * v / 60 * s - 3.0 * s**2 - 400.0 * s**3

    rng = np.random.default_rng(2)
    stats = synthetic(h, [40.0, 60.0], 2e-5, rng, drift=(0.3, -0.05), dispersion=(0.0, 4e-3))
    fit = fit_h(stats, degree=3)
    # each to three of its least-squares standard errors, 2e-5 / (1e-3 sqrt(4000)) = 3e-4 and 3e-5
    np.testing.assert_allclose(fit.drift, [0.3, -0.05], atol=1e-3)
    np.testing.assert_allclose(fit.dispersion, [0.0, 4e-3], atol=1e-4)
    assert isinstance(fit.table, Table)
    assert np.all(fit.chi2 < 2.5)
    # inside the bulk of the data (2 standard deviations of the curvature), to about two standard
    # errors of a bin mean (2e-5 / sqrt(4000 / 24) = 1.5e-6)
    s = np.linspace(-1e-2, 1e-2, 11)
    for i, v in enumerate([40.0, 60.0]):
        np.testing.assert_allclose(fit.table.at_speed(v)(s), h(s, v), atol=3e-6)
    # a straight line cannot carry the cubic: the fit says so
    assert np.all(fit_h(stats, degree=1).chi2 > 10)


def test_fitted_h_reproduces_the_disk_wheel_statistics_it_was_fitted_to(wheel_220):
    rng = np.random.default_rng(0)
    geometries = [roundness.random_perturbation(64, rms, 2, 16, rng) for rms in (20e-6, 50e-6, 80e-6)]
    v = wheel_220.speed

    def frozen(speed):
        return DiskWheel(wheel_220, **WEAR, service=ServiceSpeeds((speed,)), revolutions=3,
                              transient_revolutions=3, samples=2)

    stats = gather(frozen, [v], geometries, rng)
    fit = fit_h(stats, degree=2, bins=12)
    # the bin means lie on the fitted h within their standard errors (reduced chi^2 near 1)
    assert fit.chi2[0] < 3
    table = fit.table.at_speed(v)
    bins = np.array_split(np.argsort(stats.curvature.values[0].ravel(), kind="stable"), 12)
    of_table = np.array([table(stats.curvature.values[0].ravel()[b]).mean() for b in bins])
    resid = (of_table - fit.bin_rate[0]) / fit.bin_error[0]
    assert np.mean(np.abs(resid) < 2.5) >= 0.8
    # and the mean over the cells is the mean wear of the wheel
    mean_error = 2 * float(np.mean(fit.bin_error[0])) / np.sqrt(fit.bin_error[0].size)
    assert float(np.mean(table(stats.curvature.values[0]))) == pytest.approx(float(stats.rate.mean()), abs=mean_error)
    # wear: h < 0; smoothing at this speed: h rises with the curvature
    assert fit.coefficients[0][0] < 0 and fit.coefficients[0][1] > 0


def test_bad_fit_options():
    stats = synthetic(lambda s, v: s, [40.0], 1e-6, np.random.default_rng(0), cells=100)
    with pytest.raises(ScenarioError):
        fit_h(stats, degree=0)
    with pytest.raises(ScenarioError):
        fit_h(stats, degree=3, bins=4)


def test_fitted_odd_terms_are_the_fourier_phase_of_the_disk_wheel():
    """The drift and dispersion (coefficients of u_x and u_xxx) fitted to frozen-geometry statistics
    against the Fourier technique's ``Im λ_n``: by Parseval, the least-squares fit over the cells is
    that of ``c n - d n³`` to ``Im λ_n F_n`` weighted by ``|û_n|²``, with ``F_n = sinc³(n / N)`` the
    grid filter (u read linearly interpolated, wear gathered on cells)."""
    from railwear.longterm.fourier import Fourier
    from railwear.scenario import build, load_scenario

    scenario = load_scenario("direct")
    law, band, life = build.wear_law(scenario), build.band_width(scenario), scenario.operation.life_distance_km * 1e3
    v, points = 70 / 3.6, 128
    model = build.disk_wheel_model(scenario, v)
    rng = np.random.default_rng(0)
    geometries = [roundness.random_perturbation(points, rms, 2, 12, rng) for rms in (5e-6, 10e-6)]
    stats = gather(lambda s: DiskWheel(model, law, band, life, ServiceSpeeds((s,)), revolutions=4,
                                            transient_revolutions=4, samples=2), [v], geometries, rng)
    fit = fit_h(stats, degree=3, bins=16)
    power = sum(np.abs(np.fft.rfft(g))[1 : points // 2] ** 2 for g in geometries)
    odd = Fourier.disk_wheel(model, law, band).odd_terms(power, points)
    expected = np.array(odd) * life / v  # per unit normed time
    # small amplitudes, where the Hertz contact is linear: measured -1.1 % and +0.6 % (at 30-60 um
    # rms the nonlinearity moves them by 3-4 %)
    np.testing.assert_allclose([fit.drift[0], fit.dispersion[0]], expected, rtol=0.02)
