"""Flange parameters as plan triggers and a turning that restores the design profile
(docs/maintenance.md, "The flange triggers"): the geometric cut against analytic cases, the
distance at which a linear wear rate reaches a flange limit, the plan on the wheelset body
deterministic and resumed bit for bit, refusals, and the command in a fresh interpreter."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from railwear.errors import OptionError, ScenarioError
from railwear.geometry import Profile, load_profile, worn_profile
from railwear.geometry.flange import flange_parameters, restoring_depth
from railwear.maintenance import plan as planning
from railwear.maintenance.lateral import FlangeLimit, ProfileWear
from railwear.maintenance.plan import plan
from railwear.maintenance.policy import parse_policy
from railwear.maintenance.turning import BELOW, CutRule, Policy, RateTable, Residual, Triggers, Turning, WheelState
from railwear.results import read_netcdf
from railwear.scenario import load_scenario
from railwear.units import KM, MM

SLOPE = 2.0  # |dz/dy| of the synthetic straight flank
FINE = np.linspace(-0.075, 0.040, 115_001)  # 1 µm steps for the synthetic profile's integral
POINTS = np.linspace(-0.075, 0.040, 2301)  # the profile's points, 0.05 mm apart
# A wheelset-wear run small enough for a test: 20 km, one step, 0.2 s per start, 0.5 mm table shifts
SMALL = ["solver.t_end=0.02", "body.seconds_per_sample_s=0.2", "body.transient_s=0.2", "strategy.step_limit_um=1000",
         "body.shift_step_mm=0.5"]


def _plateau(y, a, b, ramp=0.002):
    """1 on [a, b], 0 beyond ``ramp`` outside it, a C² quintic smoothstep between."""
    t = np.clip(np.minimum(y - (a - ramp), (b + ramp) - y) / ramp, 0.0, 1.0)
    return t**3 * (10 - 15 * t + 6 * t**2)


def _synthetic():
    """A wheel profile z(y) (m) with a straight front flank of slope -SLOPE from y = -34 to -22 mm
    (28 mm of flange over a flat tread, the tape circle at y = 0), a flat tip and a back flank,
    smooth (C²) everywhere: the flank carries Sd's measuring height (10 mm)."""
    slope = -SLOPE * _plateau(FINE, -0.034, -0.022) + SLOPE * _plateau(FINE, -0.060, -0.044)
    z = np.concatenate([[0.0], np.cumsum(0.5 * (slope[1:] + slope[:-1]) * np.diff(FINE))])
    z -= z[-1]  # flat tread at z = 0
    return lambda y: np.interp(y, FINE, z)


Z0 = _synthetic()
DESIGN = Profile(POINTS, Z0(POINTS), kind="wheel", name="synthetic")


def test_the_geometric_cut_of_the_design_profile_against_itself_is_zero_and_against_uniform_wear_the_wear():
    s1002 = load_profile("S1002")
    assert restoring_depth(s1002, s1002) == 0.0
    for w in (1e-5, 0.7e-3, 3e-3):
        assert abs(restoring_depth(s1002, worn_profile(s1002, np.full(s1002.y.size, -w))) - w) < 1e-9


def test_a_flange_thinned_by_t_costs_the_flank_slope_times_t_of_radius():
    """The flank moved towards the flange back by t: ``d = max_y (z_0(y) - z_0(y + t)) = |dz/dy| t``
    where the flank is straight over more than t, and Sd falls by t."""
    new = flange_parameters(DESIGN)
    for t in (0.2e-3, 1e-3, 4e-3):
        thin = Profile(POINTS, Z0(POINTS + t), kind="wheel", name="thinned")
        assert restoring_depth(DESIGN, thin) == pytest.approx(SLOPE * t, abs=1e-8)
        assert flange_parameters(thin).thickness == pytest.approx(new.thickness - t, abs=1e-8)
        assert flange_parameters(thin).height == pytest.approx(new.height, abs=1e-8)


def _life(wear, policy, diameter=0.92):
    """The life of a round wheel of ``diameter`` (m) under ``policy`` on the lateral ``wear``: no
    polygon growth, the mean radius worn at the tape circle, 30 m/s."""
    speed = 30.0

    def technique(d):
        return RateTable(np.zeros(64, complex), -wear.tape_rate * speed, speed, d / 2)

    return policy.life(WheelState(np.zeros(128), diameter), technique, horizon=1e10, lateral=wear)


