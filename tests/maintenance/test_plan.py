"""``railwear plan``: deterministic for a seed, the growth band stated, the outputs written and read
back, and the command run the way a user runs it, in a fresh interpreter."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from railwear.errors import OptionError, ScenarioError
from railwear.maintenance import outputs
from railwear.maintenance import plan as planning
from railwear.maintenance.plan import plan, re_profiled
from railwear.results import read_netcdf
from railwear.scenario import load_scenario
from railwear.units import MM


METRO = load_scenario("metro", ["solver.points=128"])  # orders 1-64 hold its roughness (1-40); a build 4x cheaper


@pytest.fixture(scope="module")
def drawn():
    """Two policies, two wheels drawn from the metro's [service] besides wheel 0, at x0.5 and x2."""
    return plan(METRO, ["metro-condition", "metro-interval"], samples=2, seed=5, growth=(0.5, 2.0), horizon_km=450_000)


def test_a_plan_is_deterministic_for_a_seed_and_draws_other_wheels_for_another(drawn):
    again = plan(METRO, ["metro-condition", "metro-interval"], samples=2, seed=5, growth=(0.5, 2.0), horizon_km=450_000)
    xr.testing.assert_identical(drawn, again)
    other = plan(METRO, ["metro-condition"], samples=2, seed=6, growth=(2.0,), horizon_km=450_000)
    assert not np.array_equal(other.speed.values[1:], drawn.speed.values[1:])
    assert np.array_equal(other.speed.values[:1], drawn.speed.values[:1])  # wheel 0: the scenario's own 70 km/h
    assert np.array_equal(other.turning_distance.sel(wheel=0).values,
                          drawn.turning_distance.sel(policy=["metro-condition"], growth=[2.0], wheel=0).values)


def test_the_plan_states_its_growth_band_and_faster_growth_turns_sooner(drawn):
    assert "growth multipliers 0.5, 2" in drawn.attrs["growth_band"] and "no field growth rate" in drawn.attrs["growth_band"]
    first = drawn.turning_distance.sel(policy="metro-condition", turning=1)
    assert np.all(first.sel(growth=2.0).values < first.sel(growth=0.5).values)
    assert set(np.unique(drawn.trigger.sel(policy="metro-interval").values)) <= {"", "interval 200,000 km"}
    assert "distance_to_scrap_p50" in drawn and drawn.sizes["wheel"] == 3
    # not scrapped within 450 000 km: no distance to scrap, and the file says why
    assert np.all(np.isinf(drawn.distance_to_scrap.values)) and "undefined_because" in drawn.distance_to_scrap.attrs


def test_with_the_rates_scaled_to_zero_the_polygon_stays_as_the_lathe_left_it():
    ds = plan(METRO, ["metro-interval"], growth=(0.0,), horizon_km=700_000)
    k = int(ds.turnings.values[0, 0, 0])
    assert k == 3
    base = re_profiled(METRO)
    ptp = ds.peak_to_peak_at_turning.sel(wheel=0).values[0, 0, :k]
    assert np.allclose(ptp, np.ptp(base), rtol=1e-12, atol=0)
    assert np.allclose(ds.turning_distance.sel(wheel=0).values[0, 0, :k], [200_000, 400_000, 600_000], rtol=1e-12)
    after, cut = ds.diameter_after.values[0, 0, 0, :k], ds.cut_depth.values[0, 0, 0, :k]
    assert np.array_equal(after, ds.diameter_before.values[0, 0, 0, :k] - 2 * cut)


def test_the_order_selected_after_each_turning_follows_the_diameter(drawn):
    d0 = drawn.attrs["new_diameter_m"]
    n0 = drawn.selected_order_new.values
    after = drawn.diameter_after.values
    chosen = drawn.selected_order.values
    done = np.isfinite(after)
    assert done.sum() > 10
    expected = n0[..., None] * after / d0
    assert np.all(np.abs(chosen[done] - expected[done]) <= 1)


def test_the_outputs_are_written_and_read_back(drawn, tmp_path):
    paths = outputs.write(drawn, tmp_path)
    assert [p.name for p in paths] == ["plan.nc", "plan.txt", "plan.csv", "turnings.csv", "plan.png", "plan.html"]
    back = read_netcdf(tmp_path / "plan.nc")
    assert np.array_equal(back.turning_distance.values, drawn.turning_distance.values, equal_nan=True)
    assert outputs.report(back) == outputs.report(drawn)
    table = (tmp_path / "plan.csv").read_text().splitlines()
    assert table[0].startswith("policy,growth,turnings,distance_to_scrap_km,km_per_mm_diameter,turnings_per_million_km")
    assert len(table) == 1 + 4
    rows = (tmp_path / "turnings.csv").read_text().splitlines()
    assert len(rows) == 1 + int(drawn.turnings.sum())
    first = rows[1].split(",")
    assert first[0] == "metro-condition" and float(first[6]) == pytest.approx(0.1, rel=1e-9)  # p-p at the trigger, mm


def test_bad_options_are_refused_naming_them():
    with pytest.raises(OptionError, match="growth: 1 to 20 multipliers in \\[0, 100\\], got 0.5, -1"):
        plan(METRO, ["metro-interval"], growth=(0.5, -1.0))
    with pytest.raises(OptionError, match="samples"):
        plan(METRO, ["metro-interval"], samples=-1)
    with pytest.raises(ScenarioError, match="metro-condition: trigger.peak_to_peak_mm: body.kind 'wheelset' has no model "
                                            "of the polygon's growth"):
        plan("wheelset-wear", ["metro-condition"])


