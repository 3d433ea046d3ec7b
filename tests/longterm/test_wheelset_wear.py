"""Long-term wear of the wheelset on real profiles (S1002 on UIC60): deposit, feedback, convergence."""

from dataclasses import replace

import numpy as np
import pytest
from helpers import Killed, killed_after

from railwear.dynamics import TableWheelsetModel
from railwear.errors import ScenarioError
from railwear.geometry import contact_table, load_profile, worn_profile
from railwear.geometry.flange import flange_parameters
from railwear.longterm.direct import Direct
from railwear.longterm.stepwise import Stepwise
from railwear.longterm.wheelset_wear import Wheelset, WheelsetWear, band_width, sweep_deposit
from railwear.wear import EnergyLaw

SUSPENSION = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6)
SMALL = dict(lateral_edges=np.round(np.linspace(-0.050, 0.040, 91), 12), n_angle=16, transient=2.0,
             output_rate=1000.0)


@pytest.fixture(scope="module")
def profiles():
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    return wheel, rail, contact_table(wheel, rail)


def make(profiles, speed, **options):
    wheel, rail, table = profiles
    model = TableWheelsetModel(speed=speed, **SUSPENSION, table=table, friction_coefficient=0.3)
    return WheelsetWear(model, wheel, rail, EnergyLaw(), 1e6, **{**SMALL, **options})


def WheelsetStepwise(p, step_limit, seconds=2.0, samples=4, seed=0):
    return Stepwise(Wheelset(p, seconds=seconds, samples=samples), step_limit, seed=seed)


def WheelsetDirect(p, acceleration, update_seconds=0.5, seed=0):
    return Direct(Wheelset(p, update_seconds=update_seconds), acceleration, n_save=None, seed=seed)


def relative(ds, ref):
    a, b = ds.worn_depth.values[-1], ref.worn_depth.values[-1]
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def test_swept_deposit_conserves_volume_at_the_seam_and_the_edges(profiles):
    """Patches crossing the periodic seam and reaching past the lateral grid lose nothing."""
    surface = make(profiles, 30.0).new_surface()
    rng = np.random.default_rng(0)
    n = 200
    volume = rng.uniform(0, 1e-9, n)
    start = rng.uniform(2 * np.pi - 0.3, 2 * np.pi + 0.1, n)
    lateral = rng.uniform(-0.06, 0.05, n)
    added = sweep_deposit(surface, volume, start, start + rng.uniform(0, 0.2, n), lateral,
                          rng.uniform(2e-3, 6e-3, n), rng.uniform(3e-3, 1e-2, n))
    assert added == pytest.approx(volume.sum(), rel=1e-13)
    assert surface.removed_volume() == pytest.approx(volume.sum(), rel=1e-12)


def test_deposit_volume_is_the_law_integral(profiles):
    """The volume put on both wheels equals beta times the trapezoidal integral of the
    simulation's frictional power, to round-off."""
    p = make(profiles, 60.0)
    table = p.model.table
    ds, _ = p.run(table, 1.0, offset=2e-3)
    surfaces = (p.new_surface(), p.new_surface())
    added, law, _ = p.deposit(surfaces, ds, table, phase=6.2)
    power = ds.frictional_power.values
    expected = p.beta * float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(ds.time.values)[:, None]))
    assert law == pytest.approx(expected, rel=1e-12)
    assert added == pytest.approx(expected, rel=1e-12)
    assert sum(s.removed_volume() for s in surfaces) == pytest.approx(expected, rel=1e-12)


def test_uniform_wear_lowers_every_rolling_radius_by_the_depth(profiles):
    """A depth uniform over the tread moves no contact point on the tread: every rolling radius
    falls by it and the rolling-radius difference is unchanged (for shifts up to 3 mm; further
    out the roll angle, up to 0.011 rad, and the steep flanks move the contact by amounts of the
    order of the depth times the roll angle)."""
    p = make(profiles, 30.0)
    depth = 50e-6
    new, worn = (p.table(np.full(p.lateral.size, d)).sel(y=slice(-0.003, 0.003)) for d in (0.0, depth))
    np.testing.assert_allclose(worn.wheel_contact_y.values, new.wheel_contact_y.values, atol=1e-7)
    np.testing.assert_allclose(worn.rolling_radius.values, new.rolling_radius.values - depth, atol=1e-8)
    np.testing.assert_allclose(worn.rolling_radius_difference.values, new.rolling_radius_difference.values,
                               atol=1e-8)


