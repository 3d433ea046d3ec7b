"""Bad input gets a one-line ScenarioError naming the field; blow-up an error, never NaNs."""

import math

import numpy as np
import pytest

from railwear.dynamics import DiskWheelModel, WheelsetModel
from railwear.dynamics import simulate
from railwear.errors import NumericalInstabilityError, ScenarioError

WHEELSET = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6,
                f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05, speed=40.0)
DISK = dict(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3,
            hertz_constant=1.05e11, primary_stiffness=1e6, f11=1.15e7)


def _raises_naming(field, build):
    with pytest.raises(ScenarioError) as info:
        build()
    message = str(info.value)
    assert field in message and "\n" not in message
    return message


@pytest.mark.parametrize("field, value", [("mass", 0.0), ("mass", -5.0), ("yaw_inertia", 0.0), ("speed", 0.0),
                                          ("speed", -10.0), ("rolling_radius", math.nan), ("f11", -1.0),
                                          ("friction_coefficient", 0.0)])
def test_wheelset_rejects_bad_fields(field, value):
    _raises_naming(field, lambda: WheelsetModel(**dict(WHEELSET, **{field: value})))


@pytest.mark.parametrize("field, value", [("wheel_mass", 0.0), ("wheel_mass", -600.0), ("sprung_mass", 0.0),
                                          ("rail_mass", -1.0), ("speed", 0.0), ("speed", -30.0),
                                          ("hertz_constant", 0.0), ("static_load", -1.0)])
def test_disk_wheel_rejects_bad_fields(field, value):
    _raises_naming(field, lambda: DiskWheelModel(**dict(DISK, **{field: value})))


def test_no_contact_at_the_start():
    approach = DiskWheelModel(**DISK).static_approach
    _raises_naming("initial_lift", lambda: DiskWheelModel(**DISK, initial_lift=1.01 * approach))
    # a worn spot under the contact lifts the wheel off as well
    _raises_naming("initial_lift", lambda: DiskWheelModel(**DISK, radius_deviation=np.full(64, -2 * approach)))
    DiskWheelModel(**DISK, initial_lift=0.99 * approach)  # still touching: fine


def test_torque_beyond_adhesion():
    _raises_naming("traction_torque", lambda: DiskWheelModel(**DISK, friction_coefficient=0.3,
                                                            traction_torque=0.31 * 70e3 * 0.46))


@pytest.mark.parametrize("option, value", [("rtol", 1e-16), ("rtol", 0.0), ("rtol", 2.0), ("atol", 0.0),
                                           ("atol", -1e-9), ("method", "euler"), ("t_eval", [0.0, 0.2, 0.1]),
                                           ("output_every", 0), ("n_output", 0), ("max_norm", 0.0),
                                           ("max_step", -1.0)])
def test_impossible_options(option, value):
    model = WheelsetModel(**WHEELSET)
    _raises_naming(option, lambda: simulate(model, 1.0, **{option: value}))


@pytest.mark.parametrize("t_end", [0.0, -1.0, math.inf])
def test_bad_end_time(t_end):
    _raises_naming("t_end", lambda: simulate(WheelsetModel(**WHEELSET), t_end))


def test_blow_up_raises_with_the_last_good_state():
    # far above the critical speed, no flange, no saturation: exponential growth without bound
    model = WheelsetModel(**dict(WHEELSET, speed=400.0))
    with pytest.raises(NumericalInstabilityError) as info:
        simulate(model, 20.0, max_norm=1.0)
    assert info.value.last_time is not None and 0.0 < info.value.last_time < 20.0
    assert np.all(np.isfinite(info.value.last_good)) and np.max(np.abs(info.value.last_good)) <= 1.0


def test_step_budget_exhausted_raises():
    with pytest.raises(NumericalInstabilityError, match="max_steps"):
        simulate(WheelsetModel(**WHEELSET), 10.0, rtol=1e-12, max_steps=50)


@pytest.mark.parametrize("model", [WheelsetModel(**WHEELSET), DiskWheelModel(**DISK, traction_torque=2e3)])
def test_every_variable_has_cf_units_and_long_name(model):
    ds = simulate(model, 0.05, n_output=11)
    for name, var in list(ds.data_vars.items()) + [("time", ds.time)]:
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
        assert np.all(np.isfinite(var.values)), name
    assert ds.time.size == 11 and ds.attrs["rhs_evaluations"] > 0


def test_build_model_from_a_section():
    from railwear.dynamics import CooperriderBogie, build_model

    assert build_model("wheelset", WHEELSET) == WheelsetModel(**WHEELSET)
    assert build_model("cooperrider", {"speed": 40.0, "conicity": 0.1}) == CooperriderBogie(40.0, conicity=0.1)
    _raises_naming("masss", lambda: build_model("wheelset", dict(WHEELSET, masss=1.0)))
    _raises_naming("conicity", lambda: build_model("wheelset", {k: v for k, v in WHEELSET.items() if k != "conicity"}))
    _raises_naming("model", lambda: build_model("tram", {}))
    _raises_naming("speed", lambda: build_model("cooperrider", {}))
    _raises_naming("wheel_mass", lambda: build_model("disk_wheel", dict(DISK, wheel_mass=-1.0)))


@pytest.mark.parametrize("output", [dict(n_output=401), dict(output_every=5)])
def test_chunked_run_with_progress_matches_one_run(output):
    model = DiskWheelModel(**DISK, sprung_mass=5000.0, rail_mass=150.0, pad_stiffness=1e8,
                           initial_vertical_velocity=0.3, traction_torque=2e3)
    whole = simulate(model, 0.04, rtol=1e-10, **output)
    seen = []
    chunked = simulate(model, 0.04, rtol=1e-10, progress=seen.append, chunks=7, **output)
    assert seen == pytest.approx(np.arange(1, 8) / 7) and seen[-1] == 1.0
    assert np.all(np.diff(chunked.time.values) > 0.0)
    assert chunked.time.values[0] == 0.0 and chunked.time.values[-1] == pytest.approx(0.04)
    np.testing.assert_allclose(chunked.event_time.values, whole.event_time.values, rtol=0, atol=1e-9)
    if "n_output" in output:
        np.testing.assert_array_equal(chunked.time.values, whole.time.values)
        scale = float(np.abs(whole.normal_force).max())
        np.testing.assert_allclose(chunked.normal_force.values, whole.normal_force.values, rtol=0, atol=1e-6 * scale)
    _raises_naming("chunks", lambda: simulate(model, 0.04, chunks=0))


def test_critical_speed_needs_a_state_matrix():
    from railwear.dynamics import critical_speed

    with pytest.raises(TypeError, match="state matrix"):
        critical_speed(DiskWheelModel(**DISK))
