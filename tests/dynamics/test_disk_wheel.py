"""The disk wheel (paper Fig. 5): linear transfer function, contact filter, energy, contact loss."""

import math

import numpy as np
import pytest

from railwear.dynamics import DiskWheelModel
from railwear.dynamics import kernels
from railwear.dynamics import simulate
from railwear.errors import ScenarioError

N_CELLS = 512
ANGLES = 2.0 * np.pi * np.arange(N_CELLS) / N_CELLS
# a wheel on a rail mass on pads (P2 resonance near 58 Hz) under a sprung mass
P2 = dict(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3, hertz_constant=1.05e11,
          primary_stiffness=1e6, primary_damping=4e4, sprung_mass=5000.0, rail_mass=150.0, pad_stiffness=1e8,
          pad_damping=5e4, f11=1.15e7, friction_coefficient=0.3, patch_half_length=6e-3)
RIGID = dict(P2, sprung_mass=None, rail_mass=None, pad_stiffness=0.0, pad_damping=0.0, primary_damping=1.5e5)


def _harmonic_fit(t, signal, omega):
    """Complex amplitude (``exp(i omega t)`` convention) and RMS residual of a harmonic fit."""
    basis = np.stack([np.cos(omega * t), np.sin(omega * t), np.ones_like(t)], axis=1)
    coef = np.linalg.lstsq(basis, signal, rcond=None)[0]
    residual = signal - basis @ coef
    return coef[0] - 1j * coef[1], float(np.sqrt(np.mean(residual**2)))


@pytest.mark.parametrize("config, order", [(P2, 3), (P2, 7), (P2, 12), (RIGID, 5)])
def test_normal_force_follows_the_linear_transfer_function(config, order):
    amplitude = 1e-7  # small against the static approach (7.6e-5 m)
    model = DiskWheelModel(**config, radius_deviation=amplitude * np.cos(order * ANGLES))
    ds = simulate(model, 2.0, rtol=1e-9, n_output=20001)
    late = ds.time.values > 1.0  # transients have decayed
    t = ds.time.values[late]
    omega = order * model.speed / model.radius
    n_hat, n_res = _harmonic_fit(t, ds.normal_force.values[late], omega)
    u_hat, _ = _harmonic_fit(t, ds.radius_deviation_at_contact.values[late], omega)
    assert n_res < 1e-2 * abs(n_hat)  # the force oscillates at n V / R0
    ratio = (n_hat / u_hat) / model.contact_force_transfer(omega)
    assert abs(ratio) == pytest.approx(1.0, abs=1e-3)  # amplitude within 0.1 % (issue: 1 %)
    assert abs(np.angle(ratio)) < 1e-3  # phase within 1 mrad


@pytest.mark.parametrize("order", [1, 7, 20])
def test_contact_filter_is_the_patch_mean(order):
    """The filter against a brute-force mean of the interpolated ``u`` over +-w, and against the
    spectral factor ``sinc(n w) sinc(n dx / 2)^2`` of the piecewise-linear ``cos(n x)`` (up to the
    aliases at ``M -+ n``, each below ``(n dx / 2 pi)^2`` in relative amplitude)."""
    amplitude = 1e-5
    model = DiskWheelModel(**P2, radius_deviation=amplitude * np.cos(order * ANGLES))
    w = model.patch_half_length / model.radius
    dx = 2 * np.pi / N_CELLS
    x = np.linspace(0.0, 2 * np.pi, 97)
    filtered = np.array([model.filtered_deviation(xi) for xi in x])
    window = np.linspace(-w, w, 20001)
    nodes, values = np.append(ANGLES, 2 * np.pi), np.append(model.radius_deviation, model.radius_deviation[0])
    brute = [np.trapezoid(np.interp((xi + window) % (2 * np.pi), nodes, values), window) / (2 * w) for xi in x]
    np.testing.assert_allclose(filtered, brute, rtol=0, atol=amplitude * 1e-9)
    sinc = lambda z: math.sin(z) / z  # noqa: E731
    factor = sinc(order * w) * sinc(order * dx / 2) ** 2
    alias = 2.0 * (order * dx / (2 * np.pi)) ** 2
    np.testing.assert_allclose(filtered, amplitude * factor * np.cos(order * x), rtol=0, atol=amplitude * alias)


