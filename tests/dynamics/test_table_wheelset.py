"""Wheelset on real profiles (S1002 on UIC60 through the contact table)."""

import numpy as np
import pytest

from railwear.dynamics import TableWheelsetModel, critical_speed, kernels, simulate
from railwear.geometry import contact_table, equivalent_conicity, load_profile

SUSPENSION = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6)


@pytest.fixture(scope="module")
def table():
    return contact_table(load_profile("S1002"), load_profile("UIC60"))


def _crossings(x, y):
    i = np.nonzero(np.sign(y[:-1]) != np.sign(y[1:]))[0]
    return x[i] - y[i] * (x[i + 1] - x[i]) / (y[i + 1] - y[i])


@pytest.mark.parametrize("amplitude", [1e-3, 3e-3, 5e-3])
def test_kinematic_wavelength_matches_the_equivalent_conicity(table, amplitude):
    """Huge creep coefficients (no spin), no suspension: the wheelset follows Klingel's motion
    with the real rolling-radius difference; its wavelength is the one EN 15302 turns into the
    equivalent conicity (railwear.geometry.equivalent_conicity, an independent integration)."""
    model = TableWheelsetModel(speed=20.0, mass=1000.0, yaw_inertia=600.0, lateral_stiffness=0.0, yaw_stiffness=0.0,
                               table=table, creep_scale=1e3, spin=False, initial_lateral_displacement=amplitude)
    ds = simulate(model, 1.2, method="rosenbrock", rtol=1e-8, n_output=12001)
    crossings = _crossings(ds.distance.values, ds.lateral_displacement.values)
    wavelength = crossings[2] - crossings[0]  # the first full wave, before the amplitude drifts
    centre = table.sel(y=0.0)
    e0 = 0.5 * float(centre.contact_Y.sel(side="right") - centre.contact_Y.sel(side="left"))
    r0 = float(centre.rolling_radius.mean())
    expected = 2 * np.pi * np.sqrt(e0 * r0 / equivalent_conicity(table, amplitude))
    assert wavelength == pytest.approx(expected, rel=0.02)


def test_centred_running_is_an_equilibrium(table):
    model = TableWheelsetModel(speed=40.0, **SUSPENSION, table=table, friction_coefficient=0.3)
    out = np.empty(4)
    kernels.rhs(model.kind, 0.0, np.zeros(4), model.params(), model.surface(), out)
    np.testing.assert_allclose(out, 0.0, atol=1e-6)


def test_hunting_on_real_profiles(table):
    """The linear critical speed uses the rolling-radius slope at y = 0 (local conicity 0.11);
    S1002/UIC60 is far steeper just beyond 0.1 mm (0.59 by regression over 0.3 mm), so below Vc
    a tiny motion dies out while a 0.3 mm one grows to a stable cycle (coexistence: the
    nonlinear critical speed lies below the linear one). Above Vc the cycle reaches the flange."""
    def run(factor, y0, t_end):
        model = TableWheelsetModel(speed=factor * vc, **SUSPENSION, table=table, friction_coefficient=0.3,
                                   initial_lateral_displacement=y0)
        return np.abs(simulate(model, t_end, n_output=int(500 * t_end) + 1).lateral_displacement.values)

    vc = critical_speed(TableWheelsetModel(speed=40.0, **SUSPENSION, table=table))
    assert 20.0 < vc < 300.0
    assert np.max(run(0.8, 1e-5, 6.0)[-500:]) < 1e-9
    cycle = run(0.8, 3e-4, 6.0)
    assert np.max(cycle[-500:]) == pytest.approx(np.max(cycle[-1000:-500]), rel=1e-3)
    assert np.max(cycle[-500:]) > 1e-3
    above = run(1.2, 1e-3, 6.0)
    assert np.max(above[-500:]) == pytest.approx(np.max(above[-1000:-500]), rel=1e-2)
    assert 6e-3 < np.max(above[-500:]) < 10e-3  # in flange contact (contact angle > 0.4 beyond 6 mm)


def test_result_variables(table):
    ds = simulate(TableWheelsetModel(speed=60.0, **SUSPENSION, table=table, friction_coefficient=0.3), 0.5,
                  n_output=101)
    assert np.all(ds.frictional_power.values >= 0.0)
    assert float(ds.normal_force.min()) > 0.0
    for name, var in ds.data_vars.items():
        assert var.attrs["units"] and var.attrs["long_name"], name


def test_contact_positions_follow_the_table(table):
    model = TableWheelsetModel(speed=60.0, **SUSPENSION, table=table, initial_lateral_displacement=4e-3)
    ds = simulate(model, 0.3, n_output=61)
    y = ds.lateral_displacement.values
    for wheel in ("left", "right"):
        # the table's y is to the right, the model's to the left
        expected = np.interp(-y, table.y.values, table.wheel_contact_y.sel(side=wheel).values)
        np.testing.assert_allclose(ds.contact_lateral_position.sel(wheel=wheel).values, expected, atol=1e-12)
    angle = np.unwrap(ds.contact_angle.values)
    assert np.all(np.diff(angle) > 0.0) and angle[-1] == pytest.approx(60.0 * 0.3 / 0.46, rel=0.01)


def test_result_writes_to_netcdf(table, tmp_path):
    import xarray as xr

    ds = simulate(TableWheelsetModel(speed=50.0, **SUSPENSION, table=table), 0.05, n_output=11)
    path = tmp_path / "table_wheelset.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    back = xr.open_dataset(path, engine="h5netcdf")
    assert back.attrs["model_table_profiles"] == "S1002/UIC60"
    np.testing.assert_array_equal(back.lateral_displacement.values, ds.lateral_displacement.values)
