"""The wheelset wear on tables of several contacts per wheel (contact_model "multi-hertz",
"semi-hertzian"): each point worn by its own frictional power, the volume the law's, "hertz"
unchanged."""

from dataclasses import replace

import numpy as np
import pytest
import xarray as xr
from helpers import Killed, killed_after

from railwear.dynamics import TableWheelsetModel
from railwear.errors import ScenarioError
from railwear.geometry import contact_table, load_profile
from railwear.longterm.direct import Direct
from railwear.longterm.wheelset_wear import WHEELS, Wheelset, WheelsetWear, sweep_deposit
from railwear.scenario import build, builtin_text, parse_scenario
from railwear.wear import EnergyLaw, WearLaw

SUSPENSION = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6)
SMALL = dict(lateral_edges=np.round(np.linspace(-0.050, 0.040, 91), 12), n_angle=16, transient=2.0,
             output_rate=1000.0)
SHIFTS = np.round(np.linspace(-0.010, 0.010, 201), 12)
MODELS = ("hertz", "multi-hertz", "semi-hertzian")


@pytest.fixture(scope="module")
def tables():
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    return wheel, rail, {m: contact_table(wheel, rail, y=SHIFTS, contact_model=m) for m in MODELS}


def make(tables, model, speed=60.0, law=None, creep_law="cubic", **options):
    wheel, rail, by_model = tables
    dynamics = TableWheelsetModel(speed=speed, **SUSPENSION, table=by_model[model], friction_coefficient=0.3,
                                  creep_law=creep_law)
    return WheelsetWear(dynamics, wheel, rail, law or EnergyLaw(), 1e6, contact_model=model, **{**SMALL, **options})


class PowerTimesBeta(WearLaw, name="test-power-times-beta"):
    """The energy law's rate without declaring its beta: the deposit takes the law's own path."""

    def volume_rate_of(self, contact):
        return EnergyLaw().beta * np.asarray(contact.frictional_power)


def todays_deposit(p, surfaces, ds, table, phase):
    """The deposit of the single-point wheelset wear before several contacts (energy law)."""
    t = ds.time.values
    shift = -0.5 * (ds.lateral_displacement.values[1:] + ds.lateral_displacement.values[:-1])
    at = {(wheel, v): np.interp(shift, table.y.values, table[v].sel(side=wheel).values)
          for wheel in WHEELS for v in ("a", "b", "rolling_radius")}
    turned = 2 * p.model.speed * np.diff(t) / (at["left", "rolling_radius"] + at["right", "rolling_radius"])
    angle = phase + np.concatenate([[0.0], np.cumsum(turned)])
    added = law = 0.0
    for surface, wheel in zip(surfaces, WHEELS):
        power = ds.frictional_power.sel(wheel=wheel).values
        volume = p.beta * 0.5 * (power[1:] + power[:-1]) * np.diff(t)
        position = ds.contact_lateral_position.sel(wheel=wheel).values
        added += sweep_deposit(surface, volume, angle[:-1], angle[1:], 0.5 * (position[1:] + position[:-1]),
                               at[wheel, "a"], at[wheel, "b"], p.footprint)
        law += float(volume.sum())
    return added, law, float(angle[-1])


def test_hertz_deposits_as_before_bit_for_bit(tables):
    """contact_model = "hertz" (the default): the surfaces, volumes and end angle of a hunting run
    are today's single-point deposit's to the bit, and its checkpoint fingerprint has no new part."""
    p = make(tables, "hertz")
    assert WheelsetWear(p.model, p.wheel, p.rail, EnergyLaw(), 1e6).contact_model == "hertz"
    table = tables[2]["hertz"]
    ds, _ = p.run(table, 0.5, offset=2e-3)
    new, old = (p.new_surface(), p.new_surface()), (p.new_surface(), p.new_surface())
    assert p.deposit(new, ds, table, 1.3) == todays_deposit(p, old, ds, table, 1.3)
    for a, b in zip(new, old):
        np.testing.assert_array_equal(a.depth, b.depth)
    assert old[0].depth.max() > 0
    parts = Wheelset(p).fingerprint_parts()
    assert len(parts) == 19 and parts[-1] == p.radius  # the parts of before: hertz checkpoints stay valid


@pytest.mark.parametrize("model, creep_law", [("multi-hertz", "cubic"), ("semi-hertzian", "cubic"),
                                              ("semi-hertzian", "strip-fastsim")])
