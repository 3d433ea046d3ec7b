"""Figures that do not mislead (issue 22, item 7): one-line titles and no "-0" tick on the polar
plot, the shape seen under the mean loss, band and distance axes that end with the data, labelled
axes, round colour-bar levels and legends for the numbers drawn. Hand-made datasets, no runs."""

import re

import numpy as np
import pytest
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg

from railwear import plots

UM = 1e-6


def drawn(fig):
    FigureCanvasAgg(fig).draw()
    return fig


def texts(fig):
    """Every text of a drawn figure: titles, labels, tick labels, annotations, legends."""
    out = [t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text"))]
    return [t for t in out if t]


def result(drop_um=2000.0, orders=((8, 20.0, 60.0), (1, 11.0, 10.0)), points=256):
    """A worn wheel over (time, angle): the mean radius falls by ``drop_um``, each ``(order,
    start, end)`` amplitude in µm grows from start to end; on a 0.84 m wheel at 70 km/h."""
    t = np.linspace(0.0, 1.0, 11)
    x = np.arange(points) * 2 * np.pi / points
    u = -drop_um * UM * t[:, None] + 0 * x
    for n, a0, a1 in orders:
        u = u + (a0 + (a1 - a0) * t)[:, None] * UM * np.cos(n * x + 0.3 * n)[None, :]
    return xr.Dataset({"u": (("time", "angle"), u), "nominal_radius": ((), 0.42)},
                      coords={"time": t, "angle": x, "speed": ((), 70 / 3.6)}, attrs={"scenario_name": "made"})


def test_tick_number_never_writes_minus_zero():
    assert plots.tick_number(-3.5e-15, 60.0) == "0"
    assert plots.tick_number(-0.0, 1.0) == "0"
    assert plots.tick_number(-30.0, 60.0) == "-30"
    assert plots.tick_number(2.5e-9, 1e-8) == "2.5e-09"  # a small axis keeps its small ticks


@pytest.mark.parametrize("drop_um, orders", [(2000.0, ((8, 20.0, 60.0),)), (0.3, ((3, 0.6, 0.7), (2, 0.3, 0.1)))])
def test_the_polar_plot_has_one_title_line_and_no_minus_zero(drop_um, orders):
    """The radial ticks and the mean radius lost (0.3 µm: "-0 µm" before) never read -0."""
    fig = drawn(plots.polar(result(drop_um=drop_um, orders=orders)))
    words = texts(fig)
    assert not [t for t in words if re.search(r"(^|\s)[−-]0(\.0*)? ?µm", t)], words
    assert "0 µm" in words
    assert "\n" not in fig.get_suptitle()
    assert any("exaggerated" in t for t in words)  # the scale, under the wheels


def _band_heights(fig):
    """The y extent (µm) of each panel of the profiles figure but the last (the shape)."""
    return [np.diff(ax.get_ylim())[0] for ax in fig.axes[:-1]]


def test_the_profiles_top_panel_shows_the_shape_under_a_large_mean_loss():
    """2 mm of mean loss under a 120 µm shape: the radius panel is broken into a band at the start
    and one at the end, each of one height, where the shape fills at least a third."""
    ds = result(drop_um=2000.0)
    fig = drawn(plots.profiles(ds))
    heights = _band_heights(fig)
    assert len(heights) == 2 and heights[0] == pytest.approx(heights[1])
    shape = float(np.ptp(ds.u.isel(time=-1).values)) / UM
    assert shape / heights[1] > 1 / 3
    ends = fig.axes[1].get_ylim()
    assert ends[0] < float(ds.u.isel(time=-1).min()) / UM and float(ds.u.isel(time=-1).max()) / UM < ends[1]
    assert "broken" in " ".join(texts(fig))


def test_the_profiles_panel_is_whole_where_the_mean_loss_is_small():
    fig = drawn(plots.profiles(result(drop_um=50.0)))
    assert len(fig.axes) == 2
    assert "broken" not in " ".join(texts(fig))


def test_the_band_panel_ends_with_the_bands_drawn():
    """A spectrum of orders 1-12 on a 0.84 m wheel: bands of the record reach 3 mm, but every
    level past the shortest drawn band is empty; the axis ends within a band of it."""
    fig = drawn(plots.spectrum(result(orders=[(n, 10.0 / n, 10.0 / n) for n in range(1, 13)])))
    band_ax = fig.axes[1]
    shortest = min(float(np.min(line.get_xdata()[np.isfinite(line.get_ydata())]))
                   for line in band_ax.get_lines() if np.any(np.isfinite(line.get_ydata())) and
                   len(line.get_xdata()) > 1)
    right = min(band_ax.get_xlim())
    assert shortest / 1.3 < right <= shortest


def test_the_hunting_figure_labels_every_panel():
    t = np.linspace(0.0, 1.0, 200)
    speeds = np.array([50.0, 78.0])
    y = np.stack([1e-3 * np.exp(-3 * t) * np.sin(40 * t), 5e-3 * np.sin(40 * t)])
    ds = xr.Dataset({"lateral_displacement": (("speed", "time"), y)}, coords={"speed": speeds, "time": t})
    fig = drawn(plots.lateral_motion(ds))
    for ax in fig.axes:
        assert ax.get_xlabel() == "distance run (m)" and "(mm)" in ax.get_ylabel()


def test_the_hunting_map_levels_are_round():
    conicity = np.linspace(0.02, 0.4, 20)
    yaw = np.linspace(1e5, 2e7, 12)
    speed = 26.75 + 300.0 * (yaw[None, :] / 2e7) / conicity[:, None] ** 0.5  # m/s
    ds = xr.Dataset({"critical_speed": (("conicity", "yaw_stiffness"), speed, {"units": "m s-1"})},
                    coords={"conicity": conicity, "yaw_stiffness": yaw})
    fig = drawn(plots.hunting_map(ds))
    levels = fig.axes[0].collections[0].levels if hasattr(fig.axes[0].collections[0], "levels") else None
    bar = fig.axes[1]
    ticks = [float(t.get_text().replace(",", "").replace("−", "-")) for t in bar.get_yticklabels() if t.get_text()]
    assert ticks and all(v == round(v) and v % 10 == 0 for v in ticks), ticks
    assert levels is None or all(v % 10 == 0 for v in levels)


def _sweep(two):
    speeds = np.array([50.0, 60.0, 70.0])
    coords = {"operation.speed_kmh": speeds}
    shape = (3,)
    if two:
        coords["contact.traction_coefficient"] = np.array([0.03, 0.05])
        shape = (3, 2)
    dims = tuple(coords)
    regime = np.full(shape, "polygonalising", dtype="<U14")
    regime.flat[0] = "onset"
    distance = np.full(shape, 170000.0)
    distance.flat[0] = np.nan
    return xr.Dataset({"regime": (dims, regime), "dominant_order": (dims, np.full(shape, 8)),
                       "limit_distance": (dims, distance), "distance_run": (dims, np.full(shape, 170000.0)),
                       "peak_to_peak_limit": ((), 1e-4)}, coords=coords, attrs={"base_scenario_name": "made"})


@pytest.mark.parametrize("two", [False, True])
def test_sweep_axes_are_words_and_the_numbers_have_a_legend(two):
    fig = drawn(plots.sweep(_sweep(two)))
    ax = fig.axes[0]
    assert ax.get_xlabel() == "speed (km/h)"
    if two:
        assert ax.get_ylabel() == "traction coefficient"
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("dominant order" in t for t in legend), legend
    assert "operation.speed_kmh" in ax.get_title()  # the field itself, once, in the title


def forecast(limit_db=None):
    """32 samples over 500 000 km: 24 cross the limit between 30 000 and 90 000 km and grow on,
    +75 dB above it 100 000 km later; 8 stay under it."""
    distance = np.linspace(0.0, 500000.0, 201)
    cross = np.concatenate([np.linspace(30000.0, 90000.0, 24), np.full(8, np.inf)])
    slope = 75.0 / 100000.0  # dB per km after the crossing
    excess = np.where(np.isfinite(cross)[:, None], slope * (distance[None, :] - np.where(np.isfinite(cross), cross,
                                                                                          0)[:, None]), -3.0)
    attrs = {"crossing_median_km": 50000.0, "crossing_p05_km": 31000.0, "crossing_p95_km": np.inf,
             "above_at_start": 0, "limit_name": "20 dB re 1 um in every order"}
    data = {"excess": (("sample", "distance"), excess), "crossing_distance": ("sample", cross)}
    if limit_db is None:
        attrs["limit_m"] = 1e-4
        data["peak_to_peak"] = (("sample", "distance"), 1e-4 * 10 ** (excess / 20))
    return xr.Dataset(data, coords={"sample": np.arange(32), "distance": distance}, attrs=attrs)


@pytest.mark.parametrize("limit_db", [None, 20.0])
def test_the_forecast_axes_end_with_the_crossings(limit_db):
    ds = forecast(limit_db)
    fig = drawn(plots.forecast(ds))
    ax = fig.axes[0]
    last = float(np.nanmax(np.where(np.isfinite(ds.crossing_distance), ds.crossing_distance, np.nan)))
    assert last < ax.get_xlim()[1] <= plots.FORECAST_REACH * last
    words = " ".join(texts(fig))
    assert "8 samples stay under the limit to 500,000 km" in words
    if limit_db is not None:  # the dB panel: +20 dB at most, not the +75 dB the model runs on to
        assert ax.get_ylim()[1] <= 20 * np.log10(plots.FORECAST_SPAN) + 2
        assert "axis cut at +20 dB" in words
