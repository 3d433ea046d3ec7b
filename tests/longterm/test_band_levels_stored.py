"""The EN 15610 band levels in the result every long-term strategy returns: the same numbers as
``railwear.geometry.bands.band_levels`` of the start and end states, masked where undefined, kept
through netCDF, and what the spectrum figure draws."""

import numpy as np
import pytest
import xarray as xr

from railwear import plots
from railwear.dynamics import DiskWheelModel, contact_constants
from railwear.geometry import bands, roundness
from railwear.longterm.direct import Direct
from railwear.longterm.disk_wheel import DiskWheel
from railwear.longterm.fourier import Fourier, FourierStrategy
from railwear.longterm.multiplier import Multiplier
from railwear.longterm.phenomenological import Phenomenological
from railwear.longterm.spectra import NO_BAND_LEVEL, UNDEFINED, describe
from railwear.pde import DiskContact
from railwear.results import read_netcdf, write_netcdf
from railwear.wear import EnergyLaw

R0 = 0.46  # m
LIFE = 5e7  # m per unit normed time


def wheel(speed=70 / 3.6):
    """The built-in direct scenario's disk wheel (80 kN, a rail mass on pads, μ = 0.3), at 70 km/h."""
    c = contact_constants(80e3, 1 / (2 * R0), 1 / (2 * 0.3), 210e9, 0.28)
    return DiskWheelModel(speed=speed, radius=R0, wheel_mass=1000.0, wheel_inertia=80.0, static_load=80e3,
                          hertz_constant=c["hertz_constant"], primary_stiffness=1.2e6, primary_damping=2e4,
                          f11=c["f11"], rail_mass=150.0, pad_stiffness=1e8, pad_damping=6e4, friction_coefficient=0.3,
                          traction_torque=0.05 * 80e3 * R0, patch_half_length=c["patch_half_length"])


def u_start(points=128, highest=30):
    return roundness.random_perturbation(points, 20e-6, 2, highest, np.random.default_rng(2))


def expected(u, batch=()):
    """``bands.band_levels`` of ``u`` (batch rows first) on this wheel, -inf masked as NaN."""
    level = bands.band_levels(u.transpose(*batch, "angle").values, 2 * R0).level
    return np.where(np.isfinite(level), level, np.nan)


def check(ds, batch=()):
    """The stored levels are the band computation's at the start and the end, bit for bit."""
    start, end = (expected(ds.u.isel(time=k), batch) for k in (0, -1))
    np.testing.assert_array_equal(ds.band_level_initial.transpose(*batch, "wavelength").values, start)
    np.testing.assert_array_equal(ds.band_level.transpose(*batch, "wavelength").values, end)
    levels = bands.band_levels(ds.u.isel(time=-1).transpose(*batch, "angle").values, 2 * R0)
    np.testing.assert_array_equal(ds.wavelength.values, levels.wavelength)
    np.testing.assert_array_equal(ds.band.values, levels.index)
    np.testing.assert_array_equal(ds.band_resolved.values, levels.resolved)
    assert ds.wavelength.attrs["units"] == "m" and ds.band_level.attrs["units"] == "dB"
    assert "re 1 um" in ds.band_level.attrs["long_name"] and float(ds.nominal_radius) == R0
    assert not np.isinf(ds.band_level.values).any() and np.isfinite(end).sum() >= 10


def test_fourier_and_multiplier_results_store_the_band_levels():
    fourier = Fourier.disk_wheel(wheel(), EnergyLaw(), 0.01)
    check(FourierStrategy(fourier, LIFE).run(u_start(), 0.5))
    check(Multiplier.from_fourier(fourier, LIFE).run(u_start(), 0.5))


def test_disk_wheel_results_store_the_band_levels():
    """A direct run of a few revolutions (A = 1e5, to 2 µm): the body's result has them too."""
    ds = Direct(DiskWheel(wheel(), EnergyLaw(), 0.01, LIFE), 1e5).run(u_start(64), 1.0, 2e-6)
    check(ds)


def test_a_batch_over_speeds_stores_them_per_speed_and_without_a_radius_none():
    h = DiskContact(wheel_radius=R0)
    ds = Phenomenological(h, np.array([20.0, 30.0, 40.0]), 1e-3, 1e-3, radius=R0).run(u_start(256, highest=16), 0.05)
    assert ds.band_level.dims == ("speed", "wavelength")
    check(ds, ("speed",))
    bare = Phenomenological(h, 30.0, 1e-3, 1e-3).run(u_start(256, highest=16), 0.05)
    assert "band_level" not in bare and "wavelength" not in bare.dims


def test_an_empty_band_is_nan_with_its_reason_and_survives_the_file(tmp_path):
    """A round start (u = 0) has no level in any band: NaN there (never -inf) with the reason;
    an end with one harmonic has levels. Written and read back through the result writer."""
    x = 2 * np.pi * np.arange(64) / 64
    u = np.stack([np.zeros(64), 3e-6 * np.cos(9 * x)])
    ds = describe(xr.Dataset({"u": (("time", "angle"), u, {"units": "m"})}, coords={"time": [0.0, 1.0]}), R0)
    assert np.isnan(ds.band_level_initial.values).all()
    assert ds.band_level_initial.attrs[UNDEFINED] == NO_BAND_LEVEL
    end = expected(ds.u.isel(time=-1))
    np.testing.assert_array_equal(ds.band_level.values, end)
    assert np.nanmax(end) == pytest.approx(10 * np.log10((3e-6) ** 2 / 2 / 1e-12), abs=0.5)  # most of one line
    write_netcdf(ds, tmp_path / "result.nc")
    back = read_netcdf(tmp_path / "result.nc")
    np.testing.assert_array_equal(back.band_level_initial.values, ds.band_level_initial.values)
    np.testing.assert_array_equal(back.band_level.values, ds.band_level.values)
    np.testing.assert_array_equal(back.band_resolved.values, ds.band_resolved.values)
    assert back.wavelength.attrs["units"] == "m" and back.band_level_initial.attrs[UNDEFINED] == NO_BAND_LEVEL


def test_the_spectrum_figure_draws_the_stored_levels():
    """Shift the stored end levels by 7 dB: the figure's solid band curve moves with them (it
    draws the variable, not a recomputation), and an explicit other diameter recomputes."""
    ds = FourierStrategy(Fourier.disk_wheel(wheel(), EnergyLaw(), 0.01), LIFE).run(u_start(), 0.5)

    def drawn(data, **kw):
        band_ax = plots.spectrum(data, **kw).axes[1]
        (line,) = [c for c in band_ax.get_lines() if c.get_linestyle() == "-" and c.get_label().endswith("end")]
        return np.asarray(line.get_ydata(), float)

    base = drawn(ds)
    shifted = ds.copy()
    shifted["band_level"] = ds.band_level + 7.0
    moved = drawn(shifted)
    both = np.isfinite(base) & np.isfinite(moved)
    assert both.sum() >= 8
    np.testing.assert_allclose(moved[both] - base[both], 7.0, rtol=0, atol=1e-12)
    keep = np.isfinite(base)
    np.testing.assert_array_equal(base[keep], ds.band_level.values[keep])
    other = drawn(ds, diameter=1.0)  # not the stored wheel: computed from u
    assert other.size == bands.band_levels(ds.u.isel(time=-1).values, 1.0).level.size
