"""Longitudinal compliance in series with the contact (the rail head's and the wheel's), issue 21 item 2."""

import dataclasses

import numpy as np
import pytest
from scipy import integrate

from railwear.errors import ScenarioError
from railwear.longterm.vehicle_track import METRO, VehicleTrackModel
from railwear.track import rail
from railwear.track.longitudinal import HEAD_DISTANCE, longitudinal_receptance
from railwear.units import kmh_to_m_s
from railwear.wear import EnergyLaw

V = kmh_to_m_s(70.0)
ORDERS = np.arange(1, 81)


def _model(traction=0.05, tangential=(), contact="steady"):
    case = dataclasses.replace(METRO, traction_coefficient=traction)
    return VehicleTrackModel(case.wheel(V), case.track, 8, case.wheel_modes, case._contact(contact), tangential)


def _omega(model):
    return ORDERS * model.speed * (1 + model.steady_creepage()) / model.radius


def _wave_integral(g, k, tail):
    """(1/2π) ∫ g(ξ) dξ over the real line for an even ``g`` with a pole near ``ξ = k``, plus the
    analytic ``tail`` beyond ``40 k``."""
    total = 0.0
    for lo, hi in ((0, 2 * k), (2 * k, 40 * k)):
        pts = [k] if lo == 0 else None
        total += integrate.quad(lambda x: g(x).real, lo, hi, points=pts, limit=500, epsabs=0, epsrel=1e-10)[0]
        total += 1j * integrate.quad(lambda x: g(x).imag, lo, hi, points=pts, limit=500, epsabs=0, epsrel=1e-10)[0]
    return (total + tail(40 * k)) / np.pi


def test_rail_receptance_against_the_wave_integrals():
    """Rod and Euler beam under a point force and a point moment, by the wavenumber integral with a
    loss (E(1 + iη), η = 0.05), against the closed forms with the same loss: to 1e-5 (the tails beyond 40 k summed to first order)."""
    r = rail("60E1")
    omega, eta = 2 * np.pi * 340.0, 0.05
    e = r.youngs_modulus * (1 + 1j * eta)
    rho_a, ei, ea = r.mass_per_metre, e * r.second_moment, e * r.area
    k_rod, k = np.sqrt(rho_a * omega**2 / ea), (rho_a * omega**2 / ei) ** 0.25
    rod = _wave_integral(lambda x: 1 / (ea * x**2 - rho_a * omega**2), k_rod.real, lambda c: 1 / (ea * c))
    assert abs(rod - (-1j / (2 * omega * np.sqrt(ea * rho_a)))) < 1e-5 * abs(rod)
    beam = _wave_integral(lambda x: x**2 / (ei * x**4 - rho_a * omega**2), k.real, lambda c: 1 / (ei * c))
    assert abs(beam - (1 - 1j) / (4 * ei * k)) < 1e-5 * abs(beam)
    # The module's loss-free form: the rod's -i/(2ω sqrt(EA ρA)) plus h² times the beam's.
    h = HEAD_DISTANCE["60E1"]
    e0, k0 = r.youngs_modulus, (rho_a * omega**2 / (r.youngs_modulus * r.second_moment)) ** 0.25
    expected = -1j / (2 * omega * np.sqrt(e0 * r.area * rho_a)) + h**2 * (1 - 1j) / (4 * e0 * r.second_moment * k0)
    assert abs(longitudinal_receptance(r, omega) - expected) < 1e-12 * abs(expected)
    assert np.isclose(h, 0.09108, atol=1e-5)  # 172 mm rail, neutral axis 80.9 mm above the foot


def test_rigid_tangential_is_the_steady_model():
    """Without compliance the default path is untouched (bit for bit), and the closed form with
    every factor 1 equals the state-space transfer (to 1e-7: the two linearisations round apart)."""
    rigid, closed = _model(), _model()
    omega = _omega(rigid)
    before = METRO.fourier(V, EnergyLaw()).rates(ORDERS)
    assert np.array_equal(METRO.fourier(V, EnergyLaw(), tangential=()).rates(ORDERS), before)
    for output in ("frictional_power", "creepage", "creep_force", "normal_force"):
        a, b = rigid._steady_transfer(omega, output), closed._closed_form(omega, output)
        assert np.max(np.abs(a - b)) <= 1e-7 * np.max(np.abs(a)), output


