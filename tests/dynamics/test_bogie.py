"""The Cooperrider bogie: Hopf point, subcritical limit cycle, ramp-down nonlinear critical speed."""

import dataclasses

import numpy as np
import pytest

from railwear.dynamics import BogieModel, critical_speed, linear_critical_speed, simulate
from railwear.dynamics.bifurcation import ramp_down

SATURATED = dict(friction_coefficient=0.15, wheel_load=50e3)  # the wheel load is an assumption


def test_frame_held_fixed_gives_two_single_wheelsets():
    """With an immovable frame each wheelset is the single wheelset of the closed form, with the
    primary lateral stiffness and primary yaw stiffness as its suspension."""
    bogie = BogieModel.cooperrider(40.0, frame_mass=1e15, frame_yaw_inertia=1e15, secondary_lateral_stiffness=1e15,
                                   secondary_yaw_stiffness=1e15, secondary_lateral_damping=2e15,
                                   secondary_yaw_damping=2e15)
    closed = linear_critical_speed(bogie.wheelset_mass, bogie.wheelset_yaw_inertia, bogie.primary_lateral_stiffness,
                                   bogie.primary_yaw_stiffness, bogie.f11, bogie.f22, bogie.half_gauge,
                                   bogie.rolling_radius, bogie.conicity)
    assert critical_speed(bogie) == pytest.approx(closed, rel=1e-6)


def test_hopf_point_of_the_cooperrider_bogie():
    bogie = BogieModel.cooperrider(40.0)
    vc = critical_speed(bogie)
    eig = np.linalg.eigvals(bogie.state_matrix(vc))
    critical = eig[np.argmax(eig.real)]
    assert abs(critical.real) < 1e-8 * abs(critical)
    assert abs(critical.imag) > 1.0  # an oscillatory (Hopf) crossing, not a divergence
    print(f"Cooperrider bogie: linear critical speed (Hopf point) {vc:.4f} m/s = {3.6 * vc:.2f} km/h, "
          f"hunting frequency {abs(critical.imag) / (2 * np.pi):.3f} Hz")
    # a small motion dies out 5 % below and grows 5 % above (real parts -0.26 and +0.28 1/s)
    small = BogieModel.cooperrider(0.95 * vc, initial_lateral_displacement=1e-4)
    assert np.max(np.abs(simulate(small, 10.0, n_output=1001).lateral_displacement.values[-100:])) < 2e-5
    large = dataclasses.replace(small, speed=1.05 * vc)
    assert np.max(np.abs(simulate(large, 10.0, n_output=1001).lateral_displacement.values[-100:])) > 5e-4


def test_stable_limit_cycle_below_the_hopf_point_and_ramp_down():
    vc = critical_speed(BogieModel.cooperrider(40.0))
    start = BogieModel.cooperrider(1.1 * vc, initial_lateral_displacement=15e-3, **SATURATED)
    result = ramp_down(start, vc * np.arange(1.1, 0.9, -0.005))
    nonlinear = result.nonlinear_critical_speed
    print(f"Cooperrider bogie (mu = 0.15, 50 kN per wheel): nonlinear critical speed by ramping down "
          f"{nonlinear:.3f} m/s = {nonlinear / vc:.3f} of the Hopf point; cycle amplitude there "
          f"{1e3 * result.amplitudes[-2]:.2f} mm")
    assert nonlinear < vc
    # the branch below the Hopf point is a stable cycle coexisting with stable centred running
    below = dataclasses.replace(start, speed=nonlinear)
    ds = simulate(below, 20.0, n_output=4001, initial_state=result.cycle_state)
    y = np.abs(ds.lateral_displacement.values[:, 0])
    assert np.max(y[-400:]) > start.flange_clearance
    assert np.max(y[-400:]) == pytest.approx(np.max(y[400:800]), rel=1e-2)
    small = dataclasses.replace(below, initial_lateral_displacement=1e-3)
    assert np.max(np.abs(simulate(small, 20.0, n_output=801).lateral_displacement.values[-100:])) < 1e-4