def _energy(ds, model):
    """Kinetic + spring + contact potential (2/5 k_H delta^(5/2) - W delta) [J]."""
    d = ds.approach.values
    return (0.5 * model.wheel_mass * ds.wheel_velocity.values**2
            + 0.5 * model.sprung_mass * ds.sprung_velocity.values**2
            + 0.5 * model.rail_mass * ds.rail_velocity.values**2
            + 0.5 * model.wheel_inertia * ds.angular_velocity.values**2
            + 0.5 * model.primary_stiffness * (ds.wheel_displacement.values - ds.sprung_displacement.values)**2
            + 0.5 * model.pad_stiffness * ds.rail_displacement.values**2
            + 0.4 * model.hertz_constant * np.maximum(d, 0.0)**2.5 - model.static_load * d)


def test_energy_is_conserved_without_creep_and_damping_through_contact_loss():
    # 0.3 m/s upward at the start: the wheel jumps off the rail again and again
    model = DiskWheelModel(**dict(P2, primary_damping=0.0, pad_damping=0.0, f11=0.0), initial_vertical_velocity=0.3)
    drifts = {}
    for rtol in (1e-7, 1e-10):
        ds = simulate(model, 0.2, rtol=rtol, n_output=4001)
        energy = _energy(ds, model)
        static = -0.6 * model.static_load * model.static_approach  # potential at rest
        drifts[rtol] = np.max(np.abs(energy - energy[0])) / (energy[0] - static)
        lost = ds.event_direction.values
        assert lost.size >= 10 and lost[0] == -1
        assert np.all(lost[1:] == -lost[:-1])  # loss and regain alternate
        flight = ds.approach.values < 0.0
        assert flight.any() and np.all(ds.normal_force.values[flight] == 0.0)
    assert drifts[1e-10] < 1e-6
    assert drifts[1e-10] < drifts[1e-7] / 100.0  # the drift follows the tolerance


def test_events_sit_on_the_contact_boundary():
    from railwear.dynamics import integrators as integ

    model = DiskWheelModel(**P2, initial_vertical_velocity=0.3)
    p, surf = model.params(), model.surface()
    out = integ.integrate(model.kind, p, surf, model.initial_state(), 0.0, 0.05, 1e-9, 1e-13, integ.METHOD_DOPRI5,
                          0.0, np.inf, 10**6, np.zeros(0), 1, True, 1e6, np.zeros(0))
    ev_t, ev_y = out[7], out[8]
    assert ev_t.size >= 2
    gaps = [kernels.event(model.kind, t, y, p, surf) for t, y in zip(ev_t, ev_y)]
    assert np.max(np.abs(gaps)) < 1e-12 * model.static_approach * 1e3


def test_traction_torque_sets_the_steady_creepage_and_power():
    model = DiskWheelModel(**P2, traction_torque=8e3)
    xi = model.steady_creepage()
    force = model.traction_torque / model.radius
    assert force * k_sat_free(model, xi) == pytest.approx(force, rel=1e-9)
    ds = simulate(model, 0.5, rtol=1e-9, n_output=501)
    assert ds.creepage.values[-1] == pytest.approx(xi, rel=1e-6)
    assert ds.creep_force.values[-1] == pytest.approx(force, rel=1e-6)
    assert ds.frictional_power.values[-1] == pytest.approx(force * xi * model.speed, rel=1e-6)
    # with creep the contact angle advances at Omega = V (1 + xi) / R0
    angle = np.unwrap(ds.contact_angle.values)
    rate = np.polyfit(ds.time.values, angle, 1)[0]
    assert rate == pytest.approx(model.speed * (1 + xi) / model.radius, rel=1e-8)


def k_sat_free(model, xi):
    """Saturated creep force over the demanded force at the static load (1 at the steady creepage)."""
    lin = model.f11 * xi
    return lin * kernels.saturation_factor(abs(lin), model.friction_coefficient * model.static_load) / (
        model.traction_torque / model.radius)


def test_rosenbrock_and_dormand_prince_agree_through_contact_loss():
    model = DiskWheelModel(**P2, initial_vertical_velocity=0.3, traction_torque=5e3)
    explicit = simulate(model, 0.1, rtol=1e-9, n_output=1001)
    implicit = simulate(model, 0.1, rtol=1e-7, n_output=1001, method="rosenbrock")
    assert explicit.event_time.size == implicit.event_time.size >= 4
    np.testing.assert_allclose(implicit.event_time.values, explicit.event_time.values, rtol=0, atol=1e-6)
    peak = float(explicit.normal_force.max())
    assert float(np.abs(implicit.normal_force - explicit.normal_force).max()) < 1e-3 * peak


