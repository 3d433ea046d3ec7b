"""``railwear fleet``: a synthetic fleet of known exponential growth gives back its crossing
distances within the sampling error; the band over growth multipliers, the plan's own trigger
search, broken files named with file and line, integers stored as integers, Dask."""

from math import gcd

import numpy as np
import pytest
import xarray as xr

from railwear.errors import MeasuredFileError
from railwear.geometry.roundness import resample_measured
from railwear.maintenance import fleet as fleets
from railwear.maintenance.fleet import evolve_batch, fleet, interpolated
from railwear.maintenance.fleet_input import write_synthetic
from railwear.maintenance.plan import WheelRates, re_profiled
from railwear.maintenance.policy import load_policy
from railwear.maintenance.turning import RateTable, WheelState
from railwear.measured import read_measured
from railwear.results import read_netcdf
from railwear.scenario import load_scenario
from railwear.units import KM, MM, UM

POINTS = 128
SCENARIO = load_scenario("metro", [f"solver.points={POINTS}"])
SPEED = 70 / 3.6  # m/s: the metro's
SIGMA0, SLOPE, DRIFT = 4e-7, 1.5, 2e-7  # 1/s at 810 mm, its relative change per m of diameter, rad/s per order
WEAR = -2.3e-10  # m/s of radius, as the metro's mean rate
PTP_MM, LEVEL_DB = 0.1, 30.0
FILE_POINTS = 120  # angles of a synthetic measured line (3 degrees)

POLICY = f"""name = "known"
source = "a test policy"
[trigger]
peak_to_peak_mm = {PTP_MM}
order_level_db = {LEVEL_DB}
[wheel]
last_turning_diameter_mm = 770.0
"""


def sigma(diameter):
    """The known growth rate (1/s), every order alike, linear in the diameter (so interpolating
    between rate nodes is exact)."""
    return SIGMA0 * (1 + SLOPE * (diameter - 0.81))


