"""Wear laws in the linear strategies: each law's linearisation against central differences of its
volume rate, the refusals, and Archard's Fourier growth against an analytic rigid-wheel limit and
against a direct run of the same disk wheel."""

import dataclasses

import numpy as np
import pytest

from railwear.dynamics import DiskWheelModel, contact_constants
from railwear.errors import ScenarioError
from railwear.geometry import roundness
from railwear.longterm.direct import Direct
from railwear.longterm.disk_wheel import DiskWheel
from railwear.longterm.fourier import Fourier, law_terms, operating_point, stability_map
from railwear.longterm.multiplier import Multiplier, QuasiStaticDriver, load_nonlinearity
from railwear.longterm.vehicle_track import METRO, VehicleTrackModel, growth_parts
from railwear.pde import DiskContact
from railwear.units import MM2, UG, kmh_to_m_s
from railwear.wear import USFD, Archard, ContactSample, EnergyLaw, Hardening, WearLaw
from railwear.wear.laws import LINEARISED

BAND = 0.01  # m
LIFE = 5e7  # m per unit normed time


def direct_wheel(speed):
    """The disk wheel of the built-in ``direct`` scenario (80 kN on a rail mass on pads, traction
    coefficient 0.05, μ = 0.3), built here so that the test does not read the scenario layer."""
    load, radius = 80e3, 0.46
    c = contact_constants(load, 1 / (2 * radius), 1 / (2 * 0.3), 210e9, 0.28)
    return DiskWheelModel(speed=speed, radius=radius, wheel_mass=1000.0, wheel_inertia=80.0, static_load=load,
                          hertz_constant=c["hertz_constant"], primary_stiffness=1.2e6, primary_damping=2e4,
                          f11=c["f11"], rail_mass=150.0, pad_stiffness=1e8, pad_damping=6e4,
                          friction_coefficient=0.3, traction_torque=0.05 * load * radius,
                          patch_half_length=c["patch_half_length"])


def point(tgamma_over_area=5.0, area=1.2e-4, speed=20.0):
    """One instant with ``Tγ/A`` in N/mm² on a patch of ``area`` m² at ``speed`` m/s."""
    power = tgamma_over_area * (area / MM2) * speed
    return ContactSample(np.array(power), np.array(80e3), np.array(0.05), np.array(speed), np.array(area))


CASES = [(EnergyLaw(), point(), ""), (Archard(), point(), ""),
         (USFD(), point(5.0), "mild"), (USFD(), point(40.0), "plateau"), (USFD(), point(100.0), "severe"),
         (USFD("as_printed"), point(10.39), "mild"), (USFD("as_printed"), point(40.0), "plateau"),
         (USFD("as_printed"), point(77.2001), "clipped"), (USFD("as_printed"), point(100.0), "severe")]


@pytest.mark.parametrize("law, at, regime", CASES, ids=lambda c: getattr(c, "name", None) or str(c))
def test_linearisation_is_the_central_difference_of_the_volume_rate(law, at, regime):
    """``∂V/∂q`` of the linearisation against ``(V(q + h) - V(q - h)) / 2h`` of ``volume_rate_of``
    with ``h = 1e-6 q0`` for every field: within ``1e-8 V0/q0``. On a piece each law is affine in
    each field, so the difference is exact up to round-off (about ``1e-16 V0 / h = 1e-10 V0/q0``);
    a wrong derivative or piece is off by order ``V0/q0``."""
    lin = law.linearisation(at)
    assert lin.regime == regime
    v0 = float(law.volume_rate_of(at))
    assert lin.volume_rate == pytest.approx(v0, rel=1e-14)
    for field in LINEARISED:
        q0 = float(getattr(at, field))
        h = 1e-6 * q0
        up, down = (float(law.volume_rate_of(dataclasses.replace(at, **{field: np.array(q0 + s)}))) for s in (h, -h))
        assert abs((up - down) / (2 * h) - lin.derivative(field)) <= 1e-8 * v0 / q0, field