def test_removed_volume_is_the_law_of_the_summed_point_powers(tables, model, creep_law):
    """Hunting at 60 m/s for 0.5 s (strip-wise FASTSIM 0.25 s) on a table of several contacts per
    wheel: the volume each surface receives, summed over the points (on the semi-hertzian table
    over their strips), equals beta times the trapezoidal integral of the wheel's frictional power
    (the sum of its contacts' own powers), to 1e-12; a law without a declared beta (rate of each
    point's power) puts down the same surfaces to 1e-12."""
    table = tables[2][model]
    p = make(tables, model, creep_law=creep_law)
    ds, _ = p.run(table, 0.5 if creep_law == "cubic" else 0.25, offset=2e-3)
    assert ("point_strip_frictional_power" in ds) == (creep_law == "strip-fastsim")
    assert np.abs(ds.lateral_displacement.values).max() > 1e-3  # the contact moves over the table's shifts
    np.testing.assert_allclose(ds.point_frictional_power.sum("point"), ds.frictional_power, rtol=1e-12)
    surfaces = (p.new_surface(), p.new_surface())
    added, law, _ = p.deposit(surfaces, ds, table, 0.4)
    power = ds.frictional_power.values
    expected = p.beta * float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(ds.time.values)[:, None]))
    assert law == pytest.approx(expected, rel=1e-12)
    assert added == pytest.approx(expected, rel=1e-12)
    assert sum(s.removed_volume() for s in surfaces) == pytest.approx(expected, rel=1e-12)
    other = make(tables, model, law=PowerTimesBeta(), creep_law=creep_law)
    again = (p.new_surface(), p.new_surface())
    assert other.deposit(again, ds, table, 0.4)[1] == pytest.approx(expected, rel=1e-12)
    for a, b in zip(again, surfaces):
        np.testing.assert_allclose(a.depth, b.depth, rtol=1e-12, atol=1e-12 * b.depth.max())


def steady(table_shift, tracks, seconds=0.01, power=((560.0, 240.0), (900.0, 300.0)), n=21):
    """A run standing at the table shift ``table_shift`` (m) with constant frictional powers of the
    contacts (W; left and right, of the contacts holding the table's points 0 and 1 there, as
    ``point_tracks`` follows them)."""
    t = np.linspace(0.0, seconds, n)
    node = int(np.searchsorted(SHIFTS, table_shift, side="right") - 1)
    points = np.zeros((n, 2, tracks["left"].shape[1]))
    for w, wheel in enumerate(WHEELS):
        for point, value in enumerate(power[w]):
            points[:, w, list(tracks[wheel][node]).index(point)] = value
    creep = {f"point_{v}_creepage": (("time", "wheel", "point"), np.full(points.shape, value))
             for v, value in (("longitudinal", 1e-3), ("lateral", 5e-4), ("spin", 0.05))}
    return xr.Dataset({
        "lateral_displacement": ("time", np.full(n, -table_shift)),
        "frictional_power": (("time", "wheel"), np.tile(np.sum(power, 1), (n, 1))),
        "point_frictional_power": (("time", "wheel", "point"), points), **creep,
    }, coords={"time": t, "wheel": list(WHEELS)})


@pytest.mark.parametrize("model", ["multi-hertz", "semi-hertzian"])
@pytest.mark.parametrize("shift", [0.0, 0.00005, 0.00013])
def test_two_points_each_receive_their_own_power(tables, model, shift):
    """S1002/UIC60 near y = 0 has two contacts per wheel. With the two moved 45 mm apart on the
    wheel (the table otherwise as built; semi-hertzian: their strips with them), the volume under
    each is beta times its own frictional power times the time, on a node and between nodes, to
    1e-12; each footprint is the point's own semi-axes or strips (the band of the lone narrow point
    is within its 2 b)."""
    from railwear.dynamics.table_wheelset import point_tracks

    table = tables[2][model].copy(deep=True)
    loaded = table.point_normal_force.values > 0
    assert np.all(loaded.sum(-1)[97:104] == 2)  # two contacts from -0.3 to 0.3 mm
    y = table.point_wheel_y.values.copy()
    moved = y.copy()
    moved[..., 0], moved[..., 1] = np.where(loaded[..., 0], 0.015, np.nan), np.where(loaded[..., 1], -0.030, np.nan)
    table["point_wheel_y"] = (table.point_wheel_y.dims, moved)
    if "point_strip_wheel_y" in table:
        table["point_strip_wheel_y"] = (table.point_strip_wheel_y.dims,
                                        table.point_strip_wheel_y.values + (moved - y)[..., None])
    p = make(tables, model, n_angle=64)
    power = ((560.0, 240.0), (900.0, 300.0))
    ds = steady(shift, point_tracks(table), power=power)
    surfaces = (p.new_surface(), p.new_surface())
    added, law, _ = p.deposit(surfaces, ds, table, 0.0)
    k = np.searchsorted(SHIFTS, shift, side="right") - 1
    lateral = p.lateral
    for surface, wheel, own in zip(surfaces, WHEELS, power):
        per_cell = surface.depth.sum(0) * surface.cell_area
        for point, side in ((0, lateral > -0.0075), (1, lateral < -0.0075)):
            assert per_cell[side].sum() == pytest.approx(p.beta * own[point] * 0.01, rel=1e-12)
        b = table.point_b.sel(side=wheel).values[k, 1]
        worn = lateral[(per_cell > 0) & (lateral < -0.0075)]
        assert worn.max() - worn.min() <= 2 * b + (lateral[1] - lateral[0])
    assert added == pytest.approx(law, rel=1e-12)
    assert law == pytest.approx(p.beta * np.sum(power) * 0.01, rel=1e-12)


