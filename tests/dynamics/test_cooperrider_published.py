"""The published Cooperrider bogie (``CooperriderBogie``, 7 degrees of freedom with frame roll):
its compiled kernel against an independent linearisation, its reduction to the six-degree-of-
freedom ``BogieModel``, its linear critical speed against the published Hopf point, and the
subcritical Hopf bifurcation (docs/dynamics.md, "The published Cooperrider bogie")."""

import dataclasses

import numpy as np
import pytest

from railwear.dynamics import BogieModel, CooperriderBogie, critical_speed, simulate
from railwear.dynamics.bifurcation import ramp_down
from railwear.dynamics.cooperrider import G_PI_AB, PHI, PSI, PUBLISHED_HOPF_SPEED


def _linear_matrix(m, v, frame_yaw_stiffness=0.0):
    """State matrix of Kaas-Petersen's equations linearised by hand (no flange, no saturation),
    assembled from the springs' deflections: each spring or damper ``c`` of stiffness ``k`` adds
    ``k c c^T`` to the stiffness (damping) matrix. Coordinates ``y1, psi1, y2, psi2, yf, psif,
    phif``; a frame point ``z`` above the centre of mass moves ``-z phif`` laterally.
    ``frame_yaw_stiffness`` [N m/rad]: a yaw spring from the frame to the car body, which the
    model does not have (for the comparison in docs/dynamics.md only)."""
    n = 7
    stiff, damp = np.zeros((n, n)), np.zeros((n, n))

    def add(matrix, entries, value):
        c = np.zeros(n)
        for j, w in entries.items():
            c[j] = w
        matrix += value * np.outer(c, c)

    for i, x in ((0, m.half_wheelbase), (2, -m.half_wheelbase)):
        add(stiff, {i: 1.0, 4: -1.0, 5: -x, 6: -m.primary_height}, 2 * m.primary_lateral_stiffness)
        add(stiff, {i + 1: 1.0, 5: -1.0}, 2 * m.primary_longitudinal_stiffness * m.primary_spring_half_spacing**2)
    add(stiff, {4: 1.0, 6: -m.secondary_height}, 2 * m.secondary_lateral_stiffness)
    add(damp, {4: 1.0, 6: -m.secondary_height}, 2 * m.secondary_lateral_damping)
    add(stiff, {6: 1.0}, 4 * m.primary_vertical_stiffness * m.primary_spring_half_spacing**2
        + 2 * m.secondary_vertical_stiffness * m.secondary_spring_half_spacing**2)
    add(damp, {6: 1.0}, 2 * m.secondary_vertical_damping * m.secondary_spring_half_spacing**2)
    add(stiff, {5: 1.0}, frame_yaw_stiffness)
    a, lam, r0 = m.half_gauge, m.conicity, m.rolling_radius
    for i in (0, 2):  # both wheels: -2 f22 (y'/V - psi) and -2 f11 a (a psi'/V + lam y / r0)
        damp[i, i] += 2 * m.f22 / v
        stiff[i, i + 1] -= 2 * m.f22
        damp[i + 1, i + 1] += 2 * m.f11 * a * a / v
        stiff[i + 1, i] += 2 * m.f11 * a * lam / r0
    inv = np.linalg.inv(np.diag([m.wheelset_mass, m.wheelset_yaw_inertia, m.wheelset_mass, m.wheelset_yaw_inertia,
                                 m.frame_mass, m.frame_yaw_inertia, m.frame_roll_inertia]))
    return np.block([[np.zeros((n, n)), np.eye(n)], [-inv @ stiff, -inv @ damp]])


def test_kernel_linearisation_matches_the_equations():
    """The compiled right-hand side linearised by central differences equals the hand-linearised
    equations of motion (to 1e-6 of the largest entry), so both give the same Hopf point (1e-9)."""
    model = CooperriderBogie(60.0)
    a = model.state_matrix()
    b = _linear_matrix(model, 60.0)
    assert np.max(np.abs(a - b)) < 1e-6 * np.max(np.abs(b))
    vc = critical_speed(model)

    class Hand:
        def state_matrix(self, speed):
            return _linear_matrix(model, speed)

    assert critical_speed(Hand()) == pytest.approx(vc, rel=1e-9)


def test_without_roll_coupling_it_is_the_six_dof_bogie():
    """With the roll lever arms h1 = h2 = 0 the roll decouples, and the lateral and yaw motion is
    ``BogieModel``'s with the per-side springs doubled (2 k1, 2 k2 d1^2, 2 k4, 2 D1) and no
    secondary yaw restraint: the same critical speed to 1e-9."""
    cp = CooperriderBogie(50.0, primary_height=0.0, secondary_height=0.0)
    six = BogieModel(
        speed=50.0, wheelset_mass=cp.wheelset_mass, wheelset_yaw_inertia=cp.wheelset_yaw_inertia,
        frame_mass=cp.frame_mass, frame_yaw_inertia=cp.frame_yaw_inertia,
        primary_lateral_stiffness=2 * cp.primary_lateral_stiffness,
        primary_yaw_stiffness=2 * cp.primary_longitudinal_stiffness * cp.primary_spring_half_spacing**2,
        secondary_lateral_stiffness=2 * cp.secondary_lateral_stiffness,
        secondary_lateral_damping=2 * cp.secondary_lateral_damping, secondary_yaw_stiffness=0.0,
        secondary_yaw_damping=0.0, half_wheelbase=cp.half_wheelbase, f11=cp.f11, f22=cp.f22,
        half_gauge=cp.half_gauge, rolling_radius=cp.rolling_radius, conicity=cp.conicity,
        flange_clearance=cp.flange_clearance, flange_stiffness=cp.flange_stiffness)
    assert critical_speed(cp) == pytest.approx(critical_speed(six), rel=1e-9)


