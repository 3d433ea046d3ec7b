"""The wheelset's axle spin deviation as a state (``spin_inertia``)."""

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import brentq

from railwear.dynamics import WheelsetModel, critical_speed, kernels, simulate
from railwear.dynamics.bifurcation import settle
from railwear.dynamics.models import numerical_state_matrix
from railwear.errors import ScenarioError

BASE = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6, f22=5.9e6,
            half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05)
# conicity 0.2, flange contact, saturation: critical speed 63.1 m/s; a 3 mm start at 70 m/s
HUNT = dict(BASE, conicity=0.2, flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3,
            wheel_load=50e3, initial_lateral_displacement=3e-3)


@pytest.mark.parametrize("spin_inertia", [12.0, 120.0, 1e4])
def test_linearised_spin_decouples_and_keeps_the_critical_speed(spin_inertia):
    """To first order the spin deviation enters both wheels' longitudinal creepages alike, so it
    exerts no yaw moment, and the antisymmetric creepages exert no net torque on the axle: the
    state matrix is block diagonal with the eigenvalue -2 f11 r0^2 / (J V) for the spin, and
    the critical speed is the one without the spin state, for any J. The compiled kernel's
    central-difference Jacobian must show the same."""
    coupled = dict(BASE, f23=1.5e3, f33=20.0, lateral_damping=1e3, yaw_damping=2e3)
    model = WheelsetModel(speed=40.0, **coupled, spin_inertia=spin_inertia)
    plain = WheelsetModel(speed=40.0, **coupled)
    a = model.state_matrix()
    np.testing.assert_allclose(numerical_state_matrix(model.kind, model.params(), 5, model.surface()), a,
                               rtol=1e-6, atol=1e-6)
    spin_eigenvalue = -2 * model.f11 * model.rolling_radius**2 / (spin_inertia * model.speed)
    expected = np.sort_complex(np.append(np.linalg.eigvals(plain.state_matrix()), spin_eigenvalue))
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(a)), expected, rtol=1e-9)
    assert critical_speed(model) == pytest.approx(critical_speed(plain), rel=1e-9)


def test_free_spin_decay_is_exponential():
    """Centred running with linear creep and an initial spin deviation: the two longitudinal
    forces f11 omega r0 / V brake the axle, omega = omega0 exp(-2 f11 r0^2 t / (J V)), and the
    lateral motion stays zero."""
    model = WheelsetModel(speed=30.0, **BASE, spin_inertia=120.0, initial_lateral_displacement=0.0,
                          initial_spin_deviation=0.1)
    ds = simulate(model, 0.02, rtol=1e-10, atol=1e-16, n_output=101)
    rate = 2 * model.f11 * model.rolling_radius**2 / (model.spin_inertia * model.speed)
    np.testing.assert_allclose(ds.spin_deviation.values, 0.1 * np.exp(-rate * ds.time.values), rtol=1e-7)
    assert np.all(ds.lateral_displacement.values == 0.0) and np.all(ds.yaw_angle.values == 0.0)
    assert ds.spin_deviation.attrs["units"] == "rad s-1"


def test_large_spin_inertia_tends_to_constant_spin():
    """J -> inf: the axle keeps V / r0 (the model without the state) and J omega(t) tends to the
    impulse of the creep torque -(r_L Fx_L + r_R Fx_R) along that run, with an error O(1/J)
    (the spin's own decay, rate 2 f11 r0^2 / (J V)). Measured: 2.9e-2 at J = 1e6, 2.9e-3 at 1e7."""
    n = 20001
    reference = simulate(WheelsetModel(speed=70.0, **HUNT), 1.0, rtol=1e-10, n_output=n)
    y, fx = reference.lateral_displacement.values, reference.longitudinal_creep_force.values
    r0, lam = HUNT["rolling_radius"], HUNT["conicity"]
    torque = -((r0 + lam * y) * fx[:, 0] + (r0 - lam * y) * fx[:, 1])
    impulse = cumulative_trapezoid(torque, reference.time.values, initial=0.0)
    errors = []
    for inertia in (1e6, 1e7):
        ds = simulate(WheelsetModel(speed=70.0, **HUNT, spin_inertia=inertia), 1.0, rtol=1e-10, n_output=n)
        errors.append(np.max(np.abs(inertia * ds.spin_deviation.values - impulse)) / np.max(np.abs(impulse)))
        # the spin hardly acts back on the hunting motion of the conical wheelset
        assert np.max(np.abs(ds.lateral_displacement.values - y)) < 1e-8
    assert errors[1] < 5e-3
    assert 8.0 < errors[0] / errors[1] < 12.0


def _torque_free_spin(model, state):
    """The spin deviation at which the creep torque on the axle vanishes (quasi-static spin)."""
    p, surf, out = model.params(), model.surface(), np.empty(5)

    def torque(omega):
        kernels.rhs(model.kind, 0.0, np.append(state[:4], omega), p, surf, out)
        return out[4]

    return brentq(torque, -1.0, 1.0, xtol=1e-15)


def test_small_spin_inertia_tends_to_the_torque_free_spin():
    """J -> 0: the spin follows the quasi-static value at which the creep torque vanishes, with a
    lag proportional to J (a singular perturbation). Measured: 1.43e-7 J rad/s against a
    torque-free spin of up to 2.4e-5 rad/s; halving J halves the lag."""
    lags = []
    for inertia in (0.5, 0.25, 0.125):
        model = WheelsetModel(speed=70.0, **HUNT, spin_inertia=inertia)
        ds = simulate(model, 0.6, method="rosenbrock", rtol=1e-10, n_output=121)
        states = np.stack([ds[v].values for v in ("lateral_displacement", "yaw_angle", "lateral_velocity",
                                                   "yaw_rate", "spin_deviation")], axis=1)[60:]
        quasi_static = np.array([_torque_free_spin(model, s) for s in states])
        lags.append(np.max(np.abs(states[:, 4] - quasi_static)))
        assert np.max(np.abs(quasi_static)) > 1e-5
    np.testing.assert_allclose(np.array(lags[:-1]) / np.array(lags[1:]), 2.0, rtol=0.02)
    assert lags[-1] < 2e-3 * np.max(np.abs(quasi_static))


def test_spin_state_runs_through_settle_and_validates():
    model = WheelsetModel(speed=70.0, **HUNT, spin_inertia=120.0)
    assert model.n_states == 5 and model.initial_state().shape == (5,)
    sustained, amplitude, state = settle(model, window=0.5, max_time=3.0)
    assert state.shape == (5,) and amplitude > HUNT["flange_clearance"]
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ScenarioError, match="^spin_inertia:"):
            WheelsetModel(speed=70.0, **BASE, spin_inertia=bad)


def test_spin_state_and_fastsim_from_a_scenario(tmp_path):
    from railwear import api
    from railwear.scenario import dynamics

    text = dynamics._builtin_dir().joinpath("hunting.toml").read_text()
    path = tmp_path / "spin.toml"
    path.write_text(text.replace("[run]", 'spin_inertia_kg_m2 = 120.0\ncreep_law = "fastsim"\n\n[run]'))
    ds = api.simulate(dynamics.load_dynamics_scenario(path))
    assert ds.spin_deviation.dims == ("speed", "time") and ds.attrs["linear_critical_speed_kmh"] > 0
    path.write_text(text.replace("[run]", 'spin_inertia_kg_m2 = "heavy"\n\n[run]'))
    with pytest.raises(ScenarioError, match="spin_inertia_kg_m2: must be a number"):
        dynamics.build(dynamics.load_dynamics_scenario(path), 50.0)