def known_rates(diameter):
    """A wheel of known exponential growth: ``λ_n = σ(D) - i n c`` (each order grows at σ and
    turns round the wheel at c: the polygon keeps its shape), and the metro's wear rate."""
    n = np.arange(1, POINTS // 2 + 1)
    return RateTable(sigma(diameter) - 1j * DRIFT * n, WEAR, SPEED, diameter / 2)


@pytest.fixture(scope="module")
def policy_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("policy") / "known.toml"
    path.write_text(POLICY)
    return path


@pytest.fixture(scope="module")
def thousand(tmp_path_factory, policy_file):
    """1000 synthetic wheels, one harmonic each (orders 3-12, 5-30 um), no roughness."""
    folder = tmp_path_factory.mktemp("fleet")
    manifest, truth = write_synthetic(folder, 1000, np.random.default_rng(24), orders=(3, 12), roughness_um=0.0,
                                      points=FILE_POINTS)
    ds = fleet(SCENARIO, manifest, policy_file, growth=(0.5, 1.0, 2.0), rates=known_rates)
    return ds, truth


def test_a_thousand_wheels_of_known_growth_give_back_their_crossings_within_the_sampling_error(thousand):
    """The peak to peak of ``A cos(n x + φ)`` reaches L after ``V / σ ln(L / 2A)`` and its level
    L_dB after ``V / σ ln(√2 1 µm 10^(L_dB / 20) / A)``. What the fleet sees differs by the
    sampling: a spline through the file's M points is off by at most ``5/384 (2π n / M)^4 A``
    (a periodic cubic spline's error bound on a harmonic), and the peak to peak on the N grid
    points may miss the crest by up to ``π gcd(n, N) / N`` in phase, a factor ``cos`` of it. A
    relative error ε of the amplitude moves the crossing by ``V / σ ε``."""
    ds, truth = thousand
    assert ds.sizes["wheel"] == 1000 and ds.sizes["failure"] == 0
    n, amplitude, _, diameter = (np.array(x) for x in zip(*truth))
    assert np.array_equal(ds.dominant_order.values, n)
    efold = SPEED / sigma(diameter) / KM  # km per e-fold
    ptp_known = efold * np.log(PTP_MM * MM / (2 * amplitude))
    level_known = efold * np.log(np.sqrt(2) * UM * 10 ** (LEVEL_DB / 20) / amplitude)
    spline = 5 / 384 * (2 * np.pi * n / FILE_POINTS) ** 4
    written = 2e-5  # the file's angles to 1e-4 degrees: a shift of n x 1.7e-6 rad of the harmonic
    grid = -np.log(np.cos(np.pi * np.array([gcd(int(k), POINTS) for k in n]) / POINTS))
    bisection = 1e-6  # km: 48 halvings of a scan step
    g1 = ds.distance_to_trigger.sel(growth=1.0)
    ptp_error = g1.sel(trigger=f"{PTP_MM:g} mm peak to peak").values - ptp_known
    level_error = g1.sel(trigger=f"{LEVEL_DB:g} dB re 1 um in every order").values - level_known
    assert np.all(np.abs(ptp_error) <= efold * (2 * spline + written + grid) + bisection)
    assert np.all(np.abs(level_error) <= efold * (2 * spline + written) + bisection)
    # the grid's sampling makes the peak to peak late, never early, beyond the spline's share
    assert np.all(ptp_error >= -efold * (2 * spline + written) - bisection)
    print(f"\nptp crossing error: median {np.median(np.abs(ptp_error)):.3g} km, largest {np.max(np.abs(ptp_error)):.3g} km "
          f"({np.max(np.abs(ptp_error) / ptp_known):.2e} relative); level crossing error: largest "
          f"{np.max(np.abs(level_error)):.3g} km ({np.max(np.abs(level_error) / level_known):.2e} relative)")


def test_the_band_is_the_distance_at_growth_1_over_the_multiplier_and_wear_has_its_closed_form(thousand):
    ds, truth = thousand
    d = ds.distance_to_trigger
    for g in (0.5, 2.0):
        assert np.allclose(d.sel(growth=g).values, d.sel(growth=1.0).values / g, rtol=1e-12)
    assert np.array_equal(ds.distance_to_action_early.values, ds.distance_to_action.sel(growth=2.0).values)
    assert np.array_equal(ds.distance_to_action_late.values, ds.distance_to_action.sel(growth=0.5).values)
    # the first trigger acts: here the level (30 dB, A = 44.7 um) before the peak to peak (A = 50 um)
    assert set(ds.action_reason.values) == {f"{LEVEL_DB:g} dB re 1 um in every order"}
    assert np.array_equal(ds.distance_to_action.sel(growth=1.0).values,
                          d.sel(growth=1.0, trigger=f"{LEVEL_DB:g} dB re 1 um in every order").values)
    worn = (ds.mean_diameter.values - 0.77) / (2 * -WEAR / SPEED) / KM
    expected = np.where(worn <= ds.attrs["horizon_km"], worn, np.inf)
    assert np.allclose(ds.distance_to_last_turning_diameter.values, expected, rtol=1e-12)
    days = np.floor(ds.distance_to_action.sel(growth=1.0).values / ds.attrs["daily_km"]).astype(int)
    assert np.array_equal(ds.days_to_action.values, days)


def test_the_fleet_finds_the_trigger_where_the_plan_machinery_turns(tmp_path):
    """On the metro's own rates at 128 points, the distance to the 0.1 mm trigger and the cut are
    those of the plan's segment (:meth:`Policy.advance`) from the same wheel, at growth 1 and 2."""
    sc = load_scenario("metro", ["solver.points=128"])
    manifest, _ = write_synthetic(tmp_path, 4, np.random.default_rng(3), diameter_range_mm=(801, 819), orders=(7, 9))
    wheels = WheelRates(sc, 64)  # the technique at a diameter, as the fleet builds it (once a node)
    ds = fleet(sc, manifest, "metro-condition", diameter_step_mm=10.0, rates=wheels.at)
    policy = load_policy("metro-condition").build(re_profiled(sc))
    nodes = ds.node_diameter.values
    assert nodes.size >= 2 and np.allclose(np.diff(nodes), 0.01)  # the wheels lie between nodes
    tables = [wheels.at(float(d)) for d in nodes]
    for w in range(4):
        d = float(ds.diameter[w])
        table = interpolated(tables, nodes, d)
        path = tmp_path / str(ds.file.values[w])
        u0 = resample_measured(*read_measured(path, field=str(path)), 128)
        for g in (2.0, 1.0):
            segment = policy.advance(WheelState(u0, d, since=float(ds.since_last_turning[w]) * KM), table.scaled(g),
                                     1e9, 500 * KM)
            assert segment.reason == "0.1 mm peak to peak"
            fleet_km = float(ds.distance_to_trigger.sel(growth=g, trigger="0.1 mm peak to peak")[w])
            assert fleet_km == pytest.approx(segment.state.distance / KM, rel=1e-9)
        assert float(ds.cut_depth[w]) == policy.turning.cut.depth(segment.state.u)  # at growth 1


def test_the_batched_evolution_is_the_techniques():
    rng = np.random.default_rng(1)
    tables = [known_rates(d) for d in (0.78, 0.8, 0.84)]
    u0 = rng.normal(size=(3, POINTS)) * 1e-5
    s = np.array([[0.0, 1e6, 5e7], [2e5, 3e5, 4e5], [1e7, 2e7, 3e7]])
    rates = np.array([t.rates(np.arange(1, POINTS // 2 + 1)) / t.speed for t in tables])
    batch = evolve_batch(np.fft.rfft(u0, axis=-1), rates, np.array([t.mean_rate / t.speed for t in tables]), POINTS, s)
    for k, t in enumerate(tables):
        assert np.allclose(batch[k], t.evolve(u0[k], s[k] / t.speed), rtol=0, atol=1e-15)


def _tiny(folder, rows, files):
    (folder / "wheels").mkdir(parents=True, exist_ok=True)
    head = "wheel_id,car,axle,side,diameter_mm,mileage_km,date,last_turning_km,lateral_mm,file"
    (folder / "fleet.csv").write_text("\n".join([head] + rows) + "\n")
    for name, text in files.items():
        (folder / "wheels" / name).write_text(text)
    return folder / "fleet.csv"


def _line(amplitude_um, order=8, points=90, bad_row=None):
    x = np.arange(points) * 360 / points
    rows = [f"{a:.3f},{amplitude_um * np.cos(order * np.radians(a)):.5f}" for a in x]
    if bad_row is not None:
        rows[bad_row] = rows[bad_row].split(",")[0] + ",12.x"
    return "angle_deg,deviation_um\n" + "\n".join(rows) + "\n"


def test_broken_files_and_rows_are_refused_with_file_and_line_and_the_rest_runs(tmp_path, policy_file):
    manifest = _tiny(tmp_path, [
        "A1,1,1,L,820,100000,2024-05-14,50000,,wheels/a1.csv",
        "A2,1,1,R,820,100000,2024-05-14,50000,,wheels/a2.csv",     # line 3: its file has text in a number
        "A3,1,2,L,,100000,2024-05-14,50000,,wheels/a1.csv",        # line 4: no diameter
        "A4,1,2,X,820,100000,2024-05-14,50000,,wheels/a1.csv",     # line 5: no such side
        "A5,1,1,L,820,100000,2024-05-14,50000,,wheels/a1.csv",     # line 6: car 1 axle 1 L is A1
        "A6,1,3,L,820,100000,14.5.2024,50000,,wheels/a1.csv",      # line 7: not an ISO date
        "A7,1,3,R,820,100000,2024-05-14,50000,,wheels/none.csv",   # line 8: no file
        "A8,1,4,L,900,100000,2024-05-14,50000,,wheels/a1.csv",     # line 9: larger than the new wheel
        "B1,2,1,L,815,90000,2024-05-15,10000,20,wheels/b1a.csv",   # two lines of one wheel
        "B1,2,1,L,815,90000,2024-05-15,10000,40,wheels/b1b.csv",
        "B1,2,1,L,815,90000,2024-05-15,10000,40,wheels/a1.csv",    # line 12: the 40 mm line again
    ], {"a1.csv": _line(20), "a2.csv": _line(20, bad_row=17), "b1a.csv": _line(10), "b1b.csv": _line(30)})
    ds = fleet(SCENARIO, manifest, policy_file, rates=known_rates)
    failed = list(ds.failed.values)
    expected = ["wheels/a2.csv line 19, column 2 (deviation_um): '12.x' is not a number",
                "fleet.csv line 4, column 5 (diameter_mm): missing value",
                "fleet.csv line 5, column side: 'X' is not L or R",
                "fleet.csv line 6: car 1 axle 1 side L is wheel A1 on line 2",
                "fleet.csv line 7, column date: '14.5.2024' is not a date YYYY-MM-DD",
                "wheels/none.csv: no such file (wheel A7, fleet.csv line 8)",
                "fleet.csv line 9, column diameter_mm: wheel A8 is 900 mm, larger than the scenario's new wheel",
                "fleet.csv line 12, column lateral_mm: wheel B1's line at 40 mm is also on line 11"]
    assert len(failed) == len(expected)
    for start in expected:
        assert sum(f.startswith(start) for f in failed) == 1, start
    assert list(ds.wheel.values) == ["A1", "B1"]
    b1 = ds.sel(wheel="B1")
    assert int(b1.lines) == 2 and float(b1.lateral_position) == pytest.approx(0.040)  # the 30 um line acts first
    assert str(b1.file.values) == "wheels/b1b.csv"
    text = fleets.report(ds)
    assert "refused (8):" in text and all(f in text for f in failed)


def test_a_fleet_with_nothing_readable_is_refused(tmp_path, policy_file):
    manifest = _tiny(tmp_path, ["A1,1,1,L,820,100000,2024-05-14,50000,,wheels/a1.csv"], {"a1.csv": "angle_deg\n1\n"})
    with pytest.raises(MeasuredFileError, match=r"no wheel of the fleet could be read .*wheels/a1.csv"):
        fleet(SCENARIO, manifest, policy_file, rates=known_rates)
    with pytest.raises(MeasuredFileError, match="needs a last_turning_km column"):
        manifest.write_text("wheel_id,car,axle,side,diameter_mm,mileage_km,date,file\n")
        fleet(SCENARIO, manifest, "metro-condition", rates=known_rates)


def test_the_command_exits_2_with_one_line_for_a_fleet_of_nothing_readable(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from railwear.cli import app

    (tmp_path / "fleet.csv").write_text("wheel_id,car,axle,side,diameter_mm,mileage_km,date,last_turning_km,file\n"
                                        "A1,1,1,L,820,1000,2024-05-14,0,missing.csv\n")
    monkeypatch.chdir(tmp_path)
    done = CliRunner().invoke(app, ["fleet", "metro", "fleet.csv", "-o", "out"])
    assert done.exit_code == 2
    assert done.output == ("railwear: error: fleet.csv: no wheel of the fleet could be read (1 refused; the first: "
                           "missing.csv: no such file (wheel A1, fleet.csv line 2))\n")


def test_integers_are_stored_as_integers_and_the_files_read_back(tmp_path, policy_file):
    manifest, _ = write_synthetic(tmp_path / "in", 12, np.random.default_rng(5), roughness_um=0.5)
    ds = fleet(SCENARIO, manifest, policy_file, rates=known_rates, batch=5)
    paths = fleets.write(ds, tmp_path / "out", figures=False)  # the figures: in the e2e test
    assert [p.name for p in paths] == ["fleet.nc", "fleet.txt", "wheels.csv", "fleet.html"]
    back = read_netcdf(tmp_path / "out" / "fleet.nc")
    for name in ("axle", "lines", "manifest_line", "dominant_order", "selected_order", "days_to_action",
                 "days_to_action_early", "node_selected_order"):
        assert back[name].dtype == np.int64, name
    for name in ("distance_to_trigger", "peak_to_peak", "diameter", "distance_to_action"):
        assert "units" in back[name].attrs
    assert fleets.report(back) == fleets.report(ds)
    table = (tmp_path / "out" / "wheels.csv").read_text().splitlines()
    assert table[0].startswith("wheel_id,car,axle,side,lines,diameter_mm,mileage_km,measured,peak_to_peak_um,dominant_order")
    assert "to_0_1mm_peak_to_peak_km" in table[0] and len(table) == 13
    again = fleet(SCENARIO, manifest, policy_file, rates=known_rates, batch=64)
    xr.testing.assert_identical(again, ds)  # the batches change nothing


def test_on_dask_the_fleet_is_the_same(tmp_path, policy_file):
    distributed = pytest.importorskip("distributed")
    from railwear.sweep import DaskExecutor

    manifest, _ = write_synthetic(tmp_path, 10, np.random.default_rng(7))
    serial = fleet(SCENARIO, manifest, policy_file, rates=known_rates, batch=3)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        executor = DaskExecutor(cluster.scheduler_address)
        try:
            on_dask = fleet(SCENARIO, manifest, policy_file, rates=known_rates, batch=3, executor=executor)
        finally:
            executor.close()
    xr.testing.assert_identical(on_dask, serial)


def test_the_built_in_example_fleet_reads_whole():
    from railwear.maintenance.fleet_input import read_fleet

    lines, failed, manifest = read_fleet("example-fleet", interval=True)
    assert not failed and manifest.name == "fleet.csv"
    assert len(lines) == 25 and len({line.wheel_id for line in lines}) == 24
    assert sorted(line.lateral / MM for line in lines if line.wheel_id == "W0003") == pytest.approx([70, 80])
