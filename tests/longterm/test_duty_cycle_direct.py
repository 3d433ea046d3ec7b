"""The direct strategy over a duty cycle (railwear.longterm.direct): every segment from its own
settled state over the same surface, the wear weighed by distance. A cycle of one segment is the
single run bit for bit; two segments grow the averaged Fourier rates as one segment grows its
own; resume; bad input."""

import subprocess
import sys
import tomllib

import numpy as np
import pytest
from helpers import Killed, killed_after

import railwear
from railwear.errors import ScenarioError
from railwear.longterm.base import Checkpoint
from railwear.longterm.direct import Direct
from railwear.scenario import build, builtin_text, parse_scenario
from railwear.units import KM

PULL_BRAKE = [{"share": 0.5, "speed_kmh": 70.0, "traction_coefficient": 0.05},
              {"share": 0.5, "speed_kmh": 70.0, "traction_coefficient": -0.05}]
HARMONICS = {"kind": "harmonics", "orders": [6, 7, 8, 9, 10, 11, 12], "amplitudes_um": [5.0] * 7,
             "phases_deg": [0, 40, 80, 120, 160, 200, 240]}
ORDERS = np.arange(6, 13)


def direct_with(cycle=None, traction=None, depth_mm=0.01, factor=20000.0, initial=None, n_save=5):
    """The `direct` built-in (64 cells) over ``cycle``, or at the single ``traction`` demand."""
    data = tomllib.loads(builtin_text("direct"))
    data["contact"].pop("traction_coefficient")
    if cycle is not None:
        data["operation"] = {"life_distance_km": 50000.0, "cycle": cycle}
    if traction is not None:
        data["contact"]["traction_coefficient"] = traction
    data["solver"].update(points=64, depth_limit_mm=depth_mm, t_end=20.0, n_save=n_save)
    data["strategy"]["acceleration_factor"] = factor
    if initial is not None:
        data["initial"] = initial
    return parse_scenario(data)


def growth_per_km(ds):
    n = ORDERS
    return np.log(ds.amplitude.sel(order=n).values / ds.amplitude_initial.sel(order=n).values) / float(ds.distance[-1])


def test_a_cycle_of_one_segment_is_the_single_traction_run_bit_for_bit():
    single = railwear.run(direct_with(traction=0.05))
    cycle = railwear.run(direct_with([{"share": 1.0, "speed_kmh": 70.0, "traction_coefficient": 0.05}]))
    assert "duty cycle of 1 segment" in cycle.attrs["strategy_description"]
    for name in single.data_vars:
        a, b = single[name].values, cycle[name].values
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), name
    np.testing.assert_array_equal(single.time.values, cycle.time.values)


def test_two_equal_segments_are_the_single_run():
    """The same speed and demand split 0.3 / 0.7: the weights sum to one update of the single
    run (w = 0.3, 0.7), each segment from the same settled state, so the wheel is the single
    run's to 1e-6 of its out-of-roundness (the round-off of ``0.3 Δu + 0.7 Δu`` passes through
    the adaptive integrator's step choices, rtol 1e-7; measured 1e-8); a weighting off by a
    share would miss by 30 %."""
    single = railwear.run(direct_with(traction=0.05))
    split = railwear.run(direct_with([{"share": 0.3, "speed_kmh": 70.0, "traction_coefficient": 0.05},
                                      {"share": 0.7, "speed_kmh": 70.0, "traction_coefficient": 0.05}]))
    u, v = single.u.values, split.u.values
    assert u.shape == v.shape
    np.testing.assert_allclose(v, u, rtol=0, atol=1e-6 * np.ptp(u[0]))
    assert float(split.cost_revolutions) == pytest.approx(2 * float(single.cost_revolutions))


@pytest.fixture(scope="module")
def pull_brake():
    """Pulling at +0.05 and braking at -0.05, half the distance each, 70 km/h, A = 4000 (the
    rates below agree with A = 2000 to 0.1 %), 5 um harmonics 6-12 to 0.1 mm (about 3000 km);
    and each segment alone."""
    runs = {"cycle": railwear.run(direct_with(PULL_BRAKE, depth_mm=0.1, factor=4000.0, initial=HARMONICS))}
    for f in (0.05, -0.05):
        runs[f] = railwear.run(direct_with(traction=f, depth_mm=0.1, factor=4000.0, initial=HARMONICS))
    return runs


def test_two_segments_grow_the_averaged_fourier_rates(pull_brake):
    """The cycle's fastest orders 7, 8, 9 (Fourier: 4.0, 5.3, 3.8e-5 per km) grow at the
    averaged Fourier rates ``Σ p_k λ_k / V_k`` (with the grid's sinc³(n/64)) within the band
    measured for one segment against its own, -10 % to +7 % (measured -1.1, -1.7, -3.9 %); the
    mean wear per km within 2 % (measured 0.06 %)."""
    sc = direct_with(PULL_BRAKE, depth_mm=0.1, factor=4000.0, initial=HARMONICS)
    ds = pull_brake["cycle"]
    technique = build.fourier_technique(sc)
    fourier = technique.rates(ORDERS).real / technique.speed * KM * np.sinc(ORDERS / 64) ** 3
    ratio = growth_per_km(ds) / fourier
    fastest = np.argsort(fourier)[-3:]
    assert set(ORDERS[fastest]) == {7, 8, 9}
    assert np.all(ratio[fastest] > 0.90) and np.all(ratio[fastest] < 1.07), ratio
    per_km = float(ds.mean_removed_depth[-1]) / float(ds.distance[-1])
    assert per_km == pytest.approx(-technique.mean_rate / technique.speed * KM, rel=0.02)


