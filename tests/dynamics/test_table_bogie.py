"""The bogie on real profiles (S1002 on UIC60 through the contact table)."""

import numpy as np
import pytest

from railwear.dynamics import TableBogieModel, TableWheelsetModel, critical_speed, simulate
from railwear.errors import ScenarioError
from railwear.geometry import contact_table, load_profile

# an immovable frame: each wheelset then hangs from the ground by the primary suspension
FIXED_FRAME = dict(frame_mass=1e15, frame_yaw_inertia=1e15, secondary_lateral_stiffness=1e15,
                   secondary_yaw_stiffness=1e15, secondary_lateral_damping=2e15, secondary_yaw_damping=2e15)


@pytest.fixture(scope="module")
def table():
    return contact_table(load_profile("S1002"), load_profile("UIC60"))


def _wheelset_of(bogie, **extra):
    return TableWheelsetModel(speed=bogie.speed, mass=bogie.wheelset_mass, yaw_inertia=bogie.wheelset_yaw_inertia,
                              lateral_stiffness=bogie.primary_lateral_stiffness,
                              yaw_stiffness=bogie.primary_yaw_stiffness, table=bogie.table, **extra)


def test_fixed_frame_gives_two_table_wheelsets_linear(table):
    """With an immovable frame the bogie's critical speed is the table wheelset's with the primary
    suspension (measured: equal to 1e-15)."""
    bogie = TableBogieModel.cooperrider(40.0, table, **FIXED_FRAME)
    assert critical_speed(bogie) == pytest.approx(critical_speed(_wheelset_of(bogie)), rel=1e-9)


def test_fixed_frame_gives_two_table_wheelsets_nonlinear(table):
    """... and, with saturation, the front wheelset runs as the table wheelset from the same start
    (1 mm at 80 m/s, 0.82 Vc: it grows to a 3.5 mm cycle, the coexisting branch below Vc) while
    the rear one, started centred, stays there. Measured: 4e-9 m apart over 1.5 s, where two
    tolerances of the single wheelset (rtol 1e-10 and 1e-12) give 1.6e-9 m."""
    bogie = TableBogieModel.cooperrider(80.0, table, **FIXED_FRAME, friction_coefficient=0.3,
                                        initial_lateral_displacement=1e-3)
    ds = simulate(bogie, 1.5, rtol=1e-12, n_output=1501)
    single = simulate(_wheelset_of(bogie, friction_coefficient=0.3, initial_lateral_displacement=1e-3), 1.5,
                      rtol=1e-12, n_output=1501)
    front = ds.lateral_displacement.sel(wheelset="front").values
    assert np.max(np.abs(front)) > 3e-3  # grown well into the nonlinear range of the profiles
    np.testing.assert_allclose(front, single.lateral_displacement.values, rtol=0, atol=2e-8)
    np.testing.assert_allclose(ds.frictional_power_left.sel(wheelset="front").values,
                               single.frictional_power.sel(wheel="left").values, rtol=1e-4, atol=1e-2)
    assert np.max(np.abs(ds.lateral_displacement.sel(wheelset="rear").values)) < 1e-12


@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_hunting_mode_grows_at_the_eigenvalue_of_the_numerical_linearisation(table, factor):
    """The Cooperrider suspension on S1002/UIC60: Hopf point 29.77 m/s, 2.6 Hz. Started on the
    critical eigenvector (0.1 um), the compiled model's motion grows or decays at the real part of
    the critical eigenvalue of the central-difference state matrix (measured: within 3e-5;
    without saturation, as the state matrix is taken: the spin creepage of the contact angle
    loads the contacts in centred running, so saturation changes the slopes already there)."""
    vc = critical_speed(TableBogieModel.cooperrider(40.0, table))
    assert vc == pytest.approx(29.77, rel=1e-3)
    model = TableBogieModel.cooperrider(factor * vc, table)
    eigenvalues, vectors = np.linalg.eig(model.state_matrix())
    critical = np.argmax(eigenvalues.real)
    start = np.real(vectors[:, critical])
    start *= 1e-7 / np.max(np.abs(start[:6]))
    ds = simulate(model, 3.0, rtol=1e-10, atol=1e-16, n_output=30001, initial_state=start)
    t, y = ds.time.values, ds.lateral_displacement.sel(wheelset="front").values
    peaks = np.nonzero((y[1:-1] > y[:-2]) & (y[1:-1] > y[2:]))[0] + 1
    rate = np.polyfit(t[peaks], np.log(y[peaks]), 1)[0]
    assert rate == pytest.approx(eigenvalues[critical].real, rel=1e-3)
    assert abs(eigenvalues[critical].imag) / (2 * np.pi) == pytest.approx(2.6, abs=0.4)


def test_result_variables_and_bad_input(table):
    ds = simulate(TableBogieModel.cooperrider(40.0, table, friction_coefficient=0.3), 0.2, n_output=21)
    assert np.all(ds.frictional_power_left.values >= 0.0)
    for name, var in ds.data_vars.items():
        assert var.attrs["units"] and var.attrs["long_name"], name
    with pytest.raises(ScenarioError, match="^frame_mass:"):
        TableBogieModel.cooperrider(40.0, table, frame_mass=-1.0)
    with pytest.raises(ScenarioError, match="^table:"):
        TableBogieModel.cooperrider(40.0, None)


def _scenario(tmp_path, text):
    from railwear.scenario import dynamics

    path = tmp_path / "scenario.toml"
    path.write_text(text)
    return dynamics.load_dynamics_scenario(path)


def test_scenarios_on_real_profiles(tmp_path):
    """``model.profiles`` puts the wheelset and the Cooperrider bogie of a scenario on real
    profiles; the built-in hunting-profiles scenario decays at 250 km/h and hunts at 340 km/h
    (linear critical speed 314.5 km/h)."""
    from railwear import api
    from railwear.scenario import dynamics

    run = '\n[run]\nspeeds_kmh = [100.0]\n'
    profiles = 'profiles = { wheel = "S1002", rail = "UIC60" }\n'
    bogie = dynamics.build(_scenario(tmp_path, '[model]\nkind = "cooperrider"\n' + profiles + run), 30.0)
    assert isinstance(bogie, TableBogieModel) and bogie.frame_mass == 2918.9
    with pytest.raises(ScenarioError, match="flange_clearance_mm: not a field"):
        dynamics.build(_scenario(tmp_path, '[model]\nkind = "cooperrider"\nflange_clearance_mm = 5.0\n' + profiles + run),
                       30.0)
    with pytest.raises(ScenarioError, match="^model.profiles: profile file 'XYZ'"):
        dynamics.build(_scenario(tmp_path, '[model]\nkind = "cooperrider"\nprofiles = { wheel = "XYZ" }\n' + run), 30.0)
    ds = api.simulate("hunting-profiles")
    assert ds.attrs["linear_critical_speed_kmh"] == pytest.approx(314.5, abs=0.1)
    assert float(abs(ds.sel(speed=250 / 3.6).lateral_displacement[-500:]).max()) < 1e-8
    assert float(abs(ds.sel(speed=340 / 3.6).lateral_displacement[-500:]).max()) > 5e-3
