"""The spectrum and polar figures on real results: floors, wavelength axes, band levels, limits."""

import re

import numpy as np
import pytest

from railwear import api, plots
from railwear.geometry import bands
from railwear.longterm.spectra import with_band_levels
from railwear.scenario import load_scenario, parse_scenario, to_toml

UM = 1e-6


@pytest.fixture(scope="module")
def result():
    return api.run("smoothing")


@pytest.fixture(scope="module")
def batch():
    text = to_toml(load_scenario("smoothing")).replace("speed_kmh = 120.0", "speed_kmh = [100.0, 150.0, 200.0]")
    return api.run(parse_scenario(text))


def _finite_axes(fig):
    for ax in fig.axes:
        if ax.axison:
            assert np.all(np.isfinite(ax.get_xlim())) and np.all(np.isfinite(ax.get_ylim()))


def _curves(ax):
    return [line for line in ax.get_lines() if len(line.get_xdata()) > 1]


def test_spectrum_floor_wavelength_axis_and_bands(result):
    fig = plots.spectrum(result)
    _finite_axes(fig)
    ax, band_ax = fig.axes[0], fig.axes[1]
    peak = max(float(np.max(bands.order_amplitudes(result.u.isel(time=k).values)[1])) for k in (0, -1)) / UM
    floor = peak / 100  # 40 dB under the peak, not the -300 dB of exact zeros
    drawn = np.concatenate([line.get_ydata() for line in ax.get_lines() if len(line.get_ydata())])
    assert drawn.min() == pytest.approx(floor, rel=1e-12)
    assert ax.get_ylim()[0] == pytest.approx(floor / 1.6, rel=1e-9)
    # the top axis: wavelength pi D / n with D = 2 R0 = 0.92 m, labelled with its origin
    top = [a for a in ax.child_axes if "wavelength" in a.get_xlabel()]
    assert len(top) == 1 and "D = 0.92 m (from the" in top[0].get_xlabel()
    for tick in top[0].get_xticks():  # each tick sits at its order pi D / lambda
        assert 1 <= np.pi * 0.92 / tick <= ax.get_xlim()[1]
    # the band panel: the end's levels are the EN 15610 bands of the end state
    end = bands.band_levels(result.u.isel(time=-1).values, 0.92)
    solid = [line for line in _curves(band_ax) if line.get_linestyle() == "-" and line.get_label().endswith("end")]
    assert len(solid) == 1
    shown = np.asarray(solid[0].get_ydata(), float)
    keep = np.isfinite(shown)
    np.testing.assert_allclose(shown[keep], end.level[keep], rtol=0, atol=1e-12)
    band_peak = max(np.max(bands.band_levels(result.u.isel(time=k).values, 0.92).level) for k in (0, -1))
    assert np.nanmin(shown) >= band_peak - 40 - 1e-9 and keep.sum() >= 8
    np.testing.assert_array_equal(keep, end.level >= band_peak - 40)  # every band within 40 dB is drawn
    assert band_ax.xaxis_inverted() and band_ax.get_xscale() == "log"
    assert "dB re 1 µm" in band_ax.get_ylabel() and "(m)" in band_ax.get_xlabel()


def test_spectrum_draws_the_iso3095_limit_and_counts_bands_above(result):
    fig = plots.spectrum(result, limit="iso3095")
    band_ax = fig.axes[1]
    limit = [line for line in band_ax.get_lines() if "ISO 3095" in line.get_label()]
    assert len(limit) == 1
    iso = bands.iso3095_limit()
    np.testing.assert_allclose(limit[0].get_xdata(), iso.wavelength)
    np.testing.assert_allclose(limit[0].get_ydata(), iso.level)
    over = int(bands.exceedance(bands.band_levels(result.u.isel(time=-1).values, 0.92), iso).count)
    assert f": {over} band" in limit[0].get_label()
    # a limit 30 dB lower is passed in some bands, and the figure says how many
    low = bands.limit_spectrum(iso.wavelength, iso.level - 30, name="low")
    low_count = int(bands.exceedance(bands.band_levels(result.u.isel(time=-1).values, 0.92), low).count)
    assert low_count > 0
    label = [line.get_label() for line in plots.spectrum(result, limit=low).axes[1].get_lines()
             if line.get_label().startswith("low")][0]
    assert f"low: {low_count} bands above" in label


