"""The rotating disk wheel with rigid contact (GGL DAE, IDA) as the limit of the Hertzian ODE."""

import dataclasses

import numpy as np
import pytest

from railwear.dynamics import DiskWheelModel, kernels
from railwear.dynamics import integrators as integ
from railwear.dynamics.dae import disk_wheel_dae_outputs, disk_wheel_ggl_problem, solve_ggl

# wheel on a rail mass on pads under a sprung mass; the traction torque spins the wheel up from
# zero creepage (creep time constant J V / (R0^2 f11) = 0.7 ms) to the steady creepage 1.2e-3
P2 = dict(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3, hertz_constant=1.05e11,
          primary_stiffness=1e6, primary_damping=4e4, sprung_mass=5000.0, rail_mass=150.0, pad_stiffness=1e8,
          pad_damping=5e4, f11=1.15e7, friction_coefficient=0.3, patch_half_length=6e-3, traction_torque=5e3)
STIFFNESS_FACTORS = (1.0, 10.0, 100.0)


def _compare(model, t_end, lift):
    """Errors of the ODE at Hertz constants ``k_H`` times ``STIFFNESS_FACTORS`` against the rigid
    DAE: rows per stiffness, columns ``z_w`` [m], ``Omega`` [rad/s], ``Fx`` [N], ``N`` [N]; and the
    DAE solution. Both start from the same state: the wheel and the rail lifted by ``lift``, the
    spin ``V / R0``, the ODE's approach set to carry the DAE's initial normal force."""
    spin = model.speed / model.radius
    problem, q0, v0 = disk_wheel_ggl_problem(model, rotation=True, initial_spin=spin)
    q0[1] += lift
    q0[3] += lift
    t_eval = np.linspace(0.0, t_end, int(round(t_end * 2e4)) + 1)
    sol = solve_ggl(problem, t_eval, q0, v0, rtol=1e-8, atol=1e-14)
    rigid = disk_wheel_dae_outputs(model, sol)
    errors = []
    for factor in STIFFNESS_FACTORS:
        hertz = dataclasses.replace(model, hertz_constant=factor * model.hertz_constant)
        approach = (rigid[0, 0] / hertz.hertz_constant) ** (2.0 / 3.0)
        y0 = np.array([0.0, spin, q0[1] + hertz.static_approach - approach, v0[1], q0[2], v0[2], q0[3], v0[3]])
        p, surf = hertz.params(), hertz.surface()
        out = integ.integrate(hertz.kind, p, surf, y0, 0.0, t_end, 1e-11, 1e-15, integ.METHOD_DOPRI5, 0.0, np.inf,
                              10**7, t_eval, 1, True, 1e6, np.zeros(0))
        assert out[3] == integ.STATUS_OK
        ys = out[1][:out[2]]
        contact = kernels.outputs(hertz.kind, t_eval, ys, p, surf, kernels.DW_N_OUTPUTS)
        errors.append([np.max(np.abs(ys[:, 2] - sol.q[:, 1])), np.max(np.abs(ys[:, 1] - spin - sol.v[:, 0])),
                       np.max(np.abs(contact[:, 2] - rigid[:, 2])), np.max(np.abs(contact[:, 0] - rigid[:, 0]))])
    return np.array(errors), sol, rigid


@pytest.mark.parametrize(
    "case, min_ratios, bounds",
    [
        # a round wheel with the wheel and rail lifted 20 um: the wheel-rail mass rings on the pads
        # (N from 68.4 to 71.0 kN); errors at the stiffest contact 6e-8 m, 4e-6 rad/s, 0.5 N, 6 N
        ("round", (4.0, 4.0, 2.0, 3.0), (1e-7, 1e-5, 1.0, 10.0)),
        # order-7 out-of-round wheel (2 um on 4096 cells): the contact angle follows the spin;
        # errors at the stiffest contact 4e-9 m, 5e-7 rad/s, 0.09 N, 1 N
        ("out-of-round", (4.0, 4.0, 2.0, 2.5), (1e-8, 1e-6, 0.2, 2.0)),
    ],
)
def test_ode_approaches_the_rigid_contact_dae_as_the_contact_stiffens(case, min_ratios, bounds):
    if case == "round":
        model, t_end, lift = DiskWheelModel(**P2), 0.05, 2e-5
    else:
        angles = 2.0 * np.pi * np.arange(4096) / 4096
        model, t_end, lift = DiskWheelModel(**P2, radius_deviation=2e-6 * np.cos(7 * angles)), 0.01, 0.0
    errors, sol, rigid = _compare(model, t_end, lift)
    assert sol.constraint_drift < 1e-8  # metres
    # the DAE itself: the wheel spins up towards the steady creepage, the force towards T / R0
    assert rigid[-1, 1] == pytest.approx(model.steady_creepage(), rel=0.05)
    assert rigid[-1, 2] == pytest.approx(model.traction_torque / model.radius, rel=0.05)
    # displacement and spin errors fall like the contact compliance, k_H^(-2/3): 4.6 per decade
    ratios = errors[:-1] / errors[1:]
    assert np.all(ratios >= np.array(min_ratios)), ratios
    assert np.all(errors[-1] < np.array(bounds)), errors[-1]


def test_rotation_changes_nothing_without_creep_and_torque():
    """With f11 = 0 and no torque the rotating DAE spins at V / R0 and its vertical motion is that
    of the rotation-free form."""
    angles = 2.0 * np.pi * np.arange(512) / 512
    model = DiskWheelModel(**dict(P2, f11=0.0, traction_torque=0.0), radius_deviation=2e-6 * np.cos(5 * angles))
    t_eval = np.linspace(0.0, 0.005, 101)
    problem, q0, v0 = disk_wheel_ggl_problem(model)
    plain = solve_ggl(problem, t_eval, q0, v0, rtol=1e-9, atol=1e-14)
    problem, q0, v0 = disk_wheel_ggl_problem(model, rotation=True, initial_spin=model.speed / model.radius)
    rotating = solve_ggl(problem, t_eval, q0, v0, rtol=1e-9, atol=1e-14)
    assert np.max(np.abs(rotating.q[:, 0])) < 1e-14 and np.max(np.abs(rotating.v[:, 0])) < 1e-12
    np.testing.assert_allclose(rotating.q[:, 1:], plain.q, rtol=0, atol=1e-12)
    # the normal forces (about 130 N dynamic) agree except on the jumps of the staircase u_bar''
    assert np.mean(np.abs(rotating.lam - plain.lam) < 0.05) > 0.97
