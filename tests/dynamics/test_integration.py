"""``Integrator``: the compiled loop's options named, the same numbers as ``integrate`` bit for bit."""

import math

import numpy as np
import pytest

from railwear.dynamics import (BogieModel, DiskWheelModel, IntegrationStats, Integrator, WheelsetModel,
                               contact_constants)
from railwear.dynamics import integrators as integ
from railwear.errors import NumericalInstabilityError, ScenarioError

WHEELSET = WheelsetModel(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2e6, f11=6.4e6,
                         f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05, speed=150.0,
                         flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3)


def _disk_wheel():
    c = contact_constants(80e3, 1 / 0.92, 1 / 0.6, 210e9, 0.28)
    u = 20e-6 * np.cos(7 * 2 * np.pi * np.arange(128) / 128)
    return DiskWheelModel(speed=60.0, radius=0.46, wheel_mass=1000.0, wheel_inertia=80.0, static_load=80e3,
                          hertz_constant=c["hertz_constant"], primary_stiffness=1.2e6, f11=c["f11"], rail_mass=150.0,
                          pad_stiffness=1e8, pad_damping=6e4, friction_coefficient=0.3, traction_torque=1800.0,
                          patch_half_length=c["patch_half_length"], radius_deviation=u, initial_vertical_velocity=0.3)


def _same(run, out):
    ts, ys, n_out, status, t_last, y_last, stats, ev_t, ev_y, ev_dir = out
    assert run.status == status and run.t == t_last
    np.testing.assert_array_equal(run.y, y_last)
    np.testing.assert_array_equal(run.t_out, ts[:n_out])
    np.testing.assert_array_equal(run.y_out, ys[:n_out])
    np.testing.assert_array_equal(run.event_t, ev_t)
    np.testing.assert_array_equal(run.event_y, ev_y)
    np.testing.assert_array_equal(run.event_direction, ev_dir)
    assert run.stats == IntegrationStats.from_array(stats)


def test_the_disk_wheel_call_of_the_long_term_runs():
    """``wheel_runs.advance``'s 17 arguments against ``Integrator(events=True, ...)``, with the
    frictional energy swept onto the cells."""
    model = _disk_wheel()
    p, surf, y0 = model.params(), model.surface(), model.initial_state()
    e_old, e_new = np.zeros(model.n_cells()), np.zeros(model.n_cells())
    out = integ.integrate(model.kind, p, surf, y0, 0.0, 0.03, 1e-7, 1e-13, integ.METHOD_DOPRI5, 0.0, math.inf,
                          50_000_000, np.zeros(0), 1_000_000_000, True, 1e6, e_old)
    run = Integrator(rtol=1e-7, atol=1e-13, max_steps=50_000_000, events=True).run(
        model.kind, p, surf, y0, 0.0, 0.03, energy=e_new)
    _same(run, out)
    np.testing.assert_array_equal(e_new, e_old)
    assert run.success and run.event_t.size >= 2 and e_new.sum() > 0.0
    assert run.t_out.tolist() == [0.0, 0.03]  # no output_every: the ends only


@pytest.mark.parametrize("method", ["dopri5", "dop853", "rosenbrock"])
def test_dense_output_of_every_method(method):
    p, surf, y0 = WHEELSET.params(), WHEELSET.surface(), WHEELSET.initial_state()
    t_eval = np.linspace(0.0, 1.0, 101)
    out = integ.integrate(WHEELSET.kind, p, surf, y0, 0.0, 1.0, 1e-8, 1e-10, integ.METHODS[method], 0.0, 0.01, 10**6,
                          t_eval, 1, False, 1e6, np.zeros(0))
    run = Integrator(method=method, max_step=0.01, max_steps=10**6).run(WHEELSET.kind, p, surf, y0, 0.0, 1.0,
                                                                         t_eval=t_eval)
    _same(run, out)
    assert run.stats.rejected_steps >= 0 and (run.stats.jacobian_evaluations > 0) == (method == "rosenbrock")


def test_output_every_n_steps_and_switch_cuts_off():
    bogie = BogieModel.cooperrider(40.0, friction_coefficient=0.15)
    p, surf, y0 = bogie.params(), bogie.surface(), bogie.initial_state()
    out = integ.integrate(bogie.kind, p, surf, y0, 0.0, 1.0, 1e-9, 1e-11, integ.METHOD_DOP853, 1e-4, np.inf, 10**6,
                          np.zeros(0), 5, False, 1e6, np.zeros(0), False)
    run = Integrator(method="dop853", rtol=1e-9, atol=1e-11, first_step=1e-4, output_every=5,
                     cut_at_switches=False).run(bogie.kind, p, surf, y0, 0.0, 1.0)
    _same(run, out)
    assert run.t_out.size == 1 + -(-run.stats.accepted_steps // 5)


def test_stats_add_and_a_failed_run_says_why():
    p, surf, y0 = WHEELSET.params(), WHEELSET.surface(), WHEELSET.initial_state()
    run = Integrator(max_steps=10).run(WHEELSET.kind, p, surf, y0, 0.0, 1.0)
    assert not run.success and run.status == integ.STATUS_MAX_STEPS and run.stats.accepted_steps == 10
    assert (run.stats + run.stats).accepted_steps == 20
    with pytest.raises(NumericalInstabilityError, match=r"wheelset: max_steps = 10 reached at t = ") as err:
        run.check("wheelset")
    assert err.value.last_time == run.t and np.array_equal(err.value.last_good, run.y)


@pytest.mark.parametrize("options, field", [
    (dict(method="rk4"), "method"), (dict(rtol=1e-16), "rtol"), (dict(atol=0.0), "atol"),
    (dict(max_steps=0), "max_steps"), (dict(first_step=-1.0), "first_step"), (dict(max_step=0.0), "max_step"),
    (dict(max_norm=-1.0), "max_norm"), (dict(output_every=0), "output_every"),
])
def test_bad_options_name_their_field(options, field):
    with pytest.raises(ScenarioError, match=f"^{field}: "):
        Integrator(**options)


def test_the_energy_array_must_take_the_sum_in_place():
    model = _disk_wheel()
    with pytest.raises(ScenarioError, match="^energy: "):
        Integrator(events=True).run(model.kind, model.params(), model.surface(), model.initial_state(), 0.0, 1e-3,
                                    energy=np.zeros(model.n_cells(), dtype=np.float32))
