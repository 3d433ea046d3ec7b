"""``railwear fleet --load-speeds``: which wheels a wheel-impact-load detector flags at which
speed now, and the distance at which the predicted growth takes each wheel over a threshold,
against a wheel whose crossing the linear model predicts."""

import numpy as np
import pytest

from railwear.errors import OptionError, ScenarioError
from railwear.longterm.vehicle_track import VehicleTrackModel
from railwear.maintenance import impact
from railwear.maintenance.fleet import csv_text, fleet, report
from railwear.maintenance.impact import Detector, DynamicLoad, filtered_harmonics, peak_forces
from railwear.maintenance.turning import RateTable
from railwear.scenario import load_scenario

POINTS = 128
SCENARIO = load_scenario("metro", [f"solver.points={POINTS}"])
SPEED = 70 / 3.6  # m/s
SIGMA = 4e-7  # 1/s: every order grows alike, so the single harmonic keeps its shape
ORDER, A0 = 8, 20e-6  # the wheel now: 20 um of order 8 (40 um peak to peak)
THRESHOLD = 100e3  # N: an increment of 31 kN over the 68.8 kN static load, the wheel keeps contact (A* = 217 um)
RUN = {"load_revolutions": 4, "load_transient_s": 0.5}  # a shorter record than railwear load's, for the test's time
POLICY = """name = "known"
source = "a test policy"
[trigger]
peak_to_peak_mm = 0.5
[wheel]
last_turning_diameter_mm = 770.0
"""
OWN = Detector("own", "a test threshold", THRESHOLD / 1e3, "kN", "flags the wheel", "the test")