def test_railwear_plan_runs_in_a_fresh_interpreter(tmp_path):
    done = subprocess.run([sys.executable, "-m", "railwear", "plan", "metro", "--policy", "metro-condition", "--policy",
                           "metro-noise", "--growth", "0.5,1", "--samples", "2", "--seed", "3", "--horizon-km", "400000",
                           "--set", "solver.points=128",
                           "-o", str(tmp_path / "out")], capture_output=True, text=True, timeout=600, stdin=subprocess.DEVNULL)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "Traceback" not in done.stderr
    assert "comparison (distance to scrap, km: wheel 0; median and 5-95 % band over 2 drawn wheels)" in done.stdout
    ds = read_netcdf(tmp_path / "out" / "plan.nc")
    assert list(ds.policy.values) == ["metro-condition", "metro-noise"] and list(ds.growth.values) == [0.5, 1.0]
    assert ds.sizes["wheel"] == 3 and int(ds.turnings.sel(policy="metro-condition", growth=1.0, wheel=0)) == 2
    assert float(ds.peak_to_peak_at_turning.sel(policy="metro-condition", growth=1.0, wheel=0, turning=1)) == pytest.approx(
        0.1 * MM, rel=1e-9)
    assert (tmp_path / "out" / "plan.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len((tmp_path / "out" / "plan.csv").read_text().splitlines()) == 5
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "b"\nsource = "example"\n[trigger]\npeak_to_peak_mm = 0.1\n[cut]\nstep_mm = 0\n'
                   '[wheel]\nlast_turning_diameter_mm = 770.0\n')
    refused = subprocess.run([sys.executable, "-m", "railwear", "plan", "--policy", str(bad), "-o", str(tmp_path / "bad")],
                             capture_output=True, text=True, timeout=600, stdin=subprocess.DEVNULL)
    assert refused.returncode == 2
    assert refused.stderr.strip().splitlines()[-1] == (
        "railwear: error: bad.toml: field 'cut.step_mm': Input should be greater than or equal to 0.01")


def test_a_killed_plan_resumes_from_its_file_to_the_same_lives(drawn, tmp_path):
    """Killed after its third life, the plan's last checkpoint written to and read from a file,
    resumed: identical to the uninterrupted plan; another plan's checkpoint is refused."""
    from helpers import Killed, killed_after

    saved = []
    with pytest.raises(Killed):
        plan(METRO, ["metro-condition", "metro-interval"], samples=2, seed=5, growth=(0.5, 2.0), horizon_km=450_000,
             checkpoint=killed_after(3, saved))
    assert len(saved[-1].lives) == 3
    planning.write_checkpoint(saved[-1], tmp_path / planning.CHECKPOINT)
    stopped = planning.read_checkpoint(tmp_path / planning.CHECKPOINT)
    resumed = plan(METRO, ["metro-condition", "metro-interval"], samples=2, seed=5, growth=(0.5, 2.0),
                   horizon_km=450_000, resume=stopped)
    xr.testing.assert_identical(drawn, resumed)
    with pytest.raises(ScenarioError, match="resume: the plan checkpoint was written for another plan"):
        plan(METRO, ["metro-condition", "metro-interval"], samples=2, seed=6, growth=(0.5, 2.0), horizon_km=450_000,
             resume=stopped)


def test_a_peak_force_trigger_turns_the_wheel_where_the_detector_would_read_it(tmp_path):
    """A planner's 100 kN threshold on the metro wheel (static 68.8 kN) at 70 km/h: the wheel is
    turned where the time-domain peak force of its grown shape first passes 100 kN (the detector
    search's bracket, 2 % of the peak to peak), later than the 0.1 mm peak-to-peak trigger."""
    from dataclasses import replace

    from railwear.maintenance.impact import DynamicLoad, peak_forces
    from railwear.maintenance.plan import WheelRates

    policy = tmp_path / "force.toml"
    policy.write_text('name = "force-100"\nsource = "example"\n[trigger]\npeak_force_kN = 100.0\n'
                      '[wheel]\nlast_turning_diameter_mm = 770.0\n')
    ds = plan(METRO, [str(policy), "metro-condition"], growth=(1.0,), horizon_km=300_000)
    first = ds.isel(growth=0, wheel=0, turning=0)
    assert list(first.trigger.values) == ["peak wheel-rail force 100 kN", "0.1 mm peak to peak"]
    at, pp_trigger = first.turning_distance.values
    assert pp_trigger < at < 300_000
    table = WheelRates(METRO, re_profiled(METRO).size // 2).at(0.84)
    grown = table.evolve(re_profiled(METRO), np.array([at * 1e3 / table.speed]))[0]
    case = METRO.body.case(METRO)
    load = DynamicLoad(case, grown - grown.mean(), speeds=(table.speed,), wheel="grown")
    assert peak_forces(load, (table.speed,), load.ring())[0] > 100e3
    smaller = replace(load, deviation=(grown - grown.mean()) * 0.97)  # 3 % less than at the turning
    assert peak_forces(smaller, (table.speed,), smaller.ring())[0] < 100e3 * 1.02


def test_a_peak_force_trigger_needs_the_time_domain_track(tmp_path):
    policy = tmp_path / "force.toml"
    policy.write_text('name = "force"\nsource = "example"\n[trigger]\ninterval_km = 100000.0\npeak_force_speeds_kmh = [70.0]\n'
                      '[wheel]\nlast_turning_diameter_mm = 770.0\n')
    with pytest.raises(ScenarioError, match="peak_force_speeds_kmh"):
        plan(METRO, [str(policy)])
    policy.write_text('name = "force"\nsource = "example"\n[trigger]\npeak_force_kN = 150.0\n'
                      '[wheel]\nlast_turning_diameter_mm = 770.0\n')
    with pytest.raises(ScenarioError, match="body.kind"):
        plan(load_scenario("linear-dynamics"), [str(policy)], horizon_km=10_000)
