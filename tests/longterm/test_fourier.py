"""The Fourier strategy against closed forms and against the evolution equation in the rigid limit."""

import numpy as np
import pytest

from railwear.dynamics import DiskWheelModel
from railwear.longterm.fourier import Fourier, contact_filter, stability_map
from railwear.pde import DiskContact, dispersion
from railwear.wear import EnergyLaw


def spring_wheel(speed=30.0, **extra):
    base = dict(speed=speed, radius=0.46, wheel_mass=600.0, wheel_inertia=80.0, static_load=80e3,
                hertz_constant=9e10, primary_stiffness=1.2e6, f11=1.2e7, patch_half_length=6e-3)
    base.update(extra)
    return DiskWheelModel(**base)


def test_normal_force_driver_matches_mass_spring_contact_spring_to_round_off():
    """Wheel mass m on a primary spring k1, contact spring kc on a rigid rail, wear c N:
    N̂/û = kc (k1 - m ω²) / (k1 + kc - m ω²)."""
    model = spring_wheel()
    c = 1e-15  # m/s per N
    strategy = Fourier.disk_wheel(model, c, 0.012, driver="normal_force")
    orders = np.arange(1, 40)
    w = orders * strategy.wheel_speed
    kc, k1, m = model.contact_stiffness, model.primary_stiffness, model.wheel_mass
    closed = kc * (k1 - m * w**2) / (k1 + kc - m * w**2)
    expected = -c * closed * contact_filter(orders, model.patch_half_length / model.radius) ** 2
    np.testing.assert_allclose(strategy.rates(orders), expected, rtol=1e-12)


def test_rigid_limit_agrees_with_the_evolution_equation():
    """Stiff contact, no suspension, fast wheel spin, no saturation, no patch filter: the Fourier
    rates are the PDE's round-wheel dispersion for the disk-contact h (per second of running),
    plus one term the PDE leaves out: the torque acts through the lever R0 + u, so the creep force,
    and with it the creepage, falls like 1 - u/R0 and the frictional power like 1 - 2u/R0 at every
    order: a rate 2 c π0 / R0."""
    disk = DiskContact(friction_coefficient=1e3, load_scatter=0.01)
    v = 40.0
    model = DiskWheelModel(
        speed=v, radius=disk.wheel_radius, wheel_mass=disk.unsprung_mass, wheel_inertia=1e-3,
        static_load=disk.static_load, hertz_constant=1e16, primary_stiffness=0.0,
        f11=disk.creep_stiffness, traction_torque=disk.traction_coefficient * disk.static_load * disk.wheel_radius)
    band = 2 * float(disk.patch.b)
    strategy = Fourier.disk_wheel(model, EnergyLaw(disk.specific_wear, disk.density), band)
    orders = np.arange(1, 9)
    per_second = strategy.rates(orders).real
    a = -float(disk.slope(0.0, v))
    pde_per_second = dispersion(a, orders) * v / disk.life_distance
    lever = -2 * strategy.mean_rate / disk.wheel_radius
    np.testing.assert_allclose(per_second, pde_per_second + lever, rtol=2e-3)
    # and the mean radius falls at the same rate
    assert strategy.mean_rate == pytest.approx(float(disk(0.0, speed=v)) * v / disk.life_distance, rel=2e-3)


def test_run_evolves_each_harmonic_exponentially():
    model = spring_wheel(rail_mass=150.0, pad_stiffness=2e8, pad_damping=5e4, traction_torque=2e3)
    strategy = Fourier.disk_wheel(model, EnergyLaw(), 0.012)
    x = 2 * np.pi * np.arange(256) / 256
    u0 = 1e-6 * np.cos(3 * x) + 2e-6 * np.sin(11 * x + 0.3)
    ds = strategy.run(u0, 3.6e5, n_save=5)
    lam = strategy.rates([3, 11])
    t = ds.time.values[-1]
    spectrum = np.fft.rfft(ds.u.values[-1]) / 128  # amplitudes A with u = Re(A e^{inx})
    assert spectrum[3] == pytest.approx(1e-6 * np.exp(lam[0] * t), rel=1e-12)
    assert spectrum[11] == pytest.approx(2e-6 * np.exp(1j * (0.3 - np.pi / 2)) * np.exp(lam[1] * t), rel=1e-12)
    assert ds.u.values[-1].mean() == pytest.approx(strategy.mean_rate * t, rel=1e-12)


def test_p2_resonance_selects_the_frequency_constant_order():
    """With a rail mass on pads the fastest-growing order excites one frequency at every speed:
    n* V / (2π R0) is constant to within one order (the frequency-constant rule)."""
    law = EnergyLaw()
    speeds = np.array([20.0, 30.0, 40.0, 60.0])
    m = stability_map(lambda v: spring_wheel(v, rail_mass=150.0, pad_stiffness=2e8, pad_damping=5e4,
                                             traction_torque=2e3),
                      speeds, np.arange(1, 100), law, 0.012)
    fastest = m.order.values[m.growth_rate.argmax("order").values]
    assert np.all(m.growth_rate.max("order") > 0)
    frequency = fastest * speeds / (2 * np.pi * 0.46)
    one_order = speeds / (2 * np.pi * 0.46)
    assert np.all(np.abs(frequency - np.median(frequency)) <= one_order)