def known_rates(diameter):
    n = np.arange(1, POINTS // 2 + 1)
    return RateTable(SIGMA - 1j * 2e-7 * n, -2.3e-10, SPEED, diameter / 2)


def one_wheel(folder, amplitude_um, name="W1"):
    """A manifest of one wheel of 840 mm with ``amplitude_um`` of order 8 on 360 angles."""
    (folder / "wheels").mkdir(exist_ok=True)
    x = np.arange(360)
    u = amplitude_um * np.cos(np.radians(ORDER * x))
    (folder / "wheels" / f"{name}.csv").write_text("angle_deg,deviation_um\n"
                                                    + "".join(f"{a},{v:.9f}\n" for a, v in zip(x, u)))
    manifest = folder / "fleet.csv"
    manifest.write_text("wheel_id,car,axle,side,diameter_mm,mileage_km,date,file\n"
                        f"{name},1,1,L,840,100000,2024-05-14,wheels/{name}.csv\n")
    (folder / "policy.toml").write_text(POLICY)
    return manifest, folder / "policy.toml"


@pytest.fixture(scope="module")
def crossed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("detector")
    manifest, policy = one_wheel(folder, A0 * 1e6)
    ds = fleet(SCENARIO, manifest, policy, growth=(0.5, 1.0, 2.0), rates=known_rates, load_speeds_kmh=[70.0],
               detectors=(OWN,), **RUN)
    return ds


def test_the_grown_wheel_passes_the_threshold_where_the_linear_model_puts_it(crossed):
    """Under the linear model the peak of ``A cos(8 x)`` is the static load plus ``|H̄(8Ω)| F_8 A``,
    plus at most the round wheel's sleeper ripple above the static load: the threshold is passed at
    an amplitude between ``(T - P_round) / (|H̄| F_8)`` and ``(T - W) / (|H̄| F_8)``, and the
    amplitude grows as ``A0 exp(σ s / V)``, so the crossing lies in a known window of distance.
    The search stops when the peak to peak across its bracket differs by 2 %, and the linear model
    reads the time domain's line within 1 % (test_impact.py): the window is widened by 3 % of
    amplitude, ``0.03 V / σ`` (1,460 km) on either side."""
    ds = crossed
    case = SCENARIO.body.case(SCENARIO)
    wheel = case.wheel(SPEED)
    x = 2 * np.pi * np.arange(POINTS) / POINTS
    filtered = filtered_harmonics(wheel, np.cos(ORDER * x))[ORDER]
    omega = SPEED * (1 + wheel.steady_creepage()) / wheel.radius
    gain = abs(VehicleTrackModel(wheel, case.track, SCENARIO.track.bay_positions).contact_force_transfer(
        np.array([ORDER * omega]))[0]) * filtered
    flat = DynamicLoad(case, np.zeros(POINTS), (SPEED,), revolutions=RUN["load_revolutions"],
                       transient=RUN["load_transient_s"])
    round_peak = peak_forces(flat)[0]
    w = wheel.static_load
    a_low, a_high = (THRESHOLD - round_peak) / gain, (THRESHOLD - w) / gain
    per = SIGMA / SPEED  # 1/m
    window = np.log(np.array([a_low, a_high]) / A0) / per / 1e3  # km
    slack = 0.03 / per / 1e3
    found = float(ds.distance_to_detector.sel(detector="own", growth=1.0)[0])
    assert window[0] - slack <= found <= window[1] + slack, (found, window)
    # measured: the crossing at 0.3-0.7 of the window (printed by -s)
    print(f"crossing {found:,.0f} km in the linear window {window[0]:,.0f}-{window[1]:,.0f} km "
          f"(+-{slack:,.0f}); round-wheel ripple {(round_peak - w) / 1e3:.2f} kN; {int(ds.load_runs[0])} runs")
    assert float(ds.detector_speed.sel(detector="own")[0]) == pytest.approx(SPEED)
    assert float(ds.detector_peak_force.sel(detector="own")[0]) > THRESHOLD
    # the band: the distance under g is the one under 1 divided by g
    band = ds.distance_to_detector.sel(detector="own").values[0]
    np.testing.assert_allclose(band, found / np.array([0.5, 1.0, 2.0]), rtol=1e-12)


def test_the_peak_now_is_the_load_commands_and_nothing_is_flagged_below_the_threshold(crossed):
    ds = crossed
    case = SCENARIO.body.case(SCENARIO)
    x = 2 * np.pi * np.arange(POINTS) / POINTS
    assert ds.attrs["load_revolutions"] == 4
    direct = impact.dynamic_load(DynamicLoad(case, A0 * np.cos(ORDER * x), (SPEED,), revolutions=4, transient=0.5))
    assert float(ds.peak_force_now[0, 0]) == pytest.approx(float(direct.peak_force[0]), rel=2e-3)
    assert int(ds.flagged_now.sum()) == 0
    text = report(ds)
    assert "dynamic wheel load at 70 km/h" in text and "a test threshold 100 kN: none flagged now" in text
    head = csv_text(ds).splitlines()[0].split(",")
    assert {"peak_now_70kmh_kN", "to_own_100kN_km", "own_100kN_speed_kmh", "flagged_now_by"} <= set(head)


def test_a_wheel_over_the_threshold_now_is_flagged_now_at_distance_0(tmp_path):
    manifest, policy = one_wheel(tmp_path, 150.0)
    ds = fleet(SCENARIO, manifest, policy, rates=known_rates, load_speeds_kmh=[70.0], detectors=(OWN,), **RUN)
    assert int(ds.flagged_now.sel(detector="own").sum()) == 1
    assert float(ds.distance_to_detector.sel(detector="own", growth=1.0)[0]) == 0.0
    assert "1 flagged now (W1)" in report(ds)


def test_the_options_are_refused_naming_them(tmp_path):
    manifest, policy = one_wheel(tmp_path, 10.0)
    with pytest.raises(OptionError, match="--load-speeds"):
        fleet(SCENARIO, manifest, policy, rates=known_rates, load_speeds_kmh=[0.5])
    disk = load_scenario("linear-dynamics")
    with pytest.raises(ScenarioError, match="body.kind"):
        fleet(disk, manifest, policy, rates=known_rates, load_speeds_kmh=[70.0])
