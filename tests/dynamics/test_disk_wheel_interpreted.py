"""The disk wheel's steady creepage and linearisation without numba's registries or scipy.optimize:
the kernels' source interpreted and Brent's method written out give the compiled kernels' and
``scipy.optimize.brentq``'s numbers bit for bit."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from railwear.dynamics import DiskWheelModel, disk_wheel, kernels

P2 = dict(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3, hertz_constant=1.05e11,
          primary_stiffness=1e6, primary_damping=4e4, sprung_mass=5000.0, rail_mass=150.0, pad_stiffness=1e8,
          pad_damping=5e4, f11=1.15e7, friction_coefficient=0.3, patch_half_length=6e-3)
RIGID = dict(P2, sprung_mass=None, rail_mass=None, pad_stiffness=0.0, pad_damping=0.0, primary_damping=1.5e5)


def _functions(rng):
    """Bracketed roots of several shapes: cubics, a saturating tanh, the cubic creep law's force,
    an exponential; tolerances as the disk wheel asks them and looser."""
    for i in range(600):
        c = rng.normal(size=3)
        shape = i % 4
        if shape == 0:
            f, a, b = (lambda x, c=c: c[0] + c[1] * x + c[2] * x ** 3), -3.0, 3.0
        elif shape == 1:
            f, a, b = (lambda x, c=c: math.tanh(c[0] * x) - 0.5 * c[1]), -abs(c[2]) - 2.0, abs(c[2]) + 2.0
        elif shape == 2:
            f, a, b = (lambda x, c=c: x * (1 - x / 3 + x * x / 27) - abs(c[0]) % 1), 0.0, 3.0
        else:
            f, a, b = (lambda x, c=c: math.exp(c[0] * x) - 1 - c[1]), -2.0, 2.0
        if np.sign(f(a)) != np.sign(f(b)):
            yield (f, a, b) + [(1e-16, 1e-14), (2e-12, 8.9e-16), (1e-8, 1e-10)][i % 3]


def test_brents_method_takes_brentqs_steps():
    """Bit for bit against scipy.optimize.brentq on some 450 brackets (a different step, a
    different order of operations or another stopping test changes the last bits)."""
    cases = list(_functions(np.random.default_rng(7)))
    assert len(cases) > 400
    for f, a, b, xtol, rtol in cases:
        assert disk_wheel._bracketed_root(f, a, b, xtol, rtol) == brentq(f, a, b, xtol=xtol, rtol=rtol)
    with pytest.raises(ValueError):
        disk_wheel._bracketed_root(lambda x: x * x + 1, -1.0, 1.0, 1e-12, 1e-12)


@pytest.mark.parametrize("creep_law", ["cubic", "fastsim"])
def test_steady_creepage_as_with_brentq(monkeypatch, creep_law):
    torques = np.linspace(-0.95, 0.95, 39) * P2["friction_coefficient"] * P2["static_load"] * P2["radius"]
    ours = [DiskWheelModel(**P2, traction_torque=t, creep_law=creep_law).steady_creepage() for t in torques]
    monkeypatch.setattr(disk_wheel, "_bracketed_root",
                        lambda f, a, b, xtol, rtol: brentq(f, a, b, xtol=xtol, rtol=rtol))
    theirs = [DiskWheelModel(**P2, traction_torque=t, creep_law=creep_law).steady_creepage() for t in torques]
    assert ours == theirs and len(set(ours)) == len(torques)


def _compiled(kernel):
    """The compiled ``kernel``; the disk wheel's right-hand side and outputs reached as the
    integrators reach them (``rhs`` and ``outputs`` of its kind, on float64 arrays), with the
    interpreted form's arguments (lists of floats)."""
    if kernel is kernels.disk_wheel_rhs:
        def rhs(t, y, p, surf, dydt):
            f = np.empty(len(dydt))
            kernels.rhs(kernels.KIND_DISK_WHEEL, t, np.array(y), np.array(p), np.array(surf), f)
            dydt[:] = f.tolist()
        return rhs
    if kernel is not kernels.disk_wheel_outputs:
        return kernel

    def outputs(t, y, p, surf, out):
        out[:] = kernels.outputs(kernels.KIND_DISK_WHEEL, np.full(1, t), np.array([y]), np.array(p), np.array(surf),
                                 len(out))[0].tolist()
    return outputs


@pytest.mark.parametrize("config, creep_law, torque", [(P2, "cubic", 6e3), (P2, "fastsim", -9e3), (RIGID, "cubic", 0.0),
                                                      (RIGID, "fastsim", 8.5e3)])
def test_linearisation_as_from_the_compiled_kernels(monkeypatch, config, creep_law, torque):
    ours = DiskWheelModel(**config, traction_torque=torque, creep_law=creep_law).linearisation()
    monkeypatch.setattr(disk_wheel, "_interpreted", _compiled)
    theirs = DiskWheelModel(**config, traction_torque=torque, creep_law=creep_law).linearisation()
    for mine, compiled in zip(ours, theirs):
        assert np.array_equal(mine, compiled)
    assert np.count_nonzero(ours[0]) >= 5 and np.count_nonzero(ours[2]) >= 4  # a linearisation that is there