@pytest.mark.parametrize("model", ["multi-hertz", "semi-hertzian"])
def test_a_run_wears_every_loaded_point_and_keeps_the_volume(tables, model):
    """Centred running at 30 m/s (no hunting) for 0.2 units of normed time, direct, on the new
    contact: the worn band holds both contacts of y = 0 (depth above 1 % of the deepest within
    1 mm of each point), removed volume equals the law's to 1e-12; the contact range reported is
    that of the loaded points (at least the 9.2 / 10.9 mm between them)."""
    p = make(tables, model, speed=30.0)
    ds = Direct(Wheelset(p, update_seconds=0.25), 2e4, n_save=None).run(until=0.2)
    np.testing.assert_allclose(ds.removed_volume.values, ds.law_volume.values, rtol=1e-12)
    depth = ds.worn_depth.values[-1].mean(0)
    points = tables[2][model].point_wheel_y.sel(y=0.0, side="right").values[:2]
    for point in points:
        near = np.abs(p.lateral - point) < 1e-3
        assert depth[near].max() > 0.01 * depth.max()
    assert float(ds.contact_max[1] - ds.contact_min[1]) >= abs(points[0] - points[1]) - 1e-9


def test_a_checkpoint_of_another_contact_model_is_refused(tables):
    """A direct run on "hertz" killed after one update: resumed as "semi-hertzian" it is refused
    in one line (the contact model is part of the problem)."""
    p = make(tables, "hertz")
    strategy = Direct(Wheelset(p, update_seconds=0.1), 2e3, n_save=None, seed=3)
    saved = []
    with pytest.raises(Killed):
        strategy.run(until=0.036, checkpoint=killed_after(1, saved))
    other = Direct(Wheelset(replace(p, contact_model="semi-hertzian"), update_seconds=0.1), 2e3, n_save=None, seed=3)
    with pytest.raises(ScenarioError, match="another wheelset problem") as err:
        other.run(until=0.036, resume=saved[-1])
    assert "\n" not in str(err.value)


def test_a_bad_contact_model_is_a_one_line_error(tables):
    with pytest.raises(ScenarioError, match="contact_model") as err:
        WheelsetWear(make(tables, "hertz").model, tables[0], tables[1], EnergyLaw(), 1e6,
                     contact_model="kalker")
    assert "\n" not in str(err.value) and "'kalker'" in str(err.value)
    text = builtin_text("wheelset-wear").replace('rail_profile = "UIC60"\n',
                                                  'rail_profile = "UIC60"\ncontact_model = "kalker"\n')
    with pytest.raises(ScenarioError, match="body.contact_model") as err:
        parse_scenario(text)
    assert "\n" not in str(err.value)


def test_the_scenario_builds_the_problem_on_its_contact_model():
    """[wheelset_wear] contact_model reaches the model's table and the problem's tables."""
    text = builtin_text("wheelset-wear").replace('rail_profile = "UIC60"\n',
                                                  'rail_profile = "UIC60"\ncontact_model = "semi-hertzian"\n')
    sc = parse_scenario(text)
    p = sc.body.problem(sc)
    assert p.contact_model == "semi-hertzian" and p.model.table.attrs["contact_model"] == "semi-hertzian"
    assert p.table(np.zeros(p.lateral.size)).attrs["contact_model"] == "semi-hertzian"
    sc = parse_scenario(builtin_text("wheelset-wear"))
    assert sc.body.problem(sc).contact_model == "hertz"