def test_a_flank_worn_at_a_linear_rate_is_turned_where_sd_reaches_its_limit_and_the_thin_flange_costs_diameter():
    """A depth rate c uniform over the straight flank (none on the tread and the tip): Sd falls as
    ``Sd_0 - c s / |dz/dy|``, so a limit 1 mm below Sd_0 is reached at ``s* = 1 mm |dz/dy| / c``;
    each turning cuts ``c s* = 2 mm`` of radius, and the wheel of 920 mm is turned five times before
    the sixth cut would take it below 900 mm."""
    c = 2e-11  # m of depth per m run: 2 mm per 10^5 km
    wear = ProfileWear(DESIGN, POINTS, c * _plateau(POINTS, -0.031, -0.025, ramp=0.0015))
    sd0 = flange_parameters(DESIGN).thickness
    limit = FlangeLimit("flange_thickness_min_mm", sd0 - 1 * MM)
    policy = Policy("flange", Triggers(flange=(limit,)), Turning(CutRule(0.0, 0.1 * MM, 0.5 * MM), Residual("round")),
                    0.900)
    life = _life(wear, policy)
    s_star = 1 * MM * SLOPE / c
    assert [t.distance for t in life.turnings] == pytest.approx(s_star * np.arange(1, 6), rel=1e-6)
    assert all(t.trigger == limit.name for t in life.turnings)
    assert [t.cut for t in life.turnings] == pytest.approx([2 * MM] * 5, abs=1e-12)
    assert [t.profile_cut for t in life.turnings] == pytest.approx([2 * MM] * 5, rel=1e-6)
    assert [t.flange[1] for t in life.turnings] == pytest.approx([sd0 - 1 * MM] * 5, abs=1e-9)
    assert [t.after for t in life.turnings] == pytest.approx(0.92 - 4 * MM * np.arange(1, 6), abs=1e-12)
    assert life.reason == BELOW and life.end.distance == pytest.approx(6 * s_star, rel=1e-6)
    assert life.asked == limit.name  # the sixth turning was asked for by the flange, and refused


def test_a_tread_worn_at_a_linear_rate_is_turned_where_sh_reaches_its_limit_at_the_least_cut():
    """S1002 with its tread worn at c (none on the flange): Sh grows as ``Sh_0 + c s``, so a limit
    Sh_0 + 1 mm is reached at ``1 mm / c``; the design profile lowered to the worn tape circle lies
    inside the worn one (only the flange tip stands above it), so the cut is the least cut."""
    c = 1e-11
    s1002 = load_profile("S1002")
    wear = ProfileWear(s1002, POINTS, c * _plateau(POINTS, -0.020, 0.040, ramp=0.005))
    sh0 = flange_parameters(s1002).height
    limit = FlangeLimit("flange_height_max_mm", sh0 + 1 * MM)
    policy = Policy("high", Triggers(flange=(limit,)), Turning(CutRule(0.0, 0.1 * MM, 0.5 * MM), Residual("round")),
                    0.90)
    life = _life(wear, policy)
    first = life.turnings[0]
    assert first.distance == pytest.approx(1 * MM / c, rel=1e-6) and first.trigger == limit.name
    assert first.flange[0] == pytest.approx(sh0 + 1 * MM, abs=1e-9)
    assert abs(first.profile_cut) < 1e-9 and first.cut == 0.5 * MM
    # the diameter before is the new one less twice the tape circle's wear
    assert first.before == pytest.approx(0.92 - 2 * c * first.distance, abs=1e-12)


def test_flange_triggers_are_read_with_bounds_and_refused_where_there_is_no_lateral_profile():
    text = ('name = "f"\nsource = "an example"\n[trigger]\nflange_thickness_min_mm = 22.0\n'
            '[wheel]\nlast_turning_diameter_mm = 770.0\n')
    policy = parse_policy(text)
    assert policy.build().triggers.flange == (FlangeLimit("flange_thickness_min_mm", 22 * MM),)
    with pytest.raises(ScenarioError, match="field 'trigger.flange_gradient_min_mm'"):
        parse_policy(text.replace("flange_thickness_min_mm = 22.0", "flange_gradient_min_mm = -1.0"))
    with pytest.raises(ScenarioError, match="field 'trigger.flange_height_max_mm'"):
        parse_policy(text.replace("flange_thickness_min_mm = 22.0", "flange_height_max_mm = 11.0"))
    with pytest.raises(ScenarioError) as refused:
        plan(load_scenario("metro", ["solver.points=128"]), [policy])
    assert str(refused.value) == ("f: trigger.flange_thickness_min_mm: body.kind 'vehicle_track' does not simulate the "
                                  "lateral profile; flange triggers need body.kind 'wheelset'")
    from railwear.maintenance.fleet import fleet

    with pytest.raises(ScenarioError, match="^f: trigger.flange_thickness_min_mm: body.kind 'vehicle_track' does not"):
        fleet(load_scenario("metro", ["solver.points=128"]), "example-fleet", policy)  # never ignored silently
    with pytest.raises(OptionError, match="samples: a plan on body.kind 'wheelset' runs one wheel"):
        plan(load_scenario("wheelset-wear", SMALL), ["wheelset-flange"], samples=2)


@pytest.fixture(scope="module")
def flange_plan():
    """The built-in flange policy on a short wheelset-wear run, at x1 and x20 of its wear rate."""
    return plan(load_scenario("wheelset-wear", SMALL), ["wheelset-flange", "metro-interval"], growth=(1.0, 20.0))