def test_the_run_feeds_its_worn_profile_into_the_table(profiles):
    """After a run, the table the dynamics continue on is that of the profile worn by the fed
    (angle and wheel averaged) depth: its rolling radius at y = 0 is the nominal one plus the
    unworn profile minus that depth at the table's contact point, and the rolling-radius
    difference has changed."""
    p = make(profiles, 30.0)
    ds = WheelsetDirect(p, 2e4, update_seconds=0.5).run(until=0.3)
    fed = ds.worn_depth.values[-1].mean(0)
    assert fed.max() > 2e-6
    expected = contact_table(worn_profile(p.wheel, -np.interp(p.wheel.y, p.lateral, fed, left=0, right=0)),
                             p.rail, y=np.asarray(p.shifts))
    np.testing.assert_array_equal(ds.rolling_radius_difference.values[-1], expected.rolling_radius_difference.values)
    centre = expected.sel(y=0.0, side="right")
    s = float(centre.wheel_contact_y)
    worn_there = np.interp(s, p.lateral, fed)
    assert worn_there > 1e-6
    # the profile is a spline through the worn points; the depth is read linearly between cells
    assert float(centre.rolling_radius) == pytest.approx(0.46 + float(p.wheel(s)) - worn_there, abs=1e-9)
    change = np.abs(ds.rolling_radius_difference.values[-1] - ds.rolling_radius_difference.values[0])
    assert change.max() > 1e-7
    # the flange parameters are the new S1002's at the start and those of each wheel's worn profile after
    np.testing.assert_allclose(ds.flange_height.values[0], 0.028, atol=1e-4)
    worn = flange_parameters(p.profile(ds.worn_depth.values[-1, 1]))
    assert float(ds.flange_thickness[-1, 1]) == worn.thickness and float(ds.flange_height[-1, 1]) == worn.height
    assert ds.flange_height.values[-1, 1] > ds.flange_height.values[0, 1]  # the tread wears, the tip does not


def test_band_is_the_footprint_below_and_the_hunting_range_above(profiles):
    """Centred running: the lateral depth of a rolled elliptic Hertz pressure is proportional to
    1 - ((s - s_c)/b)², whose central 90 % is 2 x b wide with x³ - 3x + 1.8 = 0 (x = 0.729).
    Hunting: the band covers the contact positions seen, widened by at most the footprint."""
    x = min(r.real for r in np.roots([1, 0, -3, 1.8]) if 0 < r.real < 1 and abs(r.imag) < 1e-12)
    bands = {}
    for speed in (30.0, 60.0):
        p = make(profiles, speed, transient=4.0)
        rates, laws, (lo, hi, amplitude), _ = Wheelset(p, seconds=1.0, samples=2).statistics(
            p.model.table, np.random.default_rng(1))
        bands[speed] = band_width(rates.mean((0, 1, 2)), p.lateral), hi - lo, amplitude
    b = float(profiles[2].b.sel(y=0.0, side="right"))
    cell = SMALL["lateral_edges"][1] - SMALL["lateral_edges"][0]
    assert bands[30.0][1] < 1e-5 and bands[30.0][2] < 1e-5  # no hunting: one contact point
    assert bands[30.0][0] == pytest.approx(2 * x * b, abs=cell)
    assert bands[60.0][2] > 1e-3  # hunting
    assert bands[60.0][1] < bands[60.0][0] < bands[60.0][1] + 2 * b
    assert bands[60.0][0] > bands[30.0][0] + 5e-3


def test_direct_converges_as_the_factor_falls_and_stepwise_as_the_step_limit_falls(profiles):
    """Hunting at 60 m/s to 400 km: against the direct run at A = 1250 the difference of the worn
    lateral profile falls with the factor (first order: the profile lags one update of A V dt)
    and with the stepwise step limit (forward Euler in the long-term time)."""
    p = make(profiles, 60.0)
    ref = WheelsetDirect(p, 1250.0, update_seconds=0.25).run(until=0.4)
    direct = [relative(WheelsetDirect(p, a, update_seconds=0.25).run(until=0.4), ref) for a in (1e4, 5e3, 2.5e3)]
    stepwise = [relative(WheelsetStepwise(p, s, seconds=1.5, samples=2).run(until=0.4), ref)
                for s in (4e-6, 2e-6, 1e-6)]
    # measured: direct 0.086, 0.012, 0.006; stepwise 0.040, 0.021, 0.007
    for errors in (direct, stepwise):
        assert errors[0] > errors[1] > errors[2]
        assert errors[2] < 0.5 * errors[0] and errors[2] < 0.02


def test_volume_removed_equals_the_law_through_the_steps(profiles):
    """The extrapolated steps and the direct updates keep the surface's volume equal to the law's."""
    p = make(profiles, 60.0)
    for ds in (WheelsetStepwise(p, 4e-6, seconds=1.0, samples=2).run(until=0.2),
               WheelsetDirect(p, 2e4, update_seconds=0.25).run(until=0.2)):
        np.testing.assert_allclose(ds.removed_volume.values, ds.law_volume.values, rtol=1e-12)
        assert ds.removed_volume.values[-1] > 0
        assert float(ds.distance[-1]) == pytest.approx(0.2e3)  # km


@pytest.mark.parametrize("make_strategy, field", [
    (lambda p: WheelsetStepwise(p, 0.0), "step_limit"),
    (lambda p: WheelsetStepwise(p, -1e-6), "step_limit"),
    (lambda p: WheelsetDirect(p, 0.5), "acceleration factor"),
    (lambda p: WheelsetStepwise(p, 1e-6, samples=1), "samples"),
    (lambda p: WheelsetDirect(p, 10.0, update_seconds=0.0), "update_seconds"),
])
def test_bad_input_is_a_one_line_error_naming_the_field(profiles, make_strategy, field):
    with pytest.raises(ScenarioError, match=field) as err:
        make_strategy(make(profiles, 30.0))
    assert "\n" not in str(err.value)