def test_without_strips_the_points_wear_under_their_ellipses_as_before(tables):
    """Multi-hertz tables (no strips), and a semi-hertzian table without its strip variables, wear
    each point under its own ellipse, as before the strips: the surfaces are those of
    sweep_deposit over point_volumes, to the bit (against the previous commit's code the
    multi-hertz surfaces of this run were compared to the bit too)."""
    for model, table in (("multi-hertz", tables[2]["multi-hertz"]),
                         ("semi-hertzian", tables[2]["semi-hertzian"].drop_vars(
                             [v for v in tables[2]["semi-hertzian"].data_vars if v.startswith("point_strip")]
                             + ["strip"]))):
        p = make(tables, model)
        ds, _ = p.run(table, 0.2, offset=2e-3)
        new = (p.new_surface(), p.new_surface())
        p.deposit(new, ds, table, 0.7)
        t = ds.time.values
        shift = -0.5 * (ds.lateral_displacement.values[1:] + ds.lateral_displacement.values[:-1])
        radii = sum(np.interp(shift, table.y.values, table.rolling_radius.sel(side=w).values) for w in WHEELS)
        angle = 0.7 + np.concatenate([[0.0], np.cumsum(2 * p.model.speed * np.diff(t) / radii)])
        for surface, wheel in zip(new, WHEELS):
            old = p.new_surface()
            interval, volume, position, a, b = p.point_volumes(ds, table, wheel)
            sweep_deposit(old, volume, angle[interval], angle[interval + 1], position, a, b, p.footprint)
            np.testing.assert_array_equal(surface.depth, old.depth)
            assert old.depth.max() > 0


def with_strips(table, wheel, half_length, lateral, width):
    """``table`` (deep copy) with the strips of every loaded point of ``wheel`` replaced:
    ``half_length(pt)``, ``lateral(pt)`` (m, on the wheel profile) and ``width(pt)`` (in the contact
    plane) from the point's row ``pt``."""
    t = table.copy(deep=True)
    side = list(t.side.values).index(wheel)
    L, y, w = (t[v].values for v in ("point_strip_half_length", "point_strip_wheel_y", "point_strip_width"))
    for j in range(t.sizes["y"]):
        for i in range(t.sizes["point"]):
            pt = t.isel(y=j, side=side, point=i)
            if float(pt.point_normal_force) > 0:
                L[j, side, i], y[j, side, i], w[j, side, i] = half_length(pt), lateral(pt), width(pt)
    return t


def strip_run(table, shift, wheel, point_power, strip_power=None, creepage=(1e-3, 5e-4, 0.0), n=11):
    """A run standing at the table's ``shift`` with constant powers of ``wheel``'s contacts (W, by
    the table's point numbers there; the other wheel none), the contacts' creepages ``creepage``
    (xi, eta, phi) and optionally each strip's power (``{point: array}``)."""
    from railwear.dynamics.table_wheelset import point_tracks

    tracks = point_tracks(table)
    node = int(np.argmin(np.abs(table.y.values - shift)))
    contacts = tracks["left"].shape[1]
    w = WHEELS.index(wheel)
    points = np.zeros((n, 2, contacts))
    strips = np.zeros((n, 2, contacts, table.sizes["strip"]))
    for point, value in point_power.items():
        c = list(tracks[wheel][node]).index(point)
        points[:, w, c] = value
        if strip_power is not None:
            strips[:, w, c] = strip_power[point]
    data = {"lateral_displacement": ("time", np.full(n, -shift)),
            "frictional_power": (("time", "wheel"), points.sum(-1)),
            "point_frictional_power": (("time", "wheel", "point"), points)}
    for name, value in zip(("longitudinal", "lateral", "spin"), creepage):
        data[f"point_{name}_creepage"] = (("time", "wheel", "point"), np.full(points.shape, value))
    if strip_power is not None:
        data["point_strip_frictional_power"] = (("time", "wheel", "point", "strip"), strips)
    return xr.Dataset(data, coords={"time": np.linspace(0.0, 0.01, n), "wheel": list(WHEELS)})


