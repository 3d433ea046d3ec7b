"""Several wheels on the time-domain track as a long-term body (stepwise and direct): a draw
runs every wheel together over its own frozen radius deviation; one wheel is the one-wheel body
bit for bit; two wheels half a long ring apart wear as two single wheels; a bogie's combinations
grow at the eigen-rates of the linear several-wheel model (WheelsOnRail); a resumed run is the
same run; `railwear run` takes a bogie stepwise file."""

import json
import math
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from railwear.dynamics.disk_wheel_track import WheelOnRing
from railwear.dynamics.wheels_track import WheelsOnRing
from railwear.errors import ScenarioError
from railwear.longterm.base import Checkpoint
from railwear.longterm.direct import Direct
from railwear.longterm.disk_wheel import depth_per_energy, start_lift, wheel_turn
from railwear.longterm.stepwise import Stepwise
from railwear.longterm.vehicle_track import METRO, VehicleTrackModel, WheelsOnRail
from railwear.longterm.vehicle_track_body import VehicleTrackBody, ring_for
from railwear.wear import EnergyLaw

LAW = EnergyLaw()
SPEED = 70 / 3.6
N = 128  # cells: the grid filter sinc³(n/N) is put on the linear rates
X = 2 * np.pi * np.arange(N) / N
LIFE = 1e7  # 10 000 km per unit normed time
RING = ring_for(METRO.track)  # 32 bays, 19.2 m
BOGIE = (0.0, 2.5)


def body(ring=RING, **kw):
    settings = dict(revolutions=4, transient_revolutions=2, samples=2, ring=ring, dt=1e-4)
    settings.update(kw)
    return VehicleTrackBody(METRO.wheel(SPEED), LAW, METRO.band_width, LIFE, **settings)


@pytest.mark.parametrize("positions", [None, BOGIE])
def test_a_draw_runs_the_wheels_together_on_the_ring(positions):
    """A frozen-geometry draw against the dynamics run by hand: the service's speed, one phase
    and one ring position for all wheels (the generator's draws in that order), the transient,
    then each wheel's frictional energy on its own cells as depth per unit normed time. Bit
    for bit: one wheel through WheelOnRing, the bogie through WheelsOnRing."""
    b = body(wheel_positions=positions)
    u = np.array([2e-6 * np.cos(8 * X) + 1e-6 * np.sin(3 * X), 1e-6 * np.cos(5 * X)])
    u = u if positions else u[0]
    rates, _ = b.draw(u, np.random.default_rng(5))
    rng = np.random.default_rng(5)
    speeds, _ = b.service.draw(rng, 2)
    phases, wheres = rng.uniform(0, 2 * np.pi, 2), rng.uniform(0, RING.length, 2)
    for i in range(2):
        shapes = np.atleast_2d(u - u.mean(-1, keepdims=True))
        models = [replace(b.model, speed=float(speeds[i]), radius_deviation=s, initial_angle=float(phases[i]),
                          initial_lift=start_lift(b.model, s, phases[i])) for s in shapes]
        turn = wheel_turn(models[0])
        per = math.ceil(turn / 1e-4 - 1e-9)
        if positions:
            dyn = WheelsOnRing(models[0], RING, turn / per, positions=positions)
            y = dyn.static_state(wheres[i], [m.initial_lift for m in models], models)
            p, surf = [m.params() for m in models], [m.surface() for m in models]
        else:
            dyn = WheelOnRing(models[0], RING, turn / per)
            y, p, surf = dyn.static_state(wheres[i], models[0].initial_lift), models[0].params(), models[0].surface()
        y, _ = dyn.run(y, 0.0, 2 * per, wheres[i], p, surf, np.zeros(0))
        energy = np.zeros(shapes.shape if positions else N)
        dyn.run(y, 2 * per * dyn.dt, 4 * per, wheres[i] + models[0].speed * (2 * per) * dyn.dt, p, surf, energy)
        depth = energy * depth_per_energy(models[0], N, LAW.beta, METRO.band_width)
        assert np.array_equal(rates[i], depth / (4 * per * dyn.dt * models[0].speed) * LIFE)
    assert rates.shape == (2,) + np.shape(u)