def test_creep_coefficient_grows_with_the_load_like_kalker():
    """f11 ~ c^2 ~ N^(2/3): at twice the static approach (N = 2^1.5 W) it doubles."""
    model = DiskWheelModel(**dict(P2, friction_coefficient=math.inf), traction_torque=2e3)
    y = model.initial_state()
    y[2] = -model.static_approach  # wheel pressed down: approach 2 delta_0
    out = kernels.outputs(model.kind, np.zeros(1), y[None, :], model.params(), model.surface(), kernels.DW_N_OUTPUTS)[0]
    normal, creepage, force = out[0], out[1], out[2]
    assert normal == pytest.approx(2**1.5 * model.static_load, rel=1e-12)
    assert force / creepage == pytest.approx(model.f11 * (normal / model.static_load) ** (2 / 3), rel=1e-12)


def test_numerical_linearisation_reproduces_the_analytic_force_transfer():
    model = DiskWheelModel(**P2, traction_torque=8e3)
    omega = np.array([50.0, 300.0, 456.0, 800.0])
    np.testing.assert_allclose(model.transfer(omega, "normal_force"), model.contact_force_transfer(omega), rtol=1e-8)


def test_creepage_and_frictional_power_follow_their_transfer_functions_under_traction():
    """The linearisation about steady traction (the Fourier strategy's building block): a small
    harmonic u of order 7 modulates creepage, creep force and frictional power at 7 Omega, with
    Omega = V (1 + xi) / R0, as the transfer functions say."""
    order = 7
    model = DiskWheelModel(**P2, traction_torque=8e3, radius_deviation=1e-7 * np.cos(order * ANGLES))
    ds = simulate(model, 2.0, rtol=1e-10, n_output=20001)
    late = ds.time.values > 1.0
    t = ds.time.values[late]
    omega = order * model.speed * (1 + model.steady_creepage()) / model.radius
    u_hat, _ = _harmonic_fit(t, ds.radius_deviation_at_contact.values[late], omega)
    for name in ("creepage", "creep_force", "frictional_power"):
        s_hat, residual = _harmonic_fit(t, ds[name].values[late], omega)
        assert residual < 1e-3 * abs(s_hat), name
        assert s_hat / u_hat == pytest.approx(model.transfer(omega, name), rel=1e-3), name


def test_rigid_disk_limit_normal_force_is_mass_times_curvature():
    """Paper: for a rigid disk wheel the normal force is, up to the load, the squared speed times
    the curvature: N - W = m (V/R0)^2 u_xx, i.e. N_hat / u_hat = -m omega^2 below the contact
    resonance (free wheel, rigid rail)."""
    model = DiskWheelModel(**dict(RIGID, primary_stiffness=0.0, primary_damping=0.0))
    omega = np.array([5.0, 20.0, 60.0])
    ratio = model.contact_force_transfer(omega) / (-model.wheel_mass * omega**2)
    np.testing.assert_allclose(ratio, 1.0, rtol=2e-3)