def test_a_hertz_like_patch_on_its_strips_gives_the_ellipse_footprint(tables):
    """Every loaded patch of the semi-hertzian table given the 32 strips of its own equivalent
    ellipse (half-lengths a sqrt(1 - s^2/b^2), 2 b across on the wheel profile), powers of the two
    contacts at y = 0 under the cubic law without spin (each strip's share its share of the load),
    against the ellipse footprint of the wear of before: cut into the strips' 32 bands across, the
    lateral depth is the ellipse's to 1e-12 and the surface over angle x lateral within 1 % (8
    pieces along rolling against 32); against the ellipse's 8 bands of before (sweep_deposit's
    default) the lateral depth differs by 5.2 % (L1, relative; the 8-band staircase on 1 mm cells).
    The volume is the same to 1e-12."""
    table = tables[2]["semi-hertzian"]
    n = table.sizes["strip"]
    centres = (np.arange(n) + 0.5) / n * 2 - 1  # in units of b
    hertz_like = with_strips(
        table, "right",
        lambda pt: float(pt.point_a) * np.sqrt(1 - centres ** 2),
        lambda pt: float(pt.point_wheel_y) + float(pt.point_b) * centres,
        lambda pt: 2 * float(pt.point_b) / n / np.cos(float(pt.point_contact_angle)))
    ellipse = table.drop_vars([v for v in table.data_vars if v.startswith("point_strip")] + ["strip"])
    p = make(tables, "semi-hertzian", n_angle=64)
    ds = strip_run(table, 0.0, "right", {0: 700.0, 1: 300.0})
    pair = (p.new_surface(), p.new_surface())
    added, _, _ = p.deposit(pair, ds, hertz_like, 0.3)
    assert added == pytest.approx(p.beta * 1000.0 * 0.01, rel=1e-12)
    strips = pair[1].depth
    turned = 2 * p.model.speed * np.diff(ds.time.values) / float(ellipse.rolling_radius.sel(y=0.0).sum())
    angle = 0.3 + np.concatenate([[0.0], np.cumsum(turned)])
    interval, volume, position, a, b = p.point_volumes(ds, ellipse, "right")
    for bands, lateral_tol, tol in ((n, 1e-12, 0.01), (8, 0.06, 0.06)):
        old = p.new_surface()
        sweep_deposit(old, volume, angle[interval], angle[interval + 1], position, a, b, "hertz", n=bands)
        lateral = strips.sum(0), old.depth.sum(0)
        assert np.abs(lateral[0] - lateral[1]).sum() / lateral[1].sum() < lateral_tol
        assert np.abs(strips - old.depth).sum() / old.depth.sum() < tol
    assert np.abs(lateral[0] - lateral[1]).sum() / lateral[1].sum() > 0.04  # the 8 bands of before


def test_the_lateral_distribution_follows_the_strips_of_a_two_lobe_patch(tables):
    """The main patch at y = 0 with its middle quarter of strips empty (two lobes), each strip's
    power given (strip-wise FASTSIM: 70 % on the outer lobe, 30 % on the inner): the wear under each
    lobe is its share of the contact's power to 1e-12 and none falls in the gap, where the
    equivalent ellipse (the wear of before) puts its deepest band."""
    table = tables[2]["semi-hertzian"]
    n = table.sizes["strip"]
    gap = slice(n // 2 - n // 8, n // 2 + n // 8)
    row = table.sel(y=0.0, side="right").isel(point=0)
    L = row.point_strip_half_length.values.copy()
    L[gap] = 0.0
    main = lambda pt: np.isclose(float(pt.point_wheel_y), float(row.point_wheel_y))  # noqa: E731
    lobes = with_strips(table, "right", lambda pt: L if main(pt) else pt.point_strip_half_length.values,
                        lambda pt: pt.point_strip_wheel_y.values, lambda pt: float(pt.point_strip_width))
    power = np.zeros(n)
    left, right = np.arange(n) < gap.start, np.arange(n) >= gap.stop
    power[left], power[right] = 700.0 / left.sum(), 300.0 / right.sum()
    p = make(tables, "semi-hertzian", n_angle=64)
    ds = strip_run(table, 0.0, "right", {0: 1000.0}, {0: power})
    pair = (p.new_surface(), p.new_surface())
    p.deposit(pair, ds, lobes, 0.0)
    per_cell = pair[1].depth.sum(0) * pair[1].cell_area
    y = row.point_strip_wheel_y.values
    split = 0.5 * (y[gap.start] + y[gap.stop - 1])
    cell = p.lateral[1] - p.lateral[0]
    assert per_cell[p.lateral < split].sum() == pytest.approx(p.beta * 700.0 * 0.01, rel=1e-12)
    assert per_cell[p.lateral > split].sum() == pytest.approx(p.beta * 300.0 * 0.01, rel=1e-12)
    half_width = 0.5 * float(row.point_strip_width) * np.cos(float(row.point_contact_angle))
    inside = (p.lateral - cell / 2 > y[gap.start - 1] + half_width) & (p.lateral + cell / 2 < y[gap.stop] - half_width)
    assert inside.sum() >= 2 and np.all(per_cell[inside] == 0)
    ellipse = table.drop_vars([v for v in table.data_vars if v.startswith("point_strip")] + ["strip"])
    before = (p.new_surface(), p.new_surface())
    p.deposit(before, ds, ellipse, 0.0)
    old = before[1].depth.sum(0)
    assert old[inside].min() > 0.8 * old.max()