def test_one_wheel_is_the_one_wheel_body_bit_for_bit():
    """``wheel_positions`` of one wheel, and the scenario's ``wheel_positions_m = [0]``: the
    same stepwise result (u, its standard error), checkpoint fingerprint and result layout as
    without them."""
    from railwear.scenario import build, load_scenario

    u0 = 2e-6 * np.cos(8 * X)
    runs = []
    for positions in (None, (0.0,)):
        marks = []
        ds = Stepwise(body(wheel_positions=positions), 0.5e-6, limit_on="shape").run(
            u0, until=0.3, checkpoint=marks.append)
        runs.append((ds, marks[-1].fingerprint))
    (a, key_a), (b, key_b) = runs
    assert a.u.dims == ("time", "angle") and key_a == key_b
    assert np.array_equal(a.u.values, b.u.values) and np.array_equal(a.u_standard_error.values,
                                                                     b.u_standard_error.values)
    parts = [build.strategy(load_scenario("metro", {"strategy.kind": "stepwise", **extra})).body.fingerprint_parts()
             for extra in ({}, {"body.wheel_positions_m": [0.0]})]
    assert parts[0] == parts[1]


def test_far_apart_wheels_wear_as_two_single_wheels():
    """Two wheels half a 64-bay ring apart (19.2 m, a whole number of bays, so each sits where
    its single run sits in the bay), each with its own polygon, against each wheel alone with
    the same seed, 10 000 km in steps of 0.5 um on the shape: at the end every cell within one
    Monte Carlo standard error (measured 0.18 and 0.41 of it; the polygons' amplitudes within
    0.13 %, the single runs' steps differing as their shapes do)."""
    ring = ring_for(METRO.track, 64)
    u = np.array([2e-6 * np.cos(8 * X) + 1e-6 * np.sin(5 * X), 2e-6 * np.cos(6 * X + 1)])

    def run(b, u0):
        return Stepwise(b, 0.5e-6, limit_on="shape", seed=3).run(u0, until=1.0)

    pair = run(body(ring, wheel_positions=(0.0, ring.length / 2)), u)
    assert pair.u.dims == ("time", "wheel", "angle")
    for a in range(2):
        alone = run(body(ring), u[a])
        difference = pair.u.values[-1, a] - alone.u.values[-1]
        assert np.all(np.abs(difference) < pair.u_standard_error.values[-1, a]), a
        assert np.max(np.abs(u[a] - alone.u.values[-1] - np.mean(u[a] - alone.u.values[-1]))) > 0  # the shape wore


def combination_start(modes, orders, which, amplitude=2e-6):
    """The wheels' radius deviations (m) with each of ``orders`` in combination ``which`` of
    ``modes`` (``WheelsOnRail.rates``), the largest wheel at ``amplitude``."""
    u = np.zeros((2, N))
    for i, n in enumerate(orders):
        v = modes[i, :, which] / np.abs(modes[i, :, which]).max()
        u += amplitude * np.abs(v)[:, None] * np.cos(n * X + np.angle(v)[:, None])
    return u


