"""The table wheelset and bogie on several contacts per wheel: each contact evaluated on its own
(its angle, radius, spin, Kalker coefficients and saturation), the forces summed."""

import numpy as np
import pytest
import xarray as xr

from railwear.contact.constants import creep_coefficients, shear_modulus
from railwear.dynamics import TableBogieModel, TableWheelsetModel, critical_speed, kernels, simulate
from railwear.dynamics.table_wheelset import point_tracks
from railwear.geometry import contact_table, load_profile

SUSPENSION = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6)
SHIFTS = np.round(np.linspace(-0.010, 0.010, 201), 12)
FIELDS = ("rolling_radius", "contact_angle", "normal_force", "wheel_y", "a", "b", "f11", "f22", "f23", "f33")


@pytest.fixture(scope="module")
def hertz():
    return contact_table(load_profile("S1002"), load_profile("UIC60"), y=SHIFTS)


def wheel_contact(h):
    """The hertz table's one contact per wheel as the fields of a point (arrays over y, side)."""
    shear = shear_modulus(float(h.attrs["youngs_modulus"]), float(h.attrs["poisson"]))
    f = creep_coefficients(shear, h.a.values, h.b.values, *(h[c].values for c in ("c11", "c22", "c23", "c33")))
    point = {name: h[name].values for name in ("rolling_radius", "contact_angle", "normal_force", "a", "b")}
    point["wheel_y"] = h.wheel_contact_y.values
    point.update(zip(("f11", "f22", "f23", "f33"), f))
    return point


def with_points(h, points):
    """The table ``h`` with a ``point`` dimension holding ``points`` (dicts of FIELDS over y, side)."""
    t = h.copy()
    for name in FIELDS:
        t[f"point_{name}"] = (("y", "side", "point"), np.stack([p[name] for p in points], -1))
    normal = t.point_normal_force.values
    t["point_creep_share"] = (("y", "side", "point"), t.point_f11.values / t.point_f11.values.sum(-1, keepdims=True))
    t["contact_count"] = (("y", "side"), (normal > 0).sum(-1))
    return t


def unloaded(h):
    """A second contact that carries no load anywhere (its geometry that of a flange)."""
    shape = h.normal_force.shape
    point = {name: np.zeros(shape) for name in FIELDS}
    point.update(rolling_radius=np.full(shape, 0.47), contact_angle=np.full(shape, 0.6), wheel_y=np.full(shape, -0.035),
                 a=np.full(shape, 2e-3), b=np.full(shape, 1e-3))
    return point


def scaled(point, share, load_share=None, **changes):
    out = dict(point)
    for name in ("f11", "f22", "f23", "f33"):
        out[name] = share * point[name]
    out["normal_force"] = (share if load_share is None else load_share) * point["normal_force"]
    out.update(changes)
    return out


def flange_pair(h, load_share=0.3, creep_share=0.3):
    """Two contacts per wheel: the hertz one with the rest of the load and creep coefficients, and
    one 0.3 rad steeper on a 4 mm larger radius, 20 mm towards the flange."""
    c = wheel_contact(h)
    tread = scaled(c, 1 - creep_share, 1 - load_share)
    flange = scaled(c, creep_share, load_share, contact_angle=c["contact_angle"] + 0.3,
                    rolling_radius=c["rolling_radius"] + 0.004, wheel_y=c["wheel_y"] - 0.020, b=0.5 * c["b"])
    return with_points(h, [tread, flange])


def assert_same(a, b):
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)


def held_at_centre(h, point):
    """``point`` with its position on the wheel profile held at the table's y = 0 value: its lever
    arm is then the half gauge-point distance ``e`` at every shift."""
    out = dict(point)
    centre = int(np.flatnonzero(h.y.values == 0.0)[0])
    out["wheel_y"] = np.broadcast_to(point["wheel_y"][centre], point["wheel_y"].shape).copy()
    return out


