"""The disk wheel on the time-domain track (ring track) as a long-term body: its linear response
and the growth of the direct and stepwise strategies against the Fourier technique on the metro
case of railwear.longterm.vehicle_track, and the sleeper passing under the rolling wheel."""

import numpy as np
import pytest

from railwear.dynamics.disk_wheel_track import WheelOnRing
from railwear.errors import ScenarioError
from railwear.longterm.direct import Direct
from railwear.longterm.stepwise import Stepwise
from railwear.longterm.vehicle_track import METRO, vehicle_track_fourier
from railwear.longterm.vehicle_track_body import VehicleTrackBody, ring_for
from railwear.wear import Archard, EnergyLaw

LAW = EnergyLaw()
SPEED = 70 / 3.6
N = 256  # cells: the grid filter sinc³(n/N) on order 8 is 0.5 %, put on the Fourier rates
X = 2 * np.pi * np.arange(N) / N
LIFE = 1e7  # 10 000 km per unit normed time


def body(**kw):
    settings = dict(revolutions=4, transient_revolutions=2, samples=2, ring=ring_for(METRO.track), dt=1e-4)
    settings.update(kw)
    return VehicleTrackBody(METRO.wheel(SPEED), LAW, METRO.band_width, LIFE, **settings)


def fourier_rates(orders):
    """Fourier rates per unit normed time with the grid filter."""
    fourier = vehicle_track_fourier(METRO.wheel(SPEED), METRO.track, SPEED, LAW, METRO.band_width)
    orders = np.asarray(orders)
    return fourier.rates(orders) * np.sinc(orders / N) ** 3 * LIFE / SPEED


def test_linear_response_matches_fourier():
    """Frozen geometry over ±2 µm of one order (the difference removes what is even in u: the
    round wheel's wear and the sleeper passing), 8 revolutions after 4: the complex rate of
    orders 6-10 against the Fourier technique's (rigid-rail linearisation closed through the
    exact receptance, 8 bay offsets): 0.2-1.6 % measured (3 % asserted on the real part, 3 % of
    |λ| on the imaginary part)."""
    b = body(revolutions=8, transient_revolutions=4)
    orders = [6, 7, 8, 9, 10]
    expected = fourier_rates(orders)
    for n, lam in zip(orders, expected):
        u = 2e-6 * np.cos(n * X)
        plus, _ = b.draw(u, np.random.default_rng(1))
        minus, _ = b.draw(-u, np.random.default_rng(1))
        got = np.fft.rfft(-(plus - minus).mean(0))[n] / np.fft.rfft(2 * u)[n]
        assert abs(got.real - lam.real) < 0.03 * abs(lam.real), n
        assert abs(got.imag - lam.imag) < 0.03 * abs(lam), n


def growth(ds, orders):
    """Fitted ln-amplitude rates of ``orders`` over the run (per unit normed time)."""
    spectrum = np.abs(np.fft.rfft(ds.u.values, axis=1)[:, orders])
    return np.array([np.polyfit(ds.time.values, np.log(spectrum[:, i]), 1)[0] for i in range(len(orders))])


def test_direct_and_stepwise_growth_agree_with_fourier():
    """From 2 µm in each of orders 6, 8, 9, 10 over 10 000 km at 70 km/h (orders 8-10 grow,
    6 decays, by 6-18 %): direct at A = 2e4 against Fourier 0.1-1.2 % measured, stepwise
    (Adams-Bashforth, 0.2 µm on the shape) against direct 0.7-2.5 % (5 % asserted, the issue's
    target, for both)."""
    orders = [6, 8, 9, 10]
    u0 = sum(2e-6 * np.cos(n * X + n) for n in orders)
    fourier = fourier_rates(orders).real
    direct = growth(Direct(body(), 2e4, n_save=21).run(u0, until=1.0), orders)
    stepwise = growth(Stepwise(body(), 0.2e-6, limit_on="shape", scheme="adams-bashforth").run(u0, until=1.0), orders)
    assert np.all(np.abs(direct / fourier - 1) < 0.05)
    assert np.all(np.abs(stepwise / direct - 1) < 0.05)
    assert fourier[0] < 0 < fourier[1]  # a decaying and a growing order, not only one kind


def test_rolling_wheel_feels_the_sleepers():
    """A round wheel rolling at 70 km/h: the normal force oscillates at the sleeper-passing
    frequency V/L = 32.4 Hz (one FFT bin), the largest line of its spectrum after the start."""
    b = body()
    wheel = METRO.wheel(SPEED)
    dyn = b.dynamics(wheel)
    y = dyn.static_state(0.0)
    _, rec = dyn.run(y, 0.0, 6000, 0.0, wheel.params(), wheel.surface(), every=1)
    force = rec[1000:, 1] - rec[1000:, 1].mean()
    spectrum = np.abs(np.fft.rfft(force * np.hanning(force.size)))
    freqs = np.fft.rfftfreq(force.size, dyn.dt)
    assert abs(freqs[np.argmax(spectrum[1:]) + 1] - SPEED / 0.6) <= freqs[1]
    assert abs(rec[:, 1].mean() / wheel.static_load - 1) < 0.01


def test_energy_is_swept_exactly():
    """The swept energy of a run equals the trapezoidal integral of the recorded power (1e-12)."""
    wheel = METRO.wheel(SPEED)
    dyn = body().dynamics(wheel)
    energy = np.zeros(N)
    _, rec = dyn.run(dyn.static_state(1.0), 0.0, 500, 1.0, wheel.params(), wheel.surface(), energy, every=1)
    assert abs(energy.sum() / np.trapezoid(rec[:, 3], rec[:, 0]) - 1) < 1e-12


def test_bad_input():
    with pytest.raises(ScenarioError, match="^ring:"):
        VehicleTrackBody(METRO.wheel(SPEED), LAW, METRO.band_width, LIFE)
    with pytest.raises(ScenarioError, match="^law:"):
        body().__class__(METRO.wheel(SPEED), Archard(), METRO.band_width, LIFE, ring=ring_for(METRO.track))
    with pytest.raises(ScenarioError, match="^dt:"):
        WheelOnRing(METRO.wheel(SPEED), ring_for(METRO.track), 1e-3)


def test_worked_example():
    """docs/vehicle_track_time.md's example prints what it says (about 0.5 s)."""
    from helpers import doc_blocks, run_doc_block

    printed, expected = run_doc_block(doc_blocks("vehicle_track_time.md")[0], "vehicle_track_time.md")
    assert printed == expected