def test_bogie_combinations_grow_at_the_linear_eigen_rates():
    """A 2.5 m bogie at 70 km/h, 2 um of orders 8 and 10 started in the fastest and then in
    the slowest combination of WheelsOnRail (order 8 fastest in anti-phase, 0.177 against 0.162
    per unit normed time, order 10 in phase, 0.071 against 0.043; the wheels' shares 0.996-1):
    the fitted growth of each combination's amplitude ``sqrt(|û_1|² + |û_2|²)`` over 10 000 km
    (Adams-Bashforth, 0.2 um on the shape, 2 draws of 2 + 4 revolutions) against ``Re λ``
    with the grid filter. Within 5 %, the tolerance the one-wheel stepwise and direct runs are
    held to against the Fourier technique (tests/longterm/test_vehicle_track_body.py);
    measured +1.2 / +2.9 % (fastest), -1.3 / +3.4 % (slowest). The faster combination grows
    faster in the run too."""
    orders = [8, 10]
    lam, modes = WheelsOnRail(VehicleTrackModel(METRO.wheel(SPEED), METRO.track), BOGIE).rates(
        orders, LAW, METRO.band_width)
    expected = lam.real * LIFE / SPEED * np.sinc(np.array(orders) / N)[:, None] ** 3
    assert np.all(expected[:, 0] - expected[:, 1] > 0.08 * expected[:, 0])  # the combinations split
    grown = np.empty((2, 2))
    for which in (0, 1):
        ds = Stepwise(body(wheel_positions=BOGIE), 0.2e-6, limit_on="shape", scheme="adams-bashforth",
                      seed=which).run(combination_start(modes, orders, which), until=1.0)
        harmonics = np.fft.rfft(ds.u.values, axis=-1)[:, :, orders]
        norm = np.sqrt(np.sum(np.abs(harmonics) ** 2, axis=1))
        grown[:, which] = [np.polyfit(ds.time.values, np.log(norm[:, i]), 1)[0] for i in range(len(orders))]
    assert np.all(np.abs(grown / expected - 1) < 0.05), grown / expected - 1
    assert np.all(grown[:, 0] > grown[:, 1])


def test_direct_bogie_combinations_grow_at_the_linear_eigen_rates():
    """The bogie of the stepwise test coupled (direct, A = 2e4, 192 revolutions, 10 000 km):
    each combination's growth against ``Re λ`` within 5 % (measured -1.3 / -0.8 % fastest,
    -0.7 / -0.5 % slowest), the faster combination faster."""
    orders = [8, 10]
    lam, modes = WheelsOnRail(VehicleTrackModel(METRO.wheel(SPEED), METRO.track), BOGIE).rates(
        orders, LAW, METRO.band_width)
    expected = lam.real * LIFE / SPEED * np.sinc(np.array(orders) / N)[:, None] ** 3
    grown = np.empty((2, 2))
    for which in (0, 1):
        ds = Direct(body(wheel_positions=BOGIE), 2e4, n_save=21).run(combination_start(modes, orders, which), until=1.0)
        norm = np.sqrt(np.sum(np.abs(np.fft.rfft(ds.u.values, axis=-1)[:, :, orders]) ** 2, axis=1))
        grown[:, which] = [np.polyfit(ds.time.values, np.log(norm[:, i]), 1)[0] for i in range(len(orders))]
    assert np.all(np.abs(grown / expected - 1) < 0.05), grown / expected - 1
    assert np.all(grown[:, 0] > grown[:, 1])


def test_direct_far_apart_wheels_wear_as_two_single_wheels():
    """Direct (A = 2e4, 5000 km) with two wheels half a 64-bay ring apart against each alone
    with the same seed (so the same start on the ring): the radius deviations at the end differ
    by under 3e-3 of the change of their shapes (measured 2.6e-4 and 1.0e-3: the ring's motion
    under the other wheel's load)."""
    ring = ring_for(METRO.track, 64)
    u = np.array([2e-6 * np.cos(8 * X) + 1e-6 * np.sin(5 * X), 2e-6 * np.cos(6 * X + 1)])

    def run(b, u0):
        return Direct(b, 2e4, n_save=11, seed=3).run(u0, until=0.5)

    pair = run(body(ring, wheel_positions=(0.0, ring.length / 2)), u)
    for a in range(2):
        alone = run(body(ring), u[a]).u.values[-1]
        change = u[a] - alone
        assert np.max(np.abs(pair.u.values[-1, a] - alone)) < 3e-3 * np.max(np.abs(change - change.mean())), a