def test_hertz_table_with_an_unloaded_second_point_is_bit_identical(hertz):
    """The hertz table (no points: the resultant path, lever arm e) against the same table with a
    point dimension of the same contact and a second one without load (evaluated contact by
    contact, each on its own lever arm ``e + (position - position at y = 0)``), the contact's
    position held at its y = 0 value so that its lever arm is e: the wheelset's and the bogie's runs
    (hunting, mu = 0.3), right-hand sides and state matrices agree to the bit, and the one
    contact's power is the wheel's. With the contact's own position, the right-hand side at
    y = 0 is still the resultant's to the bit, and off centre the yaw moment differs by the lever
    arm's change (test_two_contact_angles_against_a_hand_computation checks it)."""
    moving = with_points(hertz, [wheel_contact(hertz), unloaded(hertz)])
    model = TableWheelsetModel(speed=60.0, **SUSPENSION, table=moving)
    resultant = TableWheelsetModel(speed=60.0, **SUSPENSION, table=hertz)
    for y, same in (([0.0, 1e-3, 0.05, -0.1], True), ([3e-3, 1e-3, 0.05, -0.1], False)):
        out = [np.empty(4), np.empty(4)]
        for m, o in zip((resultant, model), out):
            kernels.rhs(m.kind, 0.0, np.array(y), m.params(), m.surface(), o)
        assert np.array_equal(out[0], out[1]) == same
        assert np.array_equal(out[0][:3], out[1][:3])  # the lever arm moves the yaw moment only
    points = with_points(hertz, [held_at_centre(hertz, wheel_contact(hertz)), unloaded(hertz)])
    plain = TableWheelsetModel(speed=60.0, **SUSPENSION, table=hertz, friction_coefficient=0.3,
                               initial_lateral_displacement=3e-3)
    each = TableWheelsetModel(speed=60.0, **SUSPENSION, table=points, friction_coefficient=0.3,
                              initial_lateral_displacement=3e-3)
    assert plain.contacts == 0 and each.contacts == 1
    a, b = simulate(plain, 1.0, n_output=501), simulate(each, 1.0, n_output=501)
    assert_same(a, b)
    assert a.attrs["rhs_evaluations"] == b.attrs["rhs_evaluations"]
    assert np.abs(a.lateral_displacement.values).max() > 2e-3
    rows = each.point_outputs(b)
    np.testing.assert_array_equal(rows.point_frictional_power.sel(point=0).values, b.frictional_power.values)
    np.testing.assert_array_equal(rows.point_normal_force.sel(point=0).values, b.normal_force.values)
    np.testing.assert_array_equal(plain.state_matrix(70.0), each.state_matrix(70.0))
    rng = np.random.default_rng(7)
    for y in rng.uniform(-1, 1, (20, 4)) * [9e-3, 3e-3, 0.1, 0.1]:
        out = [np.empty(4), np.empty(4)]
        for model, o in zip((plain, each), out):
            kernels.rhs(model.kind, 0.0, y, model.params(), model.surface(), o)
        np.testing.assert_array_equal(out[0], out[1])
    bogies = [TableBogieModel.cooperrider(35.0, t, friction_coefficient=0.3) for t in (hertz, points)]
    a, b = (simulate(m, 0.5, n_output=251) for m in bogies)
    assert_same(a, b)
    np.testing.assert_array_equal(bogies[0].state_matrix(30.0), bogies[1].state_matrix(30.0))
    power = bogies[1].point_outputs(b).point_frictional_power.sel(point=0)
    np.testing.assert_array_equal(power.sel(wheel="left").values, b.frictional_power_left.values)


def test_two_points_of_one_geometry_are_the_resultant(hertz):
    """One wheel contact split into two of the same angle, radius and position (60 / 40 % of its
    load and creep coefficients; the position held at y = 0, lever arm e): in the linear range (no
    saturation) the right-hand sides and the per-wheel outputs are the resultant's to 1e-12."""
    c = held_at_centre(hertz, wheel_contact(hertz))
    split = with_points(hertz, [scaled(c, 0.6), scaled(c, 0.4)])
    plain = TableWheelsetModel(speed=50.0, **SUSPENSION, table=hertz)
    each = TableWheelsetModel(speed=50.0, **SUSPENSION, table=split)
    assert each.contacts >= 2
    rng = np.random.default_rng(3)
    ys = rng.uniform(-1, 1, (200, 4)) * [9e-3, 3e-3, 0.1, 0.1]
    for y in ys:
        out = [np.empty(4), np.empty(4)]
        for model, o in zip((plain, each), out):
            kernels.rhs(model.kind, 0.0, y, model.params(), model.surface(), o)
        np.testing.assert_allclose(out[1], out[0], rtol=1e-12, atol=1e-12 * np.abs(out[0]).max())
    rows = [kernels.outputs(m.kind, np.zeros(len(ys)), ys, m.params(), m.surface(), kernels.TW_N_OUTPUTS)
            for m in (plain, each)]
    for column in range(kernels.TW_N_OUTPUTS):
        np.testing.assert_allclose(rows[1][:, column], rows[0][:, column], rtol=1e-12,
                                   atol=1e-12 * np.abs(rows[0][:, column]).max(), err_msg=str(column))