def test_spectrum_diameter_from_result_scenario_argument_or_none(result):
    no_radius = result.drop_vars("nominal_radius", errors="ignore")
    with_radius = no_radius.assign(nominal_radius=((), 0.5, {"units": "m"}))
    label = [a for a in plots.spectrum(with_radius).axes[0].child_axes][0].get_xlabel()
    assert "D = 1 m (from the result)" in label
    label = [a for a in plots.spectrum(no_radius).axes[0].child_axes][0].get_xlabel()
    assert "D = 0.92 m (from the scenario)" in label
    label = [a for a in plots.spectrum(no_radius, diameter=1.25).axes[0].child_axes][0].get_xlabel()
    assert "D = 1.25 m (given)" in label
    bare = no_radius.copy()
    bare.attrs = {k: v for k, v in bare.attrs.items() if k != "scenario"}
    fig = plots.spectrum(bare)
    _finite_axes(fig)
    assert not fig.axes[0].child_axes  # no wavelength axis without a diameter
    assert not fig.axes[1].axison
    assert "wheel diameter unknown" in fig.axes[1].texts[0].get_text()


def test_polar_states_its_exaggeration(result):
    fig = plots.polar(result)
    _finite_axes(fig)
    (ax,) = fig.axes
    shape = [result.u.isel(time=k).values for k in (0, -1)]
    span = max(np.max(np.abs(u - u.mean())) for u in shape) / UM
    assert ax.get_ylim() == pytest.approx((-1.15 * span, 1.15 * span), rel=1e-12)
    assert ax.get_rorigin() == pytest.approx(-2.5 * span, rel=1e-12)
    scale = fig.get_supxlabel()  # under the wheels; the title is one line
    factor = float(re.search(r"exaggerated about ([\d,]+)x", scale).group(1).replace(",", ""))
    assert factor == pytest.approx(0.46 / (2.5 * span * UM), abs=0.5)  # R0 over the drawn hub
    assert "R0 = 460 mm" in scale and "\n" not in fig.get_suptitle()
    curves = _curves(ax)
    end = [c for c in curves if c.get_label() == "end"][0]
    u = shape[1]
    np.testing.assert_allclose(end.get_ydata()[:-1], (u - u.mean()) / UM, rtol=1e-12)
    labels = [t.get_text() for t in ax.texts]  # the radial ticks, written on a white ground
    assert len(labels) == len(ax.get_yticks()) and all(t.endswith(" µm") for t in labels) and "0 µm" in labels


def test_polar_is_drawn_by_run(result, tmp_path):
    assert plots.FIGURES["polar"] is plots.polar and plots.FIGURES["spectrum"] is plots.spectrum
    paths = plots.write_figures(result, tmp_path)
    assert (tmp_path / "polar.png") in paths and (tmp_path / "polar.png").stat().st_size > 10_000


def test_batch_rows(batch):
    fig = plots.spectrum(batch)
    _finite_axes(fig)
    ends = [line for line in _curves(fig.axes[1]) if line.get_label().endswith("end")]
    assert len(ends) == 3
    levels = [bands.band_levels(batch.u.isel(speed=i, time=k).values, 0.92).level for i in range(3) for k in (0, -1)]
    band_peak = max(np.max(lv) for lv in levels)
    for line, lv in zip(ends, levels[1::2]):  # every band within 40 dB of the largest is drawn
        np.testing.assert_array_equal(np.isfinite(np.asarray(line.get_ydata(), float)), lv >= band_peak - 40)
    fig = plots.polar(batch)
    _finite_axes(fig)
    assert len(fig.axes) == 3 and all(ax.name == "polar" for ax in fig.axes)
    assert re.search(r"exaggerated about [\d,]+x to [\d,]+x", fig.get_supxlabel())


def test_round_wheel_draws_without_error(result):
    # the result stores the band levels of its own u: a new u has its own (every band empty here)
    flat = with_band_levels(result.assign(u=result.u * 0 - 1e-4), float(result.nominal_radius))
    assert np.isnan(flat.band_level.values).all()
    fig = plots.spectrum(flat)
    _finite_axes(fig)
    drawn = np.concatenate([line.get_ydata() for line in fig.axes[0].get_lines() if len(line.get_ydata())])
    assert np.all(drawn == 1e-6)  # everything on the 1 pm floor, not at round-off
    assert "round wheel" in fig.axes[1].texts[0].get_text()
    _finite_axes(plots.polar(flat))
