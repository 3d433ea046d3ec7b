"""Model constants from railwear.contact: Hertz constant and Kalker coefficients, as the disk wheel takes them."""

import math

import pytest

import railwear.dynamics
from railwear.contact import contact_constants, hertz_contact, kalker_coefficients
from railwear.dynamics import DiskWheelModel

# wheel radius 0.46 m on a rail head of 0.3 m: A along rolling from the wheel, B across from the rail
A, B = 0.5 / 0.46, 0.5 / 0.3
E, NU = 210e9, 0.28


def test_hertz_constant_reproduces_the_approach_at_other_loads():
    const = contact_constants(70e3, A, B, E, NU)
    for load in (20e3, 70e3, 150e3):
        approach = float(hertz_contact(load, A, B, E, NU).approach)
        assert const["hertz_constant"] * approach**1.5 == pytest.approx(load, rel=1e-12)


def test_kalker_constants_scale_with_the_patch():
    const = contact_constants(70e3, A, B, E, NU)
    patch = hertz_contact(70e3, A, B, E, NU)
    c11, c22, c23, c33 = kalker_coefficients(patch.a / patch.b, NU)
    shear = E / (2 * (1 + NU))
    assert const["f11"] == pytest.approx(shear * patch.a * patch.b * c11, rel=1e-12)
    assert const["f23"] == pytest.approx(shear * (patch.a * patch.b) ** 1.5 * c23, rel=1e-12)
    assert const["patch_half_length"] == pytest.approx(float(patch.a))
    # a wheel on a sharper rail head: patch longer than wide, so C11 > C22 and f11 of order 1e7 N
    assert const["f11"] > const["f22"] and 5e6 < const["f11"] < 2e7


def test_disk_wheel_from_contact_constants_starts_at_static_equilibrium():
    const = contact_constants(70e3, A, B, E, NU)
    model = DiskWheelModel(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3,
                           hertz_constant=const["hertz_constant"], primary_stiffness=1e6, f11=const["f11"],
                           patch_half_length=const["patch_half_length"])
    assert model.static_approach == pytest.approx(const["static_approach"], rel=1e-12)
    assert math.isclose(model.contact_stiffness, 1.5 * 70e3 / const["static_approach"])


def test_the_dynamics_re_export_the_contact_constants():
    from railwear.dynamics.models import contact_constants as old_path

    assert railwear.dynamics.contact_constants is contact_constants is old_path