def test_two_segments_grow_as_the_mean_of_each_run_alone(pull_brake):
    """Running the segments in proportion: the cycle's growth per km is the mean of the two
    single-segment direct runs' within 1 % at orders 6-12 (measured 0.06-0.35 %; orders 10-12
    sit 8-22 % below the averaged Fourier rate, as the traction run alone sits below its own
    there, where pulling and braking nearly cancel)."""
    mean = 0.5 * (growth_per_km(pull_brake[0.05]) + growth_per_km(pull_brake[-0.05]))
    np.testing.assert_allclose(growth_per_km(pull_brake["cycle"]), mean, rtol=0.01)


def test_a_killed_cycle_resumes_bit_for_bit_through_a_file(tmp_path):
    """Each segment's carried state goes through the checkpoint (an .npz file) and back."""
    sc = direct_with(PULL_BRAKE, depth_mm=0.02, factor=4000.0, n_save=6)
    strategy, u0 = build.strategy(sc), build.initial_wear(sc)
    whole = strategy.run(u0, until=1.0, depth_limit=2e-5)
    saved = []
    with pytest.raises(Killed):
        strategy.run(u0, until=1.0, depth_limit=2e-5, checkpoint=killed_after(3, saved))
    assert any(k.startswith("carry_s1_") for k in saved[-1].fields)
    np.savez(tmp_path / "cp.npz", **saved[-1].plain())
    with np.load(tmp_path / "cp.npz") as data:
        back = Checkpoint.from_plain({k: data[k] for k in data.files})
    resumed = strategy.run(u0, until=1.0, depth_limit=2e-5, resume=back)
    np.testing.assert_array_equal(resumed.u.values, whole.u.values)
    np.testing.assert_array_equal(resumed.time.values, whole.time.values)


@pytest.fixture(scope="module")
def one_body():
    return build.strategy(direct_with(traction=0.05)).body


@pytest.mark.parametrize("cycle, message", [
    (((0.5, None), (0.5, None)), "cycle: segment 0: body must be a railwear.longterm.base.Body, not NoneType"),
    (((0.0, "body"),), "cycle: segment 0: share must be > 0, got 0.0"),
    (((float("nan"), "body"),), "cycle: segment 0: share must be > 0, got nan"),
    (((0.5, "body"), (0.4, "body")), "cycle: the shares of the distance must sum to 1, not 0.9"),
    (((1.0,),), r"cycle: segment 0: must be a \(share, body\) pair"),
])
def test_a_bad_cycle_is_a_one_line_error_naming_it(one_body, cycle, message):
    cycle = tuple(tuple(one_body if x == "body" else x for x in part) for part in cycle)
    with pytest.raises(ScenarioError, match=message) as err:
        Direct(one_body, 4000.0, cycle=cycle)
    assert "\n" not in str(err.value)


