"""FASTSIM creep (``creep_law="fastsim"``) in the conical wheelset and the bogie."""

import dataclasses

import numpy as np
import pytest

from railwear.contact import fastsim, kalker_coefficients
from railwear.dynamics import BogieModel, WheelsetModel, critical_speed, kernels, simulate
from railwear.errors import ScenarioError

BASE = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6, f22=5.9e6,
            half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05)
HUNT = dict(BASE, conicity=0.2, flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3,
            wheel_load=50e3)


def test_small_creepage_slope_is_kalkers_up_to_the_strip_rule():
    """FASTSIM's linear force is Kalker's in the limit; on ny = 40 strips the midpoint rule over
    the strips overestimates it by exactly 1 / (2 ny^2) = 3.125e-4 (the rule along x is exact for
    the linear traction): the factor at zero creepage."""
    model = WheelsetModel(speed=40.0, **BASE, creep_law="fastsim")
    p, surf = model.params(), model.surface()
    factor = kernels.creep_factor(0.0, 1e5, p[kernels.WS_LAW], surf, int(p[kernels.WS_LAW_OFFSET]),
                                  int(p[kernels.WS_LAW_POINTS]))
    assert factor - 1.0 == pytest.approx(1.0 / (2 * 40**2), rel=1e-6)


@pytest.mark.parametrize("xi, eta", [(1e-4, 2e-4), (1e-3, -5e-4), (3e-3, 2e-3), (-4e-4, 1e-3), (2e-2, 1e-2)])
def test_wheelset_creep_forces_are_fastsims(xi, eta):
    """Without spin FASTSIM's traction keeps the direction of (f11 xi, f22 eta) and its size
    depends on their resultant only, so the tabulated factor gives FASTSIM's combined forces:
    the kernel's forces at a state with these creepages against railwear.contact.fastsim on a
    5 x 8 mm patch (measured: within 2.3e-5)."""
    a, b, load, mu, shear, nu = 5e-3, 8e-3, 6e4, 0.3, 8e10, 0.28
    c11, c22, _, _ = kalker_coefficients(a / b, nu)
    model = WheelsetModel(speed=40.0, **dict(BASE, f11=shear * a * b * c11, f22=shear * a * b * c22), wheel_load=load,
                          friction_coefficient=mu, creep_law="fastsim")
    # left wheel: xi = -(lam y / r0), eta = y'/V (psi = psi' = 0)
    state = np.array([-xi * model.rolling_radius / model.conicity, 0.0, eta * model.speed, 0.0])
    out = kernels.outputs(model.kind, np.zeros(1), state[None, :], model.params(), model.surface(),
                          kernels.WS_N_OUTPUTS)[0]
    assert out[0] == pytest.approx(xi, rel=1e-12) and out[1] == pytest.approx(eta, rel=1e-12)
    direct = fastsim(a, b, load, xi, eta, 0.0, mu, shear, nu)
    assert out[3] == pytest.approx(direct.Fx, rel=1e-4)
    assert out[4] == pytest.approx(direct.Fy, rel=1e-4)


@pytest.mark.parametrize("make", [
    lambda law: WheelsetModel(speed=40.0, **BASE, creep_law=law),
    lambda law: BogieModel.cooperrider(40.0, creep_law=law),
])
def test_linear_critical_speed_agrees_with_kalker(make):
    """The FASTSIM model linearises to Kalker's with all creep coefficients times FASTSIM's slope
    1 + 3.125e-4; that moves the critical speed by -6.3e-6 (wheelset) and -3.1e-5 (bogie)."""
    kalker, fast = make("cubic"), make("fastsim")
    slope = 1.0 + 1.0 / (2 * 40**2)
    scaled = dataclasses.replace(kalker, f11=slope * kalker.f11, f22=slope * kalker.f22)
    vc = critical_speed(fast)
    assert vc == pytest.approx(critical_speed(scaled), rel=1e-8)
    assert vc == pytest.approx(critical_speed(kalker), rel=1e-4)
    print(f"{type(fast).__name__}: FASTSIM critical speed {vc:.4f} m/s, Kalker {critical_speed(kalker):.4f} m/s")


def _cycle(model, t_end, column=None):
    y = np.abs(simulate(model, t_end, n_output=int(500 * t_end) + 1).lateral_displacement.values)
    y = y if column is None else y[:, column]
    last, before = np.max(y[-500:]), np.max(y[-1000:-500])
    assert last == pytest.approx(before, rel=1e-3)  # settled
    return last


def test_hunting_cycles_under_fastsim_and_the_cubic_law():
    """At large amplitude the two laws part (FASTSIM's elliptic-bound curve lies 0.03 above the
    cubic one at s = 0.5-1 and 0.03 below at s = 2-3): the flange-bounded cycle of the conical
    wheelset at 1.2 Vc grows from 6.852 to 6.862 mm (+0.14 %), the Cooperrider bogie's at 1.05 Vc
    (mu = 0.15) from 10.157 to 10.184 mm (+0.27 %)."""
    vc = critical_speed(WheelsetModel(speed=40.0, **HUNT))
    wheelset = {law: _cycle(WheelsetModel(speed=1.2 * vc, **HUNT, creep_law=law), 6.0) for law in ("cubic", "fastsim")}
    vb = critical_speed(BogieModel.cooperrider(40.0))
    bogie = {law: _cycle(BogieModel.cooperrider(1.05 * vb, initial_lateral_displacement=15e-3,
                                                friction_coefficient=0.15, creep_law=law), 10.0, column=0)
             for law in ("cubic", "fastsim")}
    for cycles, clearance in ((wheelset, 5e-3), (bogie, 9.1e-3)):
        print(f"cycle amplitude cubic {1e3 * cycles['cubic']:.4f} mm, FASTSIM {1e3 * cycles['fastsim']:.4f} mm")
        assert min(cycles.values()) > clearance
        assert 2e-4 < cycles["fastsim"] / cycles["cubic"] - 1.0 < 1e-2


def test_bad_creep_law_names_the_field():
    with pytest.raises(ScenarioError, match="^creep_law:"):
        WheelsetModel(speed=40.0, **BASE, creep_law="kalker")
    with pytest.raises(ScenarioError, match="^creep_law:"):
        BogieModel.cooperrider(40.0, creep_law="polach")