def hand(table, lat, yaw, vlat, vyaw, speed, mu, e0):
    """Lateral force and yaw moment of the contacts on the wheelset (Kalker's linear creep of each
    contact in its own plane, each saturated by the cubic law at its own mu N, the normal forces'
    lateral components), from the table interpolated at the table's shift ``-lat``; and each
    contact's creep force magnitude against its limit."""
    at = lambda name, side: np.array([np.interp(-lat, table.y.values, table[name].sel(side=side, point=i).values)  # noqa: E731
                                      for i in range(table.sizes["point"])])
    radius = {s: np.interp(-lat, table.y.values, table.rolling_radius.sel(side=s).values) for s in ("left", "right")}
    spin = 2 * speed / (radius["left"] + radius["right"])
    force = moment = 0.0
    limits = {}
    for side, sign in (("left", 1.0), ("right", -1.0)):
        r, g, n = at("point_rolling_radius", side), at("point_contact_angle", side), at("point_normal_force", side)
        f11, f22, f23, f33 = (at(f"point_{c}", side) for c in ("f11", "f22", "f23", "f33"))
        y0 = float(table.wheel_contact_y.sel(y=0.0, side=side))
        lever = e0 + (at("point_wheel_y", side) - y0)  # the contact's own distance from the centre
        xi = (speed - spin * r) / speed - sign * lever * vyaw / speed
        eta = (vlat / speed - yaw) / np.cos(g)
        phi = vyaw * np.cos(g) / speed - sign * np.sin(g) / r
        fx, fy, mz = -f11 * xi, -f22 * eta - f23 * phi, f23 * eta - f33 * phi
        u = np.hypot(fx, fy) / (mu * n)
        factor = np.where(u < 3, 1 - u / 3 + u * u / 27, 1 / np.maximum(u, 3))
        fx, fy, mz = fx * factor, fy * factor, mz * factor
        force += np.sum(fy * np.cos(g) - sign * n * np.sin(g))
        moment += np.sum(mz * np.cos(g) - sign * lever * fx)
        limits[side] = np.hypot(fx, fy), mu * n, u
    return force, moment, limits


@pytest.mark.parametrize("mu", [np.inf, 0.3])
def test_two_contact_angles_against_a_hand_computation(hertz, mu):
    """A tread contact and a flange-like one (0.3 rad steeper, 4 mm larger radius, 30 % of the
    load): the wheelset's lateral force and yaw moment are the sums of each contact's own creep
    forces (each on its own lever arm, e plus its offset on the wheel profile from the y = 0
    contact) and normal force, as computed by hand, to 1e-10, between table nodes and on both sides
    of the tread's jump."""
    table = flange_pair(hertz)
    model = TableWheelsetModel(speed=45.0, **SUSPENSION, table=table, friction_coefficient=mu,
                               lateral_damping=1e4, yaw_damping=2e3)
    p, surf = model.params(), model.surface()
    e0 = p[kernels.TW_HALF_GAUGE]
    for y in ([2.345e-3, 1e-3, 0.02, -0.03], [-4.567e-3, -2e-3, -0.05, 0.04], [0.3e-3, 0.0, 0.0, 0.0],
              [-6.05e-3, 4e-4, 0.01, 0.1]):
        y = np.array(y)
        out = np.empty(4)
        kernels.rhs(model.kind, 0.0, y, p, surf, out)
        force = out[2] * model.mass + model.lateral_stiffness * y[0] + model.lateral_damping * y[2]
        moment = out[3] * model.yaw_inertia + model.yaw_stiffness * y[1] + model.yaw_damping * y[3]
        expected_force, expected_moment, _ = hand(table, *y, 45.0, mu, e0)
        assert force == pytest.approx(expected_force, rel=1e-10, abs=1e-9)
        assert moment == pytest.approx(expected_moment, rel=1e-10, abs=1e-9)


