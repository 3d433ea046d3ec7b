"""A disk wheel with a P2 rail for the long-term strategy tests (the linear-dynamics scenario's)."""

import numpy as np
import pytest

from railwear.dynamics import DiskWheelModel, contact_constants
from railwear.geometry import roundness


def p2_wheel(speed):
    load = 80e3
    c = contact_constants(load, 1 / 0.92, 1 / 0.6, 210e9, 0.28)
    return DiskWheelModel(
        speed=speed, radius=0.46, wheel_mass=1000.0, wheel_inertia=80.0, static_load=load,
        hertz_constant=c["hertz_constant"], primary_stiffness=1.2e6, primary_damping=2e4, f11=c["f11"],
        rail_mass=150.0, pad_stiffness=1e8, pad_damping=6e4, friction_coefficient=0.3,
        traction_torque=0.05 * load * 0.46, patch_half_length=c["patch_half_length"])


@pytest.fixture(scope="session")
def wheel_220():
    return p2_wheel(220 / 3.6)


@pytest.fixture(scope="session")
def rough_u0():
    return roundness.random_perturbation(64, 40e-6, 2, 16, np.random.default_rng(1))


@pytest.fixture(scope="session")
def make_wheel():
    return p2_wheel
