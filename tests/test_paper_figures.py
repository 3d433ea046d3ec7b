"""The paper's figures make the paper's points (issue 12, item 3), on real, small runs: each test
reads the data a figure draws, not only that it draws."""

import numpy as np
import pytest
import xarray as xr

import railwear
from railwear import analysis, plots
from railwear.geometry import bands
from railwear.longterm.fitting import fit_h
from railwear.units import HOUR, MM, PM, UM


@pytest.fixture(scope="module")
def contact():
    return railwear.simulate("contact-path")


@pytest.fixture(scope="module")
def teeth():
    return analysis.figure("teeth")


@pytest.fixture(scope="module")
def surface():
    return analysis.figure("wear-surface")


@pytest.fixture(scope="module")
def fitted():
    return analysis.figure("fitted-h")


@pytest.fixture(scope="module")
def linear():
    return railwear.run("linear-dynamics")


def _inside(fig):
    """Everything drawn (titles, labels, legends) lies within the figure, to a hundredth of an inch."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()  # lays the figure out as saving it does
    box, frame = fig.get_tightbbox(), fig.bbox_inches
    return box.x0 >= frame.x0 - 0.01 and box.y0 >= frame.y0 - 0.01 and box.x1 <= frame.x1 + 0.01 \
        and box.y1 <= frame.y1 + 0.01


def _data_axes(fig):
    return [ax for ax in fig.axes if not hasattr(ax, "_colorbar") and ax.get_visible() and ax.axison
            and (ax.lines or ax.collections or ax.images)]


def _readable(fig):
    """No clipped text, every axis labelled, a legend wherever lines are drawn."""
    assert _inside(fig)
    for ax in _data_axes(fig):
        assert ax.get_xlabel() and ax.get_ylabel(), ax.get_title()
        if any(line.get_linestyle() != "None" for line in ax.lines):
            assert ax.get_legend() is not None, ax.get_title()


@pytest.mark.parametrize("name", ["teeth", "surface"])
def test_no_text_is_clipped_every_axis_is_labelled_and_every_line_has_a_legend(request, name):
    _readable(request.getfixturevalue(name).figure)  # contact path, evolution, fitted h: in their tests


def test_profiles_titles_fit_and_both_panels_say_their_line_styles(linear):
    fig = plots.profiles(linear)
    assert _inside(fig)
    *tops, shape = fig.axes  # the u panel, or its two bands where the mean radius falls far below the shape
    assert tops[0].get_legend() is not None and shape.get_legend() is not None
    end = linear.u.isel(time=-1).values / UM
    np.testing.assert_allclose(shape.lines[1].get_ydata(), end - end.mean())  # the shape, not 950 µm below


def test_contact_path_draws_the_deviation_from_rigid_rotation_and_it_is_not_a_straight_line(contact):
    fig = plots.contact_path(contact)
    _readable(fig)
    _, dynamic, power = fig.axes[:3]
    d = contact.isel(speed=0)
    deviation = float(contact.attrs["model_radius"]) * d.rotation_deviation.values
    t = d.time.values
    expected = (deviation - np.polyval(np.polyfit(t, deviation, 1), t)) / UM
    drawn = np.concatenate([line.get_ydata() for line in dynamic.lines if line.get_label().startswith("revolution")])
    np.testing.assert_allclose(np.sort(drawn), np.sort(expected), atol=1e-9)
    x = np.concatenate([line.get_xdata() for line in dynamic.lines if line.get_label().startswith("revolution")])
    straight = np.polyval(np.polyfit(x, drawn, 1), x)
    assert np.ptp(drawn) > 5.0  # µm of tread: the 3rd and 8th orders move the contact point
    assert np.std(drawn - straight) > 0.5 * np.std(drawn)
    grid = power.collections[0].get_array()
    row = grid[1]  # a whole revolution after the start
    assert np.ptp(row) / np.mean(row) > 0.1  # the power follows the radius under the contact


def test_wear_surface_depth_is_physical_and_the_patch_is_drawn_against_the_panels(surface):
    from matplotlib.image import AxesImage
    from matplotlib.patches import Ellipse

    assert 0 < surface.data.depth.max() < 1e-7  # 12 turns wear nanometres, not millimetres
    whole, coarse, fine = _data_axes(surface.figure)
    assert isinstance(whole.images[0], AxesImage)  # an image: no cell edges to beat into a moiré
    ellipses = [p for ax in (coarse, fine) for p in ax.patches if isinstance(p, Ellipse)]
    assert len(ellipses) == 2
    model = analysis.FIT_DEFAULT and railwear.scenario.build.disk_wheel_model(
        railwear.load_scenario("stepwise"), railwear.scenario.build.service_speeds(railwear.load_scenario("stepwise")).mean)
    assert ellipses[0].width == pytest.approx(2 * model.patch_half_length / MM)
    panel = lambda ax: np.diff(np.unique(np.round(np.concatenate([s[:, 0] for s in ax.collections[1].get_segments()]), 6)))
    assert panel(coarse).min() > 3 * ellipses[0].width > 3 * panel(fine).max()  # the point of Fig. 4


def test_teeth_figure_zooms_on_one_tooth_and_shows_the_spread_of_the_tooth_integrals(teeth):
    ds, fig = teeth
    drawn = ds.sample_tooth_depth.values
    assert drawn.size == analysis.TEETH_DRAWS and np.std(drawn) > 0.005 * np.mean(drawn)
    whole = ds.tooth_depth.values[1:-1]
    assert np.ptp(whole) < 0.1 * np.std(drawn)  # one speed: identical needles; over service: a spread
    hist = fig.axes[2]
    assert sum(p.get_height() for p in hist.patches) == drawn.size
    zoom = fig.axes[1].lines[0]
    ms, rate = zoom.get_xdata(), zoom.get_ydata()
    area = np.trapezoid(rate, ms) * UM / HOUR * 1e-3 / PM
    label = [t.get_text() for t in fig.axes[1].get_legend().get_texts()][1]
    assert area == pytest.approx(float(label.split(": ")[1].split()[0]), rel=0.03)


def _stats(h, rng, n=400):
    s = rng.uniform(-20e-3, 20e-3, (1, 1, n))
    rate = h(s) + 1e-5 * rng.standard_normal(s.shape)
    dims = ("speed", "geometry", "angle")
    return xr.Dataset({"curvature": (dims, s), "rate": (dims, rate), "slope": (dims, np.zeros_like(s)),
                       "third_derivative": (dims, np.zeros_like(s))}, coords={"speed": ("speed", [20.0])})


def _styles(ax):
    return {line.get_linestyle() for line in ax.lines  # the curves: not markers nor axvlines
            if len(line.get_xdata()) > 2 and line.get_linestyle() != "None"}


def test_fitted_relation_draws_both_branches_where_the_data_are_non_monotone(rng):
    bowl = _stats(lambda s: -1.6e-3 + 8.0 * (s + 5e-3) ** 2, rng)  # falls, then rises
    fig = plots.fitted_relation(bowl, fit_h(bowl, degree=3, bins=16))
    assert _styles(fig.axes[0]) == {"-", "--"}
    assert "non-monotone" in fig.axes[0].get_legend().get_texts()[0].get_text()
    line = _stats(lambda s: -1.6e-3 + 0.01 * s, rng)
    fig = plots.fitted_relation(line, fit_h(line, degree=3, bins=16))
    assert _styles(fig.axes[0]) == {"-"}


def test_fitted_h_figure_says_the_statistics_are_monotone_and_draws_the_rigid_wheels_two_branches(fitted):
    (stats, fit), fig = fitted
    _readable(fig)
    said = [t.get_text() for t in fig.axes[0].get_legend().get_texts()[:stats.sizes["speed"]]]
    for i, text in enumerate(said):
        grid = np.linspace(fit.bin_curvature[i].min(), fit.bin_curvature[i].max(), 400)
        monotone = np.all(np.diff(fit(grid, i)) > 0) or np.all(np.diff(fit(grid, i)) < 0)
        assert ("non-monotone" not in text) == monotone
    assert stats.sizes["speed"] == 2 and _styles(fig.axes[1]) == {"-", "--"}


def test_evolution_draws_the_amplitude_of_the_growing_and_decaying_orders_over_distance(linear):
    fig = plots.evolution(linear)
    _readable(fig)
    amp_ax = fig.axes[1] if fig.axes[1].get_yscale() == "log" else fig.axes[2]
    assert amp_ax.get_yscale() == "log"
    n, amp = bands.order_amplitudes(linear.u.values)
    styles = {}
    for line in amp_ax.lines:
        order = int(line.get_label().split()[1].rstrip(":"))
        np.testing.assert_allclose(line.get_ydata(), np.maximum(amp[:, order - 1] / UM, amp_ax.get_ylim()[0] * 1.3))
        styles[order] = line.get_linestyle()
    growing = [k for k in styles if amp[-1, k - 1] > amp[0, k - 1]]
    decaying = [k for k in styles if amp[-1, k - 1] < amp[0, k - 1]]
    assert growing and decaying  # the Fourier technique: the P2 orders grow, others decay
    assert all(styles[k] == "-" for k in growing) and all(styles[k] == "--" for k in decaying)