def test_the_driver_times_the_coefficient_is_the_volume_rate():
    """``κ D`` (``driver_of``) against ``volume_rate_of`` over random contacts, out-of-contact
    instants among them (N < 0, no patch): to 1e-14."""
    rng = np.random.default_rng(5)
    n = 200
    contact = ContactSample(rng.uniform(0, 3e5, n), rng.uniform(-1e4, 1e5, n), rng.uniform(-0.5, 0.5, n),
                            rng.uniform(1, 80, n), np.where(rng.random(n) < 0.1, 0.0, rng.uniform(1e-5, 2e-4, n)))
    for law in (EnergyLaw(), Archard(), USFD(), USFD("as_printed")):
        kappa = law.linearisation(point()).coefficient
        np.testing.assert_allclose(kappa * law.driver_of(contact), law.volume_rate_of(contact), rtol=1e-14, atol=0)


def test_kinks_and_laws_without_a_linearisation_are_refused():
    model = direct_wheel(kmh_to_m_s(70.0))
    for law in (Hardening(), type("Constant", (WearLaw,), {"volume_rate_of": lambda self, c: 1e-12})()):
        with pytest.raises(ScenarioError, match=r"^wear\.law: .*needs a law with a linearisation \(energy, archard"):
            Fourier.disk_wheel(model, law, BAND)
        with pytest.raises(ScenarioError, match=r"^wear\.law: .*needs a law with a linearisation"):
            Multiplier.from_model(model, law, BAND, LIFE)
    with pytest.raises(ScenarioError, match=r"^wear\.law: .*needs a law with a linearisation"):
        METRO.fourier(kmh_to_m_s(70.0), Hardening())
    # Archard's |s| without traction, USFD on the step between its printed mild and plateau pieces
    with pytest.raises(ScenarioError, match=r"^wear\.law: Archard's \|s\| has a kink"):
        Fourier.disk_wheel(dataclasses.replace(model, traction_torque=0.0), Archard(), BAND)
    with pytest.raises(ScenarioError, match=r"^wear\.law: USFD's rate has a kink"):
        USFD("as_printed").linearisation(point(10.4))


def test_usfd_mild_is_the_energy_law_of_5_3_ug_per_joule():
    """Below ``Tγ/A`` = 10.4 N/mm² USFD's rate ``K = 5.3 Tγ/A`` is the energy law with ``k_e = 5.3
    µg/J``: the same Fourier rates to 1e-12 (the direct scenario's wheel at 70 km/h sits at
    ``Tγ/A`` = 0.013 N/mm² on its 10 mm band: mild)."""
    model = direct_wheel(kmh_to_m_s(70.0))
    usfd, energy = Fourier.disk_wheel(model, USFD(), BAND), Fourier.disk_wheel(model, EnergyLaw(5.3e-9), BAND)
    assert law_terms(model, USFD(), BAND)[0].regime == "mild"
    orders = np.arange(1, 17)
    np.testing.assert_allclose(usfd.rates(orders), energy.rates(orders), rtol=1e-12)
    assert usfd.mean_rate == pytest.approx(energy.mean_rate, rel=1e-12)


def rigid_wheel(**extra):
    """The disk wheel in the limit of the evolution equation's rigid disk: stiff contact, no
    suspension, fast spin (``J`` = 1e-3 kg m²), no saturation, 40 m/s."""
    disk = DiskContact(friction_coefficient=1e3, load_scatter=0.01)
    return disk, DiskWheelModel(
        speed=40.0, radius=disk.wheel_radius, wheel_mass=disk.unsprung_mass, wheel_inertia=1e-3,
        static_load=disk.static_load, hertz_constant=1e16, primary_stiffness=0.0, f11=disk.creep_stiffness,
        traction_torque=disk.traction_coefficient * disk.static_load * disk.wheel_radius, **extra)