def test_frictional_energy_per_cell_is_conserved_and_placed_under_the_patch():
    base = dict(P2, patch_half_length=6e-3)
    round_wheel = DiskWheelModel(**base, traction_torque=8e3, radius_deviation=np.zeros(N_CELLS))
    omega = round_wheel.speed * (1 + round_wheel.steady_creepage()) / round_wheel.radius
    revolution = 2 * np.pi / omega
    # steady rolling over whole revolutions: every cell gets the same energy
    ds = simulate(round_wheel, 4 * revolution, rtol=1e-10, n_output=4001, cell_energy=True)
    energy = ds.frictional_energy.values
    assert ds.frictional_energy.attrs["units"] == "J" and ds.cell_angle.size == N_CELLS
    assert energy.sum() == pytest.approx(float(ds.frictional_power[0]) * 4 * revolution, rel=1e-9)
    assert np.std(energy) < 1e-9 * np.mean(energy)
    # a point contact over a quarter turn: only the swept cells, equally (the end cells by halves)
    point = DiskWheelModel(**dict(base, patch_half_length=0.0), traction_torque=8e3,
                           radius_deviation=np.zeros(N_CELLS))
    quarter = simulate(point, 0.25 * revolution, rtol=1e-10, n_output=11, cell_energy=True).frictional_energy.values
    assert np.all(quarter[N_CELLS // 4 + 1:] == 0.0)
    np.testing.assert_allclose(quarter[1:N_CELLS // 4], quarter[1], rtol=1e-9)
    np.testing.assert_allclose([quarter[0], quarter[N_CELLS // 4]], 0.5 * quarter[1], rtol=1e-6)
    # an out-of-round wheel: the total still equals the integral of the power
    worn = DiskWheelModel(**base, traction_torque=8e3, radius_deviation=2e-6 * np.cos(7 * ANGLES))
    ds = simulate(worn, 3 * revolution, rtol=1e-10, n_output=30001, cell_energy=True)
    total = np.trapezoid(ds.frictional_power.values, ds.time.values)
    assert ds.frictional_energy.values.sum() == pytest.approx(total, rel=1e-6)
    with pytest.raises(ScenarioError, match="cell_energy"):
        simulate(DiskWheelModel(**base), 0.01, cell_energy=True)


@pytest.mark.parametrize("torque", [2e3, 8e3, 9.5e3, -8e3])
def test_fastsim_creep_law_meets_fastsim_itself(torque):
    """With creep_law="fastsim" the steady creepage under a torque is the one at which FASTSIM
    (railwear.contact.fastsim, called directly on a patch with the model's f11) gives T / R0."""
    from railwear.contact import fastsim, kalker_coefficients

    model = DiskWheelModel(**P2, traction_torque=torque, creep_law="fastsim")
    xi = model.steady_creepage()
    ds = simulate(model, 0.3, rtol=1e-9, n_output=301)
    assert ds.creepage.values[-1] == pytest.approx(xi, rel=1e-6)
    a = b = 6e-3
    shear = model.f11 / (a * b * float(kalker_coefficients(1.0, 0.28)[0]))
    direct = -fastsim(a, b, model.static_load, xi, 0.0, 0.0, model.friction_coefficient, shear, 0.28).Fx
    assert direct == pytest.approx(torque / model.radius, rel=2e-3)  # braking too (negative torque)
    cubic = DiskWheelModel(**P2, traction_torque=torque)
    if torque > 9e3:  # near full slip the laws part
        assert abs(cubic.steady_creepage() / xi - 1) > 0.05


def test_surface_for_another_u_keeps_the_layout():
    model = DiskWheelModel(**P2, traction_torque=2e3, creep_law="fastsim",
                           radius_deviation=1e-6 * np.cos(3 * ANGLES))
    np.testing.assert_array_equal(model.surface_for(model.radius_deviation), model.surface())
    worn = model.surface_for(2e-6 * np.cos(3 * ANGLES))
    assert worn.size == model.surface().size
    offset = int(model.params()[kernels.DW_CREEP_TABLE_OFFSET])
    np.testing.assert_array_equal(worn[offset:], model.surface()[offset:])  # the creep curve follows
    with pytest.raises(ScenarioError, match="radius_deviation"):
        model.surface_for(np.zeros(7))


def test_fastsim_creep_curve_does_not_depend_on_the_patch():
    """The tabulated curve serves every model: FASTSIM's F/(mu N) against f11 xi/(mu N) is the
    same for other patch shapes, loads, friction and moduli."""
    from railwear.contact import fastsim, kalker_coefficients

    model = DiskWheelModel(**P2, creep_law="fastsim")
    surf, p = model.surface(), model.params()
    offset, points = int(p[kernels.DW_CREEP_TABLE_OFFSET]), int(p[kernels.DW_CREEP_TABLE_POINTS])
    for a, b, normal, mu, shear in ((4e-3, 8e-3, 5e4, 0.2, 7e10), (9e-3, 5e-3, 1.2e5, 0.45, 8.2e10)):
        f11 = shear * a * b * float(kalker_coefficients(a / b, 0.28)[0])
        for s in (0.3, 1.0, 2.5):
            direct = -fastsim(a, b, normal, s * mu * normal / f11, 0.0, 0.0, mu, shear, 0.28).Fx / (mu * normal)
            assert kernels.creep_curve(surf, offset, points, s) == pytest.approx(direct, rel=2e-3)


@pytest.mark.parametrize("creep_law", ["cubic", "fastsim"])
def test_linearisation_reads_the_creep_law_of_the_model(creep_law):
    """The linearisation's outputs against central differences of the compiled outputs on the
    model's own surface (round wheel, so ``u_bar = 0`` for both); under FASTSIM the creep force's
    slope is the creep curve's, not zero (the uniform surface once lacked the curve)."""
    model = DiskWheelModel(**P2, traction_torque=6e3, creep_law=creep_law)
    _, _, c, _ = model.linearisation()
    p, surf, y0 = model.params(), model.surface(), model.initial_state()
    step = 1e-7 * y0[1]
    yp, ym = y0.copy(), y0.copy()
    yp[1] += step
    ym[1] -= step
    out = kernels.outputs(model.kind, np.zeros(2), np.stack([yp, ym]), p, surf, kernels.DW_N_OUTPUTS)[:, :4]
    direct = (out[0] - out[1]) / (2 * step)  # d[N, xi, Fx, power] / d Omega
    assert abs(direct[2]) > 1e3  # the creep force does change with the spin
    np.testing.assert_allclose(c[:, 1], direct, rtol=1e-6, atol=1e-9 * np.abs(direct).max())