def test_linear_critical_speed_of_this_reading():
    """Hopf point of the published parameters as read here (docs/dynamics.md): 52.245 m/s,
    3.085 Hz, an oscillatory crossing. Creep coefficients ``G pi a b / psi``, ``/ phi``."""
    model = CooperriderBogie(50.0)
    assert model.f11 == G_PI_AB / PSI and model.f22 == G_PI_AB / PHI
    vc = critical_speed(model)
    eig = np.linalg.eigvals(model.state_matrix(vc))
    crit = eig[np.argmax(eig.real)]
    print(f"CooperriderBogie: Hopf point {vc:.4f} m/s, {abs(crit.imag) / (2 * np.pi):.4f} Hz; "
          f"published {PUBLISHED_HOPF_SPEED} m/s")
    assert vc == pytest.approx(52.245, abs=1e-3)
    assert abs(crit.imag) / (2 * np.pi) == pytest.approx(3.085, abs=1e-3)
    assert abs(crit.real) < 1e-8 * abs(crit)


class _WithFrameYawSpring:
    def __init__(self, model, stiffness):
        self.model, self.stiffness = model, stiffness

    def state_matrix(self, speed):
        return _linear_matrix(self.model, speed, self.stiffness)


def test_readings_compared_with_the_published_hopf_point():
    """The readings compared in docs/dynamics.md ("The published Cooperrider bogie"), each to
    1e-3 m/s: none that a source supports gives 68.66 m/s. Swapping Vermeulen-Johnson's psi and
    phi gives 55.936; a frame with no yaw inertia at all only 67.790; the yaw spring to the car
    body of DYTSI's fixed-car-body variant (2 x 0.90335 MN/m at +-1.5 m) 67.343, 1.9 % short.
    What would give 68.66: a frame yaw spring of 4.5464 MN m/rad, a half wheelbase of 1.5515 m,
    or a conicity of 0.029770."""
    base = CooperriderBogie(50.0)
    assert critical_speed(dataclasses.replace(base, f11=G_PI_AB / PHI, f22=G_PI_AB / PSI)) == pytest.approx(
        55.936, abs=1e-3)
    assert critical_speed(dataclasses.replace(base, frame_yaw_inertia=6.78)) == pytest.approx(67.790, abs=1e-3)
    assert critical_speed(_WithFrameYawSpring(base, 2 * 0.90335e6 * 1.5**2)) == pytest.approx(67.343, abs=1e-3)
    assert critical_speed(_WithFrameYawSpring(base, 4.5464e6)) == pytest.approx(PUBLISHED_HOPF_SPEED, abs=1e-3)
    assert critical_speed(dataclasses.replace(base, half_wheelbase=1.5515)) == pytest.approx(
        PUBLISHED_HOPF_SPEED, abs=1e-3)
    assert critical_speed(dataclasses.replace(base, conicity=0.029770)) == pytest.approx(
        PUBLISHED_HOPF_SPEED, abs=1e-3)


@pytest.mark.xfail(strict=True, reason="this reading gives 52.24 m/s against the published 68.66 m/s; "
                   "the cause is not found (docs/dynamics.md: what was compared and ruled out)")
def test_linear_critical_speed_against_the_published_hopf_point():
    """Seydel (bifurcation.de, example exd10, from Hassard's worksheet of Kaas-Petersen's
    equations): the stationary solution loses stability at 68.66 m/s. Within 1 %."""
    assert critical_speed(CooperriderBogie(50.0)) == pytest.approx(PUBLISHED_HOPF_SPEED, rel=0.01)


def test_subcritical_hopf_bifurcation():
    """True & Kaas-Petersen (1984): the Hopf bifurcation of the Cooperrider bogie is subcritical.
    Ramping down from the flange cycle at 1.1 Vc keeps a stable cycle below the Hopf point
    (to 0.98 Vc with the 0.01 Vc steps here), where a small motion about centred running decays:
    two attractors."""
    vc = critical_speed(CooperriderBogie(50.0))
    start = CooperriderBogie(1.1 * vc, initial_lateral_displacement=10e-3)
    result = ramp_down(start, vc * np.arange(1.10, 0.90, -0.01))
    nonlinear = result.nonlinear_critical_speed
    print(f"CooperriderBogie: nonlinear critical speed {nonlinear:.3f} m/s = {nonlinear / vc:.3f} Vc, "
          f"amplitude there {1e3 * result.amplitudes[-2]:.2f} mm")
    assert 0.95 * vc < nonlinear < 0.995 * vc
    below = dataclasses.replace(start, speed=nonlinear)
    ds = simulate(below, 10.0, n_output=2001, initial_state=result.cycle_state)
    y = np.abs(ds.lateral_displacement.values[:, 0])
    assert np.max(y[-200:]) > below.flange_clearance  # a flange-contact cycle
    assert np.max(y[-200:]) == pytest.approx(np.max(y[:200]), rel=1e-2)  # sustained
    assert np.max(np.abs(ds.frame_roll_angle.values[-200:])) > 1e-4  # the frame rolls with it
    # centred running is stable there: a 1 mm motion dies out at the least damped eigenvalue's rate
    small = dataclasses.replace(below, initial_lateral_displacement=1e-3)
    decay = float(np.max(np.linalg.eigvals(small.state_matrix()).real))
    y = np.abs(simulate(small, 20.0, n_output=801).lateral_displacement.values[:, 0])
    early, late = np.max(y[160:240]), np.max(y[640:720])  # t in [4, 6) and [16, 18) s
    assert decay < 0.0 and late < 0.5 * early
    assert late / early == pytest.approx(np.exp(12.0 * decay), rel=0.1)