def test_each_contact_saturates_at_its_own_limit(hertz):
    """A flange-like contact with 10 % of the load but half the creep coefficients saturates fully
    at mu N_2 (|F| = mu N_2 to 1e-12) while the tread contact, at the same creepages, does not
    (|F| < mu N_1); the resultant contact (the hertz table) under mu |N| does not saturate either,
    and its force differs."""
    table = flange_pair(hertz, load_share=0.1, creep_share=0.5)
    model = TableWheelsetModel(speed=45.0, **SUSPENSION, table=table, friction_coefficient=0.3)
    state = xr.Dataset({v: ("time", [x]) for v, x in (("lateral_displacement", 1.05e-3), ("yaw_angle", 6e-4),
                                                      ("lateral_velocity", 0.0), ("yaw_rate", 0.0))},
                       coords={"time": [0.0]})
    rows = model.point_outputs(state).isel(time=0)
    _, _, limits = hand(table, 1.05e-3, 6e-4, 0.0, 0.0, 45.0, 0.3, model.params()[kernels.TW_HALF_GAUGE])
    assert len(rows.point) == 2 and np.all(rows.point_normal_force.values > 0)
    for side in ("left", "right"):
        r = rows.sel(wheel=side)
        magnitude = np.hypot(r.point_longitudinal_creep_force.values, r.point_lateral_creep_force.values)
        np.testing.assert_allclose(magnitude, limits[side][0], rtol=1e-12)
        u = limits[side][2]
        assert u[1] > 3 and u[0] < 1.5  # the flange contact fully slides, the tread one is far from it
        assert magnitude[1] == pytest.approx(0.3 * r.point_normal_force.values[1], rel=1e-12)
        assert magnitude[0] < 0.3 * r.point_normal_force.values[0]
    plain = TableWheelsetModel(speed=45.0, **SUSPENSION, table=hertz, friction_coefficient=0.3)
    ds = [simulate(m, 1e-9, n_output=2, initial_state=np.array([1.05e-3, 6e-4, 0.0, 0.0])) for m in (plain, model)]
    wheel = ds[0].isel(time=0)
    resultant = np.hypot(wheel.longitudinal_creep_force, wheel.lateral_creep_force).values
    assert np.all(resultant < 0.3 * wheel.normal_force.values)
    assert np.all(np.abs(ds[1].lateral_creep_force.isel(time=0).values - wheel.lateral_creep_force.values)
                  > 0.05 * np.abs(wheel.lateral_creep_force.values))


@pytest.fixture(scope="module")
def semi():
    return contact_table(load_profile("S1002"), load_profile("UIC60"), y=SHIFTS, contact_model="semi-hertzian")


def resultant_only(table):
    """The table without its point dimension: the dynamics read the per-wheel resultant."""
    return table.drop_vars([v for v in table.data_vars if v.startswith("point_")] + ["point"])


def test_contacts_are_followed_across_the_shifts(semi):
    """The table numbers its contacts by gap, so tread and flange root swap near 5 mm (4.4 to
    5.3 mm, where both carry load); the tracked contacts hold every loaded point of the table once,
    each over one unbroken run of shifts, and move continuously on the wheel profile (under 1.5 mm
    per 0.1 mm shift) between shifts of two contacts each; a lone contact may jump (as the
    per-wheel resultant does)."""
    tracks = point_tracks(semi)
    for side, sign in (("right", 1.0), ("left", -1.0)):
        index = tracks[side]
        position = semi.point_wheel_y.sel(side=side).values
        normal = semi.point_normal_force.sel(side=side).values
        count = (normal > 0).sum(1)
        assert index.shape[1] == 3
        for j in range(SHIFTS.size):
            assert sorted(i for i in index[j] if i >= 0) == sorted(np.flatnonzero(normal[j] > 0))
        for c in range(index.shape[1]):
            rows = np.flatnonzero(index[:, c] >= 0)
            assert np.all(np.diff(rows) == 1)
            step = np.abs(np.diff(position[rows, index[rows, c]]))
            shared = (count[rows[1:]] > 1) & (count[rows[:-1]] > 1)
            assert shared.any() and step[shared].max() < 1.5e-3
        j0, j1 = (int(np.argmin(np.abs(SHIFTS - sign * v))) for v in (0.0045, 0.0052))
        assert np.all(count[[j0, j1]] == 2)
        swapped = [c for c in range(3) if index[j0, c] >= 0 and index[j1, c] >= 0 and index[j0, c] != index[j1, c]]
        assert len(swapped) == 2  # the table's point numbers swap, the contacts do not