@pytest.mark.parametrize("traction", [0.05, -0.05])
def test_rod_is_a_dashpot_in_series_with_the_creep_damper(traction):
    """With the rail's axial wave alone (h = 0) the compliance is ``1/(iωZ)`` and the creep force is
    a damper ``f/V``: at fixed wheel speed and load the rolling-radius power falls by exactly
    ``1 / (1 + f / (V Z))`` at every order (0.53-0.55 on the metro wheel)."""
    model = _model(traction, ("rail",))
    omega = _omega(model)
    r = model.track.rail
    z = 2 * r.area * np.sqrt(r.youngs_modulus * r.mass_per_metre / r.area)
    rod = 1 / (1j * omega * z)
    object.__setattr__(model, "tangential_receptance", lambda w: rod)
    parts = model.frictional_power_parts(omega)
    _, b_p, d_xi = model.power_sensitivities()
    ratio = parts["rolling_radius"] / (b_p * d_xi)
    f = model._linear[2][2, 1] / model._linear[2][1, 1]  # ∂F/∂ξ
    assert np.allclose(ratio, 1 / (1 + f / (model.speed * z)), rtol=1e-12, atol=0)
    assert 0.5 < ratio[0].real < 0.6  # f / (V Z) = 0.8-0.9 on the metro wheel
    total = model.transfer(omega, "frictional_power")
    assert np.allclose(sum(parts.values()), total, rtol=1e-12, atol=1e-12 * np.max(np.abs(total)))


def test_wheel_mass_compliance_falls_with_frequency():
    """The wheel's centre as a free mass: ``P = 1 / (1 - i f / (V ω m))``, so the creep force
    follows the kinematic creepage again at high orders (rolling-radius part → rigid one)."""
    model = _model(-0.05, ("wheel",))
    omega = _omega(model)
    parts = model.frictional_power_parts(omega)
    _, b_p, d_xi = model.power_sensitivities()
    f = model._linear[2][2, 1] / model._linear[2][1, 1]
    expected = 1 / (1 - 1j * f / (model.speed * omega * model.wheel.wheel_mass))
    assert np.allclose(parts["rolling_radius"] / (b_p * d_xi), expected, rtol=1e-12, atol=0)
    assert abs(expected[-1] - 1) < 0.2 < 0.6 < abs(expected[7] - 1)  # order 80 against order 8


def test_refusals():
    with pytest.raises(ScenarioError, match="^tangential:"):
        _model(tangential=("axle",))
    with pytest.raises(ScenarioError, match="^tangential:"):
        _model(tangential=("rail", "rail"))
    with pytest.raises(ScenarioError, match="^tangential:"):
        _model(tangential=("rail",)).passive_bound(1000.0)
    with pytest.raises(ScenarioError, match="^head_distance:"):
        longitudinal_receptance(dataclasses.replace(rail("60E1"), name="custom"), 100.0)
    with pytest.raises(ScenarioError, match="^angular_frequency:"):
        longitudinal_receptance(rail("60E1"), 0.0)


def test_the_scenario_fields_reach_the_model_and_one_wheel_models_refuse_them():
    """``[body] rolling_contact`` and ``tangential_compliance`` give the Fourier run the model built
    by hand (rates to 1e-12); the time-domain body refuses them by name; unset, the hash holds."""
    from railwear import api
    from railwear.longterm.fourier import Fourier
    from railwear.scenario import build, load_scenario, scenario_hash

    fields = {"body.rolling_contact": "transient", "body.tangential_compliance": ["rail", "wheel"]}
    sc = load_scenario("metro", fields)
    ds = api.run(sc)
    model = _model(tangential=("rail", "wheel"), contact="transient")
    expected = Fourier.disk_wheel(model, EnergyLaw(), METRO.band_width).rates(ds.order.values)
    np.testing.assert_allclose(ds.harmonic_growth_rate.values, expected.real, rtol=1e-12)
    for field, value in fields.items():
        with pytest.raises(ScenarioError, match=f"^{field}: the time-domain body"):
            build.strategy(load_scenario("metro", {field: value, "strategy.kind": "stepwise"}))
    with pytest.raises(ScenarioError, match="body.tangential_compliance"):
        load_scenario("metro", {"body.tangential_compliance": ["rail", "rail"]})
    with pytest.raises(ScenarioError, match="body.rolling_contact"):
        load_scenario("metro", {"body.rolling_contact": "fast"})
    assert scenario_hash(load_scenario("metro")) == "81ff3b9629ebc6e8ba258436b5ba02648541e629e1dbd215ab8aa5accb3a451c"


@pytest.mark.parametrize("contact, tangential", [("transient", ()), ("steady", ("rail", "wheel"))])
def test_several_wheels_take_the_non_steady_contact_and_the_compliances(contact, tangential):
    """The closed form is affine in the load, so over several wheels ``Y = P I + Q N̄``: one wheel
    is the single-wheel model and two wheels 60 m apart two single wheels (to 1e-12)."""
    from railwear.longterm.fourier import Fourier
    from railwear.longterm.vehicle_track import WheelsOnRail

    model = _model(-0.05, tangential, contact)
    single = Fourier.disk_wheel(model, EnergyLaw(), METRO.band_width).rates(ORDERS)
    one = WheelsOnRail(model, (0.0,)).rates(ORDERS, EnergyLaw(), METRO.band_width)[0][:, 0]
    far = WheelsOnRail(model, (0.0, 60.0)).rates(ORDERS, EnergyLaw(), METRO.band_width)[0]
    scale = np.max(np.abs(single))
    assert np.max(np.abs(one - single)) < 1e-12 * scale
    assert np.max(np.abs(far - single[:, None])) < 1e-12 * scale