def test_bad_run_arguments(profiles):
    p = make(profiles, 30.0)
    with pytest.raises(ScenarioError, match="until"):
        WheelsetDirect(p, 10.0).run(until=0.0)
    with pytest.raises(ScenarioError, match="depth_limit"):
        WheelsetStepwise(p, 1e-6).run(until=1.0, depth_limit=-1.0)
    with pytest.raises(ScenarioError, match="u0"):
        WheelsetDirect(p, 10.0).run(u0=np.zeros(3), until=0.1)


@pytest.mark.slow
def test_section_script_runs_and_the_hunting_band_is_wider():
    """docs/strategies_wheelset.py --quick prints the section with both speeds, the strategies and
    the statement on the other two strategies; the band on the new profiles is wider when hunting."""
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "docs" / "strategies_wheelset.py"
    text = subprocess.run([sys.executable, str(script), "--quick"], check=True, capture_output=True, text=True,
                          env={"MPLBACKEND": "agg", "PATH": ""}, timeout=600).stdout
    rows = [line.split("|") for line in text.splitlines() if line.startswith("| 30 m/s (") or line.startswith("| 60 m/s (")]
    assert [row[2].strip() for row in rows] == ["centred running", "hunting"]
    band_new = [float(row[6]) for row in rows]  # 90 % band on the new profiles, mm
    assert band_new[1] > band_new[0] + 5
    for label in ("| stepwise, 2 um |", "| direct, A = 10000 |", "| direct, A = 5000 | reference |"):
        assert label in text
    assert "Fourier and phenomenological" in text and "### Why" in text


RESUMED = [
    (lambda p: WheelsetStepwise(p, 2e-7, seconds=0.5, samples=2, seed=3), 2),
    (lambda p: WheelsetDirect(p, 2e3, update_seconds=0.1, seed=3), 2),
]


def _assert_same(resumed, whole):
    for name in whole.data_vars:
        np.testing.assert_array_equal(resumed[name].values, whole[name].values, err_msg=name)
    np.testing.assert_array_equal(resumed.distance.values, whole.distance.values)


@pytest.mark.parametrize("make_strategy, k", RESUMED)
def test_a_killed_run_resumes_bit_for_bit(profiles, make_strategy, k):
    """Killed after k steps (updates) and resumed from the last checkpoint: the same worn depth,
    surface, volumes, Monte Carlo error and cost as the uninterrupted run, to the bit; another
    problem's run refuses the checkpoint in one line."""
    p = make(profiles, 60.0)
    strategy = make_strategy(p)
    whole = strategy.run(until=0.06)
    assert whole.sizes["time"] > k + 2
    saved = []
    with pytest.raises(Killed):
        strategy.run(until=0.06, checkpoint=killed_after(k, saved))
    assert saved[-1].steps == k
    resumed = strategy.run(until=0.06, resume=saved[-1])
    _assert_same(resumed, whole)
    assert float(resumed.worn_depth.values[-1].max()) > 0
    for other in (replace(strategy, seed=4), make_strategy(make(profiles, 59.0))):
        with pytest.raises(ScenarioError, match="another wheelset problem") as err:
            other.run(until=0.06, resume=saved[-1])
        assert "\n" not in str(err.value)


@pytest.mark.parametrize("make_strategy, k", RESUMED)
def test_checkpoints_survive_an_npz_file(profiles, make_strategy, k, tmp_path):
    """Written as the result files write them (plain fields in an .npz), told apart from the disk
    wheel's checkpoints by their kind, read back and resumed to the same result."""
    from railwear.longterm.base import Checkpoint

    p = make(profiles, 60.0)
    strategy = make_strategy(p)
    saved = []
    whole = strategy.run(until=0.06, checkpoint=saved.append)
    np.savez(tmp_path / "cp.npz", **saved[k - 1].plain())
    with np.load(tmp_path / "cp.npz", allow_pickle=False) as data:
        back = Checkpoint.from_plain({n: data[n] for n in data.files})
    assert back.kind == strategy.name and isinstance(back.fingerprint, str)
    _assert_same(strategy.run(until=0.06, resume=back), whole)


def test_rebuilt_tables_keep_the_load_radius_and_constants_of_the_first(profiles):
    """A table rebuilt on a worn profile takes the axle load, nominal radius and elastic constants
    of the model's first table (they fell back to contact_table's defaults, 133.4 kN and 0.46 m)."""
    wheel, rail, _ = profiles
    first = contact_table(wheel, rail, axle_load=160e3, rolling_radius=0.42, youngs_modulus=2.0e11, poisson=0.3)
    p = replace(make(profiles, 30.0), model=replace(make(profiles, 30.0).model, table=first))
    again = p.table(np.zeros(len(p.lateral)))
    for name in ("axle_load", "nominal_rolling_radius", "youngs_modulus", "poisson", "gauge", "cant"):
        assert again.attrs[name] == first.attrs[name], name
    np.testing.assert_array_equal(again.normal_force.values, first.normal_force.values)