def test_the_flange_plan_is_deterministic_and_reports_each_turning(flange_plan):
    again = plan(load_scenario("wheelset-wear", SMALL), ["wheelset-flange", "metro-interval"], growth=(1.0, 20.0))
    xr.testing.assert_identical(flange_plan, again)
    ds = flange_plan.sel(policy="wheelset-flange", growth=1.0, wheel=0)
    turned = ds.turning_distance.notnull()
    assert turned.sum() >= 1
    assert np.all(ds.flange_thickness_at_turning.where(turned).notnull() == turned)
    assert float(ds.flange_thickness_at_turning.isel(turning=0)) > 0.022  # the tread's wear thickens Sd's place
    assert np.all(ds.cut_depth.values[turned.values] >= ds.profile_cut.values[turned.values])
    assert float(flange_plan.flange_thickness_min.sel(policy="wheelset-flange")) == 22 * MM
    assert np.isnan(float(flange_plan.flange_thickness_min.sel(policy="metro-interval")))
    assert "lateral profile's wear rate" in flange_plan.attrs["growth_band"]
    assert flange_plan.profile_wear_rate.attrs["units"] == "m km-1" and float(flange_plan.profile_wear_rate.max()) > 0
    # the history starts from the new S1002 (Sd 32.5 mm) and meets the turning's values before each cut
    assert float(ds.history_flange_thickness[0]) == pytest.approx(32.5 * MM, abs=0.1 * MM)
    at = ds.history_distance.values == float(ds.turning_distance[0])
    assert float(ds.flange_thickness_at_turning[0]) in ds.history_flange_thickness.values[at]
    assert np.all(ds.selected_order.values == 0) and int(ds.selected_order_new) == 0  # no polygon model


def test_a_killed_flange_plan_resumes_from_its_file_to_the_same_lives(flange_plan, tmp_path):
    from helpers import Killed, killed_after

    saved = []
    with pytest.raises(Killed):
        plan(load_scenario("wheelset-wear", SMALL), ["wheelset-flange", "metro-interval"], growth=(1.0, 20.0),
             checkpoint=killed_after(2, saved))
    planning.write_checkpoint(saved[-1], tmp_path / planning.CHECKPOINT)
    stopped = planning.read_checkpoint(tmp_path / planning.CHECKPOINT)
    assert stopped.lives[0, 0, 0].turnings == saved[-1].lives[0, 0, 0].turnings  # flange fields too, exactly
    resumed = plan(load_scenario("wheelset-wear", SMALL), ["wheelset-flange", "metro-interval"], growth=(1.0, 20.0),
                   resume=stopped)
    xr.testing.assert_identical(flange_plan, resumed)


def test_railwear_plan_with_a_flange_policy_runs_in_a_fresh_interpreter(tmp_path):
    sets = [a for s in SMALL for a in ("--set", s)]
    done = subprocess.run([sys.executable, "-m", "railwear", "plan", "wheelset-wear", "--policy", "wheelset-flange",
                           "--growth", "1,20", *sets, "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=600, stdin=subprocess.DEVNULL)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "Traceback" not in done.stderr
    ds = read_netcdf(tmp_path / "out" / "plan.nc")
    assert float(ds.flange_thickness_min.squeeze()) == pytest.approx(22 * MM)
    assert "flange_thickness_at_turning" in ds and "profile_wear_rate" in ds
    assert "Sh, Sd, qR before (mm)" in (tmp_path / "out" / "plan.txt").read_text()
    fast = ds.sel(policy="wheelset-flange", growth=20.0, wheel=0)  # the hollow tread asks a cut the wheel lacks
    assert str(fast.end_reason.values) == BELOW and str(fast.end_trigger.values) != ""
    assert str(ds.end_trigger.sel(policy="wheelset-flange", growth=1.0, wheel=0).values) == ""  # worn to D_s
    assert "flange_thickness_mm" in (tmp_path / "out" / "turnings.csv").read_text().splitlines()[0]
    flange = tmp_path / "flange.toml"
    flange.write_text('name = "f"\nsource = "an example"\n[trigger]\nflange_thickness_min_mm = 22.0\n'
                      '[wheel]\nlast_turning_diameter_mm = 770.0\n')
    refused = subprocess.run([sys.executable, "-m", "railwear", "plan", "metro", "--policy", str(flange),
                              "-o", str(tmp_path / "bad")], capture_output=True, text=True, timeout=600,
                             stdin=subprocess.DEVNULL)
    assert refused.returncode == 2 and "Traceback" not in refused.stderr
    assert refused.stderr.strip().splitlines()[-1] == (
        "railwear: error: f: trigger.flange_thickness_min_mm: body.kind 'vehicle_track' does not simulate the lateral "
        "profile; flange triggers need body.kind 'wheelset'")