def test_archard_in_the_rigid_limit_is_the_analytic_rate():
    """Rigid wheel on a rigid rail (stiff contact, no suspension, fast spin), no saturation, no patch
    filter: the wheel follows the radius, ``N = W + m ū''`` (``N̂ = -m n² Ω² û``), and the spin
    balances the torque, ``Fx = T / (R0 + ū)`` with ``ξ = Fx / f11(N)``, ``f11 ∝ N^(2/3)``. So
    Archard's driver ``D = N ξ V ∝ N^(1/3) / (R0 + ū)`` and

        λ_n = c D0 (m n² Ω² / (3 W) + 1 / R0),   c = (k/H) / (2π R0 w),  D0 = W ξ0 V

    real, positive at every order: a crest unloads and so wears less under Archard (under the
    energy law, ``π ∝ N^(-2/3)``, it wears more). Measured 1.6e-4 (the finite contact stiffness
    and spin inertia), 1e-3 asserted; the mean radius falls at ``c D0`` to 1e-12."""
    disk, model = rigid_wheel()
    v = model.speed
    law, band = Archard(1e-4, 3e9), 2 * float(disk.patch.b)
    fourier = Fourier.disk_wheel(model, law, band)
    n = np.arange(1, 9)
    lam = fourier.rates(n)
    W, R0, m, xi0 = model.static_load, model.radius, model.wheel_mass, model.steady_creepage()
    omega = v * (1 + xi0) / R0
    c, d0 = law.coefficient / law.hardness / (2 * np.pi * R0 * band), W * xi0 * v
    np.testing.assert_allclose(lam.real, c * d0 * (m * n**2 * omega**2 / (3 * W) + 1 / R0), rtol=1e-3)
    assert np.max(np.abs(lam.imag)) < 1e-3 * np.max(lam.real)
    assert fourier.mean_rate == pytest.approx(-c * d0, rel=1e-12)


def test_usfd_plateau_in_the_rigid_limit_wears_by_the_patch_area():
    """On USFD's plateau ``K = 55`` the driver ``D = 55 A v`` does not see the frictional power but
    the patch area, ``A ∝ N^(2/3)`` (Hertz): ``δD/D0 = (2/3) δN/W``, so in the rigid limit (``N̂ =
    -m n² Ω² û``, see the Archard case) ``λ_n = c D0 (2/3) m n² Ω² F_n² / W``, ``c = (1 µg/ρ) /
    (2π R0 w)``, ``D0 = 55 A0 v``. The band is narrowed to put ``Tγ/A`` at 40 N/mm². Measured
    1.6e-4, 1e-3 asserted."""
    _, model = rigid_wheel(patch_half_length=6e-3)
    law, v, R0, W = USFD(), model.speed, model.radius, model.static_load
    per_band = float(operating_point(model, 1.0).patch_area) / MM2  # mm² per m of band
    band = float(operating_point(model, 1.0).frictional_power) / v / 40.0 / per_band
    assert law_terms(model, law, band)[0].regime == "plateau"
    n = np.arange(1, 9)
    lam = Fourier.disk_wheel(model, law, band).rates(n)
    omega = v * (1 + model.steady_creepage()) / R0
    c, d0 = UG / law.density / (2 * np.pi * R0 * band), 55.0 * per_band * band * v
    filt = np.sinc(n * model.patch_half_length / R0 / np.pi) ** 2
    np.testing.assert_allclose(lam.real, c * d0 * 2 / 3 * model.wheel_mass * n**2 * omega**2 / W * filt, rtol=1e-3)


def test_archard_fourier_growth_matches_a_direct_run():
    """The direct scenario's wheel at 70 km/h worn by Archard (k = 1e-4, H = 3 GPa) on 64 points,
    harmonics 2-12 of 15 µm, A = 2000, until 0.1 mm (2750 km, 481 revolutions, about 2 s): the
    slope of ln |û_n| over the distance of the fastest order against the Fourier rate times the
    grid's filter ``sinc³(n/64)`` (docs/strategies.md, grid study). Measured: order 6 (the energy
    law's is 8) at 1.644e-5 /km against 1.658e-5 (+0.9 %; +5.4 % without the filter), 3 %
    asserted; the mean wear rate 0.04 % apart, 0.5 % asserted."""
    v = kmh_to_m_s(70.0)
    model, law, points = direct_wheel(v), Archard(), 64
    rng = np.random.default_rng(4)
    orders = np.arange(2, 13)
    u0 = roundness.harmonics(points, orders, np.full(orders.size, 15e-6), rng.uniform(0, 2 * np.pi, orders.size))
    fourier = Fourier.disk_wheel(model, law, BAND)
    per_km = fourier.rates(orders).real / v * 1e3 * np.sinc(orders / points) ** 3
    fastest = int(orders[np.argmax(per_km)])
    assert fastest == 6 and int(np.argmax(Fourier.disk_wheel(model, EnergyLaw(), BAND).rates(orders).real)) + 2 == 8
    ds = Direct(DiskWheel(model, law, BAND, LIFE, outputs_per_revolution=500), 2000.0).run(u0, 1.0, 0.1e-3)
    u = ds.u.values
    km = ds.time.values * LIFE / 1e3
    amp = np.abs(np.fft.rfft(u - u.mean(1, keepdims=True), axis=1))
    direct = np.array([np.polyfit(km, np.log(amp[:, n]), 1)[0] for n in orders])
    assert int(orders[np.argmax(direct)]) == fastest
    assert per_km[fastest - 2] == pytest.approx(direct[fastest - 2], rel=0.03)
    assert fourier.mean_rate / v * 1e3 == pytest.approx(-float(ds.mean_removed_depth[-1]) / km[-1], rel=5e-3)