@pytest.mark.parametrize("kind", ["stepwise", "direct"])
def test_resume_after_a_checkpoint_is_the_same_run(kind):
    """A bogie run resumed from its second save's checkpoint (through the file's plain fields)
    ends bit for bit where the uninterrupted run ends."""
    u0 = combination_start(np.ones((1, 2, 1)) / np.sqrt(2), [8], 0)
    if kind == "stepwise":
        strategy, until = Stepwise(body(wheel_positions=BOGIE), 0.05e-6, limit_on="shape",
                                   scheme="adams-bashforth"), 0.4
    else:
        strategy, until = Direct(body(wheel_positions=BOGIE), 2e4), 0.02
    marks = []
    whole = strategy.run(u0, until=until, checkpoint=marks.append)
    assert len(marks) >= 3
    again = strategy.run(u0, until=until, resume=Checkpoint.from_plain(marks[1].plain()))
    assert np.array_equal(whole.u.values, again.u.values)
    if kind == "stepwise":
        assert np.array_equal(whole.u_standard_error.values, again.u_standard_error.values)


def test_bad_input():
    with pytest.raises(ScenarioError, match=r"^wheel_positions: the wheels must be more than"):
        body(wheel_positions=(0.0, 0.6))
    with pytest.raises(ScenarioError, match=r"^u0: one radius deviation per wheel \(2 rows\)"):
        Stepwise(body(wheel_positions=BOGIE), 1e-6).run(np.zeros((3, N)), until=0.1)


def bogie_file(tmp_path, positions="[0, 2.5]"):
    """The metro scenario as a bogie on the stepwise strategy, small: 64 cells, 2 draws of
    1 + 2 revolutions, 5000 km, one speed."""
    from railwear.scenario import builtin_text

    text = builtin_text("metro")
    for old, new in (('kind = "vehicle_track"', f'kind = "vehicle_track"\nwheel_positions_m = {positions}\n'
                                                'samples = 2\nrevolutions = 2\ntransient_revolutions = 1'),
                     ('[strategy]\nkind = "fourier"', '[strategy]\nkind = "stepwise"\nstep_limit_um = 10.0'),
                     ("points = 512\nt_end = 5.0", "points = 64\nt_end = 0.05"), ("peak_to_peak_limit_mm = 0.1\n", ""),
                     ("highest_order = 40", "highest_order = 20"), ("speed_scatter_kmh = 5.0", "speed_scatter_kmh = 0.0")):
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "bogie.toml"
    path.write_text(text)
    return path


def test_railwear_run_on_a_bogie_stepwise_file(tmp_path):
    """The user path in a fresh interpreter (about 3 s): the bogie runs, the result has a
    ``wheel`` dimension, the summary names each wheel with its dominant order and the linear
    model's fastest combination of it; wheels closer than the ring allows are one line naming
    the field, exit 2."""
    import xarray as xr

    command = [sys.executable, "-m", "railwear", "run", "-o", str(tmp_path / "out"), "--no-figures"]
    out = subprocess.run(command + [str(bogie_file(tmp_path))], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    runs = json.loads((tmp_path / "out" / "summary.json").read_text())["runs"]
    assert [r["wheel"] for r in runs] == [0.0, 2.5]
    assert all("linear_growth_per_10000_km" in r and "dominant_amplitude_um" in r for r in runs)
    assert "wheel at 2.5 m: order" in out.stdout and "the linear model's fastest combination" in out.stdout
    with xr.open_dataset(tmp_path / "out" / "result.nc") as ds:
        assert ds.u.dims == ("time", "wheel", "angle") and list(ds.wheel.values) == [0.0, 2.5]
    bad = subprocess.run(command + [str(bogie_file(tmp_path, "[0, 1.0]"))], capture_output=True, text=True,
                         timeout=300)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr
    assert bad.stderr.strip().count("\n") == 0 and "body.wheel_positions_m: the wheels must be" in bad.stderr