def test_linear_critical_speed_on_the_semi_hertzian_table(semi):
    """Each contact on its own (its own lever arm) against the resultant (the same table without
    its points, the dynamics of before): the wheelset's linear critical speed moves from 66.15 to
    68.55 m/s (+3.6 %; 68.51 with the lever arm e for every contact), the Cooperrider bogie's from
    18.87 to 21.49 m/s (+14 %; 21.48)."""
    before = critical_speed(TableWheelsetModel(speed=40.0, **SUSPENSION, table=resultant_only(semi)))
    after = critical_speed(TableWheelsetModel(speed=40.0, **SUSPENSION, table=semi))
    assert before == pytest.approx(66.154, abs=2e-3)
    assert after == pytest.approx(68.548, abs=2e-3)
    before = critical_speed(TableBogieModel.cooperrider(20.0, resultant_only(semi)))
    after = critical_speed(TableBogieModel.cooperrider(20.0, semi))
    assert before == pytest.approx(18.867, abs=2e-3)
    assert after == pytest.approx(21.491, abs=2e-3)


def test_strip_fastsim_creep_law(semi, hertz):
    """creep_law="strip-fastsim" on the semi-hertzian table: each contact's forces are the library's
    strip-wise FASTSIM (railwear.contact.strip_fastsim) on the table's strips at that shift, every
    strip's creepage from its own radius (the first-order part carried by the spin term); the
    cubic law's right-hand side stays as it was (asserted on the same model with creep_law
    "cubic"); the linear critical speed 68.55 -> 78.47 m/s (68.51 -> 78.39 with the lever arm e for
    every contact). Refused on a table without strips."""
    from railwear.contact.strip_fastsim import strip_fastsim
    from railwear.errors import ScenarioError

    cubic = TableWheelsetModel(speed=40.0, **SUSPENSION, table=semi, friction_coefficient=0.3)
    strip = TableWheelsetModel(speed=40.0, **SUSPENSION, table=semi, friction_coefficient=0.3,
                               creep_law="strip-fastsim")
    plain = TableWheelsetModel(speed=40.0, **SUSPENSION, table=semi.drop_vars(
        [v for v in semi.data_vars if v.startswith("point_strip")] + ["strip"]), friction_coefficient=0.3)
    state = np.array([2e-3, 1e-4, 0.01, 0.0])  # table y = -2 mm, a node: no interpolation
    d = [np.zeros(4) for _ in range(3)]
    for m, out in zip((cubic, plain, strip), d):
        kernels.table_wheelset_rhs(0.0, state, m.params(), m.surface(), out)
    assert np.array_equal(d[0], d[1]) and not np.allclose(d[0], d[2], rtol=1e-3)
    rows = kernels.table_point_rows(state[None, :], strip.params(), 0, strip.surface(), np.arange(4))
    rows = rows.reshape(2, strip.contacts, kernels.TW_N_POINT_OUTPUTS)
    row = semi.sel(y=-2e-3, method="nearest")
    tracks = point_tracks(semi)
    j = int(np.argmin(np.abs(semi.y.values + 2e-3)))
    for w, (side, sign) in enumerate((("left", 1.0), ("right", -1.0))):
        for c in range(strip.contacts):
            i = tracks[side][j, c]
            if i < 0:
                continue
            pt = row.sel(side=side).isel(point=i)
            xi, eta, phi = rows[w, c, :3]
            angle, yc, r = float(pt.point_contact_angle), float(pt.point_wheel_y), float(pt.point_rolling_radius)
            s = sign * (pt.point_strip_wheel_y.values - yc) / np.cos(angle)
            radii = float(row.rolling_radius.sum("side"))
            xis = xi - 2 * (pt.point_strip_rolling_radius.values - r) / radii - sign * np.sin(angle) / r * s
            ref = strip_fastsim(s, float(pt.point_strip_width), pt.point_strip_half_length.values,
                                float(pt.point_normal_force), xis, eta, phi, 0.3, 2.1e11 / 2.56, 0.28,
                                float(pt.point_a), float(pt.point_b))
            assert rows[w, c, 3:6] == pytest.approx([ref.Fx, ref.Fy, ref.Mz], rel=1e-9, abs=1e-9)
            assert rows[w, c, 6] == pytest.approx(40.0 * ref.power_local, rel=1e-9)
    assert critical_speed(strip) == pytest.approx(78.475, abs=2e-3)
    with pytest.raises(ScenarioError, match="creep_law"):
        TableWheelsetModel(speed=40.0, **SUSPENSION, table=hertz, creep_law="strip-fastsim")
    with pytest.raises(ScenarioError, match="creep_law"):
        TableBogieModel.cooperrider(20.0, semi, creep_law="fastsim")