def test_archard_load_remainder_is_the_second_order_of_n_to_the_third():
    """No saturation: ``ξ = F / f11(N) ∝ N^(-2/3)``, so Archard's ``D = N ξ V ∝ N^(1/3)`` and
    ``D(W + w) - D(W) - D'(W) w = -(1/9) D(W) (w/W)² + O(w³)``: to 2 % at ±2 % of ``W`` (the
    cubic term is 1.1 % there); the energy law's is +5/9 (test_multiplier_law.py)."""
    wheel = dataclasses.replace(METRO.wheel(kmh_to_m_s(70.0)), friction_coefficient=np.inf)
    W, c = wheel.static_load, 1.0
    driver = QuasiStaticDriver(wheel, Archard(), METRO.band_width)
    g = load_nonlinearity(wheel, c, driver).at_speed(0.0)
    w = np.array([-0.02, 0.02]) * W
    np.testing.assert_allclose(g(w), c / 9 * driver(W) * (w / W) ** 2, rtol=0.02)


def test_archard_multiplier_gives_the_fourier_growth_in_the_linear_limit():
    """The multiplier law on the metro wheel over the track with Archard, from 1 nm: the fitted
    growth of each order equals its Fourier ``Re λ_n`` to 1e-4 of the largest (as for the energy
    law in test_multiplier_law.py)."""
    speed = kmh_to_m_s(70.0)
    model = VehicleTrackModel(METRO.wheel(speed), METRO.track)
    u0 = roundness.random_perturbation(64, 40e-6, 2, 20, np.random.default_rng(3))
    u0 = u0 / np.ptp(u0) * 1e-9
    ds = Multiplier.from_model(model, Archard(), METRO.band_width, LIFE).run(u0, 0.5)
    orders = np.arange(2, 21)
    expected = METRO.fourier(speed, Archard()).rates(orders).real * LIFE / speed
    np.testing.assert_allclose(ds.growth_rate.sel(order=orders).values, expected, rtol=0,
                               atol=1e-4 * np.max(np.abs(expected)))


def test_growth_parts_split_the_law_and_maps_take_it():
    """Under Archard the three parts of the metro growth still sum to the Fourier rate (to 1e-8 of
    the largest; the energy law's split in test_vehicle_track_high_speed.py), and the stability map
    is the Fourier rate per km."""
    speed = kmh_to_m_s(70.0)
    orders = np.arange(2, 16)
    parts = growth_parts(METRO.wheel(speed), METRO.track, speed, Archard(), METRO.band_width, orders)
    total = parts["rolling_radius"] + parts["rotation"] + parts["normal_force"]
    np.testing.assert_allclose(total, parts["total"], rtol=0, atol=1e-8 * np.max(np.abs(parts["total"])))
    model = direct_wheel(speed)
    smap = stability_map(lambda s: dataclasses.replace(model, speed=s), [speed], orders, Archard(), BAND)
    np.testing.assert_allclose(smap.growth_rate.values[0],
                               Fourier.disk_wheel(model, Archard(), BAND).rates(orders).real / speed * 1e3, rtol=1e-12)
