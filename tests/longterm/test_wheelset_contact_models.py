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


def make(tables, model, speed=60.0, law=None, **options):
    wheel, rail, by_model = tables
    dynamics = TableWheelsetModel(speed=speed, **SUSPENSION, table=by_model[model], friction_coefficient=0.3)
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


@pytest.mark.parametrize("model", ["multi-hertz", "semi-hertzian"])
def test_removed_volume_is_the_law_of_the_summed_point_powers(tables, model):
    """Hunting at 60 m/s for 0.5 s on a table of several contacts per wheel: the volume each
    surface receives, summed over the points, equals beta times the trapezoidal integral of the
    wheel's frictional power (the sum of its contacts' own powers), to 1e-12; a law without a declared
    beta (rate of each point's power) puts down the same surfaces to 1e-12."""
    table = tables[2][model]
    p = make(tables, model)
    ds, _ = p.run(table, 0.5, offset=2e-3)
    assert np.abs(ds.lateral_displacement.values).max() > 1e-3  # the contact moves over the table's shifts
    np.testing.assert_allclose(ds.point_frictional_power.sum("point"), ds.frictional_power, rtol=1e-12)
    surfaces = (p.new_surface(), p.new_surface())
    added, law, _ = p.deposit(surfaces, ds, table, 0.4)
    power = ds.frictional_power.values
    expected = p.beta * float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(ds.time.values)[:, None]))
    assert law == pytest.approx(expected, rel=1e-12)
    assert added == pytest.approx(expected, rel=1e-12)
    assert sum(s.removed_volume() for s in surfaces) == pytest.approx(expected, rel=1e-12)
    other = make(tables, model, law=PowerTimesBeta())
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
    return xr.Dataset({
        "lateral_displacement": ("time", np.full(n, -table_shift)),
        "frictional_power": (("time", "wheel"), np.tile(np.sum(power, 1), (n, 1))),
        "point_frictional_power": (("time", "wheel", "point"), points),
    }, coords={"time": t, "wheel": list(WHEELS)})


@pytest.mark.parametrize("model", ["multi-hertz", "semi-hertzian"])
@pytest.mark.parametrize("shift", [0.0, 0.00005, 0.00013])
def test_two_points_each_receive_their_own_power(tables, model, shift):
    """S1002/UIC60 near y = 0 has two contacts per wheel. With the two moved 45 mm apart on the
    wheel (the table otherwise as built), the volume under each is beta times its own frictional
    power times the time, on a node and between nodes, to 1e-12; each footprint is the point's own
    semi-axes (the band of the lone narrow point is within its 2 b)."""
    from railwear.dynamics.table_wheelset import point_tracks

    table = tables[2][model].copy(deep=True)
    loaded = table.point_normal_force.values > 0
    assert np.all(loaded.sum(-1)[97:104] == 2)  # two contacts from -0.3 to 0.3 mm
    y = table.point_wheel_y.values
    y[..., 0], y[..., 1] = np.where(loaded[..., 0], 0.015, np.nan), np.where(loaded[..., 1], -0.030, np.nan)
    table["point_wheel_y"] = (table.point_wheel_y.dims, y)
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
    with pytest.raises(ScenarioError, match="wheelset_wear.contact_model") as err:
        parse_scenario(text)
    assert "\n" not in str(err.value)


def test_the_scenario_builds_the_problem_on_its_contact_model():
    """[wheelset_wear] contact_model reaches the model's table and the problem's tables."""
    text = builtin_text("wheelset-wear").replace('rail_profile = "UIC60"\n',
                                                  'rail_profile = "UIC60"\ncontact_model = "semi-hertzian"\n')
    p = build.wheelset_wear(parse_scenario(text))
    assert p.contact_model == "semi-hertzian" and p.model.table.attrs["contact_model"] == "semi-hertzian"
    assert p.table(np.zeros(p.lateral.size)).attrs["contact_model"] == "semi-hertzian"
    assert build.wheelset_wear(parse_scenario(builtin_text("wheelset-wear"))).contact_model == "hertz"