def test_railwear_run_over_a_cycle_and_a_bad_one(tmp_path):
    """`railwear run` in a fresh interpreter: the cycle runs and its summary states the duty; a
    cycle whose shares miss 1 exits 2 with one line naming operation.cycle."""
    text = builtin_text("direct").replace("traction_coefficient = 0.05\n", "")
    text = text.replace("speed_kmh = 70.0\n", "").replace("depth_limit_mm = 1.0", "depth_limit_mm = 0.005")
    cycle = "".join(f"\n[[operation.cycle]]\nshare = {s['share']}\nspeed_kmh = {s['speed_kmh']}\n"
                    f"traction_coefficient = {s['traction_coefficient']}\n" for s in PULL_BRAKE)
    (tmp_path / "cycle.toml").write_text(text + cycle)
    (tmp_path / "bad.toml").write_text(text + cycle.replace("share = 0.5", "share = 0.4", 1))
    ok = subprocess.run([sys.executable, "-m", "railwear", "run", str(tmp_path / "cycle.toml"), "-o",
                         str(tmp_path / "out"), "--no-figures"], capture_output=True, text=True, timeout=300)
    assert ok.returncode == 0, ok.stderr
    summary = (tmp_path / "out" / "summary.txt").read_text()
    assert "duty cycle of 2 segment(s): mean creep force +0.0000 x wheel load, braking over 50%" in summary, summary
    bad = subprocess.run([sys.executable, "-m", "railwear", "run", str(tmp_path / "bad.toml"), "-o",
                          str(tmp_path / "bad"), "--no-figures"], capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1, bad.stderr
    assert "operation.cycle" in bad.stderr and "Traceback" not in bad.stderr


class TestTheSwitchesLeftOut:
    """What the carried settled states leave out (docs/vehicle_track.md, Direct): the switches.
    The `direct` built-in's disk wheel at 70 km/h; the 10 revolutions after a switch against 10
    settled ones."""

    @staticmethod
    def wheel(u, traction, speed_kmh=70.0):
        from dataclasses import replace

        from railwear.longterm.disk_wheel import start_lift

        m = build.disk_wheel_model(direct_with(traction=0.05), speed_kmh / 3.6)
        return replace(m, traction_torque=traction * m.static_load * m.radius, radius_deviation=u,
                       initial_lift=start_lift(m, u, 0.0))

    @staticmethod
    def turns(model, y, t0, seconds):
        """``(y, energy per cell (J))`` after ``seconds`` from ``y`` at ``t0``."""
        from railwear.longterm.disk_wheel import advance, long_term_integrator

        energy = np.zeros(model.radius_deviation.size)
        y, _ = advance(model, model.params(), model.surface(), y, t0, t0 + seconds, energy, long_term_integrator())
        return y, energy

    def switched(self, u, before, after, steps=1, over=0.0):
        """From the settled ``before`` to ``after`` (each ``(traction, km/h)``), the traction in
        ``steps`` equal steps over ``over`` seconds: the energy per cell (J) of the 10 revolutions
        after the last step, of 10 settled revolutions at ``after``, and the extra energy (J) of
        the intermediate levels over their settled power ``|f W ξ V|``."""
        from railwear.longterm.disk_wheel import wheel_turn

        a = self.wheel(u, *before)
        t = 40 * wheel_turn(a)
        y, _ = self.turns(a, a.initial_state(), 0.0, t)
        extra = 0.0
        for f in np.linspace(before[0], after[0], steps + 1)[1:-1]:
            m = self.wheel(u, f, after[1])
            y, e = self.turns(m, y, t, over / steps)
            extra += e.sum() - abs(f * m.static_load * m.steady_creepage() * m.speed) * over / steps
            t += over / steps
        b = self.wheel(u, *after)
        turn = wheel_turn(b)
        y, first = self.turns(b, y, t, 10 * turn)
        y, _ = self.turns(b, y, t + 10 * turn, 30 * turn)
        return first, self.turns(b, y, t + 40 * turn, 10 * turn)[1], extra

    def test_a_torque_step_wears_little_and_less_when_spread(self):
        """Round wheel, +0.05 -> -0.05: the creepage settles to 1e-3 within 0.05 revolutions
        (measured 0.03); the step's extra frictional energy is under 2 % of a
        revolution's (measured -0.85 %); in 10 equal steps over 1 s a tenth of that within 25 %
        (measured 0.102: a step's excess is quadratic in its size). Over 5 um harmonics of orders
        6-12 the step's uneven wear is under that of 3 settled revolutions (measured 1.6)."""
        from railwear.geometry import roundness
        from railwear.units import UM

        from railwear.longterm.disk_wheel import dense_contact, long_term_integrator, wheel_turn

        first, settled, _ = self.switched(np.zeros(64), (0.05, 70.0), (-0.05, 70.0))
        step = first.sum() - settled.sum()
        pulling, braking = self.wheel(np.zeros(64), 0.05), self.wheel(np.zeros(64), -0.05)
        y, _ = self.turns(pulling, pulling.initial_state(), 0.0, 40 * wheel_turn(pulling))
        turn = wheel_turn(braking)
        t, creepage = dense_contact(braking, braking.params(), braking.surface(), y, 0.0, turn, long_term_integrator(),
                                    2001)[2:5:2]
        late = np.abs(creepage / braking.steady_creepage() - 1) > 1e-3
        assert t[late].max() < 0.05 * turn  # the creepage settles within 0.05 revolutions (measured 0.03)
        assert 0 < abs(step) < 0.02 * settled.sum() / 10
        first, settled, extra = self.switched(np.zeros(64), (0.05, 70.0), (-0.05, 70.0), steps=10, over=1.0)
        assert 0.075 < (first.sum() - settled.sum() + extra) / step < 0.125
        u = roundness.harmonics(64, HARMONICS["orders"], np.full(7, 5 * UM), np.deg2rad(HARMONICS["phases_deg"]))
        first, settled, _ = self.switched(u, (0.05, 70.0), (-0.05, 70.0))
        assert np.std(first - settled) < 3 * np.std(settled) / 10

    def test_a_speed_step_is_the_shock_left_out(self):
        """60 -> 70 km/h at once slides the wheel until it spins up: over 10 times the frictional
        energy of 10 settled revolutions (measured 33)."""
        from railwear.geometry import roundness
        from railwear.units import UM

        u = roundness.harmonics(64, HARMONICS["orders"], np.full(7, 5 * UM), np.deg2rad(HARMONICS["phases_deg"]))
        first, settled, _ = self.switched(u, (0.05, 60.0), (0.05, 70.0))
        assert first.sum() > 10 * settled.sum()
