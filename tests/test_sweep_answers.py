"""A sweep answers 'how far' (issue 22, item 1): the distance to the out-of-roundness limit per
point in the table, sweep.nc and the figure; counts stored as integers; a quantity constant to
round-off drawn flat."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import plots, results, sweep
from railwear.cli import app

# the metro wheel to 0.1 mm peak to peak at 50-90 km/h (the 70 km/h run is README's 173,878 km)
DISTANCES = [157524, 179235, 173878, 189232, 253924]
ORDERS = [12, 10, 8, 7, 6]


@pytest.fixture(scope="module")
def metro(tmp_path_factory):
    out = tmp_path_factory.mktemp("metro-sweep")
    with pytest.MonkeyPatch.context() as patch:  # the points in this process: no pool to start
        patch.setattr(sweep, "LocalExecutor", lambda workers=None: sweep.SerialExecutor())
        done = CliRunner().invoke(app, ["sweep", "metro", "--vary", "operation.speed_kmh=50:90:10", "-o", str(out)])
    assert done.exit_code == 0, done.output
    return out, done.stdout


def test_the_file_holds_the_distance_to_the_limit_and_integer_counts(metro):
    out, _ = metro
    ds = results.read_netcdf(out / "sweep.nc")
    np.testing.assert_allclose(ds.limit_distance.values, DISTANCES, atol=1.0)
    assert ds.limit_distance.attrs["units"] == "km"
    np.testing.assert_array_equal(ds.distance_run.values, ds.limit_distance.values)
    assert float(ds.peak_to_peak_limit) == pytest.approx(1e-4)
    for name in ("dominant_order", "maxima"):
        assert ds[name].dtype.kind == "i", name
    assert list(ds.dominant_order.values) == ORDERS
    assert ds.dominant_growth_per_10000_km.values[2] == pytest.approx(19.56, abs=0.01)  # percent, as the summary's +20%


def test_the_table_says_how_far(metro):
    _, text = metro
    assert "to 0.1 mm p-p (km)" in text and "growth / 10 000 km" in text
    for km in DISTANCES:
        assert f"{km:,}" in text
    assert "p-p end/start" not in text  # constant 2.26 by construction: the run stops at the limit


def test_the_figure_draws_the_distance_per_speed(metro):
    out, _ = metro
    fig = plots.sweep(results.read_netcdf(out / "sweep.nc"))
    (ax,) = fig.axes
    assert ax.get_ylabel() == "distance to the 0.1 mm peak-to-peak limit (km)"
    assert ax.get_xlabel() == "speed (km/h)"
    (line,) = ax.get_lines()
    np.testing.assert_allclose(line.get_ydata(), DISTANCES, atol=1.0)
    assert ax.get_ylim()[0] == 0 and ax.get_ylim()[1] > max(DISTANCES)
    assert [t.get_text() for t in ax.texts] == [str(n) for n in ORDERS]


def test_a_ratio_constant_to_round_off_is_drawn_flat(metro):
    """Without the limit variables the figure falls back to the peak-to-peak ratio, 2.26 at
    every speed with a spread of 5e-15: drawn flat on a linear axis with ticks, not a cliff."""
    out, _ = metro
    ds = results.read_netcdf(out / "sweep.nc").drop_vars(["limit_distance", "distance_run"])
    ratio = (ds.peak_to_peak / ds.peak_to_peak_initial).values
    assert 0 < np.ptp(ratio) < 1e-12 * ratio.mean()
    fig = plots.sweep(ds)
    (ax,) = fig.axes
    fig.canvas.draw()
    low, high = ax.get_ylim()
    assert ax.get_yscale() == "linear" and low < ratio.mean() < high
    assert (high - low) == pytest.approx(0.1 * ratio.mean())
    ticks = [t.get_text() for t in ax.get_yticklabels() if t.get_text()]
    assert len(ticks) >= 3 and all(t.replace(".", "").isdigit() for t in ticks), ticks
    assert ax.yaxis.get_offset_text().get_text() == ""


@pytest.mark.parametrize("values, flat", [([2.26, 2.26 * (1 + 5e-15)], True), ([1.0, 1.0], True),
                                          ([0.0, 0.0], True), ([2.26, 2.26 * (1 + 1e-6)], False),
                                          ([np.nan, 3.0], True), ([np.nan], False)])
def test_flat_if_round_off(values, flat):
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    assert plots.flat_if_round_off(ax, values) is flat


def test_a_failed_point_has_no_counts():
    """Integers have no NaN: a failed point's counts are -1 and its regime says failed."""
    ds = sweep.combine({"wheel.radius_m": np.array([3.0])}, ["k"], {}, {"k": "ScenarioError: x"}, False)
    assert ds.dominant_order.dtype.kind == "i" and int(ds.dominant_order[0]) == sweep.FAILED
    assert str(ds.regime.values[0]) == "failed"


@pytest.mark.parametrize("field, label", [("operation.speed_kmh", "speed (km/h)"),
                                          ("wheel.static_load_kN", "static load (kN)"),
                                          ("track.pad_stiffness_MN_m", "pad stiffness (MN/m)"),
                                          ("contact.friction_coefficient", "friction coefficient"),
                                          ("wheel.radius_m", "radius (m)")])
def test_field_label(field, label):
    assert plots.field_label(field) == label
